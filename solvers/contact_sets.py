"""The next contact set predicted on the Newton step's linear model (solvers/newton.py;
docs/theory.md §9.3a, "An active set under Static"): for interactions whose normal law under
Static is a frozen active set of a bilateral penalty (elements/ply_active_set.py), the set of
the step's end is chosen on the linear model of the iteration before the step is taken, so
that the step and its set agree.

Why. Chosen between iterations on the new iterate's gaps, the set of the ply contact changes
by a few points an iteration where the points carry almost no force (the sag of
tests/test_plies.py: 1-7 of 20 points, each change a Newton iteration): the step taken with
the old set puts them 1e-10 to 1e-6 mm on the wrong side. Here the primal-dual rule runs on
the linearised gaps g + G dq of the step dq, and a point that switches changes the linear
system by a rank-one term k G_i G_i^T and its right-hand side by k g_i G_i (the term k g_i
d2g/dq2 left out: g_i is the point's own gap, small where points switch); the system with the
switched points is solved with the factors already made by the Sherman-Morrison-Woodbury
formula (Hager, SIAM Review 31 (1989) 221), m solves for m switched points, until the rule
keeps the set (at most MAX_PASSES times): a primal-dual active set on the iteration's linear
complementarity problem, at the cost of back-substitutions, not of tangents or
factorisations. A point's force may lie along another vector F_i than its gradient (a
sliding frictional node's n - mu v: the term k F_i G_i, not symmetric, is taken with F_i on
the left), and rows may follow another row's rule (a stuck node's stick rows, its gap's;
elements/contact_set_model.py).

How, cheaply. The new switched points' columns G_i^T are solved together, one pass of the
band's factors for all of them (solvers.band ``BandLDLT.solve_columns``, without the
accuracy check of every column: ``Factorisation.solve_columns``), and the rows are held
dense by point (``SetRows``: 30 entries a point), so that G dq, G_S K^-1 G_S^T and the
updates are gathers and scatters, not sparse products: on plies-bai-5.1's default stack the
prediction's solves fell from ~13.7 s (7806 single solves) to ~3 s (some 800 passes for
~12000 columns), benchmarks/band_columns.py and docs/theory.md §9.3a.
"""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING, Any

import numpy as np
import scipy.sparse as sp

from femcore import interaction
from femcore.state import State

if TYPE_CHECKING:
    from solvers.static import StaticRun

__all__ = [
    "MAX_PASSES",
    "MAX_SWITCHED",
    "PREDICTED",
    "REFACTOR_AT",
    "STEP_RESIDUAL",
    "SetRows",
    "predicted_sets",
]

#: The most passes of the rule on one step's linear model.
MAX_PASSES = 20
#: The most points a prediction switches: more, and the step is far from the set (the
#: iterates' own rule chooses it). Measured on plies-bai-5.1's default stack
#: (benchmarks/static_plies_active_set.py): 64, 200 and 1000 (REFACTOR_AT 16,
#: 48, 16) gave 405, 345 and 322 tangents in 19.6, 22.7 and 61.9 s.
MAX_SWITCHED = 200
#: Past this many new solves in a pass, the updated K_ff is factorised instead (by the run's
#: ``updated_linear``). With the columns solved together (0.12-0.14 ms a column against a
#: band factorisation's ~5 ms and its assembly and plan) this no longer pays on the plies:
#: plies-bai-5.1 default 48, 100 and 200 (none: MAX_SWITCHED) 17.5, 16.4 and 15.9 s, the
#: same iterations (one process, one thread, load 4.1-4.6).
#: At MAX_SWITCHED the branch is not reached (a pass with more switched points is given up
#: first): it runs only with a lower bound (tests/test_predicted_sets.py sets 0).
REFACTOR_AT = 200
#: Whether newton predicts the sets (benchmarks/static_plies_active_set.py compares).
PREDICTED = True


def predicted_sets(
    run: StaticRun,
    state: State,
    frames: Any,
    factor: Any,
    delta_free: np.ndarray,
    left: np.ndarray,
) -> tuple[State, np.ndarray, np.ndarray] | None:
    """(``state`` with the sets its step's end has on the linear model, the step dq_f with
    those sets, the change (n 5,) of the internal forces in the generalised unknowns at
    ``state`` the new sets make), or None where no interaction predicts a set or the sets
    stay.

    ``factor``: K_ff's factors at ``state``; ``delta_free`` (f,) the step, K_ff^-1 (r_f -
    K_fp dq_p); ``left`` (n, 5) the prescribed motion not yet applied."""
    model = run.model
    dofs = model.dofs
    first = len(model.parts) - len(model.interactions)
    history = list(state.history)
    pieces: list[tuple[int, Any, dict]] = []
    for i, part in enumerate(model.interactions):
        found = part.set_model(state, history[first + i], frames, dofs)
        if found is not None and len(found["points"]):
            pieces.append((first + i, part, found))
    if not pieces:
        return None
    rows = SetRows.of(pieces, dofs, left)
    k = np.concatenate([found["stiffness"] for _, _, found in pieces])
    start = np.concatenate([found["active"] for _, _, found in pieces])
    pressure = np.concatenate([found["pressure"] for _, _, found in pieces])
    leader = _leaders(pieces)
    imposed = rows.imposed
    pull = pressure if interaction.ACTIVE_SET_HYSTERESIS else 0.0  # the blocks' own rule
    active, step = start.copy(), delta_free
    # the set the factors hold, their step K^-1 (r_f - K_fp dq_p) and K^-1 G_i^T of the
    # points switched from it so far (column ``column_of[i]`` of ``solves``)
    held, held_step = start.copy(), delta_free
    held_rhs = None  # K held_step, the held system's right-hand side, made when first asked
    solves = np.empty((rows.free, 0))
    column_of = np.full(len(k), -1)
    for _ in range(MAX_PASSES):
        chosen = (pull - k * rows.linear(step) > 0.0)[leader]
        if np.array_equal(chosen, active):
            break
        active = chosen
        switched = np.flatnonzero(active != held)
        if not switched.size:
            step = held_step
            continue
        if switched.size > MAX_SWITCHED:  # far from the set: the iterations choose it
            return None
        signs = np.where(active[switched], 1.0, -1.0)
        weight = signs * k[switched]
        new = switched[column_of[switched] < 0]
        if len(new) > REFACTOR_AT:
            # more solves than a factorisation costs: the updated K_ff factorised (by a
            # linear solver of its own, so that the tangents' kept plans stay theirs)
            matrix = (factor.matrix + rows.update(switched, weight)).tocsc()
            if held_rhs is None:
                held_rhs = factor.matrix @ held_step
            right = held_rhs - rows.transposed(switched, weight * imposed[switched])
            factor = run.updated_linear.factorise(matrix)
            solution = factor.solve(right)
            if solution is None:
                return None
            held, held_step, step = active.copy(), solution, solution
            held_rhs = right
            solves, column_of = np.empty((rows.free, 0)), np.full(len(k), -1)
            run.info["predicted_factorisations"] = run.info.get("predicted_factorisations", 0) + 1
            continue
        if len(new):
            made = factor.solve_columns(rows.columns(new))
            if made is None:
                return None
            column_of[new] = solves.shape[1] + np.arange(len(new))
            solves = np.hstack([solves, made.reshape(rows.free, -1)])
        solved = solves[:, column_of[switched]]  # (f, m)
        # K^-1 (rhs - sum s k g_i G_i) = held_step - solved (s k g)
        base = held_step - solved @ (weight * imposed[switched])
        capacity = np.diag(1.0 / weight) + rows.times(switched, solved)
        try:
            step = base - solved @ _capacity_solve(capacity, rows.times(switched, base))
        except np.linalg.LinAlgError:
            return None
        if held_rhs is None:
            held_rhs = factor.matrix @ held_step
        if not _solves_its_system(factor, rows, switched, weight, step, held_rhs):
            return None  # a capacitance matrix too ill-conditioned: the step as it was
    if np.array_equal(active, start):
        return None
    linear = rows.linear(step)
    # a member kept keeps its multiplier; one that joins takes -k g of the step's end
    pressure = np.where(active, np.where(start, pressure, -k * linear), 0.0)
    offset = 0
    for index, part, found in pieces:
        count = len(found["points"])
        kept = slice(offset, offset + count)
        history[index] = part.with_set(
            history[index], found["points"], active[kept], pressure[kept]
        )
        offset += count
    run.info["predicted_sets"] = run.info.get("predicted_sets", 0) + 1
    # the residual under the new sets: each switched point's force k g G_i (w = 1) off or on
    switched = np.flatnonzero(active != start)
    signs = np.where(active[switched], 1.0, -1.0)
    change = rows.spread(switched, signs * k[switched] * rows.gap[switched])
    return replace(state, history=tuple(history)), step, change


#: The largest relative residual of a step with switched points in its own linear system
#: (``_solves_its_system``): the Sherman-Morrison-Woodbury step carries the factors' round-off
#: amplified by the capacitance matrix's condition (measured at most 1.3e-8, 1.5e-7, 6.0e-7
#: on the 2-, 4- and 8-ply sags of tests/test_ply_active_set.py); a step past this bound, far
#: above round-off and far below a wrong step's O(1), is not taken.
STEP_RESIDUAL = 1e-4


def _leaders(pieces: list) -> np.ndarray:
    """(r,) int: for each row of the stacked ``set_model`` answers, the row whose rule decides
    it (its own, or the answer's ``"leader"`` of the same answer: a frictional node's stick
    rows follow its gap's row, elements/contact_set_model.py)."""
    out, offset = [], 0
    for _, _, found in pieces:
        count = len(found["points"])
        own = found.get("leader")
        out.append(offset + (np.arange(count) if own is None else np.asarray(own)))
        offset += count
    return np.concatenate(out)


def _capacity_solve(capacity: np.ndarray, right: np.ndarray) -> np.ndarray:
    """The capacitance system's solution (m,) (its own function so that a test can spoil it)."""
    return np.linalg.solve(capacity, right)


def _solves_its_system(
    factor: Any,
    rows: SetRows,
    switched: np.ndarray,
    weight: np.ndarray,
    step: np.ndarray,
    held_rhs: np.ndarray,
) -> bool:
    """Whether ``step`` (f,) solves the linear system of the held set with the points
    ``switched`` given the penalty ``weight`` (signed k, N/mm): (K + G_S^T W G_S) dq =
    rhs - G_S^T W g_S, rhs = ``held_rhs`` (K times the held set's step), within
    STEP_RESIDUAL of its largest term, and is finite."""
    if not np.all(np.isfinite(step)):
        return False
    stiffness = factor.matrix @ step
    points = rows.transposed(
        switched, weight * (rows.times(switched, step) + rows.imposed[switched])
    )
    scale = max(np.abs(stiffness).max(), np.abs(points).max(), np.abs(held_rhs).max())
    return bool(np.abs(stiffness + points - held_rhs).max() <= STEP_RESIDUAL * scale)


class SetRows:
    """The rows G_i = dg_i/dq of the points a prediction may switch, dense by point: each
    point's entries (at most 30: six nodes, five unknowns each) and their places among the
    free unknowns, so that the products of the prediction (G dq, G^T x, G X, the columns
    G_i^T and k G_i^T G_i) are gathers and scatters of (r, 30) arrays, not sparse products.

    Attributes
    ----------
    values : (r, 30) the entries of the rows on the free unknowns (0 on the prescribed).
    forces : (r, 30) the entries of the points' force directions F_i on the free unknowns:
        a point adds k g F_i to the internal forces and k F_i^T G_i to the tangent; F_i =
        G_i unless its ``set_model`` answer gives ``"forces"`` (a sliding frictional node,
        whose friction mu k p follows its gap: elements/contact_set_model.py).
    where : (r, 30) int, the entries' free unknowns (0 where prescribed: ``values`` is 0).
    slots : (r, 30) int, ``values``'s slots among all n 5 unknowns (``spread``).
    all_forces : (r, 30) the entries of F_i on every unknown.
    gap : (r,) mm, the points' gaps; imposed : (r,) mm, with the prescribed motion's part.
    free : the number of free unknowns f; size : n 5.
    """

    def __init__(self, slots, values, gap, dofs, left, forces=None):
        free_slots, moved = dofs.free_slots, dofs.prescribed_slots
        self.size, self.free = int(dofs.free.size), int(free_slots.size)
        free_of = np.full(self.size, -1, dtype=np.int64)
        free_of[free_slots] = np.arange(self.free)
        where = free_of[slots]
        on_free = where >= 0
        forces = values if forces is None else forces
        self.slots, self.all_forces, self.gap = slots, forces, gap
        self.values = np.where(on_free, values, 0.0)
        self.forces = np.where(on_free, forces, 0.0)
        self.where = np.where(on_free, where, 0)
        self.on_free = on_free
        if moved.size:  # the gaps with the prescribed part of the step
            motion = np.zeros(self.size)
            motion[moved] = left.ravel()[moved]
            self.imposed = gap + np.sum(values * motion[slots], axis=1)
        else:
            self.imposed = gap.copy()

    @classmethod
    def of(cls, pieces: list, dofs: Any, left: np.ndarray) -> SetRows:
        """The rows of the interactions' ``set_model`` answers in ``pieces`` (index, part,
        found), stacked in their order."""
        return cls(
            np.concatenate([found["slots"] for _, _, found in pieces]),
            np.concatenate([found["values"] for _, _, found in pieces]),
            np.concatenate([found["gap"] for _, _, found in pieces]),
            dofs,
            left,
            np.concatenate([found.get("forces", found["values"]) for _, _, found in pieces]),
        )

    def linear(self, step: np.ndarray) -> np.ndarray:
        """(r,) mm: the gaps g + G dq at the end of the free step ``step`` (f,) (with the
        prescribed motion's part)."""
        return self.imposed + np.sum(self.values * step[self.where], axis=1)

    def columns(self, points: np.ndarray) -> np.ndarray:
        """(f, m) the columns F_i^T of ``points`` (m,) (G_i^T where a row's force direction
        is its gradient's)."""
        m = len(points)
        place = self.where[points] * m + np.arange(m)[:, None]
        flat = np.bincount(place.ravel(), self.forces[points].ravel(), self.free * m)
        return flat.reshape(self.free, m)

    def times(self, points: np.ndarray, x: np.ndarray) -> np.ndarray:
        """G_points x: (m,) for x (f,), (m, c) for x (f, c)."""
        values = self.values[points]
        if x.ndim == 1:
            return np.sum(values * x[self.where[points]], axis=1)
        return np.einsum("ik,ikc->ic", values, x[self.where[points]])

    def transposed(self, points: np.ndarray, y: np.ndarray) -> np.ndarray:
        """(f,) F_points^T y for y (m,)."""
        weights = (self.forces[points] * y[:, None]).ravel()
        return np.bincount(self.where[points].ravel(), weights, self.free)

    def spread(self, points: np.ndarray, y: np.ndarray) -> np.ndarray:
        """(n 5,) F_points^T y on every unknown for y (m,)."""
        weights = (self.all_forces[points] * y[:, None]).ravel()
        return np.bincount(self.slots[points].ravel(), weights, self.size)

    def update(self, points: np.ndarray, weight: np.ndarray) -> sp.csc_matrix:
        """(f, f) sum over ``points`` of weight_i F_i^T G_i on the free unknowns (only the
        pairs of free entries: no structural entry outside the points' couplings)."""
        values, where, on = self.values[points], self.where[points], self.on_free[points]
        pair = on[:, :, None] & on[:, None, :]
        data = weight[:, None, None] * self.forces[points][:, :, None] * values[:, None, :]
        rows = np.broadcast_to(where[:, :, None], pair.shape)[pair]
        cols = np.broadcast_to(where[:, None, :], pair.shape)[pair]
        return sp.csc_matrix((data[pair], (rows, cols)), shape=(self.free, self.free))
