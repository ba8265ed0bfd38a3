"""What a forming run of a square blank measures beyond its shear: the draw-in of its edges
and corners, the punch's mean force over the end of its stroke, and the wrinkles of its
outline.

The blank is a ``Mesh.rectangle`` of side 2 ``half`` (mm) centred on the punch's axis (the z
axis), its fibres along x and y. A single node's draw-in (the edge middle's) can take one of
two states on a frictionless flange (docs/hemisphere_forming.md), and a punch force at one
instant rings with the flange's release: these quantities integrate over the edge and over the
stroke's last part, where one node or one instant weighs little.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

__all__ = ["corner_draw_in", "edge_draw_in", "late_mean_force", "outline_wrinkles"]


def _edges(points: np.ndarray, half: float) -> list[tuple[np.ndarray, int, float]]:
    """The four edges' nodes, each sorted along its edge, with the axis (0: x, 1: y) the edge
    is normal to and its side (+1, -1)."""
    edges = []
    for axis in (0, 1):
        for side in (1.0, -1.0):
            nodes = np.flatnonzero(np.isclose(points[:, axis], side * half))
            edges.append((nodes[np.argsort(points[nodes, 1 - axis])], axis, side))
    return edges


def edge_draw_in(points: np.ndarray, positions: np.ndarray, half: float) -> float:
    """The draw-in (mm) averaged along the blank's four edges: at each edge node, how far it
    moved in along the edge's inward normal (half less its coordinate along it), averaged
    along the edge by the trapezoidal rule over the nodes' initial positions, then over the
    four edges.

    Parameters
    ----------
    points : numpy.ndarray, shape (n, 3)
        The flat blank's nodes, mm.
    positions : numpy.ndarray, shape (n, 3) or more rows
        Their positions at the end, mm (rows past n, a driven tool's node, are ignored).
    half : float
        Half the blank's side, mm.
    """
    means = []
    for nodes, axis, side in _edges(points, half):
        inward = half - side * positions[nodes, axis]
        along = points[nodes, 1 - axis]
        means.append(np.trapezoid(inward, along) / (along[-1] - along[0]))
    return float(np.mean(means))


def corner_draw_in(points: np.ndarray, positions: np.ndarray, half: float) -> float:
    """The draw-in (mm) of the blank's four corners, averaged: how much nearer the axis each
    ended than its initial sqrt(2) half, in the xy plane. ``points``, ``positions`` and
    ``half`` as ``edge_draw_in``."""
    corners = np.flatnonzero(
        np.isclose(np.abs(points[:, 0]), half) & np.isclose(np.abs(points[:, 1]), half)
    )
    reach = np.linalg.norm(positions[corners, :2], axis=1)
    return float(np.mean(np.sqrt(2.0) * half - reach))


def late_mean_force(
    times: np.ndarray,
    work: np.ndarray,
    travel: Callable[[np.ndarray], np.ndarray],
    share: float,
) -> float:
    """The punch's mean force (N) over the last ``share`` of its travel: the external work
    done over it (N mm) over that travel (mm), W(end) - W(at (1 - share) of the travel),
    the work interpolated linearly between its records. NaN when the records do not reach
    the end of the travel.

    Parameters
    ----------
    times : numpy.ndarray, shape (k,)
        The energy records' times, s, increasing.
    work : numpy.ndarray, shape (k,)
        The external work at them, N mm (the punch's, with any other tool's: a held holder
        that does not move does none).
    travel : callable
        The punch's travel (mm, increasing from 0 to its full travel) at the given times.
    share : float
        The part of the full travel averaged over, in (0, 1].
    """
    if not 0.0 < share <= 1.0:
        raise ValueError(f"share must be in (0, 1], got {share!r}")
    moved = travel(np.asarray(times, dtype=float))
    full = float(travel(np.array([np.inf]))[0])
    if moved[-1] < full * (1.0 - 1e-9):
        return float("nan")
    start = (1.0 - share) * full
    first = int(np.searchsorted(moved, start, side="right"))  # moved[first - 1] <= start
    before = max(first - 1, 0)
    gap = moved[first] - moved[before] if first < len(moved) else 0.0
    fraction = (start - moved[before]) / gap if gap > 0.0 else 0.0
    at_start = work[before] + fraction * (work[min(first, len(work) - 1)] - work[before])
    return float((work[-1] - at_start) / (full - start))


def outline_wrinkles(
    points: np.ndarray, positions: np.ndarray, half: float, thickness: float
) -> dict[str, int | float]:
    """Out of the die: the wrinkles of the blank's outline, as the number of crests more
    than half the ``thickness`` (mm) above the flange along it (by polar angle) and the
    largest height (mm; the folds stand up along the punch). ``points`` (n, 3) the flat
    blank's nodes (side 2 ``half``, mm, its mid-surface at thickness / 2), ``positions``
    (n, 3) where they are, mm."""
    outline = np.flatnonzero(
        np.isclose(np.abs(points[:, 0]), half) | np.isclose(np.abs(points[:, 1]), half)
    )
    x = positions[outline]
    order = np.argsort(np.arctan2(x[:, 1], x[:, 0]))
    height = x[order, 2] - 0.5 * thickness
    crest = (
        (height > np.roll(height, 1)) & (height >= np.roll(height, -1)) & (height > 0.5 * thickness)
    )
    return {"count": int(crest.sum()), "height": float(height.max())}
