"""The compiled model: a Model turned into the arrays a solver steps with.

``Model.compile()`` builds it once: the element blocks bound to their cells, the interactions
bound to the body (femcore.interaction), the DOF manager, the constraint and load vectors. Its
methods sum what the parts give (forces, energies, tangents, fields) over ``parts``: the element
blocks first, then the interactions, in the order they were added. ``State.history[i]`` belongs
to ``parts[i]``.
"""

from __future__ import annotations

import inspect
import itertools
import math
from collections.abc import Callable, Sequence
from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp

from femcore.assembly import (
    NodeGraph,
    TangentPart,
    finite_difference_tangent,
    tangent_matrix,
)
from femcore.diagnostics import interaction_notes, unheld_rigid_motions
from femcore.dofs import DOF_NAMES, DofManager, Frames, dof_columns, dof_names
from femcore.element import ElementBlock, ElementType
from femcore.gershgorin import gershgorin_largest
from femcore.interaction import Body, BodyPart, Interaction, InteractionBlock
from femcore.loads import Amplitude, Fix, NodalLoad, Prescribed
from femcore.memory import check_model_memory
from femcore.mesh import CELL_KINDS, Mesh
from femcore.rotation import drop_along, nodal_frames
from femcore.state import State
from femcore.topology import check_triangles, nodal_normals

if TYPE_CHECKING:
    from femcore.model import BlockEntry, Model

__all__ = ["CompiledModel"]

#: A part of the compiled model: what contributes forces, energies and tangents.
Part = ElementBlock | InteractionBlock


class CompiledModel:
    """The model turned into arrays: bound element blocks and interactions, DOF manager, load
    vectors.

    Attributes
    ----------
    mesh, n_nodes
    blocks : list of bound element blocks (femcore.element.ElementBlock protocol).
    interactions : list of bound interactions (femcore.interaction.InteractionBlock protocol).
    parts : the blocks, then the interactions: what the sums run over (``State.history[i]``
        belongs to ``parts[i]``).
    n_tools : the number of rigid tools the interactions act against (rows of
        ``tool_forces``).
    dofs : DofManager.
    block_entries, given_interactions : the element blocks (element type, cells) and the
        interactions the model was compiled from, as given.
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
        # Before anything is bound: a model too large for the machine is refused at once.
        check_model_memory(sum(len(entry.cells) for entry in model.blocks))
        n = mesh.n_nodes
        self.mesh = mesh
        self.n_nodes = n

        active = np.zeros((n, len(DOF_NAMES)), dtype=bool)
        shell_triangles = []
        cell_entries = list(model.blocks)
        for entry in cell_entries:
            columns = dof_columns(entry.element.dofs)
            cells = self._cells(entry)
            active[np.ix_(_used_nodes(cells, n), columns)] = True
            if entry.element.defines_directors:
                shell_triangles.append(cells)
        # Nodes of rigid bodies (a force-driven tool's translation): translations, no cell.
        self.rigid_nodes = np.array([r.node for r in model.rigid_nodes], dtype=np.int64)
        active[self.rigid_nodes, :3] = True
        self._rigid_mass = np.array([r.mass or 0.0 for r in model.rigid_nodes])
        #: The rigid nodes without a stated mass: a nominal one (the mean nodal mass of the
        #: body) and no weight; the explicit solver refuses them.
        self.nominal_mass_nodes = np.array(
            [r.node for r in model.rigid_nodes if r.mass is None], dtype=np.int64
        )
        self.has_rotation = active[:, 3].copy()
        triangle_ids = [e.cells for e in cell_entries if e.element.cell_type == "triangle"]
        if triangle_ids:
            # Duplicate nodes, zero-area triangles, non-manifold edges and flipped triangles
            # make every shell kinematics wrong: refuse them before anything is bound (each
            # triangle once, in mesh order, when blocks share cells).
            ids = (
                triangle_ids[0]
                if len(triangle_ids) == 1
                else np.unique(np.concatenate(triangle_ids))
            )
            check_triangles(mesh.points, mesh.triangles[ids])

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

        body = Body(
            mesh,
            tuple(BodyPart(e.element, self._cells(e)) for e in model.blocks),
            self.reference_directors,
            active,
        )
        self.interactions: list[InteractionBlock] = []
        for index, description in enumerate(model.interactions):
            tool = sum(int(i.n_tools) for i in self.interactions) + 1
            self.interactions.append(_bound_interaction(description, body, index, tool))
        self.parts: list[Part] = [*self.blocks, *self.interactions]
        # What the model was compiled from, as given: its fingerprint reads them
        # (femcore.fingerprint).
        self.block_entries: tuple[BlockEntry, ...] = tuple(model.blocks)
        self.given_interactions: tuple[Interaction, ...] = tuple(model.interactions)
        self.n_tools = sum(int(i.n_tools) for i in self.interactions)

        # Contiguous copies: the compiled passes of a step read them (a strided view would be
        # copied at every step).
        self.translation_free = np.ascontiguousarray(self.dofs.free[:, :3])
        self.translation_constrained = np.ascontiguousarray(self.dofs.constrained[:, :3])
        self.translation_prescribed = np.ascontiguousarray(self.dofs.prescribed[:, :3])
        self.rotation_fixed = self.dofs.fixed[:, 3:] & self.has_rotation[:, None]

        state0 = self.initial_state()
        self.mass0, self.inertia0 = self.lumped_mass(state0)
        self._weighed_mass = self.mass0.copy()  # what gravity acts on
        if self.nominal_mass_nodes.size:
            body = self.mass0 > 0
            nominal = float(self.mass0[body].mean()) if body.any() else 1.0
            unstated = np.isin(self.rigid_nodes, self.nominal_mass_nodes)
            self._rigid_mass = np.where(unstated, nominal, self._rigid_mass)
            self.mass0, self.inertia0 = self.lumped_mass(state0)
        unmassed = active[:, 0] & ~(self.mass0 > 0)
        if unmassed.any():
            raise ValueError(
                f"node {np.flatnonzero(unmassed)[0]} has no mass: every node of an "
                "element needs a positive lumped mass for the dynamic solvers"
            )
        # Interactions have no mass of their own: they size themselves from the elements.
        if self.interactions:
            dt = self.stable_dt(state0)
            for interaction in self.interactions:
                interaction.calibrate(self.mass0, dt)
        self._has_history = any(h is not None for h in state0.history)
        self._no_history = (None,) * len(self.parts)
        self._load_terms = self._loads(model.loads, active)
        self._gravity_terms = [(g.amplitude, g.vector) for g in model.gravities]
        # Each gravity's nodal weights m g (n, 3), and the nodes no element carries: made
        # once, not at every step's load.
        self._gravity_forces = [
            self._weighed_mass[:, None] * np.asarray(vector) for _, vector in self._gravity_terms
        ]
        self._unloaded = np.flatnonzero(~active[:, 0])

    # ------------------------------------------------------------- construction helpers
    def _cells(self, entry: BlockEntry) -> np.ndarray:
        kind = entry.element.cell_type
        assert kind is not None, "elements cover mesh cells"
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
            history=tuple(part.initial_history() for part in self.parts),
        )

    def commit(self, state: State) -> State:
        """The state with every block's history updated after a step a solver accepted (a new
        State; ``state`` is left as it was). The same state when no block has history (a
        block with history variables returns them, not None, from ``initial_history``)."""
        if not self._has_history:
            return state
        history = tuple(part.update_history(state, h) for part, h in zip(self.parts, state.history))
        return replace(state, history=history)

    def freeze(self, state: State, grow: bool = False) -> tuple[State, int]:
        """(the state with every interaction's contact set frozen at it, the number of nodes
        whose contact status there differs from the sets frozen before): the active-set
        strategy of the quasi-static solvers (femcore.interaction.InteractionBlock.freeze;
        ``grow``: the nodes that penetrate added to the frozen sets and those clearly off
        the tools removed, and counted)."""
        if not self.interactions:
            return state, 0
        history, changed = list(self._histories(state)), 0
        for i, part in enumerate(self.interactions, start=len(self.blocks)):
            history[i], count = part.freeze(state, history[i], grow)
            changed += count
        return replace(state, history=tuple(history)), changed

    def thaw(self, state: State) -> State:
        """The state with the contact sets decided by the gaps again (``freeze`` undone)."""
        if not self.interactions:
            return state
        history = list(self._histories(state))
        for i, part in enumerate(self.interactions, start=len(self.blocks)):
            history[i] = part.thaw(history[i])
        return replace(state, history=tuple(history))

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
        if self.rigid_nodes.size:
            np.add.at(mass, self.rigid_nodes, self._rigid_mass)
        return mass, inertia

    def _histories(self, state: State) -> tuple:
        return state.history if len(state.history) == len(self.parts) else self._no_history

    def internal_force(
        self, state: State, parts: list[int] | None = None
    ) -> tuple[np.ndarray, np.ndarray]:
        """Internal nodal forces F_int = dW/dx (n, 3) and moment vectors dW/dpsi (n, 3), summed
        over the parts (or over the parts of the given indices into ``parts``)."""
        histories = self._histories(state)
        indices = range(len(self.parts)) if parts is None else parts
        if len(indices) == 1:  # one part: its own (fresh) arrays, no sum to make
            i = indices[0]
            f, m = self.parts[i].internal_force(state, histories[i])
            return np.asarray(f, dtype=float), self._moment_or_zeros(m)
        force = np.zeros((self.n_nodes, 3))
        moment = np.zeros((self.n_nodes, 3))
        for i in indices:
            f, m = self.parts[i].internal_force(state, histories[i])
            force += f
            if m is not None:
                moment += m
        return force, moment

    def internal_force_and_energy(self, state: State) -> tuple[np.ndarray, np.ndarray, float]:
        """``internal_force`` and ``strain_energy`` of every part at ``state`` in one call:
        each element block's ``internal_force_and_energy`` (one pass where the block fuses
        them), each interaction's force and penalty energy. Returns (force (n, 3) N, moment
        (n, 3) N mm, energy N mm)."""
        histories = self._histories(state)
        if len(self.parts) == 1:  # one block: its own (fresh) arrays, no sum to make
            f, m, e = self.blocks[0].internal_force_and_energy(state, histories[0])
            return np.asarray(f, dtype=float), self._moment_or_zeros(m), 0.0 + e
        force = np.zeros((self.n_nodes, 3))
        moment = np.zeros((self.n_nodes, 3))
        energy = 0.0
        for block, history in zip(self.blocks, histories):
            f, m, e = block.internal_force_and_energy(state, history)
            force += f
            if m is not None:
                moment += m
            energy += e
        for interaction, history in zip(self.interactions, histories[len(self.blocks) :]):
            f, m = interaction.internal_force(state, history)
            force += f
            if m is not None:
                moment += m
            energy += interaction.strain_energy(state, history)
        return force, moment, float(energy)

    def _moment_or_zeros(self, moment: np.ndarray | None) -> np.ndarray:
        return np.zeros((self.n_nodes, 3)) if moment is None else np.asarray(moment, dtype=float)

    def cell_stable_dt(self, state: State) -> list[np.ndarray]:
        """Per-block arrays of per-cell critical steps (s)."""
        return [np.asarray(block.cell_stable_dt(state), dtype=float) for block in self.blocks]

    def penalty_frequency_squared(self, mass: np.ndarray) -> float:
        """The largest omega^2 = k / m (1/s^2) the interactions' penalty springs (``springs``)
        can add to one node, summed over the interactions: a node may be pinched between two
        tools, and a node not touching now may touch before the step is next evaluated.
        ``mass`` (n,) the lumped masses the solver uses, t. 0 without springs."""
        total = 0.0
        for interaction in self.interactions:
            springs = interaction.springs()
            if springs is not None and len(springs[0]):
                nodes, stiffness = springs
                total += float(np.max(np.asarray(stiffness) / mass[nodes]))
        return total

    def stable_dt(self, state: State) -> float:
        """Critical time step of the elements (s), the smallest over all cells (the
        interactions' springs come in through ``penalty_frequency_squared``)."""
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
        largest = gershgorin_largest(itertools.chain(*pieces), maps, scale, self.n_nodes, again)
        return 2.0 / np.sqrt(largest) if largest > 0.0 else None

    def strain_energy(self, state: State) -> float:
        """Total strain energy (N mm) over all parts (the interactions' penalty springs
        included)."""
        histories = self._histories(state)
        return float(sum(p.strain_energy(state, h) for p, h in zip(self.parts, histories)))

    def _interaction_histories(self, state: State) -> tuple:
        return self._histories(state)[len(self.blocks) :]

    def dissipated_energy(self, state: State) -> float:
        """Energy the interactions dissipated since the start (friction), N mm."""
        histories = self._interaction_histories(state)
        return float(sum(i.dissipated_energy(h) for i, h in zip(self.interactions, histories)))

    def tool_forces(self, state: State) -> np.ndarray:
        """(n_tools, 3) the force (N) the model exerts on each rigid tool, in the order of
        the interactions (``Model.contact``)."""
        histories = self._interaction_histories(state)
        forces = [i.tool_forces(state, h) for i, h in zip(self.interactions, histories)]
        if not forces:
            return np.zeros((0, 3))
        return np.concatenate([np.asarray(f, dtype=float).reshape(-1, 3) for f in forces])

    def tool_displacements(self, state: State) -> np.ndarray:
        """(n_tools, 3) each rigid tool's translation from where it was given (mm), in the
        order of ``tool_forces``."""
        histories = self._interaction_histories(state)
        moves = [i.tool_displacements(state, h) for i, h in zip(self.interactions, histories)]
        if not moves:
            return np.zeros((0, 3))
        return np.concatenate([np.asarray(m, dtype=float).reshape(-1, 3) for m in moves])

    def tool_work(self, state: State, start: float, end: float) -> float:
        """Work (N mm) the moving tools do on the model while the load factor goes from
        ``start`` to ``end``, with the contact forces at ``state``."""
        histories = self._interaction_histories(state)
        return float(
            sum(i.tool_work(state, h, start, end) for i, h in zip(self.interactions, histories))
        )

    def tangent_parts(self, state: State, parts: list[int]) -> list[TangentPart] | None:
        """The tangent parts of the parts of the given indices (into ``parts``), or None if
        one of them has no tangent of its own."""
        histories = self._histories(state)
        tangent: list[TangentPart] = []
        for i in parts:
            own = self.parts[i].tangent(state, histories[i])
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

    def unheld_rigid_motions(self, loaded_only: bool = True) -> list[str]:
        """The rigid motions no support holds (femcore.diagnostics.unheld_rigid_motions)."""
        return unheld_rigid_motions(self, loaded_only)

    def interaction_notes(self) -> list[str]:
        """The interactions that hold their nodes along some directions only (frictionless
        contact), as phrases (femcore.diagnostics.interaction_notes)."""
        return interaction_notes(self)

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
        for (amplitude, _), weight in zip(self._gravity_terms, self._gravity_forces):
            force += _evaluate(amplitude, tau, quasi_static) * weight
        if self._unloaded.size:
            force[self._unloaded] = 0.0
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
        cell fields spread over all mesh cells of that type (NaN where a block does not cover);
        the interactions' node fields after the blocks'. Element blocks on disjoint nodes give
        one node field of a name (each node's value from its own block); parts that share
        nodes give name, name_2, ... in the order of the parts."""
        out: dict[str, dict] = {"point": {}, **{kind: {} for kind in CELL_KINDS}}
        counts = {kind: len(self.mesh.cells(kind)) for kind in CELL_KINDS}
        covered: dict[str, np.ndarray | None] = {}  # field -> the nodes element blocks gave it
        for part, history in zip(self.parts, self._histories(state)):
            nodes = np.unique(part.connectivity) if isinstance(part, ElementBlock) else None
            for name, values in part.node_fields(state, history).items():
                before = covered.get(name)
                if nodes is not None and before is not None:
                    if not np.isin(nodes, before).any():
                        # Element blocks on their own nodes (the plies of a layup): one
                        # field, each node's value from the block it belongs to.
                        merged = np.array(out["point"][name], copy=True)
                        merged[nodes] = np.asarray(values)[nodes]
                        out["point"][name] = merged
                        covered[name] = np.union1d(before, nodes)
                        continue
                # Two parts with the same field on shared nodes (two tools' contact_gap):
                # the second is named contact_gap_2, and so on, in the order of the parts.
                key, count = name, 1
                while key in out["point"]:
                    count += 1
                    key = f"{name}_{count}"
                out["point"][key] = values
                covered.setdefault(key, nodes)
            if not isinstance(part, ElementBlock):  # interactions have no cells
                continue
            kind = part.cell_type
            for name, values in part.cell_fields(state, history).items():
                values = np.asarray(values, dtype=float)
                full = out[kind].setdefault(
                    name, np.full((counts[kind],) + values.shape[1:], np.nan)
                )
                full[part.cell_ids] = values
        return out


def _bound_interaction(
    interaction: Interaction, body: Body, index: int, tool: int
) -> InteractionBlock:
    """``interaction.bind(body)``, checked as ``_check_block`` checks an element block, and
    its ``check_start``; their ValueErrors (a body that starts inside a tool) name the
    interaction (``model.interactions[index]``) and the tool number ``tool`` it has (the
    ``tool1`` ... of the histories) when it acts against a tool."""
    against = f", tool {tool}" if getattr(interaction, "tool", None) is not None else ""
    where = f"interaction {index} ({type(interaction).__name__}{against})"
    try:
        block = interaction.bind(body)
    except ValueError as error:
        raise ValueError(f"{where}: {error}") from None
    _check_bound(
        type(interaction).__name__,
        block,
        InteractionBlock,
        ("internal_force", "strain_energy", "tangent", "node_fields"),
        interaction.dofs,
        body.active,
    )
    n_tools = getattr(block, "n_tools", None)
    if isinstance(n_tools, bool) or not isinstance(n_tools, (int, np.integer)) or n_tools < 0:
        raise ValueError(f"{type(block).__name__}.n_tools is {n_tools!r}: expected an int >= 0")
    try:
        block.check_start()
    except ValueError as error:
        raise ValueError(f"{where}: {error}") from None
    return block


def _check_block(element: ElementType, block: ElementBlock, active: np.ndarray) -> None:
    """A bound block must be an ElementBlock that declares its reach, with a (m, k) node
    connectivity whose nodes carry the DOFs it needs."""
    _check_bound(
        type(element).__name__,
        block,
        ElementBlock,
        ("internal_force", "strain_energy", "tangent", "cell_fields", "node_fields"),
        element.dofs,
        active,
    )


def _check_bound(
    name: str,
    block: Part,
    protocol: type,
    methods: tuple[str, ...],
    dofs: tuple[str, ...],
    active: np.ndarray,
) -> None:
    """What ``name.bind`` returned is a ``protocol`` block (ElementBlock, InteractionBlock)
    that declares its reach, whose ``methods`` take (state, history), and whose
    connectivity's nodes carry ``dofs``."""
    if not isinstance(block, protocol):
        raise ValueError(
            f"{name}.bind returned {type(block).__name__}: expected an {protocol.__name__} "
            f"({protocol.__module__})"
        )
    reach = getattr(block, "reach", None)
    if isinstance(reach, bool) or not isinstance(reach, (int, np.integer)) or reach < 1:
        raise ValueError(
            f"{type(block).__name__}.reach is {reach!r}: every block declares how many cell-hops "
            "its forces reach (1: cell-local, 2: bending patches over neighbours)"
        )
    for method in methods:
        if not _takes_history(getattr(block, method)):
            raise ValueError(
                f"{type(block).__name__}.{method} must take (state, history=None): the model "
                "passes each part its history variables"
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
        nodes = _used_nodes(connectivity, len(active))
        lacking = ~active[np.ix_(nodes, dof_columns(dofs))]
        if lacking.any():
            node = nodes[np.argwhere(lacking)[0, 0]]
            raise ValueError(
                f"{name} acts on node {node}, which carries only "
                f"{', '.join(dof_names(active[node])) or 'no DOF'}: it needs nodes of an "
                "element with the DOFs it uses"
            )


def _used_nodes(connectivity: np.ndarray, n_nodes: int) -> np.ndarray:
    """The nodes (increasing) that the cells (m, k) use: np.unique by a count, without the
    sort (a tenth of its time at 400k triangles)."""
    return np.flatnonzero(np.bincount(np.asarray(connectivity).ravel(), minlength=n_nodes))


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
    """a(tau), or ValueError naming the amplitude and where it failed: a user amplitude that
    returns NaN or raises would otherwise surface as a diverged step, far from its cause."""
    function: Callable = amplitude.quasi_static if quasi_static else amplitude.dynamic
    try:
        value = float(function(tau))
    except Exception as exc:  # the user's function: report what it did and where
        what, where = _amplitude_named(amplitude, function, tau, quasi_static)
        raise ValueError(f"the {what} failed at {where}: {exc}") from exc
    if not math.isfinite(value):
        what, where = _amplitude_named(amplitude, function, tau, quasi_static)
        raise ValueError(
            f"the {what} returned {value!r} at {where}: an amplitude must return a finite "
            "number at every time and load factor"
        )
    return value


def _amplitude_named(
    amplitude: Amplitude, function: Callable, tau: float, quasi_static: bool
) -> tuple[str, str]:
    """("amplitude 'user' (ramp)", "load factor 0.5") for a message: built only on failure,
    since amplitudes are evaluated at every step."""
    what = f"amplitude {amplitude.name!r}"
    if amplitude.name == "user":
        what += f" ({getattr(function, '__name__', repr(function))})"
    where = f"load factor {tau:.6g}" if quasi_static else f"tau = t / duration = {tau:.6g}"
    return what, where
