"""Static: Newton-Raphson on the free DOFs, along the load or along the arc length of the
equilibrium path.

Loads and prescribed displacements are scaled by one load factor lambda, all of them (gravity
and "step" loads included) ramped linearly with it, as a static step does: amplitudes shape
time histories in dynamics only. Each converged increment gives one frame.

Two ways along the path (``path``):

- "load": ``increments`` equal load-factor steps; an increment that does not converge is cut in
  half and retried from the last converged state.
- "arc_length": Crisfield's cylindrical arc-length method (docs/theory.md §6.6): lambda is an
  unknown, and each increment moves a fixed distance along the path in the space of the nodal
  motions (translations, and director rotations times the element size), so that limit points
  (the load passes a maximum), snap-backs and post-buckling branches are followed instead of
  jumped over. The step length adapts to the number of iterations the previous increment
  needed; the last increment lands on lambda = 1 exactly.

Unknowns per node: ux uy uz and, at shell nodes, alpha beta: small rotations of the director
about V2 and V1 of its nodal frame (Bai Eq. 7, 13; docs/theory.md §1.3), applied as finite
rotations.

Each Newton iteration:

- predictor: on the arc-length path (and on the load path with ``predictor=True``), from the
  second increment on, the previous increment extrapolated (the secant of the path,
  translations and director rotations);
- tangent: the blocks' own ``tangent`` where they give one, assembled in the generalised
  coordinates of femcore.dofs by femcore.assembly; for the other blocks, K = dF_int/dq by
  central differences with a colouring of the node graph (femcore.assembly.NodeGraph), 10 x
  (number of colours) force evaluations whatever the mesh size;
- linear solve: an LDL^T of K_ff whose symbolic factorisation is kept between iterations
  (solvers.linear), its negative pivots counting the negative eigenvalues of K_ff;
- line search (load path), a watchdog (Chamberlain, Powell, Lemarechal and Pedersen, Math.
  Prog. Study 16 (1982) 1): full Newton steps are taken as long as, within WATCHDOG
  iterations, one of them lowers the residual norm below that of the best iterate so far or
  the total potential energy (by the Armijo fraction of the first-order decrease of the step
  that left the best iterate; the energy is evaluated only when the residual does not show
  the decrease). Otherwise the iteration goes back to the best iterate and
  backtracks along its Newton step (halving, down to 1/64) until one of the two falls; when
  none does, the line search says no and the increment is cut. Full steps first because the
  first iterations of a large rotation climb the energy on the way (the straight update
  stretches the membrane) and still reach the equilibrium in a few steps, where a
  monotone line search would crawl.
"""

from __future__ import annotations

import time
from dataclasses import replace
from typing import Any

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import ArpackNoConvergence, eigsh

from femcore.assembly import FreeTangentAssembler, TangentPart
from femcore.dofs import N_COLUMNS, Frames
from femcore.model import CompiledModel, Model
from femcore.results import Result
from femcore.rotation import cross, rotate_about
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
from solvers.linear import Factorisation, LinearSolver

__all__ = ["PATHS", "Static"]

PATHS = ("load", "arc_length")

# Armijo's sufficient-decrease fraction, the smallest line-search step, and how many full
# Newton steps the watchdog lets go by without a decrease before it backtracks.
ARMIJO = 1e-4
SMALLEST_STEP = 1.0 / 64.0
WATCHDOG = 4
# A load step that leaves a limit point (at_limit="jump") may take this many times
# max_iterations: the stable branch beyond a snap is far.
JUMP_ITERATIONS = 5
# The shift sigma of the descent off a limit point (Static._descend), in units of the
# Gershgorin row sums of the tangent: below the floor it is dropped (plain Newton), and at the
# ceiling K + sigma G is diagonally dominant many times over.
SHIFT_FLOOR = 1e-6
SHIFT_CEILING = 1e3
# Iterations an arc-length increment should take: the next step length is scaled by
# sqrt(DESIRED_ITERATIONS / iterations taken) (Crisfield), within [1/2, 2].
DESIRED_ITERATIONS = 5
# The longest arc-length step, in lengths of the first one (4 jumped the fold of the von Mises
# truss at 12 increments and saved nothing on bai-5.1: 19.3 s against 17.5 s).
LONGEST_STEP = 1.0


class Static:
    """Quasi-static solver: Newton-Raphson on the free DOFs with a sparse tangent.

    increments : load path: the number of equal load-factor steps (one frame each); arc-length
        path: sets the first step, whose load-factor increment is 1 / increments (later steps
        adapt).
    tol : convergence when ||r_forces|| <= tol F_ref and ||r_moments|| <= tol F_ref L_e (or,
        at the round-off floor, when a full Newton step moves no DOF by more than 1e-9 of an
        element or 1e-9 rad while the ratio is below 1e-3), with
        F_ref = max(||F_ext||, ||F_int||, ||M_ext|| / L_e, ||M_int|| / L_e) (the internal
        forces include the reactions) and L_e the median element edge.
    max_iterations : Newton iterations per (sub-)increment before it is cut in half.
    line_search : the Armijo line search of the load path (module docstring); without it
        every Newton step is taken whole (after the step cap below).
    max_cuts : how many times an increment may be halved before a ConvergenceError.
    path : "load" (default) or "arc_length" (module docstring).
    max_increments : arc-length path: the most increments per phase before a ConvergenceError
        (default 20 x increments + 20).
    at_limit : arc-length path, at a limit point (the load factor would have to fall):
        "follow" (default) the path down and on, as it is; "jump": go on with load steps of
        1 / increments from there to the end of the phase, which land on the stable branch
        beyond the snap (seek_stable, line search), as a test under growing load or
        displacement does. Each such limit is listed in ``info["jumps"]``.
    predictor : load path: start each increment after the first of a phase from the previous
        increment extrapolated (module docstring) instead of the last converged state. Off by
        default: on the strips of the tests and benchmarks it saved nothing and cost the last
        roll-up increment 9 iterations (the chord of a turning strip stretches it).
    seek_stable : when the tangent of a converged state has negative eigenvalues (an unstable
        equilibrium: a compressed plate that stayed flat), leave it along its lowest mode and
        settle on the stable branch. Load path: the Newton steps that meet an indefinite
        tangent are turned downhill along its negative modes (a "saddle-free" step) and a
        converged saddle is pushed by half an element along its mode, up to three times per
        increment; the stable branch beyond a snap-through is then found (the jump a
        quasi-static test shows), not the unstable part of the path. Arc-length path: where
        the count of negative eigenvalues grows while the load keeps its direction (a
        bifurcation, not a limit point), the next increment starts along the buckling mode
        (up to three times per phase). Each switch is listed in ``info["branch_switches"]``.
    step_loads_first : apply the loads whose amplitude is "step" (gravity by default) first,
        over load factors 0 to 1 with the prescribed displacements held at zero, then the
        other loads and the prescribed displacements over 1 to 2 (a specimen hangs under its
        weight before a support moves it). Frames then run over load factors 0 to 2.
    tangent : "element" (default): each block's own ``tangent`` where it has one, coloured
        finite differences of ``internal_force`` for the others; "finite_difference": coloured
        finite differences for every block.
    progress : print status lines (None: only on an interactive terminal).

    Prescribed displacements enter each iteration consistently: the update solves
    K_ff dq_f = r_f - K_fp dq_p for the part dq_p of the prescribed motion not yet applied, so
    the first iteration of an increment moves the structure with the imposed nodes instead of
    dragging them alone.

    Stability: every converged state gets the number of negative eigenvalues of its tangent
    K_ff, counted from the pivots of its LDL^T (``info["negative_eigenvalues"]``, one entry per
    frame after the first); load factors with a non-zero count (unstable equilibria, past a
    limit point or a bifurcation) are listed in ``info["indefinite_at"]``. A singular tangent
    is regularised for one update (see ``_newton``) and reported if the increment then fails.
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
        path: str = "load",
        max_increments: int | None = None,
        at_limit: str = "follow",
        predictor: bool = False,
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
        if path not in PATHS:
            raise ValueError(f"path must be one of {PATHS}, got {path!r}")
        self.path = path
        self.max_increments = (
            20 * self.increments + 20
            if max_increments is None
            else check_integer(max_increments, "max_increments")
        )
        if at_limit not in ("follow", "jump"):
            raise ValueError(f"at_limit must be 'follow' or 'jump', got {at_limit!r}")
        self.at_limit = at_limit
        self.predictor = bool(predictor)
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
            ``info``: iterations per increment, cuts, the negative-eigenvalue count of each
            frame, branch switches, evaluation counts and the linear-solver statistics.

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
        run = _Run(self, compiled)
        phases = 2 if self.step_loads_first else 1
        for phase in range(phases):
            run.phase = phase
            if self.path == "load":
                self._load_path(run, phase)
            else:
                self._arc_length_path(run, phase)
        return run.result(True)

    # ------------------------------------------------------------------ load path
    def _load_path(self, run: _Run, phase: int, jump: bool = False) -> None:
        """``increments`` equal steps of the load factor over [phase, phase + 1]. ``jump``:
        the first step leaves a limit point; the way to the stable branch beyond is long, and
        that step may take JUMP_ITERATIONS x max_iterations Newton iterations."""
        step = 1.0 / self.increments
        iterations_allowed = JUMP_ITERATIONS * self.max_iterations if jump else None
        for increment in range(1, self.increments + 1):
            target = phase + increment / self.increments
            if target <= run.reached + 1e-12:  # reached by an arc-length path already
                continue
            iterations = 0
            cuts_here = 0
            while run.reached < target - 1e-12:
                # Land on the target exactly: sums of step fractions miss it by rounding.
                trial = target if run.reached + step >= target - 1e-12 else run.reached + step
                start = run.predict(trial)
                try:
                    if iterations_allowed is not None:
                        converged, count, ratio, history = self._descend(
                            run, start, trial, iterations_allowed
                        )
                    else:
                        converged, count, ratio, history = self._newton(run, start, trial)
                except _Failed as failure:
                    total = self.increments * (2 if self.step_loads_first else 1)
                    cuts_here = run.cut(
                        cuts_here,
                        f"increment {increment + phase * self.increments}/{total}",
                        failure,
                    )
                    step = 0.5 * (trial - run.reached)
                    continue
                iterations += count
                iterations_allowed = None
                run.accept(converged, trial)
                # After a cut, grow the step back towards the nominal one.
                step = min(1.0 / self.increments, 2.0 * step)
            run.frame(iterations, ratio, history)

    def _newton(
        self, run: _Run, state: State, load_factor: float, max_iterations: int | None = None
    ):
        """Newton-Raphson at one load factor from ``state``.

        Returns (converged state, iterations, final ratio, ratio per iteration starting with
        the ratio before the first update); raises _Failed when the increment has to be cut.
        """
        model = run.model
        dofs = model.dofs
        equilibrium = run.equilibrium(load_factor)
        index, moved_index = dofs.free_slots, dofs.prescribed_slots
        size = model.element_size
        singular = False
        escapes = 0
        translation = index % N_COLUMNS < 3
        factor: Factorisation | None = None
        forces = None  # the internal forces of the accepted trial, reused next iteration
        history: list[float] = []
        watchdog = _Watchdog(run, equilibrium, self.line_search)
        allowed = max_iterations or self.max_iterations
        for iteration in range(1, allowed + 1):
            frames = dofs.frames(state.directors)
            r, ratio, forces = equilibrium.residual(state, frames, forces)
            left = equilibrium.remaining(state)
            history.append(ratio)
            if not np.isfinite(ratio):
                raise _Failed("non-finite residual")
            push = False
            if ratio <= self.tol and np.abs(left).max(initial=0.0) <= 1e-9 * size:
                if factor is None:  # no factorisation yet: one for the stability report
                    factor = run.factorise(run.tangent(state, frames)[0])
                negative = factor.negative or 0
                if not (negative and self.seek_stable and escapes < 3):
                    return run.settled(state, factor), iteration - 1, ratio, history
                # An unstable equilibrium: leave it along its buckling mode.
                escapes += 1
                push = True
                run.info["branch_switches"].append(load_factor)
                run.progress(
                    f"load factor {load_factor:.4g}: unstable equilibrium, leaving it along "
                    "the buckling mode",
                    force=True,
                )
            k_ff, k_fp = run.tangent(state, frames)
            rhs = r.ravel()[index]
            if moved_index.size:
                rhs = rhs - k_fp @ left.ravel()[moved_index]
            factor = run.factorise(k_ff)
            delta_free = factor.solve(rhs)
            if delta_free is None:
                # Exactly singular: a straight stress-free cable or membrane has no transverse
                # stiffness until it sags. A spring of 1e-6 x the largest diagonal on every
                # free unknown, for this update only, gives a finite step; the residual stays
                # exact, so a converged state is still an exact equilibrium. A mechanism or a
                # rigid motion under load keeps failing and is reported as singular.
                shift = 1e-6 * np.abs(k_ff.diagonal()).max(initial=0.0)
                factor = run.factorise(k_ff + shift * sp.identity(index.size, format="csc"))
                delta_free = factor.solve(rhs)
                singular = True
                run.info["regularised_iterations"] += 1
                if delta_free is None:
                    raise _Failed(f"singular tangent stiffness: {_mechanism(model)}")
            if (factor.negative or escapes) and self.seek_stable:
                load = equilibrium.load(frames).ravel()[index]
                delta_free = _downhill(
                    k_ff, rhs, delta_free, load, translation, size, push, factor.negative
                )
            flat = left.ravel().copy()
            flat[index] = delta_free
            delta = flat.reshape(-1, N_COLUMNS)
            imposing = bool(np.abs(left).max(initial=0.0) > 0.0)
            scale, state, forces = watchdog.step(state, frames, delta, r, push or imposing)
            # Round-off floor: the internal forces come from differences of nearly equal
            # metrics, so a tiny load on a stiff shell can leave a residual of ~1e-4 of the
            # load that no update removes. A full step that moves nothing (1e-9 of an element,
            # 1e-9 rad) with the residual already small is converged.
            if _at_round_off_floor(scale, delta, ratio, size):
                _, ratio, forces = equilibrium.residual(state, dofs.frames(state.directors))
                history.append(ratio)
                return run.settled(state, factor), iteration, ratio, history
            run.progress(
                f"load factor {load_factor:.4g}: iteration {iteration}, residual ratio "
                f"{history[-1]:.3g} (tol {self.tol:g})"
            )
        raise _Failed(
            f"residual ratio {history[-1]:.3g} after {allowed} iterations"
            + (f"; the tangent was singular: {_mechanism(model)}" if singular else "")
        )

    def _descend(self, run: _Run, state: State, load_factor: float, allowed: int):
        """The load step off a limit point: Newton on (K + sigma G) d = r, G the Gershgorin
        row sums |K| 1 of the tangent (diagonal), as a Levenberg-Marquardt minimisation of
        the total potential. A shift that leaves negative pivots is raised (x 4), so every
        step goes downhill, and one that lowers the potential by the Armijo fraction is
        lowered (/ 4) and dropped below SHIFT_FLOOR, so the last iterations are Newton's and
        converge quadratically. With sigma >= 1, K + sigma G is diagonally dominant, hence
        positive definite: a step always exists. This follows the snap of a test under
        growing displacement to a stable state (a minimum of the potential), where Newton
        with pushes along the negative modes wandered for hundreds of iterations (bai-6.1.2,
        Mindlin: 718 iterations, each with an eigen solve).

        Same returns as _newton; a converged state that is still unstable (a saddle, reached
        only by accident) is handed to _newton, which leaves it along its buckling mode.
        """
        model = run.model
        dofs = model.dofs
        equilibrium = run.equilibrium(load_factor)
        index, moved_index = dofs.free_slots, dofs.prescribed_slots
        size = model.element_size
        history: list[float] = []
        shift = 0.0
        potential = None  # strain energy of the current iterate, when known
        for iteration in range(1, allowed + 1):
            frames = dofs.frames(state.directors)
            r, ratio, _ = equilibrium.residual(state, frames)
            left = equilibrium.remaining(state)
            history.append(ratio)
            if not np.isfinite(ratio):
                raise _Failed("non-finite residual")
            k_ff, k_fp = run.tangent(state, frames)
            if ratio <= self.tol and np.abs(left).max(initial=0.0) <= 1e-9 * size:
                factor = run.factorise(k_ff)
                if factor.negative:
                    state, count, ratio, more = self._newton(run, state, load_factor, allowed)
                    return state, iteration - 1 + count, ratio, history + more[1:]
                return run.settled(state, factor), iteration - 1, ratio, history
            rhs = r.ravel()[index]
            imposing = bool(np.abs(left).max(initial=0.0) > 0.0)
            if moved_index.size:
                rhs = rhs - k_fp @ left.ravel()[moved_index]
            rows = np.asarray(abs(k_ff).sum(axis=1)).ravel()
            rows[rows <= 0.0] = 1.0
            while True:
                matrix = k_ff + shift * sp.diags(rows, format="csc") if shift else k_ff
                factor = run.factorise(matrix)
                delta_free = factor.solve(rhs) if not factor.negative else None
                if delta_free is None:
                    if shift >= SHIFT_CEILING:
                        raise _Failed(f"no stable descent: {_mechanism(model)}")
                    shift = max(4.0 * shift, SHIFT_FLOOR)
                    continue
                flat = left.ravel().copy()
                flat[index] = delta_free
                delta = flat.reshape(-1, N_COLUMNS)
                cap = _step_cap(model, delta)
                trial = dofs.advance(state, cap * delta, frames)
                if imposing:  # the prescribed motion changes the problem: no comparison
                    potential = None
                    break
                if potential is None:
                    potential = run.energy(state)
                after = run.energy(trial)
                work = cap * float(equilibrium.load(frames).ravel() @ delta.ravel())
                slope = -float(rhs @ delta_free)  # dPi/ds at s = 0, < 0 with K + sigma G > 0
                drop = potential - (after - work)
                if np.isfinite(after) and drop >= -ARMIJO * cap * slope:
                    potential = after
                    shift = shift / 4.0 if shift / 4.0 >= SHIFT_FLOOR else 0.0
                    break
                if shift >= SHIFT_CEILING:
                    raise _Failed("the shifted Newton steps no longer lower the potential")
                shift = max(4.0 * shift, SHIFT_FLOOR)
            state = trial
            run.progress(
                f"load factor {load_factor:.4g}: descent iteration {iteration}, residual ratio "
                f"{ratio:.3g}, shift {shift:.3g}"
            )
        raise _Failed(f"residual ratio {history[-1]:.3g} after {allowed} descent iterations")

    # ------------------------------------------------------------------ arc-length path
    def _arc_length_path(self, run: _Run, phase: int) -> None:
        """Crisfield's cylindrical arc length over the load factors [phase, phase + 1]."""
        end = phase + 1.0
        pattern = run.pattern(phase)
        if not any(np.any(part) for part in pattern):
            # Nothing is applied in this phase (step_loads_first without "step" loads): the
            # state stays where it is.
            run.accept(run.state, end)
            run.frame(0, 0.0, [0.0])
            return
        arc: float | None = None  # step length (the scaled norm of _Motion)
        previous: _Motion | None = None  # the last converged increment
        # The longest step: LONGEST_STEP x that of the first increment (lambda up by
        # 1 / increments), so that ``increments`` keeps a meaning of resolution along the path.
        longest: float | None = None
        switches = 0
        negative_before = run.negative
        for _ in range(self.max_increments):
            if run.reached >= end - 1e-12:
                return
            cuts_here = 0
            while True:
                prediction: _Motion | None = None
                try:
                    prediction = self._arc_predictor(run, pattern, arc, previous)
                    arc = prediction.length
                    outcome = None
                    if run.reached + prediction.load < end - 1e-12 or prediction.load <= 0.0:
                        outcome = self._arc_corrector(run, pattern, prediction)
                        if outcome[1] > end + 1e-12:  # it went past the end of the phase
                            prediction = run.motion_between(
                                run.state, run.reached, outcome[0], outcome[1]
                            )
                            outcome = None
                    if outcome is None:
                        # Land on the end of the phase with a load step along the secant.
                        fraction = (end - run.reached) / prediction.load
                        start = run.apply(prediction.scaled(fraction), end)
                        state, count, ratio, history = self._newton(run, start, end)
                        outcome = (state, end, count, ratio, history)
                    motion = run.motion_between(run.state, run.reached, *outcome[:2])
                    if (
                        self.at_limit == "jump"
                        and previous is not None
                        and previous.load > 0.0
                        and motion.load < 0.0
                    ):
                        # A limit point: the load would have to fall. Jump instead, as a
                        # test under growing load or displacement does, with load steps.
                        run.info["limit_points"].append(run.reached)
                        run.info["jumps"].append(run.reached)
                        run.progress(
                            f"load factor {run.reached:.4g}: limit point, jumping to the "
                            "stable branch with load steps",
                            force=True,
                        )
                        self._load_path(run, phase, jump=True)
                        return
                    if (
                        previous is not None
                        and not prediction.mode
                        and motion.vector @ previous.vector <= 0.0
                    ):
                        # At a limit point the load turns back, the motion does not: a step
                        # that reverses the motion jumped onto another part of the path.
                        raise _Failed("the step turned back along the path")
                    break
                except _Failed as failure:
                    cuts_here = run.cut(cuts_here, "arc-length increment", failure)
                    arc = 0.5 * arc if arc is not None else None
                    if prediction is not None and prediction.mode:
                        switches = 3  # the push did not work: stay on the path
            state, load_factor, count, ratio, history = outcome
            if previous is not None and previous.load * motion.load < 0.0:
                run.info["limit_points"].append(run.reached)
            run.accept(state, load_factor)
            run.frame(count, ratio, history)
            previous = motion
            # Crisfield's step-length rule: aim at DESIRED_ITERATIONS next time.
            arc = motion.length * float(
                np.clip(np.sqrt(DESIRED_ITERATIONS / max(count, 1)), 0.5, 2.0)
            )
            if longest is None:
                # The first step's length, stretched to the path length of a load step of
                # 1 / increments where the first step carried less (a path that starts soft:
                # its tangent predicts far more motion than the load gives).
                carried = max(motion.load, 1e-300)
                longest = LONGEST_STEP * motion.length * max(1.0, 1.0 / (self.increments * carried))
            arc = min(arc, longest)
            negative = run.negative
            if (
                self.seek_stable
                and switches < 3
                and negative is not None
                and negative_before is not None
                and negative > negative_before
                and motion.load > 0.0
            ):
                # More negative eigenvalues with the load still rising: a limit point just
                # passed, or a bifurcation. At a bifurcation the new mode does no work with the
                # load pattern (the load does not drive it); start the next increment along it.
                run.mode = run.buckling_mode(pattern, motion)
                if run.mode is not None:
                    switches += 1
                    run.info["branch_switches"].append(load_factor)
                    run.progress(
                        f"load factor {load_factor:.4g}: bifurcation, following the buckling mode",
                        force=True,
                    )
            negative_before = negative
        raise run.failure(
            f"the arc-length path did not reach load factor {end:g} in {self.max_increments} "
            "increments (raise max_increments, or the path turns back: the load cannot be "
            "carried)"
        )

    def _arc_predictor(self, run, pattern, arc, previous) -> _Motion:
        """The first guess of an increment: along the buckling mode after a bifurcation, along
        the previous increment (the secant) otherwise, or along the tangent at the start."""
        if run.mode is not None:
            mode, run.mode = run.mode, None
            return mode.scaled((arc if arc is not None else mode.length) / mode.length)
        if previous is not None and arc is not None:
            return previous.scaled(arc / previous.length)
        tangent = run.tangent_motion(pattern)
        first = tangent.scaled(1.0 / self.increments)
        return first if arc is None else tangent.scaled(arc / tangent.length)

    def _arc_corrector(self, run: _Run, pattern, prediction: _Motion):
        """Newton iterations on (free DOFs, lambda) on the cylinder ||motion|| = length around
        the last converged state. Returns (state, lambda, iterations, ratio, history)."""
        model = run.model
        dofs = model.dofs
        index = dofs.free_slots
        start, start_load = run.state, run.reached
        length = prediction.length
        load_factor = start_load + prediction.load
        state = run.apply(prediction, load_factor)
        history: list[float] = []
        factor = None
        for iteration in range(1, self.max_iterations + 1):
            frames = dofs.frames(state.directors)
            equilibrium = run.equilibrium(load_factor)
            r, ratio, _ = equilibrium.residual(state, frames)
            history.append(ratio)
            if not np.isfinite(ratio):
                raise _Failed("non-finite residual")
            if ratio <= self.tol:
                if factor is None:
                    factor = run.factorise(run.tangent(state, frames)[0])
                return run.settled(state, factor), load_factor, iteration - 1, ratio, history
            k_ff, k_fp = run.tangent(state, frames)
            factor = run.factorise(k_ff)
            load_rhs, u_pattern = run.load_rate(pattern, frames, k_fp)
            solved = factor.solve(np.column_stack([r.ravel()[index], load_rhs]))
            if solved is None:
                raise _Failed("singular tangent stiffness on the arc-length path")
            residual_part = np.zeros(dofs.n_slots)
            residual_part[index] = solved[:, 0]
            load_part = u_pattern.ravel().copy()
            load_part[index] = solved[:, 1]
            a = run.motion_between(start, start_load, state, load_factor).vector
            c = run.scaled_motion(residual_part.reshape(-1, N_COLUMNS), frames)
            b = run.scaled_motion(load_part.reshape(-1, N_COLUMNS), frames)
            d_load = _constraint_root(a, b, c, length)
            delta = (residual_part + d_load * load_part).reshape(-1, N_COLUMNS)
            cap = _step_cap(model, delta)
            load_factor += cap * d_load
            state = run.place(dofs.advance(state, cap * delta, frames), load_factor)
            if _at_round_off_floor(cap, delta, ratio, model.element_size) and abs(
                d_load
            ) <= 1e-9 * max(abs(prediction.load), 1e-300):
                _, ratio, _ = run.equilibrium(load_factor).residual(
                    state, dofs.frames(state.directors)
                )
                history.append(ratio)
                return run.settled(state, factor), load_factor, iteration, ratio, history
            run.progress(
                f"arc length: load factor {load_factor:.4g}, iteration {iteration}, residual "
                f"ratio {ratio:.3g} (tol {self.tol:g})"
            )
            if _stalled(history):
                raise _Failed(
                    f"no progress: residual ratio {min(history[-STALL_WINDOW:]):.3g} or more over "
                    f"the last {STALL_WINDOW} of {iteration} iterations"
                )
        raise _Failed(f"residual ratio {history[-1]:.3g} after {self.max_iterations} iterations")

    # ------------------------------------------------------------------ loads
    def loads(self, model: CompiledModel, load_factor: float):
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


# An arc-length increment whose last STALL_WINDOW residual ratios all stay above half the
# best one before them is cut at once rather than after max_iterations: on the paper cases
# such increments sat near ratio 0.9-1.0 for all 40 iterations (40 % of the tangents of a
# run), while those that converge after a slow start gain an order within 6 iterations. (The
# load path has its line search to refuse a step; a straight cable that must sag first
# gains little for a dozen iterations there and then converges.)
STALL_WINDOW = 6


def _stalled(history: list[float]) -> bool:
    """No progress in the last STALL_WINDOW iterations (checked from 2 STALL_WINDOW on)."""
    if len(history) < 2 * STALL_WINDOW:
        return False
    return min(history[-STALL_WINDOW:]) > 0.5 * min(history[:-STALL_WINDOW])


def _at_round_off_floor(scale: float, delta: np.ndarray, ratio: float, size: float) -> bool:
    """A full Newton update delta (n, 5) that moves no translation by more than 1e-9 of an
    element (size) and no rotation by more than 1e-9 rad, from a residual ratio already below
    1e-3: converged at the round-off floor of the internal forces."""
    moved = scale * np.abs(delta)
    return (
        scale == 1.0
        and ratio <= 1e-3
        and float(moved[:, :3].max(initial=0.0)) <= 1e-9 * size
        and float(moved[:, 3:].max(initial=0.0)) <= 1e-9
    )


def _mechanism(model: CompiledModel) -> str:
    """What a singular tangent means for this model, naming the rigid motions no support
    holds when there are any."""
    free = model.unheld_rigid_motions(loaded_only=False)
    if free:
        return "a mechanism: nothing holds the " + ", ".join(free)
    return "a mechanism (a part or a node that nothing holds) or a bifurcation"


def _constraint_root(a: np.ndarray, b: np.ndarray, c: np.ndarray, length: float) -> float:
    """The load-factor correction dl with ||a + c + dl b|| = length (Crisfield's cylinder): of
    the two roots, the one whose new increment points most along the current one (so that the
    path does not turn back on itself); without a real root, the dl nearest to the cylinder
    (Lam and Morley's fallback)."""
    ac = a + c
    qa = float(b @ b)
    qb = 2.0 * float(b @ ac)
    qc = float(ac @ ac) - length * length
    if qa <= 0.0:
        return 0.0
    disc = qb * qb - 4.0 * qa * qc
    if disc < 0.0:
        return -qb / (2.0 * qa)
    root = np.sqrt(disc)
    roots = ((-qb + root) / (2.0 * qa), (-qb - root) / (2.0 * qa))
    return max(roots, key=lambda dl: float((ac + dl * b) @ a))


def _downhill(k_ff, rhs, delta, load, translation, size, push, negative=None) -> np.ndarray:
    """The Newton step with its components along the negative modes of K_ff turned downhill.

    A Newton step heads for the nearest equilibrium, stable or not. Along a mode phi with
    eigenvalue lambda < 0 (of the symmetric part), its component (phi . r) / lambda climbs
    the energy towards the saddle; the step is given the component (phi . r) / |lambda|
    instead, at least half an element long when ``push`` (leaving a converged saddle), in the
    direction where the external load does positive work (gravity picks the buckling side).
    """
    values, vectors = _lowest_modes(k_ff, negative)
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


def _lowest_modes(k_ff, negative: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Eigenvalues of the symmetric part of K_ff with their unit eigenvectors (columns),
    ascending: the ``negative`` ones (at most 6) when the inertia says there are some, else
    the (up to) 6 nearest zero; empty when ARPACK fails.

    Both come from shift-invert about 0, where an eigenvalue l maps to 1 / l: the negative
    eigenvalues nearest zero are the smallest (most negative) 1 / l, and the eigenvalues
    nearest zero those of largest |1 / l|. The largest negative eigenvalue of a buckled plate
    may lie beyond several small positive ones, so asking for the nearest to zero alone can
    miss it."""
    n = k_ff.shape[0]
    if n <= 200:  # small: all of them, densely (ARPACK needs k < n - 1)
        values, vectors = np.linalg.eigh(0.5 * (k_ff + k_ff.T).toarray())
        count = min(max(negative or 0, 1), 6) if negative else 6
        return values[:count], vectors[:, :count]
    symmetric = (0.5 * (k_ff + k_ff.T)).tocsc()
    # A fixed start vector: ARPACK's default is a random one drawn from a generator that
    # advances with every call in the process, so the modes (and a push decided on an
    # eigenvalue near zero) would depend on what ran before in the same process.
    start = np.random.default_rng(0).standard_normal(n)
    try:
        if negative:
            values, vectors = eigsh(
                symmetric, k=min(negative, 6, n - 2), sigma=0.0, which="SA", v0=start
            )
        else:
            values, vectors = eigsh(symmetric, k=6, sigma=0.0, which="LM", v0=start)
    except (RuntimeError, ArpackNoConvergence):
        return np.zeros(0), np.zeros((n, 0))
    order = np.argsort(values)
    return values[order], vectors[:, order]


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

    def __init__(self, model: CompiledModel, f_ext, m_ext, imposed, counts=None):
        self.model, self.f_ext, self.m_ext = model, f_ext, m_ext
        self.counts = counts if counts is not None else {"residual": 0}
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
        if forces is None:
            self.counts["residual"] += 1
            forces = model.internal_force(state)
        f_int, m_int = forces
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


class _Watchdog:
    """The watchdog line search of the load path (module docstring).

    The merits of an iterate are its residual norm on the free DOFs and its total potential
    Pi relative to the best iterate: Pi(x) - Pi(best) = W(x) - W(best) - (the dead loads' work
    along the straight updates since the best iterate; exact for forces, and for moments on
    each update, a rotation about a fixed axis). The strain energies W are evaluated only when
    the residual does not already show the decrease.
    """

    def __init__(self, run: _Run, equilibrium: _Equilibrium, enabled: bool):
        self.run, self.equilibrium, self.enabled = run, equilibrium, enabled
        self.free = run.model.dofs.free.ravel()
        self.best: dict | None = None  # the best iterate and its Newton step
        self.work = 0.0  # dead-load work along the updates since the best iterate
        self.misses = 0

    def step(self, state: State, frames: Frames, delta: np.ndarray, r: np.ndarray, whole: bool):
        """The next iterate from ``state`` with Newton step delta (n, 5) and residual r (n, 5):
        (scale taken, new state, its internal forces); scale 0 when it went back."""
        cap = _step_cap(self.run.model, delta) if self.enabled else 1.0
        if not self.enabled or whole:
            self.best = None  # the imposed motion starts a new search
            return self._take(state, frames, delta, cap)
        here = {
            "state": state,
            "frames": frames,
            "delta": delta,
            "cap": cap,
            "residual": float(np.linalg.norm(r.ravel()[self.free])),
            "slope": -float(r.ravel()[self.free] @ delta.ravel()[self.free]),  # dPi/ds
            "energy": None,
        }
        if self.best is None or self._better(here):
            self.best, self.misses, self.work = here, 0, 0.0
        else:
            self.misses += 1
            if self.misses >= WATCHDOG:
                return self._backtrack()
        scale, trial, forces = self._take(state, frames, delta, cap)
        if not np.isfinite(self.equilibrium.residual(trial, frames, forces)[1]):
            return self._backtrack()
        return scale, trial, forces

    def _take(self, state, frames, delta, scale):
        run = self.run
        trial = run.model.dofs.advance(state, scale * delta, frames)
        forces = run.model.internal_force(trial)
        run.counts["residual"] += 1
        self.work += scale * float(self.equilibrium.load(frames).ravel() @ delta.ravel())
        return scale, trial, forces

    def _energy(self, entry: dict) -> float:
        if entry["energy"] is None:
            entry["energy"] = self.run.energy(entry["state"])
        return entry["energy"]

    def _better(self, here: dict) -> bool:
        """A real decrease from the best iterate: the residual norm by the Armijo fraction, or
        the energy by that fraction of the best step's first-order decrease."""
        best = self.best
        assert best is not None
        if here["residual"] <= (1.0 - ARMIJO) * best["residual"]:
            return True
        if best["slope"] >= 0.0:
            return False
        before, after = self._energy(best), self._energy(here)
        drop = before - (after - self.work)
        noise = 1e-10 * (abs(before) + abs(after))
        return drop >= -ARMIJO * best["slope"] and drop > noise

    def _backtrack(self):
        """Back to the best iterate, then halve its Newton step until the residual or the
        energy falls (Armijo); _Failed when none does down to SMALLEST_STEP."""
        best = self.best
        assert best is not None
        state, frames, delta = best["state"], best["frames"], best["delta"]
        load_rate = float(self.equilibrium.load(frames).ravel() @ delta.ravel())
        scale = 0.5 * best["cap"]
        while scale >= SMALLEST_STEP * best["cap"]:
            trial = self.run.model.dofs.advance(state, scale * delta, frames)
            r, ratio, forces = self.equilibrium.residual(trial, frames)
            if np.isfinite(ratio):
                residual = float(np.linalg.norm(r.ravel()[self.free]))
                accepted = residual <= (1.0 - ARMIJO * scale) * best["residual"]
                if not accepted and best["slope"] < 0.0:
                    change = self.run.energy(trial) - self._energy(best) - scale * load_rate
                    accepted = change <= ARMIJO * scale * best["slope"]
                if accepted:
                    self.best, self.misses, self.work = None, 0, 0.0
                    return 0.0, trial, forces
            scale *= 0.5
        raise _Failed("the line search found no step that lowers the energy or the residual")


class _Motion:
    """A change of configuration: translations (n, 3), director rotation vectors (n, 3, rad,
    global components) and a load-factor change, with the scaled norm of the arc-length
    constraint (rotations count as rotation x element size, so that both are lengths).
    ``mode``: a push along a buckling mode."""

    def __init__(self, translations, rotations, load: float, size: float, mode: bool = False):
        self.translations, self.rotations, self.load = translations, rotations, float(load)
        self.size, self.mode = size, mode
        self.vector = np.concatenate([translations.ravel(), size * rotations.ravel()])
        self.length = float(np.linalg.norm(self.vector))

    def scaled(self, factor: float) -> _Motion:
        return _Motion(
            factor * self.translations,
            factor * self.rotations,
            factor * self.load,
            self.size,
            self.mode,
        )


class _Run:
    """One solve in progress: the model, its tangent and linear solver, the last converged
    state and load factor, the frames and the info written so far."""

    def __init__(self, solver: Static, model: CompiledModel):
        self.solver, self.model = solver, model
        self.started = time.perf_counter()
        self.state = model.initial_state()
        self.reached = 0.0
        own_parts = model.own_tangents(self.state) if solver.tangent == "element" else {}
        own = list(own_parts)
        others = [i for i in range(len(model.parts)) if i not in own]
        self._tangent = _Tangent(model, own, others, (self.state, own_parts))
        self.linear = LinearSolver()
        self.frames = [make_frame(model, self.state)]
        self.strain_energies = [model.strain_energy(self.state)]  # one per frame, N mm
        self.progress = ProgressLine(resolve_progress(solver.progress), "static")
        self.negative: int | None = 0
        self.mode: _Motion | None = None  # the next arc-length increment starts along it
        self.last_motion: tuple[int, float, _Motion] | None = None  # (phase, lambda, motion)
        self.phase = 0
        self.counts = {"residual": 0, "energy": 0, "tangent": 0}
        self.info: dict[str, Any] = {
            "solver": "Static",
            "path": solver.path,
            "tangent": {
                "element": [type(model.parts[i]).__name__ for i in own],
                "finite_difference": [type(model.parts[i]).__name__ for i in others],
            },
            "load_factors": [],
            "iterations_per_increment": [],
            "cuts": 0,
            "tangent_colours": self._tangent.graph.n_colours if self._tangent.graph else 0,
            "residual_ratio_per_increment": [],
            "negative_eigenvalues": [],
            "indefinite_at": [],
            "limit_points": [],
            "jumps": [],
            "regularised_iterations": 0,
            "branch_switches": [],
            "residual_history": [],
            "evaluations": self.counts,
        }

    # ------------------------------------------------------------------ model evaluations
    def equilibrium(self, load_factor: float) -> _Equilibrium:
        force, moment, imposed = self.solver.loads(self.model, load_factor)
        return _Equilibrium(self.model, force, moment, imposed, self.counts)

    def pattern(self, phase: int):
        """(forces, moments, imposed displacements) per unit load factor in a phase."""
        upper = self.solver.loads(self.model, phase + 1.0)
        lower = self.solver.loads(self.model, float(phase))
        return tuple(a - b for a, b in zip(upper, lower))

    def energy(self, state: State) -> float:
        self.counts["energy"] += 1
        return self.model.strain_energy(state)

    def tangent(self, state: State, frames: Frames):
        self.counts["tangent"] += 1
        return self._tangent(state, frames)

    def factorise(self, k_ff) -> Factorisation:
        return self.linear.factorise(k_ff)

    # ------------------------------------------------------------------ configurations
    def place(self, state: State, load_factor: float) -> State:
        """The state with its prescribed translations at their values for ``load_factor``."""
        model = self.model
        if not model.has_prescribed:
            return state
        target = model.reference_positions + self.solver.loads(model, load_factor)[2]
        positions = np.where(model.translation_prescribed, target, state.positions)
        return replace(state, positions=positions)

    def apply(self, motion: _Motion, load_factor: float) -> State:
        """The last converged state moved by ``motion``, placed at ``load_factor``."""
        model, state = self.model, self.state
        directors = state.directors
        if model.dofs.any_rotation:
            turned = rotate_about(directors, motion.rotations)
            directors = np.where(model.has_rotation[:, None], turned, directors)
        moved = replace(state, positions=state.positions + motion.translations, directors=directors)
        return self.place(moved, load_factor)

    def motion_between(self, old: State, old_load, new: State, new_load) -> _Motion:
        """The motion from one state to another: translations and the rotation vectors that
        take each old director to the new one about their common normal."""
        axis = cross(old.directors, new.directors)
        sine = np.linalg.norm(axis, axis=1)
        cosine = np.sum(old.directors * new.directors, axis=1)
        angle = np.arctan2(sine, cosine)
        rotations = (
            axis * np.where(sine > 0.0, angle / np.where(sine > 0.0, sine, 1.0), 0.0)[:, None]
        )
        rotations[~self.model.has_rotation] = 0.0
        return _Motion(
            new.positions - old.positions,
            rotations,
            new_load - old_load,
            self.model.element_size,
        )

    def scaled_motion(self, delta: np.ndarray, frames: Frames) -> np.ndarray:
        """The scaled-norm vector (_Motion.vector) of a generalised increment delta (n, 5)."""
        return self.as_motion(delta, frames, 0.0).vector

    def as_motion(self, delta: np.ndarray, frames: Frames, load: float, mode=False) -> _Motion:
        rotations = np.zeros((self.model.n_nodes, 3))
        if frames is not None:
            v1, v2 = frames
            rotations = delta[:, 3:4] * v2 + delta[:, 4:5] * v1
            rotations[~self.model.has_rotation] = 0.0
        return _Motion(delta[:, :3].copy(), rotations, load, self.model.element_size, mode)

    def predict(self, load_factor: float) -> State:
        """Load path: the start of the Newton iteration at ``load_factor``: the last
        increment of the same phase extrapolated (the secant), else the last state."""
        if (
            not self.solver.predictor
            or self.last_motion is None
            or self.last_motion[0] != self.phase
        ):
            return self.state
        motion = self.last_motion[2]
        if motion.load <= 0.0:
            return self.state
        return self.apply(motion.scaled((load_factor - self.reached) / motion.load), load_factor)

    def load_rate(self, pattern, frames: Frames, k_fp) -> tuple[np.ndarray, np.ndarray]:
        """P = dR/dlambda on the free DOFs, F_pattern - K_fp U_pattern, and the prescribed
        motion per unit load factor U_pattern as a flat generalised vector (n_slots,)."""
        model, dofs = self.model, self.model.dofs
        rate = np.zeros((model.n_nodes, N_COLUMNS))
        rate[:, :3] = np.where(model.translation_prescribed, pattern[2], 0.0)
        drive = dofs.generalised(frames, pattern[0], pattern[1]).ravel()[dofs.free_slots]
        if dofs.prescribed_slots.size:
            drive = drive - k_fp @ rate.ravel()[dofs.prescribed_slots]
        return drive, rate.ravel()

    def tangent_motion(self, pattern) -> _Motion:
        """The motion per unit load factor along the tangent of the path at the last state:
        K_ff dq = dR/dlambda, with the prescribed DOFs moving at their rate."""
        dofs, state = self.model.dofs, self.state
        frames = dofs.frames(state.directors)
        k_ff, k_fp = self.tangent(state, frames)
        rhs, rate = self.load_rate(pattern, frames, k_fp)
        solved = self.factorise(k_ff).solve(rhs)
        if solved is None:
            raise _Failed("singular tangent stiffness at the start of the arc-length path")
        flat = rate.ravel()
        flat[dofs.free_slots] = solved
        motion = self.as_motion(flat.reshape(-1, N_COLUMNS), frames, 1.0)
        if motion.length == 0.0:
            raise _Failed("the loads of this phase move nothing")
        return motion

    def buckling_mode(self, pattern, previous: _Motion | None = None) -> _Motion | None:
        """The unit motion (no load change) along the lowest negative mode phi of the tangent
        at the last state, to the side where the loads do positive work; None if there is
        none, or if phi is the path's own direction: a limit point, which the arc length
        follows by itself. A limit point shows either way: the load pattern P drives the mode
        (|phi . P| > 0.1 |P|), or the mode is the last increment ``previous`` (the cosine of
        their scaled motions above 0.5; at a limit point the path's tangent is the null
        vector of K, while a bifurcation mode is transverse to the path). Under an imposed
        displacement P is spread over the whole model and phi may be local, so the first test
        alone took the limit point of bai-6.1.2 (Mindlin) for a bifurcation and sent the path
        back along itself."""
        dofs, state = self.model.dofs, self.state
        frames = dofs.frames(state.directors)
        k_ff, k_fp = self.tangent(state, frames)
        values, vectors = _lowest_modes(k_ff, self.negative or 1)
        negative = np.flatnonzero(values < 0.0)
        if negative.size == 0:
            return None
        phi = vectors[:, negative[np.argmax(values[negative])]]
        drive, _ = self.load_rate(pattern, frames, k_fp)
        if abs(phi @ drive) > 0.1 * np.linalg.norm(drive):
            return None
        load = self.equilibrium(self.reached).load(frames).ravel()[dofs.free_slots]
        side = np.sign(phi @ load) or 1.0
        flat = np.zeros(dofs.n_slots)
        flat[dofs.free_slots] = side * phi
        motion = self.as_motion(flat.reshape(-1, N_COLUMNS), frames, 0.0, mode=True)
        if motion.length <= 0.0:
            return None
        if previous is not None and previous.length > 0.0:
            along = motion.vector @ previous.vector / (motion.length * previous.length)
            if abs(along) > 0.5:
                return None
        return motion

    # ------------------------------------------------------------------ bookkeeping
    def settled(self, state: State, factor: Factorisation) -> State:
        """A converged state: note the inertia of its tangent."""
        self.negative = factor.negative
        return state

    def accept(self, state: State, load_factor: float) -> None:
        motion = self.motion_between(self.state, self.reached, state, load_factor)
        self.last_motion = (self.phase, load_factor, motion)
        self.reached = load_factor
        self.state = self.model.commit(replace(state, load_factor=load_factor, time=load_factor))

    def frame(self, iterations: int, ratio: float, history: list[float]) -> None:
        info, model, state = self.info, self.model, self.state
        info["load_factors"].append(self.reached)
        info["iterations_per_increment"].append(iterations)
        info["residual_ratio_per_increment"].append(ratio)
        info["residual_history"].append(history)
        info["negative_eigenvalues"].append(self.negative)
        if self.negative:
            info["indefinite_at"].append(self.reached)
            self.progress(
                f"load factor {self.reached:.4g}: the tangent stiffness has {self.negative} "
                "negative eigenvalue(s): an unstable equilibrium, past a limit point or a "
                "bifurcation",
                force=True,
            )
        f_ext, m_ext, _ = self.solver.loads(model, self.reached)
        reactions, reaction_moments = equilibrium_reactions(model, state, f_ext, m_ext)
        self.frames.append(make_frame(model, state, reactions, reaction_moments))
        self.strain_energies.append(model.strain_energy(state))
        self.progress(
            f"load factor {self.reached:.4g} converged in {iterations} Newton iterations",
            force=True,
            fraction=self.reached / (2.0 if self.solver.step_loads_first else 1.0),
        )

    def cut(self, cuts: int, what: str, failure: Exception) -> int:
        """Count one more cut of an increment (``cuts`` so far), or raise the ConvergenceError
        of ``failure`` when that makes more than the solver's max_cuts."""
        self.info["cuts"] += 1
        if cuts + 1 > self.solver.max_cuts:
            raise self.failure(f"{what} did not converge after {cuts} cuts ({failure})") from None
        return cuts + 1

    def failure(self, reason: str) -> ConvergenceError:
        hint = (
            "try path='arc_length' to follow a limit point"
            if self.solver.path == "load"
            else "try smaller increments or DynamicRelaxation"
        )
        error = ConvergenceError(
            f"static solver stopped at load factor {self.reached:.6g}: {reason}. A limit point "
            f"or buckling may be near: {hint}.",
            None,
        )
        if self.reached > self.frames[-1].load_factor:  # keep the last good state
            self.frames.append(make_frame(self.model, self.state))
            self.strain_energies.append(self.model.strain_energy(self.state))
        error.result = self.result(False)
        error.load_factor = self.reached
        return error

    def result(self, converged: bool) -> Result:
        result = empty_result(self.model, self.frames)
        result.steps = int(sum(self.info["iterations_per_increment"]))
        result.wall_time = time.perf_counter() - self.started
        result.converged = converged
        result.energies = {
            "time": np.array([frame.time for frame in self.frames]),
            "internal": np.array(self.strain_energies),
        }
        self.info["linear_solver"] = {
            "symbolic_factorisations": self.linear.symbolic,
            "numeric_factorisations": self.linear.numeric,
        }
        result.info = dict(self.info, tol=self.solver.tol)
        return result
