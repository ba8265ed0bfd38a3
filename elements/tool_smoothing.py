"""The smoothed surface of a meshed rigid tool (``RigidSurface(smooth=True)``; docs/theory.md
§9.3): each point's gap measured to a curved (Phong) surface over the facets, whose normal
turns with the tool's curvature, so that a node pressed on a faceted curved tool sees no jump
of its contact force where its closest facet changes.

Why. The closest-point distance to a triangulated tool is smooth on the convex side of its
edges and only continuous on the concave side: a point inside a faceted bowl (or over a
faceted rim, seen from inside the circle) is nearest to one facet or its neighbour, and its
normal jumps by the dihedral angle where it crosses their bisector. A pressed node there lies
in a V-shaped valley of the contact energy, whose force jumps by f_N times that angle (1.9 deg
on the hemisphere die of validation/cases/hemisphere_forming.py): Newton cannot converge to
an equilibrium on the kink, however short the increment.

What. Each facet corner gets a unit normal: the normals of the facets around its vertex,
weighted by their angles there (Thurmer and Wuthrich, J. Graphics Tools 3 (1998) 1), among
those within FEATURE_ANGLE of the facet's own, so that a sharp edge (a die's rim) stays sharp
and a curved part is smoothed. Over each facet the surface is the Phong tessellation of
Boubekeur and Alexa (ACM Trans. Graph. 27 (2008) 141) with shape factor 1/2, the one
elements/ply_surface.py gives a ply's face (its docstring has the formulas): on a sphere with
its corners and normals exact it is exact to second order in the facet's angle (the flat
facet's sag s^2 / 8R becomes O(s^4 / R^3)), and along an edge it depends on that edge's
two corners alone, so it is continuous from facet to facet. A point is projected on the
patches of the facets that share a vertex with its closest facet (Gauss-Newton from the flat
projection); of those that hold it the nearest, and its gap is the signed distance to that
patch along the patch's unit normal, which is the gap's gradient (the tool is rigid: the
corners and normals do not move), so the force k p n is the exact gradient of the energy
1/2 k p^2 and the contact tangent's k n n^T its exact normal part. The normal turns with
the patch, 1.9 deg across a facet of the die, where the flat facets keep it and then jump.

What it is not. The Phong patches meet with continuous positions but not exactly continuous
normals: on the die the normal still turns by 0.005 deg across an edge (against 1.9). Where no
patch of the ring holds the projection (past an open edge, over a sharp edge kept by the
feature angle) the closest-point distance and normal stand: there the kinks of the faceted
rim remain. On a flat tool (a table, a holder) every patch is its facet and nothing changes.
The contact tangent takes in the surface's curvature: the normal's turn dn/dx as the
closest point slides over the patch (elements/facet_normal.py ``turn_on_patches``), k p / R
on the die's bowl; the closest-point normal of a flat facet has none.
"""

from __future__ import annotations

import numpy as np

from elements import ply_surface
from elements.facet_normal import turn_on_patches

__all__ = ["FEATURE_ANGLE", "corner_normals", "facet_rings", "project", "smoothed_gap"]

# How far outside a patch (in barycentric units) a projection still counts as on it: round-off
# at the shared edges, where two patches give the same answer.
INSIDE = 1e-9
# Facets whose normals differ by more than this (deg) meet at a sharp edge, which the smooth
# surface keeps (the rim of a die): a corner's normal averages only the facets within it of
# its own facet's.
FEATURE_ANGLE = 30.0
# A patch is projected on only when its flat facet's barycentric projection of the point is
# within this of it (the curved projection differs by the sag over the cell).
NEAR = 0.25
# Gauss-Newton steps of the projection on a patch from the flat one (it is off by the sag's
# share of the cell, and each step shrinks the error by about g / R, the gap over the
# radius): four left the last step above 1e-9 for points more than about 0.4 mm off the
# hemisphere die (97 % of them at 0.6 mm), which then fell back to the closest-point
# normal, 1.3 deg off; eight hold the projection to 1.5 mm (the largest facet's reach).
PROJECTION_STEPS = 8


def corner_normals(corners: np.ndarray, triangles: np.ndarray, normals: np.ndarray):
    """(f, 3, 3) the unit normal of the smooth surface at each facet's corners: the unit
    normals ``normals`` (f, 3) of the facets around that vertex whose normal is within
    FEATURE_ANGLE of the facet's own, weighted by their angles at the vertex and summed
    (module docstring); ``corners`` (f, 3, 3) the facets' corners, ``triangles`` (f, 3)
    their vertex ids."""
    edges_out = np.roll(corners, -1, axis=1) - corners
    edges_in = np.roll(corners, 1, axis=1) - corners
    cosine = np.sum(edges_out * edges_in, axis=2) / (
        np.linalg.norm(edges_out, axis=2) * np.linalg.norm(edges_in, axis=2)
    )
    angle = np.arccos(np.clip(cosine, -1.0, 1.0)).ravel()  # (f 3,) each corner's angle
    owner = np.repeat(np.arange(len(triangles)), 3)
    vertex = triangles.ravel()
    order = np.argsort(vertex, kind="stable")
    starts = np.searchsorted(vertex[order], np.arange(vertex.max() + 2))
    counts = starts[1:] - starts[:-1]
    # around each vertex its corners (facet, angle), padded: (n_vertices, M)
    width = int(counts.max())
    slot = np.arange(len(order)) - np.repeat(starts[:-1], counts)
    around = np.full((len(counts), width), -1, dtype=np.int64)
    around[vertex[order], slot] = order
    corner_ids = around[vertex]  # (f 3, M) the corners at each corner's vertex
    present = corner_ids >= 0
    ids = np.where(present, corner_ids, 0)
    theirs = normals[owner[ids]]  # (f 3, M, 3)
    alike = present & (
        np.einsum("cmi,ci->cm", theirs, normals[owner]) >= np.cos(np.radians(FEATURE_ANGLE))
    )
    summed = np.einsum("cm,cmi->ci", np.where(alike, angle[ids], 0.0), theirs)
    return (summed / np.linalg.norm(summed, axis=1)[:, None]).reshape(-1, 3, 3)


def facet_rings(triangles: np.ndarray) -> np.ndarray:
    """(f, K) each facet's ring: the facets that share a vertex with it (itself first),
    padded with -1."""
    f = len(triangles)
    owner = np.repeat(np.arange(f), 3)
    vertex = triangles.ravel()
    order = np.argsort(vertex, kind="stable")
    vertex, owner = vertex[order], owner[order]
    starts = np.searchsorted(vertex, np.arange(vertex.max() + 2))
    rings: list[set[int]] = [set() for _ in range(f)]
    for facet, corners in enumerate(triangles):
        for v in corners:
            rings[facet].update(owner[starts[v] : starts[v + 1]].tolist())
    width = max(len(r) for r in rings)
    out = np.full((f, width), -1, dtype=np.int64)
    for facet, ring in enumerate(rings):
        ordered = [facet] + sorted(ring - {facet})
        out[facet, : len(ordered)] = ordered
    return out


def smoothed_gap(
    x: np.ndarray,
    facet: np.ndarray,
    corners: np.ndarray,
    triangles: np.ndarray,
    facet_normals: np.ndarray,
    normals_at_corners: np.ndarray,
    rings: np.ndarray,
    turning: bool = False,
):
    """The signed distance to the Phong surface (module docstring) of points x (k, 3) whose
    closest facets are ``facet`` (k,): (d (k,), mm; the surface's unit normal there (k, 3),
    towards the body; found (k,) bool, False where no patch of the ring holds the projection:
    the caller keeps the closest-point distance there). ``corners`` (f, 3, 3), ``triangles``
    (f, 3) and ``facet_normals`` (f, 3) (unit, towards the body) of the facets,
    ``normals_at_corners`` (f, 3, 3) of corner_normals, ``rings`` (f, K) of facet_rings.
    ``turning``: a fourth answer, the normal's turn dn/dx (k, 3, 3), 1/mm, at the projection
    on the patch picked (elements/facet_normal.py ``turn_on_patches``; NaN where not found)."""
    count, width = len(x), rings.shape[1]
    ring = rings[facet]  # (k, K)
    valid = ring >= 0
    rows = np.where(valid, ring, 0).ravel()
    y = corners[rows]  # (k K, 3, 3)
    normals = normals_at_corners[rows]
    p = np.repeat(x, width, axis=0)
    # The start: the flat facet's barycentric projection.
    e1, e2 = y[:, 1] - y[:, 0], y[:, 2] - y[:, 0]
    r = p - y[:, 0]
    g11, g12, g22 = (np.sum(e1 * e1, axis=1), np.sum(e1 * e2, axis=1), np.sum(e2 * e2, axis=1))
    r1, r2 = np.sum(r * e1, axis=1), np.sum(r * e2, axis=1)
    det = g11 * g22 - g12 * g12
    u, v = (g22 * r1 - g12 * r2) / det, (g11 * r2 - g12 * r1) / det
    start = np.column_stack([1.0 - u - v, u, v])
    # Only the patches whose flat facet nearly holds the point are projected on: the curved
    # projection is within the sag over the cell of the flat one.
    tried = valid.ravel() & (start.min(axis=1) >= -NEAR)
    lam = np.full((len(p), 3), np.nan)
    normal = np.full((len(p), 3), np.nan)
    gap = np.full(len(p), np.nan)
    lam[tried], normal[tried], gap[tried] = project(
        p[tried], y[tried], normals[tried], start[tried]
    )
    # project's normal has the triangle's winding: turned towards the body like the facet's
    turn = np.where(np.sum(normal * facet_normals[rows], axis=1) < 0.0, -1.0, 1.0)
    gap, normal = (
        (turn * gap).reshape(count, width),
        (turn[:, None] * normal).reshape(count, width, 3),
    )
    holds = valid & np.all(lam >= -INSIDE, axis=1).reshape(count, width) & np.isfinite(gap)
    # Of the patches that hold the projection (two or three at a shared edge or vertex, with
    # nearly the same answer), the nearest: a patch enters the choice with its projection on
    # its edge, no nearer than the neighbour's own, so the distance does not jump.
    pick = np.argmin(np.where(holds, np.abs(gap), np.inf), axis=1)
    at = np.arange(count)
    found = holds[at, pick]
    if not turning:
        return gap[at, pick], normal[at, pick], found
    chosen = at * width + pick  # the picked patch's row among the k K tried
    turn_normal = np.full((count, 3, 3), np.nan)
    rows = chosen[found]
    turn_normal[found] = turn[rows, None, None] * turn_on_patches(
        p[rows], y[rows], normals[rows], lam[rows]
    )
    return gap[at, pick], normal[at, pick], found, turn_normal


def project(p: np.ndarray, y: np.ndarray, n: np.ndarray, start: np.ndarray):
    """The closest points of ``p`` (P, 3) on the Phong patches over corners ``y`` and corner
    normals ``n`` (P, 3, 3), from barycentric coordinates ``start`` (P, 3): (lambda (P, 3),
    the patch's unit normal there (P, 3) with the winding of y, the signed gap (P,), mm); NaN
    where Gauss-Newton did not settle to 1e-9. The surface and its projection are those of a
    ply's curved face (elements/ply_surface.py ``project``), here PROJECTION_STEPS steps."""
    lam, _, normal, gap, _, _ = ply_surface.project(
        p, y, n, start, steps=PROJECTION_STEPS, settled=1e-9
    )
    return lam, normal, gap
