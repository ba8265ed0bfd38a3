"""Model: the fixed description of a problem (mesh, element blocks, constraints, loads).

A ``Model`` is written by the user through a few builder methods, each of which validates its
input at once. Solvers call ``model.compile()``, which binds the element blocks to the mesh and
turns the records into the index arrays and nodal vectors a time step needs. The changing
quantities live in ``femcore.state.State``.
"""

from __future__ import annotations

import inspect
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace

import numpy as np
import scipy.sparse as sp
from numpy.typing import ArrayLike

from femcore.assembly import NodeGraph, TangentPart, finite_difference_tangent, tangent_matrix
from femcore.dofs import DOF_NAMES, DofManager, Frames, dof_columns, dof_names
from femcore.element import ElementBlock, ElementType
from femcore.loads import (
    Amplitude,
    AmplitudeFunction,
    Fix,
    Gravity,
    NodalLoad,
    Prescribed,
    amplitude_of,
)
from femcore.mesh import CELL_KINDS, Mesh, NodePredicate
from femcore.rotation import drop_along, nodal_frames
from femcore.state import State
from femcore.topology import check_triangles, nodal_normals

__all__ = ["BlockEntry", "CompiledModel", "Model", "NodeSelection"]

#: A node selection: the name of a node set of the mesh, node ids, or a predicate
#: ``(x, y, z) -> mask`` over the node coordinates (as ``Mesh.nodes`` takes).
NodeSelection = str | int | Sequence[int] | np.ndarray | NodePredicate


def _vector3(value, what: str) -> np.ndarray:
    vector = np.asarray(value, dtype=float)
    if vector.shape != (3,) or not np.all(np.isfinite(vector)):
        raise ValueError(f"{what} must be 3 finite numbers, got {value!r}")
    return vector


@dataclass(frozen=True)
class BlockEntry:
    """An element type and the mesh cells (of its cell type) it covers."""

    element: ElementType
    cells: np.ndarray


class Model:
    """Mesh + element blocks + constraints + loads.

    The builder methods (add, fix, displace, force, moment, gravity) append to the description
    and validate their arguments immediately, so that a wrong node id or DOF name is reported
    where it was written.
    """

    def __init__(self, mesh: Mesh):
        if not isinstance(mesh, Mesh):
            raise ValueError(f"Model needs a femcore.Mesh, got {type(mesh).__name__}")
        self.mesh = mesh
        self.blocks: list[BlockEntry] = []
        self.fixes: list[Fix] = []
        self.prescribed: list[Prescribed] = []
        self.loads: list[NodalLoad] = []
        self.gravities: list[Gravity] = []
        self._compiled: CompiledModel | None = None

    # ----------------------------------------------------------------- description
    def add(self, element: ElementType, cells: str | np.ndarray | list[int] | None = None) -> int:
        """Add an element block.

        Parameters
        ----------
        element : ElementType
            An element type (femcore.element.ElementType): a cell element (cable, shell) or a
            block that acts on nodes (``cell_type`` None: a contact, a tie).
        cells : None, str or array of int
            Ids of the mesh cells of the element's cell type; None = all of them; a string = a
            named set of those cells. Must be None for a node block.

        Returns
        -------
        int
            The block index (``model.blocks[i]``, ``State.history[i]``).
        """
        if not isinstance(element, ElementType):
            raise ValueError(
                f"{type(element).__name__} is not an element type: expected an instance of a "
                "subclass of femcore.element.ElementType (elements.base)"
            )
        cell_type = element.cell_type
        if cell_type is None:
            if cells is not None:
                raise ValueError(
                    f"{type(element).__name__} acts on nodes (cell_type None): add it without "
                    f"cells, got cells={cells!r}"
                )
            self.blocks.append(BlockEntry(element, np.zeros(0, dtype=np.int64)))
            self._compiled = None
            return len(self.blocks) - 1
        if cell_type not in CELL_KINDS:
            raise ValueError(
                f"{type(element).__name__}.cell_type is {cell_type!r}: expected one of "
                f"{tuple(CELL_KINDS)} or None (a block acting on nodes)"
            )
        n_cells = len(self.mesh.cells(cell_type))
        if cells is None:
            ids = np.arange(n_cells)
        elif isinstance(cells, str):
            sets = self.mesh.cell_sets(cell_type)
            if cells not in sets:
                raise ValueError(
                    f"no {cell_type} set named {cells!r}: the mesh has {sorted(sets) or 'none'}"
                )
            ids = np.asarray(sets[cells], dtype=np.int64)
        else:
            ids = self._ids(cells, n_cells, f"{cell_type} cell")
        if ids.size == 0:
            raise ValueError(
                f"{type(element).__name__} block covers no cell: the mesh has "
                f"{n_cells} {cell_type} cells"
            )
        # Two blocks on one cell would add its mass and stiffness twice, silently.
        for index, entry in enumerate(self.blocks):
            if entry.element.cell_type != cell_type:
                continue
            shared = np.intersect1d(entry.cells, ids)
            if shared.size:
                again = " (the same element object added again)" if entry.element is element else ""
                raise ValueError(
                    f"{type(element).__name__} on {cell_type} cells {shared[:5].tolist()}"
                    f"{'...' if shared.size > 5 else ''} that block {index} "
                    f"({type(entry.element).__name__}) already covers{again}: one element per "
                    "cell; give each block its own cells (a cell set or ids)"
                )
        self.blocks.append(BlockEntry(element, ids))
        self._compiled = None
        return len(self.blocks) - 1

    def fix(self, nodes: NodeSelection, dofs: str | Sequence[str] | None = None) -> None:
        """Hold DOFs at zero.

        Parameters
        ----------
        nodes : str, array of int or callable
            A node-set name of the mesh, node ids, or a predicate ``(x, y, z) -> mask``.
        dofs : None, str or sequence of str
            None = every DOF of those nodes, or names such as "uz", ("ux", "uy", "uz"),
            "alpha" (femcore.dofs.DOF_NAMES).

        Raises
        ------
        ValueError
            For an unknown set, node id or DOF name.
        """
        columns = None if dofs is None else dof_columns(dofs)
        self.fixes.append(Fix(self._node_ids(nodes), columns))
        self._compiled = None

    def displace(
        self,
        nodes: NodeSelection,
        ux: ArrayLike | None = None,
        uy: ArrayLike | None = None,
        uz: ArrayLike | None = None,
        amplitude: str | AmplitudeFunction = "smooth",
    ) -> None:
        """Prescribe translations, reached at the end of the step or of the load increments.

        Parameters
        ----------
        nodes : str, array of int or callable
            A node-set name of the mesh, node ids, or a predicate ``(x, y, z) -> mask``.
        ux, uy, uz : float, (k,) floats or None
            Displacement (mesh length unit), one number or one per selected node; a component
            left None stays free.
        amplitude : str or callable
            Time history in dynamics ("smooth", "linear", "step" or a(tau)); static solvers
            ramp with the load factor.

        Raises
        ------
        ValueError
            For an unknown set or node id, a non-finite value, or no component given.
        """
        ids = self._node_ids(nodes)
        values = np.full((ids.size, 3), np.nan)
        given = False
        for column, (name, value) in enumerate((("ux", ux), ("uy", uy), ("uz", uz))):
            if value is None:
                continue
            value = np.asarray(value, dtype=float)
            if value.shape not in ((), (ids.size,)) or not np.all(np.isfinite(value)):
                raise ValueError(
                    f"{name} must be a finite number or {ids.size} finite numbers (one per node), "
                    f"got shape {value.shape}"
                )
            values[:, column] = value
            given = True
        if not given:
            raise ValueError("displace needs at least one of ux, uy, uz")
        self.prescribed.append(Prescribed(ids, values, amplitude_of(amplitude)))
        self._compiled = None

    def force(
        self,
        nodes: NodeSelection,
        vector: ArrayLike,
        amplitude: str | AmplitudeFunction = "step",
    ) -> None:
        """The same global force vector on each selected node (dead load).

        Parameters
        ----------
        nodes : str, array of int or callable
            A node-set name of the mesh, node ids, or a predicate ``(x, y, z) -> mask``.
        vector : (3,) float
            Force, N.
        amplitude : str or callable
            Time history in dynamics; static solvers ramp with the load factor.
        """
        self._add_load("force", nodes, vector, amplitude)

    def moment(
        self,
        nodes: NodeSelection,
        vector: ArrayLike,
        amplitude: str | AmplitudeFunction = "step",
    ) -> None:
        """The same global moment vector on each selected node with rotational DOFs.

        Parameters
        ----------
        nodes : str or array of int
            A node-set name of the mesh, or node ids (of nodes with rotational DOFs).
        vector : (3,) float
            Moment, N mm; its component along the director is dropped (no drilling DOF).
        amplitude : str or callable
            Time history in dynamics; static solvers ramp with the load factor.
        """
        self._add_load("moment", nodes, vector, amplitude)

    def contact(
        self,
        tool,
        nodes: NodeSelection | None = None,
        friction: float = 0.0,
        penalty: float | None = None,
    ):
        """Penalty contact of ``nodes`` with a rigid ``tool`` (elements.tools), with Coulomb
        friction, as a node block (elements/contact.py). The contact surface is the
        mid-surface offset by half the thickness of the shell at each node
        (``ElementType.half_thickness``; 0 for cables), so a stack of thickness h rests h / 2
        above the tool. Which side of a sphere or cylinder the body stays on is the tool's
        ``side``.

        Parameters
        ----------
        tool : elements.tools.RigidTool
        nodes : node selection, optional
            The nodes that may touch (default: every node of the model's cells).
        friction : float
            Coulomb coefficient mu >= 0 (stick below mu times the normal force, slip at it).
        penalty : float, optional
            N/mm per node, normal and tangential; None: 0.1 m (2 / dt)^2 per node, chosen
            when the model is compiled (m the node's lumped mass, dt the critical step of the
            model without contact: the explicit step stays stable; elements/contact.py).

        Returns
        -------
        int
            The block index; ``CompiledModel.tool_forces(state)`` gives the force on each tool.
        """
        from elements.contact import Contact  # femcore builds on no element; this one is asked

        offset = np.zeros(self.mesh.n_nodes)
        covered = np.zeros(self.mesh.n_nodes, dtype=bool)
        for entry in self.blocks:
            kind = entry.element.cell_type
            if kind is None:
                continue
            used = np.unique(self.mesh.cells(kind)[entry.cells])  # the block's nodes
            covered[used] = True
            offset[used] = np.maximum(offset[used], float(entry.element.half_thickness))
        if nodes is None:
            ids = np.flatnonzero(covered)
            if ids.size == 0:
                raise ValueError("contact: add the elements first (no node is covered yet)")
        else:
            ids = self._node_ids(nodes)
        return self.add(Contact(tool, ids, offset[ids], penalty, friction))

    def gravity(self, vector: ArrayLike, amplitude: str | AmplitudeFunction = "step") -> None:
        """Acceleration of gravity acting on the lumped mass.

        Parameters
        ----------
        vector : (3,) float
            Acceleration, e.g. (0, 0, -9810) mm/s^2.
        amplitude : str or callable
            Time history in dynamics; static solvers ramp with the load factor.
        """
        self.gravities.append(Gravity(_vector3(vector, "gravity"), amplitude_of(amplitude)))
        self._compiled = None

    # ----------------------------------------------------------------- helpers
    def _add_load(self, kind: str, nodes, vector, amplitude) -> None:
        """Record a dead nodal force or moment (validated here, where it was written)."""
        self.loads.append(
            NodalLoad(kind, self._node_ids(nodes), _vector3(vector, kind), amplitude_of(amplitude))
        )
        self._compiled = None

    def _node_ids(self, nodes) -> np.ndarray:
        if isinstance(nodes, str):
            if nodes not in self.mesh.node_sets:
                raise ValueError(
                    f"no node set named {nodes!r}: "
                    f"the mesh has {sorted(self.mesh.node_sets) or 'none'}"
                )
            nodes = self.mesh.node_sets[nodes]
        elif callable(nodes):  # a predicate(x, y, z) -> mask, as Mesh.nodes takes
            nodes = self.mesh.nodes(nodes)
        return self._ids(nodes, self.mesh.n_nodes, "node")

    @staticmethod
    def _ids(ids, count: int, what: str) -> np.ndarray:
        array = np.atleast_1d(np.asarray(ids))
        if array.size == 0:
            raise ValueError(f"empty {what} selection: expected at least one {what} id")
        if array.dtype == bool:
            raise ValueError(f"{what} selection is a boolean mask: pass ids (np.flatnonzero(mask))")
        if not np.issubdtype(array.dtype, np.integer):
            if not np.all(np.isfinite(array)) or np.any(array != np.round(array)):
                raise ValueError(f"{what} ids must be integers, got {array.dtype} values")
            array = array.astype(np.int64)
        bad = (array < 0) | (array >= count)
        if bad.any():
            raise ValueError(
                f"{what} id {int(array[bad][0])} out of range: the mesh has {count} {what}s "
                f"(ids 0..{count - 1})"
            )
        return np.unique(array.astype(np.int64))

    # ----------------------------------------------------------------- compile
    def compile(self) -> CompiledModel:
        """Bind blocks, build DOF, constraint and load arrays (cached until the model changes)."""
        if self._compiled is None:
            self._compiled = CompiledModel(self)
        return self._compiled


#: Names of the six elementary rigid motions (rotations about axes through the centroid).
RIGID_MOTIONS: tuple[str, ...] = (
    "translation along x",
    "translation along y",
    "translation along z",
    "rotation about x",
    "rotation about y",
    "rotation about z",
)


class CompiledModel:
    """The model turned into arrays: bound element blocks, DOF manager, load vectors.

    Attributes
    ----------
    mesh, n_nodes
    blocks : list of bound element blocks (elements.base.ElementBlock protocol).
    dofs : DofManager.
    reference_positions : (n, 3), the mesh points.
    reference_directors : (n, 3), initial unit directors (area-weighted normals of the shell
        triangles around each node), zero rows at nodes without rotational DOFs.
    has_rotation : (n,) bool.
    translation_free / translation_constrained / translation_prescribed : (n, 3) bool.
    rotation_fixed : (n, 2) bool for (alpha, beta).
    mass0, inertia0 : (n,) physical lumped mass and rotary inertia in the reference state.
    element_size : median element edge length (length unit).
    """

    def __init__(self, model: Model):
        mesh = model.mesh
        if not model.blocks:
            raise ValueError("the model has no elements: add an element block with model.add(...)")
        n = mesh.n_nodes
        self.mesh = mesh
        self.n_nodes = n

        active = np.zeros((n, len(DOF_NAMES)), dtype=bool)
        shell_triangles = []
        cell_entries = [e for e in model.blocks if e.element.cell_type is not None]
        if not cell_entries:
            raise ValueError(
                "the model has only node blocks (contact, tie): add an element over mesh cells"
            )
        for entry in cell_entries:
            columns = dof_columns(entry.element.dofs)
            cells = self._cells(entry)
            active[np.ix_(np.unique(cells), columns)] = True
            if entry.element.defines_directors:
                shell_triangles.append(cells)
        self.has_rotation = active[:, 3].copy()
        triangle_cells = [self._cells(e) for e in cell_entries if e.element.cell_type == "triangle"]
        if triangle_cells:
            # Duplicate nodes, zero-area triangles, non-manifold edges and flipped triangles
            # make every shell kinematics wrong: refuse them before anything is bound.
            check_triangles(mesh.points, np.unique(np.concatenate(triangle_cells), axis=0))

        fixed = self._fixed_mask(model.fixes, active)
        prescribed, self._prescribed_terms = self._prescribed(model.prescribed, active)
        self.dofs = DofManager(n, active, fixed, prescribed)

        self.reference_positions = mesh.points.copy()
        self.reference_directors = np.zeros((n, 3))
        if self.has_rotation.any():
            normals = np.zeros((n, 3))
            if shell_triangles:
                normals = nodal_normals(mesh.points, np.concatenate(shell_triangles))
            missing = self.has_rotation & (np.linalg.norm(normals, axis=1) == 0)
            if missing.any():
                raise ValueError(
                    f"node {np.flatnonzero(missing)[0]} has rotational DOFs but no shell "
                    "triangle to define its director: an element type whose triangles define "
                    "the directors declares defines_directors = True"
                )
            self.reference_directors[self.has_rotation] = normals[self.has_rotation]

        self.element_size = _median_edge(mesh, cell_entries, self._cells)
        self.blocks: list[ElementBlock] = [
            entry.element.bind(mesh, entry.cells, self.reference_directors)
            for entry in model.blocks
        ]
        for entry, block in zip(model.blocks, self.blocks):
            _check_block(entry.element, block, active)
        for entry, block in zip(model.blocks, self.blocks):
            # The nodes where every DOF of the block is fixed or prescribed (femcore.element).
            held = self.dofs.constrained[:, dof_columns(entry.element.dofs)].all(axis=1)
            block.apply_supports(held)

        self.translation_free = self.dofs.free[:, :3]
        self.translation_constrained = self.dofs.constrained[:, :3]
        self.translation_prescribed = self.dofs.prescribed[:, :3]
        self.rotation_fixed = self.dofs.fixed[:, 3:] & self.has_rotation[:, None]

        state0 = self.initial_state()
        self.mass0, self.inertia0 = self.lumped_mass(state0)
        unmassed = active[:, 0] & ~(self.mass0 > 0)
        if unmassed.any():
            raise ValueError(
                f"node {np.flatnonzero(unmassed)[0]} has no mass: every node of an "
                "element needs a positive lumped mass for the dynamic solvers"
            )
        # Blocks without mass of their own (contact) size themselves from the others.
        if any(type(b).calibrate is not ElementBlock.calibrate for b in self.blocks):
            dt = self.stable_dt(state0)
            for block in self.blocks:
                block.calibrate(self.mass0, dt)
        self._has_history = any(h is not None for h in state0.history)
        #: The blocks that act against a rigid tool (ElementBlock.tool_force is not None).
        self.tool_blocks = [
            i
            for i, b in enumerate(self.blocks)
            if b.tool_force(state0, state0.history[i]) is not None
        ]
        self._no_history = (None,) * len(self.blocks)
        self._load_terms = self._loads(model.loads, active)
        self._gravity_terms = [(g.amplitude, g.vector) for g in model.gravities]

    # ------------------------------------------------------------- construction helpers
    def _cells(self, entry: BlockEntry) -> np.ndarray:
        kind = entry.element.cell_type
        assert kind is not None, "node blocks have no mesh cells"
        return self.mesh.cells(kind)[entry.cells]

    def _fixed_mask(self, fixes: list[Fix], active: np.ndarray) -> np.ndarray:
        fixed = np.zeros_like(active)
        for fix in fixes:
            node_active = active[fix.nodes].any(axis=1)
            if not node_active.any():
                raise ValueError(
                    f"fix selects nodes {fix.nodes[:5].tolist()}... that no element "
                    "uses: they carry no DOF"
                )
            nodes = fix.nodes[node_active]
            if fix.columns is None:
                fixed[nodes] |= active[nodes]
                continue
            lacking = ~active[np.ix_(nodes, fix.columns)]
            if lacking.any():
                row, col = np.argwhere(lacking)[0]
                raise ValueError(
                    f"cannot fix {DOF_NAMES[fix.columns[col]]} at node {nodes[row]}: it carries "
                    f"only {', '.join(dof_names(active[nodes[row]]))}"
                )
            fixed[np.ix_(nodes, fix.columns)] = True
        return fixed

    def _prescribed(self, records: list[Prescribed], active: np.ndarray):
        mask = np.zeros_like(active)
        terms = []
        for record in records:
            inactive = ~active[record.nodes, 0]
            if inactive.any():
                raise ValueError(
                    f"cannot displace node {record.nodes[inactive][0]}: no element uses it"
                )
            given = np.isfinite(record.values)
            already = mask[record.nodes, :3] & given
            if already.any():
                row, col = np.argwhere(already)[0]
                raise ValueError(
                    f"{DOF_NAMES[col]} of node {record.nodes[row]} is prescribed twice"
                )
            mask[record.nodes, :3] |= given
            values = np.zeros((self.n_nodes, 3))
            values[record.nodes] = np.where(given, record.values, 0.0)
            terms.append((record.amplitude, values))
        return mask, terms

    def _loads(self, records: list[NodalLoad], active: np.ndarray):
        terms = []
        for record in records:
            column = 0 if record.kind == "force" else 3
            lacking = ~active[record.nodes, column]
            if lacking.any():
                need = "any DOF" if record.kind == "force" else "rotational DOFs"
                raise ValueError(
                    f"{record.kind} on node {record.nodes[lacking][0]}, which has no {need}"
                )
            values = np.zeros((self.n_nodes, 3))
            values[record.nodes] = record.vector
            terms.append((record.kind, record.amplitude, values))
        return terms

    # ------------------------------------------------------------- state and fields
    def initial_state(self) -> State:
        """The reference configuration at rest."""
        n = self.n_nodes
        return State(
            positions=self.reference_positions.copy(),
            directors=self.reference_directors.copy(),
            velocities=np.zeros((n, 3)),
            angular_velocities=np.zeros((n, 3)),
            history=tuple(block.initial_history() for block in self.blocks),
        )

    def commit(self, state: State) -> State:
        """The state with every block's history updated after a step a solver accepted (a new
        State; ``state`` is left as it was). The same state when no block has history (a
        block with history variables returns them, not None, from ``initial_history``)."""
        if not self._has_history:
            return state
        history = tuple(
            block.update_history(state, h) for block, h in zip(self.blocks, state.history)
        )
        return replace(state, history=history)

    def lumped_mass(self, state: State, density_scale: list | None = None):
        """Nodal mass (n,) and rotary inertia (n,) summed over blocks. ``density_scale``: one
        (cells,) factor array per block (selective mass scaling) or None."""
        mass = np.zeros(self.n_nodes)
        inertia = np.zeros(self.n_nodes)
        for i, block in enumerate(self.blocks):
            m, j = block.lumped_mass(state, None if density_scale is None else density_scale[i])
            mass += m
            if j is not None:
                inertia += j
        return mass, inertia

    def _histories(self, state: State) -> tuple:
        return state.history if len(state.history) == len(self.blocks) else self._no_history

    def internal_force(
        self, state: State, blocks: list[int] | None = None
    ) -> tuple[np.ndarray, np.ndarray]:
        """Internal nodal forces F_int = dW/dx (n, 3) and moment vectors dW/dpsi (n, 3), summed
        over the blocks (or over the blocks of the given indices)."""
        force = np.zeros((self.n_nodes, 3))
        moment = np.zeros((self.n_nodes, 3))
        histories = self._histories(state)
        for i in range(len(self.blocks)) if blocks is None else blocks:
            f, m = self.blocks[i].internal_force(state, histories[i])
            force += f
            if m is not None:
                moment += m
        return force, moment

    def cell_stable_dt(self, state: State) -> list[np.ndarray]:
        """Per-block arrays of per-cell critical steps (s)."""
        return [np.asarray(block.cell_stable_dt(state), dtype=float) for block in self.blocks]

    def penalty_frequency_squared(self, mass: np.ndarray) -> float:
        """The largest omega^2 = k / m (1/s^2) the blocks' penalty springs (``penalty_springs``)
        can add to one node, summed over the blocks: a node may be pinched between two tools,
        and a node not touching now may touch before the step is next evaluated. ``mass``
        (n,) the lumped masses the solver uses, t. 0 without springs."""
        total = 0.0
        for block in self.blocks:
            springs = block.penalty_springs()
            if springs is not None and len(springs[0]):
                nodes, stiffness = springs
                total += float(np.max(np.asarray(stiffness) / mass[nodes]))
        return total

    def stable_dt(self, state: State) -> float:
        """Critical time step of the whole model (s), the smallest over all cells."""
        return float(min(dt.min() for dt in self.cell_stable_dt(state)))

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
        parts = self.tangent_parts(state, list(range(len(self.blocks))))
        if parts is None:
            return None
        free = self.dofs.free_slots
        diagonal = np.column_stack([mass, mass, mass, inertia, inertia]).ravel()[free]
        if free.size == 0 or not np.all(diagonal > 0.0):
            return None
        stiffness = abs(self.stiffness(state, "element").tocsr()[free][:, free])
        scale = 1.0 / np.sqrt(diagonal)
        rows = np.asarray(stiffness @ scale).ravel() * scale
        largest = float(rows.max(initial=0.0))
        return 2.0 / np.sqrt(largest) if largest > 0.0 else None

    def strain_energy(self, state: State) -> float:
        """Total strain energy (N mm) over all blocks."""
        histories = self._histories(state)
        return float(sum(b.strain_energy(state, h) for b, h in zip(self.blocks, histories)))

    def dissipated_energy(self, state: State) -> float:
        """Energy dissipated inside the blocks since the start (friction), N mm."""
        histories = self._histories(state)
        return float(sum(b.dissipated_energy(h) for b, h in zip(self.blocks, histories)))

    def tool_forces(self, state: State) -> np.ndarray:
        """(t, 3) the force (N) the model exerts on each rigid tool, in the order of the
        contact blocks (``Model.contact``)."""
        histories = self._histories(state)
        forces = [self.blocks[i].tool_force(state, histories[i]) for i in self.tool_blocks]
        return np.array(forces, dtype=float).reshape(len(forces), 3)

    def tool_work(self, state: State, start: float, end: float) -> float:
        """Work (N mm) the moving tools do on the model while the load factor goes from
        ``start`` to ``end``, with the contact forces at ``state``."""
        histories = self._histories(state)
        return float(
            sum(self.blocks[i].tool_work(state, histories[i], start, end) for i in self.tool_blocks)
        )

    def tangent_parts(self, state: State, blocks: list[int]) -> list[TangentPart] | None:
        """The element tangent parts of the blocks of the given indices, or None if one of
        them has no tangent of its own."""
        histories = self._histories(state)
        parts: list[TangentPart] = []
        for i in blocks:
            own = self.blocks[i].tangent(state, histories[i])
            if own is None:
                return None
            parts.extend(own)
        return parts

    def stiffness(
        self,
        state: State,
        method: str = "element",
        frames: Frames = None,
        blocks: list[int] | None = None,
    ) -> sp.csr_matrix:
        """Tangent stiffness K = dF_int/dq (n x 5 slots square, femcore.dofs) at ``state``.

        Parameters
        ----------
        state : State
        method : "element" or "finite_difference"
            The blocks' own tangents (every block must give one), or coloured central
            differences of their internal forces (translation step 1e-6 of the median element
            edge, rotation step 1e-6 rad).
        frames : Frames
            Nodal frames of the generalised rotations (default: those of ``state.directors``).
        blocks : list of int or None
            Indices of the blocks to include (default: all).

        Raises
        ------
        ValueError
            For an unknown method, or "element" with a block that has no tangent of its own.
        """
        indices = list(range(len(self.blocks))) if blocks is None else list(blocks)
        frames = self.dofs.frames(state.directors) if frames is None else frames
        if method == "element":
            parts = self.tangent_parts(state, indices)
            if parts is None:
                raise ValueError(
                    "a block has no tangent of its own: use method='finite_difference'"
                )
            return tangent_matrix(self.dofs, parts, frames)
        if method == "finite_difference":
            return self.finite_difference_stiffness(
                state, indices, self.node_graph(indices), frames
            )
        raise ValueError(f"method must be 'element' or 'finite_difference', got {method!r}")

    def node_graph(self, blocks: list[int]) -> NodeGraph:
        """The colouring of the finite-difference tangent of the blocks of the given indices
        (built once per solve: its greedy colouring loops over the nodes)."""
        reach = max(self.blocks[i].reach for i in blocks)
        return NodeGraph(self.n_nodes, [self.blocks[i].connectivity for i in blocks], reach)

    def finite_difference_stiffness(
        self, state: State, blocks: list[int], graph: NodeGraph, frames: Frames
    ) -> sp.csr_matrix:
        """K of the blocks of the given indices by coloured central differences of their
        internal forces: translation step 1e-6 of the median element edge, rotation step
        1e-6 rad, the nodal frames held."""
        return finite_difference_tangent(
            self.dofs,
            lambda s: self.internal_force(s, blocks),
            state,
            graph,
            step=1e-6 * self.element_size,
            frames=frames,
        )

    def own_tangents(self, state: State) -> dict[int, Sequence[TangentPart]]:
        """The tangent parts at ``state`` of the blocks that give a tangent of their own,
        by block index (the others return None: the finite-difference fallback)."""
        own = {}
        for i, (block, history) in enumerate(zip(self.blocks, self._histories(state))):
            parts = block.tangent(state, history)
            if parts is not None:
                own[i] = parts
        return own

    def unheld_rigid_motions(self, loaded_only: bool = True) -> list[str]:
        """The rigid motions that no support holds and the full dead loads would push: an
        equilibrium the quasi-static solvers cannot find (a mechanism). With
        ``loaded_only=False``, every rigid motion no support holds, loaded or not (what makes a
        tangent stiffness singular).

        The six rigid motions (translations along x, y, z; rotations about the axes through
        the centroid, directors turning with the body) restricted to the fixed and
        prescribed DOFs span what the supports hold; a motion in the rest does work with
        the loads (forces and moments at load factor 1) unless they are self-balanced along
        it. Models with node blocks (contact, ties) are not checked: those may hold the body.

        Returns
        -------
        list of str
            The elementary motions (e.g. "translation along z") along which the loads do work
            with nothing holding the model, or a description of the combined motion; empty
            when every loaded rigid motion is held.
        """
        if any(block.cell_type is None for block in self.blocks):
            return []
        dofs = self.dofs
        x = self.reference_positions
        centre = x[dofs.active[:, 0]].mean(axis=0) if dofs.active[:, 0].any() else x.mean(0)
        axes = np.eye(3)
        # (6 motions, n, 6): u then psi per node.
        motions = np.zeros((6, self.n_nodes, 6))
        motions[:3, :, :3] = axes[:, None, :]
        motions[3:, :, :3] = np.cross(axes[:, None, :], (x - centre)[None])
        motions[3:, :, 3:] = np.where(self.has_rotation[None, :, None], axes[:, None, :], 0.0)
        frames = dofs.frames(self.reference_directors)
        v1, v2 = frames if frames is not None else (x, x)
        # Generalised components (u, alpha = psi . V2, beta = psi . V1) as the DOF masks.
        generalised = np.concatenate(
            [
                motions[..., :3],
                np.sum(motions[..., 3:] * v2, axis=-1)[..., None],
                np.sum(motions[..., 3:] * v1, axis=-1)[..., None],
            ],
            axis=-1,
        )
        held = generalised[:, dofs.constrained].T  # (constrained DOFs, 6)
        length = max(float(np.ptp(x, axis=0).max()), 1e-300)
        scale = np.array([1.0, 1.0, 1.0, length, length, length])  # rotations as translations
        held = held / scale
        if held.size:
            _, singular, vt = np.linalg.svd(held, full_matrices=True)
            rank = int(np.sum(singular > 1e-9 * max(float(singular.max()), 1.0)))
            free_motions = vt[rank:] / scale  # (k, 6): q = z / scale for held z = 0
        else:
            free_motions = np.eye(6)
        if not len(free_motions):
            return []
        if not loaded_only:
            names = list(RIGID_MOTIONS)
            column_free = np.abs(held).max(axis=0, initial=0.0) == 0.0
            return [name for name, free in zip(names, column_free) if free] or [
                "a rigid motion combining "
                + ", ".join(
                    name
                    for name, weight in zip(names, np.abs(free_motions[0] * scale))
                    if weight > 1e-6
                )
            ]
        force, moment = self.external_load(1.0, quasi_static=True)
        load = np.concatenate([force, moment], axis=1)
        work = np.einsum("kc,cnj,nj->k", free_motions, motions, load)
        size = max(float(np.linalg.norm(force)) * length + float(np.linalg.norm(moment)), 1e-300)
        pushed = free_motions[np.abs(work) > 1e-9 * size]
        if not len(pushed):
            return []
        names = list(RIGID_MOTIONS)
        column_free = np.abs(held).max(axis=0, initial=0.0) == 0.0
        elementary = [
            name
            for i, name in enumerate(names)
            if column_free[i] and abs(float(np.sum(motions[i] * load))) > 1e-9 * size
        ]
        return elementary or [
            "a rigid motion combining "
            + ", ".join(
                name for name, weight in zip(names, np.abs(pushed[0] * scale)) if weight > 1e-6
            )
        ]

    def external_load(self, tau: float, quasi_static: bool = False):
        """External nodal forces (n, 3) and moments (n, 3) at progress tau (dead loads)."""
        force = np.zeros((self.n_nodes, 3))
        moment = np.zeros((self.n_nodes, 3))
        for kind, amplitude, values in self._load_terms:
            factor = _evaluate(amplitude, tau, quasi_static)
            if kind == "force":
                force += factor * values
            else:
                moment += factor * values
        for amplitude, vector in self._gravity_terms:
            force += _evaluate(amplitude, tau, quasi_static) * self.mass0[:, None] * vector
        force[~self.dofs.active[:, 0]] = 0.0
        return force, moment

    def prescribed_displacement(self, tau: float, quasi_static: bool = False) -> np.ndarray:
        """Imposed displacements (n, 3) at progress tau (zero where not prescribed)."""
        displacement = np.zeros((self.n_nodes, 3))
        for amplitude, values in self._prescribed_terms:
            displacement += _evaluate(amplitude, tau, quasi_static) * values
        return displacement

    @property
    def has_prescribed(self) -> bool:
        return bool(self._prescribed_terms)

    def constrain_angular(self, vectors: np.ndarray, directors: np.ndarray) -> np.ndarray:
        """Remove from angular vectors (n, 3) the drilling part (along the director) and the
        components of fixed alpha / beta (about V2 / V1 of the nodal frame); zero at nodes
        without rotations."""
        out = drop_along(vectors, directors)
        out[~self.has_rotation] = 0.0
        fixed_any = self.rotation_fixed.any(axis=1)
        if fixed_any.any():
            v1, v2 = nodal_frames(directors[fixed_any])
            sub = out[fixed_any]
            alpha, beta = self.rotation_fixed[fixed_any].T
            sub -= (alpha * np.sum(sub * v2, axis=1))[:, None] * v2
            sub -= (beta * np.sum(sub * v1, axis=1))[:, None] * v1
            out[fixed_any] = sub
        return out

    def fields(self, state: State) -> dict:
        """Output fields: {"point": {name: (n, ...)}, kind: {...} for each cell kind} with the
        cell fields spread over all mesh cells of that type (NaN where a block does not cover)."""
        out: dict[str, dict] = {"point": {}, **{kind: {} for kind in CELL_KINDS}}
        counts = {kind: len(self.mesh.cells(kind)) for kind in CELL_KINDS}
        for block, history in zip(self.blocks, self._histories(state)):
            for name, values in block.node_fields(state, history).items():
                # Two blocks with the same field (two tools' contact_gap): the second is
                # named contact_gap_2, and so on, in the order of the blocks.
                key, count = name, 1
                while key in out["point"]:
                    count += 1
                    key = f"{name}_{count}"
                out["point"][key] = values
            kind = block.cell_type
            if kind is None:  # node blocks have no mesh cells to carry a cell field
                continue
            for name, values in block.cell_fields(state, history).items():
                values = np.asarray(values, dtype=float)
                full = out[kind].setdefault(
                    name, np.full((counts[kind],) + values.shape[1:], np.nan)
                )
                full[block.cell_ids] = values
        return out


def _check_block(element: ElementType, block: ElementBlock, active: np.ndarray) -> None:
    """A bound block must be an ElementBlock that declares its reach, with a (m, k) node
    connectivity whose nodes carry the DOFs it needs (node blocks act on nodes that some
    cell element carries)."""
    name = type(element).__name__
    if not isinstance(block, ElementBlock):
        raise ValueError(
            f"{name}.bind returned {type(block).__name__}: expected an ElementBlock "
            "(femcore.element)"
        )
    reach = getattr(block, "reach", None)
    if isinstance(reach, bool) or not isinstance(reach, (int, np.integer)) or reach < 1:
        raise ValueError(
            f"{type(block).__name__}.reach is {reach!r}: every block declares how many cell-hops "
            "its forces reach (1: cell-local, 2: bending patches over neighbours)"
        )
    for method in ("internal_force", "strain_energy", "tangent", "cell_fields", "node_fields"):
        if not _takes_history(getattr(block, method)):
            raise ValueError(
                f"{type(block).__name__}.{method} must take (state, history=None): the model "
                "passes each block its history variables (femcore.element)"
            )
    connectivity = np.asarray(block.connectivity)
    if connectivity.ndim != 2 or not np.issubdtype(connectivity.dtype, np.integer):
        raise ValueError(
            f"{type(block).__name__}.connectivity must be an (m, k) integer array of node ids"
        )
    if connectivity.size:
        if connectivity.min() < 0 or connectivity.max() >= len(active):
            raise ValueError(
                f"{type(block).__name__}.connectivity refers to nodes outside 0..{len(active) - 1}"
            )
        nodes = np.unique(connectivity)
        lacking = ~active[np.ix_(nodes, dof_columns(element.dofs))]
        if lacking.any():
            node = nodes[np.argwhere(lacking)[0, 0]]
            raise ValueError(
                f"{name} acts on node {node}, which carries only "
                f"{', '.join(dof_names(active[node])) or 'no DOF'}: a "
                "node block needs nodes of a cell element with the DOFs it uses"
            )


def _takes_history(method: Callable) -> bool:
    """Whether a bound method accepts two positional arguments (state, history)."""
    try:
        parameters = list(inspect.signature(method).parameters.values())
    except (TypeError, ValueError):  # no signature to read (a C function): trust it
        return True
    positional = [p for p in parameters if p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD)]
    variadic = any(p.kind is p.VAR_POSITIONAL for p in parameters)
    return variadic or len(positional) >= 2


def _median_edge(mesh: Mesh, entries, cells_of) -> float:
    """Median length of the element edges (mesh length unit): the scale that turns a force
    into a moment in residual checks."""
    lengths = []
    for entry in entries:
        cells = mesh.points[cells_of(entry)]
        for k in range(cells.shape[1]):
            lengths.append(np.linalg.norm(cells[:, k] - cells[:, k - 1], axis=1))
    return float(np.median(np.concatenate(lengths)))


def _evaluate(amplitude: Amplitude, tau: float, quasi_static: bool) -> float:
    function: Callable = amplitude.quasi_static if quasi_static else amplitude.dynamic
    return float(function(tau))
