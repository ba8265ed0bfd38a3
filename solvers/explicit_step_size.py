"""The explicit solver's step-size rule (``CentralDifference``, solvers/explicit.py;
docs/theory.md §6.2-6.3): safety times the critical step, the smaller of the cells' own bound
and the assembly's Gershgorin bound (evaluated again only when the cells' bound has moved),
lowered for the contacts' penalty springs and for mass-proportional damping, and the mass
scaling's density factors. ``CentralDifference`` inherits it; its loop asks for a step every
STABLE_DT_EVERY steps (solvers/explicit.py).
"""

from __future__ import annotations

import math

import numpy as np

from femcore.model import CompiledModel
from femcore.state import State

__all__ = [
    "ASSEMBLED_DT_MAX",
    "ASSEMBLED_DT_ROOM",
    "ASSEMBLED_DT_STEADY",
    "STEP_GROWTH_HELD",
    "StableStepRule",
]

# The held contact springs are asked for this factor times the step taken since the last
# evaluation (and again for the step if it comes out larger: docs/theory.md §6.2).
STEP_GROWTH_HELD = 1.25
# The assembled (Gershgorin) stable step (looked at every ASSEMBLED_DT_EVERY steps,
# solvers/explicit.py) is evaluated again when the cells' bound has moved by more than this
# fraction since it was last evaluated (the geometry and the tensions that set both have
# changed), or this many steps have passed. Measured on the hemisphere forming blank: the
# ratio of the two bounds stays within 0.5 % while the cells' bound does within 1 % (the first
# third of the stroke), and follows it when it moves. The rotary inertia only grows (a stale
# bound is the smaller) and the contact springs are counted apart, every contact node as
# pressed (penalty_frequency_squared).
ASSEMBLED_DT_STEADY = 0.01
ASSEMBLED_DT_MAX = 4000
# Where the cells' bound governed with room to spare (the assembled bound a fraction h above
# it), the assembled bound waits until the cells' bound has moved by ASSEMBLED_DT_ROOM x h
# (or ASSEMBLED_DT_STEADY, the larger): the ratio of the two moved by at most half what the
# cells' bound moved on the hemisphere blank, so that it cannot fall to 1 before the cells'
# bound has moved by 2 h / (1 + h). On that blank (20k triangles) the assembled bound of the
# element blocks starts 1.40 times the cells' bound: evaluated at 1 % moves it cost 3.3 s of
# CPU every few hundred steps.
ASSEMBLED_DT_ROOM = 0.5


class StableStepRule:
    """The step-size rule of the explicit solver (its methods ``_density_scale``,
    ``_step_size``, ``_lowered`` and ``_assembled_due``); the solver sets the attributes below
    and clears ``_assembled`` at the start of a run."""

    #: s, the fixed step (None: the rule's)
    dt: float | None
    #: the fraction of the critical step taken
    safety: float
    #: 1/s, c of the mass-proportional damping C = c M
    damping: float
    #: s, the step mass scaling aims at (None: no mass scaling)
    mass_scaling_dt: float | None
    #: (assembled Gershgorin step, the cells' bound and the step when it was evaluated)
    _assembled: tuple[float, float, int] | None

    def _density_scale(self, model: CompiledModel, state: State):
        """Mass scaling's density factors, one (m,) array per block, (mass_scaling_dt /
        (safety dt_cell))^2 at least 1; None without mass scaling."""
        if self.mass_scaling_dt is None:
            return None
        target = self.mass_scaling_dt / self.safety
        return [np.maximum(1.0, (target / dt) ** 2) for dt in model.cell_stable_dt(state)]

    def _step_size(
        self,
        model: CompiledModel,
        state: State,
        scale,
        mass: np.ndarray,
        inertia=None,
        step=0,
        previous: float | None = None,
    ) -> float:
        """safety x the critical step: the smaller of two bounds, the cells' own (cheap,
        every STABLE_DT_EVERY steps) and the assembly's Gershgorin bound (``inertia`` given:
        evaluated now with ``mass`` unless the cells' bound has stayed within
        ASSEMBLED_DT_STEADY of its value then for fewer than ASSEMBLED_DT_MAX steps; else the
        last one, carried along with the cells' bound as the geometry changes), lowered for
        the penalty springs of contacts. The smaller:
        the fibrous cells' bound is an estimate, not a bound (docs/theory.md §6.2), and the
        larger of the two took a forming blank past its exact critical step. ``previous``
        the step taken since the last evaluation (s; None at the start): the springs held
        until the next one are asked for STEP_GROWTH_HELD times it, and again for the step
        if that is larger: the step is never above a step whose springs allow it."""
        if self.dt is not None:
            return self.dt
        cell_dt = model.cell_stable_dt(state)
        if scale is not None:
            cell_dt = [dt * np.sqrt(s) for dt, s in zip(cell_dt, scale)]
        critical = min(float(dt.min()) for dt in cell_dt)
        if inertia is not None and self._assembled_due(critical, step):
            assembled = model.assembled_stable_dt(state, mass, inertia)
            self._assembled = None if assembled is None else (assembled, critical, step)
        if self._assembled is not None:
            assembled, cells_then, _ = self._assembled
            critical = min(critical, assembled * critical / cells_then)
        # The springs held until the next evaluation need the largest step until then (their
        # points' slide grows with it): the elements' critical one at the start (the springs
        # and the safety only shorten it), then STEP_GROWTH_HELD times the step taken (asked
        # at the critical one where the springs keep the step near a third of it, they counted
        # three times the slide: docs/theory.md §6.2); a step above that is asked for again.
        largest = critical if previous is None else min(critical, STEP_GROWTH_HELD * previous)
        dt = self._lowered(critical, model.penalty_frequency_squared(mass, state, largest))
        if dt > largest:  # asked again (springs counting the points a longer step may bring
            # in); where they keep it under the step asked first, that one holds (its springs
            # bound every step up to it, and are stable at it)
            again = self._lowered(critical, model.penalty_frequency_squared(mass, state, dt))
            dt = max(largest, min(dt, again))
        return dt

    def _lowered(self, critical: float, springs: float) -> float:
        """safety x the critical step (s) with the springs' omega^2 (1/s^2) added: a penalty
        spring on a node adds k / m to the omega^2 of its stiffest mode (an upper bound: the
        two add exactly when they act along the same direction of one node); mass-proportional
        damping shortens it, dt <= (2/w)(sqrt(1+xi^2) - xi) with xi = c / (2 w) on the highest
        mode w = 2 / dt_crit (docs/theory.md §6.3)."""
        if springs > 0.0:
            critical = 2.0 / math.sqrt((2.0 / critical) ** 2 + springs)
        xi = self.damping * critical / 4.0
        return self.safety * critical * (math.sqrt(1.0 + xi * xi) - xi)

    def _assembled_due(self, cells: float, step: int) -> bool:
        """Whether the assembled bound is evaluated again at ``step``, the cells' bound
        ``cells`` (s): none yet, the cells' bound moved since the last by more than
        ASSEMBLED_DT_STEADY or ASSEMBLED_DT_ROOM of the room the cells had then (the
        assembled bound's excess over theirs, a fraction), whichever is larger, or
        ASSEMBLED_DT_MAX steps since."""
        if self._assembled is None:
            return True
        assembled, cells_then, then = self._assembled
        room = max(ASSEMBLED_DT_STEADY, ASSEMBLED_DT_ROOM * (assembled / cells_then - 1.0))
        return step - then >= ASSEMBLED_DT_MAX or abs(cells / cells_then - 1.0) > room
