"""The ply springs' compiled passes (elements/ply_springs_kernels.py) against the numpy
expressions they replace in ``ply_springs.reachable_springs`` and ``_node_weights``: the
points near the outline (``near_outline``: the points facing a rim triangle or past an edge,
the outline's nearest edge by ``ply_fade.nearest_segments``, the distance by
``ply_springs._distance``), flag for flag, and the points' loads spread on the nodes
(``spread_loads``: two bincounts and the ring's CSR product) and their sizes and loads
(``held_points``: the fade's factor, the points counted, the clipped weights), to the bit.

The flags compare a distance with the slide plus the gap, so a pass that rounded the distance
otherwise would differ only at the threshold: each draw puts the threshold exactly on the
numpy distance of some asked points (their gap 0, the slide that distance), where one ulp
either way flips the flag. The draws hold NaN weights, gaps and face points, outline edges of
zero length, ties between edges, and points far off the outline.
"""

import numpy as np
import pytest

from elements import ply_springs, ply_springs_kernels
from elements.ply_fade import OutlineTree, nearest_segments


def _numpy_flags(face, triangle, weights, rim, gap, starts, ends, slide):
    """``reachable_springs``' numpy path for ``near_edge``."""
    asked = np.flatnonzero(rim[triangle] | np.any(weights < 0.0, axis=1))
    nearest = nearest_segments(face[asked], starts, ends, OutlineTree())
    segments = np.stack([starts, ends], axis=1)
    flags = np.zeros(len(weights), bool)
    flags[asked] = ply_springs._distance(face[asked], segments[nearest]) <= slide + np.abs(
        gap[asked]
    )
    return flags, asked, nearest


def _draw(rng, points=300, triangles=40, edges=25):
    face = rng.uniform(-10.0, 10.0, (points, 3))
    triangle = rng.integers(0, triangles, points)
    weights = rng.uniform(-0.3, 1.0, (points, 3))
    rim = rng.random(triangles) < 0.4
    gap = rng.normal(0.0, 0.3, points)
    starts = rng.uniform(-10.0, 10.0, (edges, 3))
    ends = starts + rng.normal(0.0, 3.0, (edges, 3))
    ends[0] = starts[0]  # an edge of zero length
    starts[1], ends[1] = starts[2], ends[2]  # two edges the same: a tie
    weights[3, 1] = np.nan
    gap[4] = np.nan
    face[5, 2] = np.nan
    weights[5] = -0.1  # asked, with a NaN face point
    return face, triangle, weights, rim, gap, starts, ends


@pytest.mark.parametrize("seed", range(6))
def test_the_near_outline_pass_gives_numpy_s_flags_at_the_threshold(seed):
    rng = np.random.default_rng(seed)
    face, triangle, weights, rim, gap, starts, ends = _draw(rng)
    slide = 0.7
    flags, asked, nearest = _numpy_flags(face, triangle, weights, rim, gap, starts, ends, slide)
    found = ply_springs_kernels.near_outline(face, triangle, weights, rim, gap, starts, ends, slide)
    np.testing.assert_array_equal(found, flags)
    assert 0 < flags.sum() < len(asked) < len(face)  # some near, some asked and far
    # the threshold on the numpy distance of asked points (gap 0): equal, so near
    distance = ply_springs._distance(face[asked], np.stack([starts, ends], axis=1)[nearest])
    finite = np.flatnonzero(np.isfinite(distance))
    for at in rng.choice(finite, 8, replace=False):
        gap_at = gap.copy()
        gap_at[asked[at]] = 0.0
        flags, _, _ = _numpy_flags(face, triangle, weights, rim, gap_at, starts, ends, distance[at])
        assert flags[asked[at]]
        found = ply_springs_kernels.near_outline(
            face, triangle, weights, rim, gap_at, starts, ends, distance[at]
        )
        np.testing.assert_array_equal(found, flags)
        # one ulp below the distance: not near, in both
        below = np.nextafter(distance[at], 0.0)
        flags, _, _ = _numpy_flags(face, triangle, weights, rim, gap_at, starts, ends, below)
        assert not flags[asked[at]]
        found = ply_springs_kernels.near_outline(
            face, triangle, weights, rim, gap_at, starts, ends, below
        )
        np.testing.assert_array_equal(found, flags)


def test_points_neither_on_the_rim_nor_past_an_edge_are_not_near():
    """However near the outline, a point facing an inner triangle from inside it is not
    asked (it lies a height from the outline): False, as the numpy path leaves it."""
    face = np.zeros((2, 3))
    starts, ends = np.array([[0.0, 0.0, 0.0]]), np.array([[1.0, 0.0, 0.0]])
    weights = np.array([[0.2, 0.3, 0.5], [0.2, -0.1, 0.9]])
    found = ply_springs_kernels.near_outline(
        face, np.array([0, 0]), weights, np.array([False]), np.zeros(2), starts, ends, 1.0
    )
    np.testing.assert_array_equal(found, [False, True])


def _grid_cells(count=4):
    """The triangles of a count x count grid of squares, two a square (nodes row by row)."""
    cells = []
    for i in range(count):
        for j in range(count):
            a, b = i * (count + 1) + j, i * (count + 1) + j + 1
            c, d = a + count + 1, b + count + 1
            cells += [[a, b, d], [a, d, c]]
    return np.array(cells)


@pytest.mark.parametrize("seed", range(4))
def test_the_spread_loads_pass_gives_numpy_s_sums_to_the_bit(seed):
    """``spread_loads`` against ``reachable_springs``' numpy sums (``_lumped``'s and the
    facing corners' bincounts, the ring's CSR product of the loads per triangle): loads over
    twelve decades, so that another order of the sums would round otherwise."""
    rng = np.random.default_rng(seed)
    cells = _grid_cells()
    lower_nodes = np.unique(cells)
    nodes = len(lower_nodes) + 20  # the upper ply's 20 nodes after the lower ones
    points = 200
    load = rng.uniform(0.0, 1.0, points) * 10.0 ** rng.uniform(-6, 6, points)
    shape = rng.dirichlet(np.ones(3), points)
    above = rng.integers(len(lower_nodes), nodes, (points, 3))
    size = rng.uniform(0.0, 1.2, (points, 3))
    triangle = rng.integers(0, len(cells), points)
    ring = ply_springs.ring_matrix(cells, lower_nodes)
    lumped, at, ringed = ply_springs_kernels.spread_loads(
        load, shape, above, size, cells, triangle, ring.indptr.astype(np.int64),
        ring.indices.astype(np.int64), ring.data.astype(float), nodes,
    )  # fmt: skip
    np.testing.assert_array_equal(
        lumped, np.bincount(above.ravel(), (shape * load[:, None]).ravel(), nodes)
    )
    np.testing.assert_array_equal(
        at, np.bincount(cells[triangle].ravel(), (load[:, None] * size).ravel(), nodes)
    )
    np.testing.assert_array_equal(ringed, ring @ np.bincount(triangle, load, len(cells)))
    # the sums do round: summed in reverse the ring's would differ
    assert not np.array_equal(
        ringed, ring @ np.bincount(triangle[::-1], load[::-1], len(cells))
    ) or not np.array_equal(at, np.bincount(
        cells[triangle[::-1]].ravel(), (load[::-1, None] * size[::-1]).ravel(), nodes
    ))  # fmt: skip


@pytest.mark.parametrize("seed", range(4))
def test_the_held_points_pass_gives_numpy_s_sizes_and_loads_to_the_bit(seed):
    """``held_points`` against ``reachable_springs``' numpy (the fade's factor by
    ``ply_fade.stiffness_factor``, the points counted, the weights clipped beside a growth,
    |lambda| + delta and c_p k_p), with NaN weights, gaps and depths, points on the slide's
    threshold and on the reach's."""
    from elements.ply_fade import stiffness_factor
    from elements.ply_projection import MARGIN

    rng = np.random.default_rng(seed)
    points, slide, delta, faded = 400, 0.3, 0.05, 1.7
    past, beside = rng.random(points) < 0.3, rng.random(points) < 0.2
    reached = rng.uniform(0.1, 3.0, points)
    gap = rng.normal(0.0, 0.5, points)
    weights = rng.uniform(-0.5, 1.3, (points, 3))
    reach = rng.uniform(0.0, 0.3, (points, 3))
    stiffness = rng.uniform(1.0, 1e4, points)
    gap[:10] = slide  # on the threshold: not counted
    weights[10:20, 0] = -(reach[10:20, 0] + delta)  # on the reach: counted
    weights[20, 1], gap[21], reached[22] = np.nan, np.nan, np.nan
    beside[20] = True
    factor = stiffness_factor(past, beside, reached, faded)
    counted = (gap < slide) & (beside | ~np.any(weights < -(reach + delta), axis=1))
    clipped = np.where(beside[:, None], np.clip(weights, -MARGIN, 1.0 + 2.0 * MARGIN), weights)
    size, held = ply_springs_kernels.held_points(
        past, beside, reached, faded, gap, slide, weights, reach, delta, stiffness, MARGIN
    )
    np.testing.assert_array_equal(size, np.abs(clipped) + delta)
    np.testing.assert_array_equal(held, np.where(counted, stiffness * factor, 0.0))
    assert 0 < counted.sum() < points and np.isnan(size[20, 1])
