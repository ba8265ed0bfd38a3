"""Measures of the two-ply hemisphere that a mesh's cells do not choose: each ply's shear field
sampled at one set of material points at every resolution, against the pin-jointed net where
the ply lies on the punch, and against the same field on another mesh; the fibres along the
symmetry planes and the places where the flange lifts.

A ply's shear angle is constant on a triangle (``elements.layup.ply_shear``). Averaged to the
nodes by area (``nodal_average``) and interpolated linearly in the flat blank
(``field_at``), it is a continuous field whose value at a material point X no longer depends
on which cell X falls in: on the fibre-aligned blank (``femcore.blank.ply_blank``) an interior
node's six triangles are symmetric about it, so the average of a linear field's cell values is
its nodal value, and the interpolant of a smooth field is second order in the cell away from
the outline (tests/test_hemisphere_plies_fields.py). The per-cell rms over the cells in the
die (validation/studies/hemisphere_plies_run.py) changes its set of cells with the mesh and
carries the cells' own first-order sampling error; these measures do neither.

The region compared with the net is the material points whose place on the net lies within
a polar angle ``theta`` of the pole (the net of their ply, ``validation.references.drape``):
inside the die's bowl, away from its entry round and the wrinkled flange, where the net is
the drape's reference (docs/theory.md §9.4).
"""

from __future__ import annotations

import numpy as np
from matplotlib.tri import LinearTriInterpolator, Triangulation
from scipy.interpolate import RegularGridInterpolator

from validation.references.drape import fishnet_on_sphere, net_coordinates

__all__ = [
    "centre_lines",
    "groups_round",
    "field_at",
    "line_strain",
    "material_grid",
    "net_on_sphere",
    "nodal_average",
]


def nodal_average(points: np.ndarray, triangles: np.ndarray, values: np.ndarray) -> np.ndarray:
    """(n,) each node's average of the values of the triangles around it, weighted by their
    areas in ``points`` (NaN at a node no triangle uses).

    Parameters
    ----------
    points : (n, 2) or (n, 3) float
        The nodes' reference positions, mm (the first two columns are used).
    triangles : (m, 3) int
        Node indices.
    values : (m,) float
        One value per triangle (any unit).
    """
    points = np.asarray(points, dtype=float)[:, :2]
    triangles = np.asarray(triangles)
    values = np.asarray(values, dtype=float)
    if triangles.ndim != 2 or triangles.shape[1] != 3 or values.shape != (len(triangles),):
        raise ValueError(
            f"need (m, 3) triangles and (m,) values, got {triangles.shape} and {values.shape}"
        )
    a, b, c = (points[triangles[:, i]] for i in range(3))
    area = 0.5 * np.abs((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0])
    n = len(points)
    weight = np.bincount(triangles.ravel(), np.repeat(area, 3), minlength=n)
    total = np.bincount(triangles.ravel(), np.repeat(area * values, 3), minlength=n)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(weight > 0.0, total / weight, np.nan)


def field_at(
    points: np.ndarray, triangles: np.ndarray, nodal: np.ndarray, at: np.ndarray
) -> np.ndarray:
    """(p, ...) a nodal field interpolated linearly over the triangles of the flat blank at
    the points ``at``; NaN outside the triangles.

    Parameters
    ----------
    points : (n, 2) or (n, 3) float
        The nodes' reference positions, mm (the first two columns are used).
    triangles : (m, 3) int
        Node indices (nodes no triangle uses are left out).
    nodal : (n,) or (n, k) float
        The field at the nodes.
    at : (p, 2) float
        Reference positions, mm.
    """
    points = np.asarray(points, dtype=float)[:, :2]
    triangles = np.asarray(triangles)
    nodal = np.asarray(nodal, dtype=float)
    used, local = np.unique(triangles, return_inverse=True)
    mesh = Triangulation(points[used, 0], points[used, 1], local.reshape(triangles.shape))
    at = np.asarray(at, dtype=float)
    columns = nodal[used].reshape(len(used), -1)
    out = np.empty((len(at), columns.shape[1]))
    for j in range(columns.shape[1]):
        value = LinearTriInterpolator(mesh, columns[:, j])(at[:, 0], at[:, 1])
        out[:, j] = np.ma.filled(value.astype(float), np.nan)
    return out.reshape((len(at),) + nodal.shape[1:])


def material_grid(extent: float, spacing: float) -> np.ndarray:
    """(p, 2) the points of a square grid of ``spacing`` (mm) over [-extent, extent]^2 in the
    flat blank's plane coordinates (centred on the pole, a point on each axis): one set of
    material points for every resolution."""
    if not (0.0 < spacing <= extent):
        raise ValueError(f"need 0 < spacing <= extent, got {spacing!r} and {extent!r}")
    side = np.arange(spacing, extent + 1e-9 * extent, spacing)
    axis = np.concatenate([-side[::-1], [0.0], side])
    x, y = np.meshgrid(axis, axis, indexing="ij")
    return np.column_stack([x.ravel(), y.ravel()])


def net_on_sphere(radius: float, cell: float, angle: float, at: np.ndarray) -> dict:
    """The pin-jointed net of a ply laid at ``angle`` (deg) on the sphere of ``radius`` (mm,
    its segment ``cell``, mm) at the plane points ``at`` (p, 2) of the flat blank: ``shear``
    (p,) rad and ``polar`` (p,) the polar angle of the point's place on the net, rad (NaN
    where the net leaves the hemisphere)."""
    net = fishnet_on_sphere(radius, cell, int(0.5 * np.pi * radius / cell))
    polar = np.arccos(np.clip(net["points"][..., 2] / radius, -1.0, 1.0))
    uv = net_coordinates(np.asarray(at, dtype=float), angle)
    grid = (net["u"], net["v"])
    return {
        "shear": RegularGridInterpolator(grid, net["shear"], bounds_error=False)(uv),
        "polar": RegularGridInterpolator(grid, polar, bounds_error=False)(uv),
    }


def centre_lines(points: np.ndarray, half: float) -> list[np.ndarray]:
    """The flat blank's four half-axes from the pole to the edge middles (+x, +y, -x, -y):
    each the indices of the ``points`` (n, 2+) on it, from the pole outwards."""
    points = np.asarray(points, dtype=float)
    lines = []
    for axis, side in ((0, 1.0), (1, 1.0), (0, -1.0), (1, -1.0)):
        on = np.isclose(points[:, 1 - axis], 0.0, atol=1e-9 * half) & (
            side * points[:, axis] >= -1e-9 * half
        )
        nodes = np.flatnonzero(on)
        lines.append(nodes[np.argsort(side * points[nodes, axis])])
    return lines


def line_strain(points: np.ndarray, positions: np.ndarray, line: np.ndarray) -> float:
    """The mean strain of the fibre through the nodes ``line`` (in order): its length at
    ``positions`` (polyline) over its length in ``points`` (both (n, 3)), less 1."""
    points, positions = np.asarray(points, dtype=float), np.asarray(positions, dtype=float)
    now = np.linalg.norm(np.diff(positions[line], axis=0), axis=1).sum()
    before = np.linalg.norm(np.diff(points[line], axis=0), axis=1).sum()
    return float(now / before - 1.0)


def groups_round(angles: np.ndarray, gap: float) -> int:
    """How many groups points at polar ``angles`` (rad) make round a circle, a group's
    neighbours being less than ``gap`` (rad) apart (the last point's next the first's, 2 pi
    on): the lifted places of a flange counted as wrinkles. 0 for no points."""
    angles = np.sort(np.mod(np.asarray(angles, dtype=float).ravel(), 2.0 * np.pi))
    if not (gap > 0.0):
        raise ValueError(f"the gap must be positive, got {gap!r}")
    if angles.size == 0:
        return 0
    if not np.all(np.isfinite(angles)):
        raise ValueError("angles must be finite")
    steps = np.diff(np.concatenate([angles, [angles[0] + 2.0 * np.pi]]))
    return max(int(np.sum(steps >= gap)), 1)
