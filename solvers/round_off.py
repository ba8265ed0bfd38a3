"""The round-off floor of Static's residual, so that the convergence test asks no more than
the rounding of the internal forces allows (docs/theory.md §6.5).

The internal forces of a shell are sums of terms much larger than their resultant: on a light
fabric under its own weight the fibres' tension stiffness (1200 N/mm) times the rounding of
coordinates of order 40 mm is 1e-11 N per fibre, 1e-9 of the strip's weight, and at a small
load factor more. An exact equilibrium then has a residual ratio of that order, and an
increment whose tolerance lies below it spends Newton iterations (a tangent and a
factorisation each) on steps of 1e-9 of an element that do not lower it
(solvers.newton.at_round_off_floor ends them).

The rounding is measured where it is met: the residual at the state moved by a rigid
translation of every node (ROUND_OFF_SHIFT element sizes). Every element's internal forces are
invariant under it (the conformance kits of femcore.testing check rigid translations), the
dead loads and the frames do not change, so the change of the residual is the rounding alone,
at the state's own coordinates and forces. An iteration whose ratio is at most
FLOOR_FACTOR times that change is converged, when that is at most ROUND_OFF_GATE: a larger
change is not rounding but a force that the translation moves (an element tied to fixed
points in space, which the conformance kits would not pass), and the strict test stays. Not
for models with interactions (a tool does not move with the translation) or stabilised
increments (the dashpots pull towards the last converged positions).

A solve that stops where that floor is above the gate (``rounding_stop``) stopped at the
rounding, not at a limit point: a load so small beside the stiffness that the internal forces'
rounding is a share of it (the thin twisted beam of MacNeal and Harder, t = 0.0032, its load
scaled by 1e-3, 48 x 8 cells: a rigid translation changes the internal forces by 4.9e-11 N, the
load is 1.1e-10 N a tip node, and Newton's ratio stays near 1.7e-3). Its stop says so, with
those figures and the remedy (a larger load, or units in which the load is not so small
beside the stiffness), in place of the generic hint of a limit point.
"""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np

from femcore.dofs import Frames
from femcore.state import State

if TYPE_CHECKING:
    from solvers.newton import Residual

__all__ = [
    "FLOOR_FACTOR", "ROUND_OFF_GATE", "ROUND_OFF_SHIFT", "RoundOffFloor", "round_off_ratio",
    "rounding_stop",
]  # fmt: skip

# The rigid translation of the probe, in element sizes: not a power of two, so that every
# coordinate rounds differently.
ROUND_OFF_SHIFT = (0.37, 0.59, 0.23)
# The residual after an exact Newton step at the floor is the force evaluations' rounding
# plus the solve's (the step's relative error times the condition of K): on Peirce's fibrous
# strip (benchmarks/newton_iterations.py) the ratios left by steps of 1e-9 to 1e-16 of an
# element were 2-7 times the probe's change.
FLOOR_FACTOR = 10.0
# The largest ratio ever accepted at the floor, and the largest floor taken for rounding;
# beyond it the full-step test of solvers.newton.at_round_off_floor decides.
ROUND_OFF_GATE = 1e-6


def rounding_stop(equilibrium: Residual, state: State, frames: Frames) -> str:
    """The sentence of a stop at the rounding of the internal forces, or "".

    Parameters
    ----------
    equilibrium : solvers.newton.Residual
        Of the load factor the failed increment aimed at.
    state : State
        The last converged state (its internal forces' rounding is probed there).
    frames : the nodal frames of ``state.directors`` (DofManager.frames).

    Returns
    -------
    str
        "" when FLOOR_FACTOR times ``round_off_ratio`` is at most ROUND_OFF_GATE (the
        solver takes such rounding for convergence: the stop has another cause); else the
        cause with its figures: the largest change of a nodal internal force (N) under the
        rigid translation, the largest nodal load (N), the ratio and the remedy.
    """
    r, _, forces = equilibrium.residual(state, frames)
    ratio = round_off_ratio(equilibrium, state, frames, r, forces)
    if FLOOR_FACTOR * ratio <= ROUND_OFF_GATE:
        return ""
    shift = np.asarray(ROUND_OFF_SHIFT) * equilibrium.model.element_size
    moved, _ = equilibrium.model.internal_force(replace(state, positions=state.positions + shift))
    change = float(np.linalg.norm(moved - forces[0], axis=1).max(initial=0.0))
    load = float(np.linalg.norm(equilibrium.f_ext, axis=1).max(initial=0.0))
    return (
        f"; the load is at the rounding of the internal forces: a rigid translation of the "
        f"model changes them by up to {change:.2g} N at a node, where the largest nodal load is "
        f"{load:.2g} N (a residual ratio of {ratio:.2g} from rounding alone, more than the "
        f"{ROUND_OFF_GATE / FLOOR_FACTOR:g} the solver can take for it), so equilibrium cannot "
        "be told from rounding and no cut helps: apply a larger load (a linear answer scales "
        "with it) or choose units in which the load is not so small beside the stiffness "
        "(docs/theory.md §6.5)"
    )


def round_off_ratio(equilibrium: Residual, state: State, frames: Frames, r: np.ndarray, forces):
    """The residual ratio of the rounding at ``state`` (module docstring).

    Parameters
    ----------
    equilibrium : solvers.newton.Residual of the load factor.
    state : State
        The iterate, with residual r (n, 5) (free DOFs, generalised components in
        ``frames``) and internal ``forces`` (f_int, m_int), each (n, 3), N and N mm.

    Returns
    -------
    float
        ||r(x + t) - r(x)|| judged as a residual of ``state`` (solvers.convergence: forces
        against F_ref, moments against F_ref L_e), t the rigid translation ROUND_OFF_SHIFT
        times the element size; one evaluation of the internal forces.
    """
    model = equilibrium.model
    shift = np.asarray(ROUND_OFF_SHIFT) * model.element_size
    moved = replace(state, positions=state.positions + shift)
    r_moved, _, _ = equilibrium.residual(moved, frames)
    change = r_moved - r
    return equilibrium.test.ratios(change[:, :3], change[:, 3:], *forces).largest


class RoundOffFloor:
    """The tolerance of one increment's iterations with its rounding floor: the solver's
    ``tol``, raised to FLOOR_FACTOR times the rounding of the residual (``round_off_ratio``,
    probed once, the first time the ratio lies between ``tol`` and ROUND_OFF_GATE) when that
    floor is at most ROUND_OFF_GATE (more is not rounding: a force a translation moves).
    ``probe`` False (interactions, stabilisation) keeps ``tol``; ``info["round_off_probes"]``
    counts the probes."""

    def __init__(self, tol: float, probe: bool, info: dict):
        self.tol, self.probe, self.info = tol, probe, info
        self.floor: float | None = None

    def tolerance(self, ratio: float, equilibrium: Residual, state: State, frames: Frames,
                  r: np.ndarray, forces) -> float:  # fmt: skip
        """The tolerance the iterate of residual ratio ``ratio`` is judged by (the arguments
        as ``round_off_ratio``'s)."""
        if not (self.probe and self.tol < ratio <= ROUND_OFF_GATE):
            return self.tol
        if self.floor is None:
            self.floor = FLOOR_FACTOR * round_off_ratio(equilibrium, state, frames, r, forces)
            self.info["round_off_probes"] += 1
        return max(self.tol, self.floor) if self.floor <= ROUND_OFF_GATE else self.tol
