"""Folds of a MindlinShell mesh (docs/theory.md §5.9): where the one director of a node leans
far from the normals of its cells, as at a fold or a kink between two flat parts.

The shell has one director per node and two rotations (no drilling, docs/theory.md §1.3), and
its fibres keep the length h along the director (§5.1). At a fold of angle theta the
area-weighted director lies about half-way, tilted by theta / 2 from each side's normal, so that
the cells next to the fold are thinned to h cos(theta / 2) at that corner and wedge-shaped: the
fold is partly a hinge. On an L cantilever the tip's error against beam theory (CalculiX S4
on the same grid: -0.01 %) falls at first order with the element length while the cells stay
longer than about 2 h tan(theta / 2), then levels off (90 deg: +1.6 % at 40 and +1.8 % at 80
elements a leg) and is refused once the cells are shorter than about h sin(theta / 2) / 2.
Commercial shells give such nodes a director per side and a third rotation; this shell warns.
"""

from __future__ import annotations

import warnings

import numpy as np

from femcore.topology import build_topology

__all__ = ["FOLD_TILT_DEG", "director_tilt", "fold_angle", "turned_inside_out", "warn_folds"]

#: The director's tilt from a cell's normal, deg, beyond which MindlinShell warns. Measured on
#: the L cantilever of docs/theory.md §5.9 (a strip two cells wide, whose area-weighted
#: directors at the strip's edges lean further from the side with less area; tip against beam
#: theory at 10 / 20 / 40 / 80 elements a leg): a fold of 30 deg (tilt up to 20.1 deg)
#: +0.19 / +0.11 / +0.06 / +0.03 %, first order, silent; 45 deg (30.4 deg) +0.57 / +0.30 /
#: +0.16 / +0.09 %, and with h = 2 +0.58 / +0.32 / +0.18 / +0.14 %, stalling once the cells
#: are shorter than h / 2; 90 deg (63.4 deg) +4.6 / +2.6 / +1.6 / +1.8 %. The shipped curved
#: cases lean at most 7.5 deg (the pinched cylinder at 8 cells).
FOLD_TILT_DEG = 25.0


def director_tilt(
    points: np.ndarray, connectivity: np.ndarray, directors: np.ndarray
) -> np.ndarray:
    """The angle between each corner's director and its cell's normal, deg.

    Parameters
    ----------
    points : (n, 3) float, mm
        Node positions.
    connectivity : (m, 3) int
        Triangles, counter-clockwise about their normal.
    directors : (n, 3) float
        Unit directors of the nodes.

    Returns
    -------
    (m, 3) float, deg
        0 where the director is the cell's normal; theta / 2 on both sides of a symmetric fold
        of theta with area-weighted nodal directors.
    """
    return _degrees(_corner_cosines(points, connectivity, directors))


def turned_inside_out(
    points: np.ndarray, connectivity: np.ndarray, directors: np.ndarray
) -> np.ndarray:
    """(m,) bool: every corner's director at or past 90 deg from the cell's normal, where
    the fibres x + zeta V through the thickness leave the cell on the side its normal does
    not point to: the cell is mirrored, its volume turned inside out (det of the shell's
    deformation gradient through zero everywhere in it). Its membrane strain, the change of
    the metric, cannot see it: a cell mirrored onto itself keeps its metric. One corner past
    90 deg is a fold sharper than the mesh resolves (a coarse blank's flange wrinkle folded
    over, whose increments converge and whose run goes on; a fold warns from FOLD_TILT_DEG
    on, ``warn_folds``): not refused. Same arguments as ``director_tilt``."""
    return np.all(_corner_cosines(points, connectivity, directors) <= 0.0, axis=1)


def _degrees(cosine: np.ndarray) -> np.ndarray:
    return np.degrees(np.arccos(np.clip(cosine, -1.0, 1.0)))


def _corner_cosines(
    points: np.ndarray, connectivity: np.ndarray, directors: np.ndarray
) -> np.ndarray:
    """V_k . n_e (m, 3) of each corner's director and its cell's unit normal."""
    return np.einsum("mkj,mj->mk", directors[connectivity], _unit_normals(points, connectivity))


def _unit_normals(points: np.ndarray, connectivity: np.ndarray) -> np.ndarray:
    """(m, 3) each cell's unit normal."""
    corners = points[connectivity]
    normal = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    return normal / np.linalg.norm(normal, axis=1, keepdims=True)


def warn_folds(
    points: np.ndarray,
    connectivity: np.ndarray,
    directors: np.ndarray,
    limit: float = FOLD_TILT_DEG,
) -> None:
    """Warn when a node's director leans more than ``limit`` deg from one of its cells' normals.

    Parameters
    ----------
    points, connectivity, directors
        As in ``director_tilt``: the block's reference geometry and directors.
    limit : float, deg
        The largest tilt left silent (default ``FOLD_TILT_DEG``).
    """
    # the usual case, no corner past the limit, costs one pass over the cells at bind
    cosine = _corner_cosines(points, connectivity, directors)
    if not (cosine < np.cos(np.radians(limit))).any():
        return
    tilt = _degrees(cosine)  # director_tilt's, from the cosines already taken
    node_tilt = np.zeros(len(points))
    np.maximum.at(node_tilt, connectivity.ravel(), tilt.ravel())
    folded = np.flatnonzero(node_tilt > limit)
    if folded.size == 0:
        return
    worst = folded[np.argmax(node_tilt[folded])]
    fold = fold_angle(points, connectivity)[worst]
    # the fold may be between this block and another, whose cells share the node's director
    # (its turn is not among this block's cells)
    where = (
        f"where neighbouring cells turn by {fold:.3g} deg"
        if fold >= 0.5 * limit
        else "where the director is shared with cells of another block"
    )
    warnings.warn(
        f"MindlinShell: at {folded.size} nodes the director leans more than {limit:g} deg from "
        f"a cell's normal (up to {node_tilt[worst]:.3g} deg at node {int(worst)}, {where}): "
        "a fold, or a curve meshed coarsely. With "
        "one director and no drilling rotation a fold is partly a hinge and its cells are "
        "thinned to h cos(tilt): on an L cantilever, against beam theory, a fold of 45 deg "
        "errs by +0.57 % at 10 elements a leg, of 90 deg by +4.6 % at 10, +1.6 % at 40 and "
        "+1.8 % at 80, and cells shorter than about h sin(tilt) / 2 are refused "
        "(docs/theory.md §5.9). A fillet of 8 cells over 90 deg (radius h / 2 to 4 h) keeps "
        "the tip within 0.1 % of the beam on its centreline",
        UserWarning,
        stacklevel=2,
    )


def fold_angle(points: np.ndarray, connectivity: np.ndarray) -> np.ndarray:
    """The largest angle between the normals of two cells that share an edge at each node, deg.

    Parameters
    ----------
    points : (n, 3) float, mm
    connectivity : (m, 3) int

    Returns
    -------
    (n,) float, deg
        0 at nodes of a flat part (and at nodes outside ``connectivity``).
    """
    topology = build_topology(connectivity)
    normal = _unit_normals(points, connectivity)
    pairs = topology.edge_triangles
    inner = pairs[:, 1] >= 0
    cosine = np.sum(normal[pairs[inner, 0]] * normal[pairs[inner, 1]], axis=1)
    turn = _degrees(cosine)
    node_turn = np.zeros(len(points))
    for end in (0, 1):
        np.maximum.at(node_turn, topology.edges[inner, end], turn)
    return node_turn
