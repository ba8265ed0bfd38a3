"""Which triangles of a mesh face the other way from their neighbours: the count and the ids a
message about an inconsistent orientation names, so that a user can find and reverse them.

Two neighbours are consistently oriented when they traverse their shared edge in opposite
directions (femcore.topology.check_orientation). Over a connected surface the relation "same
side" or "other side" between neighbours spreads along the interior edges; on the double cover
of the triangles (each triangle once as it is, once reversed) a consistent pair joins as-is to
as-is and an inconsistent pair as-is to reversed. A surface is orientable when no triangle
reaches its own reversal; the triangles then split in two sides, and the smaller side is the
one to reverse."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

__all__ = ["FacingSides", "facing_sides"]


@dataclass(frozen=True)
class FacingSides:
    """The sides of one connected surface.

    Attributes
    ----------
    surface : (k,) int
        The surface's triangles (rows of the checked triangles), increasing.
    other_way : (j,) int
        Its triangles on the smaller side (the ones to reverse), increasing; empty when the
        surface is not orientable.
    orientable : bool
        Whether reversing ``other_way`` makes the surface consistent (False: a Moebius band,
        which no reversal makes consistent).
    """

    surface: np.ndarray
    other_way: np.ndarray
    orientable: bool


def facing_sides(m: int, pairs: np.ndarray, inconsistent: np.ndarray, triangle: int) -> FacingSides:
    """The sides of the connected surface that holds ``triangle``.

    Parameters
    ----------
    m : int
        How many triangles were checked.
    pairs : (p, 2) int
        The two triangles (rows) of each interior edge.
    inconsistent : (p,) bool
        Whether the pair traverses its edge the same way.
    triangle : int
        A triangle (row) of the surface asked about.
    """
    t0, t1 = pairs[:, 0], pairs[:, 1]
    # double cover: vertex 2 t as given, 2 t + 1 reversed
    flip = inconsistent.astype(np.int64)
    heads = np.concatenate([2 * t0, 2 * t0 + 1])
    tails = np.concatenate([2 * t1 + flip, 2 * t1 + 1 - flip])
    cover = coo_matrix((np.ones(len(heads)), (heads, tails)), shape=(2 * m, 2 * m))
    _, sides = connected_components(cover, directed=False)
    plain = coo_matrix((np.ones(len(t0)), (t0, t1)), shape=(m, m))
    _, surfaces = connected_components(plain, directed=False)
    surface = np.flatnonzero(surfaces == surfaces[triangle])
    as_given, reversed_ = sides[2 * surface], sides[2 * surface + 1]
    if np.any(as_given == reversed_):
        return FacingSides(surface, np.zeros(0, dtype=np.int64), False)
    with_first = as_given == as_given[0]
    smaller = ~with_first if np.count_nonzero(~with_first) <= len(surface) / 2 else with_first
    return FacingSides(surface, surface[smaller], True)
