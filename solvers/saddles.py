"""A converged state of Static's load path judged (solvers.newton; docs/theory.md §6.5, "The
stability of a converged state"): refused where cells turned inside out, counted by the
inertia of its own tangent (its neutral modes left out: solvers.neutral_modes), and with
``seek_stable`` a saddle left along a negative mode where
a relaxed push lowers the energy (solvers.stability.push_descends) and Newton converges from
there, kept otherwise.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

from femcore.dofs import N_COLUMNS
from femcore.state import State
from solvers.common import IncrementFailed, TurnedInsideOut
from solvers.linear import Factorisation
from solvers.neutral_modes import unstable_modes
from solvers.stability import lowest_modes, push_descends

if TYPE_CHECKING:
    from solvers.newton import Residual
    from solvers.static_run import StaticRun

__all__ = ["judged"]

# Newton from a pushed state: (state, iterations, residual ratio, residual history).
Resume = Callable[[State], tuple[State, int, float, list[float]]]


def judged(
    run: StaticRun,
    equilibrium: Residual,
    state: State,
    factor: Factorisation | None,
    load_factor: float,
    escapes: int,
    resume: Resume,
) -> tuple[State, tuple[int, float, list[float]] | None]:
    """A converged ``state``, refused where it has cells turned inside out
    (StaticRun.refuse_inverted, TurnedInsideOut) and judged by the inertia of its own tangent
    (StaticRun.factor_at: the one factorised on the way, ``factor``, is an iterate's before
    it). With seek_stable and fewer than three ``escapes`` in this increment so far, a saddle
    is left along a negative mode where a push there, relaxed, lowers the energy
    (solvers.stability.push_descends) and ``resume`` (Newton from the pushed state, its steps
    turned downhill) converges; it is kept otherwise (``info["saddles_kept"]``).

    Returns (the state, None), or (the state Newton reached from the push, (its iterations,
    residual ratio, residual history)).
    """
    run.refuse_inverted(state)  # before it is judged or pushed
    factor = run.factor_at(state, factor)
    negative = factor.negative or 0
    if not (negative and run.solver.seek_stable and escapes < 3):
        return run.settled(state, factor), None
    dofs = run.model.dofs
    frames = dofs.frames(state.directors)
    index = dofs.free_slots
    k_ff = run.tangent(state, frames)[0]
    # every negative pivot's mode, then those beyond round-off (solvers.neutral_modes): a
    # zero-energy mode is no way off
    modes = unstable_modes(k_ff, lowest_modes(k_ff, negative + factor.neutral))
    run.info["mode_searches"] += 1
    load = equilibrium.load(frames).ravel()[index]
    translation = index % N_COLUMNS < 3
    descent = push_descends(run, state, frames, load, modes, translation, factor, equilibrium)
    if descent is not None:
        escaped = _escape(run, descent[1], load_factor, resume)
        if escaped is not None:
            left, count, ratio, history = escaped
            return left, (count, ratio, history)
    run.info["saddles_kept"].append(load_factor)
    settled = run.settled(state, factor)
    run.on_kept_saddle = True
    return settled, None


def _escape(run: StaticRun, pushed: State, load_factor: float, resume: Resume):
    """``resume(pushed)``, or None when it fails (the saddle is then kept: a push may find a
    descent where no lower branch is within Newton's reach), except where it converged with
    cells turned inside out (TurnedInsideOut: the increment is cut, shorter increments find
    the branch)."""
    try:
        left = resume(pushed)
    except TurnedInsideOut:
        raise  # no saddle is kept for it: the increment is cut
    except IncrementFailed as failure:
        run.info["escapes_failed"].append(load_factor)
        run.progress(f"load factor {load_factor:.4g}: no way off the saddle ({failure})")
        return None
    run.info["branch_switches"].append(load_factor)
    run.progress(
        f"load factor {load_factor:.4g}: unstable equilibrium, left along the buckling mode",
        force=True,
    )
    return left
