"""What holds an explicit run's step below the one its mass scaling aims at
(``CentralDifference(mass_scaling_dt=...)``, solvers/explicit_step_size.py; docs/theory.md
§6.2-6.3).

Mass scaling raises the density of the cells whose own stable step is below the target, so
that the cells' bound reaches it; the step the run takes is then lowered by what the scaling
does not touch: the assembly's Gershgorin bound, the contacts' penalty springs (their omega^2
k / m added to the elements' at the node where they sum highest: penalties sized before the
scaling, a pinched node's springs of several contacts summed, a light tool's node on its
contact springs) and the mass-proportional damping. A run whose step ends well below the
target gets the mass it asked for without the step it was for: the report names each bound
and the one that holds the step, and a warning says so.
"""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np

from femcore.model import CompiledModel
from femcore.state import State
from solvers.common import outside_stacklevel

__all__ = ["REACHED_SHARE", "step_limits", "warn_step_short"]

#: The share of ``mass_scaling_dt`` below which a run's step is said to fall short of it (the
#: safety factor is in both; the damping of the shipped forming cases, c = 20 /s, shortens the
#: step by 1e-4 of it, far less).
REACHED_SHARE = 0.95


def _interaction_name(model: CompiledModel, index: int) -> str:
    """ "tool<k>" for an interaction with rigid tools (``tool_forces``' numbering), else
    "interaction <i>" (its place in the model's interactions, from 1) and its class."""
    row = sum(int(i.n_tools) for i in model.interactions[:index])
    part = model.interactions[index]
    if int(part.n_tools) > 0:
        return f"tool{row + 1}"
    return f"interaction {index + 1} ({type(part).__name__})"


def step_limits(
    model: CompiledModel,
    state: State,
    scale: list | None,
    mass: np.ndarray,
    rule: Any,
    dt: float,
) -> dict[str, Any]:
    """Each bound on the step at ``state`` (a run's start), the step ``dt`` (s) the rule took
    and what holds it.

    Parameters
    ----------
    model : CompiledModel
    state : State
    scale : list of (m,) float or None
        Mass scaling's density factors per block.
    mass : (n,) float
        The lumped masses the run divides by, t.
    rule : solvers.explicit_step_size.StableStepRule
        The solver (its ``safety``, ``damping``, ``mass_scaling_dt``, ``_assembled``).
    dt : float
        The step the rule gave, s.

    Returns
    -------
    dict
        ``target_dt_s`` (mass_scaling_dt), ``reached_dt_s`` (dt), and safety times each
        bound: ``cells_dt_s`` (the cells' own, mass-scaled), ``assembled_dt_s`` (with the
        assembly's Gershgorin bound), ``springs_dt_s`` (with the penalty springs at
        ``springs_node``, whose omega^2 ``springs_by`` shares out among the interactions);
        ``limited_by``: "the cells", "the assembled bound", "the contacts' penalty springs"
        or "the damping", the bound that took most off the step.
    """
    cell_dt = model.cell_stable_dt(state)
    if scale is not None:
        cell_dt = [d * np.sqrt(s) for d, s in zip(cell_dt, scale)]
    cells = min(float(d.min()) for d in cell_dt)
    critical = cells
    assembled = getattr(rule, "_assembled", None)
    if assembled is not None:
        critical = min(cells, assembled[0] * cells / assembled[1])
    parts = [
        (_interaction_name(model, index), omega)
        for index, omega in enumerate(model.penalty_frequencies(mass, state, critical))
        if omega is not None
    ]
    total = sum((omega for _, omega in parts), np.zeros(len(mass)))
    node = int(np.argmax(total)) if len(total) else 0
    squared = float(total[node]) if len(total) else 0.0
    with_springs = critical if squared <= 0.0 else 2.0 / math.sqrt((2.0 / critical) ** 2 + squared)
    safety = rule.safety
    bounds = {
        "the cells": safety * cells,
        "the assembled bound": safety * critical,
        "the contacts' penalty springs": safety * with_springs,
        "the damping": dt,
    }
    names = list(bounds)
    target = rule.mass_scaling_dt
    steps = [target if target is not None else bounds["the cells"]] + list(bounds.values())
    drops = [steps[i] / steps[i + 1] if steps[i + 1] > 0.0 else math.inf for i in range(4)]
    return {
        "target_dt_s": target,
        "reached_dt_s": dt,
        "cells_dt_s": bounds["the cells"],
        "assembled_dt_s": bounds["the assembled bound"],
        "springs_dt_s": bounds["the contacts' penalty springs"],
        "springs_node": node,
        "springs_by": {
            name: float(omega[node] / squared) for name, omega in parts if omega[node] > 0.0
        }
        if squared > 0.0
        else {},  # fmt: skip
        "limited_by": names[int(np.argmax(drops))],
        "is_tool_node": bool(node in set(model.rigid_nodes.tolist())),
    }


def warn_step_short(limits: dict[str, Any]) -> None:
    """A UserWarning where the step reached is below ``REACHED_SHARE`` of the mass scaling's
    target: the step, each bound, what holds it and what to do."""
    target, reached = limits["target_dt_s"], limits["reached_dt_s"]
    if target is None or reached >= REACHED_SHARE * target:
        return
    held = limits["limited_by"]
    said = {
        "the cells": "",
        "the assembled bound": (
            ": the assembly's Gershgorin bound is below the cells' own, which the scaling "
            "raised; a larger mass_scaling_dt scales the cells further"
        ),
        "the contacts' penalty springs": (
            f": at node {limits['springs_node']}"
            + (" (a force-driven tool's node: its mass)" if limits["is_tool_node"] else "")
            + " the springs of "
            + ", ".join(f"{name} ({share:.0%})" for name, share in limits["springs_by"].items())
            + " add their k / m to the elements' omega^2 (the automatic penalties are sized "
            "before the scaling, and a pinched node sums its contacts' springs): give those "
            "contacts a smaller penalty ([[contact]] penalty; a layup's ply contacts: [layup] "
            "penalty), or a force-driven tool a larger mass"
        ),
        "the damping": ": the mass-proportional damping shortens it; lower damping",
    }[held]
    warnings.warn(
        f"mass_scaling_dt = {target:.4g} s is not reached: the step is {reached:.4g} s "
        f"(the cells' bound {limits['cells_dt_s']:.4g} s, with the assembled bound "
        f"{limits['assembled_dt_s']:.4g} s, with the contacts' springs "
        f"{limits['springs_dt_s']:.4g} s). It is held by {held}{said}; the mass the scaling "
        "added buys only the step reached",
        UserWarning,
        stacklevel=outside_stacklevel(),
    )
