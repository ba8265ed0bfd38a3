"""The two-ply hemisphere's measure of the plies' order in the die: each top-ply node's gap to
the bottom ply's face along the radius from the die's centre (validation/studies/
hemisphere_plies.py, "The gap's measure").

Why along the radius. In the die both plies lie on spheres about the die's centre (the
origin; the punch's centre ends there), the top ply on the punch, the bottom one against the
die's bowl. Interpolating the bottom ply's nodes' distances from the centre over a triangle
puts its face on their sphere wherever its nodes are, with no chord (a flat facet's sag
s^2 / (8 R), 1.5-3 mm at the coarse mesh's 25-35 mm cells) and no nodal normals: the curved
(Phong) face over the nodal normals bulges towards the top ply where the bottom ply's cells
next to the die's entry radius turn its corners' normals (13.7 deg towards the rim at the
coarse fibrous [0/45] run's end), and read -0.70 mm there where the radii give the plies in
order. The measure is the study's, not the contact's: the contact acts on its own faces.
"""

from __future__ import annotations

import numpy as np

from elements.layup import Layup

__all__ = ["radial_gaps"]

#: barycentric slack of a ray through a triangle's edge or vertex (shared by its neighbours)
EDGE_SLACK = 1e-9


def radial_gaps(
    layup: Layup, positions: np.ndarray, thickness: float, below: float = -5.0
) -> np.ndarray:
    """(s,) each top-ply node's gap to the bottom ply's upper face along the radius, mm.

    Parameters
    ----------
    layup : Layup
        The two-ply layup (``ply_nodes``, ``ply_cells``, ``mesh``).
    positions : (n, 3) float
        The nodes' positions, mm, the die's centre at the origin.
    thickness : float
        The two faces' half thicknesses together, mm (the plies' faces touch when the
        mid-surfaces are that far apart).
    below : float
        mm: only the bottom ply's triangles whose three corners lie below z = ``below`` (in
        the die) count.

    Returns
    -------
    (s,) float
        Over the top ply's nodes (``layup.ply_nodes[-1]``): r_b - r - ``thickness``, r the
        node's distance from the centre and r_b the bottom ply's, interpolated over the
        triangle the node's ray from the centre passes through (barycentric coordinates of
        the ray's crossing of its plane); the least where the ray passes several (a fold).
        < 0: the node lies beyond the bottom ply's face. NaN where the ray passes no such
        triangle.
    """
    x = np.asarray(positions, dtype=float)
    top = layup.ply_nodes[-1]
    triangles = layup.mesh.triangles[layup.ply_cells[0]]
    triangles = triangles[(x[triangles, 2] < below).all(axis=1)]
    gaps = np.full(len(top), np.nan)
    if len(triangles) == 0:
        return gaps
    corners = x[triangles]  # (m, 3 corners, 3)
    radii = np.linalg.norm(corners, axis=2)  # (m, 3)
    r = np.linalg.norm(x[top], axis=1)  # (s,)
    direction = x[top] / np.where(r > 0.0, r, 1.0)[:, None]
    # the ray t u meets the plane of Y = [y_1 y_2 y_3] at Y lambda with sum lambda = 1:
    # lambda = Y^-1 u / (1 . Y^-1 u), in front of the centre where that sum is positive
    columns = np.transpose(corners, (0, 2, 1))  # (m, 3 xyz, 3 corners)
    solved = np.linalg.solve(
        columns[None, :, :, :],
        np.broadcast_to(direction[:, None, :, None], (len(top), len(triangles), 3, 1)),
    )[..., 0]  # (s, m, 3)
    total = solved.sum(axis=2)
    weights = solved / np.where(np.abs(total) > 0.0, total, 1.0)[..., None]
    through = (total > 0.0) & (weights >= -EDGE_SLACK).all(axis=2)
    bottom = np.einsum("smk,mk->sm", weights, radii)
    gap = np.where(through, bottom - r[:, None] - thickness, np.inf).min(axis=1)
    gaps[np.isfinite(gap)] = gap[np.isfinite(gap)]
    return gaps
