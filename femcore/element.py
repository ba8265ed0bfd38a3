"""The element protocol: what an element type must provide to plug into a Model and every solver.

An element *type* (``Cable``, ``FibrousShell``, a user's own class) holds only material and
options. ``Model.compile`` binds it to the mesh: ``ElementType.bind`` returns an element *block*,
one element type over many cells, holding the reference geometry, the index arrays and every
option it needs, all computed once. Every block method is vectorised over the cells of the block
(leading axis = cell); none loops in Python over cells or nodes.

What acts on nodes without cells of its own (a contact with a rigid tool, a tie, the contact
of two bodies) is not an element: it is an interaction (femcore.interaction), with its own
small protocol.

Supports: after the DOF manager is built, ``CompiledModel`` tells each block which of its nodes
the model holds (every DOF of the block at the node fixed or prescribed) through
``ElementBlock.apply_supports``; a block whose mechanics depend on it (the rotation-free bending
of ``FibrousShell`` clamps itself there) overrides it, every other block ignores it.

Capabilities: what the static solver asks of a block beyond forces, energies and tangents
(a tangent without the fibres' compression, ``compression_free_tangent``; the fibre edges and
the levels' fibre strains it keeps, ``fibre_edges``, ``has_fibre_strains``) are members of
this protocol, each with a default on ``ElementBlock`` that means the block lacks it; the
solvers call them and never test a block's class or probe it for an attribute, and the
element kit checks what a block declares (femcore/capability_checks.py).

History variables (plastic strains, damage) live in the ``State``, one entry per block
(``State.history[i]`` for ``model.blocks[i]``). The model passes a
block its entry with the state; a block never mutates it: ``update_history`` returns the new one
when a solver accepts a step (state in, new state out).

Sign convention: ``internal_force`` returns F_int = dW/dx and the moment vectors dW/dpsi (Bai
Eq. 22's F_int, the fibrous shell's nodal forces Eq. 24 and moments Eq. 28), so that the
residual a solver drives to zero is F_ext - F_int. Units in the
docstrings are those of the examples (mm, N, t, s); any consistent set works.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Iterator, Sequence
from typing import Any, ClassVar

import numpy as np

from femcore.assembly import CellTangent, Scatter, SparseTangent, TangentPart
from femcore.mesh import Mesh
from femcore.read_only_state import ReadOnlyState
from femcore.state import State

__all__ = [
    "CellTangent",
    "ElementBlock",
    "ElementType",
    "SparseTangent",
    "TangentPart",
    "are_node_pairs",
]


def are_node_pairs(edges: object) -> bool:
    """Whether ``edges`` is what ``ElementBlock.fibre_edges`` gives: a (k, 2) integer array of
    node ids (the static solver's fibre projection and the element kit both ask)."""
    return (
        isinstance(edges, np.ndarray)
        and edges.ndim == 2
        and edges.shape[1] == 2
        and edges.dtype.kind in "iu"
    )


class ElementType(ABC):
    """Material and options of one element family; ``bind`` makes a block over mesh cells.

    Class attributes
    ----------------
    dofs : tuple of str
        DOF names each node of the element needs, e.g. ``("ux", "uy", "uz")`` (femcore.dofs).
    cell_type : str
        The mesh cells the element covers: ``"line"`` (2-node, ``mesh.lines``) or
        ``"triangle"`` (``mesh.triangles``).
    defines_directors : bool
        True for shells: the area-weighted normals of the element's triangles define the
        reference directors of their nodes (the rotational DOFs turn them).
    takes_moments : bool
        For an element with rotational DOFs: True when a nodal moment on them bends it (a
        Mindlin shell's rotations are its sections'); False when they are something else (the
        fibrous shell's directors are material normals, its bending rotation-free): a moment
        on nodes only such elements use is refused when the model is compiled.
    """

    dofs: ClassVar[tuple[str, ...]] = ()
    cell_type: ClassVar[str]
    defines_directors: ClassVar[bool] = False
    takes_moments: ClassVar[bool] = True

    @property
    def half_thickness(self) -> float:
        """Distance (mm) from the mid-surface to the element's surface along the normal: half
        the thickness for a shell, 0 by default (a cable). Interactions read it (a contact
        surface lies there: femcore.interaction.Body.half_thickness)."""
        return 0.0

    @abstractmethod
    def bind(self, mesh: Mesh, cell_ids: np.ndarray, directors: np.ndarray) -> ElementBlock:
        """Block over the given cells of the mesh, with every option resolved once.

        Parameters
        ----------
        mesh : Mesh
            The model's mesh.
        cell_ids : (m,) int
            Ids into the mesh cells of ``cell_type``.
        directors : (n, 3) float
            Reference unit directors (zero rows at nodes without rotations).
        """


class ElementBlock(ReadOnlyState, ABC):
    """One element type over many cells, bound to a mesh.

    Attributes
    ----------
    dofs : tuple of str
        The DOF names of its nodes (those of its type).
    cell_type : str
        As its type.
    cell_ids : (m,) int
        Mesh cells covered.
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

    compression_free_tangent : bool
        Whether the block gives a tangent with the fibres' compression left out of its stress
        terms (``tangent_compression_free``), which the static solver takes far from
        equilibrium (docs/theory.md §6.5); False by default: the block's tangent is its only
        one (the fibrous shell declares True).
    has_fibre_strains : bool
        Whether the block gives its levels' fibre strains, their gradient and their laws'
        range (``fibre_strains``, ``fibre_strain_gradient``, ``fibre_strain_range``), which
        the static solver's level projection keeps at their first order
        (solvers/newton_levels.py) and the quasi-static solvers' acceptance judges
        (solvers/acceptance.py); False by default:
        the block has no nearly inextensible measures to keep (the fibrous shell declares
        True).
    """

    dofs: tuple[str, ...]
    cell_type: str
    cell_ids: np.ndarray
    connectivity: np.ndarray
    scatter: Scatter
    reach: int
    compression_free_tangent: bool = False
    has_fibre_strains: bool = False

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
    def internal_force_and_energy(
        self, state: State, history: Any = None
    ) -> tuple[np.ndarray, np.ndarray | None, float]:
        """``internal_force`` and ``strain_energy`` at the same state, in one call.

        The explicit solver asks for both on the steps where it checks the energy balance.
        The default makes the two calls (two passes over the cells); a block whose force pass
        meets the energy on the way (a compiled kernel summing 1/2 E . D E where it forms the
        stresses) overrides it and returns both from one pass. An override must return the
        same values as the two methods (to rounding): the conformance tests hold it there.

        Returns
        -------
        force : (n, 3) float, N
            As ``internal_force``.
        moment : (n, 3) float, N mm, or None
            As ``internal_force``.
        energy : float, N mm
            As ``strain_energy``.
        """
        force, moment = self.internal_force(state, history)
        return force, moment, float(self.strain_energy(state, history))

    def tangent(self, state: State, history: Any = None) -> Sequence[TangentPart] | None:
        """The block's own stiffness d(internal_force)/d(u, psi) as tangent parts (CellTangent
        blocks per cell, or a SparseTangent over all nodes for wider couplings), or None
        (the default): the assembler then differentiates ``internal_force`` by coloured central
        differences over the node graph of ``connectivity`` and ``reach``."""
        return None

    def tangent_pieces(self, state: State, history: Any = None) -> Iterator[TangentPart] | None:
        """``tangent`` in pieces whose sum is the block's tangent (CellTangent parts over
        subsets of its cells), or None when it has no tangent of its own. The default gives
        ``tangent``'s parts; a block that forms its tangent a slice of cells at a time
        overrides it, so that a caller summing the pieces as they come (the explicit
        solver's Gershgorin bound, femcore/gershgorin.py) never holds all the cells' blocks
        at once."""
        parts = self.tangent(state, history)
        return None if parts is None else iter(parts)

    def tangent_compression_free(
        self, state: State, history: Any = None, real: State | None = None
    ) -> Sequence[TangentPart] | None:
        """``tangent`` with the fibres' compression left out of its stress terms, asked only
        of a block that declares ``compression_free_tangent`` (femcore/compiled_tangent.py):
        the compression beyond that of ``real``, the last converged state (whose
        compression is real, not a step's remainder), or all of it without ``real``. The
        default is ``tangent`` itself: a block without fibres has no compression to leave
        out."""
        return self.tangent(state, history)

    def fibre_edges(self) -> np.ndarray:
        """(k, 2) int node pairs of the edges that run along the fibres in the reference: the
        nearly inextensible lines the static solver's fibre-length projection keeps
        (solvers/newton_fibres.py). The default, (0, 2): the block has no such edge."""
        return np.zeros((0, 2), dtype=np.int64)

    def fibre_strains(self, state: State) -> np.ndarray:
        """(m, p) float, the fibre strains (and shear angles, rad) of each cell's levels at
        ``state``, zero in the reference; asked only of a block that declares
        ``has_fibre_strains`` (solvers/newton_levels.py), which must override it."""
        raise NotImplementedError(
            f"{type(self).__name__} declares has_fibre_strains but does not override "
            "fibre_strains: give both, or neither"
        )

    def fibre_strain_range(self) -> tuple[np.ndarray, np.ndarray]:
        """(lower, upper) float, each (p,) per column of ``fibre_strains`` or (m, p) per cell and
        column (a cell whose columns are different fibres' measures): the strains past
        which the block's force along that measure falls as it stretches (in tension, above
        ``upper``) or as it shortens (in compression, below ``lower``): its law's own range,
        where a quasi-static solver may accept a state (solvers/acceptance.py, docs/theory.md
        §6.4d); -inf and inf where the force never falls (a shear angle, a stiffening law).
        Asked only of a block that declares ``has_fibre_strains``, which must override it."""
        raise NotImplementedError(
            f"{type(self).__name__} declares has_fibre_strains but does not override "
            "fibre_strain_range: give it with fibre_strains"
        )

    def fibre_strain_gradient(self, state: State) -> tuple:
        """The derivatives of ``fibre_strains`` at each cell's corners and the pairs of
        corners they are combined over (elements/fibrous/level_jacobian.py
        ``level_strain_gradient``); asked only of a block that declares ``has_fibre_strains``,
        which must override it."""
        raise NotImplementedError(
            f"{type(self).__name__} declares has_fibre_strains but does not override "
            "fibre_strain_gradient: give both, or neither"
        )

    def inverted_cells(self, state: State) -> np.ndarray:
        """(k,) int, the mesh cells (of ``cell_ids``) turned inside out at ``state``: their
        material's volume ratio is not positive, an unphysical state some energies cannot
        tell (a Saint Venant-Kirchhoff membrane mirrored onto itself is unstrained); the
        static solver refuses a converged increment that has one (solvers/static_run.py).
        The default, none: the block's energy sees no such state, or it cannot tell."""
        return np.zeros(0, dtype=np.int64)

    def apply_supports(self, held: np.ndarray, constrained: np.ndarray | None = None) -> None:
        """Learn which nodes the model's supports hold; the default ignores it.

        Called once by ``CompiledModel`` after ``bind`` and before any force, mass or tangent
        is evaluated. ``held`` (n,) bool is True at the nodes where every DOF of the block
        (its ``dofs``) is fixed (``model.fix``) or prescribed (``model.displace``);
        ``constrained`` (n, len(dofs)) bool says which of them, DOF by DOF in the order of
        ``dofs``. A block may update its own tables here (and raise ValueError for options
        the supports contradict); it must not keep a reference to either.
        """
        return None

    def support_moments(self, state: State, history: Any = None) -> np.ndarray | None:
        """Moments (n, 3), N mm, that the supports exert on the block through no DOF: a wall
        its energy bends against (the fibrous shell's clamp, docs/theory.md §4.5), which the
        DOFs' reactions do not see. The solvers add them to the frames' reaction moments.
        The default, None: every support moment of the block acts on a DOF."""
        return None

    def initial_history(self) -> Any:
        """History variables of the block in the reference state (None: it has none)."""
        return None

    def update_history(self, state: State, history: Any) -> Any:
        """The history after a step a solver accepted at ``state``; never mutates ``history``."""
        return history

    def stable_dt(self, state: State) -> float:
        """Critical time step of the block, s."""
        return float(np.min(self.cell_stable_dt(state)))

    def penalty_stable_dt(self, state: State) -> float:
        """The step the interactions' automatic penalty is sized on, s: the block's critical
        step at a rotary inertia fixed by the model, so that a chosen mass scaling of the
        rotations alone leaves the contacts' stiffness as it is (docs/theory.md §6.2, "The
        penalty's step"). The default is ``stable_dt``: blocks without a rotary inertia to
        choose; the Mindlin shell overrides it (its step at B2's closed-form j)."""
        return self.stable_dt(state)

    def cell_fields(self, state: State, history: Any = None) -> dict[str, np.ndarray]:
        """Per-cell outputs {name: (m, ...)} for results and VTU files."""
        return {}

    def node_fields(self, state: State, history: Any = None) -> dict[str, np.ndarray]:
        """Nodal outputs {name: (n, ...)} for results and VTU files."""
        return {}
