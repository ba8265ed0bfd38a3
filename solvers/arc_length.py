"""The arc-length path of the static solver (solvers.static.Static, ``path="arc_length"``):
Crisfield's cylindrical arc-length method (docs/theory.md §6.6).

The load factor lambda is an unknown, and each increment moves a fixed distance along the path
in the space of the nodal motions (translations, and director rotations times the element size;
``Motion``), so that limit points (the load passes a maximum), snap-backs and post-buckling
branches are followed instead of jumped over. The step length adapts to the number of
iterations the previous increment needed (Crisfield's rule), within the bounds of the load a
step may carry and of the path's turn (solvers.arc_step); the last increment lands on the end
of the phase exactly. Where the count of negative eigenvalues grows while the load keeps
its direction (a bifurcation), the next increment starts along the buckling mode
(solvers.stability).

With ``at_limit="jump"`` the path stops at the first limit point and the solver goes on with
load steps; the first of them crosses the snap by ``descend``, a shifted Newton that lowers the
total potential at every step.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp

from femcore.compiled_loads import evaluate
from femcore.dofs import N_COLUMNS
from femcore.state import State
from solvers.arc_step import ArcStep, iterations_spent
from solvers.common import check_integer, check_non_negative
from solvers.line_search import ARMIJO, model_extent, step_cap
from solvers.newton import IncrementFailed, at_round_off_floor, mechanism, newton
from solvers.round_off import RoundOffFloor
from solvers.stability import buckling_mode

if TYPE_CHECKING:
    from femcore.model import CompiledModel
    from solvers.static import StaticRun

__all__ = [
    "CHORD_GAIN",
    "LARGEST_CHORD_RATIO",
    "DESIRED_ITERATIONS",
    "changed_options",
    "JUMP_ITERATIONS",
    "SHIFT_CEILING",
    "SHIFT_FLOOR",
    "STALL_WINDOW",
    "Motion",
    "arc_length_path",
    "check_arc_options",
    "check_proportional",
    "constraint_root",
    "descend",
    "stalled",
    "tangent_motion",
]

# Iterations an arc-length increment should take by default (``Static(arc_iterations=...)``):
# the next step length is scaled by sqrt(arc_iterations / iterations taken) (Crisfield),
# within [1/2, 2].
DESIRED_ITERATIONS = 5
# A load step that leaves a limit point (at_limit="jump") may take this many times
# max_iterations: the stable branch beyond a snap is far.
JUMP_ITERATIONS = 5
# The shift sigma of the descent off a limit point (``descend``), in units of the Gershgorin
# row sums of the tangent: below the floor it is dropped (plain Newton), and at the ceiling
# K + sigma G is diagonally dominant many times over.
SHIFT_FLOOR = 1e-6
SHIFT_CEILING = 1e3
# An arc-length increment whose last STALL_WINDOW residual ratios all stay above half the
# best one before them is cut at once rather than after max_iterations: on the paper cases
# such increments sat near ratio 0.9-1.0 for all 40 iterations (40 % of the tangents of a
# run), while those that converge after a slow start gain an order within 6 iterations. (The
# load path has its line search to refuse a step; a straight cable that must sag first
# gains little for a dozen iterations there and then converges.)
STALL_WINDOW = 6
# A chord step (``Static(arc_chords=...)``) follows another only if the other lowered the
# residual ratio at least this many times over; else the iteration forms its tangent.
CHORD_GAIN = 0.1
# The largest ``arc_chords`` Static accepts. Crisfield's rule counts only the iterations that
# factorised, so an increment of many chord steps looks cheap and the next step is lengthened:
# at ratios near 1 that carried the von Mises truss from its near branch onto the far one past
# the unstable part (arc_chords 0.5), and at 0.1 its first limit came 6 % low. At 1e-2 and
# below every increment count from 3 to 20 found both limits (tests/test_arc_chords.py).
LARGEST_CHORD_RATIO = 1e-2


#: The arc-length path's own options of ``Static`` and their defaults (max_increments None:
#: 20 x increments + 20).
ARC_DEFAULTS = {
    "max_increments": None,
    "arc_iterations": DESIRED_ITERATIONS,
    "arc_chords": 0.0,
    "at_limit": "follow",
}


def changed_options(given: dict, defaults: dict) -> list[str]:
    """The options of ``given`` (name -> value) that differ from their ``defaults``, as
    "name=value": those a path would ignore, named in its refusal."""
    return [f"{name}={given[name]!r}" for name in defaults if given[name] != defaults[name]]


def check_arc_options(
    path: str, max_increments: object, arc_iterations: object, arc_chords: object, at_limit: object
) -> tuple[int, float, str]:
    """``Static``'s arc-length options checked: (arc_iterations, arc_chords, at_limit).

    Parameters
    ----------
    path : "load" or "arc_length", Static's path (already checked).
    max_increments, arc_iterations, arc_chords, at_limit : as given to Static.

    Raises
    ------
    ValueError
        arc_iterations not an integer >= 1, arc_chords not a ratio in [0,
        LARGEST_CHORD_RATIO], at_limit not "follow" or "jump"; any of the four other than its
        default with path="load", which does not use them (it would be ignored).
    """
    iterations = check_integer(arc_iterations, "arc_iterations")
    chords = check_non_negative(arc_chords, "arc_chords", "a residual ratio")
    if chords > LARGEST_CHORD_RATIO:
        raise ValueError(
            f"arc_chords must be at most {LARGEST_CHORD_RATIO:g} (a residual ratio at which "
            f"Newton is already near the path; larger ones let steps pass limit points), "
            f"got {arc_chords!r}"
        )
    if at_limit not in ("follow", "jump"):
        raise ValueError(f"at_limit must be 'follow' or 'jump', got {at_limit!r}")
    if path == "load":
        given = {
            "max_increments": max_increments,
            "arc_iterations": iterations,
            "arc_chords": chords,
            "at_limit": at_limit,
        }
        ignored = changed_options(given, ARC_DEFAULTS)
        if ignored:
            raise ValueError(
                f"{', '.join(ignored)} given with path='load': the arc-length path's options, "
                "which the load path does not use; expected path='arc_length' with them, or "
                "their defaults"
            )
    return iterations, chords, str(at_limit)


#: The load factors at which a user amplitude a(lambda) is checked against lambda a(1) on the
#: arc-length path (``check_proportional``), and the relative tolerance of that check.
PROPORTIONAL_SAMPLES = np.linspace(0.0, 1.0, 17)
PROPORTIONAL_TOLERANCE = 1e-9


def check_proportional(model: CompiledModel) -> None:
    """ValueError when a load or a prescribed displacement has a user amplitude a(lambda) that
    is not lambda a(1) (checked at PROPORTIONAL_SAMPLES): the arc length makes the load factor
    an unknown of loads F = lambda F_ref, one pattern (docs/theory.md §6.6), which such an
    amplitude is not."""
    for amplitude in model.user_amplitudes():
        function = amplitude.quasi_static
        # evaluate: a callable that fails or is not finite is named with where it failed.
        full = evaluate(amplitude, 1.0, True)
        values = np.array([evaluate(amplitude, lam, True) for lam in PROPORTIONAL_SAMPLES])
        expected = PROPORTIONAL_SAMPLES * full
        scale = max(abs(full), float(np.abs(values).max(initial=0.0)), 1e-300)
        worst = int(np.argmax(np.abs(values - expected)))
        if abs(values[worst] - expected[worst]) > PROPORTIONAL_TOLERANCE * scale:
            name = getattr(function, "__name__", repr(function))
            raise ValueError(
                f"the user amplitude {name} gives a({PROPORTIONAL_SAMPLES[worst]:g}) = "
                f"{values[worst]:.6g}, not lambda a(1) = {expected[worst]:.6g}: "
                "path='arc_length' scales one load pattern by an unknown load factor "
                "(F = lambda F_ref), so it cannot follow an amplitude's shape; expected "
                "path='load', which follows a(lambda), or DynamicRelaxation"
            )


class Motion:
    """A change of configuration: translations (n, 3), director rotation vectors (n, 3, rad,
    global components) and a load-factor change, with the scaled norm of the arc-length
    constraint (rotations count as rotation x element size, so that both are lengths).
    ``mode``: a push along a buckling mode."""

    def __init__(self, translations, rotations, load: float, size: float, mode: bool = False):
        self.translations, self.rotations, self.load = translations, rotations, float(load)
        self.size, self.mode = size, mode
        self.vector = np.concatenate([translations.ravel(), size * rotations.ravel()])
        self.length = float(np.linalg.norm(self.vector))

    def scaled(self, factor: float) -> Motion:
        return Motion(
            factor * self.translations,
            factor * self.rotations,
            factor * self.load,
            self.size,
            self.mode,
        )


def arc_length_path(run: StaticRun, phase: int) -> bool:
    """Crisfield's cylindrical arc length over the load factors [phase, phase + 1].

    Returns True when it stopped at a limit point to jump (``at_limit="jump"``): the solver
    then goes on with load steps from there to the end of the phase."""
    solver = run.solver
    end = phase + 1.0
    pattern = run.pattern(phase)
    if not any(np.any(part) for part in pattern):
        # Nothing is applied in this phase (step_loads_first without "step" loads): the
        # state stays where it is.
        run.accept(run.state, end)
        run.frame(0, 0.0, [0.0])
        return False
    arc: float | None = None  # step length (the scaled norm of Motion)
    previous: Motion | None = None  # the last converged increment
    step = ArcStep(solver.increments, solver.arc_iterations)
    switches = 0
    negative_before = run.negative
    for _ in range(solver.max_increments):
        if run.reached >= end - 1e-12:
            return False
        cuts_here = 0
        while True:
            prediction: Motion | None = None
            try:
                prediction = arc_predictor(run, pattern, arc, previous)
                arc = prediction.length
                outcome = None
                if run.reached + prediction.load < end - 1e-12 or prediction.load <= 0.0:
                    outcome = arc_corrector(run, pattern, prediction)
                    if outcome[1] > end + 1e-12:  # it went past the end of the phase
                        prediction = run.motion_between(
                            run.state, run.reached, outcome[0], outcome[1]
                        )
                        outcome = None
                if outcome is None:
                    # Land on the end of the phase with a load step along the secant.
                    fraction = (end - run.reached) / prediction.load
                    start = run.apply(prediction.scaled(fraction), end)
                    state, count, ratio, history = newton(run, start, end)
                    outcome = (state, end, count, ratio, history, 0)  # no arc chord steps
                motion = run.motion_between(run.state, run.reached, *outcome[:2])
                if (
                    solver.at_limit == "jump"
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
                    return True
                if (
                    previous is not None
                    and not prediction.mode
                    and motion.vector @ previous.vector <= 0.0
                ):
                    # At a limit point the load turns back, the motion does not: a step
                    # that reverses the motion jumped onto another part of the path.
                    raise IncrementFailed("the step turned back along the path")
                break
            except IncrementFailed as failure:
                cuts_here = run.cut(cuts_here, "arc-length increment", failure)
                # A phase's first step is the tangent's guess, and each failure shows it further
                # off: its k-th cut takes 1/2^k of the last length (1/2, 1/8, 1/64 of the guess;
                # docs/theory.md §6.6). A step after a converged one is halved.
                shrink = 0.5**cuts_here if previous is None else 0.5
                arc = shrink * arc if arc is not None else None
                if prediction is not None and prediction.mode:
                    switches = 3  # the push did not work: stay on the path
        state, load_factor, count, ratio, history, chord_steps = outcome
        if previous is not None and previous.load * motion.load < 0.0:
            run.info["limit_points"].append(run.reached)
        run.accept(state, load_factor)
        run.frame(count, ratio, history)
        previous = motion
        # Crisfield's rule within the bounds of the load carried and the path's turn
        # (solvers.arc_step), counting the iterations that factorised (a chord step costs one
        # solve).
        pushed = prediction is not None and prediction.mode
        spent = iterations_spent(history, count, chord_steps, solver.tol)
        arc = step.after(motion, spent, pushed)
        negative = run.negative
        if (
            solver.seek_stable
            and switches < 3
            and negative is not None
            and negative_before is not None
            and negative > negative_before
            and motion.load > 0.0
        ):
            # More negative eigenvalues with the load still rising: a limit point just
            # passed, or a bifurcation. At a bifurcation the new mode does no work with the
            # load pattern (the load does not drive it); start the next increment along it.
            run.mode = buckling_mode(run, pattern, motion)
            if run.mode is not None:
                switches += 1
                run.info["branch_switches"].append(load_factor)
                run.progress(
                    f"load factor {load_factor:.4g}: bifurcation, following the buckling mode",
                    force=True,
                )
        negative_before = negative
    raise run.failure(
        f"the arc-length path did not reach load factor {end:g} in {solver.max_increments} "
        "increments (raise max_increments, or the path turns back: the load cannot be "
        "carried)"
    )


def arc_predictor(run: StaticRun, pattern, arc, previous) -> Motion:
    """The first guess of an increment: along the buckling mode after a bifurcation, along
    the previous increment (the secant) otherwise, or along the tangent at the start."""
    if run.mode is not None:
        mode, run.mode = run.mode, None
        return mode.scaled((arc if arc is not None else mode.length) / mode.length)
    if previous is not None and arc is not None:
        return previous.scaled(arc / previous.length)
    tangent = tangent_motion(run, pattern)
    first = tangent.scaled(1.0 / run.solver.increments)
    return first if arc is None else tangent.scaled(arc / tangent.length)


def arc_corrector(run: StaticRun, pattern, prediction: Motion):
    """Newton iterations on (free DOFs, lambda) on the cylinder ||motion|| = length around
    the last converged state. Returns (state, lambda, iterations, ratio, history, chord
    steps), the chord steps (``Static(arc_chords=...)``) among the iterations (each also
    counted in ``run.info["arc_chords"]``)."""
    solver = run.solver
    model = run.model
    dofs = model.dofs
    index = dofs.free_slots
    extent = model_extent(model)
    start, start_load = run.state, run.reached
    length = prediction.length
    load_factor = start_load + prediction.load
    state = run.apply(prediction, load_factor)
    history: list[float] = []
    factor = None
    chords = 0  # chord steps in a row (``Static(arc_chords=...)``)
    chord_steps = 0  # chord steps in all
    # The residual's round-off floor (solvers.round_off), measured once an iterate is within
    # ROUND_OFF_GATE, as Newton on the load path does: a fibrous strip's increments otherwise
    # spent 2-3 of their 4-5 iterations at ratios of 2e-7 that no step lowers, and Crisfield's
    # rule read them as a hard increment (docs/theory.md §6.6, "Step length").
    rounding = RoundOffFloor(solver.tol, not model.interactions and run.dashpots is None, run.info)
    for iteration in range(1, solver.max_iterations + 1):
        frames = dofs.frames(state.directors)
        equilibrium = run.equilibrium(load_factor)
        r, ratio, forces = equilibrium.residual(state, frames)
        history.append(ratio)
        if not np.isfinite(ratio):
            raise IncrementFailed("non-finite residual")
        tol = rounding.tolerance(ratio, equilibrium, state, frames, r, forces)
        if ratio <= tol:
            run.info["round_off_converged"] += int(ratio > solver.tol)
            if factor is None:
                factor = run.factorise(run.tangent(state, frames)[0])
            return (
                run.settled(state, factor),
                load_factor,
                iteration - 1,
                ratio,
                history,
                chord_steps,
            )
        if (
            factor is not None
            and ratio <= solver.arc_chords
            and (not chords or ratio <= CHORD_GAIN * history[-2])
        ):
            # A chord step: near the path the tangent barely changes, and the factorisation of
            # an earlier iterate of this increment takes the ratio down for one solve
            # (docs/theory.md §6.6, "Chord steps"), while it gains CHORD_GAIN a step.
            chords += 1
            chord_steps += 1
            run.info["arc_chords"] += 1
        else:
            chords = 0
            k_ff, k_fp = run.tangent(state, frames)
            factor = run.factorise(k_ff)
        load_rhs, u_pattern = run.load_rate(pattern, frames, k_fp)
        solved = factor.solve(np.column_stack([r.ravel()[index], load_rhs]))
        if solved is None:
            raise IncrementFailed("singular tangent stiffness on the arc-length path")
        residual_part = np.zeros(dofs.n_slots)
        residual_part[index] = solved[:, 0]
        load_part = u_pattern.ravel().copy()
        load_part[index] = solved[:, 1]
        a = run.motion_between(start, start_load, state, load_factor).vector
        c = run.scaled_motion(residual_part.reshape(-1, N_COLUMNS), frames)
        b = run.scaled_motion(load_part.reshape(-1, N_COLUMNS), frames)
        d_load = constraint_root(a, b, c, length)
        delta = (residual_part + d_load * load_part).reshape(-1, N_COLUMNS)
        cap = step_cap(extent, delta)
        load_factor += cap * d_load
        state = run.place(dofs.advance(state, cap * delta, frames), load_factor)
        if (
            not chords
            and at_round_off_floor(cap, delta, ratio, model.element_size)
            and abs(d_load) <= 1e-9 * max(abs(prediction.load), 1e-300)
        ):
            # A full Newton update this small: converged at the round-off floor. Not after a
            # chord step, whose update is the stale tangent's: small is no proof there
            # (docs/theory.md §6.6, "Chord steps"); the next iteration checks its residual.
            _, ratio, _ = run.equilibrium(load_factor).residual(state, dofs.frames(state.directors))
            history.append(ratio)
            return run.settled(state, factor), load_factor, iteration, ratio, history, chord_steps
        run.progress(
            f"arc length: load factor {load_factor:.4g}, iteration {iteration}, residual "
            f"ratio {ratio:.3g} (tol {solver.tol:g})"
        )
        if stalled(history):
            raise IncrementFailed(
                f"no progress: residual ratio {min(history[-STALL_WINDOW:]):.3g} or more over "
                f"the last {STALL_WINDOW} of {iteration} iterations"
            )
    raise IncrementFailed(
        f"residual ratio {history[-1]:.3g} after {solver.max_iterations} iterations"
    )


def stalled(history: list[float]) -> bool:
    """No progress in the last STALL_WINDOW iterations (checked from 2 STALL_WINDOW on)."""
    if len(history) < 2 * STALL_WINDOW:
        return False
    return min(history[-STALL_WINDOW:]) > 0.5 * min(history[:-STALL_WINDOW])


def constraint_root(a: np.ndarray, b: np.ndarray, c: np.ndarray, length: float) -> float:
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


def tangent_motion(run: StaticRun, pattern) -> Motion:
    """The motion per unit load factor along the tangent of the path at the last state:
    K_ff dq = dR/dlambda, with the prescribed DOFs moving at their rate."""
    dofs, state = run.model.dofs, run.state
    frames = dofs.frames(state.directors)
    k_ff, k_fp = run.tangent(state, frames)
    rhs, rate = run.load_rate(pattern, frames, k_fp)
    solved = run.factorise(k_ff).solve(rhs)
    if solved is None:
        raise IncrementFailed("singular tangent stiffness at the start of the arc-length path")
    flat = rate.ravel()
    flat[dofs.free_slots] = solved
    motion = run.as_motion(flat.reshape(-1, N_COLUMNS), frames, 1.0)
    if motion.length == 0.0:
        raise IncrementFailed("the loads of this phase move nothing")
    return motion


def descend(run: StaticRun, state: State, load_factor: float, allowed: int):
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

    Same returns as solvers.newton.newton; a converged state that is still unstable (a
    saddle, reached only by accident) is handed to newton, which leaves it along its buckling
    mode.
    """
    solver = run.solver
    model = run.model
    dofs = model.dofs
    equilibrium = run.equilibrium(load_factor)
    index, moved_index = dofs.free_slots, dofs.prescribed_slots
    size = model.element_size
    extent = model_extent(model)
    history: list[float] = []
    shift = 0.0
    potential = None  # strain energy of the current iterate, when known
    for iteration in range(1, allowed + 1):
        frames = dofs.frames(state.directors)
        r, ratio, _ = equilibrium.residual(state, frames)
        left = equilibrium.remaining(state)
        history.append(ratio)
        if not np.isfinite(ratio):
            raise IncrementFailed("non-finite residual")
        k_ff, k_fp = run.tangent(state, frames)
        if ratio <= solver.tol and np.abs(left).max(initial=0.0) <= 1e-9 * size:
            factor = run.factorise(k_ff)
            if factor.negative:
                state, count, ratio, more = newton(run, state, load_factor, allowed)
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
                    raise IncrementFailed(f"no stable descent: {mechanism(model)}")
                shift = max(4.0 * shift, SHIFT_FLOOR)
                continue
            flat = left.ravel().copy()
            flat[index] = delta_free
            delta = flat.reshape(-1, N_COLUMNS)
            cap = step_cap(extent, delta)
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
                raise IncrementFailed("the shifted Newton steps no longer lower the potential")
            shift = max(4.0 * shift, SHIFT_FLOOR)
        state = trial
        run.progress(
            f"load factor {load_factor:.4g}: descent iteration {iteration}, residual ratio "
            f"{ratio:.3g}, shift {shift:.3g}"
        )
    raise IncrementFailed(f"residual ratio {history[-1]:.3g} after {allowed} descent iterations")
