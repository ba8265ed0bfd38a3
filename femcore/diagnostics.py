"""Diagnostics of a compiled model before it is solved: the rigid motions its supports leave
free (a mechanism the quasi-static solvers cannot equilibrate), checked on each connected part
of the body (femcore.connected_parts): a strip that no element joins to a clamped one is a
free body of its own, whatever holds the other."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from femcore.connected_parts import body_nodes, connected_parts, described_part

if TYPE_CHECKING:
    from femcore.compiled import CompiledModel

__all__ = [
    "RIGID_MOTIONS",
    "USER_LEVELS",
    "interaction_notes",
    "unbalanced_translations",
    "unbalanced_turns",
    "unheld_rigid_motions",
]

#: Names of the six elementary rigid motions (rotations about axes through the centroid).
RIGID_MOTIONS: tuple[str, ...] = (
    "translation along x",
    "translation along y",
    "translation along z",
    "rotation about x",
    "rotation about y",
    "rotation about z",
)


#: How many parts with free motions a message names before it counts the rest.
LISTED_PARTS = 5


@dataclass(frozen=True)
class _Body:
    """The model's body, or one connected part of it, restricted to its k nodes (the
    arrays of the checks, so that a model of many parts costs its node count, not the square
    of it).

    nodes (k,) int: the nodes' ids. x (k, 3): their reference positions, mm. has_rotation,
    active (k, 5) and constrained (k, 5): as the model's. frames: (V1, V2) (k, 3) each, the
    director frames of the DOFs alpha and beta. contact: (local rows (c,), unit directions (c,
    3)) the interactions hold, or None where one does not say. levels: the dead loads (forces
    (k, 3) N, moments (k, 3) N mm) at the load factors checked. tool_forces: (levels, t, 3)
    the forces on the force-driven tools' own nodes, N (they push the body through contact).
    """

    nodes: np.ndarray
    x: np.ndarray
    has_rotation: np.ndarray
    active: np.ndarray
    constrained: np.ndarray
    frames: tuple[np.ndarray, np.ndarray]
    contact: tuple[np.ndarray, np.ndarray] | None
    levels: list[tuple[np.ndarray, np.ndarray]]
    tool_forces: list[np.ndarray]


def _bodies(model: CompiledModel) -> tuple[list[_Body], list[np.ndarray] | None]:
    """The body as one ``_Body`` when it is in one piece, else one per connected part with
    the parts' node ids, largest first."""
    parts = connected_parts(model)
    whole = len(parts) <= 1
    dofs = model.dofs
    x = model.reference_positions
    frames = dofs.frames(model.reference_directors)
    v1, v2 = frames if frames is not None else (x, x)
    levels = _load_levels(model)
    contact = _interaction_rows(model)
    groups = [np.flatnonzero(body_nodes(model))] if whole else parts
    # each node's part and its row in it (-1 off the body), to share out the contact rows
    label = np.full(model.n_nodes, -1, dtype=np.int64)
    local = np.full(model.n_nodes, -1, dtype=np.int64)
    for index, nodes in enumerate(groups):
        label[nodes], local[nodes] = index, np.arange(len(nodes))
    rows: list[tuple[np.ndarray, np.ndarray] | None] = [None] * len(groups)
    if contact is not None:
        owner = label[contact[0]]
        order = np.argsort(owner, kind="stable")
        bounds = np.searchsorted(owner[order], np.arange(len(groups) + 1))
        for index in range(len(groups)):
            taken = order[bounds[index] : bounds[index + 1]]
            rows[index] = (local[contact[0][taken]], contact[1][taken])
    on_tools = [force[model.rigid_nodes] for force, _ in levels]
    views = [
        _Body(
            nodes=nodes,
            x=x[nodes],
            has_rotation=model.has_rotation[nodes],
            active=dofs.active[nodes],
            constrained=dofs.constrained[nodes],
            frames=(v1[nodes], v2[nodes]),
            contact=held,
            levels=[(force[nodes], moment[nodes]) for force, moment in levels],
            tool_forces=on_tools,
        )
        for nodes, held in zip(groups, rows)
    ]
    return views, None if whole else parts


def _per_part(model: CompiledModel, check: Callable[[_Body], list[str]]) -> list[str]:
    """``check`` on the whole body when it is in one piece; on each connected part otherwise,
    each part's findings joined and named after the part ("translation along z of the part of
    15 nodes ...")."""
    bodies, parts = _bodies(model)
    if parts is None:
        return check(bodies[0])
    found = []
    for body, part in zip(bodies, parts):
        motions = check(body)
        if motions:
            found.append(f"{', '.join(motions)} of {described_part(part, len(parts))}")
    if len(found) > LISTED_PARTS:  # a mesh of unmerged facets: the first few say it
        more = len(found) - LISTED_PARTS
        found = found[:LISTED_PARTS] + [f"and {more} more part{'s' if more > 1 else ''} so"]
    return found


def _rigid_basis(body: _Body):
    """The six rigid motions of ``body`` and those its supports leave free: (motions (6, k,
    6), generalised (6, k, 5), held (rows, 6), free_motions (f, 6): each a translation and a
    rotation vector about ``centre``, scale (6,), centre (3,)); None where an interaction does
    not say what it holds."""
    if body.contact is None:
        return None
    x = body.x
    # (A rigid tool's own node, a force-driven tool, is another body: not among the nodes.)
    centre = x.mean(axis=0) if len(x) else np.zeros(3)
    axes = np.eye(3)
    # (6 motions, k, 6): u then psi per node.
    motions = np.zeros((6, len(x), 6))
    motions[:3, :, :3] = axes[:, None, :]
    motions[3:, :, :3] = np.cross(axes[:, None, :], (x - centre)[None])
    motions[3:, :, 3:] = np.where(body.has_rotation[None, :, None], axes[:, None, :], 0.0)
    v1, v2 = body.frames
    # Generalised components (u, alpha = psi . V2, beta = psi . V1) as the DOF masks.
    generalised = np.concatenate(
        [
            motions[..., :3],
            np.sum(motions[..., 3:] * v2, axis=-1)[..., None],
            np.sum(motions[..., 3:] * v1, axis=-1)[..., None],
        ],
        axis=-1,
    )
    held = generalised[:, body.constrained].T  # (constrained DOFs, 6)
    nodes, directions = body.contact
    if len(nodes):  # n . u of each rigid motion at the held nodes
        along = np.einsum("knj,nj->nk", motions[:, nodes, :3], directions)
        held = np.concatenate([held, along])
    length = max(float(np.ptp(x, axis=0).max(initial=0.0)) if len(x) else 0.0, 1e-300)
    scale = np.array([1.0, 1.0, 1.0, length, length, length])  # rotations as translations
    held = held / scale
    if held.size:
        _, singular, vt = _right_singular(held)
        rank = int(np.sum(singular > 1e-9 * max(float(singular.max(initial=0.0)), 1.0)))
        free_motions = vt[rank:] / scale  # (f, 6): q = z / scale for held z = 0
    else:
        free_motions = np.eye(6)
    return motions, generalised, held, free_motions, scale, centre


def unheld_rigid_motions(model: CompiledModel, loaded_only: bool = True) -> list[str]:
    """The rigid motions that no support holds and the full dead loads would push: an
    equilibrium the quasi-static solvers cannot find (a mechanism). With
    ``loaded_only=False``, every rigid motion no support holds, loaded or not (what makes a
    tangent stiffness singular).

    The six rigid motions (translations along x, y, z; rotations about the axes through
    the centroid, directors turning with the body) restricted to the fixed and
    prescribed DOFs span what the supports hold; a motion in the rest does work with
    the loads (forces and moments at load factor 1, and at USER_LEVELS too where some have a
    user amplitude, which may vanish at 1) unless they are self-balanced along it. An
    interaction holds what its ``held_directions`` state (a frictionless tool: the motion
    along its normal at the contact nodes, so that a translation along a plane or a turn
    about a cylinder's axis stays free); a model with an interaction that does not say is not
    checked.

    A body in several connected parts (femcore.connected_parts) is checked part by part,
    each part's motions named after it.

    Returns
    -------
    list of str
        The elementary motions (e.g. "translation along z") along which the loads do work
        with nothing holding the model, or a description of the combined motion; empty
        when every loaded rigid motion is held. For a body in parts, one entry per part with
        unheld motions: its motions "of the part of 15 nodes 15, 16, ..., 29 (...)".
    """
    return _per_part(model, lambda body: _unheld(body, loaded_only))


def _unheld(body: _Body, loaded_only: bool) -> list[str]:
    """unheld_rigid_motions of one body (the whole, or a part)."""
    basis = _rigid_basis(body)
    if basis is None:
        return []
    motions, generalised, held, free_motions, scale, centre = basis
    length = scale[3]
    if not loaded_only:
        # Only the motions that move some free DOF count: a cable turning about its own
        # line, or any body about an axis through all its nodes, moves nothing.
        moving = generalised[:, body.active].T  # (active DOFs, 6)
        if len(free_motions) and moving.size:
            _, moved, turns = np.linalg.svd(moving @ free_motions.T, full_matrices=False)
            free_motions = turns[moved > 1e-9 * max(float(moved.max()), 1.0)] @ free_motions
    if not len(free_motions):
        return []
    if not loaded_only:
        moves = np.abs(moving).max(axis=0, initial=0.0) > 0.0
        column_free = (np.abs(held).max(axis=0, initial=0.0) == 0.0) & moves
        named = [name for name, free in zip(RIGID_MOTIONS, column_free) if free]
        # The free motions that are no elementary one (a turn about a cylinder's axis that
        # does not pass through the centroid): the free space less the elementary axes.
        scaled = free_motions * scale
        scaled = scaled - scaled[:, column_free] @ np.eye(6)[column_free]
        rest, weights, _ = np.linalg.svd(scaled.T, full_matrices=False)
        others = rest[:, weights > 1e-6].T / scale  # (the rows of free_motions are unit)
        return named + [_described(q, centre) for q in others]
    for force, moment in body.levels:
        load = np.concatenate([force, moment], axis=1)
        work = np.einsum("kc,cnj,nj->k", free_motions, motions, load)
        size = max(float(np.linalg.norm(force)) * length + float(np.linalg.norm(moment)), 1e-300)
        pushed = free_motions[np.abs(work) > 1e-9 * size]
        if len(pushed):
            break
    else:
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
        + ", ".join(name for name, weight in zip(names, np.abs(pushed[0] * scale)) if weight > 1e-6)
    ]


def unbalanced_translations(model: CompiledModel) -> list[str]:
    """The rigid translations no support holds along which the full dead loads have a net
    force: no equilibrium exists at any shape, since a dead load's resultant does not turn
    with the body (a free body under its weight). A model whose loaded free motions are
    rotations only (a strip held at a pin-like edge, a cable pinned at one end) is a mechanism
    at its starting shape but may hang in equilibrium a finite motion away.

    Returns
    -------
    list of str
        The direction of the net force's part along the free translations ("translation
        along z", or "translation along (0.6, 0, 0.8)"); empty when there is none (or an
        interaction does not say what it holds, as for ``unheld_rigid_motions``). Part by
        part for a body in parts, as ``unheld_rigid_motions``.
    """
    return _per_part(model, _unbalanced_translations)


def _unbalanced_translations(body: _Body) -> list[str]:
    if body.contact is None:
        return []
    held_columns = body.constrained[:, :3].any(axis=0)
    rows = [np.eye(3)[held_columns], body.contact[1]]
    held = np.concatenate(rows) if any(len(r) for r in rows) else np.zeros((0, 3))
    if len(held):
        _, singular, vt = _right_singular(held)
        rank = int(np.sum(singular > 1e-9 * max(float(singular.max(initial=0.0)), 1.0)))
        free = vt[rank:]
    else:
        free = np.eye(3)
    for force, _ in body.levels:
        along = free.T @ (free @ force.sum(axis=0))
        magnitude = float(np.abs(force).sum())
        if float(np.linalg.norm(along)) > 1e-9 * max(magnitude, 1e-300):
            break
    else:
        return []
    axes = np.flatnonzero(np.abs(along) > 1e-9 * float(np.abs(along).max()))
    if len(axes) == 1:
        return [RIGID_MOTIONS[int(axes[0])]]
    return [_described(np.concatenate([along, np.zeros(3)]), np.zeros(3))]


def unbalanced_turns(model: CompiledModel) -> list[str]:
    """The free rotations along which dead nodal moments turn the model with no force able to
    turn it back: no equilibrium exists at any shape. A dead force's moment about an axis of
    direction w is (r x F) . w = r . (F x w), nothing at any shape r where F is along w; a dead
    moment's is M . w at every shape. So where every force is along w (or none acts) and the
    moments have a part along w, nothing balances them however the body turns (a strip on a
    hinge under a moment about the hinge). Forces across w may balance a moment a finite turn
    away (a pendulum): not counted here.

    Returns
    -------
    list of str
        The directions w ("rotation about y", or "rotation about (0.6, 0, 0.8)"); empty when
        there is none, or an interaction does not say what it holds. Part by part for a body
        in parts, as ``unheld_rigid_motions``.
    """
    return _per_part(model, _unbalanced_turns)


def _unbalanced_turns(body: _Body) -> list[str]:
    basis = _rigid_basis(body)
    if basis is None or not len(basis[3]):
        return []
    free, scale = basis[3], basis[4]
    # The free motions are unit with rotations counted as translations at the model's size
    # (scale): a turn among them has a rotation part of about 1 / size.
    axes, weights, _ = np.linalg.svd(free[:, 3:].T, full_matrices=False)
    directions = axes[:, weights > 1e-6 / scale[3]].T
    found = []
    for w in directions:
        for (force, moment), on_tools in zip(body.levels, body.tool_forces):
            # Every force counts, a force-driven tool's too: it pushes the body through its
            # contact, and across w it may balance the moment a finite turn away.
            forces = np.concatenate([force, on_tools])
            across = float(np.abs(np.cross(forces, w)).sum())
            if across > 1e-9 * max(float(np.abs(forces).sum()), 1e-300):
                continue  # a force across w may turn it back a finite turn away
            about = float(moment.sum(axis=0) @ w)
            if abs(about) > 1e-9 * max(float(np.abs(moment).sum()), 1e-300):
                axis = np.flatnonzero(np.abs(w) > 1e-9)
                along = w * np.sign(w[np.argmax(np.abs(w))])
                found.append(
                    RIGID_MOTIONS[3 + int(axis[0])]
                    if len(axis) == 1
                    else "rotation about an axis along ("
                    + ", ".join(f"{v:.3g}" for v in np.where(np.abs(along) < 1e-9, 0.0, along))
                    + ")"
                )
                break
    return found


#: The load factors besides 1 at which the loads are checked when some have a user amplitude,
#: which may vanish at 1 (a load then unload).
USER_LEVELS = (0.25, 0.5, 0.75)


def _load_levels(model: CompiledModel) -> list[tuple[np.ndarray, np.ndarray]]:
    """The dead loads (forces (n, 3), moments (n, 3)) the checks look at: those at load factor
    1, and with user amplitudes those at USER_LEVELS too."""
    levels = [1.0] + (list(USER_LEVELS) if model.user_amplitudes() else [])
    return [model.external_load(level, quasi_static=True) for level in levels]


def _described(motion: np.ndarray, centre: np.ndarray) -> str:
    """A rigid motion (t (3,), omega (3,)) about ``centre`` in words: a translation along a
    direction, or a rotation about an axis (its direction and a point on it, mm)."""
    t, omega = motion[:3], motion[3:]
    turn = float(np.linalg.norm(omega))

    def written(vector: np.ndarray) -> str:
        return ", ".join(f"{v:.3g}" for v in np.where(np.abs(vector) < 1e-9, 0.0, vector))

    def unit(vector: np.ndarray) -> np.ndarray:
        vector = vector / np.linalg.norm(vector)
        return vector * np.sign(vector[np.argmax(np.abs(vector))])

    if turn < 1e-9 * float(np.linalg.norm(t)):
        return f"translation along ({written(unit(t))})"
    point = centre + np.cross(omega, t) / turn**2
    scale = max(float(np.abs(point).max()), 1.0)
    return (
        f"rotation about the axis along ({written(unit(omega))}) through "
        f"({written(np.where(np.abs(point) < 1e-9 * scale, 0.0, point))})"
    )


def _right_singular(held: np.ndarray) -> tuple[None, np.ndarray, np.ndarray]:
    """The singular values and the full set of right singular vectors (c, c) of ``held``
    (rows, c), without its left ones: the rows that hold nothing (another part's supports)
    are left out, and with at least c rows the thin decomposition already holds every right
    vector (the full one costs rows^2: 70 s for 100 parts of 9 nodes each fixed)."""
    held = held[np.abs(held).max(axis=1) > 0.0]
    columns = held.shape[1]
    if len(held) < columns:
        if not len(held):
            return None, np.zeros(0), np.eye(columns)
        _, singular, vt = np.linalg.svd(held, full_matrices=True)
    else:
        _, singular, vt = np.linalg.svd(held, full_matrices=False)
    return None, singular, vt


def _interaction_rows(model: CompiledModel) -> tuple[np.ndarray, np.ndarray] | None:
    """The nodes (k,) and unit directions (k, 3) the interactions hold against the ground,
    or None when one of them does not say (InteractionBlock.held_directions)."""
    nodes, directions = [np.zeros(0, dtype=np.int64)], [np.zeros((0, 3))]
    for block in model.interactions:
        held = block.held_directions()
        if held is None:
            return None
        nodes.append(np.asarray(held[0], dtype=np.int64).reshape(-1))
        directions.append(np.asarray(held[1], dtype=float).reshape(-1, 3))
    return np.concatenate(nodes), np.concatenate(directions)


def interaction_notes(model: CompiledModel) -> list[str]:
    """What the interactions that hold only some directions at their nodes leave free, for
    a message about unheld motions: e.g. "interaction 0 (ContactBlock, tool 1) holds each
    node only along the tool's normal (frictionless): it resists no sliding along the tool"."""
    notes = []
    tool = 1
    for index, block in enumerate(model.interactions):
        held = block.held_directions()
        count = int(block.n_tools)
        if held is not None and len(held[0]):
            _, per_node = np.unique(np.asarray(held[0]), return_counts=True)
            if per_node.max() < 3:
                which = f", tool {tool}" if count else ""
                notes.append(
                    f"interaction {index} ({type(block).__name__.removesuffix('Block')}{which}) "
                    "holds its nodes only "
                    "along the tool's normal (frictionless contact): it resists no sliding "
                    "along the tool"
                )
        tool += count
    return notes
