"""Pieces of the pseudo-dynamic and dynamic solvers: the damped central-difference velocity
update that CentralDifference and DynamicRelaxation share, the energy account and its
divergence check, and the output schedule of frames.

The configuration update itself (move the nodes, turn the directors by finite rotations) is
``femcore.dofs.DofManager.move``, the one the static solver uses too.
"""

from __future__ import annotations

import numpy as np

__all__ = ["EnergyAccount", "FrameSchedule", "damped_velocity"]


def damped_velocity(
    rate: np.ndarray, force: np.ndarray, inverse_mass: np.ndarray, dt_bar: float, damping: float
) -> np.ndarray:
    """Central-difference update of a nodal rate with mass-proportional damping C = c M
    (Bai Eq. 23 with damping, docs/theory.md §6.1):

        v(i+1/2) = [(1 - c dt_bar/2) v(i-1/2) + dt_bar M^-1 F(i)] / (1 + c dt_bar/2)

    Parameters
    ----------
    rate : (n, 3) float
        v(i-1/2): velocities (mm/s) or angular velocities (rad/s).
    force : (n, 3) float
        Out-of-balance forces (N) or moments (N mm) at t(i).
    inverse_mass : (n, 1) float
        1/m or 1/I per node, 0 where the node has no such DOF.
    dt_bar : float
        s, (dt_prev + dt) / 2.
    damping : float
        c, 1/s.
    """
    return ((1.0 - 0.5 * damping * dt_bar) * rate + dt_bar * inverse_mass * force) / (
        1.0 + 0.5 * damping * dt_bar
    )


class EnergyAccount:
    """Kinetic energy, internal and external work and damping dissipation of an explicit run,
    with the records kept for the result (about ``records`` of them, thinned every ``thin``
    steps) and the blow-up check.

    Work over [t(i-1/2), t(i+1/2)] is taken with the forces at t(i) (midpoint rule).
    """

    KEYS = ("time", "kinetic", "internal", "external_work", "damping")

    def __init__(self, thin: int):
        self.thin = thin
        self.kinetic = self.internal = self.external = self.dissipated = 0.0
        #: Sum of |external work increments|: the yardstick for a blow-up.
        self.work_scale = 0.0
        self.records: dict[str, list[float]] = {k: [0.0] for k in self.KEYS}

    @staticmethod
    def increments(
        forces: tuple[np.ndarray, np.ndarray],
        rates: tuple[np.ndarray, np.ndarray],
        mass: np.ndarray,
        damping: float,
        dt_prev: float,
        dt: float,
    ) -> tuple[float, float, float, float]:
        """(external, internal, damping work, new kinetic energy) of one kind of DOF over a
        step: ``forces`` = (external + reaction, internal) at t(i), ``rates`` = (old, new)."""
        external, internal = forces
        old, new = rates
        dx = 0.5 * (dt_prev * old + dt * new)
        d_ext = float(np.sum(external * dx))
        d_int = float(np.sum(internal * dx))
        d_damp = float(np.sum(damping * mass[:, None] * 0.5 * (old + new) * dx))
        kinetic = 0.5 * float(np.sum(mass[:, None] * new * new))
        return d_ext, d_int, d_damp, kinetic

    def blows_up(self, d_ext: float, d_int: float, d_damp: float, kinetic_new: float) -> bool:
        """Count the step's external work into ``work_scale``, then judge it: energy
        conservation bounds the kinetic energy by the work done on the model; ten times that
        work means the integration is unstable."""
        self.work_scale += abs(d_ext)
        return (not np.isfinite(kinetic_new)) or kinetic_new > 10.0 * (
            self.work_scale + abs(self.internal)
        ) + 1e-300

    def accept(self, d_ext: float, d_int: float, d_damp: float, kinetic: float) -> None:
        self.kinetic = kinetic
        self.external += d_ext
        self.internal += d_int
        self.dissipated += d_damp

    def record(self, step: int, time: float) -> None:
        if step % self.thin == 0:
            values = (time, self.kinetic, self.internal, self.external, self.dissipated)
            for key, value in zip(self.KEYS, values):
                self.records[key].append(value)

    def arrays(self) -> dict[str, np.ndarray]:
        return {k: np.asarray(v) for k, v in self.records.items()}


class FrameSchedule:
    """When to write a frame: every ``interval`` of time and at the end of ``duration``."""

    def __init__(self, interval: float, duration: float):
        self.interval = interval
        self.duration = duration
        self.next = interval

    def due(self, time: float) -> bool:
        """True (and the next output time moved past ``time``) when a frame is due."""
        if time >= self.next * (1.0 - 1e-9) or time >= self.duration * (1.0 - 1e-12):
            while self.next <= time * (1.0 + 1e-9):
                self.next += self.interval
            return True
        return False
