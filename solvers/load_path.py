"""Static's load path: ``increments`` equal steps of the load factor per phase, an increment
that does not converge cut in half and retried from the last converged state, and with
``Static(first_turn=...)`` an increment whose first Newton step turns a director too far cut
before it is iterated (docs/theory.md §6.5, "Increments sized by the first step")."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from solvers.arc_length import JUMP_ITERATIONS, changed_options, descend
from solvers.augmentation import augment
from solvers.load_jumps import jumped
from solvers.newton import IncrementFailed, StepTooLong
from solvers.penalty_start import newton_with_soft_start
from solvers.stick_start import newton_with_stick_start

if TYPE_CHECKING:
    from solvers.static import Static, StaticRun

__all__ = ["LOAD_DEFAULTS", "MOST_HALVINGS", "check_load_options", "load_path", "turn_fraction"]

#: The smallest share a cut by ``first_turn`` keeps, 1/2^MOST_HALVINGS of the increment: a
#: step of less is no step at the load factor's rounding.
MOST_HALVINGS = 30


#: The load path's own options of ``Static`` and their defaults: the arc-length path never
#: reads them (it has its own predictor, solvers.arc_length.arc_predictor), except after a
#: limit point with at_limit="jump", where load steps go on.
LOAD_DEFAULTS = {
    "predictor": False,
    "first_turn": None,
    "ply_penalty_start": None,
    "follow_tools": False,
    "follow_tools_after_cut": False,
}


def check_load_options(path: str, at_limit: str, given: dict) -> None:
    """ValueError for any of the load path's own options (LOAD_DEFAULTS; ``given``: name ->
    value as Static holds it) other than its default with path="arc_length" and
    at_limit="follow", which would ignore it."""
    if path != "arc_length" or at_limit != "follow":
        return
    ignored = changed_options(given, LOAD_DEFAULTS)
    if ignored:
        raise ValueError(
            f"{', '.join(ignored)} given with path='arc_length': the load path's options, "
            "which the arc-length path does not use (it has its own predictor); expected "
            "path='load' with them, at_limit='jump' (load steps after a limit point), or "
            "their defaults"
        )


def turn_fraction(turn: float, limit: float) -> float:
    """The share 1/2^k (k >= 1) of an increment whose first Newton step turns a director by
    ``turn`` (rad) that turns it by at most ``limit`` (rad): the step is linear in the
    increment, and the halves are those a cut would take, so the sub-increments land where
    the cuts' did."""
    # log2 of each apart: turn / limit overflows for a limit near the smallest float.
    halvings = math.ceil(math.log2(turn) - math.log2(limit))
    return 0.5 ** min(max(1, halvings), MOST_HALVINGS)


def load_path(solver: Static, run: StaticRun, phase: int, jump: bool = False) -> None:
    """``solver.increments`` equal steps of the load factor over [phase, phase + 1]. ``jump``:
    the first step leaves a limit point; the way to the stable branch beyond is long, and
    that step may take JUMP_ITERATIONS x max_iterations Newton iterations."""
    step = 1.0 / solver.increments
    iterations_allowed = JUMP_ITERATIONS * solver.max_iterations if jump else None
    for increment in range(1, solver.increments + 1):
        target = phase + increment / solver.increments
        if target <= run.reached + 1e-12:  # reached by an arc-length path already
            continue
        iterations = 0
        passes = 0
        cuts_here = 0
        # The first increment of a phase of several, its attempts and sub-increments
        # (solvers/newton.py ``opens_on_ramp``; each phase's end is reached by a later one).
        run.opening = increment == 1 and solver.increments > 1
        resized = False  # the attempt follows a cut by ``first_turn``: not cut so again
        # Cuts by ``first_turn`` in this increment. The rule assumes the first step's turn
        # shrinks with the step; where it does not (a turn with a floor), each attempt is cut
        # again and the sub-increments would shrink without end: past max_cuts of them the
        # increment's attempts are iterated unchecked, as without the rule.
        turn_cuts = 0
        while run.reached < target - 1e-12:
            # Land on the target exactly: sums of step fractions miss it by rounding.
            trial = target if run.reached + step >= target - 1e-12 else run.reached + step
            start = run.predict(trial, follow=solver.follow_tools_after_cut and cuts_here > 0)
            run.met_indefinite = False
            stable_start, begun, before = run.negative == 0, run.reached, run.balanced
            run.damp(trial)
            checked = not resized and iterations_allowed is None and turn_cuts < solver.max_cuts
            limit = solver.first_turn if checked else None
            resized = False
            try:
                if iterations_allowed is not None:
                    converged, count, ratio, history = descend(
                        run, start, trial, iterations_allowed
                    )
                else:
                    try:
                        converged, count, ratio, history = newton_with_soft_start(
                            run, start, trial, solver.ply_penalty_start, limit
                        )
                    except StepTooLong:
                        raise
                    except IncrementFailed as failure:
                        # before a cut of the first increment, once more with stiff stick
                        # springs first (solvers/stick_start.py): plies laid on each other
                        # hold nothing tangentially at the first iterate under the normal
                        # law's spring
                        if len(run.frames) > 1:
                            raise
                        try:
                            converged, count, ratio, history = newton_with_stick_start(
                                run, start, trial
                            )
                        except IncrementFailed as again:
                            failure.iterations += again.iterations
                            raise failure from None
                        count += failure.iterations
                converged, count, ratio, history, more = augment(
                    run, converged, trial, count, ratio, history
                )
            except StepTooLong as long:
                # Cut before iterating: no Newton iteration was spent on the step.
                assert limit is not None
                fraction = turn_fraction(long.turn, limit)
                run.info["first_turn_cuts"].append((trial, long.turn, fraction))
                turn_cuts += 1
                step = fraction * (trial - run.reached)
                resized = True
                continue
            except IncrementFailed as failure:
                run.info["iterations_cut"] += failure.iterations
                total = solver.increments * (2 if solver.step_loads_first else 1)
                cuts_here = run.cut(
                    cuts_here,
                    f"increment {increment + phase * solver.increments}/{total}",
                    failure,
                    trial,
                )
                step = 0.5 * (trial - run.reached)
                continue
            iterations += count
            passes += more
            iterations_allowed = None
            crossed = stable_start and run.met_indefinite and iterations_allowed is None
            run.accept(converged, trial, count)
            if crossed and run.negative == 0 and jumped(run, before, begun, converged, trial):
                run.note_jump(begun, trial)
            run.damp(None)
            # After a cut, grow the step back towards the nominal one.
            step = min(1.0 / solver.increments, 2.0 * step)
        run.opening = False
        run.frame(iterations, ratio, history)
        if run.constraint is not None:
            run.info["augmentations"].append(passes)
            run.info["augmented_penetration"].append(run.constraint["penetration"])
            run.info["augmented_slip"].append(run.constraint["slip"])
