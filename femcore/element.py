"""The element protocol: what an element type must provide to plug into a Model and every solver.

An element *type* (``Cable``, ``FibrousShell``, a user's own class) holds only material and
options. ``Model.compile`` binds it to the mesh: ``ElementType.bind`` returns an element *block*,
one element type over many cells, holding the reference geometry, the index arrays and every
option it needs, all computed once. Every block method is vectorised over the cells of the block
(leading axis = cell); none loops in Python over cells or nodes.

A block may also act on nodes rather than on mesh cells (a contact with a rigid tool, a tie):
its type declares ``cell_type = None`` and its block's ``connectivity`` lists the nodes it acts
on, one row per "cell" of its own (a node, a node pair, ...).

Supports: after the DOF manager is built, ``CompiledModel`` tells each block which of its nodes
the model holds (every DOF of the block at the node fixed or prescribed) through
``ElementBlock.apply_supports``; a block whose mechanics depend on it (the rotation-free bending
of ``FibrousShell`` clamps itself there) overrides it, every other block ignores it.

History variables (plastic strains, stick/slip anchors of a frictional contact) live in the
``State``, one entry per block (``State.history[i]`` for ``model.blocks[i]``). The model passes a
block its entry with the state; a block never mutates it: ``update_history`` returns the new one
when a solver accepts a step (state in, new state out).

Sign convention: ``internal_force`` returns F_int = dW/dx and the moment vectors dW/dpsi (Bai
Eq. 22-23), so that the residual a solver drives to zero is F_ext - F_int. Units in the
docstrings are those of the examples (mm, N, t, s); any consistent set works.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Sequence
from typing import Any, ClassVar

import numpy as np

from femcore.assembly import CellTangent, Scatter, SparseTangent, TangentPart
from femcore.mesh import Mesh
from femcore.state import State

__all__ = ["CellTangent", "ElementBlock", "ElementType", "SparseTangent", "TangentPart"]


class ElementType(ABC):
    """Material and options of one element family; ``bind`` makes a block over mesh cells.

    Class attributes
    ----------------
    dofs : tuple of str
        DOF names each node of the element needs, e.g. ``("ux", "uy", "uz")`` (femcore.dofs).
    cell_type : str or None
        The mesh cells the element covers: ``"line"`` (2-node, ``mesh.lines``), ``"triangle"``
        (``mesh.triangles``), or None for a block that acts on nodes (contact, tie): it is added
        with ``model.add(element)`` and finds its nodes itself at bind.
    defines_directors : bool
        True for shells: the area-weighted normals of the element's triangles define the
        reference directors of their nodes (the rotational DOFs turn them).
    """

    dofs: ClassVar[tuple[str, ...]] = ()
    cell_type: ClassVar[str | None] = None
    defines_directors: ClassVar[bool] = False

    @property
    def half_thickness(self) -> float:
        """Distance (mm) from the mid-surface to the contact surface along the normal, for
        ``Model.contact``: half the thickness for a shell; 0 by default (a cable)."""
        return 0.0

    @abstractmethod
    def bind(self, mesh: Mesh, cell_ids: np.ndarray, directors: np.ndarray) -> ElementBlock:
        """Block over the given cells of the mesh, with every option resolved once.

        Parameters
        ----------
        mesh : Mesh
            The model's mesh.
        cell_ids : (m,) int
            Ids into the mesh cells of ``cell_type`` (empty for node blocks).
        directors : (n, 3) float
            Reference unit directors (zero rows at nodes without rotations).
        """


class ElementBlock(ABC):
    """One element type over many cells, bound to a mesh.

    Attributes
    ----------
    dofs : tuple of str
        The DOF names of its nodes (those of its type).
    cell_type : str or None
        As its type.
    cell_ids : (m,) int
        Mesh cells covered (empty for node blocks).
    connectivity : (m, k) int
        Global node ids of each cell; the node graph of the finite-difference tangent and the
        sparsity of the element tangent are built from it.
    scatter : femcore.assembly.Scatter
        Gather/scatter over ``connectivity``.
    reach : int
        How many cell-hops the internal force at a node reaches: 1 when each cell's loads
        depend on its own nodes only, 2 for rotation-free bending over neighbour patches.
        Every block declares it (the model refuses a block without it): a reach too small
        gives a wrong finite-difference tangent without any error.
    """

    dofs: tuple[str, ...]
    cell_type: str | None
    cell_ids: np.ndarray
    connectivity: np.ndarray
    scatter: Scatter
    reach: int

    # ------------------------------------------------------------------ required
    @abstractmethod
    def lumped_mass(
        self, state: State, density_scale: np.ndarray | None = None
    ) -> tuple[np.ndarray, np.ndarray | None]:
        """Nodal translational mass and rotary inertia.

        Parameters
        ----------
        state : State
        density_scale : (m,) float or None
            Factor >= 1 per cell for selective mass scaling.

        Returns
        -------
        mass : (n,) float, t
        inertia : (n,) float, t mm^2, or None for elements without rotational DOFs.
        """

    @abstractmethod
    def internal_force(
        self, state: State, history: Any = None
    ) -> tuple[np.ndarray, np.ndarray | None]:
        """Nodal internal forces, already scattered to the nodes.

        Returns
        -------
        force : (n, 3) float, N
            F_int = dW/dx.
        moment : (n, 3) float, N mm, or None
            dW/dpsi at the directors, None for elements without rotational DOFs.
        """

    @abstractmethod
    def cell_stable_dt(self, state: State) -> np.ndarray:
        """Critical time step of each cell (m,), s: lumped mass, no damping."""

    @abstractmethod
    def strain_energy(self, state: State, history: Any = None) -> float:
        """Energy stored in the block (N mm): the potential whose gradient is the force."""

    # ------------------------------------------------------------------ optional
    def tangent(self, state: State, history: Any = None) -> Sequence[TangentPart] | None:
        """The block's own stiffness d(internal_force)/d(u, psi) as tangent parts (CellTangent
        blocks per cell, or a SparseTangent over all nodes for wider couplings), or None
        (the default): the assembler then differentiates ``internal_force`` by coloured central
        differences over the node graph of ``connectivity`` and ``reach``."""
        return None

    def apply_supports(self, held: np.ndarray) -> None:
        """Learn which nodes the model's supports hold; the default ignores it.

        Called once by ``CompiledModel`` after ``bind`` and before any force, mass or tangent
        is evaluated. ``held`` (n,) bool is True at the nodes where every DOF of the block
        (its ``dofs``) is fixed (``model.fix``) or prescribed (``model.displace``). A block
        may update its own tables here (and raise ValueError for options the supports
        contradict); it must not keep a reference to ``held``.
        """
        return None

    def calibrate(self, mass: np.ndarray, stable_dt: float) -> None:
        """Size the block from the assembled model; the default ignores it.

        Called once by ``CompiledModel`` after the supports, with the lumped nodal masses of
        the whole model (n,), t, and its critical step, s (the smallest of every block's
        cells'): what a block without mass of its own needs to choose a stiffness that keeps
        the explicit step stable (a contact penalty, elements/contact.py).
        """
        return None

    def penalty_springs(self) -> tuple[np.ndarray, np.ndarray] | None:
        """Springs the block puts between single nodes and the ground: (nodes (s,), stiffness
        (s,) N/mm), each acting along any direction (a contact penalty, its friction's stick
        stiffness the same); None by default. They have no cells of their own, so the explicit
        step takes their frequency sqrt(k / m) in with the nodes' masses."""
        return None

    def initial_history(self) -> Any:
        """History variables of the block in the reference state (None: it has none)."""
        return None

    def update_history(self, state: State, history: Any) -> Any:
        """The history after a step a solver accepted at ``state``; never mutates ``history``."""
        return history

    def dissipated_energy(self, history: Any = None) -> float:
        """Energy the block has dissipated since the start (N mm), kept in its history (the
        friction of a contact); 0 by default. The explicit solver's energy balance counts it."""
        return 0.0

    def tool_force(self, state: State, history: Any = None) -> np.ndarray | None:
        """(3,) the force (N) the model exerts on the block's rigid tool, for blocks that act
        against one (contact); None by default."""
        return None

    def tool_work(self, state: State, history: Any, start: float, end: float) -> float:
        """Work (N mm) a block's moving tool does on the model while the load factor goes from
        ``start`` to ``end``, with the forces at ``state``; 0 by default (no tool, or one that
        stays put). The explicit solver's energy balance counts it as external work."""
        return 0.0

    def stable_dt(self, state: State) -> float:
        """Critical time step of the block, s."""
        return float(np.min(self.cell_stable_dt(state)))

    def cell_fields(self, state: State, history: Any = None) -> dict[str, np.ndarray]:
        """Per-cell outputs {name: (m, ...)} for results and VTU files."""
        return {}

    def node_fields(self, state: State, history: Any = None) -> dict[str, np.ndarray]:
        """Nodal outputs {name: (n, ...)} for results and VTU files."""
        return {}
