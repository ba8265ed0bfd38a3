"""A gripper's jaws: a set of nodes that translate together, as one rigid body that neither turns
nor deforms, wherever the rest of the model takes it.

A test rig lifts a specimen by a patch held between two jaws on a carriage: the patch moves as
one, and the carriage may be free to slide. ``model.displace`` prescribes components of each
node's motion; it cannot say "the same unknown motion for all of them". ``Grip`` does, by
penalty: a spring of stiffness k (N/mm) on the relative displacement of each node of the set
to its first node, energy 1/2 k sum_i |(x_i - x_0) - (X_i - X_0)|^2. Components that are
prescribed alike at every node (a lift) cost nothing; the free ones (a carriage's horizontal
slide) move together. Holding the directors (the jaws' faces) is the supports' job:
``model.fix(nodes, ("alpha", "beta"))``.
"""

from __future__ import annotations

import numpy as np

from femcore.assembly import CellTangent
from femcore.checks import check_positive
from femcore.interaction import Body, Interaction, InteractionBlock
from femcore.state import State

__all__ = ["Grip", "GripBlock"]


class Grip(Interaction):
    """The nodes ``nodes`` (node ids or a node-set name, at least two) translate together.

    Parameters
    ----------
    nodes : str or array of int
        The gripped nodes; the first (lowest id for a node set) is the one the others are
        tied to.
    stiffness : float
        k, N/mm, of each node's spring to the first: large against the structure's own
        stiffness at the nodes (the nodes part by the force they carry / k).

    Raises
    ------
    ValueError
        For a stiffness that is not positive and finite; at bind, for fewer than two nodes.
    """

    dofs = ("ux", "uy", "uz")

    def __init__(self, nodes: str | np.ndarray | list[int], stiffness: float):
        self.nodes = nodes
        self.stiffness = check_positive(stiffness, "Grip stiffness", "N/mm")

    def bind(self, body: Body) -> GripBlock:
        """The springs from the first node to each other one."""
        nodes = self.nodes
        ids = body.mesh.nodes(nodes) if isinstance(nodes, str) else np.asarray(nodes, np.int64)
        ids = np.asarray(ids, dtype=np.int64).ravel()
        if ids.size < 2 or len(np.unique(ids)) != ids.size:
            raise ValueError(f"Grip needs two or more distinct nodes, got {ids.tolist()}")
        pairs = np.column_stack([np.full(ids.size - 1, ids[0]), ids[1:]])
        return GripBlock(pairs, self.stiffness, body.mesh.points)


class GripBlock(InteractionBlock):
    """A bound ``Grip``: ``connectivity`` (m, 2) the pairs (first node, other node)."""

    dofs = Grip.dofs
    reach = 1

    def __init__(self, pairs: np.ndarray, stiffness: float, points: np.ndarray):
        self.connectivity = pairs
        self.stiffness, self.n_nodes = stiffness, len(points)
        self.rest = points[pairs[:, 0]] - points[pairs[:, 1]]  # X_0 - X_i, (m, 3)

    def _parting(self, state: State) -> np.ndarray:
        """(x_0 - x_i) - (X_0 - X_i) per pair, (m, 3) mm: zero while they move as one."""
        x = state.positions
        return x[self.connectivity[:, 0]] - x[self.connectivity[:, 1]] - self.rest

    def internal_force(self, state: State, history=None) -> tuple[np.ndarray, None]:
        """dW/dx (n, 3), N: k (parting) on the first node, its opposite on the other."""
        pull = self.stiffness * self._parting(state)
        force = np.zeros((self.n_nodes, 3))
        np.add.at(force, self.connectivity[:, 0], pull)
        np.add.at(force, self.connectivity[:, 1], -pull)
        return force, None

    def strain_energy(self, state: State, history=None) -> float:
        """1/2 k sum |parting|^2, N mm."""
        return float(0.5 * self.stiffness * np.sum(self._parting(state) ** 2))

    def tangent(self, state: State, history=None) -> list[CellTangent]:
        """Constant: k I on the diagonal blocks of each pair, -k I off them."""
        k = self.stiffness * np.eye(3)
        blocks = np.empty((len(self.connectivity), 2, 3, 2, 3))
        blocks[:, 0, :, 0] = blocks[:, 1, :, 1] = k
        blocks[:, 0, :, 1] = blocks[:, 1, :, 0] = -k
        return [CellTangent(self.connectivity, blocks)]

    def springs(self) -> tuple[np.ndarray, np.ndarray]:
        """For the explicit step: a spring between two nodes raises omega^2 by at most
        k (1 / m_a + 1 / m_b), which a spring of 2 k to the ground at each bounds; the first
        node carries all of its pairs' springs."""
        others = self.connectivity[:, 1]
        spring = 2.0 * self.stiffness
        nodes = np.r_[self.connectivity[0, 0], others]
        return nodes, np.r_[spring * len(others), np.full(len(others), spring)]
