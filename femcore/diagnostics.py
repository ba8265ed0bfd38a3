"""Diagnostics of a compiled model before it is solved: the rigid motions its supports leave
free (a mechanism the quasi-static solvers cannot equilibrate), checked on each connected part
of the body (femcore.connected_parts): a strip that no element joins to a clamped one is a
free body of its own, whatever holds the other."""

from __future__ import annotations

from collections.abc import Callable
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


def _per_part(model: CompiledModel, check: Callable[[np.ndarray | None], list[str]]) -> list[str]:
    """``check`` on the whole body when it is in one piece; on each connected part otherwise,
    each part's findings joined and named after the part ("translation along z of the part of
    15 nodes ...")."""
    parts = connected_parts(model)
    if len(parts) <= 1:
        return check(None)
    found = []
    for part in parts:
        motions = check(part)
        if motions:
            found.append(f"{', '.join(motions)} of {described_part(part, len(parts))}")
    return found


def _rigid_basis(model: CompiledModel, part: np.ndarray | None = None):
    """The six rigid motions of the model (of its nodes in ``part``, (n,) bool, when given)
    and those its supports leave free: (motions (6, n, 6), generalised (6, n, 5), held (rows,
    6), free_motions (k, 6): each a translation and a rotation vector about ``centre``, scale
    (6,), centre (3,)); None where an interaction does not say what it holds."""
    contact_rows = _interaction_rows(model, part)
    if contact_rows is None:
        return None
    dofs = model.dofs
    x = model.reference_positions
    # A rigid tool's own node (a force-driven tool) is another body: it does not move with
    # the model's rigid motions, and its supports and loads hold or push none of them.
    body = body_nodes(model)
    if part is not None:
        body &= part
    centre = x[body].mean(axis=0) if body.any() else x.mean(0)
    axes = np.eye(3)
    # (6 motions, n, 6): u then psi per node.
    motions = np.zeros((6, model.n_nodes, 6))
    motions[:3, :, :3] = axes[:, None, :]
    motions[3:, :, :3] = np.cross(axes[:, None, :], (x - centre)[None])
    motions[3:, :, 3:] = np.where(model.has_rotation[None, :, None], axes[:, None, :], 0.0)
    motions[:, model.rigid_nodes] = 0.0
    if part is not None:
        motions[:, ~part] = 0.0  # another part moves on its own
    frames = dofs.frames(model.reference_directors)
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
    nodes, directions = contact_rows
    if len(nodes):  # n . u of each rigid motion at the held nodes
        along = np.einsum("knj,nj->nk", motions[:, nodes, :3], directions)
        held = np.concatenate([held, along])
    length = max(float(np.ptp(x[body] if body.any() else x, axis=0).max()), 1e-300)
    scale = np.array([1.0, 1.0, 1.0, length, length, length])  # rotations as translations
    held = held / scale
    if held.size:
        _, singular, vt = np.linalg.svd(held, full_matrices=True)
        rank = int(np.sum(singular > 1e-9 * max(float(singular.max()), 1.0)))
        free_motions = vt[rank:] / scale  # (k, 6): q = z / scale for held z = 0
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
    return _per_part(model, lambda part: _unheld(model, loaded_only, part))


def _unheld(model: CompiledModel, loaded_only: bool, part: np.ndarray | None) -> list[str]:
    """unheld_rigid_motions of the body's nodes in ``part`` (all of them: None)."""
    basis = _rigid_basis(model, part)
    if basis is None:
        return []
    motions, generalised, held, free_motions, scale, centre = basis
    dofs = model.dofs
    length = scale[3]
    if not loaded_only:
        # Only the motions that move some free DOF count: a cable turning about its own
        # line, or any body about an axis through all its nodes, moves nothing.
        moving = generalised[:, dofs.active].T  # (active DOFs, 6)
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
    for force, moment in _load_levels(model):
        if part is not None:  # another part's loads push that part alone
            force, moment = (
                np.where(part[:, None], force, 0.0),
                np.where(part[:, None], moment, 0.0),
            )
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
    return _per_part(model, lambda part: _unbalanced_translations(model, part))


def _unbalanced_translations(model: CompiledModel, part: np.ndarray | None) -> list[str]:
    contact_rows = _interaction_rows(model, part)
    if contact_rows is None:
        return []
    body = body_nodes(model)
    if part is not None:
        body &= part
    held_columns = model.dofs.constrained[body, :3].any(axis=0)
    rows = [np.eye(3)[held_columns], contact_rows[1]]
    held = np.concatenate(rows) if any(len(r) for r in rows) else np.zeros((0, 3))
    if len(held):
        _, singular, vt = np.linalg.svd(held, full_matrices=True)
        rank = int(np.sum(singular > 1e-9 * max(float(singular.max()), 1.0)))
        free = vt[rank:]
    else:
        free = np.eye(3)
    for force, _ in _load_levels(model):
        along = free.T @ (free @ force[body].sum(axis=0))
        magnitude = float(np.abs(force[body]).sum())
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
    return _per_part(model, lambda part: _unbalanced_turns(model, part))


def _unbalanced_turns(model: CompiledModel, part: np.ndarray | None) -> list[str]:
    basis = _rigid_basis(model, part)
    if basis is None or not len(basis[3]):
        return []
    free, scale = basis[3], basis[4]
    # The free motions are unit with rotations counted as translations at the model's size
    # (scale): a turn among them has a rotation part of about 1 / size.
    axes, weights, _ = np.linalg.svd(free[:, 3:].T, full_matrices=False)
    directions = axes[:, weights > 1e-6 / scale[3]].T
    found = []
    for w in directions:
        for force, moment in _load_levels(model):
            # Every force on the part counts, a force-driven tool's too: it pushes the body
            # through its contact, and across w it may balance the moment a finite turn away.
            forces = force if part is None else force[part | _tool_nodes(model)]
            if part is not None:
                moment = moment[part]
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


def _tool_nodes(model: CompiledModel) -> np.ndarray:
    """(n,) bool: the force-driven tools' own nodes."""
    tools = np.zeros(model.n_nodes, dtype=bool)
    tools[model.rigid_nodes] = True
    return tools


def _interaction_rows(
    model: CompiledModel, part: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray] | None:
    """The nodes (k,) and unit directions (k, 3) the interactions hold against the ground
    (those of the nodes in ``part`` when given), or None when one of them does not say
    (InteractionBlock.held_directions)."""
    nodes, directions = [np.zeros(0, dtype=np.int64)], [np.zeros((0, 3))]
    for block in model.interactions:
        held = block.held_directions()
        if held is None:
            return None
        nodes.append(np.asarray(held[0], dtype=np.int64).reshape(-1))
        directions.append(np.asarray(held[1], dtype=float).reshape(-1, 3))
    held_nodes, held_directions = np.concatenate(nodes), np.concatenate(directions)
    if part is not None:
        kept = part[held_nodes]
        held_nodes, held_directions = held_nodes[kept], held_directions[kept]
    return held_nodes, held_directions


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
