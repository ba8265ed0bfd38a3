"""The node-to-tool contact's automatic penalty and its damping's check (elements/contact.py,
"Penalty"; docs/theory.md §6.2, "The penalty's step").

The automatic penalty of a node is k_i = ``PENALTY_SHARE`` m_i (2 / dt_p)^2, m_i its lumped
mass and dt_p the elements' critical step with a Mindlin shell's rotary inertia at B2's
closed form (docs/theory.md §6.2), whatever rotary_scaling the shell was given: with the
closed j dt_p is the critical step (the penalty as it always was), with another j (the
element rule, a scaled j) it is the step the cells would have at the closed j, so that a
change of j changes no contact spring. Fibrous shells and cables: their critical step.
"""

from __future__ import annotations

import numpy as np

from femcore.checks import as_number

__all__ = ["PENALTY_SHARE", "automatic_penalty", "damping_ratio"]

PENALTY_SHARE = 0.1  # k m^-1 / omega_max^2 of the automatic penalty


def automatic_penalty(mass: np.ndarray, stable_dt: float, penalty_step: float | None) -> np.ndarray:
    """k (s,), N/mm, of nodes of lumped masses ``mass`` (s,), t: ``PENALTY_SHARE`` m (2 /
    dt)^2 with dt ``penalty_step`` (the critical step at the closed-form j, s), or
    ``stable_dt`` (the critical step, s) where it is None."""
    step = stable_dt if penalty_step is None else penalty_step
    return PENALTY_SHARE * mass * (2.0 / step) ** 2


def damping_ratio(damping) -> float:
    """The contact damping's fraction of critical, checked: a number in [0, 1]."""
    zeta = as_number(damping, "damping", "a fraction of the critical damping in [0, 1]")
    if not (np.isfinite(zeta) and 0.0 <= zeta <= 1.0):
        raise ValueError(
            "damping must be a fraction of the contact spring's critical damping in [0, 1], "
            f"got {damping!r}"
        )
    return float(zeta)
