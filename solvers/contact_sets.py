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
factorisations.
"""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING, Any

import numpy as np
import scipy.sparse as sp

from femcore.state import State

if TYPE_CHECKING:
    from solvers.static import StaticRun

__all__ = ["MAX_PASSES", "MAX_SWITCHED", "REFACTOR_AT", "PREDICTED", "predicted_sets"]

#: The most passes of the rule on one step's linear model.
MAX_PASSES = 20
#: The most points a prediction switches: more, and the step is far from the set (the
#: iterates' own rule chooses it). Measured on plies-bai-5.1's default stack
#: (benchmarks/static_plies_newton.py ``--active-set``): 64, 200 and 1000 (REFACTOR_AT 16,
#: 48, 16) gave 405, 345 and 322 tangents in 19.6, 22.7 and 61.9 s.
MAX_SWITCHED = 200
#: Past this many new solves in a pass, the updated K_ff is factorised instead (a band
#: factorisation of the plies costs some 15 solves, but a new pattern its analysis too).
REFACTOR_AT = 48
#: Whether newton predicts the sets (benchmarks/static_plies_newton.py compares).
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
        if hasattr(part, "set_model"):
            found = part.set_model(state, history[first + i], frames, dofs)
            if found is not None and len(found["points"]):
                pieces.append((first + i, part, found))
    if not pieces:
        return None
    from elements import ply_active_set

    gradient = sp.vstack([found["gradient"] for _, _, found in pieces]).tocsr()
    gap = np.concatenate([found["gap"] for _, _, found in pieces])
    k = np.concatenate([found["stiffness"] for _, _, found in pieces])
    start = np.concatenate([found["active"] for _, _, found in pieces])
    pressure = np.concatenate([found["pressure"] for _, _, found in pieces])
    free, moved = dofs.free_slots, dofs.prescribed_slots
    g_free = gradient[:, free]
    # the gaps with the prescribed part of the step
    imposed = gap + gradient[:, moved] @ left.ravel()[moved] if moved.size else gap.copy()
    pull = pressure if ply_active_set.HYSTERESIS else 0.0
    active, step = start.copy(), delta_free
    # the set the factors hold, their step K^-1 (r_f - K_fp dq_p) and K^-1 G_i^T of the
    # points switched from it so far
    held, held_step = start.copy(), delta_free
    solves: dict[int, np.ndarray] = {}
    for _ in range(MAX_PASSES):
        linear = imposed + g_free @ step
        chosen = pull - k * linear > 0.0
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
        rows = g_free[switched]
        new = [int(i) for i in switched if int(i) not in solves]
        if len(new) > REFACTOR_AT:
            # more solves than a factorisation costs: the updated K_ff factorised
            matrix = (factor.matrix + rows.T @ sp.diags(weight) @ rows).tocsc()
            right = factor.matrix @ held_step - rows.T @ (weight * imposed[switched])
            factor = run.factorise(matrix)
            solution = factor.solve(right)
            if solution is None:
                return None
            held, held_step, step, solves = active.copy(), solution, solution, {}
            run.info["predicted_factorisations"] = run.info.get("predicted_factorisations", 0) + 1
            continue
        if new:
            made = factor.solve(g_free[new].T.toarray())
            if made is None:
                return None
            made = made.reshape(len(free), -1)
            solves.update({i: made[:, j] for j, i in enumerate(new)})
        solved = np.column_stack([solves[int(i)] for i in switched])
        # K^-1 (rhs - sum s k g_i G_i) = held_step - solved (s k g)
        base = held_step - solved @ (weight * imposed[switched])
        columns = rows.T.toarray()  # (f, m)
        capacity = np.diag(1.0 / weight) + columns.T @ solved
        try:
            step = base - solved @ np.linalg.solve(capacity, columns.T @ base)
        except np.linalg.LinAlgError:
            return None
    if np.array_equal(active, start):
        return None
    linear = imposed + g_free @ step
    # a member kept keeps its multiplier; one that joins takes -k g of the step's end
    pressure = np.where(active, np.where(start, pressure, -k * linear), 0.0)
    offset = 0
    for index, part, found in pieces:
        count = len(found["points"])
        rows = slice(offset, offset + count)
        history[index] = part.with_set(
            history[index], found["points"], active[rows], pressure[rows]
        )
        offset += count
    run.info["predicted_sets"] = run.info.get("predicted_sets", 0) + 1
    # the residual under the new sets: each switched point's force k g G_i (w = 1) off or on
    switched = np.flatnonzero(active != start)
    signs = np.where(active[switched], 1.0, -1.0)
    change = gradient[switched].T @ (signs * k[switched] * gap[switched])
    return replace(state, history=tuple(history)), step, change
