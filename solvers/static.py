"""Static: Newton-Raphson on the free DOFs with a sparse finite-difference tangent.

Loads and prescribed displacements are applied in ``increments`` equal load-factor steps, all of
them (gravity and "step" loads included) ramped linearly with the load factor, as a static step
does: amplitudes shape time histories in dynamics only, and an increment that has to be cut can
then always be made smaller. Each increment is solved by Newton-Raphson and gives one frame; an
increment that does not converge is cut in half and retried from the last converged state.

Unknowns per node: ux uy uz and, at shell nodes, alpha beta: small rotations of the director
about V2 and V1 of its nodal frame (Bai Eq. 7, 13; docs/theory.md §1.3), applied as finite
rotations.

Tangent: the blocks' own ``tangent`` where they give one, assembled in the generalised
coordinates of femcore.dofs by femcore.assembly; for the other blocks, K = dF_int/dq by central
differences with a colouring of the node graph (femcore.assembly.NodeGraph): all nodes of one
colour are perturbed together, and each perturbation gives the columns of all of them, so the
cost is 10 x (number of colours) force evaluations, independent of the mesh size.
"""

from __future__ import annotations

import time
import warnings
from dataclasses import replace
from typing import Any

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import ArpackNoConvergence, MatrixRankWarning, eigsh, splu

from femcore.assembly import FreeTangentAssembler, TangentPart
from femcore.dofs import N_COLUMNS, Frames
from femcore.model import CompiledModel, Model
from femcore.results import Result
from femcore.state import State
from solvers.common import (
    ConvergenceError,
    ProgressLine,
    check_held,
    check_integer,
    check_tolerance,
    empty_result,
    equilibrium_reactions,
    make_frame,
    resolve_progress,
)

__all__ = ["Static"]


class Static:
    """Quasi-static solver: Newton-Raphson on the free DOFs with a sparse tangent.

    increments : number of equal load-factor steps (one frame each).
    tol : convergence when ||r_forces|| <= tol F_ref and ||r_moments|| <= tol F_ref L_e (or,
        at the round-off floor, when a full Newton step moves no DOF by more than 1e-9 of an
        element or 1e-9 rad while the ratio is below 1e-3), with
        F_ref = max(||F_ext||, ||F_int||, ||M_ext|| / L_e, ||M_int|| / L_e) (the internal
        forces include the reactions) and L_e the median element edge.
    max_iterations : Newton iterations per (sub-)increment before it is cut in half.
    line_search : backtrack (halve the update, up to 5 times) while the residual ratio of the
        trial exceeds 10 x the current one.
    max_cuts : how many times an increment may be halved before a ConvergenceError.
    seek_stable : when an update meets an indefinite tangent (det K_ff < 0), turn it downhill
        along the negative modes (their components of the Newton step get the sign that lowers
        the energy, a "saddle-free" step), and push a converged unstable equilibrium (a
        compressed plate that stayed flat) along its buckling mode by half an element, up to
        three times per increment: the solver then settles on the stable, buckled branch.
        Each push is listed in ``info["branch_switches"]``.
    step_loads_first : apply the loads whose amplitude is "step" (gravity by default) first,
        over load factors 0 to 1 in ``increments`` increments with the prescribed displacements
        held at zero, then the other loads and the prescribed displacements over 1 to 2 (a
        specimen hangs under its weight before a support moves it). Frames then run over load
        factors 0 to 2.
    tangent : "element" (default): each block's own ``tangent`` where it has one, coloured
        finite differences of ``internal_force`` for the others; "finite_difference": coloured
        finite differences for every block.
    progress : print status lines (None: only on an interactive terminal).

    Prescribed displacements enter each iteration consistently: the update solves
    K_ff dq_f = r_f - K_fp dq_p for the part dq_p of the prescribed motion not yet applied, so
    the first iteration of an increment moves the structure with the imposed nodes instead of
    dragging them alone.

    Stability: a converged state whose tangent has det(K_ff) < 0 (an odd number of negative
    eigenvalues: an unstable equilibrium, past a limit point or a bifurcation) is reported in
    ``info["indefinite_at"]`` (load factors) and on the progress line; an even number of
    negative eigenvalues escapes this test. A singular tangent is regularised for one update
    (see ``_newton``) and reported if the increment then fails. There is no arc-length option:
    with ``seek_stable`` a limit point is passed by turning the steps downhill, which lands on
    the stable branch beyond a snap-through (the jump a quasi-static test shows), not on the
    unstable part of the path; with ``seek_stable=False`` a run that cannot pass a limit point
    stops with the load factor it reached, and DynamicRelaxation or CentralDifference remain
    the tools for a path that needs dynamics.
    """

    def __init__(
        self,
        increments: int = 10,
        tol: float = 1e-8,
        max_iterations: int = 50,
        line_search: bool = True,
        max_cuts: int = 8,
        tangent: str = "element",
        seek_stable: bool = True,
        step_loads_first: bool = False,
        progress: bool | None = None,
    ):
        self.increments = check_integer(increments, "increments")
        self.tol = check_tolerance(tol)
        self.max_iterations = check_integer(max_iterations, "max_iterations")
        self.line_search = bool(line_search)
        self.max_cuts = check_integer(max_cuts, "max_cuts", minimum=0)
        if tangent not in ("element", "finite_difference"):
            raise ValueError(f"tangent must be 'element' or 'finite_difference', got {tangent!r}")
        self.tangent = tangent
        self.seek_stable = bool(seek_stable)
        self.step_loads_first = bool(step_loads_first)
        self.progress = progress

    def solve(self, model: Model | CompiledModel) -> Result:
        """Solve every increment.

        Parameters
        ----------
        model : Model or CompiledModel

        Returns
        -------
        femcore.results.Result
            The reference state and one frame per increment (``time`` = load factor), with
            ``info`` (iterations, cuts, stability, tangent kinds).

        Raises
        ------
        ValueError
            When the loads push the model along a rigid motion that no support holds (no
            equilibrium exists; the message names the motion).
        ConvergenceError
            When an increment cannot be completed: ``error.result`` holds the converged
            frames and the last good state, ``error.load_factor`` the load factor reached.
        """
        # Trial states of a wild update may overflow; every residual is checked for
        # finiteness and such an update is cut back, so numpy's warnings would only be noise.
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            return self._solve(model)

    def _solve(self, model: Model | CompiledModel) -> Result:
        compiled = model.compile() if isinstance(model, Model) else model
        check_held(compiled)
        started = time.perf_counter()
        state = compiled.initial_state()
        own_parts = compiled.own_tangents(state) if self.tangent == "element" else {}
        own = list(own_parts)
        others = [i for i in range(len(compiled.blocks)) if i not in own]
        tangent = _Tangent(compiled, own, others, (state, own_parts))
        frames = [make_frame(compiled, state)]
        progress = ProgressLine(resolve_progress(self.progress), "static")
        info: dict[str, Any] = {
            "solver": "Static",
            "tangent": {
                "element": [type(compiled.blocks[i]).__name__ for i in own],
                "finite_difference": [type(compiled.blocks[i]).__name__ for i in others],
            },
            "iterations_per_increment": [],
            "cuts": 0,
            "tangent_colours": tangent.graph.n_colours if tangent.graph else 0,
            "residual_ratio_per_increment": [],
            "indefinite_at": [],
            "regularised_iterations": 0,
            "branch_switches": [],
            "residual_history": [],
        }

        phases = 2 if self.step_loads_first else 1
        total = phases * self.increments
        step = 1.0 / self.increments
        reached = 0.0
        for increment in range(1, total + 1):
            target = increment / self.increments
            iterations = 0
            cuts_here = 0
            while reached < target - 1e-12:
                trial = min(target, reached + step)
                try:
                    converged, count, ratio, history = self._newton(
                        compiled, tangent, state, trial, progress, info
                    )
                except _Failed as failure:
                    # ``state`` is still the last converged one: the Newton loop works on its
                    # own states.
                    cuts_here += 1
                    info["cuts"] += 1
                    if cuts_here > self.max_cuts:
                        error = ConvergenceError(
                            f"static solver stopped at load factor {reached:.6g}: increment "
                            f"{increment}/{total} did not converge after {cuts_here - 1}"
                            f" cuts ({failure}). A limit point or buckling may be near: try "
                            "DynamicRelaxation or CentralDifference for this path.",
                            None,
                        )
                        # Keep the last good state, also when it is part of an increment.
                        if reached > frames[-1].load_factor:
                            frames.append(make_frame(compiled, state))
                        error.result = self._result(compiled, frames, info, started, False)
                        error.load_factor = reached
                        raise error from None
                    step = 0.5 * (trial - reached)
                    continue
                iterations += count
                reached = trial
                state = compiled.commit(replace(converged, load_factor=reached, time=reached))
                # After a cut, grow the step back towards the nominal one.
                step = min(1.0 / self.increments, 2.0 * step)
            info["iterations_per_increment"].append(iterations)
            info["residual_ratio_per_increment"].append(ratio)
            info["residual_history"].append(history)
            f_ext, m_ext, _ = self._loads(compiled, reached)
            reactions, reaction_moments = equilibrium_reactions(compiled, state, f_ext, m_ext)
            frames.append(make_frame(compiled, state, reactions, reaction_moments))
            progress(
                f"increment {increment}/{total} converged in {iterations} Newton iterations",
                force=True,
            )
        return self._result(compiled, frames, info, started, True)

    # ------------------------------------------------------------------ one increment
    def _newton(
        self, model: CompiledModel, tangent: _Tangent, state: State, load_factor, progress, info
    ):
        """Newton-Raphson at one load factor from ``state`` (left unchanged).

        Returns (converged state, iterations, final ratio, ratio per iteration starting with
        the ratio before the first update); raises _Failed when the increment has to be cut.
        """
        dofs = model.dofs
        equilibrium = _Equilibrium(model, *self._loads(model, load_factor))
        index, moved_index = dofs.free_slots, dofs.prescribed_slots
        size = model.element_size
        singular = False
        escapes = 0
        translation = index % N_COLUMNS < 3
        forces = None  # the internal forces of the accepted trial, reused next iteration
        for iteration in range(1, self.max_iterations + 1):
            frames = dofs.frames(state.directors)
            r, ratio, _ = equilibrium.residual(state, frames, forces)
            left = equilibrium.remaining(state)
            if iteration == 1:
                history = [ratio]
            if not np.isfinite(ratio):
                raise _Failed("non-finite residual")
            push = False
            if ratio <= self.tol and np.abs(left).max(initial=0.0) <= 1e-9 * size:
                if iteration == 1:  # no factorisation yet: one for the stability report
                    k_ff = tangent(state, frames)[0]
                    negative = _solve(k_ff, np.zeros(index.size))[1]
                if self.seek_stable and escapes < 3 and not negative:
                    # det K > 0 misses an even number of negative modes: look for them.
                    negative = _lowest_modes(k_ff)[0].min(initial=np.inf) < 0.0
                if not (negative and self.seek_stable and escapes < 3):
                    self._report_stability(negative, load_factor, info, progress)
                    return state, iteration - 1, ratio, history
                # An unstable equilibrium: leave it along its buckling mode.
                escapes += 1
                push = True
                info["branch_switches"].append(load_factor)
                progress(
                    f"load factor {load_factor:.4g}: unstable equilibrium, leaving it along "
                    "the buckling mode",
                    force=True,
                )
            k_ff, k_fp = tangent(state, frames)
            rhs = r.ravel()[index]
            if moved_index.size:
                rhs = rhs - k_fp @ left.ravel()[moved_index]
            delta_free, negative = _solve(k_ff, rhs)
            if delta_free is None:
                # Exactly singular: a straight stress-free cable or membrane has no transverse
                # stiffness until it sags. A spring of 1e-6 x the largest diagonal on every
                # free unknown, for this update only, gives a finite step; the residual stays
                # exact, so a converged state is still an exact equilibrium. A mechanism or a
                # rigid motion under load keeps failing and is reported as singular.
                shift = 1e-6 * np.abs(k_ff.diagonal()).max(initial=0.0)
                delta_free, negative = _solve(
                    k_ff + shift * sp.identity(index.size, format="csc"), rhs
                )
                singular = True
                info["regularised_iterations"] += 1
                if delta_free is None:
                    raise _Failed(
                        "singular tangent stiffness: a mechanism, an unconstrained rigid "
                        "motion or a bifurcation"
                    )
            if (negative or escapes) and self.seek_stable:
                load = equilibrium.load(frames).ravel()[index]
                delta_free = _downhill(k_ff, rhs, delta_free, load, translation, size, push)
            flat = left.ravel().copy()
            flat[index] = delta_free
            delta = flat.reshape(-1, N_COLUMNS)
            scale, state, ratio, forces = self._line_search(
                dofs, equilibrium, state, frames, delta, ratio, push
            )
            history.append(ratio)
            # Round-off floor: the internal forces come from differences of nearly equal
            # metrics, so a tiny load on a stiff shell can leave a residual of ~1e-4 of the
            # load that no update removes. A full step that moves nothing (1e-9 of an element,
            # 1e-9 rad) with the residual already small is converged.
            moved = scale * np.abs(delta)
            if (
                scale == 1.0
                and ratio <= 1e-3
                and moved[:, :3].max() <= 1e-9 * size
                and moved[:, 3:].max(initial=0.0) <= 1e-9
            ):
                self._report_stability(negative, load_factor, info, progress)
                return state, iteration, ratio, history
            progress(
                f"load factor {load_factor:.4g}: iteration {iteration}, residual ratio "
                f"{ratio:.3g} (tol {self.tol:g})"
            )
        if ratio <= self.tol and np.abs(equilibrium.remaining(state)).max(initial=0.0) <= (
            1e-9 * size
        ):
            self._report_stability(negative, load_factor, info, progress)
            return state, self.max_iterations, ratio, history
        raise _Failed(
            f"residual ratio {ratio:.3g} after {self.max_iterations} iterations"
            + (
                "; the tangent was singular (a mechanism, an unconstrained rigid motion or a "
                "bifurcation)"
                if singular
                else ""
            )
        )

    def _line_search(self, dofs, equilibrium, state, frames, delta, ratio, push):
        """Backtracking along the Newton step: (scale, new state, its ratio, its forces).

        The full Newton step of a large rotation first moves along the tangent and stretches
        the structure, so a growing residual is normal for one iteration; only a blow-up (or a
        non-finite state) is cut back, halving the step up to 5 times. Before that, a step
        that would turn a director by more than MAX_ROTATION or move a node by more than the
        model's size is scaled down to that (``_step_cap``).
        """
        scale = _step_cap(equilibrium.model, delta) if self.line_search else 1.0
        for _ in range(6 if self.line_search else 1):
            with np.errstate(all="ignore"):  # a wild trial is judged, then cut back
                trial = dofs.advance(state, scale * delta, frames)
                _, ratio_new, forces = equilibrium.residual(trial, frames)
            if (
                not self.line_search
                or push
                or (np.isfinite(ratio_new) and ratio_new <= 10.0 * max(ratio, self.tol))
            ):
                break
            scale *= 0.5
        if not np.isfinite(ratio_new):
            raise _Failed("non-finite residual after the line search")
        return scale, trial, ratio_new, forces

    @staticmethod
    def _report_stability(negative: bool, load_factor: float, info: dict, progress) -> None:
        """Record a converged state whose tangent has det(K_ff) < 0: an odd number of negative
        eigenvalues, i.e. an unstable equilibrium (past a limit point or a bifurcation)."""
        if negative:
            info["indefinite_at"].append(load_factor)
            progress(
                f"load factor {load_factor:.4g}: the tangent stiffness is indefinite "
                "(det K < 0): an unstable equilibrium, past a limit point or a bifurcation",
                force=True,
            )

    def _loads(self, model, load_factor):
        """Dead forces, moments and imposed displacements (n, 3) each at a load factor: all
        ramped together, or with ``step_loads_first`` the "step" loads over [0, 1] (imposed
        displacements held at zero) and then the rest over [1, 2]."""
        force, moment = model.external_load(1.0, quasi_static=True)
        imposed = model.prescribed_displacement(1.0, quasi_static=True)
        if not self.step_loads_first:
            return load_factor * force, load_factor * moment, load_factor * imposed
        # A "step" amplitude is 1 for any positive progress, a ramped one is proportional.
        step_force, step_moment = model.external_load(1e-300, quasi_static=True)
        first = min(load_factor, 1.0)
        then = max(load_factor - 1.0, 0.0)
        return (
            first * step_force + then * (force - step_force),
            first * step_moment + then * (moment - step_moment),
            then * imposed,
        )

    def _result(self, compiled, frames, info, started, converged):
        result = empty_result(compiled, frames)
        result.steps = int(sum(info["iterations_per_increment"]))
        result.wall_time = time.perf_counter() - started
        result.converged = converged
        result.info = dict(info, tol=self.tol)
        return result


def _downhill(k_ff, rhs, delta, load, translation, size, push) -> np.ndarray:
    """The Newton step with its components along the negative modes of K_ff turned downhill.

    A Newton step heads for the nearest equilibrium, stable or not. Along a mode phi with
    eigenvalue lambda < 0 (of the symmetric part), its component (phi . r) / lambda climbs
    the energy towards the saddle; the step is given the component (phi . r) / |lambda|
    instead, at least half an element long when ``push`` (leaving a converged saddle), in the
    direction where the external load does positive work (gravity picks the buckling side).
    """
    values, vectors = _lowest_modes(k_ff)
    delta = delta.copy()
    for value, phi in zip(values, vectors.T):
        if value >= 0.0:
            continue
        along = phi @ rhs
        wanted = along / abs(value)
        reach = np.abs(phi[translation]).max(initial=0.0)
        if push and reach > 0.0 and abs(wanted) < 0.5 * size / reach:
            side = np.sign(phi @ load) or np.sign(along) or 1.0
            wanted = side * 0.5 * size / reach
        delta += (wanted - phi @ delta) * phi
    return delta


def _lowest_modes(k_ff) -> tuple[np.ndarray, np.ndarray]:
    """The (up to) 6 eigenvalues of the symmetric part of K_ff nearest zero, with their unit
    eigenvectors (columns); empty when ARPACK fails or the matrix is tiny."""
    n = k_ff.shape[0]
    if n <= 200:  # small: all of them, densely (ARPACK needs k < n - 1)
        values, vectors = np.linalg.eigh(0.5 * (k_ff + k_ff.T).toarray())
        return values[:6], vectors[:, :6]
    count = 6
    symmetric = (0.5 * (k_ff + k_ff.T)).tocsc()
    try:
        # A fixed start vector: ARPACK's default is a random one drawn from a generator that
        # advances with every call in the process, so the modes (and a push decided on an
        # eigenvalue near zero) would depend on what ran before in the same process.
        start = np.random.default_rng(0).standard_normal(n)
        return eigsh(symmetric, k=count, sigma=0.0, which="LM", v0=start)
    except (RuntimeError, ArpackNoConvergence):
        return np.zeros(0), np.zeros((n, 0))


def _solve(k_ff: sp.csc_matrix, rhs: np.ndarray) -> tuple[np.ndarray | None, bool]:
    """Sparse LU solve, or None when the matrix is (numerically) singular; and whether
    det(K) < 0, from the signs of U's diagonal and of the two permutations (L has a unit
    diagonal)."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", MatrixRankWarning)
        try:
            lu = splu(k_ff)
            solution = lu.solve(rhs)
        except (RuntimeError, MatrixRankWarning):
            return None, False
    if not np.all(np.isfinite(solution)):
        return None, False
    odd = np.count_nonzero(lu.U.diagonal() < 0) + _odd(lu.perm_r) + _odd(lu.perm_c)
    return solution, bool(odd % 2)


def _odd(permutation: np.ndarray) -> int:
    """1 if the permutation is odd (n minus its number of cycles is odd), else 0."""
    seen = np.zeros(permutation.size, dtype=bool)
    cycles = 0
    for start in range(permutation.size):
        if not seen[start]:
            cycles += 1
            j = start
            while not seen[j]:
                seen[j] = True
                j = permutation[j]
    return (permutation.size - cycles) % 2


# Largest director rotation of one Newton update (rad). Far from equilibrium the tangent of a
# layered shell can ask for director turns of several radians, which lead Newton into states
# with collapsed cells or fibres stretched by orders of magnitude, where a log-strain
# tension law still balances (bai-5.1, fibrous: |u| = 1e51 at "equilibrium").
MAX_ROTATION = 0.5


def _step_cap(model: CompiledModel, delta: np.ndarray) -> float:
    """The factor (<= 1) that keeps an update delta (n, 5) within MAX_ROTATION of director
    rotation at every node and within the model's size (its bounding-box diagonal) of
    translation."""
    extent = float(np.linalg.norm(np.ptp(model.reference_positions, axis=0)))
    translation = float(np.linalg.norm(delta[:, :3], axis=1).max(initial=0.0))
    rotation = float(np.linalg.norm(delta[:, 3:], axis=1).max(initial=0.0))
    cap = 1.0
    if rotation > MAX_ROTATION:
        cap = MAX_ROTATION / rotation
    if extent > 0.0 and translation > extent:
        cap = min(cap, extent / translation)
    return cap


class _Equilibrium:
    """The residual at one load factor: dead loads, the prescribed target and the ratio by
    which convergence is judged."""

    def __init__(self, model: CompiledModel, f_ext, m_ext, imposed):
        self.model, self.f_ext, self.m_ext = model, f_ext, m_ext
        self.target = model.reference_positions + imposed if model.has_prescribed else None

    def remaining(self, state: State) -> np.ndarray:
        """(n, 5) prescribed motion not yet applied."""
        out = np.zeros((self.model.n_nodes, N_COLUMNS))
        if self.target is not None:
            out[:, :3] = np.where(
                self.model.translation_prescribed, self.target - state.positions, 0.0
            )
        return out

    def load(self, frames: Frames) -> np.ndarray:
        """(n, 5) external loads in generalised components."""
        return self.model.dofs.generalised(frames, self.f_ext, self.m_ext)

    def residual(self, state: State, frames: Frames, forces=None):
        """(r (n, 5) on the free DOFs, ratio, internal forces) at ``state``; ``forces`` reuses
        an evaluation of the internal forces at that state."""
        model, f_ext, m_ext = self.model, self.f_ext, self.m_ext
        f_int, m_int = forces if forces is not None else model.internal_force(state)
        r = np.where(
            model.dofs.free, model.dofs.generalised(frames, f_ext - f_int, m_ext - m_int), 0.0
        )
        # One scale for both: a moment M counts as the force M / (element size), so that a
        # pure-moment load (zero forces at equilibrium) has a force reference too.
        size = model.element_size
        force_ref = max(
            float(np.linalg.norm(f_ext)),
            float(np.linalg.norm(f_int)),
            float(np.linalg.norm(m_ext)) / size,
            float(np.linalg.norm(m_int)) / size,
            1e-300,
        )
        moment_ref = force_ref * size
        ratio = float(
            max(np.linalg.norm(r[:, :3]) / force_ref, np.linalg.norm(r[:, 3:]) / moment_ref)
        )
        if not (np.isfinite(force_ref) and np.isfinite(ratio)):
            # An overflowing state would otherwise divide its own residual by an infinite
            # reference and pass as converged.
            ratio = np.inf
        return r, ratio, (f_int, m_int)


class _Tangent:
    """(K_ff, K_fp) of the model at a state in the iteration's frames: the blocks' own tangents
    (``own``: block indices) assembled by femcore.assembly, plus coloured finite differences
    of the other blocks' forces."""

    def __init__(self, model: CompiledModel, own: list[int], others: list[int], first=None):
        """``first``: (state, {block index: parts}) already evaluated, reused at that state."""
        self.model, self.own, self.others = model, own, others
        self.first = first
        self.assemble = FreeTangentAssembler(model.dofs)
        self.graph = model.node_graph(others) if others else None

    def __call__(self, state: State, frames: Frames):
        model, dofs = self.model, self.model.dofs
        parts: list[TangentPart] | None
        if self.first is not None and state is self.first[0]:
            parts = [part for i in self.own for part in self.first[1][i]]
        else:
            parts = model.tangent_parts(state, self.own)
        if parts is None:
            raise RuntimeError(
                "an element block gave a tangent at the start of the solve and none later: a "
                "block's tangent() returns None always or never"
            )
        k_ff, k_fp = self.assemble(parts, frames)
        if self.graph is not None:
            k = model.finite_difference_stiffness(state, self.others, self.graph, frames)
            free, moved = dofs.free_slots, dofs.prescribed_slots
            k_ff = (k_ff + k[free][:, free]).tocsc()
            k_fp = k_fp + k[free][:, moved]
        return k_ff, k_fp


class _Failed(Exception):
    """An increment that did not converge (caught to cut the increment)."""
