"""Normal contact damping: a viscous pressure against the rate of approach, a fraction of the
critical damping of each node's contact spring (``Contact(damping=zeta)``; docs/theory.md
§9.7).

What it is for. A penalty contact is a spring k between each node and the tool; undamped, a
node that lands on a tool, or is kicked across a die's facets, rings on it at sqrt(k / m)
(with the automatic penalty about a third of the mesh's highest frequency) and keeps that
energy: mass-proportional damping at a rate the process tolerates hardly touches it. Explicit
codes damp the contact itself (Abaqus/Explicit's contact damping, LS-DYNA's VDC, both a
fraction of the critical damping of the contact spring).

Force. On a node in contact (penetration p > 0), along the tool's normal n:
f = -c (dr/dt . n) n, c = 2 zeta sqrt(k m), with m the node's lumped mass (the reduced mass
m m_t / (m + m_t) on a force-driven tool of mass m_t) and r the node's position in the tool's
frame (less the tool's motion and free translation). A node alone on the spring (a
Kelvin-Voigt contact) then leaves the tool with exp(-zeta pi / sqrt(1 - zeta^2)) of the
speed it came with, and critically damped (zeta = 1) it does not leave. The force is not
clipped where it pulls (a node leaving the tool while still within the penetration): the
clipped law has no such closed form, and the pull lasts only while the node crosses the
last c |dr/dt . n| / k = 2 zeta |dr/dt . n| / sqrt(k / m) of the penetration (where the
damping's pull outweighs the spring's push k p).

Rate. dr/dt is taken over the last step, (r(t) - r(t_prev)) / (t - t_prev), from the
positions the history keeps: in explicit dynamics the relative velocity at t - dt / 2, the
time level of the velocities the step has (the force lags them as a dashpot's does). The
quasi-static solvers' states are at rest (zero velocities): no force, no tangent. So is an
explicit state where nothing moves yet: a tool meeting a body entirely at rest is undamped for
that one step (its share of a bounce: c dt / m = 2 zeta omega dt of the momentum).

Energy. The block's history keeps the work of the damping force at each accepted state
against the relative motion of the step around it (the midpoint rule of the explicit
energies), so the dissipated energy is reported with the friction's (the "friction" column
of the energy records: the interactions' dissipation) and the energy balance closes.

Stable step. The force lags the velocity by half a step, which shortens the stable step of
the node: (w dt)^2 + 2 (c / m) dt <= 4 for a node of highest frequency w = sqrt(w_e^2 + k /
m), w_e the elements'. ``springs`` reports each spring as the stiffness that gives the
explicit step that bound (``damped_spring``), with w_e the elements' at calibration.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from elements.contact import ContactBlock
from femcore.state import State

__all__ = ["DampedContactBlock", "DampedHistory", "damped_spring"]


def damped_spring(
    stiffness: np.ndarray, mass: np.ndarray, damping: np.ndarray, omega_elements: float
) -> np.ndarray:
    """(s,) the spring (N/mm) that, put in the explicit step's bound as an undamped one, gives
    the stable step of a node of mass ``mass`` (s,) t on a spring ``stiffness`` (s,) N/mm with
    a lagged dashpot ``damping`` (s,) N s/mm, the elements' highest frequency at the node
    ``omega_elements`` (rad/s): the step dt with W^2 dt^2 + 2 g dt = 4, W^2 = w_e^2 + k / m,
    g = c / m, is 2 / sqrt(w_e^2 + k' / m) with k' / m = (sqrt(g^2 + 4 W^2) + g)^2 / 4 - w_e^2
    (k' = k without damping; a larger w_e gives a larger k')."""
    mass = np.asarray(mass, dtype=float)
    rate = np.divide(damping, mass, out=np.zeros_like(mass), where=mass > 0.0)
    squared = np.divide(stiffness, mass, out=np.zeros_like(mass), where=mass > 0.0)
    whole = omega_elements**2 + squared
    effective = 0.25 * (np.sqrt(rate**2 + 4.0 * whole) + rate) ** 2 - omega_elements**2
    return np.where(mass > 0.0, effective * mass, stiffness)


@dataclass(frozen=True)
class DampedHistory:
    """The history of a damped contact block.

    inner : the contact's own history (elements.contact.FrictionHistory, or None frictionless).
    before, last : (s, 3) float, mm
        The nodes' positions in the tool's frame at the accepted state before the last one and
        at the last one.
    times : (2,) float, s
        The times of those two states.
    force : (s, 3) float, N
        The damping force on the nodes at the last accepted state.
    dissipated : float, N mm
        The damping's work up to the midpoint of the last step, against the relative motion.
    """

    inner: Any
    before: np.ndarray
    last: np.ndarray
    times: tuple[float, float]
    force: np.ndarray
    dissipated: float


class DampedContactBlock(ContactBlock):
    """A ContactBlock with normal damping (module docstring): its history a ``DampedHistory``
    around the contact's own, whose methods it hands that one."""

    def __init__(self, contact, *args, **kwargs):
        super().__init__(contact, *args, **kwargs)
        self.damping_ratio = float(contact.damping)  # zeta, of the critical damping
        self.damping = np.zeros(len(self.connectivity))  # c, N s/mm, set by calibrate
        self._mass = np.zeros(len(self.connectivity))  # the nodes' masses, t
        self._tool_mass = 0.0  # a driven tool's, t
        self._omega_elements = 0.0  # rad/s, 2 / (the elements' critical step)
        self._last_damping: tuple | None = None

    def calibrate(self, mass: np.ndarray, stable_dt: float, penalty_step=None) -> None:
        super().calibrate(mass, stable_dt, penalty_step)
        node_mass = mass[self.connectivity[:, 0]]
        self._mass = node_mass
        if self.tool_node is not None:  # the relative motion's reduced mass
            self._tool_mass = float(mass[self.tool_node])
            node_mass = node_mass / (1.0 + self._mass_ratio)
        self.damping = 2.0 * self.damping_ratio * np.sqrt(self.stiffness * node_mass)
        self._omega_elements = 2.0 / stable_dt if 0.0 < stable_dt < np.inf else 0.0

    # ------------------------------------------------------------------ the damping force
    def _tool_frame(self, state: State) -> np.ndarray:
        """(s, 3) the nodes in the tool's frame: less its motion and free translation, mm."""
        return self._positions(state) - self.tool.offset(state.load_factor)

    def damping_forces(self, state: State, history: DampedHistory | None) -> np.ndarray:
        """(s, 3) the damping force the tool exerts on the nodes at ``state``, N: -c (dr/dt .
        n) n where a node penetrates; zero at rest (the quasi-static solvers) or without a
        step behind it."""
        count = len(self.connectivity)
        if history is None or not np.any(state.velocities):
            return np.zeros((count, 3))
        r = self._tool_frame(state)
        cached = self._last_damping
        if cached is not None and cached[1] is history and np.array_equal(cached[0], r):
            return cached[2].copy()
        if state.time > history.times[1]:
            span, start = state.time - history.times[1], history.last
        else:
            span, start = history.times[1] - history.times[0], history.before
        force = np.zeros((count, 3))
        if span > 0.0:
            p, n, _ = self.touch(state, history.inner)
            rate = np.sum((r - start) * n, axis=1) / span
            force = np.where((p > 0.0)[:, None], -(self.damping * rate)[:, None] * n, 0.0)
        self._last_damping = (r, history, force.copy())
        return force

    # ------------------------------------------------------------------ the contact's, wrapped
    def contact_forces(self, state: State, history: Any = None) -> np.ndarray:
        inner = None if history is None else history.inner
        return super().contact_forces(state, inner) + self.damping_forces(state, history)

    def strain_energy(self, state: State, history: Any = None) -> float:
        return super().strain_energy(state, None if history is None else history.inner)

    def tangent(self, state: State, history: Any = None):
        """The contact's: the damping has no stiffness (and no force at rest)."""
        return super().tangent(state, None if history is None else history.inner)

    def node_fields(self, state: State, history: Any = None) -> dict[str, np.ndarray]:
        return super().node_fields(state, None if history is None else history.inner)

    def freeze(self, state: State, history: Any = None, grow: bool = False):
        history = history if history is not None else self.initial_history()
        inner, changed = super().freeze(state, history.inner, grow)
        return replace(history, inner=inner), changed

    def thaw(self, history: Any):
        if history is None:
            return None
        return replace(history, inner=super().thaw(history.inner))

    def initial_history(self) -> DampedHistory:  # type: ignore[override]
        r = self._reference - self.tool.offset(0.0)
        zero = np.zeros_like(r)
        return DampedHistory(super().initial_history(), r.copy(), r, (0.0, 0.0), zero, 0.0)

    def update_history(self, state: State, history: Any) -> DampedHistory:
        """The contact's history updated; the damping force at the last state charged with
        the relative motion around it, half the step before it and half the step after (the
        midpoint rule); the new state's force kept."""
        if history is None:
            history = self.initial_history()
        r = self._tool_frame(state)
        around = 0.5 * (r - history.before)
        work = -float(np.sum(history.force * around))
        inner = super().update_history(state, history.inner)
        moved = DampedHistory(
            inner, history.last, r, (history.times[1], state.time), history.force, 0.0
        )
        force = self.damping_forces(state, moved)
        return replace(moved, force=force, dissipated=history.dissipated + work)

    def dissipated_energy(self, history: Any = None) -> float:
        """The friction's and the damping's, N mm: the damping's up to the last accepted
        state (its force there over the half step before it)."""
        if history is None:
            return 0.0
        half = -float(np.sum(history.force * 0.5 * (history.last - history.before)))
        return super().dissipated_energy(history.inner) + history.dissipated + half

    def springs(self) -> tuple[np.ndarray, np.ndarray]:
        """The contact's springs, each as the stiffness giving the stable step with its
        dashpot (``damped_spring``); the driven tool's node with the sum of the dashpots."""
        nodes, stiffness = super().springs()
        mass, damping = self._mass, self.damping
        if self.tool_node is not None:  # the tool's row: its mass on every spring and dashpot
            mass = np.append(mass, self._tool_mass)
            damping = np.append(damping, damping.sum())
        return nodes, damped_spring(stiffness, mass, damping, self._omega_elements)
