"""The compiled model: a Model turned into the arrays a solver steps with.

``Model.compile()`` builds it once: the element blocks bound to their cells, the interactions
bound to the body (femcore.interaction), the DOF manager, the constraint and load vectors. Its
methods sum what the parts give (forces, energies, tangents, fields) over ``parts``: the element
blocks first, then the interactions, in the order they were added. ``State.history[i]`` belongs
to ``parts[i]``.
"""

from __future__ import annotations

import inspect
from dataclasses import replace
from typing import TYPE_CHECKING, Any

import numpy as np

from femcore.compiled_checks import (
    Part,
    bound_block,
    bound_interaction,
    check_block,
    median_edge,
    supported_block,
    used_nodes,
)
from femcore.compiled_loads import (
    evaluate,
    fixed_mask,
    load_terms,
    moment_takers,
    prescribed_terms,
)
from femcore.compiled_tangent import CompiledTangent
from femcore.diagnostics import interaction_notes, unheld_rigid_motions
from femcore.dofs import DOF_NAMES, DofManager, dof_columns
from femcore.driven_tools import DrivenTools
from femcore.element import ElementBlock
from femcore.frame_branches import (
    check_frame_branches,
    facet_spread,
    onto_symmetry_planes,
    warn_named_planes,
)
from femcore.interaction import Body, BodyPart, Interaction, InteractionBlock
from femcore.memory import check_model_memory
from femcore.mesh import CELL_KINDS
from femcore.rotation import drop_along, nodal_frames
from femcore.state import State
from femcore.topology import check_triangles, nodal_normals

if TYPE_CHECKING:
    from femcore.loads import Amplitude
    from femcore.model import BlockEntry, Model

__all__ = ["CompiledModel"]


class CompiledModel(CompiledTangent):
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
    element_mass : float, the mass the elements carry (``mass0`` without the tools' nodes'):
        what mass scaling scales and its added mass is a share of.
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
            active[np.ix_(used_nodes(cells, n), columns)] = True
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
            check_triangles(mesh.points, mesh.triangles[ids], names=ids)

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
            # how far a one-sided director may lie off a symmetry plane (its facets' spread)
            spread = (
                facet_spread(mesh.points, np.concatenate(shell_triangles), normals)
                if shell_triangles
                else None
            )
            # a symmetry plane's directors in it, as the mirrored model's (docs/theory.md §1.2)
            onto_symmetry_planes(model.fixes, self.reference_directors, self.has_rotation, spread)
            # a fixed alpha or beta must name one rotation along its set (docs/theory.md §1.2)
            check_frame_branches(model.fixes, self.reference_directors, self.has_rotation)
            # a symmetry plane named by its DOFs where they hold another turn (§1.2)
            warn_named_planes(
                model.fixes, mesh.points, self.reference_directors, self.has_rotation, spread
            )

        # a fix's ``tilt`` is alpha or beta at each node by its frame (docs/theory.md §1.2)
        fixed = fixed_mask(model.fixes, active, self.reference_directors)
        prescribed, self._prescribed_terms = prescribed_terms(model.prescribed, active, fixed)
        self.dofs = DofManager(n, active, fixed, prescribed)

        self.element_size = median_edge(mesh, cell_entries, self._cells)
        self.blocks: list[ElementBlock] = [
            bound_block(entry.element, mesh, entry.cells, self.reference_directors, index)
            for index, entry in enumerate(model.blocks)
        ]
        for entry, block in zip(model.blocks, self.blocks):
            check_block(entry.element, block, active)
        for index, (entry, block) in enumerate(zip(model.blocks, self.blocks)):
            # The nodes where every DOF of the block is fixed or prescribed (femcore.element).
            constrained = self.dofs.constrained[:, dof_columns(entry.element.dofs)]
            supported_block(entry.element, block, constrained, index)

        body = Body(
            mesh,
            tuple(BodyPart(e.element, self._cells(e)) for e in model.blocks),
            self.reference_directors,
            active,
        )
        self.interactions: list[InteractionBlock] = []
        for index, description in enumerate(model.interactions):
            tool = sum(int(i.n_tools) for i in self.interactions) + 1
            self.interactions.append(bound_interaction(description, body, index, tool))
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
        element_mass, self.inertia0 = self._element_lumped_mass(state0)
        # The mass the elements carry, the tools' aside: what mass scaling scales, and what
        # its added mass is a share of (a 100-g holder on a 10-g blank would otherwise make
        # ten times the blank's mass read as a tenth); summed without the tools' masses, not
        # their difference (a heavy tool's would swamp the blank's digits).
        self.element_mass = float(element_mass.sum())
        # what gravity acts on: the tools' stated masses, none for an unstated one
        self._weighed_mass = self._with_tools(element_mass.copy())
        if self.nominal_mass_nodes.size:
            # the mean nodal mass of the body, the stated tools' masses aside
            body = element_mass > 0
            nominal = float(element_mass[body].mean()) if body.any() else 1.0
            unstated = np.isin(self.rigid_nodes, self.nominal_mass_nodes)
            self._rigid_mass = np.where(unstated, nominal, self._rigid_mass)
        self.mass0 = self._with_tools(element_mass)
        unmassed = active[:, 0] & ~(self.mass0 > 0)
        if unmassed.any():
            raise ValueError(
                f"node {np.flatnonzero(unmassed)[0]} has no mass: every node of an "
                "element needs a positive lumped mass for the dynamic solvers"
            )
        # Interactions have no mass of their own: they size themselves from the elements.
        if self.interactions:
            dt = self.stable_dt(state0)
            penalty_step = self.penalty_stable_dt(state0)
            for interaction in self.interactions:
                if _calibrate_takes_penalty_step(interaction.calibrate):
                    interaction.calibrate(self.mass0, dt, penalty_step)
                else:  # a block written to the protocol's calibrate(mass, stable_dt)
                    interaction.calibrate(self.mass0, dt)
        self._has_history = any(h is not None for h in state0.history)
        self._no_history = (None,) * len(self.parts)
        self._load_terms = load_terms(model.loads, active, moment_takers(model.blocks, mesh))
        self._gravity_terms = [(g.amplitude, g.vector) for g in model.gravities]
        # Each gravity's nodal weights m g (n, 3), and the nodes no element carries: made
        # once, not at every step's load.
        self._gravity_forces = [
            self._weighed_mass[:, None] * np.asarray(vector) for _, vector in self._gravity_terms
        ]
        self._unloaded = np.flatnonzero(~active[:, 0])
        #: The force-driven tools' nodes, their contact force and prescribed load
        #: (femcore/driven_tools.py).
        self.driven_tools = DrivenTools(
            self.interactions,
            self.translation_free,
            self._load_terms,
            list(zip((a for a, _ in self._gravity_terms), self._gravity_forces)),
        )

    # ------------------------------------------------------------- construction helpers
    def _cells(self, entry: BlockEntry) -> np.ndarray:
        kind = entry.element.cell_type
        assert kind is not None, "elements cover mesh cells"
        return self.mesh.cells(kind)[entry.cells]

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
        # made at once, not by a dataclass replace (the explicit solver commits every step)
        return State(
            state.positions, state.directors, state.velocities, state.angular_velocities,
            state.time, state.load_factor, history,
        )  # fmt: skip

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
        mass, inertia = self._element_lumped_mass(state, density_scale)
        return self._with_tools(mass), inertia

    def _with_tools(self, mass: np.ndarray) -> np.ndarray:
        """``mass`` (n,), the elements' nodal mass, with the tools' nodes' masses added in
        place."""
        if self.rigid_nodes.size:
            np.add.at(mass, self.rigid_nodes, self._rigid_mass)
        return mass

    def _element_lumped_mass(self, state: State, density_scale: list | None = None):
        """The elements' nodal mass (n,) and rotary inertia (n,), the tools' nodes' aside."""
        mass = np.zeros(self.n_nodes)
        inertia = np.zeros(self.n_nodes)
        for i, block in enumerate(self.blocks):
            m, j = block.lumped_mass(state, None if density_scale is None else density_scale[i])
            mass += m
            if j is not None:
                inertia += j
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
        blocks = len(self.blocks)
        for i in indices:
            if i >= blocks:  # an interaction adds its rows in place (no (n, 3) arrays)
                self.interactions[i - blocks].add_internal_force(state, histories[i], force, moment)
                continue
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
            interaction.add_internal_force(state, history, force, moment)
            energy += interaction.strain_energy(state, history)
        return force, moment, float(energy)

    def support_moments(self, state: State) -> np.ndarray:
        """The moments (n, 3), N mm, the supports exert on the element blocks through no DOF
        (``ElementBlock.support_moments``: the fibrous shell's clamp wall), summed; zeros
        where no block has any."""
        total = np.zeros((self.n_nodes, 3))
        for block, history in zip(self.blocks, self._histories(state)):
            moment = block.support_moments(state, history)
            if moment is not None:
                total += moment
        return total

    def _moment_or_zeros(self, moment: np.ndarray | None) -> np.ndarray:
        return np.zeros((self.n_nodes, 3)) if moment is None else np.asarray(moment, dtype=float)

    def cell_stable_dt(self, state: State) -> list[np.ndarray]:
        """Per-block arrays of per-cell critical steps (s)."""
        return [np.asarray(block.cell_stable_dt(state), dtype=float) for block in self.blocks]

    def penalty_frequency_squared(
        self, mass: np.ndarray, state: State | None = None, step: float | None = None
    ) -> float:
        """The largest omega^2 (1/s^2) the interactions' penalty springs (``springs``, or
        ``springs_at(state)`` with ``state`` given) can add to the elements': max over the
        nodes of sum k / m, the sum over every spring at the node, of every interaction (a
        node pinched between two tools, a ply's node pressed by the ply above and by the
        die). Each interaction's springs bound its stiffness at every contact state (a node
        not touching now may touch before the step is next evaluated), so the sum bounds
        any set of them at once (docs/theory.md §6.2, "The penalty springs"). ``mass`` (n,)
        the lumped masses the solver uses, t; ``step`` the largest step the solver may take
        until the next evaluation, s (solvers/explicit.py: the elements' critical step at the
        start, then 1.25 times the step taken, or the step if larger, at most the critical
        one; None: unknown, each interaction's own guess). 0 without springs."""
        if step is not None and not (np.isfinite(step) and step > 0.0):
            raise ValueError(f"the step until the next evaluation must be > 0 s, got {step}")
        total = np.zeros(len(mass))
        for interaction in self.interactions:
            springs = (
                interaction.springs()
                if state is None
                else _springs_at(interaction, state, step, mass)
            )
            if springs is not None and len(springs[0]):
                nodes, stiffness = springs
                nodes = np.asarray(nodes)
                total += np.bincount(nodes, np.asarray(stiffness) / mass[nodes], len(mass))
        return float(total.max()) if len(total) else 0.0

    def clearance_parts(self, state: State) -> list[int]:
        """The indices into ``parts`` of the interactions that give a clearance at ``state``
        (``InteractionBlock.clearance``; None: the others)."""
        histories = self._interaction_histories(state)
        blocks = len(self.blocks)
        return [
            blocks + i
            for i, (interaction, history) in enumerate(zip(self.interactions, histories))
            if interaction.clearance(state, history) is not None
        ]

    def reachable_springs(
        self, state: State, reach: float, parts: list[int]
    ) -> tuple[np.ndarray, np.ndarray]:
        """The springs the interactions ``parts`` (``clearance_parts``) may put on the nodes
        about to meet them: (springs (n,) N/mm, per node the sum over those interactions of
        their ``springs_at(state)`` at it where its clearance is in (0, ``reach``] mm; watch
        (n,) mm, the least clearance of a node farther off, inf where none). A node that
        touches (clearance <= 0) has its stiffness in the interaction's tangent at ``state``,
        and one farther off none until it has moved by its watch (``clearance``'s promise)."""
        histories = self._histories(state)
        springs = np.zeros(self.n_nodes)
        watch = np.full(self.n_nodes, np.inf)
        blocks = len(self.blocks)
        for i in parts:
            interaction = self.interactions[i - blocks]
            clearance = np.asarray(interaction.clearance(state, histories[i]), dtype=float)
            found = _springs_at(interaction, state, None, None)
            if found is not None and len(found[0]):
                nodes = np.asarray(found[0])
                near = (clearance[nodes] > 0.0) & (clearance[nodes] <= reach)
                springs += np.bincount(nodes[near], np.asarray(found[1])[near], self.n_nodes)
            watch = np.minimum(watch, np.where(clearance > reach, clearance, np.inf))
        return springs, watch

    def penalty_frequencies(
        self, mass: np.ndarray, state: State, step: float | None = None
    ) -> list[np.ndarray | None]:
        """Per interaction the omega^2 (n,) (1/s^2) its penalty springs add at each node, as
        ``penalty_frequency_squared`` sums them (None for one without springs): which
        contacts hold a run's step (solvers/step_limits.py)."""
        out: list[np.ndarray | None] = []
        for interaction in self.interactions:
            springs = _springs_at(interaction, state, step, mass)
            if springs is None or not len(springs[0]):
                out.append(None)
                continue
            nodes = np.asarray(springs[0])
            out.append(np.bincount(nodes, np.asarray(springs[1]) / mass[nodes], len(mass)))
        return out

    def stable_dt(self, state: State) -> float:
        """Critical time step of the elements (s), the smallest over all cells (the
        interactions' springs come in through ``penalty_frequency_squared``)."""
        return float(min(dt.min() for dt in self.cell_stable_dt(state)))

    def penalty_stable_dt(self, state: State) -> float:
        """The step the interactions' automatic penalties are sized on (s), the smallest over
        the blocks (``ElementBlock.penalty_stable_dt``): the critical step with the Mindlin
        shells' rotary inertia at B2's closed form, whatever rotary_scaling they were given
        (docs/theory.md §6.2, "The penalty's step")."""
        return float(min(block.penalty_stable_dt(state) for block in self.blocks))

    def inverted_cells(self, state: State) -> np.ndarray:
        """(k,) int, the mesh cells turned inside out at ``state``, over the blocks
        (``ElementBlock.inverted_cells``), ascending."""
        found = [block.inverted_cells(state) for block in self.blocks]
        return np.unique(np.concatenate(found)) if found else np.zeros(0, dtype=np.int64)

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

    def driven_tool_pushes(self, state: State) -> np.ndarray:
        """(k, 3) the force (N) the force-driven tools press the body with at ``state``, one
        row per tool node (``driven_tools.nodes``; its contacts summed): minus their rows of
        ``tool_forces``."""
        return self.driven_tools.pushes(
            self.interactions, self._interaction_histories(state), state
        )

    def tool_displacements(self, state: State) -> np.ndarray:
        """(n_tools, 3) each rigid tool's translation from where it was given (mm), in the
        order of ``tool_forces``."""
        histories = self._interaction_histories(state)
        moves = [i.tool_displacements(state, h) for i, h in zip(self.interactions, histories)]
        if not moves:
            return np.zeros((0, 3))
        return np.concatenate([np.asarray(m, dtype=float).reshape(-1, 3) for m in moves])

    def tool_facing(self, state: State) -> list[np.ndarray | None]:
        """(n_tools,) per rigid tool the unit normals (s, 3) from it towards the nodes it may
        touch at ``state``, in the order of ``tool_forces`` (femcore.interaction
        ``InteractionBlock.tool_facing``; None where its interaction does not say)."""
        histories = self._interaction_histories(state)
        found: list[np.ndarray | None] = []
        for interaction, history in zip(self.interactions, histories):
            found.extend(interaction.tool_facing(state, history))
        return found

    def tool_penetrations(self, state: State, share: float) -> list[dict | None]:
        """(n_tools,) how deep the body has gone into each rigid tool at ``state``, in the
        order of ``tool_forces`` (femcore.interaction.InteractionBlock.tool_penetrations;
        None for a tool its interaction does not measure)."""
        histories = self._interaction_histories(state)
        found: list[dict | None] = []
        for interaction, history in zip(self.interactions, histories):
            found.extend(interaction.tool_penetrations(state, history, share))
        return found

    def tool_work(self, state: State, start: float, end: float) -> float:
        """Work (N mm) the moving tools do on the model while the load factor goes from
        ``start`` to ``end``, with the contact forces at ``state``."""
        histories = self._interaction_histories(state)
        return float(
            sum(i.tool_work(state, h, start, end) for i, h in zip(self.interactions, histories))
        )

    def unheld_rigid_motions(self, loaded_only: bool = True) -> list[str]:
        """The rigid motions no support holds (femcore.diagnostics.unheld_rigid_motions)."""
        return unheld_rigid_motions(self, loaded_only)

    def interaction_notes(self) -> list[str]:
        """The interactions that hold their nodes along some directions only (frictionless
        contact), as phrases (femcore.diagnostics.interaction_notes)."""
        return interaction_notes(self)

    def external_load(self, tau: float, quasi_static: bool = False, user: bool | None = None):
        """External nodal forces (n, 3) and moments (n, 3) at progress tau (dead loads).

        ``user``: None, every load; True, only those with a user amplitude; False, only those
        with a named one (Static ramps the two differently: solvers.static.Static.loads)."""
        force = np.zeros((self.n_nodes, 3))
        moment = np.zeros((self.n_nodes, 3))
        for kind, amplitude, values in self._load_terms:
            if not _taken(amplitude, user):
                continue
            factor = evaluate(amplitude, tau, quasi_static)
            if kind == "force":
                force += factor * values
            else:
                moment += factor * values
        for (amplitude, _), weight in zip(self._gravity_terms, self._gravity_forces):
            if not _taken(amplitude, user):
                continue
            force += evaluate(amplitude, tau, quasi_static) * weight
        if self._unloaded.size:
            force[self._unloaded] = 0.0
        return force, moment

    def prescribed_displacement(
        self, tau: float, quasi_static: bool = False, user: bool | None = None
    ) -> np.ndarray:
        """Imposed displacements (n, 3) at progress tau (zero where not prescribed);
        ``user`` as in ``external_load``."""
        displacement = np.zeros((self.n_nodes, 3))
        for amplitude, values in self._prescribed_terms:
            if not _taken(amplitude, user):
                continue
            displacement += evaluate(amplitude, tau, quasi_static) * values
        return displacement

    def user_amplitudes(self) -> list[Amplitude]:
        """The amplitudes of the loads, gravities and prescribed displacements that are user
        callables (``femcore.loads.amplitude_of``), in that order."""
        amplitudes = [term[1] for term in self._load_terms]
        amplitudes += [term[0] for term in self._gravity_terms]
        amplitudes += [term[0] for term in self._prescribed_terms]
        return [amplitude for amplitude in amplitudes if amplitude.name == "user"]

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
        the interactions' node fields after the blocks'. An element block's node field is NaN
        at the nodes outside the block (not defined there). Element blocks on disjoint nodes give
        one node field of a name (each node's value from its own block); parts that share
        nodes give name, name_2, ... in the order of the parts, and so do cell fields of one
        name whose shapes differ between blocks. A model of several element blocks has the
        cell field "part": each cell's block, 1 for the first added (a layup's ply number,
        bottom ply 1), NaN on cells no block covers."""
        out: dict[str, dict] = {"point": {}, **{kind: {} for kind in CELL_KINDS}}
        counts = {kind: len(self.mesh.cells(kind)) for kind in CELL_KINDS}
        covered: dict[str, np.ndarray | None] = {}  # field -> the nodes element blocks gave it
        for part, history in zip(self.parts, self._histories(state)):
            nodes = np.unique(part.connectivity) if isinstance(part, ElementBlock) else None
            for name, values in part.node_fields(state, history).items():
                if nodes is not None:
                    # not defined off the block's nodes (a Mindlin part's thickness at the
                    # fibrous part's nodes): NaN there, which ParaView shows as no value,
                    # never 0, which reads as a value
                    values = _off_block_nan(np.asarray(values), nodes)
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
                # A field of another shape in an earlier block (a fibrous block's three
                # levels beside a Mindlin block's one value) is named name_2, name_3, ...
                key, count = name, 1
                while key in out[kind] and out[kind][key].shape[1:] != values.shape[1:]:
                    count += 1
                    key = f"{name}_{count}"
                full = out[kind].setdefault(
                    key, np.full((counts[kind],) + values.shape[1:], np.nan)
                )
                full[part.cell_ids] = values
        if len(self.blocks) > 1:
            # which part each cell belongs to: a layup's ply number, bottom ply 1
            # (docs/theory.md §9.3b), or the element block's in the order they were added
            for number, block in enumerate(self.blocks, start=1):
                kind = block.cell_type
                numbers = out[kind].setdefault("part", np.full(counts[kind], np.nan))
                numbers[block.cell_ids] = float(number)
        return out


def _off_block_nan(values: np.ndarray, nodes: np.ndarray) -> np.ndarray:
    """``values`` (n, ...) as floats with NaN at the nodes not in ``nodes`` (k,) int."""
    out = np.full(values.shape, np.nan)
    out[nodes] = values[nodes]
    return out


def _springs_at(interaction: Any, state: State, step: float | None, mass: np.ndarray | None):
    """``interaction.springs_at(state, step)``, with ``mass=mass`` for an interaction that
    weighs its nodes by the masses the step divides by (elements/ply_springs.py, "Weights":
    the solver's, mass scaling included, not those it was calibrated with);
    ``springs_at(state)`` for an interaction written before the step was handed down (its
    springs then bound the stiffness at the evaluated state, as that signature promised)."""
    kind = type(interaction)
    if _takes_mass(kind):
        if _takes_step(kind):
            return interaction.springs_at(state, step, mass=mass)
        return interaction.springs_at(state, mass=mass)
    if _takes_step(kind):
        return interaction.springs_at(state, step)
    return interaction.springs_at(state)


_TAKES_STEP: dict[Any, bool] = {}
_TAKES_MASS: dict[Any, bool] = {}


def _takes_mass(kind: Any) -> bool:
    """Whether ``kind.springs_at`` takes the masses as ``mass`` (kept by class)."""
    if kind not in _TAKES_MASS:
        _TAKES_MASS[kind] = "mass" in inspect.signature(kind.springs_at).parameters
    return _TAKES_MASS[kind]


def _takes_positional(function: Any, count: int, besides: tuple[str, ...] = ()) -> bool:
    """Whether ``function`` takes ``count`` positional arguments (those named ``besides`` not
    counted), or any number of them: how a protocol method written to an older, shorter
    signature is told apart."""
    parameters = inspect.signature(function).parameters.values()
    named = [
        p
        for p in parameters
        if p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD) and p.name not in besides
    ]
    return len(named) >= count or any(p.kind == p.VAR_POSITIONAL for p in parameters)


def _calibrate_takes_penalty_step(calibrate: Any) -> bool:
    """Whether an interaction block's bound ``calibrate`` takes the penalty's step beside
    (mass, stable_dt): blocks written to the two-argument form the protocol had before still
    compile, given the critical step alone."""
    return _takes_positional(calibrate, 3)


def _takes_step(kind: Any) -> bool:
    """Whether ``kind.springs_at`` (an interaction block's class) takes the step beside the
    state (kept by class: asked at every evaluation of the step)."""
    if kind not in _TAKES_STEP:
        _TAKES_STEP[kind] = _takes_positional(kind.springs_at, 3, besides=("mass",))
    return _TAKES_STEP[kind]


def _taken(amplitude: Amplitude, user: bool | None) -> bool:
    """Whether a load of ``amplitude`` is among those asked for: every one (``user`` None),
    those with a user callable (True) or those with a named amplitude (False)."""
    return user is None or (amplitude.name == "user") == user
