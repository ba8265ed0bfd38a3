"""Finite rotations of directors and the nodal frames of the rotational DOFs (docs/theory.md
§1.2-1.3).

The core needs these to apply alpha/beta boundary conditions and to advance directors in every
solver; the shell elements use the same functions, so there is one definition of the frame.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from femcore import kernel_cache

__all__ = [
    "FRAME_FALLBACK",
    "cross",
    "cross_matrix",
    "drop_along",
    "frame_of",
    "nodal_frames",
    "rotate_about",
    "turned",
]

# Below this |e2 x V| the Eq. 7 frame is ill-conditioned (V within ~6 deg of +-e2): use e3.
FRAME_FALLBACK = 0.1


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a x b over the last axis (length 3), broadcasting.

    np.cross without its per-call overhead, which dominates on the small arrays of a time
    step.

    Parameters
    ----------
    a, b : numpy.ndarray, shape (..., 3)
        Vectors; the leading shapes broadcast against each other.

    Returns
    -------
    numpy.ndarray, shape (broadcast(...), 3)
        The cross products, float64, in the product of the units of a and b.
    """
    out = np.empty(np.broadcast_shapes(a.shape, b.shape))
    out[..., 0] = a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1]
    out[..., 1] = a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2]
    out[..., 2] = a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]
    return out


def rotate_about(vectors: np.ndarray, rotation: np.ndarray) -> np.ndarray:
    """Rotate unit vectors by rotation vectors (Rodrigues), both (n, 3).

    The rotation vector psi has angle |psi| and axis psi/|psi|. For psi perpendicular to V
    (the director update of docs/theory.md §1.3) this is V+ = cos|psi| V + sin|psi|/|psi| psi x V;
    the
    general form here also handles a component of psi along V. Tiny angles use the first-order
    update renormalised, which keeps |V| = 1 to rounding.

    Parameters
    ----------
    vectors : numpy.ndarray, shape (n, 3)
        Unit vectors to rotate (dimensionless).
    rotation : numpy.ndarray, shape (n, 3)
        Rotation vectors psi (rad).

    Returns
    -------
    numpy.ndarray, shape (n, 3)
        The rotated unit vectors.
    """
    if _compiled_rotate is not None and len(vectors) >= 256:
        out = np.empty((len(vectors), 3))
        _compiled_rotate(
            np.ascontiguousarray(vectors, dtype=np.float64),
            np.ascontiguousarray(rotation, dtype=np.float64),
            out,
        )
        return out
    angle = np.linalg.norm(rotation, axis=1)
    small = angle < 1e-12
    safe = np.where(small, 1.0, angle)
    axis = rotation / safe[:, None]
    cos = np.cos(angle)[:, None]
    sin = np.sin(angle)[:, None]
    along = np.sum(axis * vectors, axis=1)[:, None]
    rotated = cos * vectors + sin * cross(axis, vectors) + (1.0 - cos) * along * axis
    if small.any():
        first_order = vectors[small] + cross(rotation[small], vectors[small])
        norms = np.linalg.norm(first_order, axis=1)[:, None]
        rotated[small] = first_order / np.where(norms > 0, norms, 1.0)
    return rotated


def nodal_frames(directors: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Nodal frame (V1, V2) of unit directors V3 = V (Bai Eq. 7 with the fallback of docs/theory.md
    §1.2).

    V1 = (a x V3)/|a x V3| with a = e2, or a = e3 where |e2 x V3| < 0.1; V2 = V3 x V1.
    For V = e3 this gives V1 = e1, V2 = e2.

    Parameters
    ----------
    directors : numpy.ndarray, shape (n, 3)
        Unit directors V3 (dimensionless).

    Returns
    -------
    v1, v2 : numpy.ndarray, shape (n, 3)
        The unit vectors V1 and V2 of each nodal frame.
    """
    e2 = np.array([0.0, 1.0, 0.0])
    e3 = np.array([0.0, 0.0, 1.0])
    axis = cross(e2, directors)
    norm = np.linalg.norm(axis, axis=1)
    fallback = norm < FRAME_FALLBACK
    if fallback.any():
        axis[fallback] = cross(e3, directors[fallback])
        norm[fallback] = np.linalg.norm(axis[fallback], axis=1)
    v1 = axis / np.where(norm > 0, norm, 1.0)[:, None]
    v2 = cross(directors, v1)
    return v1, v2


def cross_matrix(v: np.ndarray) -> np.ndarray:
    """(..., 3, 3) the matrices [v]x with [v]x w = v x w, from vectors v (..., 3)."""
    out = np.zeros(v.shape[:-1] + (3, 3))
    out[..., 0, 1], out[..., 0, 2] = -v[..., 2], v[..., 1]
    out[..., 1, 0], out[..., 1, 2] = v[..., 2], -v[..., 0]
    out[..., 2, 0], out[..., 2, 1] = -v[..., 1], v[..., 0]
    return out


def drop_along(vectors: np.ndarray, directors: np.ndarray) -> np.ndarray:
    """Remove from each vector its component along the unit director: (I - V V^T) w.

    Parameters
    ----------
    vectors : numpy.ndarray, shape (n, 3)
        Vectors w (any unit).
    directors : numpy.ndarray, shape (n, 3)
        Unit directors V.

    Returns
    -------
    numpy.ndarray, shape (n, 3)
        The components of w normal to V, in the unit of w.
    """
    return vectors - np.sum(vectors * directors, axis=1)[:, None] * directors


def frame_of(vx, vy, vz):  # pragma: no cover - compiled below
    """The nodal frame (V1, V2) of ``nodal_frames`` for one unit director (vx, vy, vz): six
    scalars (V1 then V2), for compiled loops over the nodes (compiled by numba when it is
    installed)."""
    ax, ay, az = vz, 0.0, -vx  # e2 x V
    norm = np.sqrt(ax * ax + az * az)
    if norm < FRAME_FALLBACK:
        ax, ay, az = -vy, vx, 0.0  # e3 x V
        norm = np.sqrt(ax * ax + ay * ay)
    if norm <= 0.0:
        norm = 1.0
    ax, ay, az = ax / norm, ay / norm, az / norm
    return ax, ay, az, vy * az - vz * ay, vz * ax - vx * az, vx * ay - vy * ax


def turned(vx, vy, vz, px, py, pz):  # pragma: no cover - compiled below
    """The vector (vx, vy, vz) turned by the rotation vector (px, py, pz) (``rotate_about``
    for one vector, three scalars), for compiled loops over the nodes (compiled by numba when
    it is installed)."""
    angle = np.sqrt(px * px + py * py + pz * pz)
    if angle < 1e-12:
        fx = vx + (py * vz - pz * vy)
        fy = vy + (pz * vx - px * vz)
        fz = vz + (px * vy - py * vx)
        norm = np.sqrt(fx * fx + fy * fy + fz * fz)
        if norm <= 0.0:
            norm = 1.0
        return fx / norm, fy / norm, fz / norm
    ax, ay, az = px / angle, py / angle, pz / angle
    cos, sin = np.cos(angle), np.sin(angle)
    along = ax * vx + ay * vy + az * vz
    return (
        cos * vx + sin * (ay * vz - az * vy) + (1.0 - cos) * along * ax,
        cos * vy + sin * (az * vx - ax * vz) + (1.0 - cos) * along * ay,
        cos * vz + sin * (ax * vy - ay * vx) + (1.0 - cos) * along * az,
    )


def _rotate_loop(vectors, rotation, out):  # pragma: no cover - compiled below
    """rotate_about as one loop over the vectors (compiled by numba when it is installed):
    the same formulas, node by node, with no temporary arrays."""
    for i in range(vectors.shape[0]):
        out[i, 0], out[i, 1], out[i, 2] = turned(
            vectors[i, 0], vectors[i, 1], vectors[i, 2],
            rotation[i, 0], rotation[i, 1], rotation[i, 2],
        )  # fmt: skip


_compiled_rotate: Any = None
if kernel_cache.AVAILABLE:
    frame_of = kernel_cache.njit(frame_of)
    turned = kernel_cache.njit(turned)
    _compiled_rotate = kernel_cache.njit(_rotate_loop)
