"""Kinematic draping of a woven fabric on a sphere: the pin-jointed net of Mack and Taylor
(Journal of the Textile Institute 47 (1956) T477-T488), independent of any finite element.

The fabric is a net of inextensible fibre segments of length a, free to rotate at the
crossings (no shear stiffness). Draped from the pole of a sphere of radius R with its two
generators (the warp and weft lines through the pole) along great circles, the net is
determined cell by cell: each new crossing P(i, j) lies at distance a from its two
neighbours P(i - 1, j) and P(i, j - 1) (towards the pole) and on the sphere; of the two such
points, the one away from P(i - 1, j - 1). On the sphere of centre O, |P - A| = a with
|A| = |P| = R makes A . P = R^2 - a^2 / 2, so P = alpha (A + B) + gamma A x B with alpha =
(R^2 - a^2 / 2) / (R^2 + A . B) and gamma from |P| = R.

The continuum limit is a Chebyshev net: with gamma(u, v) the shear angle (90 degrees less the
angle between the fibres) at fibre arc lengths (u, v) from the pole, the Gaussian curvature
K = 1 / R^2 gives d^2 gamma / du dv = K cos(gamma), gamma = 0 on the generators (Chebyshev
1878; Pipkin, 1984): ``chebyshev_shear`` integrates it as an independent check.
"""

from __future__ import annotations

import numpy as np

__all__ = ["chebyshev_shear", "fishnet_on_sphere", "net_coordinates"]


def fishnet_on_sphere(radius: float, cell: float, count: int, angle: float = 0.0) -> dict:
    """The pin-jointed net of segment ``cell`` (mm) on the upper hemisphere of ``radius``
    (mm, centre at the origin, pole at (0, 0, radius)), ``count`` cells from the pole along
    each generator each way, warp along x and weft along y at the pole; with ``angle`` (deg)
    the generators turned by it about z (the net of a ply laid at that angle: warp along
    (cos a, sin a, 0) at the pole), marched from them alike.

    Returns a dict: u, v (2 count + 1,) the fibre arc lengths of the crossings from the pole
    (mm, i cell and j cell); points (2 count + 1, 2 count + 1, 3), NaN where the net would
    pass below the equator (it leaves the hemisphere there); shear (same grid, rad) the
    shear angle at each crossing, 90 degrees less the angle between its warp and weft
    directions (``_shear``; positive where the fibres close up, NaN where undefined).
    """
    if not (cell > 0 and radius > 0 and cell < radius):
        raise ValueError(f"need 0 < cell < radius, got cell {cell!r}, radius {radius!r}")
    ply_angle = angle
    n = int(count)
    size = 2 * n + 1
    points = np.full((size, size, 3), np.nan)
    step = 2.0 * np.arcsin(0.5 * cell / radius)  # the angle of a chord of length cell
    k = np.arange(-n, n + 1)
    angle = k * step
    on = np.abs(angle) <= 0.5 * np.pi
    turn = np.radians(float(ply_angle))
    warp = np.array([np.cos(turn), np.sin(turn), 0.0])
    weft = np.array([-np.sin(turn), np.cos(turn), 0.0])
    pole = np.array([0.0, 0.0, 1.0])
    points[:, n][on] = (radius * (np.sin(angle)[:, None] * warp + np.cos(angle)[:, None] * pole))[
        on
    ]
    points[n, :][on] = (radius * (np.sin(angle)[:, None] * weft + np.cos(angle)[:, None] * pole))[
        on
    ]
    reach = radius**2 - 0.5 * cell**2
    # Each crossing needs its three neighbours towards the pole: those i + j = s apart lie on
    # one anti-diagonal and are independent, so the march goes one anti-diagonal of the four
    # quadrants at a time (the same operations on each crossing as one by one).
    quadrant = np.array([(si, sj) for si in (-1, 1) for sj in (-1, 1)])
    for total in range(2, 2 * n + 1):
        i = np.arange(max(1, total - n), min(n, total - 1) + 1)
        si = np.repeat(quadrant[:, 0], len(i))
        sj = np.repeat(quadrant[:, 1], len(i))
        i = np.tile(i, len(quadrant))
        j = total - i
        rows, columns = n + si * i, n + sj * j
        p = _third_crossings(
            points[rows - si, columns],  # towards the pole along warp
            points[rows, columns - sj],
            points[rows - si, columns - sj],
            radius,
            reach,
        )
        points[rows, columns] = p
    return {"u": k * cell, "v": k * cell, "points": points, "shear": _shear(points)}


def net_coordinates(xy: np.ndarray, angle: float) -> np.ndarray:
    """(p, 2) the fibre arc lengths (u, v) from the pole, mm, of a ply laid at ``angle``
    (deg) at its points of plane coordinates ``xy`` (p, 2) (a blank centred on the pole): u
    along the ply's warp (cos a, sin a), v along its weft (-sin a, cos a). The net of that
    ply (``fishnet_on_sphere(..., angle=a)``) has at (u, v) the shear of the 0-deg net at the
    same (u, v): look the 0-deg net up at these coordinates."""
    a = np.radians(float(angle))
    xy = np.asarray(xy, dtype=float)
    return np.column_stack(
        [xy[:, 0] * np.cos(a) + xy[:, 1] * np.sin(a), -xy[:, 0] * np.sin(a) + xy[:, 1] * np.cos(a)]
    )


def _third_crossings(a, b, d, radius, reach):
    """(k, 3) the points at distance cell from a and b (k, 3) on the sphere, away from d
    (k, 3); NaN where there is none (the net cannot close on the sphere), a neighbour is
    missing, or the point lies below the equator."""
    ab = _dots(a, b)
    alpha = reach / (radius**2 + ab)
    base = alpha[:, None] * (a + b)
    normal = np.cross(a, b)
    nn = _dots(normal, normal)
    rest = radius**2 - _dots(base, base)
    known = np.isfinite(a).all(axis=1) & np.isfinite(b).all(axis=1) & np.isfinite(d).all(axis=1)
    closes = known & (rest >= 0) & (nn != 0)
    with np.errstate(invalid="ignore", divide="ignore"):
        gamma = np.sqrt(rest / nn)
    first = base + gamma[:, None] * normal
    second = base - gamma[:, None] * normal
    far = np.sqrt(_dots(first - d, first - d)) > np.sqrt(_dots(second - d, second - d))
    p = np.where(far[:, None], first, second)
    p[~(closes & (p[:, 2] >= 0.0))] = np.nan
    return p


def _dots(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """(k,) the dot products of the rows of a and b (k, 3), each as ``a[i] @ b[i]`` gives it
    (a stacked matrix product: the same bits as the 3-vectors' own, where a sum of the
    products written out or einsum rounds otherwise)."""
    return (a[:, None, :] @ b[:, :, None])[:, 0, 0]


def _shear(points: np.ndarray) -> np.ndarray:
    """90 degrees less the angle at each crossing between its warp and weft directions, each
    the chord between its two neighbours along the fibre (rad; second order in the cell,
    zero on the generators by symmetry; NaN where a neighbour is missing)."""
    shear = np.full(points.shape[:2], np.nan)
    e1 = points[2:, 1:-1] - points[:-2, 1:-1]
    e2 = points[1:-1, 2:] - points[1:-1, :-2]
    cosine = np.sum(e1 * e2, axis=2) / (np.linalg.norm(e1, axis=2) * np.linalg.norm(e2, axis=2))
    shear[1:-1, 1:-1] = 0.5 * np.pi - np.arccos(np.clip(cosine, -1.0, 1.0))
    return shear


def chebyshev_shear(radius: float, extent: float, cells: int) -> dict:
    """The continuum Chebyshev net on a sphere: d^2 gamma / du dv = cos(gamma) / R^2 with
    gamma = 0 on u = 0 and v = 0, marched over [0, extent]^2 on a (cells + 1)^2 grid (the
    second-order scheme of a Goursat problem, the cosine at the cell centre from the three
    known corners). Returns u (cells + 1,) and shear (cells + 1, cells + 1), rad, gamma(u_i,
    v_j) in the quadrant u, v >= 0 (the others follow by symmetry: gamma(-u, v) =
    -gamma(u, v))."""
    h = extent / cells
    gamma = np.zeros((cells + 1, cells + 1))
    for i in range(cells):
        for j in range(cells):
            known = gamma[i, j] + gamma[i + 1, j] + gamma[i, j + 1]
            guess = gamma[i + 1, j] + gamma[i, j + 1] - gamma[i, j]
            for _ in range(4):  # implicit midpoint: the centre value from all four corners
                centre = 0.25 * (known + guess)
                guess = (
                    gamma[i + 1, j]
                    + gamma[i, j + 1]
                    - gamma[i, j]
                    + h**2 * np.cos(centre) / radius**2
                )
            gamma[i + 1, j + 1] = guess
    return {"u": np.linspace(0.0, extent, cells + 1), "shear": gamma}
