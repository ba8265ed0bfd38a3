"""A linear viscous dashpot between nodes and the ground: the force c v against each node's
velocity v (an interaction, femcore.interaction).

What it is for: a force-driven tool (a blank holder, elements/tools.py) is a mass on the
penalty springs of its contact, and with no damping of its own it rings on them: measured on
the two-ply hemisphere (validation/studies/hemisphere_plies.py), a 1-kg holder's force
averaged over the last tenth of the run was 9.9-25.9 N for a target of 10 or 20 N. A press
holds its ring down through a hydraulic cushion, which is a dashpot; at the critical damping
c = 2 sqrt(k m) of the holder's mass m on its contact stiffness k (``critical_damping``) the
ringing dies within a period and the holder's force settles on its target.

A holder also moves slowly as the process goes (the flange's wrinkles lift it, measured up
to 1.7 mm over the hemisphere's stroke), and a dashpot against that drift pushes back by c v:
with the critical damping of a 1-kg holder on its springs, 44-77 N against a target of 10.
``follow`` = tau (s) makes the dashpot act against the velocity relative to its exponential
mean over tau, v - v_bar with dv_bar/dt = (v - v_bar) / tau: a high-pass that damps the
ringing (periods well below tau) and lets a drift through (its force decays as exp(-t / tau)
at a steady velocity).

Explicit dynamics: the force is taken at the velocity v(i - 1/2) the step has (stable while
c dt / m < 2, which the critical damping of a contact the step already resolves keeps); the
energy it takes out, sum c v . dx over the accepted steps, is reported as dissipated
(``dissipated_energy``), so that the energy balance holds. Quasi-static solvers see no
velocity: no force, no tangent.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from femcore.interaction import Body, Interaction, InteractionBlock
from femcore.state import State

__all__ = ["Dashpot", "DashpotBlock", "DashpotHistory", "critical_damping"]


def critical_damping(mass: float, stiffness: float) -> float:
    """c = 2 sqrt(k m), N s/mm, of a mass ``mass`` (t) on a spring ``stiffness`` (N/mm)."""
    for name, value in (("mass", mass), ("stiffness", stiffness)):
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not value > 0:
            raise ValueError(f"critical_damping: {name} must be a positive number, got {value!r}")
        if not math.isfinite(value):
            raise ValueError(f"critical_damping: {name} must be finite, got {value!r}")
    return 2.0 * math.sqrt(mass * stiffness)


class Dashpot(Interaction):
    """A dashpot of coefficient ``damping`` c (N s/mm) from each of ``nodes`` to the ground,
    along every translation (a held one does not move; module docstring).

    Parameters
    ----------
    nodes : int or (s,) int
        Node ids (e.g. a force-driven tool's node, ``Model.contact``'s ``tool_node``).
    damping : float
        c > 0, N s/mm (``critical_damping`` for a mass on a spring).
    follow : float, optional
        tau > 0, s: the dashpot acts against the velocity relative to its mean over tau
        (module docstring); None: against the velocity.

    Raises
    ------
    ValueError
        No nodes, ids that are not non-negative integers, a damping that is not a positive
        finite number; at bind, ids out of range.
    """

    dofs = ("ux", "uy", "uz")

    def __init__(
        self, nodes: int | np.ndarray | list[int], damping: float, follow: float | None = None
    ):
        ids = np.atleast_1d(np.asarray(nodes))
        if ids.size == 0 or ids.dtype == bool or not np.issubdtype(ids.dtype, np.integer):
            raise ValueError(f"Dashpot: nodes must be node ids (integers), got {nodes!r}")
        if ids.min() < 0:
            raise ValueError(f"Dashpot: node id {int(ids.min())} is negative")
        if (
            isinstance(damping, bool)
            or not isinstance(damping, (int, float))
            or not math.isfinite(damping)
            or damping <= 0
        ):
            raise ValueError(
                f"Dashpot: damping must be a positive number (N s/mm), got {damping!r}"
            )
        if follow is not None and (
            isinstance(follow, bool)
            or not isinstance(follow, (int, float))
            or not math.isfinite(follow)
            or follow <= 0
        ):
            raise ValueError(f"Dashpot: follow must be a positive time (s) or None, got {follow!r}")
        self.nodes = np.unique(ids.astype(np.int64))
        self.damping = float(damping)
        self.follow = None if follow is None else float(follow)

    def bind(self, body: Body) -> DashpotBlock:
        if self.nodes.max() >= body.n_nodes:
            raise ValueError(
                f"Dashpot: node {int(self.nodes.max())} out of range (the model has "
                f"{body.n_nodes} nodes)"
            )
        return DashpotBlock(self.nodes, self.damping, body.mesh.points[self.nodes], self.follow)


@dataclass(frozen=True)
class DashpotHistory:
    """positions (s, 3), mm, of the nodes at the last accepted step; dissipated, N mm; the
    mean velocity v_bar (s, 3), mm/s (zero without ``follow``); time, s, of that step."""

    positions: np.ndarray
    dissipated: float
    mean_velocity: np.ndarray
    time: float


class DashpotBlock(InteractionBlock):
    """The bound dashpot: ``nodes`` (s,), ``damping`` c, N s/mm, ``follow`` tau, s, or
    None."""

    dofs = Dashpot.dofs
    reach = 1
    n_tools = 0

    def __init__(
        self, nodes: np.ndarray, damping: float, reference: np.ndarray, follow: float | None
    ):
        self.nodes = nodes
        self.damping = damping
        self.follow = follow
        self.connectivity = nodes[:, None]
        self._reference = np.array(reference, dtype=float)

    def internal_force(self, state: State, history: Any = None):
        force = np.zeros((state.n_nodes, 3))
        force[self.nodes] = self.damping * self._relative(state, history)
        return force, None

    def _relative(self, state: State, history: Any) -> np.ndarray:
        v = state.velocities[self.nodes]
        return v if history is None else v - history.mean_velocity

    def strain_energy(self, state: State, history: Any = None) -> float:
        return 0.0

    def tangent(self, state: State, history: Any = None) -> list:
        """None of its own against the positions (the force follows the velocities)."""
        return []

    def held_directions(self) -> tuple[np.ndarray, np.ndarray]:
        """None: a dashpot resists motion, it holds no position."""
        return np.zeros(0, dtype=np.int64), np.zeros((0, 3))

    def initial_history(self) -> DashpotHistory:
        return DashpotHistory(self._reference.copy(), 0.0, np.zeros_like(self._reference), 0.0)

    def update_history(self, state: State, history: Any) -> DashpotHistory:
        """The energy c (v - v_bar) . dx of the step added, v_bar followed over the step
        (exactly, for a velocity held over it), a new history."""
        x = state.positions[self.nodes]
        v = state.velocities[self.nodes]
        work = self.damping * float(
            np.sum(self._relative(state, history) * (x - history.positions))
        )
        mean = history.mean_velocity
        if self.follow is not None:
            share = 1.0 - math.exp(-(state.time - history.time) / self.follow)
            mean = mean + share * (v - mean)
        return DashpotHistory(x.copy(), history.dissipated + work, mean, state.time)

    def dissipated_energy(self, history: Any = None) -> float:
        return 0.0 if history is None else history.dissipated
