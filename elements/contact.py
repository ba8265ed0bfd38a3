"""Node-to-tool penalty contact with Coulomb friction: an interaction (femcore.interaction) of
a node set with a rigid tool of elements/tools.py, added by ``Model.contact`` (docs/theory.md §9).

Normal. The shell's contact surface is its mid-surface offset by half its thickness along the
normal (the thickness measured along the normal is conserved by both shells), so a node touches
when its distance d to the tool falls below ``offset`` = h / 2: the penetration is p = max(0,
offset - d), the normal force on the node f_N = k p n (n the tool's normal towards the body)
and the energy 1/2 k p^2.

Friction (Coulomb, penalty-regularised, return mapping). Each touching node keeps an anchor: the
point of the tool it stuck to, carried with the tool. Its tangential offset from the anchor s =
(I - n n^T)(x - a) loads a tangential spring of stiffness k_t = k (the trial force -k_t s):

* stick, |k_t s| <= mu k p: the force is -k_t s (energy 1/2 k_t |s|^2);
* slip, |k_t s| > mu k p: the force is -mu k p s / |s|, and when the step is accepted the anchor
  follows the node to where the spring holds exactly mu k p; the energy that spring lost is the
  friction dissipation mu k p x (slip length), summed in the history.

A node that was not touching when the last step was accepted has no anchor: in the step that
brings it onto the tool it is anchored at the point of its way over the step where it touched
the contact surface, a = x_0 + theta (x - x_0) with x_0 where it was then (the history's
``approach``) and theta = g / (g + p) (g its gap at x_0, the tool's exact distance computed
when it lands, p its penetration now: the gap taken linear over the step), so its tangential
motion since it touched is slip like any other node's, and the way before it touched is not
(docs/theory.md §9.2). A node off the tool at the end of a step that was anchored when the
last one was accepted slid, in that step, to the point of its way where it left the surface
(theta = p_0 / (p_0 + g), from where it was then, the history's ``place``): that slip, the
stick spring holding nothing there, is dissipated at the mean limit force mu k p_0 / 2.
The anchors, each node's accumulated slip and the dissipation are the block's history
(femcore.element), so a quasi-static increment returns to them at every iteration and the
tangent is that of the return mapping (non-symmetric in slip: the solvers' LU takes it).

Stick spring. The tangential spring may be softer than the normal one: k_t = r k with r =
``stick_stiffness`` in (0, 1] (default 1). A node then sticks until |s| = mu k p / k_t, the
elastic slip (Abaqus's slip tolerance, there 0.5 % of an element by default). With k_t = k
that is mu times the penetration, for a light body 1e-7 of an element: every Newton update
that moves a node at all crosses the stick limit, the stick and slip sets trade nodes at each
iteration, and a body that nothing but friction holds in its plane (a strip lying on a
table) is a mechanism in every iterate where all its nodes slide. A softer stick spring
leaves the friction law and the sliding force mu k p unchanged and gives the stuck nodes a
stiffness Newton can use; what it costs is the elastic slip, which the explicit solver's
step does not see (it takes k, the larger).

Active set (the quasi-static solvers). ``freeze`` fixes which nodes touch, those of a given
state, for the Newton iterations that follow: a node of that set keeps its normal spring k (h/2 -
d) n whatever the sign of h/2 - d (a bilateral spring, pulling as well as pushing), a node
outside it has none, so the force is smooth while the set stays frozen and Newton converges
quadratically. Unilateral contact would lose a node sliding on a curved tool at every linearised
step (the straight step lifts it by s^2 / 2R, more than the penalty's penetration F / k once the
slide s exceeds sqrt(2 R F / k)), and its tangent would then hold the node by nothing.
``freeze`` also counts the nodes whose status the state contradicts (``grow``: adds the nodes
that penetrate, and removes those that have left the tool: more than ``release`` body
thicknesses off it (1 by default) and facing another feature of it than the one they were
frozen on, the tool's normal at the node turned by more than ``release_turn`` (30 deg by
default) from the one the set took it in with (kept in the history). A blank node that a Newton
step carries over a die's rim would otherwise be pulled back over that distance, onto the rim's
faceted edge, where the distance is only continuous (the 16-cell hemisphere drape by Static held
four such nodes 1.3 mm off the die and 1.5 mm off the punch, and its Newton stalled there); a
node thrown straight off a flat or a bowl still faces it and keeps its spring, which brings it
back (docs/theory.md §9.1); a node without thickness, a cable, is never removed); the solver
(solvers.newton) accepts only states in equilibrium under the unilateral law (``thaw``). The
friction limit is mu k max(p, 0) for a frozen node. With friction, ``freeze`` fixes the stick
and slip sets too, and each sliding node's slip direction: the friction force of a frozen
sliding node is mu k max(p, 0) against that direction (projected on the tool's tangent plane),
smooth in x, where the return mapping's s / |s| turns over wherever a node reverses, which
sends Newton round a cycle.

Penalty: given (N/mm per node), or chosen when the model is compiled (``calibrate``): k_i =
``PENALTY_SHARE`` m_i (2 / dt)^2, m_i the node's lumped mass and dt the elements' critical step
without the contact, a Mindlin shell's at its closed-form rotary inertia whatever j it was
given (elements/contact_penalty.py: no chosen j moves it). At the closed j a contact spring
adds 10 % to omega^2 of a node, 20 % for a node pinched between two tools (a punch and a
die), and a node resting under its own weight sinks m g / k = g dt^2 / 0.4, far below the
thickness. The explicit step takes every penalty in,
given or automatic (``springs``; docs/theory.md §9.1).

Force-driven tools (a blank holder: ``RigidTool(free=..., force=...)``). The tool's free
translation c is the displacement of a node of its own, ``tool_node`` (``Model.rigid_node``),
which carries the tool's mass, the prescribed force as a nodal load, and supports on the axes
it is not free along. The contact sees each node at x - c (the tool only translates), each row
of ``connectivity`` is (node, tool node), and the tool node takes the reaction of every
contact force: its equation is m a = F(t) - sum f in explicit dynamics and F = sum f in the
quasi-static solvers, assembled, stepped and solved as any node's (docs/theory.md §9.5).
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any

import numpy as np

from elements.contact_history import (
    FrictionHistory,
    accepted,
    initial_friction,
    start_anchors,
)
from elements.contact_penalty import PENALTY_SHARE, automatic_penalty, damping_ratio
from elements.contact_reports import penetration_report
from elements.contact_set_model import released_slip, set_model, touch_changes, with_set
from elements.contact_start import check_start_gaps
from elements.contact_tangent import friction_tangent
from elements.node_rows import add_node_forces, distinct_nodes, row_sums, same_rows, shifted
from elements.rigid_surface import RigidSurface
from elements.tool_scale import warn_tool_scale
from elements.tools import RigidTool
from femcore.assembly import CellTangent, Scatter
from femcore.checks import as_number, as_reals
from femcore.interaction import Body, FacetRecord, Interaction, InteractionBlock
from femcore.state import State

__all__ = ["PENALTY_SHARE", "Contact", "ContactBlock", "FrictionHistory"]

# The default release of a frozen node (``Contact(release=..., release_turn=...)``; module
# docstring, "Active set"): off the tool by more than this many body thicknesses (2 x its
# contact offset) AND its tool normal turned by more than this angle from the one it was frozen
# with, it has left the feature it was frozen on (carried over a die's rim) and leaves the set.
RELEASE_THICKNESSES = 1.0
RELEASE_TURN_DEG = 30.0


class Contact(Interaction):
    """Penalty contact of ``nodes`` with a rigid ``tool``, with Coulomb friction ``friction``.

    Parameters
    ----------
    tool : elements.tools.RigidTool
    nodes : (s,) int, optional
        The node ids that may touch; None: every node of the body's elements.
    offset : float or (s,) float, optional
        The contact surface's distance from the mid-surface at each node, mm; None: half the
        thickness of the elements there (``Body.half_thickness``; 0 for a cable).
    penalty : float, optional
        k, N/mm per node; None: chosen when the model is compiled (module docstring).
    friction : float
        The Coulomb coefficient mu >= 0 (0: frictionless, no history kept).
    tool_node : int, optional
        The node carrying a driven tool's free translation (``Model.rigid_node``; what
        ``Model.contact`` passes); required for a tool with ``free`` axes, refused otherwise.
    stick_stiffness : float
        k_t / k in (0, 1]: the friction's stick spring over the normal penalty (module
        docstring, "Stick spring"); 1 by default.
    augmented : bool
        The augmented Lagrangian (Uzawa) under Static (not dynamic relaxation): after an increment
        converges, each node's normal and stick multipliers take the forces of the penalty
        springs and the increment is solved again until the penetration and the elastic slip
        are within ``augmented_tolerance`` (elements/augmented_contact.py). Off by default.
    augmented_tolerance : float, optional
        The penetration and the elastic slip the augmented contact accepts, mm; None: 1e-3 of
        the contact thickness 2 h / 2 (of the median cell edge where the offset is 0: a
        cable).
    damping : float
        zeta in [0, 1]: a normal viscous force against each node's rate of approach, that
        fraction of the critical damping 2 sqrt(k m) of its contact spring, in explicit
        dynamics (elements/contact_damping.py); 0 (none) by default.
    release : float
        Under Static: a frozen node further off the tool than this many body thicknesses
        (2 x its offset) whose tool normal has also turned by more than ``release_turn`` from
        the one it was frozen with leaves the frozen set while Newton iterates (module
        docstring, "Active set"); ``math.inf``: none leaves.
    release_turn : float
        The turn of the tool's normal at the node, deg in [0, 180), past which a frozen node
        off the tool by more than ``release`` thicknesses has left the feature it was frozen
        on; 0: the distance alone decides.
    """

    dofs = ("ux", "uy", "uz")

    def __init__(
        self,
        tool: RigidTool,
        nodes=None,
        offset=None,
        penalty: float | None = None,
        friction: float = 0.0,
        tool_node: int | None = None,
        stick_stiffness: float = 1.0,
        augmented: bool = False,
        augmented_tolerance: float | None = None,
        damping: float = 0.0,
        release: float = RELEASE_THICKNESSES,
        release_turn: float = RELEASE_TURN_DEG,
    ):
        if not isinstance(tool, RigidTool):
            raise ValueError(f"tool must be a rigid tool of elements.tools, got {tool!r}")
        if tool.driven and tool_node is None:
            raise ValueError(
                f"the {type(tool).__name__} is free along {', '.join(tool.free_names)} (driven "
                "by a force): add its contact with model.contact(tool, ...), which gives the "
                "tool a node of its own for that translation"
            )
        if tool_node is not None and not tool.driven:
            raise ValueError(
                f"tool_node = {tool_node!r} is given for a {type(tool).__name__} with no free "
                "axis: a tool driven by its motion has no node of its own"
            )
        self.tool_node = None if tool_node is None else int(tool_node)
        self.tool = tool
        self.nodes = None if nodes is None else np.asarray(nodes, dtype=np.int64).ravel()
        if offset is not None:
            given = as_reals(offset, "offset", "finite numbers >= 0 (mm)")
            if not np.all(np.isfinite(given)) or (given < 0).any():
                raise ValueError(f"offset must be finite and >= 0 (mm), got {offset!r}")
        self.offset = offset
        if penalty is not None:
            stiffness = as_number(penalty, "penalty", "a positive number (N/mm) or None")
            if not (np.isfinite(stiffness) and stiffness > 0):
                raise ValueError(
                    f"penalty must be a positive number (N/mm) or None, got {penalty!r}"
                )
        mu = as_number(friction, "friction", "a Coulomb coefficient >= 0")
        if not (np.isfinite(mu) and mu >= 0):
            raise ValueError(f"friction must be a Coulomb coefficient >= 0, got {friction!r}")
        self.penalty = penalty
        self.friction = mu
        ratio = as_number(stick_stiffness, "stick_stiffness", "a number in (0, 1]")
        if not (np.isfinite(ratio) and 0.0 < ratio <= 1.0):
            raise ValueError(
                "stick_stiffness must be in (0, 1] (the stick spring k_t over the normal "
                f"penalty k), got {stick_stiffness!r}"
            )
        self.stick_ratio = ratio
        if not isinstance(augmented, (bool, np.bool_)):
            raise ValueError(f"augmented must be True or False, got {augmented!r}")
        self.augmented = bool(augmented)
        if augmented_tolerance is not None:
            allowed = as_number(augmented_tolerance, "augmented_tolerance", "a length > 0 (mm)")
            if not (np.isfinite(allowed) and allowed > 0):
                raise ValueError(
                    f"augmented_tolerance must be a length > 0 (mm) or None, got "
                    f"{augmented_tolerance!r}"
                )
            if not self.augmented:
                raise ValueError("augmented_tolerance is given without augmented=True")
        self.augmented_tolerance = augmented_tolerance
        self.damping = damping_ratio(damping)
        band = as_number(release, "release", "a number of body thicknesses > 0 (math.inf: off)")
        if not band > 0.0:  # (NaN refused too)
            raise ValueError(
                f"release must be a number of body thicknesses > 0 (math.inf: off), got {release!r}"
            )
        self.release = float(band)
        turn = as_number(release_turn, "release_turn", "an angle in [0, 180) deg")
        if not (np.isfinite(turn) and 0.0 <= turn < 180.0):
            raise ValueError(f"release_turn must be an angle in [0, 180) deg, got {release_turn!r}")
        self.release_turn = float(turn)
        if self.augmented and self.damping > 0.0:
            # The multipliers are Static's and the damping explicit dynamics': one block
            # carrying both would serve neither solver better than the two options apart.
            raise ValueError(
                "augmented=True and damping > 0 are given together: the augmented Lagrangian "
                "acts under Static, the contact damping in explicit dynamics; choose one per "
                "contact"
            )

    def bind(self, body: Body) -> ContactBlock:
        mesh = body.mesh
        nodes = np.flatnonzero(body.covered()) if self.nodes is None else self.nodes
        if self.tool_node is not None:
            if not 0 <= self.tool_node < mesh.n_nodes:
                raise ValueError(
                    f"tool_node = {self.tool_node} is not a node of the mesh "
                    f"(0..{mesh.n_nodes - 1})"
                )
            if self.tool_node in nodes:
                raise ValueError(f"the contact nodes include the tool's own node {self.tool_node}")
        if self.offset is None:
            offset = body.half_thickness()[nodes]
        else:
            given = np.asarray(self.offset, dtype=float)
            if given.shape not in ((), nodes.shape):
                raise ValueError(
                    f"offset must be one number or one per contact node ({nodes.size}), got "
                    f"shape {given.shape}"
                )
            offset = np.broadcast_to(given, nodes.shape).copy()
        self.tool.exact_within(2.0 * float(offset.max(initial=0.0)))
        area = np.zeros(mesh.n_nodes)
        triangles = mesh.triangles
        if len(triangles):  # each node's share of the area, for the contact pressure
            corners = mesh.points[triangles]
            cell_area = 0.5 * np.linalg.norm(
                np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]), axis=1
            )
            np.add.at(area, triangles.ravel(), np.repeat(cell_area / 3.0, 3))
        if self.augmented:
            from elements.augmented_contact import AugmentedContactBlock, default_tolerance

            tolerance = self.augmented_tolerance or default_tolerance(mesh, offset)
            return AugmentedContactBlock(
                self, nodes, offset, mesh.n_nodes, mesh.points, area, self.tool_node, tolerance
            )
        block = ContactBlock
        if self.damping > 0.0:
            from elements.contact_damping import DampedContactBlock  # builds on this module

            block = DampedContactBlock
        bound = block(self, nodes, offset, mesh.n_nodes, mesh.points, area, self.tool_node)
        from elements import tool_contact

        if tool_contact.compiled_pass_applies(self.tool, self.friction, self.damping, False):
            bound.compiled_forces = tool_contact.contact_forces  # the same forces, compiled
        return bound


class ContactBlock(InteractionBlock):
    """The bound contact: one row of ``connectivity`` per node, one tool; a row is (node,
    tool node) for a driven tool."""

    dofs = Contact.dofs
    reach = 1
    n_tools = 1

    def __init__(
        self,
        contact: Contact,
        nodes: np.ndarray,
        offset: np.ndarray,
        n_nodes: int,
        points: np.ndarray,
        area: np.ndarray,
        tool_node: int | None = None,
    ):
        self.tool = contact.tool
        self.friction = contact.friction
        self.tool_node = tool_node
        if tool_node is None:
            self.connectivity = nodes[:, None]
        else:
            self.connectivity = np.column_stack([nodes, np.full(len(nodes), tool_node)])
            self._tool_reference = points[tool_node].copy()
        self._mass_ratio = np.ones(len(nodes))  # m_node / m_tool, set by calibrate
        # the nodes as a range where they are one (a blank's nodes): their positions gathered
        # by a slice's copy, 0.03 against 0.49 ms for fancy indexing of 50k nodes, the same
        # numbers (asked four times a step; benchmarks/threads.py)
        first = int(nodes[0]) if len(nodes) else 0
        contiguous = np.array_equal(nodes, np.arange(first, first + len(nodes)))
        self._span = slice(first, first + len(nodes)) if contiguous else None
        self.scatter = Scatter(self.connectivity, n_nodes)
        self._distinct = distinct_nodes(self.connectivity)  # (add_internal_force)
        self.n_nodes = n_nodes
        self.offset = offset
        self.area = area[nodes]
        self._reference = points[nodes]
        # the body's whole mesh (the driven tool's node aside): a contact limited to a patch
        # of it says nothing of the body's size (elements/tool_scale.py)
        self._body_points = points if tool_node is None else np.delete(points, tool_node, axis=0)
        # A node laid on the tool touches it: its distance, computed from rotated or shifted
        # coordinates, may exceed h / 2 by a rounding error.
        self.tolerance = 1e-9 * float(np.ptp(points, axis=0).max(initial=0.0) or 1.0)
        given = contact.penalty
        self.stiffness = np.full(len(nodes), np.nan if given is None else given)
        self.stick_ratio = contact.stick_ratio  # k_t / k
        self.release = contact.release  # body thicknesses (module docstring, "Active set")
        # cos of the turn past which a node has left its feature; above 1 for 0: any turn
        self.release_cos = (
            math.cos(math.radians(contact.release_turn)) if contact.release_turn > 0 else 2.0
        )
        # contact_forces's last answer: (where the nodes were, the history, the load factor,
        # the stiffness, the forces).
        self._last_forces: tuple | None = None
        # (block, x (s, 3), load factor) -> the forces (s, 3) of a frictionless contact in one
        # compiled pass (elements/tool_contact.py; set by Contact.bind where it applies).
        self.compiled_forces: Any = None

    def surface_offset(self, history: FrictionHistory | None) -> np.ndarray:
        """(s,) where the contact's spring starts, mm from the tool: the contact offset h / 2
        (an augmented contact moves it by its multipliers, elements/augmented_contact.py)."""
        return self.offset

    def check_start(self) -> None:
        """ValueError when nodes start past the tool's surface, a UserWarning when they
        start overlapping it (elements/contact_start.py), or when a meshed tool's size is
        off the body's by more than a hundred times (elements/tool_scale.py)."""
        warn_tool_scale(self.tool, self._body_points)  # a tool mesh in m beside a body in mm
        d, _ = self.tool.distance(self._reference, 0.0)
        check_start_gaps(self.tool, d, self.offset, self.connectivity[:, 0], self.tolerance)

    def held_directions(self) -> tuple[np.ndarray, np.ndarray]:
        """Frictionless: each contact node held along the tool's normal where it starts (a
        plane leaves the translations in it and the turn about its normal free, a cylinder
        the slide along and the turn about its axis, a sphere the turns about its centre).
        With friction: each contact node held along x, y and z. A driven tool holds only
        along the axes it is not free along (the parts of those directions there)."""
        nodes = self.connectivity[:, 0]
        if self.friction > 0.0:
            nodes, directions = np.repeat(nodes, 3), np.tile(np.eye(3), (len(nodes), 1))
        else:
            _, normal = self.tool.distance(self._reference, 0.0)
            directions = np.array(normal, dtype=float)
        if self.tool_node is None:
            return nodes, directions
        directions = directions.copy()
        directions[:, list(self.tool.free)] = 0.0
        length = np.linalg.norm(directions, axis=1)
        kept = length > 1e-12
        return nodes[kept], directions[kept] / length[kept, None]

    def calibrate(self, mass: np.ndarray, stable_dt: float, penalty_step=None) -> None:
        if np.isnan(self.stiffness).any():  # the automatic penalty (elements/contact_penalty.py)
            node_mass = mass[self.connectivity[:, 0]]
            self.stiffness = automatic_penalty(node_mass, stable_dt, penalty_step)
        if self.tool_node is not None:
            self._mass_ratio = mass[self.connectivity[:, 0]] / mass[self.tool_node]

    # ------------------------------------------------------------------ kinematics
    def tool_translation(self, state: State) -> np.ndarray:
        """(3,) the driven tool's free translation, mm: its node's displacement (zero for a
        tool driven by its motion alone)."""
        if self.tool_node is None:
            return np.zeros(3)
        return state.positions[self.tool_node] - self._tool_reference

    def _positions(self, state: State, view: bool = False) -> np.ndarray:
        """(s, 3) the contact nodes where the tool sees them: less its free translation (a
        translated tool's distance is the unmoved tool's at x - c). ``view``: the nodes'
        rows of ``state.positions`` themselves where they are a range and the tool is not
        driven (read, never written: the kept forces' check compares them, copying only when
        the forces are computed anew)."""
        span = getattr(self, "_span", None)  # (absent from a block pickled without it)
        if span is not None:
            x = state.positions[span]  # a view: copied, or shifted into a new array
        else:
            x = np.take(state.positions, self.connectivity[:, 0], axis=0)
        if self.tool_node is None:
            return x.copy() if span is not None and not view else x
        return shifted(x, self.tool_translation(state))

    def touch(self, state: State, history: FrictionHistory | None = None):
        """Penetration p (s,), mm, the tool's normal (s, 3) at the nodes and whether each
        node touches (s,) bool: a node exactly on the surface counts, so that a body laid
        on a tool has a stiffness against it from the first Newton iteration. With a frozen
        set in ``history``: the nodes of the set touch, p = h/2 - d of either sign."""
        d, n = self.tool.distance(self._positions(state), state.load_factor)
        active = None if history is None else history.active
        if active is None:
            return self._touching(d, n, history)
        return np.where(active, self.surface_offset(history) - d, 0.0), n, active.copy()

    def freeze(self, state: State, history: FrictionHistory | None = None, grow: bool = False):
        """(the history with the contact set frozen at ``state``'s touching nodes, the number
        of nodes whose status under the unilateral law at ``state`` differs from the set
        frozen in ``history``; all the touching nodes when none is). ``grow``: the set frozen
        in ``history`` with the nodes that penetrate at ``state`` added (their number is the
        count), the others' sets and directions kept. A meshed tool keeps its nodes' closest
        facets from then on, for the diagnosis of a stopped solve (solvers/stop_diagnosis.py)."""
        if hasattr(self.tool, "record_facets"):
            self.tool.record_facets = True
        d, n = self.tool.distance(self._positions(state), state.load_factor)
        p, n, touching = self._touching(d, n, history)
        before = None if history is None else history.active
        changed = int(touching.sum()) if before is None else int((before != touching).sum())
        if history is None:
            none = np.full((len(d), 3), np.nan)
            history = FrictionHistory(none, np.zeros(len(d)), np.zeros(len(d)), 0.0)
        free = replace(history, active=None, sliding=None, direction=None, normal=None)
        _, s, stuck, sliding = self.tangential(state, free, p, n, touching)
        length = np.linalg.norm(s, axis=1)
        direction = s / np.where(length > 0, length, 1.0)[:, None]
        # A node at the friction limit (where the return mapping left a sliding node) slides
        # on when pushed the same way: frozen as sliding, the next increment starts right.
        held = self.friction * p / self.stick_ratio  # |s| at the limit, mu k p / k_t
        at_limit = stuck & (length >= (1.0 - 1e-6) * held) & (p > 0.0)
        sliding = sliding | at_limit
        if grow and before is not None:
            offset = self.surface_offset(history)
            added = (d < offset) & ~before
            # Off the tool by more than the band and facing another feature of it than the one
            # it was frozen on: left it (module docstring, "Active set").
            band = 2.0 * np.asarray(self.offset)
            # (a history or block pickled before the release had no normals and no release)
            kept_normal = getattr(history, "normal", None)
            frozen_normal = kept_normal if kept_normal is not None else n
            turned = np.sum(n * frozen_normal, axis=1) < getattr(self, "release_cos", 2.0)
            release = getattr(self, "release", math.inf)
            released = before & (band > 0.0) & (d > offset + release * band) & turned
            before = before & ~released
            kept = history.sliding if history.sliding is not None else sliding
            kept_direction = history.direction if history.direction is not None else direction
            # a set whose stick and slip were left to the return mapping keeps them so
            mapped = history.sliding is None and self.friction > 0.0  # (solvers/slip_sets.py)
            return replace(
                history,
                active=before | added,
                sliding=None if mapped else np.where(added, sliding, kept),
                direction=None if mapped else np.where(added[:, None], direction, kept_direction),
                normal=np.where(added[:, None], n, frozen_normal),
            ), int(added.sum() + released.sum())
        if history.sliding is not None:
            changed += int((history.sliding != sliding).sum())
        return replace(
            history, active=touching, sliding=sliding, direction=direction, normal=n
        ), changed

    set_model = set_model  # the frozen set's linear model (elements/contact_set_model.py)
    with_set = staticmethod(with_set)
    touch_changes, released_slip = touch_changes, staticmethod(released_slip)

    def thaw(self, history: FrictionHistory | None):
        """The history without its frozen set (None for a frictionless contact)."""
        if history is None or self.friction == 0.0:
            return None
        return replace(history, active=None, sliding=None, direction=None, normal=None)

    def _touching(self, d: np.ndarray, n: np.ndarray, history: FrictionHistory | None = None):
        """``touch`` from the distances d (s,) and normals n (s, 3) of the tool."""
        offset = self.surface_offset(history)
        return np.maximum(offset - d, 0.0), n, d <= offset + self.tolerance

    def tangential(self, state: State, history: FrictionHistory | None, p, n, touching):
        """The friction of the return mapping at ``state`` from the accepted ``history``:
        (force (s, 3) on the nodes, N; s (s, 3) the tangential offset from the anchors, mm;
        stuck (s,) bool; sliding (s,) bool). Zero force where there is no anchor."""
        s_count = len(p)
        zero = np.zeros((s_count, 3))
        none = np.zeros(s_count, dtype=bool)
        if history is None or self.friction == 0.0:
            return zero, zero, none, none
        x, origin = self._positions(state), self.tool.offset(state.load_factor)
        # a landing node's anchor: where its way over the step touched the contact surface
        anchors = start_anchors(history, x - origin, p, touching, self)
        anchored = touching & np.isfinite(anchors[:, 0])
        anchor = np.where(anchored[:, None], anchors, 0.0)
        r = x - (anchor + origin)
        s = np.where(anchored[:, None], r - np.sum(r * n, axis=1)[:, None] * n, 0.0)
        k = self.stiffness * self.stick_ratio  # k_t, the stick spring
        trial = k * np.linalg.norm(s, axis=1)
        limit = self.friction * self.stiffness * np.maximum(p, 0.0)
        if history.sliding is not None:  # frozen (module docstring)
            sliding = anchored & history.sliding
            stuck = anchored & ~sliding
            along = self._slip_direction(history, n)
            force = np.where(stuck[:, None], -k[:, None] * s, -limit[:, None] * along)
            return np.where(anchored[:, None], force, 0.0), s, stuck, sliding
        stuck = anchored & (trial <= limit)
        sliding = anchored & ~stuck
        scale = np.where(
            stuck, k, np.where(sliding, limit / np.where(trial > 0, trial, 1.0) * k, 0)
        )
        return -scale[:, None] * s, s, stuck, sliding

    @staticmethod
    def _slip_direction(history: FrictionHistory, n: np.ndarray) -> np.ndarray:
        """(s, 3) the frozen slip directions projected on the tangent planes of normals n."""
        assert history.direction is not None
        along = history.direction - np.sum(history.direction * n, axis=1)[:, None] * n
        length = np.linalg.norm(along, axis=1)
        return along / np.where(length > 0, length, 1.0)[:, None]

    def contact_forces(self, state: State, history: FrictionHistory | None = None) -> np.ndarray:
        """(s, 3) the forces the tool exerts on the nodes, N: k p n and the friction.

        The same nodes at the same place, load factor, history and stiffness are answered
        from the last call: an explicit step asks twice (its forces, then its moving tools'
        work), and an analytic tool's distance is as costly as the rest of the step's
        contact."""
        return self._kept_forces(state, history).copy()

    def _kept_forces(self, state: State, history: FrictionHistory | None) -> np.ndarray:
        """``contact_forces``'s numbers as kept from the last call, not a copy: read by this
        block's own passes (the nodes' rows, the tool's total), never written."""
        x = self._positions(state, view=True)
        last = getattr(self, "_last_forces", None)  # (absent from a block pickled without it)
        if (
            last is not None
            and last[1] is history
            and last[2] == state.load_factor
            and last[3] is self.stiffness
            and same_rows(last[0], x)
        ):
            return last[4]
        if self.tool_node is None and getattr(self, "_span", None) is not None:
            x = x.copy()  # the view: the kept rows must not follow the state's
        compiled = getattr(self, "compiled_forces", None)  # (absent from an older pickle)
        if compiled is not None and history is None:
            forces = compiled(self, x, state.load_factor)
        else:
            p, n, touching = self.touch(state, history)
            friction, *_ = self.tangential(state, history, p, n, touching)
            forces = (self.stiffness * p)[:, None] * n + friction
        self._last_forces = (x, history, state.load_factor, self.stiffness, forces)
        return forces

    def _total(self, state: State, history: FrictionHistory | None) -> np.ndarray:
        """(3,) the sum of the rows of ``contact_forces`` (``row_sums``' numbers), kept with
        the forces it was summed from: the step's moving tools' work asks for it twice on a
        checked step, the history's tool forces once more."""
        forces = self._read_forces(state, history)
        kept = getattr(self, "_last_total", None)  # (absent from a block pickled without it)
        if kept is None or kept[0] is not forces:
            kept = (forces, row_sums(forces))
            self._last_total = kept
        return kept[1]

    def _read_forces(self, state: State, history: Any) -> np.ndarray:
        """``contact_forces`` for reading: the kept array where this class's own forces are
        the block's (a subclass that adds to them, elements/contact_damping.py, is asked)."""
        if type(self).contact_forces is ContactBlock.contact_forces:
            return self._kept_forces(state, history)
        return self.contact_forces(state, history)

    def tool_forces(self, state: State, history: FrictionHistory | None = None) -> np.ndarray:
        """(1, 3) the total force the body exerts on the tool, N."""
        return -self._total(state, history)[None, :]

    # ------------------------------------------------------------------ protocol
    def internal_force(self, state: State, history: Any = None):
        force = self.contact_forces(state, history)[:, None, :]
        if self.tool_node is not None:  # the reaction on the tool's node
            force = np.concatenate([force, -force], axis=1)
        return self.scatter.vectors(-force), None

    def add_internal_force(self, state: State, history: Any, force, moment) -> None:
        """``internal_force`` added into ``force`` (n, 3) in place, the same numbers, in one
        compiled pass over the nodes (elements/node_rows.py; a node listed twice: the sum
        of the arrays)."""
        if not getattr(self, "_distinct", False):  # (absent from a block pickled without it)
            return super().add_internal_force(state, history, force, moment)
        add_node_forces(self.connectivity, self._read_forces(state, history), force)

    def tool_nodes(self) -> np.ndarray:
        """(1,) the node of the tool's free translation, -1 for a tool without one."""
        return np.array([-1 if self.tool_node is None else self.tool_node], dtype=np.int64)

    def tool_displacements(self, state: State, history: Any = None) -> np.ndarray:
        """(1, 3) the tool's translation from where it was given, mm: its prescribed motion
        and its free translation."""
        return (self.tool.offset(state.load_factor) + self.tool_translation(state))[None, :]

    def strain_energy(self, state: State, history: Any = None) -> float:
        """1/2 k p^2 and the tangential springs' 1/2 |f_t|^2 / k_t, N mm."""
        p, n, touching = self.touch(state, history)
        stick = self.stiffness * self.stick_ratio
        if (history is None or self.friction == 0.0) and np.all(stick > 0.0):
            # no friction (``tangential``'s zeros): 0 / k_t is +0 and k p^2 + 0 is k p^2 to
            # the bit; the zero arrays cost more than the rest (the explicit energy check)
            return float(0.5 * np.sum(self.stiffness * p**2))
        friction, *_ = self.tangential(state, history, p, n, touching)
        stored = self.stiffness * p**2 + np.sum(friction**2, axis=1) / stick
        return float(0.5 * np.sum(stored))

    def initial_history(self) -> FrictionHistory | None:
        """Frictionless: None. Otherwise the nodes that touch the tool where it starts are
        anchored where they are (a fabric laid on a tool sticks from the first step)."""
        if self.friction == 0.0:
            return None
        return initial_friction(self)

    def update_history(self, state: State, history: Any) -> Any:
        """The return mapping accepted (elements/contact_history.py ``accepted``): sliding
        anchors follow their nodes to the friction limit, new contacts are anchored where
        they are, lost ones forget their anchor."""
        return None if history is None else accepted(self, state, history)

    def carried_by_tool(self, state: State, history: Any, start: float, end: float):
        """The nodes touching the tool at ``state`` and the tool's prescribed translation
        from load factor ``start`` to ``end`` for each (femcore.interaction: Static's
        tool-following predictor); zero for a tool that stays or a force-driven one (its own
        node carries it)."""
        _, _, touching = self.touch(state, history)
        shift = np.zeros(3)
        if self.tool_node is None and self.tool.moves:
            shift = self.tool.offset(end) - self.tool.offset(start)
        nodes = self.connectivity[touching, 0]
        return nodes, np.tile(shift, (len(nodes), 1))

    def dissipated_energy(self, history: Any = None) -> float:
        """Energy dissipated by friction since the start, N mm."""
        return 0.0 if history is None else history.dissipated

    def tool_work(self, state: State, history: Any, start: float, end: float) -> float:
        """Work (N mm) the tool does on the nodes while it moves from its place at load
        factor ``start`` to that at ``end``, with the contact forces at ``state``."""
        if not self.tool.moves:
            return 0.0
        shift = self.tool.offset(end) - self.tool.offset(start)
        return float(self._total(state, history) @ shift)

    def tangent(self, state: State, history: Any = None):
        """d(internal force)/dx per node: normal k n n^T - k p N with N = dn/dx
        (``RigidTool.normal_gradient``: c (I - n n^T - a a^T) on a round tool, the turn about
        a facet's edge or vertex on a meshed one), and the return mapping's friction: k_t ds/dx
        in stick, -mu k s^ n^T + mu k p / |s| (I - s^ s^T) ds/dx in slip, where ds/dx = I -
        n n^T - (n . r) N - n (N r)^T, r = x - a."""
        p, n, touching = self.touch(state, history)
        x = self._positions(state)
        k = self.stiffness[:, None, None]
        nn = n[:, :, None] * n[:, None, :]
        curvature = self.tool.normal_gradient(x, n, state.load_factor)
        blocks = k * nn - k * p[:, None, None] * curvature
        _, s, stuck, sliding = self.tangential(state, history, p, n, touching)
        if stuck.any() or sliding.any():
            assert history is not None
            origin = self.tool.offset(state.load_factor)
            blocks = blocks + friction_tangent(
                self, history, x - origin, p, n, touching, curvature, s, stuck, sliding
            )
        blocks = np.where(touching[:, None, None], blocks, 0.0)
        if self.tool_node is not None:
            # The force depends on x - c: d/dc = -d/dx, and the tool's node takes the
            # reaction: [[K, -K], [-K, K]] per (node, tool node).
            pair = np.empty((len(blocks), 2, 3, 2, 3))
            pair[:, 0, :, 0, :] = pair[:, 1, :, 1, :] = blocks
            pair[:, 0, :, 1, :] = pair[:, 1, :, 0, :] = -blocks
            return [CellTangent(self.connectivity, pair)]
        return [CellTangent(self.connectivity, blocks[:, None, :, None, :])]

    def springs(self) -> tuple[np.ndarray, np.ndarray]:
        """Each node's penalty, N/mm (the friction's stick spring has the same stiffness).
        With a driven tool the springs join the nodes to the tool's node, and every spring
        pressing at once the mass-scaled stiffness has omega^2 <= max((1 + r) K, (1 + 1/r) S)
        for any r > 0, K = max k / m over the nodes and S = sum k / m_t at the tool's node
        (x^T M^-1/2 K_c M^-1/2 x = sum k (n . (x_j / sqrt(m_j) - x_t / sqrt(m_t)))^2, and
        (a + b)^2 <= (1 + r) a^2 + (1 + 1/r) b^2): k (1 + r) at a node and sum k (1 + 1/r)
        at the tool's node, with r = S / K of the masses the contact was calibrated with
        (there the bound is K + S, exact for equal k / m). Gershgorin's row sums, which this
        replaced, gave the tool's node sum k (1 + sqrt(m_t / m)) / m_t: on the hemisphere's
        holder (m_t / m ~ 1e5) 30 times omega^2 of the elements, and the step 2.3 times too
        short."""
        nodes, k = self.connectivity[:, 0], self.stiffness
        if self.tool_node is None or len(k) == 0:
            return nodes, k
        # S / K = sum k / max(k m_t / m): the masses through m / m_t (``_mass_ratio``).
        r = float(np.sum(k)) / float(np.max(k / self._mass_ratio))
        on_tool = float(np.sum(k)) * (1.0 + 1.0 / r)
        return np.append(nodes, self.tool_node), np.append(k * (1.0 + r), on_tool)

    def clearance(self, state: State, history: Any = None) -> np.ndarray:
        """femcore.interaction: each node's gap to where its spring starts, mm (0 in a frozen
        set); a driven tool moves too, so half the gap, its node the least (its spring joins
        every node's). A node that has moved less than its gap does not touch: no stiffness."""
        d, _ = self.tool.distance(self._positions(state), state.load_factor)
        gap = d - self.surface_offset(history) - self.tolerance
        if history is not None and history.active is not None:
            gap = np.where(history.active, np.minimum(gap, 0.0), gap)
        out = np.full(self.n_nodes, np.inf)
        out[self.connectivity[:, 0]] = gap if self.tool_node is None else 0.5 * gap
        if self.tool_node is not None:
            out[self.tool_node] = 0.5 * float(gap.min(initial=np.inf))
        return out

    def facet_record(self) -> FacetRecord | None:
        """femcore.interaction: the record of a meshed tool (``RigidSurface.facet_record``)
        with its facets' corners and normals; None for an analytic tool and for a smoothed
        one (its normal continuous across its edges: no crease to name)."""
        tool = self.tool
        if not isinstance(tool, RigidSurface) or tool.smooth:
            return None
        return FacetRecord(tool.facet_record(), tool.corners, tool.normals)

    def tool_facing(self, state: State, history: Any = None) -> list[np.ndarray | None]:
        """femcore.interaction: the tool's normal at each contact node's closest point, n
        towards the body (the normal force k p n pushes the node along it)."""
        if self.connectivity.shape[0] == 0:
            return [None]
        _, n = self.tool.distance(self._positions(state), state.load_factor)
        return [np.asarray(n, dtype=float)]

    def tool_penetrations(
        self, state: State, history: Any = None, share: float = 0.25
    ) -> list[dict | None]:
        """femcore.interaction: the depth of the body's contact surface (the mid-surface
        offset by h / 2) into the tool, h / 2 - d at each node, its deepest and the nodes
        past ``share`` h; the penalty springs' normal force over the pressed nodes."""
        nodes = self.connectivity[:, 0]
        if nodes.size == 0:
            return [None]
        d, _ = self.tool.distance(self._positions(state), state.load_factor)
        return [penetration_report(nodes, state.positions, d, self.offset, self.stiffness, share)]

    def node_fields(self, state: State, history: Any = None) -> dict[str, np.ndarray]:
        """contact_gap (mm, < 0 a penetration, NaN off the node set), contact_force (the normal
        force, N), contact_pressure (that force over the node's share of the area, N/mm^2;
        NaN without area), friction_force (|tangential force|, N), contact_slip (accumulated
        slip, mm)."""
        d, n = self.tool.distance(self._positions(state), state.load_factor)
        p, n, touching = self._touching(d, n, history)
        friction, *_ = self.tangential(state, history, p, n, touching)
        nodes = self.connectivity[:, 0]
        out = {}
        normal = self.stiffness * p
        area = np.where(self.area > 0, self.area, np.nan)
        values = {
            "contact_gap": d - self.offset,
            "contact_force": normal,
            "contact_pressure": normal / area,
            "friction_force": np.linalg.norm(friction, axis=1),
            "contact_slip": np.zeros(len(p)) if history is None else history.slip,
        }
        for name, value in values.items():
            full = np.full(self.n_nodes, np.nan if name == "contact_gap" else 0.0)
            full[nodes] = value
            out[name] = full
        return out
