"""The interaction protocol: what acts between a body and something that is not an element of
it: a rigid tool (contact, friction), another body's surface (ply on ply, a blank holder on a
blank), a tie between two node sets.

An element owns mesh cells and their material; an interaction owns neither. It acts on nodes
that elements carry, and it brings what elements do not have: a penalty sized from the masses
and the stable step of the elements around it, friction anchors, dissipated energy, the force on
a tool and the work a moving tool does. The solvers see elements and interactions through two
small protocols (femcore.element and this one) and sum their forces, energies and tangents
alike; they never ask an object what it is.

An interaction *description* (``Interaction``: options only) is added with ``model.interact``
(``model.contact`` builds one from a tool). ``CompiledModel`` binds it after the element blocks,
handing it a ``Body``: the mesh, the element types with the cells they cover, the reference
directors and the DOF mask. ``Interaction.bind`` returns an ``InteractionBlock``, every method
vectorised over the nodes (or node pairs, facets) it acts on; no Python loop over them runs in a
step.

Order of the calls a block receives: ``bind``, then once ``calibrate(mass, stable_dt,
penalty_step)`` with the elements' lumped masses, critical step and the step the automatic
penalties are sized on, then, as a solver goes, ``internal_force``,
``strain_energy``, ``tangent``, ``update_history`` (state in, new history out), and the
bookkeeping (``dissipated_energy``, ``tool_forces``, ``tool_displacements``, ``tool_nodes``,
``tool_work``, ``node_fields``, ``tool_penetrations``).

Capabilities: what a quasi-static solver asks of a contact beyond its forces (its
``friction``; contact sets it freezes, ``unilateral_fallback``, ``opening_law`` and
``released``, ``set_model`` and ``with_set``; ``gaps_decide``; a soft start,
``softened_penalty``; the facets of a meshed tool, ``facet_record``) are members of this
protocol, each with a default on ``InteractionBlock`` that means the block lacks it; the
solvers call them and never test a block's class or probe it for an attribute, and the
interaction kit checks what a block declares (femcore/capability_checks.py).

History: ``State.history`` holds one entry per part of the compiled model, the element blocks
first, then the interactions (``CompiledModel.parts``); an interaction receives its entry and
never mutates it.

Sign convention as elements: ``internal_force`` returns F_int = dW/dx (the force the nodes
exert on whatever the interaction stands for), so that the residual is F_ext - F_int.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from femcore.assembly import TangentPart
from femcore.element import ElementType
from femcore.mesh import Mesh
from femcore.read_only_state import ReadOnlyState
from femcore.state import State

__all__ = [
    "ACTIVE_SET_HYSTERESIS",
    "OPENING_LAWS",
    "SPRINGS_HELD_STEPS",
    "Body",
    "BodyPart",
    "FacetRecord",
    "Interaction",
    "InteractionBlock",
    "is_friction",
]


#: The explicit step is evaluated every this many steps (solvers/explicit.py), and with it
#: ``springs_at``, whose springs must bound the stiffness until then.
SPRINGS_HELD_STEPS = 10
#: The rule by which an active set of a bilateral penalty is chosen again between Newton
#: iterations (``InteractionBlock.freeze(grow=True)``, elements/ply_active_set.py) and
#: predicted on the step's linear model (``set_model``, solvers/contact_sets.py), both read
#: here so that they agree: True, lambda_k (the multiplier stored where the last set was
#: chosen) + c (-g_{k+1}) > 0; False, g_{k+1} < 0 alone (docs/theory.md §9.3a;
#: benchmarks/static_plies_active_set.py measures the two).
ACTIVE_SET_HYSTERESIS = True
#: The laws ``InteractionBlock.opening_law`` may name: None, the block's law under Static
#: from the first increment on; "ramp", its explicit law in the first increment of each phase
#: of the load path, its history ``released`` (solvers/newton.py ``opens_on_ramp``).
OPENING_LAWS = (None, "ramp")


def is_friction(value: Any) -> bool:
    """Whether ``value`` is a Coulomb coefficient an interaction may declare: a finite real
    number >= 0, not a bool (``InteractionBlock.friction``; the compile check and the
    interaction kit both ask)."""
    return (
        not isinstance(value, (bool, np.bool_))
        and isinstance(value, (int, float, np.integer, np.floating))
        and bool(np.isfinite(value))
        and bool(value >= 0.0)
    )


@dataclass(frozen=True)
class FacetRecord:
    """The facets a meshed rigid tool's closest points lay on in the last evaluations of an
    interaction's contact (``InteractionBlock.facet_record``): what the static solver's stop
    message reads to name a node that cycles across a crease (solvers/stop_diagnosis.py).

    record : (k, c) int
        The closest facet of each of the interaction's rows (``connectivity``) in each of the
        last c evaluations, oldest first; -1 where a row had no candidate facet.
    corners : (f, 3, 3) float
        The tool's facets' corners, mm.
    normals : (f, 3) float
        The facets' unit normals.
    """

    record: np.ndarray
    corners: np.ndarray
    normals: np.ndarray


@dataclass(frozen=True)
class BodyPart:
    """One element block of the body as an interaction sees it: its element type (its
    options: a shell's ``half_thickness``) and the mesh cells it covers.

    element : ElementType
    cells : (m, k) int
        Node ids of each covered cell (rows of ``mesh.cells(element.cell_type)``).
    """

    element: ElementType
    cells: np.ndarray


@dataclass(frozen=True)
class Body:
    """What an interaction is bound to: the model's mesh and element blocks.

    mesh : Mesh
    parts : tuple of BodyPart
        The element blocks in the order they were added.
    directors : (n, 3) float
        Reference unit directors (zero rows at nodes without rotations).
    active : (n, 6) bool
        The DOFs the elements give each node (ux, uy, uz, ux', alpha, beta: femcore.dofs).
    """

    mesh: Mesh
    parts: tuple[BodyPart, ...]
    directors: np.ndarray
    active: np.ndarray

    @classmethod
    def bare(cls, mesh: Mesh) -> Body:
        """A body of the mesh's nodes with translations only and no element (an interaction
        bound on its own, as its tests do): ``covered`` is every node, ``half_thickness`` 0."""
        active = np.zeros((mesh.n_nodes, 6), dtype=bool)
        active[:, :3] = True
        return cls(mesh, (), np.zeros((mesh.n_nodes, 3)), active)

    @property
    def n_nodes(self) -> int:
        return self.mesh.n_nodes

    def covered(self) -> np.ndarray:
        """(n,) bool: the nodes some element's cells use (every node carrying DOFs in a bare
        body); a rigid tool's own node (``Model.rigid_node``) is not one."""
        if not self.parts:
            return np.asarray(self.active.any(axis=1))
        used = np.zeros(self.mesh.n_nodes, dtype=bool)
        for part in self.parts:
            used[np.asarray(part.cells).ravel()] = True
        return used

    def half_thickness(self) -> np.ndarray:
        """(n,) float, mm: at each node, the largest ``half_thickness`` of the elements around
        it (the contact surface's offset from the mid-surface; 0 for cables and free nodes)."""
        offset = np.zeros(self.mesh.n_nodes)
        for part in self.parts:
            used = np.unique(part.cells)
            offset[used] = np.maximum(offset[used], float(part.element.half_thickness))
        return offset


class Interaction(ABC):
    """Options of one interaction; ``bind`` makes a block acting on the body's nodes.

    Class attributes
    ----------------
    dofs : tuple of str
        The DOF names the interaction acts on at its nodes, e.g. ``("ux", "uy", "uz")``; every
        node it acts on must carry them (an element gives them).
    """

    dofs: ClassVar[tuple[str, ...]] = ("ux", "uy", "uz")

    @abstractmethod
    def bind(self, body: Body) -> InteractionBlock:
        """The block acting on ``body``, every option resolved once (node ids, offsets,
        search structures)."""


class InteractionBlock(ReadOnlyState, ABC):
    """An interaction bound to a body.

    Attributes
    ----------
    dofs : tuple of str
        As its description.
    connectivity : (m, k) int
        The node groups the interaction couples, one row each (a node against a tool: k = 1;
        a tie between node pairs: k = 2); the sparsity of its tangent and the node graph of
        the finite-difference tangent are built from it. A contact between moving surfaces
        lists the nodes whose forces may couple.
    reach : int
        How many hops of ``connectivity`` a force at a node depends on (1 for node-local
        interactions).
    n_tools : int
        How many rigid tools the block acts against (the rows of ``tool_forces``): 0 for an
        interaction between nodes of the body.
    friction : float
        The Coulomb coefficient of the block's contact, >= 0; 0 by default (a frictionless
        contact, a tie). The static solver holds the free unknowns in an increment's first
        iteration where a frictional block keeps no contact set (solvers/newton.py
        ``imposes_alone``).
    unilateral_fallback : bool
        For a block that keeps contact sets (overrides ``freeze``): whether a Newton attempt
        with its sets frozen that fails is tried again under its unilateral law before the
        increment is cut (solvers/newton.py ``newton``). True by default; False where that
        law is known to stall (the ply contact's active set, elements/ply_active_set.py).
    opening_law : str or None
        One of OPENING_LAWS: "ramp" for a block whose law under Static opens each phase of
        the load path with its explicit law, its history ``released`` (the ply contact's
        active set); None by default (its static law from the start).
    """

    dofs: tuple[str, ...]
    connectivity: np.ndarray
    reach: int = 1
    n_tools: int = 0
    friction: float = 0.0
    unilateral_fallback: bool = True
    opening_law: str | None = None

    # ------------------------------------------------------------------ required
    @abstractmethod
    def internal_force(
        self, state: State, history: Any = None
    ) -> tuple[np.ndarray, np.ndarray | None]:
        """Nodal forces F_int = dW/dx (n, 3), N, and moments (n, 3), N mm, or None."""

    @abstractmethod
    def strain_energy(self, state: State, history: Any = None) -> float:
        """The energy the interaction stores (N mm): the potential of ``internal_force``
        (penalty springs, stuck friction springs)."""

    # ------------------------------------------------------------------ optional
    def add_internal_force(
        self, state: State, history: Any, force: np.ndarray, moment: np.ndarray
    ) -> None:
        """``internal_force`` added into ``force`` and ``moment`` (n, 3) in place, the same
        numbers as adding the arrays it returns: how the model sums its parts
        (femcore.compiled). The default adds them; a block may add its rows without making
        (n, 3) arrays of its own (elements/node_rows.py)."""
        f, m = self.internal_force(state, history)
        force += f
        if m is not None:
            moment += m

    def tangent(self, state: State, history: Any = None) -> Sequence[TangentPart] | None:
        """d(internal_force)/d(u, psi) as tangent parts, or None (the default): the assembler
        then differentiates ``internal_force`` over ``connectivity`` and ``reach``."""
        return None

    def calibrate(
        self, mass: np.ndarray, stable_dt: float, penalty_step: float | None = None
    ) -> None:
        """Size the interaction from the elements, once, before any force is asked: the
        lumped nodal masses (n,), t, the elements' critical step, s, and the step an
        automatic penalty is sized on, s (``ElementBlock.penalty_stable_dt``: the critical
        step at the closed-form rotary inertia; None: the critical step), one that keeps the
        explicit step stable and that no chosen rotary inertia moves. The default ignores
        them."""
        return None

    def springs(self) -> tuple[np.ndarray, np.ndarray] | None:
        """Springs the interaction may put between single nodes and the ground: (nodes (s,),
        stiffness (s,) N/mm), each acting along any direction: at any contact state the
        interaction can reach before the step is evaluated again, x^T K x <= sum_s k_s |u_s|^2
        for its stiffness K and any displacement, u_s the translation of spring s's node (a
        node listed twice has both springs). The explicit step adds them up per node over
        every interaction and takes max sum k / m (docs/theory.md §6.2, "The penalty
        springs"). None: no such spring."""
        return None

    def springs_at(
        self, state: State, step: float | None = None
    ) -> tuple[np.ndarray, np.ndarray] | None:
        """``springs`` at ``state``, for a block whose springs stiffen with the configuration
        (the ply contact's fade beside the outline); the explicit step asks this one, every
        time it evaluates its step (every ``SPRINGS_HELD_STEPS`` steps), and the springs should
        bound the stiffness at every state reachable until then (the ply contact's estimate
        of that reach: elements/ply_springs.py); ``step`` (s) the largest step the solver may
        take until then (None: unknown). The default: ``springs()``. A block whose
        ``springs_at`` takes the state alone is asked so, and one that takes ``mass`` is
        handed the (n,) lumped masses the step divides by, t, mass scaling included (the ply
        contact weighs its nodes by them: elements/ply_springs.py, "Weights";
        femcore/compiled.py)."""
        return self.springs()

    def clearance(self, state: State, history: Any = None) -> np.ndarray | None:
        """(n,) float, mm: how far each node is from where the interaction can stiffen it, for
        a block whose stiffness switches on as nodes come to it (a contact), so that a
        relaxation's fictitious masses carry its springs at the nodes about to meet it and
        at no other (solvers/fictitious_masses.py; docs/theory.md §6.4a, "Contact"). The
        promise: from ``state``, while every node whose clearance is above some c > 0 has
        moved by less than its clearance (the others anyhow), the block puts no stiffness on
        those nodes; the nodes that touch at ``state`` have clearance <= 0 (their stiffness
        in ``tangent`` there), and the springs of ``springs_at(state)`` bound the block's
        stiffness at any of its nodes (as ``springs``). inf where it never acts. None (the
        default): the block's stiffness follows the configuration as an element's does, and
        its tangent at ``state`` is what the masses take."""
        return None

    def initial_history(self) -> Any:
        """History variables in the reference state (None: none)."""
        return None

    def check_start(self) -> None:
        """Raise ValueError when the body cannot start where it is (nodes that start inside
        a tool, deeper than the contact offset); called once when the model is compiled. The
        default accepts any start."""
        return None

    def held_directions(self) -> tuple[np.ndarray, np.ndarray] | None:
        """What the block holds against a rigid motion of the whole body, in the reference
        state: (nodes (k,) int, unit directions (k, 3)), each row a node held along a
        direction against the ground (a frictionless tool: its normal at each contact node;
        with friction, x, y and z too). Empty arrays for an interaction between the body's
        own nodes, which holds no rigid motion of the whole. None (the default): unknown,
        taken to hold every motion (femcore.diagnostics.unheld_rigid_motions then does not
        check the model)."""
        return None

    def touching(self, state: State, history: Any = None) -> np.ndarray | None:
        """(P,) bool: which of the block's contact points touch at ``state`` under
        ``history``, or None (the default) where the block does not say. Static compares them
        at an increment's start and at the end of its first linear step
        (solvers/imposed_alone.py)."""
        return None

    def update_history(self, state: State, history: Any) -> Any:
        """The history after a step a solver accepted at ``state``; never mutates ``history``."""
        return history

    @property
    def keeps_contact_sets(self) -> bool:
        """Whether the block has contact sets the quasi-static solvers freeze while they
        iterate: derived, not declared, from whether it overrides ``freeze`` (the tools'
        contact and the ply contact's active set do). Static treats such a block's contact as
        its sets (no curved steps, no imposed-alone rule for its friction)."""
        return type(self).freeze is not InteractionBlock.freeze

    def freeze(self, state: State, history: Any = None, grow: bool = False) -> tuple[Any, int]:
        """The active-set strategy of the quasi-static solvers: (the history with the set of
        touching nodes frozen at ``state``, so that the forces are smooth while the solver
        iterates; the number of nodes whose contact status at ``state`` differs from the set
        frozen in ``history``, all touching nodes when none is). ``grow``: only add the nodes
        that penetrate at ``state`` to the set frozen in ``history`` and remove those that are
        clearly off the tool (elements/contact.py: more than the body's thickness; a set that
        changes only so while Newton iterates cannot chatter), and count them. The default has
        no contact set: (history, 0)."""
        return history, 0

    def thaw(self, history: Any) -> Any:
        """The history without the set ``freeze`` froze (the contact decided by the gap
        again); the default returns it as it is."""
        return history

    def touch_changes(self, state: State, history: Any) -> int | None:
        """For a set frozen with stick and slip states (friction): the number of nodes whose
        touching at ``state`` differs from the set frozen in ``history``, their stick and slip
        states aside (solvers/slip_sets.py). The default, None: no such states (``freeze``'s
        count is all of it)."""
        return None

    def released_slip(self, history: Any) -> Any:
        """``history`` with its frozen set kept and its stick and slip states left to the
        return mapping (solvers/slip_sets.py); the default: as it is."""
        return history

    def carried_by_tool(
        self, state: State, history: Any, start: float, end: float
    ) -> tuple[np.ndarray, np.ndarray] | None:
        """The quasi-static solvers' tool-following predictor: (the nodes touching a tool at
        ``state`` (k,) int, the tool's prescribed translation from load factor ``start`` to
        ``end`` (k, 3), mm; zero for a tool that stays), so that an increment can start with
        them carried along instead of the tool inside them. The default: None."""
        return None

    def released(self, history: Any) -> Any:
        """``history`` without a frozen set or a solver's marker, so that the block's law is
        its explicit one: asked of a block whose ``opening_law`` is "ramp" at the first
        increment of a phase (solvers/newton.py ``on_ramp``). The default returns it as it
        is."""
        return history

    def gaps_decide(self, history: Any) -> bool:
        """Whether the block's forces at any state are decided by its gaps alone under
        ``history`` (nothing in it, such as friction anchors, that a probe of the path could
        carry past a limit): the static solver may then curve its steps
        (solvers/newton.py ``curves_with_contact``). The default: only without a history
        (None); the ply contact's sides, held through an increment, count as none."""
        return history is None

    def set_model(self, state: State, history: Any, frames: Any, dofs: Any) -> dict | None:
        """The linear model of the block's frozen active set at ``state``, from which the
        static solver predicts the next set (solvers/contact_sets.py): a dict of the points
        that may switch ("points" (r,)), the entries of dg/dq in the generalised unknowns of
        ``dofs`` in ``frames`` ("slots", "values" (r, 30)), "gap" (r,) mm, "stiffness" (r,)
        N/mm, "active" (r,) bool and "pressure" (r,) N (elements/ply_active_set.py); and
        optionally "forces" (r, 30), a row's force direction F where it is not its gradient
        (the point adds k g F to the forces, k F G^T to the tangent), "leader" (r,) int, the
        row whose rule decides each row (its own by default; elements/contact_set_model.py).
        The default, None: no set to predict (asked of every interaction at every
        iteration)."""
        return None

    def with_set(
        self, history: Any, points: np.ndarray, active: np.ndarray, pressure: np.ndarray
    ) -> Any:
        """``history`` with the frozen set's members ``active`` (r,) bool and multipliers
        ``pressure`` (r,) N at the rows ``points`` (r,) of ``set_model``: asked only of a block
        whose ``set_model`` gave a model, which must override it."""
        raise NotImplementedError(
            f"{type(self).__name__}.set_model gave a model but with_set is not overridden: "
            "a block that gives a set model changes its set with with_set"
        )

    @contextmanager
    def softened_penalty(self, share: float) -> Iterator[bool]:
        """Inside the block, the penalty of the block's contact times ``share`` (0, 1] if it
        takes a soft start, restored after it, even on an error; yields whether it does
        (Static's ``ply_penalty_start``, solvers/penalty_start.py: Newton converges an
        increment on the soft law first). The default keeps its penalty: a block whose
        history holds the penalty's past (friction anchors) or that has none."""
        yield False

    @contextmanager
    def stiff_stick(self) -> Iterator[bool]:
        """Inside the block, the block's friction held by a stick spring that does not vanish
        with the normal force, restored after it, even on an error; yields whether it has one
        to stiffen (Static's retry of an increment that failed, solvers/stick_start.py:
        Newton converges it so first, then on the block's own law). The default has none."""
        yield False

    def facet_record(self) -> FacetRecord | None:
        """The facets of a meshed rigid tool the block's rows touched in its last evaluations
        (``FacetRecord``), for the static solver's stop message; None by default: no meshed
        tool, or one whose normal is continuous across its edges (smoothed), with no crease
        to name."""
        return None

    def augment(self, state: State, history: Any) -> tuple[Any, dict | None]:
        """The augmented Lagrangian's update at a state a quasi-static solver converged: (the
        history with the multipliers updated, a report {"penetration", "slip", "tolerance"
        (mm), "within": the constraints met at ``state``}). The default has no multipliers:
        (history, None)."""
        return history, None

    def dissipated_energy(self, history: Any = None) -> float:
        """Energy dissipated since the start (N mm; friction), kept in the history."""
        return 0.0

    def tool_forces(self, state: State, history: Any = None) -> np.ndarray:
        """(n_tools, 3) the force (N) the body exerts on each of the block's rigid tools."""
        return np.zeros((self.n_tools, 3))

    def tool_displacements(self, state: State, history: Any = None) -> np.ndarray:
        """(n_tools, 3) each rigid tool's translation from where it was given, mm (its
        prescribed motion and, for a force-driven tool, its free translation); zeros by
        default."""
        return np.zeros((self.n_tools, 3))

    def tool_nodes(self) -> np.ndarray:
        """(n_tools,) int, the node carrying each tool's free translation (a force-driven
        tool's, ``Model.rigid_node``), -1 for a tool moved by its motion alone: how a solver
        sets a tool's contact force beside the force prescribed on its node. All -1 by
        default."""
        return np.full(self.n_tools, -1, dtype=np.int64)

    def tool_work(self, state: State, history: Any, start: float, end: float) -> float:
        """Work (N mm) the block's moving tools do on the body while the load factor goes from
        ``start`` to ``end``, with the forces at ``state``; 0 by default."""
        return 0.0

    def tool_facing(self, state: State, history: Any = None) -> list[np.ndarray | None]:
        """Per rigid tool of the block (``n_tools`` entries, ``tool_forces``' order) the unit
        normals (s, 3) from the tool towards each node it may touch at ``state``: the way a
        force-driven tool must be pushed to press the body (solvers/driven_tool_checks.py).
        None for a tool the block does not say, every one by default."""
        return [None] * self.n_tools

    def tool_penetrations(
        self, state: State, history: Any = None, share: float = 0.25
    ) -> list[dict | None]:
        """How deep the body's contact surface has gone into each of the block's rigid tools
        at ``state`` (``n_tools`` entries, in ``tool_forces``' order): {deepest_mm (>= 0, 0
        where no node presses it), node (the deepest's), at (3,) where it is, mm,
        thickness_mm (the body's contact thickness there, twice its offset), pressed (how
        many nodes press the tool), past_share (how many lie deeper than ``share`` of their
        thickness), force_N (the pressed nodes' normal force), mean_mm (their mean depth)};
        None for a tool the block does not measure, every one by default
        (solvers/tool_penetration.py reads them after a run)."""
        return [None] * self.n_tools

    def node_fields(self, state: State, history: Any = None) -> dict[str, np.ndarray]:
        """Nodal outputs {name: (n, ...)} for results and VTU files."""
        return {}
