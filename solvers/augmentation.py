"""The Uzawa passes of Static's load path for the augmented contacts (elements/augmented_contact.py,
docs/theory.md §9.6): after an increment converges, the contacts' multipliers take their
springs' forces and the increment is solved again from there, until the penetration and the
elastic slip are within each contact's tolerance."""

from __future__ import annotations

import warnings
from dataclasses import replace
from typing import TYPE_CHECKING

from femcore.model import CompiledModel
from femcore.state import State
from solvers.newton import IncrementFailed, newton

if TYPE_CHECKING:
    from solvers.static import StaticRun

__all__ = ["augment", "augment_contacts", "warn_penalty_only"]


def augment_contacts(model: CompiledModel, state: State) -> tuple[State, dict | None]:
    """The augmented Lagrangian's update of every interaction that has one
    (femcore.interaction.InteractionBlock.augment) at a converged ``state``: (the state with
    the updated multipliers, {"penetration", "slip": the largest over the interactions, mm;
    "excess": the largest of each one's penetration and slip over its tolerance; "within":
    every one's constraints met at ``state``}), or (state, None) when no interaction has
    multipliers."""
    history, reports = list(state.history), []
    for i, part in enumerate(model.interactions, start=len(model.blocks)):
        history[i], report = part.augment(state, history[i])
        if report is not None:
            reports.append(report)
    if not reports:
        return state, None
    summary = {
        "penetration": max(r["penetration"] for r in reports),
        "slip": max(r["slip"] for r in reports),
        "excess": max(max(r["penetration"], r["slip"]) / r["tolerance"] for r in reports),
        "within": all(r["within"] for r in reports),
    }
    return replace(state, history=tuple(history)), summary


def warn_penalty_only(model: CompiledModel, state: State, solver: str) -> None:
    """Warn that ``solver`` (a dynamic one) runs an augmented contact of ``model`` as its plain
    penalty: only Static updates the multipliers, so the penetration and elastic slip are the
    penalty's, which a user who asked for ``augmented=True`` would not expect silently."""
    if augment_contacts(model, state)[1] is not None:
        from solvers.common import outside_stacklevel  # common imports what imports this

        warnings.warn(
            f"{solver} runs an augmented contact (augmented=True) as its plain penalty: only "
            "Static's Uzawa passes update the multipliers (docs/theory.md §9.6); the "
            "penetration and elastic slip here are the penalty's",
            UserWarning,
            stacklevel=outside_stacklevel(),
        )


def augment(
    run: StaticRun,
    state: State,
    load_factor: float,
    count: int,
    ratio: float,
    history: list[float],
) -> tuple[State, int, float, list[float], int]:
    """The Uzawa passes of an increment converged at ``state``: while an augmented contact's
    penetration or elastic slip exceeds its tolerance, its multipliers are updated and the
    increment solved again from there, at most ``run.solver.augmentations`` times.

    ``count``, ``ratio`` and ``history`` are what solvers.newton.newton returned for the
    increment (its Newton iterations, final residual ratio and ratio per iteration). Returns
    (state, Newton iterations, ratio, ratio history, passes), the iterations and ratios of
    every pass; an IncrementFailed of a pass carries them too."""
    passes = 0
    while True:
        updated, report = augment_contacts(run.model, state)
        run.constraint = report
        if report is None or report["within"]:
            return state, count, ratio, history, passes
        if passes >= run.solver.augmentations:
            run.info["augmentations_short"].append((load_factor, report["excess"]))
            return state, count, ratio, history, passes
        passes += 1
        try:
            state, more, ratio, again = newton(run, updated, load_factor)
        except IncrementFailed as failure:
            failure.iterations += count
            failure.history = history + failure.history
            raise
        count, history = count + more, history + again
