"""How a ply contact's point meets the lower ply's face (elements/ply_contact.py): the penalty
law of its gap, and the facing triangle its search picks among the candidates.

Gap and energy. Each point faces the triangle of the lower face found below; its gap is the
signed distance of p to that triangle's plane, g = (p - y_1) . n, n the unit normal of the
offset triangle (towards the upper ply: the lower ply's triangles must be counter-clockwise
about the direction from the lower ply to the upper). The energy of a point is a one-sided
penalty whose stiffness ramps up over a penetration of ``smoothing`` delta (mm):

    W'' = k for g <= -delta,   k (-g / delta) for -delta < g < 0,   0 for g >= 0,

so W' = k (g + delta/2) and W = k/2 (g + delta/2)^2 + k delta^2 / 24 in penetration past
delta, W' = -k g^2 / (2 delta) and W = -k g^3 / (6 delta) on the ramp, nothing apart: W is
C2, the contact force and its stiffness are continuous at contact. Why: frictionless plies
that sag together carry almost no contact force, so the equilibrium sits at g ~ 0, where the
second derivative of the plain k/2 min(g, 0)^2 jumps from k to 0 and Newton's tangent switches
the contact on and off from one iteration to the next. Why not a softplus s(g) in k/2 s^2
(smooth on both sides): it pushes plies that merely touch apart by k delta log(2) / 2, and the
automatic penalty of a ply stack is so stiff against its weight (the 2-ply sag of
tests/test_plies.py: 0.96 N at delta = 1e-3 h/N against 2.5e-3 N of gravity per ply) that the
plies came apart by 170 delta. The price of the ramp: a pressed contact penetrates delta / 2
further than the plain penalty at the same force (F = k (|g| - delta / 2)). ``smoothing=0``
is the plain k/2 min(g, 0)^2. A point counts as touching when g < 0 (g <= 1e-9 of the mesh
size without smoothing: plies laid on each other then have the contact's stiffness from the
first iteration) and its projection is within ``MARGIN`` of the triangle.

Measured with solvers.Static (docs/theory.md §9.3a): the 4-ply sag of tests/test_plies.py
took no convergence (nodes, plain penalty), 30 iterations and a cut (centroids, plain), 24
(centroids and the ramp; 26 at 8 plies); the 4-ply bai-5.1 strip fails with the plain
penalty at nodes or centroids and with the ramp at nodes, and converges with centroids and
the ramp. The ramp has its own cost: where plies need no contact force, points near g = 0
step in and out of it and Newton converges linearly (up to ~100 iterations in an increment).

Search, refreshed at every call. A cKDTree over the current centroids of the offset
triangles gives each point ``candidates`` triangles; over them (vectorised, no loop over
points) the barycentric projection of p and the approximate distance to the triangle
sqrt(g^2 + (o sqrt(2 A))^2), o = max(0, -min lambda) the projection's overshoot past the
triangle's edges; the facing triangle is, among those that hold the projection, the one p
penetrates most (over a concave fold two do), and when none holds it (over a convex fold, or
past the ply's edge) the nearest. Rebuilding the tree costs O(m log m) per call, small against
the shells' forces at the sizes of a ply stack (measured in benchmarks/plies.py), and no cache
needs a proof that it is still valid. Within a region where the facing triangle does not
change the energy is smooth; where a point passes from one triangle to the next the plane
changes and the energy jumps by O(k g^2 phi^2), phi the angle between the two facets.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = [
    "INSIDE",
    "MARGIN",
    "Facing",
    "choose",
    "closest_facing",
    "facets",
    "penalty_law",
    "triangle_frames",
]

#: How far past a triangle's edges (in barycentric units) its plane still carries a point.
MARGIN = 0.5
#: Barycentric overshoot below which a projection counts as inside a triangle (round-off of
#: a point right above a vertex or an edge).
INSIDE = 1e-9


def penalty_law(gap: np.ndarray, stiffness: np.ndarray, smoothing: float):
    """The energy W of one contact point and its first two derivatives in the gap.

    Parameters
    ----------
    gap : (t,) float
        g, mm (< 0: penetration).
    stiffness : (t,) float
        k, N/mm.
    smoothing : float
        delta, mm: the penetration over which the stiffness ramps from 0 to k (module
        docstring); 0: W = k/2 min(g, 0)^2.

    Returns
    -------
    energy (t,) N mm, force (t,) N (dW/dg, <= 0), stiffness (t,) N/mm (d2W/dg2, >= 0).
    """
    if smoothing == 0.0:
        g = np.minimum(gap, 0.0)
        return 0.5 * stiffness * g**2, stiffness * g, np.where(gap <= 0.0, stiffness, 0.0)
    delta = smoothing
    g = np.minimum(gap, 0.0)
    deep = g <= -delta
    energy = np.where(
        deep, 0.5 * stiffness * (g + 0.5 * delta) ** 2 + stiffness * delta**2 / 24.0, 0.0
    )
    energy = np.where(deep, energy, -stiffness * g**3 / (6.0 * delta))
    force = np.where(deep, stiffness * (g + 0.5 * delta), -stiffness * g**2 / (2.0 * delta))
    curvature = np.where(deep, stiffness, -stiffness * g / delta)
    return energy, force, curvature


@dataclass(frozen=True)
class Facing:
    """Each contact point's facing triangle at a state (``PlyContactBlock.facing``).

    triangle : (P,) int
        Row of the block's lower triangles facing each point.
    gap : (P,) float
        g, mm: signed distance of the point from the facing offset triangle's plane (< 0:
        penetration).
    normal : (P, 3) float
        Unit normal n of the facing offset triangle (towards the upper ply).
    weights : (P, 3) float
        Barycentric coordinates lambda of the projection of the point.
    gradients : (P, 3, 3) float
        In-plane gradients of the triangle's barycentric functions, 1/mm (row k: grad phi_k).
    touching : (P,) bool
        g < 0 (g <= 1e-9 of the mesh's size with no smoothing) and the projection within
        ``MARGIN`` of the triangle.
    face : (P, 3) float
        The contact points p = sum_j N_j (x_j - a_j d_j), mm.
    """

    triangle: np.ndarray
    gap: np.ndarray
    normal: np.ndarray
    weights: np.ndarray
    gradients: np.ndarray
    touching: np.ndarray
    face: np.ndarray


def triangle_frames(corners: np.ndarray):
    """Unit normals (..., 3), twice the areas (...,) and the barycentric gradients
    (..., 3, 3) of triangles with corners (..., 3, 3)."""
    y1, y2, y3 = corners[..., 0, :], corners[..., 1, :], corners[..., 2, :]
    c = np.cross(y2 - y1, y3 - y1)
    area2 = np.linalg.norm(c, axis=-1)
    n = c / area2[..., None]
    edges = np.stack([y3 - y2, y1 - y3, y2 - y1], axis=-2)  # opposite corner k, cyclic
    gradients = np.cross(n[..., None, :], edges) / area2[..., None, None]
    return n, area2, gradients


def facets(p: np.ndarray, corners: np.ndarray):
    """Each point against each of its candidate triangles' planes: unit normals (P, K, 3),
    twice the areas (P, K), barycentric gradients (P, K, 3, 3), gaps (P, K) mm and the
    barycentric coordinates (P, K, 3) of the projections; p (P, 3), corners (P, K, 3, 3)."""
    n, area2, gradients = triangle_frames(corners)
    relative = p[:, None, :] - corners[..., 0, :]
    gap = np.sum(relative * n, axis=-1)  # (P, K)
    weights = np.einsum("skij,skj->ski", gradients, p[:, None, :] - corners[..., 1, :])
    weights[..., 1] = np.einsum("ski,ski->sk", gradients[..., 1, :], relative)
    weights[..., 2] = 1.0 - weights[..., 0] - weights[..., 1]
    return n, area2, gradients, gap, weights


def choose(
    gap: np.ndarray, weights: np.ndarray, area2: np.ndarray, deepest: bool = True
) -> np.ndarray:
    """(P,) the column of each point's facing candidate (module docstring, "Search"): among
    those whose projection lies in the triangle, the one the point penetrates most, else the
    nearest by sqrt(g^2 + (o sqrt(2 A))^2), o the projection's overshoot past the edges.

    gap : (P, K) float, mm; weights : (P, K, 3) barycentric coordinates of the projections;
    area2 : (P, K) float, twice the candidates' areas, mm^2.
    """
    overshoot = np.maximum(0.0, -weights.min(axis=-1))
    distance = np.hypot(gap, overshoot * np.sqrt(area2))
    # Over a concave fold two triangles hold the projection: the deeper penetration
    # counts (W = k/2 max(p_A, p_B)^2 is convex in the pair, a kink Newton crosses);
    # over a convex one none holds it: the nearest triangle.
    inside = overshoot <= INSIDE
    return np.where(
        inside.any(axis=1),
        np.argmin(np.where(inside, gap, np.inf), axis=1)
        if deepest
        else np.argmin(np.where(inside, np.abs(gap), np.inf), axis=1),
        np.argmin(distance, axis=1),
    )


def closest_facing(p: np.ndarray, y: np.ndarray, near: np.ndarray, tolerance: float) -> Facing:
    """Each contact point's facing triangle, gap, normal and projection (module docstring,
    "Search": among the candidates, the one holding the projection that the point
    penetrates most, else the nearest).

    Parameters
    ----------
    p : (P, 3) float
        The contact points, mm.
    y : (m, 3, 3) float
        The lower face's triangles' corners, mm.
    near : (P, K) int
        Each point's candidate triangles (rows of ``y``).
    tolerance : float
        The gap (mm) at or below which a point counts as touching.
    """
    n, area2, gradients, gap, weights = facets(p, y[near])
    best = choose(gap, weights, area2)
    rows = np.arange(len(p))
    chosen_gap = gap[rows, best]
    overshoot = np.maximum(0.0, -weights[rows, best].min(axis=-1))
    touching = (chosen_gap <= tolerance) & (overshoot <= MARGIN)
    return Facing(
        triangle=near[rows, best],
        gap=chosen_gap,
        normal=n[rows, best],
        weights=weights[rows, best],
        gradients=gradients[rows, best],
        touching=touching,
        face=p,
    )
