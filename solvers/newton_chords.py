"""Chord corrections of Static's Newton steps (``Static(chords=N)``, docs/theory.md §6.5
"Curved steps"): after a whole step, up to N steps K^-1 r with the factorisation just made,
each kept while it lowers the total potential energy."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from femcore.dofs import N_COLUMNS, Frames
from femcore.state import State
from solvers.linear import Factorisation

if TYPE_CHECKING:
    from solvers.line_search import Watchdog
    from solvers.newton import Residual
    from solvers.static import StaticRun

__all__ = ["chord_corrections"]


def chord_corrections(
    run: StaticRun,
    equilibrium: Residual,
    watchdog: Watchdog,
    state: State,
    frames: Frames,
    forces,
    factor: Factorisation,
    count: int,
):
    """After a whole Newton step to ``state`` (internal ``forces`` there): up to
    ``count`` chord steps K^-1 r(state) with the iteration's factorisation ``factor``
    (one solve and one force evaluation each, where a Newton iteration forms and factorises
    a tangent), each kept while it lowers the total potential energy (the residual is no
    guide: it grows along steps that lead to the equilibrium). Returns (state, forces)."""
    model, dofs = run.model, run.model.dofs
    index = dofs.free_slots
    energy = run.energy(state)
    for _ in range(count):
        r, ratio, forces = equilibrium.residual(state, frames, forces)
        if not np.isfinite(ratio) or ratio <= run.solver.tol:
            break
        step = factor.solve(r.ravel()[index])
        if step is None:
            break
        flat = np.zeros(dofs.n_slots)
        flat[index] = step
        delta = flat.reshape(-1, N_COLUMNS)
        trial = dofs.advance(state, delta, frames)
        work = float(equilibrium.load(frames).ravel() @ flat)  # of the dead loads
        trial_energy = run.energy(trial)
        if not trial_energy - work < energy:
            break
        trial_forces = model.internal_force(trial)
        run.counts["residual"] += 1
        state, forces, energy = trial, trial_forces, trial_energy
        watchdog.work += work  # the potential of the iterates is measured from its best one
        run.info["chord_corrections"] += 1
    return state, forces
