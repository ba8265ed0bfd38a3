"""Model: the fixed description of a problem (mesh, element blocks, interactions, constraints,
loads).

A ``Model`` is written by the user through a few builder methods, each of which validates its
input at once. Solvers call ``model.compile()``, which binds the element blocks and the
interactions to the mesh and turns the records into the index arrays and nodal vectors a time
step needs (femcore.compiled). The changing quantities live in ``femcore.state.State``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from femcore.checks import as_reals
from femcore.compiled import CompiledModel
from femcore.dofs import DOF_NAMES, dof_columns
from femcore.element import ElementType
from femcore.interaction import Interaction
from femcore.loads import (
    AmplitudeFunction,
    Fix,
    Gravity,
    NodalLoad,
    Prescribed,
    RigidNode,
    amplitude_of,
)
from femcore.memory import small_pages
from femcore.mesh import CELL_KINDS, Mesh, NodePredicate
from femcore.mesh_checks import check_thickness_scale
from femcore.set_names import set_named

__all__ = ["BlockEntry", "CompiledModel", "Model", "NodeSelection"]

#: A node selection: the name of a node set of the mesh, node ids, or a predicate
#: ``(x, y, z) -> mask`` over the node coordinates (as ``Mesh.nodes`` takes).
NodeSelection = str | int | Sequence[int] | np.ndarray | NodePredicate


def _vector3(value, what: str) -> np.ndarray:
    """A (3,) float vector, or ValueError naming ``what`` (a word such as "down" where a
    vector belongs is refused here, not deep inside numpy)."""
    expected = "3 finite numbers (a vector x, y, z)"
    vector = as_reals(value, what, expected)
    if vector.shape != (3,) or not np.all(np.isfinite(vector)):
        raise ValueError(f"{what} must be 3 finite numbers (a vector x, y, z), got {value!r}")
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
        self.interactions: list[Interaction] = []
        self.rigid_nodes: list[RigidNode] = []
        self._tool_nodes: list[tuple[object, int]] = []  # (driven tool, its node)
        self._compiled: CompiledModel | None = None

    # ----------------------------------------------------------------- description
    def add(self, element: ElementType, cells: str | np.ndarray | list[int] | None = None) -> int:
        """Add an element block.

        Parameters
        ----------
        element : ElementType
            An element type (femcore.element.ElementType) over mesh cells: a cable, a shell.
        cells : None, str or array of int
            Ids of the mesh cells of the element's cell type; None = all of them; a string = a
            named set of those cells.

        Returns
        -------
        int
            The block index (``model.blocks[i]``, ``State.history[i]``).

        Raises
        ------
        ValueError
            Not an element type, an unknown or empty cell set, cells another block covers, or
            a shell thicker than the largest extent of its cells (a mesh and a material in two
            systems of units; thicker than twenty times their median edge: a UserWarning,
            femcore.mesh_checks.check_thickness_scale).
        """
        if isinstance(element, Interaction):
            raise ValueError(
                f"{type(element).__name__} is an interaction, not an element: add it with "
                "model.interact(...)"
            )
        if not isinstance(element, ElementType):
            raise ValueError(
                f"{type(element).__name__} is not an element type: expected an instance of a "
                "subclass of femcore.element.ElementType (elements.base)"
            )
        cell_type: str = getattr(element, "cell_type", "")
        if cell_type not in CELL_KINDS:
            raise ValueError(
                f"{type(element).__name__}.cell_type is {cell_type!r}: expected one of "
                f"{tuple(CELL_KINDS)}, on the element type as on its block (what acts on "
                "nodes without cells is an interaction: femcore.interaction, model.interact)"
            )
        if not getattr(element, "dofs", None):
            raise ValueError(
                f"{type(element).__name__}.dofs is {getattr(element, 'dofs', None)!r}: the "
                "element type declares the DOFs its cells' nodes carry, among ux, uy, uz, "
                "alpha, beta (as its block does)"
            )
        n_cells = len(self.mesh.cells(cell_type))
        if cells is None:
            ids = np.arange(n_cells)
        elif isinstance(cells, str):
            sets = self.mesh.cell_sets(cell_type)
            cells = set_named(sets, cells, self.mesh.fold_set_names)
            if cells not in sets:
                raise ValueError(
                    f"no {cell_type} set named {cells!r}: the mesh has {sorted(sets) or 'none'}"
                )
            ids = np.asarray(sets[cells], dtype=np.int64)
        else:
            ids = self._ids(cells, n_cells, f"{cell_type} cell")
        if ids.size == 0:
            named = f" (its {cell_type} set {cells!r} is empty)" if isinstance(cells, str) else ""
            raise ValueError(
                f"{type(element).__name__} block covers no cell{named}: the mesh has "
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
        half = getattr(element, "half_thickness", None)  # a shell's section (a cable has none)
        if isinstance(half, float) and half > 0.0:
            cells_nodes = self.mesh.cells(cell_type)[ids]
            check_thickness_scale(self.mesh.points, cells_nodes, 2.0 * half, type(element).__name__)
        self.blocks.append(BlockEntry(element, ids))
        self._compiled = None
        return len(self.blocks) - 1

    def fix(
        self,
        nodes: NodeSelection,
        dofs: str | Sequence[str] | None = None,
        tilt: str | None = None,
    ) -> None:
        """Hold DOFs at zero.

        Parameters
        ----------
        nodes : str, array of int or callable
            A node-set name of the mesh, node ids, or a predicate ``(x, y, z) -> mask``.
        dofs : None, str or sequence of str
            None = every DOF of those nodes, or names such as "uz", ("ux", "uy", "uz"),
            "alpha" (femcore.dofs.DOF_NAMES); with ``tilt``, an empty sequence: none more.
        tilt : {"x", "y", "z"} or None
            Also hold the director's turn towards that global axis: the out-of-plane turn
            on a symmetry plane normal to it (``model.fix(plane, ["uz"], tilt="z")`` for
            z = const). Alpha turns the director towards V1 of its nodal frame and beta
            towards -V2, and which of them turns it towards the axis may change along a
            plane (docs/theory.md §1.2); this picks it at each node when the model is
            compiled, which refuses nodes where neither does (directors off the plane).

        Raises
        ------
        ValueError
            For an unknown set, node id, DOF name or axis, or alpha or beta beside ``tilt``.
        """
        if tilt is None:
            columns = None if dofs is None else dof_columns(dofs)
            self.fixes.append(Fix(self._node_ids(nodes), columns))
            self._compiled = None
            return
        if tilt not in ("x", "y", "z"):
            raise ValueError(f"tilt must be 'x', 'y' or 'z' (a global axis), got {tilt!r}")
        names = () if dofs is None else (dofs,) if isinstance(dofs, str) else tuple(dofs)
        columns = dof_columns(names) if names else np.zeros(0, dtype=np.int64)
        if dofs is None or np.isin(columns, (3, 4)).any():
            raise ValueError(
                f"tilt = {tilt!r} picks alpha or beta at each node: give the translations "
                f"alone in dofs, got {dofs!r}"
            )
        self.fixes.append(Fix(self._node_ids(nodes), columns, "xyz".index(tilt)))
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
            value = as_reals(value, name, f"a finite number or {ids.size} (one per node)")
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

    def interact(self, interaction: Interaction) -> int:
        """Add an interaction (femcore.interaction): a contact with a tool, a tie, a contact
        between two bodies' surfaces. It is bound after the element blocks.

        Returns
        -------
        int
            Its index in ``model.interactions``; its history is
            ``State.history[len(model.blocks) + index]`` (``CompiledModel.parts``).
        """
        if not isinstance(interaction, Interaction):
            raise ValueError(
                f"{type(interaction).__name__} is not an interaction: expected an instance of "
                "a subclass of femcore.interaction.Interaction"
            )
        self.interactions.append(interaction)
        self._compiled = None
        return len(self.interactions) - 1

    def contact(
        self,
        tool,
        nodes: NodeSelection | None = None,
        friction: float = 0.0,
        penalty: float | None = None,
        stick_stiffness: float | None = None,
        augmented: bool = False,
        augmented_tolerance: float | None = None,
        damping: float | None = None,
    ) -> int:
        """Penalty contact of ``nodes`` with a ``tool``, with Coulomb friction: the
        interaction ``tool.contact(nodes, friction=, penalty=)`` builds (a rigid tool of
        elements.tools gives elements.contact.Contact). The contact surface is the
        mid-surface offset by half the thickness of the shell at each node
        (``ElementType.half_thickness``; 0 for cables), so a stack of thickness h rests h / 2
        above the tool. Which side of a sphere or cylinder the body stays on is the tool's
        ``side``.

        Parameters
        ----------
        tool : an object with a ``contact`` method (elements.tools.RigidTool)
        nodes : node selection, optional
            The nodes that may touch (default: every node of the model's cells).
        friction : float
            Coulomb coefficient mu >= 0 (stick below mu times the normal force, slip at it).
        penalty : float, optional
            N/mm per node, normal and tangential; None: 0.1 m (2 / dt)^2 per node, chosen
            when the model is compiled (m the node's lumped mass, dt the critical step of the
            model without contact: the explicit step stays stable; elements/contact.py).
        stick_stiffness : float, optional
            The friction's stick spring k_t over the normal penalty k, in (0, 1] (None: 1).
            A node sticks until its tangential offset from its anchor reaches mu k p / k_t
            (the elastic slip); k_t = k makes that a fraction of the normal penetration, a
            stick zone so narrow that a quasi-static Newton meets stick and slip by turns
            where nothing but friction holds a body in its plane. 1e-2 leaves the elastic
            slip a small fraction of an element (elements/contact.py, "Stick spring").
        augmented : bool
            The augmented Lagrangian (Uzawa passes) under Static: the penetration and the
            elastic slip brought within ``augmented_tolerance`` whatever the penalty
            (elements/augmented_contact.py). Off by default.
        augmented_tolerance : float, optional
            The penetration and elastic slip it accepts, mm (None: 1e-3 of the contact
            thickness, or of the median cell edge for a cable).
        damping : float, optional
            Normal contact damping, a fraction zeta in [0, 1] of the critical damping 2 sqrt(k
            m) of each node's contact spring, against its rate of approach, in explicit
            dynamics (None: 0, none). It damps the ringing of nodes on the penalty springs;
            its dissipated energy is reported with the friction's
            (elements/contact_damping.py).

        Returns
        -------
        int
            The interaction's index (``model.interactions``); ``CompiledModel.tool_forces``
            gives the force on each tool.

        A tool free along some axes (``tool.driven``, ``tool.free``: a blank holder) gets a
        node of its own on its first contact (``rigid_node`` at ``tool.reference_point()``
        with ``tool.mass``), loaded by ``tool.force`` with the tool's amplitude; every contact
        with that tool shares it (``tool_node`` of the contact).
        """
        build = getattr(tool, "contact", None)
        if not callable(build):
            raise ValueError(
                f"contact needs a tool that builds its contact interaction (a rigid tool of "
                f"elements.tools: RigidPlane, RigidSphere, ...), got {tool!r}"
            )
        if nodes is None:
            if not self.blocks:
                raise ValueError("contact: add the elements first (no node is covered yet)")
            ids = None
        else:
            ids = self._node_ids(nodes)
        options: dict = {"friction": friction, "penalty": penalty}
        if stick_stiffness is not None:  # a tool's own contact may not know the option
            options["stick_stiffness"] = stick_stiffness
        if augmented:  # nor these
            options["augmented"] = augmented
            if augmented_tolerance is not None:
                options["augmented_tolerance"] = augmented_tolerance
        elif augmented_tolerance is not None:
            raise ValueError("augmented_tolerance is given without augmented=True")
        if damping is not None:
            options["damping"] = damping
        if getattr(tool, "driven", False):
            options["tool_node"] = self._tool_node(tool)
        interaction = build(ids, **options)
        return self.interact(interaction)

    def _tool_node(self, tool) -> int:
        """The node of a driven tool: made on its first contact, shared by the next."""
        for known, node in self._tool_nodes:
            if known is tool:
                return node
        free = tuple("u" + axis for axis in tool.free_names)
        node = self.rigid_node(tool.reference_point(), tool.mass, free)
        if np.any(tool.force != 0.0):
            self.force(node, tool.force, tool.amplitude_given)
        self._tool_nodes.append((tool, node))
        return node

    def rigid_node(
        self,
        position: ArrayLike,
        mass: float | None = None,
        free: str | Sequence[str] = ("ux", "uy", "uz"),
    ) -> int:
        """A node of its own, used by no cell, carrying the translations of a rigid body (a
        force-driven tool's: ``contact`` makes it): a point appended to the model's mesh
        (``model.mesh`` becomes a new Mesh; the one given is unchanged, its node ids kept).

        Parameters
        ----------
        position : (3,) float
            Where the node is, mm.
        mass : float, optional
            Its mass, t (gravity acts on it); None: none stated, which the quasi-static
            solvers accept (a nominal mass, no weight) and the explicit solver refuses.
        free : str or sequence of str
            The translations it is free along ("ux", "uy", "uz"); the others are held.

        Returns
        -------
        int
            The node's id: load it with ``force``, read it in results.
        """
        point = _vector3(position, "rigid_node position")
        if mass is not None and not (
            isinstance(mass, (int, float)) and math.isfinite(mass) and mass > 0
        ):
            raise ValueError(f"rigid_node mass must be a positive number of t, got {mass!r}")
        columns = dof_columns(free)
        if (columns > 2).any():
            raise ValueError(f"a rigid node is free along translations only, got free={free!r}")
        mesh = self.mesh
        self.mesh = Mesh(
            np.vstack([mesh.points, point]),
            node_sets=mesh.node_sets,
            cells={kind: mesh.cells(kind) for kind in CELL_KINDS},
            cell_sets={kind: mesh.cell_sets(kind) for kind in CELL_KINDS},
            fold_set_names=mesh.fold_set_names,
        )
        node = mesh.n_nodes
        self.rigid_nodes.append(RigidNode(node, None if mass is None else float(mass)))
        held = [name for name in ("ux", "uy", "uz") if name not in {DOF_NAMES[c] for c in columns}]
        if held:
            self.fixes.append(Fix(np.array([node]), dof_columns(held)))
        self._compiled = None
        return node

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
            nodes = set_named(self.mesh.node_sets, nodes, self.mesh.fold_set_names)
            if nodes not in self.mesh.node_sets:
                raise ValueError(
                    f"no node set named {nodes!r}: "
                    f"the mesh has {sorted(self.mesh.node_sets) or 'none'}"
                )
            nodes = self.mesh.node_sets[nodes]
        elif callable(nodes):  # a predicate(x, y, z) -> mask, as Mesh.nodes takes
            nodes = self.mesh.nodes(nodes)
            # A rigid tool's own node is selected by its id only: a predicate over the
            # body's coordinates must not hold or load a holder that happens to lie there.
            nodes = np.setdiff1d(nodes, [r.node for r in self.rigid_nodes])
        return self._ids(nodes, self.mesh.n_nodes, "node")

    @staticmethod
    def _ids(ids, count: int, what: str) -> np.ndarray:
        try:
            array = np.atleast_1d(np.asarray(ids))
        except (TypeError, ValueError):
            array = np.array([ids], dtype=object)
        if array.dtype.kind not in "iufb":
            raise ValueError(
                f"{what} selection must be {what} ids (integers), a set name or a predicate, "
                f"got {ids!r:.80}"
            )
        if array.ndim != 1:
            raise ValueError(
                f"{what} ids must be a flat sequence of integers, got an array of shape "
                f"{array.shape}"
            )
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
        """Bind blocks and interactions, build DOF, constraint and load arrays (cached until the
        model changes)."""
        if self._compiled is None:
            # built once, its arrays touched a few times: ordinary pages (femcore/memory.py)
            with small_pages():
                self._compiled = CompiledModel(self)
        return self._compiled
