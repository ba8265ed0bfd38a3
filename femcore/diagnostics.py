"""Diagnostics of a compiled model before it is solved: the rigid motions its supports leave
free (a mechanism the quasi-static solvers cannot equilibrate)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from femcore.compiled import CompiledModel

__all__ = ["RIGID_MOTIONS", "unheld_rigid_motions"]

#: Names of the six elementary rigid motions (rotations about axes through the centroid).
RIGID_MOTIONS: tuple[str, ...] = (
    "translation along x",
    "translation along y",
    "translation along z",
    "rotation about x",
    "rotation about y",
    "rotation about z",
)


def unheld_rigid_motions(model: CompiledModel, loaded_only: bool = True) -> list[str]:
    """The rigid motions that no support holds and the full dead loads would push: an
    equilibrium the quasi-static solvers cannot find (a mechanism). With
    ``loaded_only=False``, every rigid motion no support holds, loaded or not (what makes a
    tangent stiffness singular).

    The six rigid motions (translations along x, y, z; rotations about the axes through
    the centroid, directors turning with the body) restricted to the fixed and
    prescribed DOFs span what the supports hold; a motion in the rest does work with
    the loads (forces and moments at load factor 1) unless they are self-balanced along
    it. Models with interactions (contact, ties) are not checked: those may hold the body.

    Returns
    -------
    list of str
        The elementary motions (e.g. "translation along z") along which the loads do work
        with nothing holding the model, or a description of the combined motion; empty
        when every loaded rigid motion is held.
    """
    if model.interactions:
        return []
    dofs = model.dofs
    x = model.reference_positions
    centre = x[dofs.active[:, 0]].mean(axis=0) if dofs.active[:, 0].any() else x.mean(0)
    axes = np.eye(3)
    # (6 motions, n, 6): u then psi per node.
    motions = np.zeros((6, model.n_nodes, 6))
    motions[:3, :, :3] = axes[:, None, :]
    motions[3:, :, :3] = np.cross(axes[:, None, :], (x - centre)[None])
    motions[3:, :, 3:] = np.where(model.has_rotation[None, :, None], axes[:, None, :], 0.0)
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
    force, moment = model.external_load(1.0, quasi_static=True)
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
        + ", ".join(name for name, weight in zip(names, np.abs(pushed[0] * scale)) if weight > 1e-6)
    ]
