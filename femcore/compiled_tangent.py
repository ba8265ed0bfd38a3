"""The tangent of a compiled model: its parts' own tangents gathered, assembled, or replaced by
coloured central differences of their forces, and the Gershgorin bound of the critical step
that the assembled tangent gives (femcore.compiled.CompiledModel takes these methods).
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp

from femcore.assembly import NodeGraph, TangentPart, finite_difference_tangent, tangent_matrix
from femcore.compiled_checks import Part
from femcore.dofs import DofManager, Frames
from femcore.element import ElementBlock
from femcore.gershgorin import gershgorin_largest
from femcore.memory import small_pages
from femcore.state import State

__all__ = ["CompiledTangent"]


class CompiledTangent:
    """The tangent methods of femcore.compiled.CompiledModel, which sets the attributes
    declared here."""

    parts: list[Part]
    blocks: list[ElementBlock]
    dofs: DofManager
    n_nodes: int
    element_size: float

    if TYPE_CHECKING:

        def _histories(self, state: State) -> tuple: ...

        def internal_force(
            self, state: State, parts: list[int] | None = None
        ) -> tuple[np.ndarray, np.ndarray]: ...

    def tangent_parts(
        self,
        state: State,
        parts: list[int],
        compression_free: bool = False,
        real: State | None = None,
    ) -> list[TangentPart] | None:
        """The tangent parts of the parts of the given indices (into ``parts``), or None if
        one of them has no tangent of its own.

        ``compression_free``: the element blocks that offer it (``compression_free_tangent``
        true, femcore.element: the fibrous shell, elements/fibrous/tangent.py
        ``membrane_hessian``) give their tangent with the fibres' compression left out of its
        stress terms (beyond the compression of ``real``, the last converged state, where it is
        given), the static solver's tangent far from equilibrium (docs/theory.md §6.5); the
        other parts give their own tangent as without it.
        """
        histories = self._histories(state)
        tangent: list[TangentPart] = []
        for i in parts:
            part = self.parts[i]
            if (
                compression_free
                and isinstance(part, ElementBlock)
                and part.compression_free_tangent
            ):
                own = part.tangent_compression_free(state, histories[i], real=real)
            else:
                own = part.tangent(state, histories[i])
            if own is None:
                return None
            tangent.extend(own)
        return tangent

    def stiffness(
        self,
        state: State,
        method: str = "element",
        frames: Frames = None,
        parts: list[int] | None = None,
    ) -> sp.csr_matrix:
        """Tangent stiffness K = dF_int/dq (n x 5 slots square, femcore.dofs) at ``state``.

        Parameters
        ----------
        state : State
        method : "element" or "finite_difference"
            The parts' own tangents (every part must give one), or coloured central
            differences of their internal forces (translation step 1e-6 of the median element
            edge, rotation step 1e-6 rad).
        frames : Frames
            Nodal frames of the generalised rotations (default: those of ``state.directors``).
        parts : list of int or None
            Indices into ``parts`` of those to include (default: all).

        Raises
        ------
        ValueError
            For an unknown method, or "element" with a block that has no tangent of its own.
        """
        indices = list(range(len(self.parts))) if parts is None else list(parts)
        frames = self.dofs.frames(state.directors) if frames is None else frames
        if method == "element":
            tangent = self.tangent_parts(state, indices)
            if tangent is None:
                raise ValueError("a part has no tangent of its own: use method='finite_difference'")
            return tangent_matrix(self.dofs, tangent, frames)
        if method == "finite_difference":
            return self.finite_difference_stiffness(
                state, indices, self.node_graph(indices), frames
            )
        raise ValueError(f"method must be 'element' or 'finite_difference', got {method!r}")

    def node_graph(self, parts: list[int]) -> NodeGraph:
        """The colouring of the finite-difference tangent of the parts of the given indices
        (built once per solve: its greedy colouring loops over the nodes)."""
        reach = max(self.parts[i].reach for i in parts)
        return NodeGraph(self.n_nodes, [self.parts[i].connectivity for i in parts], reach)

    def finite_difference_stiffness(
        self, state: State, parts: list[int], graph: NodeGraph, frames: Frames
    ) -> sp.csr_matrix:
        """K of the parts of the given indices by coloured central differences of their
        internal forces: translation step 1e-6 of the median element edge, rotation step
        1e-6 rad, the nodal frames held."""
        return finite_difference_tangent(
            self.dofs,
            lambda s: self.internal_force(s, parts),
            state,
            graph,
            step=1e-6 * self.element_size,
            frames=frames,
        )

    def own_tangents(self, state: State) -> dict[int, Sequence[TangentPart]]:
        """The tangent parts at ``state`` of the parts that give a tangent of their own, by
        index into ``parts`` (the others return None: the finite-difference fallback)."""
        own = {}
        for i, (part, history) in enumerate(zip(self.parts, self._histories(state))):
            parts = part.tangent(state, history)
            if parts is not None:
                own[i] = parts
        return own

    def assembled_stable_dt(
        self, state: State, mass: np.ndarray, inertia: np.ndarray
    ) -> float | None:
        """A critical time step (s) of the assembled free system from Gershgorin's theorem:
        omega_max^2 <= max_i sum_j |K_ij| / sqrt(M_i M_j) over the free DOFs, K the blocks'
        own tangent at ``state`` and M the lumped ``mass`` and rotary ``inertia`` (n,) the
        solver uses (mass scaling included). A bound like the cells' own, but with the masses
        of the assembly: a sliver triangle's share of its nodes' mass is tiny while the nodes
        carry the mass of their other cells. Measured against the exact 2 / omega_max: 0.82 to
        0.95 on regular, stretched (aspect 20) and sliver cells of both shells, where the
        cells' bound fell to 0.03 on slivers (docs/theory.md §6.2). None when a block has no
        tangent of its own (finite differences would cost tens of force evaluations) or a
        free DOF has no mass."""
        free = self.dofs.free_slots
        diagonal = np.column_stack([mass, mass, mass, inertia, inertia]).ravel()[free]
        if free.size == 0 or not np.all(diagonal > 0.0):
            return None
        pieces = []
        histories = self._histories(state)
        # The element blocks alone: the interactions' springs are bounded apart
        # (``penalty_frequency_squared``), which the solver adds to this bound's omega^2.
        for block, history in zip(self.blocks, histories):
            given = block.tangent_pieces(state, history)
            if given is None:
                return None
            pieces.append(given)
        # The row sums of |K_ff| M^-1/2 over the free columns (a scale of 0 on the others),
        # from the pieces as they come (``again``: afresh, see gershgorin_largest).
        scale = np.zeros(self.dofs.n_slots)
        scale[free] = 1.0 / np.sqrt(diagonal)
        maps = self.dofs.node_maps(self.dofs.frames(state.directors))
        blocks = list(zip(self.blocks, histories))
        again = lambda: itertools.chain(*(b.tangent_pieces(state, h) or () for b, h in blocks))  # noqa: E731
        # the pieces are made, read once and dropped: ordinary pages (femcore/memory.py)
        with small_pages():
            largest = gershgorin_largest(
                itertools.chain(*pieces), maps, scale, self.n_nodes, again, self._seam_nodes()
            )
        return 2.0 / np.sqrt(largest) if largest > 0.0 else None

    def _seam_nodes(self) -> np.ndarray | None:
        """(n,) bool: the nodes of more than one element block (their rows held to the end
        while the bound streams, ``gershgorin_largest``'s ``shared``), or None for one block.
        A block's tangent pieces are taken to touch its cells' nodes alone; should one touch
        another node after all, the bound is made again with every pair held (the same
        number)."""
        if len(self.blocks) < 2:
            return None
        blocks_at = np.zeros(self.n_nodes, dtype=np.int64)
        for block in self.blocks:
            blocks_at[np.unique(block.connectivity)] += 1
        return blocks_at > 1
