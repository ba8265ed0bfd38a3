"""Node-to-tool penalty contact, frictionless: a node block (no mesh cells) on a node set,
against a rigid tool of elements/tools.py, added by ``Model.contact``.

The shell's contact surface is its mid-surface offset by half its thickness along the normal
(the thickness measured along the normal is conserved by both shells), so a node touches when
its distance d to the tool falls below ``offset`` = h / 2: the penetration is p = max(0,
offset - d) and the energy W = 1/2 k p^2 per node, the force on the node -k p n (n the tool's
normal towards the body) and its tangent k n n^T - k p c (I - n n^T - a a^T) (c the curvature
term of the tool, ``RigidTool.projector_scale``).

Penalty: given (N/mm per node), or chosen when the model is compiled (``calibrate``): k_i =
``PENALTY_SHARE`` m_i (2 / dt)^2, m_i the node's lumped mass and dt the model's critical step
without the contact. The contact spring then adds at most 10 % to omega^2 of a node, so the
explicit step at the default safety 0.9 stays stable (0.9 x sqrt(1.1) x 2 < 2), and a node
resting under its own weight sinks m g / k = g dt^2 / 0.4, far below the thickness.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from elements.base import CellTangent, ElementBlock, ElementType, Scatter
from elements.tools import RigidTool
from femcore.state import State

__all__ = ["PENALTY_SHARE", "Contact", "ContactBlock"]

PENALTY_SHARE = 0.1  # k m^-1 / omega_max^2 of the automatic penalty


class Contact(ElementType):
    """Frictionless penalty contact of ``nodes`` with a rigid ``tool``.

    Parameters
    ----------
    tool : elements.tools.RigidTool
    nodes : (s,) int
        The node ids that may touch.
    offset : float or (s,) float
        Half the thickness at each node, mm (the contact surface's distance from the
        mid-surface); 0 for a cable.
    penalty : float, optional
        k, N/mm per node; None: chosen when the model is compiled (module docstring).
    """

    dofs = ("ux", "uy", "uz")
    cell_type = None

    def __init__(self, tool: RigidTool, nodes, offset=0.0, penalty: float | None = None):
        if not isinstance(tool, RigidTool):
            raise ValueError(f"tool must be a rigid tool of elements.tools, got {tool!r}")
        self.tool = tool
        self.nodes = np.asarray(nodes, dtype=np.int64).ravel()
        self.offset = np.broadcast_to(np.asarray(offset, dtype=float), self.nodes.shape).copy()
        if not np.all(np.isfinite(self.offset)) or (self.offset < 0).any():
            raise ValueError(f"offset must be finite and >= 0 (mm), got {offset!r}")
        if penalty is not None and not (np.isfinite(penalty) and penalty > 0):
            raise ValueError(f"penalty must be a positive number (N/mm) or None, got {penalty!r}")
        self.penalty = penalty

    def bind(self, mesh, cell_ids, directors) -> ContactBlock:
        return ContactBlock(self, mesh.n_nodes)


class ContactBlock(ElementBlock):
    """The bound contact: one "cell" per node."""

    dofs = Contact.dofs
    cell_type = None
    reach = 1

    def __init__(self, contact: Contact, n_nodes: int):
        self.tool = contact.tool
        self.cell_ids = np.zeros(0, dtype=np.int64)
        self.connectivity = contact.nodes[:, None]
        self.scatter = Scatter(self.connectivity, n_nodes)
        self.n_nodes = n_nodes
        self.offset = contact.offset
        given = contact.penalty
        self.stiffness = np.full(len(contact.nodes), np.nan if given is None else given)

    def calibrate(self, mass: np.ndarray, stable_dt: float) -> None:
        if np.isnan(self.stiffness).any():  # the automatic penalty (module docstring)
            self.stiffness = PENALTY_SHARE * mass[self.connectivity[:, 0]] * (2.0 / stable_dt) ** 2

    def _touch(self, state: State):
        """Penetration p (s,), mm, the tool's normal (s, 3) at the nodes and whether each
        node touches (s,) bool: a node exactly on the surface counts, so that a body laid
        on a tool has a stiffness against it from the first Newton iteration."""
        x = state.positions[self.connectivity[:, 0]]
        d, n = self.tool.distance(x, state.load_factor)
        return np.maximum(self.offset - d, 0.0), n, d <= self.offset

    def contact_forces(self, state: State) -> np.ndarray:
        """(s, 3) the forces the tool exerts on the nodes, N (k p n)."""
        p, n, _ = self._touch(state)
        return (self.stiffness * p)[:, None] * n

    def tool_force(self, state: State) -> np.ndarray:
        """(3,) the total force the body exerts on the tool, N."""
        return -self.contact_forces(state).sum(axis=0)

    def lumped_mass(self, state: State, density_scale=None):
        return np.zeros(self.n_nodes), None  # a rigid tool adds no mass

    def internal_force(self, state: State, history: Any = None):
        return self.scatter.vectors(-self.contact_forces(state)[:, None, :]), None

    def strain_energy(self, state: State, history: Any = None) -> float:
        p, _, _ = self._touch(state)
        return float(0.5 * np.sum(self.stiffness * p**2))

    def tangent(self, state: State, history: Any = None):
        p, n, touching = self._touch(state)
        x = state.positions[self.connectivity[:, 0]]
        active = touching[:, None, None]
        k = self.stiffness[:, None, None]
        projector = np.eye(3) - n[:, :, None] * n[:, None, :]
        if self.tool.axis is not None:
            projector -= np.outer(self.tool.axis, self.tool.axis)
        scale = self.tool.projector_scale(x, state.load_factor)[:, None, None]
        blocks = np.where(
            active,
            k * (n[:, :, None] * n[:, None, :]) - k * p[:, None, None] * scale * projector,
            0.0,
        )
        return [CellTangent(self.connectivity, blocks[:, None, :, None, :])]

    def cell_stable_dt(self, state: State) -> np.ndarray:
        # The penalty is sized from the other blocks' step (calibrate): it cannot lower it by
        # more than the solvers' safety covers.
        return np.full(len(self.connectivity), np.inf)

    def node_fields(self, state: State, history: Any = None) -> dict[str, np.ndarray]:
        p, _, _ = self._touch(state)
        gap = np.full(self.n_nodes, np.nan)
        force = np.zeros(self.n_nodes)
        x = state.positions[self.connectivity[:, 0]]
        d, _ = self.tool.distance(x, state.load_factor)
        gap[self.connectivity[:, 0]] = d - self.offset  # < 0: penetration
        force[self.connectivity[:, 0]] = self.stiffness * p
        return {"contact_gap": gap, "contact_force": force}
