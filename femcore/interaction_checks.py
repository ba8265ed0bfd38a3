"""Conformance kit of the interaction protocol: checks any interaction block must pass (the
project's contact with its rigid tools, a user's own tie or floor), for any test suite.

Each ``check_*`` function takes a bound block (``Interaction.bind(body)``; ``Body.bare(mesh)``
binds one without elements) and a state, and raises AssertionError with what differs and by
how much when the block breaks the protocol (ValueError when the check cannot be set up). The
kit imports no test framework.

* ``check_force_is_energy_gradient``: ``internal_force`` is dW/dx of ``strain_energy`` (a
  conservative block: no friction slip);
* ``check_tangent``: ``tangent`` (when the block has one) is the derivative of the force;
* ``check_normal_force``: a node of a node-to-tool contact at penetration p gets k p along
  the tool's normal (``placed_at_penetration`` places the nodes for a block with a rigid
  tool);
* ``check_friction``: a stuck node's tangential force is at most mu N, a sliding node's mu N;
* ``check_objectivity``: the same configuration turned (body, tool, history) gives the
  turned forces, moments and tool forces and the same energies;
* ``check_energy``: the stored energy and the dissipation are >= 0, an accepted step
  dissipates no negative energy, and ``update_history`` leaves the history it is given as it
  was;
* ``check_added_force``: ``add_internal_force`` adds what ``internal_force`` returns, bit for
  bit (how the model sums its parts);
* ``check_interaction_capabilities`` (femcore/capability_checks.py): the capabilities the
  block declares through the protocol (friction, contact sets, a soft start, a meshed tool's
  facets) are of their type and do what the solvers assume;
* ``check_interaction``: the first two and the last three at one state.

Tolerances. Derivatives are central differences with a step h (default 1e-6 of the size of
the nodes' bounding box, 1e-6 rad for rotations): their truncation error is O(h^2) relative
(1e-12), far below the default ``rtol`` of 1e-6, which leaves room for the kinks of a penalty
(a node within h of the contact surface: an error of k h); their rounding error, 8 eps |W| / h
for a force from energies and 8 eps |F| / h for a tangent from forces, is added to the
allowance. Forces compared to a closed form or to a turned copy are held to ``rtol`` = 1e-9 of
the largest force (rounding of the geometry: 1e-15 relative, times the condition of the
tool's distance).

Usage::

    from femcore.interaction_checks import check_interaction, check_objectivity

    block = MyTie([0, 1], [2, 3], stiffness=20.0).bind(Body.bare(mesh))
    check_interaction(block, jittered_state)  # gradient, tangent, energy
"""

from __future__ import annotations

import copy
import dataclasses
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
import scipy.sparse as sp

from femcore.assembly import CellTangent, SparseTangent
from femcore.capability_checks import check_interaction_capabilities
from femcore.interaction import InteractionBlock
from femcore.rotation import nodal_frames, rotate_about
from femcore.state import State

__all__ = [
    "check_added_force",
    "check_energy",
    "check_force_is_energy_gradient",
    "check_friction",
    "check_interaction",
    "check_interaction_capabilities",
    "check_normal_force",
    "check_objectivity",
    "check_tangent",
    "placed_at_penetration",
]

EPS = float(np.finfo(float).eps)
#: Default relative step of the central differences (of the nodes' size, or rad).
STEP = 1e-6
#: A direction a DOF of a node moves along: (node, "u" or "psi", unit vector (3,)).
Direction = tuple[int, str, np.ndarray]


# ---------------------------------------------------------------------- helpers
def _nodes(block: InteractionBlock) -> np.ndarray:
    return np.unique(np.asarray(block.connectivity))


def _step(block: InteractionBlock, state: State, step: float | None) -> float:
    """The translation step, mm: ``step`` or 1e-6 of the bounding box of the block's nodes."""
    if step is not None:
        return float(step)
    size = float(np.ptp(state.positions[_nodes(block)], axis=0).max(initial=0.0))
    return STEP * (size if size > 0.0 else 1.0)


def _directions(block: InteractionBlock, state: State) -> list[Direction]:
    """The DOF directions of the block's nodes: the three translations, and the rotations
    about V1 and V2 of the nodal frame where the block acts on rotations (alpha, beta) and
    the node has a director (the rotation about the director changes nothing)."""
    rotations = "alpha" in block.dofs or "beta" in block.dofs
    out: list[Direction] = []
    for node in _nodes(block):
        out.extend((int(node), "u", axis) for axis in np.eye(3))
        director = state.directors[node]
        if rotations and np.linalg.norm(director) > 0.0:
            v1, v2 = nodal_frames(director[None, :])
            out.extend([(int(node), "psi", v1[0]), (int(node), "psi", v2[0])])
    return out


def _moved(state: State, direction: Direction, amount: float) -> State:
    """A copy of ``state`` with one node translated, or its director turned, by ``amount``
    along the direction (mm or rad)."""
    node, kind, axis = direction
    if kind == "u":
        positions = state.positions.copy()
        positions[node] += amount * axis
        return dataclasses.replace(state, positions=positions)
    directors = state.directors.copy()
    directors[node] = rotate_about(directors[node][None, :], amount * axis[None, :])[0]
    return dataclasses.replace(state, directors=directors)


def _loads(block: InteractionBlock, state: State, history: Any) -> np.ndarray:
    """(n, 6) the force and the moment (zeros when the block gives None) at every node."""
    force, moment = block.internal_force(state, history)
    return np.hstack(
        [
            np.asarray(force, dtype=float),
            np.zeros_like(force) if moment is None else np.asarray(moment, dtype=float),
        ]
    )


def _along(loads: np.ndarray, direction: Direction) -> float:
    """The component of the (n, 6) loads along a direction (force or moment)."""
    node, kind, axis = direction
    return float(loads[node, :3] @ axis if kind == "u" else loads[node, 3:] @ axis)


def _matrix(parts: Sequence[Any], n_nodes: int) -> sp.csr_matrix:
    """The tangent parts summed into one (6 n, 6 n) matrix over (u, psi) of every node."""
    total = sp.csr_matrix((6 * n_nodes, 6 * n_nodes))
    for part in parts:
        if isinstance(part, SparseTangent):
            total = total + sp.csr_matrix(part.matrix)
            continue
        if not isinstance(part, CellTangent):
            raise AssertionError(
                f"tangent part {type(part).__name__}: expected a CellTangent "
                "or a SparseTangent (femcore.assembly)"
            )
        nodes, blocks = np.asarray(part.nodes), np.asarray(part.blocks, dtype=float)
        c = blocks.shape[2]
        index = 6 * nodes[:, :, None] + np.arange(c)  # (m, p, c)
        shape = blocks.shape
        rows = np.broadcast_to(index[:, :, :, None, None], shape).ravel()
        cols = np.broadcast_to(index[:, None, None, :, :], shape).ravel()
        total = total + sp.csr_matrix(
            (blocks.ravel(), (rows, cols)), shape=(6 * n_nodes, 6 * n_nodes)
        )
    return total.tocsr()


def _tool_normals(block: InteractionBlock, state: State) -> np.ndarray:
    tool = getattr(block, "tool", None)
    if tool is None or not hasattr(tool, "distance"):
        raise ValueError(
            f"{type(block).__name__} has no rigid tool (a ``tool`` with a "
            "``distance``): give ``normal``"
        )
    return np.asarray(tool.distance(state.positions[_tool_nodes(block)], state.load_factor)[1])


def _tool_nodes(block: InteractionBlock) -> np.ndarray:
    connectivity = np.asarray(block.connectivity)
    if connectivity.ndim != 2 or connectivity.shape[1] != 1:
        raise ValueError(
            f"{type(block).__name__} is not a node-to-tool block: its "
            "connectivity must have one node per row"
        )
    return connectivity[:, 0]


def _per_node(value: Any, count: int, what: str) -> np.ndarray:
    array = np.broadcast_to(np.asarray(value, dtype=float), (count,))
    if not np.all(np.isfinite(array)):
        raise ValueError(f"{what} must be finite, got {value!r}")
    return array


def _same(a: Any, b: Any) -> bool:
    """Whether two histories hold the same values (arrays, dataclasses, sequences, dicts)."""
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        return bool(np.array_equal(np.asarray(a), np.asarray(b), equal_nan=True))
    if dataclasses.is_dataclass(a) and not isinstance(a, type):
        return type(a) is type(b) and all(
            _same(getattr(a, f.name), getattr(b, f.name)) for f in dataclasses.fields(a)
        )
    if isinstance(a, (tuple, list)):
        return type(a) is type(b) and len(a) == len(b) and all(map(_same, a, b))
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(_same(a[k], b[k]) for k in a)
    return bool(a == b or (a != a and b != b))  # NaN equals NaN here


# ---------------------------------------------------------------------- the checks
def check_force_is_energy_gradient(
    block: InteractionBlock,
    state: State,
    history: Any = None,
    step: float | None = None,
    rtol: float = 1e-6,
) -> None:
    """``internal_force`` is the gradient of ``strain_energy`` at the block's nodes: for a
    conservative block (penalty springs, a tie, a contact without friction; a sliding node's
    friction force has no potential, and ``check_tangent`` checks it against its derivative).

    Parameters
    ----------
    block : InteractionBlock
    state : State
    history : the block's history (as a solver would pass it), optional
    step : float, optional
        Translation step h of the central differences, mm (default 1e-6 of the bounding box
        of the nodes); rotations (for blocks acting on alpha, beta) by 1e-6 rad.
    rtol : float
        Allowance relative to the largest force (moment) component, plus the rounding 8 eps
        |W| / h of the differences (module docstring).

    Raises
    ------
    AssertionError
        Naming the first node and direction where dW/dx and the force differ by more.
    """
    h = _step(block, state, step)
    loads = _loads(block, state, history)
    rows = []
    for direction in _directions(block, state):
        amount = h if direction[1] == "u" else STEP
        plus = block.strain_energy(_moved(state, direction, amount), history)
        minus = block.strain_energy(_moved(state, direction, -amount), history)
        numeric = (plus - minus) / (2.0 * amount)
        rounding = 8.0 * EPS * max(abs(plus), abs(minus)) / amount
        rows.append((direction, _along(loads, direction), numeric, rounding))
    for kind in ("u", "psi"):
        of_kind = [r for r in rows if r[0][1] == kind]
        if not of_kind:
            continue
        scale = max(max(abs(r[1]), abs(r[2])) for r in of_kind)
        for (node, _, axis), own, numeric, rounding in of_kind:
            if abs(own - numeric) > rtol * scale + rounding:
                what = "force" if kind == "u" else "moment"
                raise AssertionError(
                    f"{type(block).__name__}: at node {node} along {axis.round(6).tolist()} "
                    f"the {what} is {own:.10g} but dW/d{kind} is {numeric:.10g} (central "
                    f"differences): off by {abs(own - numeric):.3g}, allowed "
                    f"{rtol * scale + rounding:.3g} ({rtol:g} of the largest, {scale:.3g})"
                )


def check_tangent(
    block: InteractionBlock,
    state: State,
    history: Any = None,
    step: float | None = None,
    rtol: float = 1e-6,
) -> bool:
    """The block's own ``tangent`` is the derivative of its ``internal_force``: each column
    (a translation of a node, or a rotation of its director about V1 or V2) against central
    differences of the forces and moments of every node.

    Parameters
    ----------
    block, state, history, step
        As ``check_force_is_energy_gradient``.
    rtol : float
        Allowance relative to the largest tangent entry of the compared columns (N/mm), plus
        the rounding 8 eps |F| / h of the differences.

    Returns
    -------
    bool
        True when the tangent was checked, False when the block has none (``tangent``
        returns None: the solvers difference its forces).

    Raises
    ------
    AssertionError
        Naming the column and the node where the tangent and the differences differ.
    """
    parts = block.tangent(state, history)
    if parts is None:
        return False
    n = state.n_nodes
    matrix = _matrix(parts, n)
    h = _step(block, state, step)
    directions = _directions(block, state)
    # each direction as a row of the (n, 6) loads: its node, its three columns (the force's
    # or the moment's) and its axis, to take every row's component at once
    nodes = np.array([node for node, _, _ in directions])
    load_columns = np.array([[0, 1, 2] if kind == "u" else [3, 4, 5] for _, kind, _ in directions])
    axes = np.array([axis for _, _, axis in directions])

    def along_rows(loads: np.ndarray) -> np.ndarray:
        return np.sum(loads[nodes[:, None], load_columns] * axes, axis=1)

    columns = []
    for direction in directions:
        node, kind, axis = direction
        amount = h if kind == "u" else STEP
        plus = _loads(block, _moved(state, direction, amount), history)
        minus = _loads(block, _moved(state, direction, -amount), history)
        numeric = (plus - minus) / (2.0 * amount)
        offset = 6 * node + (0 if kind == "u" else 3)
        own = (matrix[:, offset : offset + 3] @ axis).reshape(n, 6)
        rounding = 8.0 * EPS * max(np.abs(plus).max(), np.abs(minus).max()) / amount
        columns.append((direction, own, numeric, rounding))
    scale = max(max(np.abs(c[1]).max(), np.abs(c[2]).max()) for c in columns)
    for (node, kind, axis), own, numeric, rounding in columns:
        # Moments are compared across the directors (their component along it is no DOF).
        ours, theirs = along_rows(own), along_rows(numeric)
        errors = np.abs(ours - theirs)
        wrong = np.flatnonzero(errors > rtol * scale + rounding)
        if len(wrong):
            first = wrong[0]
            row = directions[first]
            raise AssertionError(
                f"{type(block).__name__}: d(load at node {row[0]} along "
                f"{row[2].round(6).tolist()})/d({kind} of node {node} along "
                f"{axis.round(6).tolist()}) is {ours[first]:.10g} in the tangent but "
                f"{theirs[first]:.10g} by central differences: off by {errors[first]:.3g}, "
                f"allowed {rtol * scale + rounding:.3g} ({rtol:g} of the largest entry, "
                f"{scale:.3g})"
            )
    return True


def placed_at_penetration(block: InteractionBlock, state: State) -> Callable[[float], State]:
    """For a block with a rigid ``tool`` (``tool.distance``) and an ``offset`` per node (the
    contact surface's distance from the nodes, mm; elements.contact.ContactBlock): a function
    ``place(p) -> State`` moving each node of ``state`` along the tool's normal there until it
    penetrates by p (mm; p < 0: apart by -p). Exact for a plane, a sphere and a cylinder
    (the distance changes as the node moves along the normal) and, inside a facet, for a
    meshed tool."""
    nodes = _tool_nodes(block)
    tool = getattr(block, "tool", None)
    offset = getattr(block, "offset", None)
    if tool is None or offset is None:
        raise ValueError(
            f"{type(block).__name__} has no ``tool`` and ``offset``: write the "
            "place(p) function for it"
        )
    x = state.positions[nodes]
    d, normal = tool.distance(x, state.load_factor)
    offset = _per_node(offset, len(nodes), "offset")

    def place(p: float) -> State:
        positions = state.positions.copy()
        positions[nodes] = x + ((offset - p) - d)[:, None] * normal
        return dataclasses.replace(state, positions=positions)

    return place


def check_normal_force(
    block: InteractionBlock,
    place: Callable[[float], State],
    penetrations: Sequence[float] = (-0.01, 0.0, 0.001, 0.01, 0.1),
    stiffness: Any = None,
    normal: Callable[[State], np.ndarray] | None = None,
    history: Any = None,
    rtol: float = 1e-9,
) -> None:
    """A node-to-tool block (one node per row of ``connectivity``) pushes each node placed at
    penetration p by k max(p, 0) along the tool's normal, with no tangential part; and, with
    one tool, the force on the tool is the opposite of the forces on the nodes.

    Parameters
    ----------
    block : InteractionBlock
    place : callable
        ``place(p) -> State`` with every node of the block at penetration p, mm (p <= 0:
        apart; ``placed_at_penetration`` for a block with a rigid tool).
    penetrations : sequence of float
        The values of p tried, mm.
    stiffness : float or (s,) float, optional
        k per node, N/mm (default: ``block.stiffness``).
    normal : callable, optional
        ``normal(state) -> (s, 3)`` the unit normals of the tool at the nodes, towards the
        body (default: from ``block.tool.distance``).
    history : optional
        The history passed to the block (None: frictionless, no anchor).
    rtol : float
        Allowance relative to k max|p| (module docstring).

    Raises
    ------
    AssertionError
        Naming the penetration and the node whose force is off.
    """
    nodes = _tool_nodes(block)
    given = getattr(block, "stiffness", None) if stiffness is None else stiffness
    if given is None:
        raise ValueError(f"{type(block).__name__} has no ``stiffness``: give it")
    k = _per_node(given, len(nodes), "stiffness")
    normals = normal or (lambda s: _tool_normals(block, s))
    allowed = rtol * float(k.max(initial=0.0)) * max(abs(float(p)) for p in penetrations)
    for p in penetrations:
        state = place(float(p))
        force, _ = block.internal_force(state, history)
        on_nodes = -np.asarray(force)[nodes]  # what the tool exerts on them
        n = np.asarray(normals(state))
        along = np.sum(on_nodes * n, axis=1)
        across = np.linalg.norm(on_nodes - along[:, None] * n, axis=1)
        expected = k * max(float(p), 0.0)
        worst = int(np.argmax(np.abs(along - expected) + across))
        if abs(along[worst] - expected[worst]) + across[worst] > allowed + EPS * expected.max():
            raise AssertionError(
                f"{type(block).__name__}: node {nodes[worst]} at penetration {p:g} gets "
                f"{along[worst]:.10g} along the normal and {across[worst]:.3g} across it; "
                f"expected k p = {expected[worst]:.10g} and 0 (allowed {allowed:.3g})"
            )
        if block.n_tools == 1:
            on_tool = np.asarray(block.tool_forces(state, history)).reshape(-1, 3)[0]
            if np.abs(on_tool + on_nodes.sum(axis=0)).max() > allowed * len(nodes) + EPS:
                raise AssertionError(
                    f"{type(block).__name__}: at penetration {p:g} the force on the tool "
                    f"{on_tool.tolist()} is not the opposite of the sum on the nodes "
                    f"{on_nodes.sum(axis=0).tolist()}"
                )


def check_friction(
    block: InteractionBlock,
    state: State,
    history: Any,
    friction: float | None = None,
    stuck: np.ndarray | None = None,
    sliding: np.ndarray | None = None,
    normal: Callable[[State], np.ndarray] | None = None,
    rtol: float = 1e-9,
    nodes: np.ndarray | None = None,
) -> None:
    """Coulomb's law at the nodes of a node-to-tool block: no node pulled towards the tool
    (N >= 0), the tangential force T of a stuck node at most mu N, that of a sliding node
    mu N; or at given ``nodes`` of any block whose force at each of them comes from one
    contact (a surface-to-surface block whose contact points do not share nodes).

    Parameters
    ----------
    block : InteractionBlock
    state : State
    history : the block's friction history (anchors)
    friction : float, optional
        mu (default: ``block.friction``).
    stuck, sliding : (s,) bool, optional
        Which nodes stick and which slide (default: from the block's ``touch`` and
        ``tangential``, as elements.contact.ContactBlock has them).
    normal : callable, optional
        As ``check_normal_force``.
    rtol : float
        Allowance relative to the largest mu N (module docstring).
    nodes : (s,) int, optional
        The nodes the law is checked at (default: the node-to-tool block's, one per row of
        its connectivity); then give stuck, sliding and normal, one per node.

    Raises
    ------
    AssertionError
        Naming the node that breaks the law; ValueError when no node sticks or slides (the
        check would check nothing).
    """
    if nodes is None:
        nodes = _tool_nodes(block)
    elif stuck is None or sliding is None or normal is None:
        raise ValueError("check_friction at given nodes needs stuck, sliding and normal")
    nodes = np.asarray(nodes, dtype=np.int64)
    mu = float(block.friction if friction is None else friction)
    if stuck is None or sliding is None:
        touch, tangential = getattr(block, "touch", None), getattr(block, "tangential", None)
        if touch is None or tangential is None:
            raise ValueError(
                f"{type(block).__name__} has no touch / tangential: give stuck and sliding"
            )
        p, n, touching = touch(state)
        _, _, own_stuck, own_sliding = tangential(state, history, p, n, touching)
        stuck = own_stuck if stuck is None else stuck
        sliding = own_sliding if sliding is None else sliding
    stuck, sliding = np.asarray(stuck, dtype=bool), np.asarray(sliding, dtype=bool)
    if not (stuck.any() or sliding.any()):
        raise ValueError("no node sticks or slides: the friction check would check nothing")
    force, _ = block.internal_force(state, history)
    on_nodes = -np.asarray(force)[nodes]
    n = np.asarray((normal or (lambda s: _tool_normals(block, s)))(state))
    pressing = np.sum(on_nodes * n, axis=1)
    tangential_force = np.linalg.norm(on_nodes - pressing[:, None] * n, axis=1)
    limit = mu * pressing
    allowed = rtol * max(float(np.abs(limit).max(initial=0.0)), EPS)
    for name, bad in (
        ("pulled towards the tool (N < 0)", pressing < -allowed),
        (
            "stuck beyond the friction limit (T > mu N)",
            stuck & (tangential_force > limit + allowed),
        ),
        (
            "sliding off the friction limit (T != mu N)",
            sliding & (np.abs(tangential_force - limit) > allowed),
        ),
    ):
        if bad.any():
            i = int(np.flatnonzero(bad)[0])
            raise AssertionError(
                f"{type(block).__name__}: node {nodes[i]} is {name}: N = {pressing[i]:.10g}, "
                f"T = {tangential_force[i]:.10g}, mu N = {limit[i]:.10g} (allowed {allowed:.3g})"
            )


def check_objectivity(
    build: Callable[[np.ndarray], tuple[InteractionBlock, State, Any]],
    rotation: np.ndarray,
    rtol: float = 1e-9,
) -> None:
    """Turning the body, its tool and its history by a rotation R turns the forces, the
    moments and the tool forces by R and leaves the energy and the dissipation of an accepted
    step unchanged.

    Parameters
    ----------
    build : callable
        ``build(R) -> (block, state, history)``: the same configuration with every position,
        director, tool and history vector turned by the (3, 3) rotation R (``build(I)`` the
        unturned one).
    rotation : (3, 3) float
        A proper rotation.
    rtol : float
        Allowance relative to the largest force (moment, energy) (module docstring).

    Raises
    ------
    AssertionError
        Naming the quantity that does not turn; ValueError for a matrix that is not a
        rotation.
    """
    rotation = np.asarray(rotation, dtype=float)
    if (
        rotation.shape != (3, 3)
        or not np.allclose(rotation @ rotation.T, np.eye(3), atol=1e-12)
        or np.linalg.det(rotation) < 0
    ):
        raise ValueError(f"rotation must be a proper (3, 3) rotation matrix, got {rotation!r}")
    quantities = []
    for turn in (np.eye(3), rotation):
        block, state, history = build(turn)
        loads = _loads(block, state, history)
        tools = np.asarray(block.tool_forces(state, history), dtype=float).reshape(-1, 3)
        after = block.update_history(state, history)
        energies = (block.strain_energy(state, history), block.dissipated_energy(after))
        quantities.append((type(block).__name__, loads, tools, energies))
    name, loads, tools, energies = quantities[0]
    _, turned_loads, turned_tools, turned_energies = quantities[1]
    pairs = (
        ("forces", loads[:, :3] @ rotation.T, turned_loads[:, :3]),
        ("moments", loads[:, 3:] @ rotation.T, turned_loads[:, 3:]),
        ("tool forces", tools @ rotation.T, turned_tools),
        ("stored and dissipated energy", np.asarray(energies), np.asarray(turned_energies)),
    )
    for what, expected, actual in pairs:
        if expected.shape != actual.shape:
            raise AssertionError(
                f"{name}: the turned configuration has {what} of shape "
                f"{actual.shape}, the unturned {expected.shape}"
            )
        scale = max(float(np.abs(expected).max(initial=0.0)), EPS)
        error = float(np.abs(actual - expected).max(initial=0.0))
        if error > rtol * scale:
            raise AssertionError(
                f"{name}: the {what} of the turned configuration are not R times the unturned "
                f"ones: off by {error:.3g} ({error / scale:.3g} of the largest, allowed {rtol:g})"
            )


def check_energy(block: InteractionBlock, state: State, history: Any = None) -> None:
    """The stored energy is finite and >= 0; the dissipation is >= 0 and an accepted step at
    ``state`` (``update_history``) does not lower it; ``update_history`` returns a new history
    and leaves the one it is given as it was.

    Raises
    ------
    AssertionError
        Naming the quantity at fault.
    """
    name = type(block).__name__
    stored = block.strain_energy(state, history)
    if not (np.isfinite(stored) and stored >= 0.0):
        raise AssertionError(f"{name}: the stored energy is {stored!r}: expected finite, >= 0")
    kept = copy.deepcopy(history)
    before = block.dissipated_energy(history)
    after = block.dissipated_energy(block.update_history(state, history))
    if not _same(history, kept):
        raise AssertionError(
            f"{name}.update_history changed the history it was given: it "
            "must return a new one (solvers keep the old for a retry)"
        )
    if not (np.isfinite(before) and before >= 0.0):
        raise AssertionError(f"{name}: the dissipated energy is {before!r}: expected >= 0")
    if not (np.isfinite(after) and after >= before):
        raise AssertionError(
            f"{name}: an accepted step took the dissipated energy from "
            f"{before!r} to {after!r}: it never decreases"
        )


def check_added_force(block: InteractionBlock, state: State, history: Any = None) -> None:
    """``add_internal_force`` into sums that start from zero gives what ``internal_force``
    returns, to the last bit (the model sums its parts so: femcore.compiled), and leaves
    the moments as they were where the block gives none.

    Raises
    ------
    AssertionError
        Naming the first node whose sum differs.
    """
    name = type(block).__name__
    force, moment = block.internal_force(state, history)
    n = len(state.positions)
    added_force, added_moment = np.zeros((n, 3)), np.zeros((n, 3))
    block.add_internal_force(state, history, added_force, added_moment)
    expected_moment = np.zeros((n, 3)) if moment is None else 0.0 + np.asarray(moment)
    for what, added, expected in (
        ("force", added_force, 0.0 + np.asarray(force, dtype=float)),
        ("moment", added_moment, expected_moment),
    ):
        differ = np.flatnonzero((added != expected).any(axis=1))
        if differ.size:
            node = int(differ[0])
            raise AssertionError(
                f"{name}.add_internal_force added the {what} {added[node]} at node {node} where "
                f"internal_force gives {expected[node]}: the same sums expected"
            )


def check_interaction(
    block: InteractionBlock,
    state: State,
    history: Any = None,
    step: float | None = None,
    rtol: float = 1e-6,
) -> None:
    """``check_force_is_energy_gradient``, ``check_tangent``, ``check_energy``,
    ``check_added_force`` and ``check_interaction_capabilities`` at one state (the checks
    that need no tool, no rotation and no placement)."""
    check_force_is_energy_gradient(block, state, history, step, rtol)
    check_tangent(block, state, history, step, rtol)
    check_energy(block, state, history)
    check_added_force(block, state, history)
    check_interaction_capabilities(block, state, history)
