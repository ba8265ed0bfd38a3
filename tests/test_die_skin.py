"""The meshed die's candidate lists (RigidSurface's Verlet list, elements/rigid_surface.py): on a
blank drawn into the hemisphere die, the distance answered from each node's kept candidates
is the full search's over every facet, to the last bit, at every call; a node moved past the
margin (half the list's skin) is searched again, with it those past REBUILD_SHARE of it, and
no other."""

import numpy as np

from elements import RigidSurface
from elements.facet_search import SLACK, closest_facets
from elements.rigid_surface import MARGIN, REBUILD_SHARE
from femcore.mesh import Mesh
from validation.cases import hemisphere_forming as case
from validation.specimens import hemisphere_die


def coarse_die() -> RigidSurface:
    """The case's die (its bowl, entry radius and flange) with 8 rings of facets."""
    return RigidSurface(hemisphere_die(case.DIE, 1.7 * case.HALF, rings=8, rim=case.DIE_RIM))


def full_search(tool: RigidSurface, x: np.ndarray) -> np.ndarray:
    """The distance (k,) of each point to its closest facet among all of them (the compiled
    closest-point kernel, every facet a candidate, no hint)."""
    start = np.arange(len(x) + 1) * tool.n_facets
    facets = np.tile(np.arange(tool.n_facets), len(x))
    point, facet, gap = x.copy(), np.zeros(len(x), dtype=np.int64), np.zeros(len(x))
    hint = np.full(len(x), -1)
    closest_facets(
        x, tool.corners, tool._centroids, tool._radius, SLACK * tool.reach,
        start, facets, hint, point, facet, gap,
    )  # fmt: skip
    return gap


def test_a_blank_drawn_into_the_die_gets_the_full_searchs_distance_to_the_last_bit():
    """A 16 x 16-cell blank on the flange, its middle pushed down into the bowl a little more
    at each of 40 calls (up to 0.06 mm a call, the steps of an explicit run taken several at
    a time), some nodes jumping 2 mm: for every node within the search distance, the
    distance is the full search's, bit for bit (the same facets' distances, the least of
    them); the normals are unit vectors; the lists were rebuilt (searched again) at some calls
    and kept at others."""
    tool = coarse_die()
    blank = Mesh.rectangle(200.0, 200.0, 16, 16)
    x0 = blank.points - [100.0, 100.0, 0.0]
    x0[:, 2] = 0.5 * case.THICKNESS  # on the flange, half a ply above it
    r = np.linalg.norm(x0[:, :2], axis=1)
    rng = np.random.default_rng(4)
    rebuilt, kept = 0, 0
    for call in range(40):
        depth = 1.2 * call * np.exp(-((r / 45.0) ** 2))  # the punch's dent, mm
        x = x0 - np.column_stack([0 * r, 0 * r, depth])
        x += rng.uniform(-0.02, 0.02, size=x.shape)
        if call % 10 == 9:
            x[rng.choice(len(x), 10, replace=False)] += 2.0
        before = tool._cache
        d, n = tool.distance(x)
        if before is not None:
            if np.any(tool._cache.points != before.points):
                rebuilt += 1
            else:
                kept += 1
        near = ~tool._cache.far
        assert near.sum() > 100
        np.testing.assert_array_equal(np.abs(d[near]), full_search(tool, x[near]))
        np.testing.assert_allclose(np.linalg.norm(n, axis=1), 1.0, atol=1e-12)
    assert rebuilt > 3 and kept > 3


def test_a_node_moved_past_half_the_skin_is_searched_again_with_those_nearly_past():
    """Four nodes on the flange: one moved just past the margin (MARGIN / sqrt(3) circumradius
    along x), one past REBUILD_SHARE of it, one below that; then all moved back less than the
    margin. The first call searches the first two again and keeps the third's list; a call
    where no node is past the margin searches none."""
    tool = coarse_die()
    x = np.array([[80.0, 0.0, 0.0], [0.0, 80.0, 0.0], [-80.0, 0.0, 0.0], [0.0, -80.0, 0.0]])
    x[:, 2] = 0.5 * case.THICKNESS
    tool.distance(x)
    limit = MARGIN / np.sqrt(3.0) * tool.reach
    moved = x.copy()
    moved[0, 0] += 1.001 * limit
    moved[1, 0] += 1.001 * REBUILD_SHARE * limit
    moved[2, 0] += 0.999 * REBUILD_SHARE * limit
    before = tool._cache.points.copy()
    tool.distance(moved)
    searched = np.any(tool._cache.points != before, axis=1)
    np.testing.assert_array_equal(searched, [True, True, False, False])
    np.testing.assert_array_equal(tool._cache.points[:2], moved[:2])
    # None past the margin (the third at 0.999 x REBUILD_SHARE, now 1.4 x): none searched.
    before = tool._cache.points.copy()
    nudged = moved.copy()
    nudged[2, 0] += 0.4 * REBUILD_SHARE * limit
    tool.distance(nudged)
    np.testing.assert_array_equal(tool._cache.points, before)
