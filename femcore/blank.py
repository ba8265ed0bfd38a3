"""A rectangular blank meshed along the fibres of a ply laid at any angle: the mesh of one ply
of a layup (elements/layup.py), fibre-aligned as ``FibrousShell`` needs (every triangle has a
corner whose two edges run along the warp and the weft, elements/fibrous/fibres.py).

The grid. The ply's fibres run along w = (cos a, sin a, 0) (warp) and f = (-sin a, cos a, 0)
(weft), a the ply angle from +x. A square grid of fibre segments s along w and f covers the
blank; each of its squares splits along one diagonal into two right triangles (right angle at
a corner, legs along the fibres), and the blank keeps the triangles whose three corners lie
inside it ("whole cells inside"): no triangle is cut, so every one stays fibre-aligned.

The outline. At a = 0 or 90 deg (mod 90) the grid is ``Mesh.rectangle``'s and the outline is
the rectangle. At 45 deg (mod 90) the squares are diamonds whose diagonals run along x and y;
with the diagonal half-length u = s / sqrt(2) dividing the half sides (lx / 2 = n_x u,
ly / 2 = n_y u) and a grid node on a corner of the blank, each diamond cut by a side splits
along the diagonal on that side (the one along the nearest side of the blank), and the kept
half-diamonds fill the blank exactly: the outline is the rectangle again. At any other angle
no grid of fibre-aligned triangles fills a rectangle, the kept cells leave a staircase along
the sides, and a UserWarning states the area lost.

Units: any length unit (mm in the presets).
"""

from __future__ import annotations

import math
import warnings

import numpy as np
from numpy.typing import ArrayLike

from femcore.checks import as_number, as_reals
from femcore.mesh import Mesh

__all__ = ["ply_blank", "ply_directions"]


def ply_directions(angle: float) -> tuple[np.ndarray, np.ndarray]:
    """The warp and weft unit vectors (3,) of a ply laid at ``angle`` degrees from +x about +z."""
    a = math.radians(angle)
    return np.array([math.cos(a), math.sin(a), 0.0]), np.array([-math.sin(a), math.cos(a), 0.0])


def _kind(angle: float) -> str:
    rest = math.remainder(angle, 90.0)
    if abs(rest) < 1e-9:
        return "rectangle"
    if abs(abs(rest) - 45.0) < 1e-9:
        return "diagonal"
    return "oblique"


def ply_blank(
    lx: float,
    ly: float,
    cells: int,
    angle: float = 0.0,
    centre: ArrayLike = (0.0, 0.0, 0.0),
) -> Mesh:
    """An lx x ly blank centred on ``centre`` in the plane z = centre z, meshed with right
    triangles along the fibres of a ply laid at ``angle`` (module docstring).

    Parameters
    ----------
    lx, ly : float
        Side lengths along x and y, > 0 (mm).
    cells : int
        Fibre segments across lx, >= 1: the segment is s = lx / cells at 0 and 90 deg
        (``ly / s`` rounded across ly); at 45 deg the diagonal half-length u = lx / (2 n_x)
        with n_x = max(1, round(cells / sqrt(2))) (s = sqrt(2) u, the same fibre length to
        rounding) and n_y = round(ly / (2 u)); at other angles s = lx / cells.
    angle : float
        The ply's warp direction, degrees from +x about +z (any real; 0, 90 and 45 mod 90
        give the exact outline).
    centre : array_like, shape (3,)
        The blank's centre (mm).

    Returns
    -------
    Mesh
        Triangles counter-clockwise about +z, with node sets "left", "right", "bottom",
        "top" (the nodes on each side of the rectangle, within 1e-9 of its size; at oblique
        angles those on the staircase's outer corners only) and "outline" (their union), and
        the triangle set "all".

    Raises
    ------
    ValueError
        Non-positive or non-finite sizes, a cell count that is not a positive integer, a
        non-finite angle, a bad centre, a 45-deg blank whose ly is not an even multiple of
        u to 1e-6 (no exact outline: give a ly that fits, or cells that make it fit).

    Warns
    -----
    UserWarning
        At an oblique angle: the staircase outline and the share of the blank's area lost.
    """
    lx = as_number(lx, "ply_blank lx", "a length > 0")
    ly = as_number(ly, "ply_blank ly", "a length > 0")
    if not (math.isfinite(lx) and math.isfinite(ly) and lx > 0 and ly > 0):
        raise ValueError(f"ply_blank needs finite sides lx, ly > 0, got {lx!r} and {ly!r}")
    if isinstance(cells, bool) or not isinstance(cells, (int, np.integer)) or cells < 1:
        raise ValueError(f"ply_blank cells must be an integer >= 1, got {cells!r}")
    angle = as_number(angle, "ply_blank angle", "a number of degrees")
    if not math.isfinite(angle):
        raise ValueError(f"ply_blank angle must be a finite number of degrees, got {angle!r}")
    centre = as_reals(centre, "ply_blank centre", "a point (x, y, z)").ravel()
    if centre.shape != (3,) or not np.isfinite(centre).all():
        raise ValueError(f"ply_blank centre must be a finite point (x, y, z), got {centre!r}")
    kind = _kind(angle)
    if kind == "rectangle":
        ny = max(1, round(cells * ly / lx))
        mesh = Mesh.rectangle(lx, ly, nx=int(cells), ny=ny, origin=centre - [lx / 2, ly / 2, 0])
        return _with_outline(mesh.points, mesh.triangles, lx, ly, centre)
    warp, weft = ply_directions(angle)
    if kind == "diagonal":
        n_x = max(1, round(cells / math.sqrt(2.0)))
        u = lx / (2.0 * n_x)
        n_y = ly / (2.0 * u)
        if abs(n_y - round(n_y)) > 1e-6 or round(n_y) < 1:
            raise ValueError(
                f"ply_blank at {angle} deg: ly = {ly} is not an even multiple of the diamond's "
                f"half-diagonal u = {u:.6g} (lx = {lx}, {cells} cells); the outline would not be "
                f"the rectangle: choose ly = 2 k u or other cells"
            )
        segment = math.sqrt(2.0) * u
        # a grid node on the corner (+lx/2, +ly/2): then on all four (module docstring)
        anchor = np.array([lx / 2.0, ly / 2.0, 0.0])
    else:
        segment = lx / cells
        anchor = np.zeros(3)
    points, triangles = _clipped_grid(lx, ly, segment, warp, weft, anchor)
    if kind == "oblique":
        kept = 0.5 * segment**2 * len(triangles)
        warnings.warn(
            f"ply_blank at {angle} deg: no fibre-aligned grid fills a rectangle at this angle; "
            f"the blank keeps its whole cells, a staircase outline with "
            f"{100.0 * (1.0 - kept / (lx * ly)):.1f} % of the {lx} x {ly} area lost",
            UserWarning,
            stacklevel=2,
        )
    return _with_outline(points + centre, triangles, lx, ly, centre)


def _clipped_grid(lx, ly, segment, warp, weft, anchor):
    """Points (p, 3) and counter-clockwise triangles (t, 3) of the fibre grid through
    ``anchor`` (centre-relative), whole triangles inside the blank, unused nodes dropped."""
    reach = 0.5 * math.hypot(lx, ly) + np.linalg.norm(anchor)
    count = int(math.ceil(reach / segment)) + 2
    k = np.arange(-count, count + 1)
    i, j = np.meshgrid(k, k, indexing="ij")
    grid = anchor + segment * (i[..., None] * warp + j[..., None] * weft)  # (g, g, 3)
    size = len(k)
    index = np.arange(size * size).reshape(size, size)
    a, b = index[:-1, :-1].ravel(), index[1:, :-1].ravel()  # square (i, j): a, b, c, d ccw
    c, d = index[1:, 1:].ravel(), index[:-1, 1:].ravel()
    points = grid.reshape(-1, 3)
    middle = 0.5 * (points[a] + points[c])
    # Split along the diagonal closer in direction to the nearest side of the blank, so that
    # the half-squares a side cuts keep the half inside (exact at 45 deg).
    to_x_side = 0.5 * lx - np.abs(middle[:, 0]) < 0.5 * ly - np.abs(middle[:, 1])
    side = np.where(to_x_side[:, None], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0])
    along_ac = np.abs(np.sum((points[c] - points[a]) * side, axis=1))
    along_bd = np.abs(np.sum((points[d] - points[b]) * side, axis=1))
    split_ac = along_ac >= along_bd
    first = np.where(split_ac[:, None], np.column_stack([a, b, c]), np.column_stack([a, b, d]))
    second = np.where(split_ac[:, None], np.column_stack([a, c, d]), np.column_stack([b, c, d]))
    triangles = np.concatenate([first, second])
    tolerance = 1e-9 * max(lx, ly)
    inside = (np.abs(points[:, 0]) <= 0.5 * lx + tolerance) & (
        np.abs(points[:, 1]) <= 0.5 * ly + tolerance
    )
    triangles = triangles[inside[triangles].all(axis=1)]
    used, renumbered = np.unique(triangles, return_inverse=True)
    return points[used], renumbered.reshape(-1, 3)


def _with_outline(points, triangles, lx, ly, centre) -> Mesh:
    relative = points - centre
    tolerance = 1e-9 * max(lx, ly)
    sets = {
        "left": np.flatnonzero(relative[:, 0] <= -0.5 * lx + tolerance),
        "right": np.flatnonzero(relative[:, 0] >= 0.5 * lx - tolerance),
        "bottom": np.flatnonzero(relative[:, 1] <= -0.5 * ly + tolerance),
        "top": np.flatnonzero(relative[:, 1] >= 0.5 * ly - tolerance),
    }
    sets["outline"] = np.unique(np.concatenate(list(sets.values())))
    return Mesh(
        points,
        triangles=triangles,
        node_sets=sets,
        element_sets={"all": np.arange(len(triangles))},
    )
