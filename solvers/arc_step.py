"""The step length of the arc-length path (solvers.arc_length, docs/theory.md §6.6, "Step
length"): Crisfield's iteration rule, bounded by the first step's length while the path keeps
its stiffness, and once it has softened by the load factor a step may carry and by how far the
path turned."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from solvers.round_off import ROUND_OFF_GATE

if TYPE_CHECKING:
    from solvers.arc_length import Motion

__all__ = [
    "LONGEST_GROWTH",
    "SETTLED_RATIO",
    "SHORTEST_GROWTH",
    "SOFTER",
    "TURN_LIMIT",
    "ArcStep",
    "iterations_spent",
    "turn_angle",
]

# Crisfield's factor sqrt(aim / iterations) is taken within [SHORTEST_GROWTH, LONGEST_GROWTH]:
# a step is at most halved or doubled from one increment to the next.
SHORTEST_GROWTH = 0.5
LONGEST_GROWTH = 2.0
# The largest angle (rad) a softened path may turn over a step lengthened past the first
# step's, between the scaled motions of two consecutive increments: such a step is shortened
# in proportion where the last one turned more (the turn over a step of length l is about
# l / rho, rho the path's radius of curvature). Near a fold of the motion (the von Mises truss
# under an imposed displacement) the secant carries little load, and without it a long step's
# cylinder would cut the path on the far branch.
TURN_LIMIT = 0.25
# The load-factor bound lengthens the steps only where it exceeds the first step's longest
# by this factor: a path that has softened (a strip past its buckling load carries 1e-3 of
# the load per length its first step did), not one whose secant wanders around its first
# stiffness (the von Mises truss, 0.95-1.1 of it away from its folds: there every run from 3
# to 20 increments keeps the steps, the increments and the limit points of the first-step
# rule; at 1, 31 of its 36 runs took other steps and one jumped a fold).
SOFTER = 2.0
# Crisfield's rule counts an increment's iterations down to this residual ratio (or to the
# tolerance where that is larger; ``iterations_spent``): the round-off floor's gate.
SETTLED_RATIO = ROUND_OFF_GATE


def iterations_spent(history: list[float], count: int, chord_steps: int, tol: float) -> int:
    """The iterations of a converged arc-length increment that Crisfield's rule counts: those
    that factorised (``count`` less its ``chord_steps``), and at most those that took the
    residual ratio (``history``, one entry per iterate) down to SETTLED_RATIO (or ``tol`` where
    that is larger). The iterations below it are the tolerance's tail, one where Newton
    converges quadratically, or several where the ratio sits at the round-off floor of stiff
    fibres (2e-7 on the fibrous strip), which say nothing about how far the predictor was
    from the path."""
    gate = max(tol, SETTLED_RATIO)
    reached = next((i for i, ratio in enumerate(history) if ratio <= gate), len(history))
    return min(count - chord_steps, reached)


def turn_angle(motion: Motion, previous: Motion) -> float:
    """The angle (rad) between two motions' scaled vectors (Motion.vector), in [0, pi]."""
    norms = motion.length * previous.length
    if norms <= 0.0:
        return 0.0
    cosine = float(motion.vector @ previous.vector) / norms
    return float(np.arccos(np.clip(cosine, -1.0, 1.0)))


class ArcStep:
    """The next arc-length step of one phase, from the increments converged so far.

    After an increment of motion ``m`` (length l, load-factor change dlambda) that took
    ``spent`` iterations (``iterations_spent``), the next length is

        l_next = min(l g, l_1)                        while l_load <= SOFTER l_1, else
        l_next = max(min(l g, l_1), min(l g, l_load, l_turn)),
        g = sqrt(aim / spent) within [1/2, 2],  l_load = l / (increments |dlambda|),
        l_turn = l TURN_LIMIT / theta  (where the turn theta from the increment before
        exceeds TURN_LIMIT; none after a push along a buckling mode).

    l_1 is the first increment's length, stretched to a load step of 1 / increments where it
    carried less (the rule before, whose cap tied every step to the first). l_load is the
    length along the last secant that carries one load step, 1 / increments: once the path
    has softened (a strip past its buckling load) the steps grow with it, and ``increments``
    keeps its meaning of a resolution along the load. No step is shorter than the rule before
    would take from the same increment.

    Parameters
    ----------
    increments : Static's increments (the resolution along the load, > 0).
    aim : Static's arc_iterations, Crisfield's aimed iterations an increment (> 0).
    """

    def __init__(self, increments: int, aim: int):
        self.increments, self.aim = increments, aim
        self.first_longest: float | None = None
        self.previous: Motion | None = None

    def after(self, motion: Motion, spent: int, pushed: bool = False) -> float:
        """The length of the next step after the converged increment ``motion`` that took
        ``spent`` factorising iterations (chord steps not counted); ``pushed``: the increment
        started along a buckling mode, a turn of the path made on purpose, not measured."""
        length = motion.length
        growth = float(np.clip(np.sqrt(self.aim / max(spent, 1)), SHORTEST_GROWTH, LONGEST_GROWTH))
        carried = abs(motion.load)
        if self.first_longest is None:
            # The first step's length, stretched to the path length of a load step of
            # 1 / increments where the first step carried less (a path that starts soft: its
            # tangent predicts far more motion than the load gives).
            self.first_longest = length * max(1.0, 1.0 / (self.increments * max(carried, 1e-300)))
        by_load = length / (self.increments * carried) if carried > 0.0 else np.inf
        arc = min(length * growth, self.first_longest)
        previous, self.previous = self.previous, motion
        turn = turn_angle(motion, previous) if previous is not None and not pushed else 0.0
        if by_load > SOFTER * self.first_longest:
            longer = min(length * growth, by_load)
            if turn > TURN_LIMIT:
                longer = min(longer, length * TURN_LIMIT / turn)
            arc = max(arc, longer)
        return arc
