"""The patches of the in-plane fibre bending (docs/theory.md §4.7): for each fibre family, each
pair of cells whose fibre edges are consecutive segments of one fibre, on one side of it.

The fibrous shell's triangles have one edge along each fibre family (Bai Eq. 9), so each
family's fibres are chains of mesh edges, and a cell's edge along the family is a material
segment of a fibre: its current direction is the fibre's there. At a node i inside a fibre,
the segment ending at i and the segment starting at i each bound one cell on either side of
the fibre; the two cells on the same side are a patch, five nodes: the segments' ends
(s, i, e) and the two cells' third corners. A fibre inside the blank has two patches at each
of its inner nodes, one on each side; a fibre on the blank's edge one.

The patches are found over all the fibrous blocks' cells together, so a fibre that runs from
one block into another on shared nodes is bent where it crosses. Cells pair only within one
``group`` (``warp_groups``: blocks whose warps agree, either way along the line, are one group,
their warps turned one way): where two blocks' warps differ, their fibres are different tows
meeting at a seam, not one fibre continued, and no patch spans the seam.

Everything here runs once, at bind, vectorised over the cells.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = ["FibrePatches", "fibre_patches", "warp_groups"]

# Local edge k of a triangle runs from corner EDGE_FROM[k] to EDGE_TO[k].
EDGE_FROM = np.array([0, 1, 2])
EDGE_TO = np.array([1, 2, 0])


class FibrePatches(NamedTuple):
    """The patches of one or more fibre families.

    Attributes
    ----------
    nodes : (P, 5) int
        Global node ids: s, i, e along the fibre (the segments s -> i and i -> e point along
        the family's direction), the first cell's third corner, the second cell's.
    ends : (P, 4, 2) int
        Local indices (into a row of ``nodes``) of the ends (from, to) of the four vectors
        of a patch: the first cell's fibre segment m_c (s -> i), its edge along the other
        family p_c (pointing along the other family's direction), the second cell's fibre
        segment m_f (i -> e) and its other edge p_f.
    stiffness : (P,) float, N mm
        k = B_in A / s^2 of each patch: its energy is 1/2 k theta^2 (A the mean of the two
        cells' reference areas, s the mean of the two segments' reference lengths).
    family : (P,) int
        0 for the warp, 1 for the weft.
    """

    nodes: np.ndarray
    ends: np.ndarray
    stiffness: np.ndarray
    family: np.ndarray


def _oriented_edge(
    points: np.ndarray,
    cells: np.ndarray,
    direction: np.ndarray,
    tolerance_deg: np.ndarray,
    name: str,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per cell, its edge along ``direction`` (m, 3) oriented along it: (from node, to node,
    local index of the third corner), all (m,) int. ValueError when a cell has no edge within
    ``tolerance_deg`` (m,) of the direction (the fibrous shell's Eq. 9 meshes always have
    one)."""
    vectors = points[cells[:, EDGE_TO]] - points[cells[:, EDGE_FROM]]  # (m, 3 edges, 3)
    lengths = np.linalg.norm(vectors, axis=2)
    along = np.einsum("mkj,mj->mk", vectors, direction) / lengths
    edge = np.argmax(np.abs(along), axis=1)
    rows = np.arange(len(cells))
    best = np.abs(along[rows, edge])
    if np.any(best < np.cos(np.radians(tolerance_deg))):
        bad = int(np.flatnonzero(best < np.cos(np.radians(tolerance_deg)))[0])
        raise ValueError(
            f"in-plane fibre bending: cell {bad} has no edge within {tolerance_deg[bad]} deg of "
            f"the {name} (its edges' cosines {np.abs(along[bad]).round(4).tolist()}); the fibrous "
            "shell's cells need one edge along each fibre family (Bai Eq. 9)"
        )
    forward = along[rows, edge] > 0.0
    start = np.where(forward, EDGE_FROM[edge], EDGE_TO[edge])
    end = np.where(forward, EDGE_TO[edge], EDGE_FROM[edge])
    third = 3 - EDGE_FROM[edge] - EDGE_TO[edge]
    return cells[rows, start], cells[rows, end], third


def _column_of(nodes: np.ndarray, node_ids: np.ndarray, columns: tuple[int, ...]) -> np.ndarray:
    """Per row of ``nodes`` (P, 5), which of ``columns`` holds ``node_ids`` (P,) (a cell's
    corners: one does)."""
    out = np.full(len(node_ids), -1)
    for column in columns:
        out = np.where(nodes[:, column] == node_ids, column, out)
    return out


def _unique_keys(node: np.ndarray, keys: np.ndarray, what: str) -> None:
    """ValueError when two cells share a pairing key (a node, a side, a group): a mesh that
    does not conform there or a cell listed in two blocks, where pairing by key would pick one
    of them silently."""
    _, first, counts = np.unique(keys, return_index=True, return_counts=True)
    if np.any(counts > 1):
        where = int(node[first[counts > 1][0]])
        raise ValueError(
            f"in-plane fibre bending: two cells' fibre segments {what} node {where} on the same "
            "side of the fibre; the fibrous cells must form a conforming, consistently oriented "
            "mesh, each cell in one block"
        )


def warp_groups(warps: np.ndarray, tolerances_deg: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The blocks whose fibres continue each other's: (group (b,) int, sign (b,) +-1.0).

    Two blocks agree when their warps' lines are within the smaller of their two tolerances,
    |cos| >= cos(min(tol_a, tol_b)): the membrane reads a fibre's line, not its sense, so a
    warp given as -x is the +x tows. The groups are the connected sets of agreeing blocks, the
    same in any order of the blocks (a chain each within tolerance of the next is one group,
    its neighbours' tows continuing each other's). ``sign`` turns each block's warp to its
    group's first block's sense along the chain, so that the fibre segments of all a group's
    cells point one way (``fibre_patches`` orients them by the warp it is given).

    Parameters
    ----------
    warps : (b, 3) float
        Each block's warp direction (any length).
    tolerances_deg : (b,) float
        Each block's fibre angle tolerance, degrees.
    """
    unit = np.asarray(warps, dtype=float)
    unit = unit / np.linalg.norm(unit, axis=1)[:, None]
    cosine = unit @ unit.T
    tolerance = np.radians(np.asarray(tolerances_deg, dtype=float))
    agree = np.abs(cosine) >= np.cos(np.minimum.outer(tolerance, tolerance))
    group = np.full(len(unit), -1)
    sign = np.ones(len(unit))
    for first in range(len(unit)):  # a walk over the blocks, once at bind
        if group[first] >= 0:
            continue
        group[first] = group.max() + 1
        reached = [first]
        while reached:
            block = reached.pop()
            for other in np.flatnonzero(agree[block] & (group < 0)):
                group[other] = group[first]
                sign[other] = sign[block] * (1.0 if cosine[block, other] >= 0.0 else -1.0)
                reached.append(int(other))
    return group, sign


def fibre_patches(
    points: np.ndarray,
    cells: np.ndarray,
    warp: np.ndarray,
    stiffness: float,
    families: tuple[int, ...] = (0, 1),
    tolerance_deg: float | np.ndarray = 1.0,
    group: np.ndarray | None = None,
) -> FibrePatches:
    """The patches of the fibre families ``families`` (0 warp, 1 weft) over ``cells``.

    Parameters
    ----------
    points : (n, 3) float, mm
        Reference node positions.
    cells : (m, 3) int
        The fibrous triangles.
    warp : (3,) or (m, 3) float
        The warp direction, one or per cell (projected on each cell's plane; the weft is the
        in-plane perpendicular n x warp, as in the fibrous shell).
    stiffness : float
        B_in, N mm (a moment per unit width per unit curvature).
    families : tuple of int
        The fibre families bent.
    tolerance_deg : float or (m,) float
        How far a cell's fibre edge may deviate from its family's direction, degrees.
    group : (m,) int, optional
        Cells pair only with cells of their own group (all one group by default).

    Raises
    ------
    ValueError
        When a cell has no edge along a family, or two cells share a pairing key.
    """
    cells = np.asarray(cells, dtype=np.int64)
    tolerance = np.broadcast_to(np.asarray(tolerance_deg, dtype=float), (len(cells),))
    group = np.zeros(len(cells), np.int64) if group is None else np.asarray(group, np.int64)
    groups = int(group.max()) + 1 if len(group) else 1
    corners = points[cells]
    normal = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    double_area = np.linalg.norm(normal, axis=1)
    normal /= double_area[:, None]
    warp = np.broadcast_to(np.asarray(warp, dtype=float), (len(cells), 3))
    a = warp - np.einsum("mj,mj->m", normal, warp)[:, None] * normal
    a /= np.linalg.norm(a, axis=1)[:, None]
    b = np.cross(normal, a)
    directions = (a, b)
    names = ("warp", "weft")
    rows = np.arange(len(cells))
    parts = []
    for family in families:
        own, other = directions[family], directions[1 - family]
        start, end, third = _oriented_edge(points, cells, own, tolerance, names[family])
        p_from, p_to, _ = _oriented_edge(points, cells, other, tolerance, names[1 - family])
        tip = cells[rows, third]
        side = np.einsum("mj,mj->m", points[tip] - points[start], other) > 0.0
        # The cell whose segment ends at node i meets the one whose segment starts there, on
        # the same side of the fibre, in the same group: a key (node, group, side) each,
        # unique in a conforming mesh.
        ends_key = 2 * (end * groups + group) + side
        starts_key = 2 * (start * groups + group) + side
        _unique_keys(ends_key // (2 * groups), ends_key, "end at")
        _unique_keys(starts_key // (2 * groups), starts_key, "start at")
        _, first, second = np.intersect1d(ends_key, starts_key, return_indices=True)
        if first.size == 0:
            continue
        nodes = np.column_stack((start[first], end[first], end[second], tip[first], tip[second]))
        ends = np.empty((len(first), 4, 2), dtype=np.int64)
        ends[:, 0] = (0, 1)
        ends[:, 1, 0] = _column_of(nodes, p_from[first], (0, 1, 3))
        ends[:, 1, 1] = _column_of(nodes, p_to[first], (0, 1, 3))
        ends[:, 2] = (1, 2)
        ends[:, 3, 0] = _column_of(nodes, p_from[second], (1, 2, 4))
        ends[:, 3, 1] = _column_of(nodes, p_to[second], (1, 2, 4))
        segment = 0.5 * (
            np.linalg.norm(points[nodes[:, 1]] - points[nodes[:, 0]], axis=1)
            + np.linalg.norm(points[nodes[:, 2]] - points[nodes[:, 1]], axis=1)
        )
        area = 0.25 * (double_area[first] + double_area[second])
        parts.append((nodes, ends, stiffness * area / segment**2, np.full(len(first), family)))
    if not parts:
        empty = np.zeros((0,), dtype=np.int64)
        return FibrePatches(
            np.zeros((0, 5), np.int64), np.zeros((0, 4, 2), np.int64), np.zeros(0), empty
        )
    return FibrePatches(*(np.concatenate(column) for column in zip(*parts, strict=True)))
