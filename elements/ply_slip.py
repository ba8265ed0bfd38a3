"""Inter-ply slip: how far each node of an upper ply has slid over the ply below since the
start, a node field of the ply contact (elements/ply_contact.py, docs/theory.md §9.3b).

Anchor. At the reference state each upper node j has a face point q_j = x_j - a_j d_j on the
upper ply's lower face (a_j its half thickness, d_j its director); its projection on the
lower ply's upper face (the offset triangles y_k = x_k + b_k d_k) falls in one triangle T_j
at barycentric coordinates Lambda_j: the material point of the lower face that started under
the node, which moves as y_j(t) = sum_k Lambda_jk y_k(t).

Slip. The relative displacement of the two face points, r_j = (q_j(t) - q_j(0)) - (y_j(t) -
y_j(0)), less its part along the current unit normal n of T_j: s_j = (I - n n^T) r_j, the
tangential relative displacement (mm). It is zero for any rigid motion of the stack (the
faces touch at the start, q_j(0) = y_j(0), so r_j = (R - I)(q_j(0) - y_j(0)) = 0) and equals
an imposed in-plane shift of the upper ply against the lower one. Nodes whose reference
projection falls outside the lower ply (past its outline by more than ``OUTSIDE`` in
barycentric units) have no ply below: NaN.

Friction's stick anchors (elements/ply_friction.py) slide with the plies and are reset where
the contact slips; this field is measured from the start, whatever the friction did.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

__all__ = ["OUTSIDE", "SlipAnchors", "anchor", "slip_summary", "slip_vectors"]

#: Barycentric overshoot past the lower ply's outline beyond which a node has no ply below
#: (round-off of outlines laid on each other).
OUTSIDE = 1e-6
#: Lower triangles examined per node (the nearest centroids).
_CANDIDATES = 8


@dataclass(frozen=True)
class SlipAnchors:
    """Where each upper node started on the lower face (module docstring).

    nodes : (U,) int
        The upper nodes.
    offsets : (U,) float
        Their half thicknesses a_j, mm.
    triangle : (U,) int
        Row of the lower triangles holding the projection.
    weights : (U, 3) float
        Its barycentric coordinates Lambda_j.
    valid : (U,) bool
        False where the projection falls outside the lower ply.
    face : (U, 3) float
        q_j(0) - y_j(0), mm (0 for faces laid on each other).
    """

    nodes: np.ndarray
    offsets: np.ndarray
    triangle: np.ndarray
    weights: np.ndarray
    valid: np.ndarray
    face: np.ndarray


def _faces(positions, directors, nodes, offsets, cells, corner_offset):
    q = positions[nodes] - offsets[:, None] * directors[nodes]
    y = positions[cells] + corner_offset[:, :, None] * directors[cells]
    return q, y


def anchor(
    positions: np.ndarray,
    directors: np.ndarray,
    nodes: np.ndarray,
    offsets: np.ndarray,
    cells: np.ndarray,
    corner_offset: np.ndarray,
) -> SlipAnchors:
    """The reference anchors of the upper ``nodes`` on the lower triangles ``cells``.

    Parameters
    ----------
    positions, directors : (n, 3) float
        The reference positions (mm) and unit directors.
    nodes : (U,) int
        Upper nodes.
    offsets : (U,) float
        Their half thicknesses a_j, mm.
    cells : (m, 3) int
        The lower triangles (counter-clockwise about the direction towards the upper ply).
    corner_offset : (m, 3) float
        b_k at their corners, mm.

    Returns
    -------
    SlipAnchors
    """
    q, y = _faces(positions, directors, nodes, offsets, cells, corner_offset)
    k = min(_CANDIDATES, len(cells))
    near = np.asarray(cKDTree(y.mean(axis=1)).query(q, k=k)[1]).reshape(len(q), k)
    corners = y[near]  # (U, K, 3, 3)
    weights = _barycentric(corners, q[:, None, :])
    overshoot = np.maximum(0.0, -weights.min(axis=-1))
    best = np.argmin(overshoot, axis=1)
    rows = np.arange(len(q))
    chosen = weights[rows, best]
    triangle = near[rows, best]
    below = np.einsum("uk,uki->ui", chosen, y[triangle])
    return SlipAnchors(
        nodes=np.asarray(nodes),
        offsets=np.asarray(offsets, dtype=float),
        triangle=triangle,
        weights=chosen,
        valid=overshoot[rows, best] <= OUTSIDE,
        face=q - below,
    )


def _barycentric(corners: np.ndarray, point: np.ndarray) -> np.ndarray:
    """(..., 3) barycentric coordinates of the projection of ``point`` (..., 3) on the
    planes of the triangles ``corners`` (..., 3, 3)."""
    e1 = corners[..., 1, :] - corners[..., 0, :]
    e2 = corners[..., 2, :] - corners[..., 0, :]
    r = point - corners[..., 0, :]
    a11, a12, a22 = (e1 * e1).sum(-1), (e1 * e2).sum(-1), (e2 * e2).sum(-1)
    b1, b2 = (r * e1).sum(-1), (r * e2).sum(-1)
    det = a11 * a22 - a12 * a12
    l1 = (a22 * b1 - a12 * b2) / det
    l2 = (a11 * b2 - a12 * b1) / det
    return np.stack([1.0 - l1 - l2, l1, l2], axis=-1)


def slip_vectors(
    anchors: SlipAnchors,
    positions: np.ndarray,
    directors: np.ndarray,
    cells: np.ndarray,
    corner_offset: np.ndarray,
) -> np.ndarray:
    """(U, 3) the tangential relative displacements s_j of the upper nodes against the lower
    face since the start (module docstring), mm; NaN rows where no ply is below.

    Parameters
    ----------
    anchors : SlipAnchors
        From ``anchor`` at the reference state.
    positions, directors : (n, 3) float
        The current positions (mm) and unit directors.
    cells, corner_offset
        As given to ``anchor``.
    """
    q, y = _faces(positions, directors, anchors.nodes, anchors.offsets, cells, corner_offset)
    corners = y[anchors.triangle]  # (U, 3, 3)
    below = np.einsum("uk,uki->ui", anchors.weights, corners)
    relative = q - below - anchors.face
    normal = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    slip = relative - np.sum(relative * normal, axis=1)[:, None] * normal
    slip[~anchors.valid] = np.nan
    return slip


def slip_summary(slip: np.ndarray) -> dict[str, float]:
    """The largest and the root-mean-square slip over the nodes that have a ply below.

    Parameters
    ----------
    slip : (n,) float
        The ``ply_slip`` field, mm (NaN where there is no ply below: left out).

    Returns
    -------
    dict
        ``{"max_mm": ..., "rms_mm": ..., "nodes": count}``; NaN values when no node has a
        ply below.
    """
    values = np.asarray(slip, dtype=float).ravel()
    values = values[np.isfinite(values)]
    if values.size == 0:
        return {"max_mm": float("nan"), "rms_mm": float("nan"), "nodes": 0}
    return {
        "max_mm": float(np.max(np.abs(values))),
        "rms_mm": float(np.sqrt(np.mean(values**2))),
        "nodes": int(values.size),
    }
