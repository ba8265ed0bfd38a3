"""What an explicit run refuses before its first step (``CentralDifference.solve``): a model it
cannot be run with whatever the step (a history node it does not have, a displacement that
jumps at t = 0, a force-driven tool without a mass), mass scaling that would make another
body of it, and more steps than ``max_steps``. Each a ValueError (a SettingError naming the
solver's option where one is at fault)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from femcore.model import CompiledModel
from solvers.common import SettingError

if TYPE_CHECKING:
    from solvers.explicit import CentralDifference

__all__ = ["refuse_unrunnable", "refuse_up_front"]


def refuse_up_front(
    solver: CentralDifference, compiled: CompiledModel, added_mass: float, dt: float
) -> None:
    """Refuse, before the first step, a run that mass scaling would turn into another
    model (more than ``max_added_mass`` times its elements' mass added) or whose steps
    would exceed ``max_steps`` at the starting step (a step far too small would otherwise
    hang)."""
    if compiled.nominal_mass_nodes.size:
        raise ValueError(
            f"node {int(compiled.nominal_mass_nodes[0])} carries a force-driven tool's "
            "free translation without a stated mass: in explicit dynamics the tool moves "
            "by m a = F - (contact forces); give the tool its mass (t), e.g. "
            "RigidPlane(..., free=('z',), force=..., mass=...), or [[contact]] mass = ..."
        )
    total = compiled.element_mass
    if total > 0.0 and added_mass > solver.max_added_mass * total:
        raise SettingError(
            "mass_scaling_dt",
            f"mass_scaling_dt = {solver.mass_scaling_dt:g} s would add {added_mass / total:.3g} "
            f"times the elements' mass ({added_mass:.3g} on {total:.3g} t, the tools' "
            "masses aside), more than "
            f"max_added_mass = {solver.max_added_mass:g}: the run would describe a much "
            "heavier body. Choose a target step nearer the stable step, or raise "
            "max_added_mass",
        )
    steps = solver.duration / dt
    if steps > solver.max_steps:
        raise SettingError(
            "max_steps",
            f"duration / dt = {solver.duration:g} s / {dt:.3g} s = {steps:.4g} steps, more "
            f"than max_steps = {solver.max_steps}: raise dt (or mass_scaling_dt), shorten "
            "the duration, or raise max_steps",
        )


def refuse_unrunnable(solver: CentralDifference, compiled: CompiledModel) -> None:
    """ValueError for what this model cannot be run with whatever the step: a history
    node it does not have, or a displacement prescribed already at t = 0 (amplitude
    "step", or a(0) != 0): in dynamics the node would jump there in one step, an infinite
    velocity (the energy records then do not close and the stable step collapses)."""
    if solver.history_nodes.size and solver.history_nodes.max() >= compiled.n_nodes:
        raise ValueError(
            f"history_nodes has node {int(solver.history_nodes.max())}, and the model's nodes "
            f"are 0 to {compiled.n_nodes - 1}"
        )
    if compiled.has_prescribed:
        at_start = compiled.prescribed_displacement(0.0)
        jumping = np.flatnonzero(np.any(at_start != 0.0, axis=1))
        if jumping.size:
            node = int(jumping[0])
            raise ValueError(
                f"{jumping.size} node(s) have a displacement prescribed at t = 0 (node {node}: "
                f"{tuple(float(v) for v in at_start[node])} mm): in explicit dynamics a "
                'prescribed displacement must start from zero (amplitude "smooth" or '
                '"linear", or a(0) = 0); "step" jumps in one time step, an infinite '
                'velocity. A suddenly applied load is a force with amplitude "step"'
            )
