"""Which part an explicit run's failed energy balance points at: each part's stored energy
(with what an interaction dissipated) at the last good state and at the failing one, and the
part whose energy changed most, named in the stop's message (solvers/explicit.py)."""

from __future__ import annotations

import numpy as np

from femcore.model import CompiledModel
from femcore.state import State

__all__ = ["largest_part_change", "part_energies"]


def part_energies(compiled: CompiledModel, state: State) -> list[float]:
    """Each part's stored energy at ``state`` (N mm), with the energy an interaction has
    dissipated (friction, a dashpot) added: what the work done on it goes into."""
    histories = (
        state.history
        if len(state.history) == len(compiled.parts)
        else (None,) * len(compiled.parts)
    )
    energies = [block.strain_energy(state, h) for block, h in zip(compiled.blocks, histories)]
    rest = histories[len(compiled.blocks) :]
    energies += [
        part.strain_energy(state, h) + part.dissipated_energy(h)
        for part, h in zip(compiled.interactions, rest)
    ]
    return energies


def largest_part_change(compiled: CompiledModel, good: State, now: State) -> str:
    """Which part's stored and dissipated energy changed most from the last good state
    ``good`` to ``now``, for the message of a failed energy balance: an energy that jumps
    within a step (a contact point changing its facing facet under a deep penetration) breaks
    the balance at any step size, where an unstable step makes the kinetic energy grow."""
    before, after = part_energies(compiled, good), part_energies(compiled, now)
    change = [b - a for a, b in zip(before, after)]
    k = int(np.argmax(np.abs(change)))
    return (
        f"from the last good state (t = {good.time:.6g} s) the stored and dissipated energy "
        f"changed most in part {k} of {len(change)} ({type(compiled.parts[k]).__name__}): "
        f"{change[k]:+.3g} N mm"
    )
