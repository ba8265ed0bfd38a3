"""The progress watch of dynamic relaxation (solvers/relaxation.py, docs/theory.md §6.4): an
increment whose smallest residual ratio stops falling is stopped as stalled; and the mechanism
watch's message."""

from __future__ import annotations

import math

from femcore.model import CompiledModel
from solvers.relaxation_cuts import more_increments

__all__ = ["PLATEAU_FACTOR", "STALL_RATIO", "Plateau", "stall_message"]

#: The factor by which the smallest residual ratio must fall in plateau_iterations.
PLATEAU_FACTOR = 0.9
#: A residual ratio above this has not fallen (the mechanism watch).
STALL_RATIO = 0.5


class Plateau:
    """The progress watch of one increment: stalled when the smallest residual ratio met has
    not fallen to PLATEAU_FACTOR of what it was ``window`` iterations before (None: never)."""

    def __init__(self, window: int | None):
        self.window = window
        self.best = math.inf  # the smallest ratio met
        self.then = math.inf  # the smallest ratio met at the last check (the first ratio)

    def stalled(self, iteration: int, ratio: float) -> bool:
        if ratio < self.best:
            self.best = ratio
            if iteration == 1:
                self.then = ratio
        if self.window is None or iteration % self.window:
            return False
        stalled = not self.best <= PLATEAU_FACTOR * self.then
        self.then = self.best
        return stalled

    def message(
        self, solver, model, increment: int, load_factor: float, ratio: float, factored=False
    ) -> str:
        """The stop's message; ``solver`` the DynamicRelaxation, ``model`` its CompiledModel,
        ``factored`` whether the masses were the factored ones a stall of the Gershgorin
        masses went on with (solvers/factored_masses.py)."""
        after = " with the factored masses after the Gershgorin ones stalled" if factored else ""
        return (
            f"dynamic relaxation stalled in increment {increment}/{solver.increments} (load "
            f"factor {load_factor:.4g}){after}: the smallest residual ratio ({self.best:.3g}, now "
            f"{ratio:.3g}, tolerance {solver.tol:g}) did not fall below {PLATEAU_FACTOR:g} of "
            f"what it was in the last {self.window} iterations (plateau_iterations). Check "
            f"what holds the model (supports, contact), {more_increments(model)}a looser tol, or "
            f"the other damping ({'kinetic' if solver.damping == 'viscous' else 'viscous'})"
        )


def stall_message(model: CompiledModel, increment: int, solver, load_factor: float) -> str:
    """The mechanism watch's stop message; ``solver`` the DynamicRelaxation."""
    motions = model.unheld_rigid_motions(loaded_only=False)
    cause = (
        f"the supports leave rigid motions free ({'; '.join(motions)})"
        if motions
        else "no rigid motion of the whole model is free, so a part or a mechanism moves "
        "without resistance"
    )
    return (
        f"dynamic relaxation stopped in increment {increment}/{solver.increments} (load factor "
        f"{load_factor:.4g}): the residual did not fall (ratio above {STALL_RATIO} for "
        f"{solver.stall_iterations} iterations), nothing stops the motion: {cause}. Fix or "
        "prescribe DOFs that hold it, or balance the loads."
    )
