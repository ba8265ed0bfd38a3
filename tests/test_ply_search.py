"""The ply contact's facing search (elements/ply_search.py): each point's candidate triangles
hold its nearest one, proven, where the nearest centroids miss it (a wrinkle's flank), and
the lists kept between calls answer as a search over every triangle would.

References: the distance from a point to a plane (closed form) and a brute-force search,
Ericson's closest point (elements/facet_search.closest_on_triangles) on every triangle of the
lower face, grown past its outline as the contact grows it.
"""

from __future__ import annotations

import copy

import numpy as np
import pytest
from scipy.spatial import cKDTree

from elements import ply_search
from elements.facet_search import closest_on_triangles
from elements.kernel_inputs import read_only
from elements.layup import Layup
from elements.ply_projection import MARGIN, closest_facing, edge_ids, grown_corners, open_edges
from elements.ply_search import FacingSearch
from elements.ply_wedge import WedgeCuts, closest_on_grown
from femcore.state import State
from materials import Fabric

PLY = Fabric(thickness=0.3, areal_density=2.85e-10, tension=60.0, shear=0.2, bending=0.375)
HEIGHT = 40.0  # mm, the wrinkle's crest above the ply
CLEAR = 0.1  # mm, the point's distance from the wrinkle's flank


def _brute_nearest(
    p: np.ndarray, y: np.ndarray, reach: np.ndarray, cuts: WedgeCuts | None = None
) -> np.ndarray:
    """(P,) each point's nearest grown triangle over all of them (the lowest row of ties),
    cut where ``cuts`` cuts it (elements/ply_wedge.py: the closest point of the cut growth)."""
    corners = grown_corners(y, reach)[None]  # (1, m, 3, 3) against p (P, 1, 3)
    point = p[:, None, :]
    q = closest_on_triangles(point, corners[..., 0, :], corners[..., 1, :], corners[..., 2, :])
    distance = np.linalg.norm(point - q, axis=-1)
    if cuts is not None:
        rows = np.flatnonzero(np.any(cuts.lines != 0.0, axis=(1, 2)))
        pairs = np.array(np.meshgrid(np.arange(len(p)), rows, indexing="ij")).reshape(2, -1)
        at = closest_on_grown(
            p[pairs[0]], y[pairs[1]], reach[pairs[1]], cuts.lines[pairs[1]], cuts.ends[pairs[1]]
        )[0]
        distance[pairs[0], pairs[1]] = np.linalg.norm(p[pairs[0]] - at, axis=1)
    return np.argmin(distance, axis=1)


def test_a_point_beside_a_wrinkle_faces_its_nearest_triangle():
    """Two 40-mm plies of 10-mm cells, the bottom one raised into a wrinkle 40 mm high along
    x = 0 (its flanks z = 40 (1 - |x| / 10): triangles stretched 4:1 up the flank); a node of
    the top ply moved to 0.1 mm off the flank's face along its normal at (-8, -0.5). Its
    facing triangle is the brute force's nearest and its gap the distance to the flank's plane,
    +0.1 mm (1e-9). The premise: that triangle's centroid is not among the point's 6 nearest
    centroids; the search of before (candidates=6) faced another triangle, 0.5 mm off."""
    layup = Layup(PLY, (0.0, 0.0), 40.0, cells=4, rule="nodes", faces="director")
    block = layup.model().compile().interactions[0]
    x = layup.mesh.points.copy()
    bottom, top = layup.ply_nodes
    x[bottom, 2] += HEIGHT * np.clip(1.0 - np.abs(x[bottom, 0]) / 10.0, 0.0, None)
    half = 0.5 * PLY.thickness
    face = layup.heights[0] + half  # the bottom ply's face off the wrinkle
    normal = np.array([-HEIGHT / 10.0, 0.0, 1.0]) / np.hypot(HEIGHT / 10.0, 1.0)
    node = top[np.argmin(np.linalg.norm(x[top, :2] - [0.0, -10.0], axis=1))]
    on_flank = np.array([-8.0, -0.5, face + HEIGHT * (1.0 - 8.0 / 10.0)])
    x[node] = on_flank + CLEAR * normal + [0.0, 0.0, half]
    directors = np.tile([0.0, 0.0, 1.0], (len(x), 1))
    state = State(x, directors, np.zeros_like(x), np.zeros_like(x))
    point = int(np.flatnonzero(block.above[np.arange(len(block.above)), 0] == node)[0])
    p, y = block._faces(state)
    nearest = _brute_nearest(p[[point]], y, np.where(block.outline, MARGIN, 0.0))[0]
    six = cKDTree(y.mean(axis=1)).query(p[point], k=6)[1]
    assert nearest not in six  # the premise
    facing = block.facing(state)
    assert facing.triangle[point] == nearest
    assert abs(facing.gap[point] - CLEAR) < 1e-9


def _crumpled(cells: int, rng: np.random.Generator):
    """A square sheet of ``cells`` x ``cells`` 10-mm squares, each split into two triangles,
    its nodes raised by N(0, 6 mm): (node positions (v, 3), triangles (m, 3))."""
    u = np.arange(cells + 1) * 10.0
    gx, gy = np.meshgrid(u, u, indexing="ij")
    nodes = np.column_stack([gx.ravel(), gy.ravel(), rng.normal(0.0, 6.0, gx.size)])
    k = np.arange(cells + 1) * (cells + 1)
    a = (k[:-1, None] + np.arange(cells)[None, :]).ravel()  # the squares' lower-left nodes
    b, c, d = a + (cells + 1), a + (cells + 2), a + 1
    triangles = np.vstack([np.column_stack([a, b, c]), np.column_stack([a, c, d])])
    return nodes, triangles


def _sheet_and_points(rng: np.random.Generator, cells: int, count: int, cut: bool):
    """``_crumpled(cells)``, its outline and growths' reach, its wedge cuts if ``cut`` (the
    premise: some triangles are cut), its FacingSearch, and ``count`` points over it within
    N(0, 8 mm) of its plane: (nodes, triangles, outline, reach, cuts, search, points)."""
    nodes, triangles = _crumpled(cells, rng)
    outline = open_edges(triangles)
    reach = np.where(outline, MARGIN, 0.0)
    cuts = WedgeCuts.of(nodes[triangles], triangles, outline, reach) if cut else None
    assert not cut or (cuts is not None and cuts.any)
    search = FacingSearch.of(nodes[triangles], outline, cuts)
    side = 10.0 * cells + 5.0
    p = np.column_stack(
        [
            rng.uniform(-5.0, side, count),
            rng.uniform(-5.0, side, count),
            rng.normal(0.0, 8.0, count),
        ]
    )
    return nodes, triangles, outline, reach, cuts, search, p


@pytest.mark.parametrize("cut", [False, True], ids=["grown", "cut"])
@pytest.mark.parametrize("seed", [0, 1])
def test_kept_lists_answer_as_a_search_over_every_triangle(seed, cut):
    """A crumpled sheet (10-mm cells, nodes raised by N(0, 6 mm)) and 300 points within 8 mm
    of it, both moved over 40 calls by random steps (mostly a five-hundredth of a cell, every
    tenth call a fifth): at every call each point's candidates hold the brute force's nearest
    triangle, and the facing (triangle, gap, normal, projection, touching, fade) is bit for
    bit that of ``closest_facing`` with every triangle a candidate. The lists are kept over
    most calls (fewer searches than calls), and on the sheet the 6 nearest centroids miss the
    nearest triangle of some points (the premise). ``cut``: the growths cut past the sheet's
    outline vertices of three triangles (elements/ply_wedge.py, fixed at the first state),
    the search's distances and the brute force's to the cut growths (the premise: some
    triangles are cut)."""
    rng = np.random.default_rng(seed)
    nodes, triangles, outline, reach, cuts, search, p = _sheet_and_points(rng, 8, 300, cut)
    edges = edge_ids(triangles)
    every = np.tile(np.arange(len(triangles)), (len(p), 1))
    missed = 0
    calls = 40
    for call in range(calls):
        size = 2.0 if call % 10 == 9 else 0.02
        nodes = nodes + rng.normal(0.0, size / 3.0, nodes.shape)
        p = p + rng.normal(0.0, size / 3.0, p.shape)
        y = nodes[triangles]
        near = search.near(p, y)
        nearest = _brute_nearest(p, y, reach, cuts)
        assert np.all(np.any(near == nearest[:, None], axis=1)), call
        found = closest_facing(p, y, near, 0.0, outline, nodes=triangles, edges=edges, cuts=cuts)
        truth = closest_facing(p, y, every, 0.0, outline, nodes=triangles, edges=edges, cuts=cuts)
        for name in ("triangle", "gap", "normal", "weights", "touching", "fade"):
            assert np.array_equal(getattr(found, name), getattr(truth, name)), (call, name)
        six = cKDTree(y.mean(axis=1)).query(p, k=6)[1]
        missed += int(np.sum(~np.any(six == nearest[:, None], axis=1)))
    assert search.searches < calls
    assert missed > 0


def test_the_compiled_pair_distances_match_the_numpy_closest_point():
    """``pair_distances`` (compiled) against ``grown_distance`` (numpy, Ericson's closest
    point): 2000 random points and triangles, every Voronoi region of a triangle visited,
    within 1e-12 mm."""
    from elements.ply_search import grown_distance, pair_distances

    rng = np.random.default_rng(3)
    corners = rng.normal(0.0, 10.0, (50, 3, 3))
    x = rng.normal(0.0, 15.0, (400, 3))
    point = rng.integers(0, len(x), 2000)
    triangle = rng.integers(0, len(corners), 2000)
    compiled = pair_distances(x, corners, point, triangle)
    reference = grown_distance(x[point], corners[triangle])
    assert np.max(np.abs(compiled - reference)) < 1e-12


@pytest.mark.parametrize("seed", [0, 1])
def test_a_curved_face_answers_the_same_whatever_the_calls_before(seed):
    # The curved faces choose among every listed patch that holds the projection, not only
    # the nearest: a kept list (within s of the nearest when it was made) would make the
    # facing depend on the history of calls (measured: a point facing triangle 84 at a gap of
    # -1.31 mm after 46 calls, triangle 98 at -0.16 mm from a fresh search of the same state).
    # Plies crumpled by N(0, 1.5 mm), moved by small and large steps, then states revisited.
    layup = Layup(PLY, (0.0, 0.0), 40.0, cells=8, rule="gauss", faces="normal", surface="curved")
    block = layup.model().compile().interactions[0]
    # A block never asked, copied for each fresh search: no call before it, as a model
    # compiled again (12 ms a compile, 0.1 ms a copy; the same answers to the bit on every
    # state of both seeds).
    unasked = layup.model().compile().interactions[0]
    rng = np.random.default_rng(seed)
    x = layup.mesh.points.copy()
    bottom, top = layup.ply_nodes
    x[bottom, 2] += rng.normal(0.0, 1.5, len(bottom))
    rng.normal(0.0, 1.5, len(top))  # the top ply left flat; the draws of the measured runs
    directors = np.tile([0.0, 0.0, 1.0], (len(x), 1))
    states = []
    for call in range(60):
        x = x + rng.normal(0.0, (1.0 if call % 7 == 6 else 0.002) / 3.0, x.shape)
        states.append(State(x.copy(), directors, np.zeros_like(x), np.zeros_like(x)))
    for i in [*range(60), 3, 20, 5, 59, 0, 40, 41]:
        block._facing_at = None  # the last state's answer, kept by value: asked anew
        after_calls = block.facing(states[i])
        fresh = copy.deepcopy(unasked).facing(states[i])
        for name in ("triangle", "gap", "normal", "weights", "touching"):
            assert np.array_equal(getattr(after_calls, name), getattr(fresh, name), equal_nan=True)


def _search_as_before(search: FacingSearch, p: np.ndarray, y: np.ndarray, measured: list):
    """``search``'s lists of every point at (p, y) as the search made them before: the pairs
    from k-d trees, every cut pair measured to its cut growth (its rows counted in
    ``measured``)."""
    distances = FacingSearch._distances

    def every_cut(self, x, y, corners, point, triangle, beyond=None, grown=None):
        return distances(self, x, y, corners, point, triangle)

    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(ply_search, "EVERY_PAIR", 0)
        patch.setattr(ply_search, "EVERY_PAIR_NUMPY", 0)
        patch.setattr(FacingSearch, "_distances", every_cut)
        return _counted(search, p, y, measured, patch)


def _counted(search, p, y, measured, patch):
    """``search._search`` of every point, the rows it measures to a cut growth appended to
    ``measured``."""
    grown = ply_search.closest_on_grown

    def counting(x, *args):
        measured.append(len(x))
        return grown(x, *args)

    patch.setattr(ply_search, "closest_on_grown", counting)
    return search._search(p, y, np.arange(len(p)))


@pytest.mark.parametrize("cut", [False, True], ids=["grown", "cut"])
@pytest.mark.parametrize("seed", [0, 1])
def test_a_small_search_lists_as_the_trees_did(seed, cut):
    """A crumpled sheet of 6 x 6 10-mm cells (72 triangles) and 100 points within 8 mm of
    it, both moved over 12 calls by steps of 2 mm (a Newton iterate's jump, past the skin):
    the search of every point, its pairs from one matrix of the centroids' distances and its
    cut triangles measured to their cut growths only where their grown distance is within
    U + s, lists the same triangles (the same arrays) as the search before (the pairs from
    k-d trees, every cut pair measured). The premises: the points times triangles are within
    ``EVERY_PAIR``, and with cuts the search before measured more cut pairs."""
    rng = np.random.default_rng(seed)
    nodes, triangles, _, _, _, search, p = _sheet_and_points(rng, 6, 100, cut)
    assert len(p) * len(triangles) <= ply_search.EVERY_PAIR
    now: list[int] = []
    before: list[int] = []
    for call in range(12):
        nodes = nodes + rng.normal(0.0, 2.0 / 3.0, nodes.shape)
        p = p + rng.normal(0.0, 2.0 / 3.0, p.shape)
        y = nodes[triangles]
        with pytest.MonkeyPatch.context() as patch:
            near, count = _counted(search, p, y, now, patch)
        near_before, count_before = _search_as_before(search, p, y, before)
        assert np.array_equal(count, count_before), call
        assert np.array_equal(near, near_before), call
    assert not cut or sum(now) < sum(before)


@pytest.mark.parametrize("cut", [False, True], ids=["grown", "cut"])
def test_a_search_of_the_two_ply_hemispheres_size_lists_as_the_trees_did(cut):
    """384 points over a crumpled sheet of 8 x 8 cells (128 triangles: the two-ply
    hemisphere's upper pass, whose full searches took the trees before ``EVERY_PAIR`` was
    raised), moved over 3 calls by steps of 2 mm: the matrix's search lists the same
    triangles as the trees' search before (every cut pair measured). The premise: the size is
    within ``EVERY_PAIR`` now and was past its former 16384."""
    rng = np.random.default_rng(3)
    nodes, triangles, _, _, _, search, p = _sheet_and_points(rng, 8, 384, cut)
    assert 16384 < len(p) * len(triangles) <= ply_search.EVERY_PAIR
    for call in range(3):
        nodes = nodes + rng.normal(0.0, 2.0 / 3.0, nodes.shape)
        p = p + rng.normal(0.0, 2.0 / 3.0, p.shape)
        y = nodes[triangles]
        with pytest.MonkeyPatch.context() as patch:
            near, count = _counted(search, p, y, [], patch)
        near_before, count_before = _search_as_before(search, p, y, [])
        assert np.array_equal(count, count_before), call
        assert np.array_equal(near, near_before), call


@pytest.mark.parametrize("epoch_share", [ply_search.EPOCH_SHARE, 10.0])
def test_a_triangle_that_comes_near_while_the_mean_move_stays_small_joins_the_list(
    epoch_share, monkeypatch
):
    """Three 2-mm triangles in planes z = 0, 3.2 and, 100 mm away, 0, a point at z = 1 and a
    skin of 1 mm: the list holds the triangle 1 mm below, not the one 2.2 mm above. The upper
    triangle then comes down by 1.5 mm while the far one rises by 1.5 mm (their moves cancel
    in the mean): the upper one, 0.7 mm from the point, is now its nearest (the planes'
    distances) and must be in its list, whatever the epoch's share of the skin (any share
    answers the same, elements/ply_search.py; at 10 skins no new epoch starts and the
    points' own bound must see the move). A bound that left out the triangles' moves would
    keep the old list."""
    monkeypatch.setattr(ply_search, "EPOCH_SHARE", epoch_share)
    triangle = np.array([[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [0.0, 1.0, 0.0]])
    y = np.stack([triangle, triangle + [0.0, 0.0, 3.2], triangle + [100.0, 0.0, 0.0]])
    p = np.array([[0.0, 0.0, 1.0]])
    search = FacingSearch(np.zeros((3, 3)), 1.0)
    np.testing.assert_array_equal(search.near(p, y), [[0]])
    moved = y + np.array([[0.0, 0.0, 0.0], [0.0, 0.0, -1.5], [0.0, 0.0, 1.5]])[:, None, :]
    assert 1 in search.near(p, moved)[0]


def test_a_grown_triangles_move_is_its_grown_corners_largest():
    """``grown_moves`` (the kept lists' M, elements/ply_search.py) on 200 random triangles
    grown by 0, MARGIN or 2 MARGIN past each edge and moved by random corner moves: equal to
    the largest move of the corners ``grown_corners`` gives before and after (to 1e-12 mm of
    moves of order 1 mm: their subtraction's rounding), no point of the grown triangle moves
    further (2000 barycentric points each, lambda_k >= -reach_k, summing to one), and never
    more than the bound it replaces, (1 + 2 sum reach) times the corners' largest move."""
    rng = np.random.default_rng(3)
    m = 200
    y0 = rng.normal(0.0, 5.0, (m, 3, 3))
    move = rng.normal(0.0, 1.0, (m, 3, 3))
    reach = MARGIN * rng.integers(0, 3, (m, 3)).astype(float)
    got = ply_search.grown_moves(move, reach)
    corners_moved = grown_corners(y0 + move, reach) - grown_corners(y0, reach)
    want = np.linalg.norm(corners_moved, axis=-1).max(axis=1)
    np.testing.assert_allclose(got, want, rtol=0.0, atol=1e-12)
    # points of the grown triangle: barycentric lambda = (1 + R) mu - reach . (mu, in the
    # triangle) maps the triangle onto the grown one (its corners onto grown_corners')
    mu = rng.dirichlet(np.ones(3), 2000)
    total = reach.sum(axis=1)
    weights = (1.0 + total)[:, None, None] * mu[None] - (mu.sum(axis=1)[None, :, None]) * reach[
        :, None, :
    ]
    points_moved = np.einsum("tpk,tkc->tpc", weights, move)
    assert np.all(np.linalg.norm(points_moved, axis=-1).max(axis=1) <= got * (1.0 + 1e-12))
    old_bound = (1.0 + 2.0 * total) * np.linalg.norm(move, axis=-1).max(axis=1)
    assert np.all(got <= old_bound * (1.0 + 1e-12))
    assert np.any(got < 0.8 * old_bound)  # the premise: tighter on some grown triangles


def test_a_swinging_outline_corner_keeps_the_lists_and_their_answer():
    """Two outline triangles of a 10-mm square (each grown by MARGIN past its two outline
    edges), a point 0.5 mm above the first, a skin of 0.5 mm; the square's far corner rises
    by delta = 0.12 skin. Off the corners' mean move (delta / 6), the old bound, (1 + 2 sum
    reach) = 3 times the far corner's move 5 delta / 6, is 2.5 delta = 0.3 skin, past the
    epoch's s / 4: a new epoch; the grown corners' largest move, 2 (5 delta / 6) + delta / 6 =
    11 delta / 6 = 0.22 skin, is not, and the point's drift (delta / 6 + 0.22 skin) is within
    its bound: the list is kept, and still holds the brute force's nearest triangle."""
    nodes = np.array([[0.0, 0.0, 0.0], [10.0, 0.0, 0.0], [0.0, 10.0, 0.0], [10.0, 10.0, 0.0]])
    triangles = np.array([[0, 1, 2], [1, 3, 2]])
    outline = open_edges(triangles)
    reach = np.where(outline, MARGIN, 0.0)
    search = FacingSearch(reach, 0.5)
    p = np.array([[2.0, 2.0, 0.5]])
    y = nodes[triangles]
    first = search.near(p, y).copy()
    swung = y.copy()
    swung[1, 1, 2] += 0.12 * search.skin  # node 3, the far corner of the second triangle
    # the premise: the old bound is past the epoch's share, the grown corners' is not
    mean = (swung - y).reshape(-1, 3).mean(axis=0)
    old = (1.0 + 2.0 * reach.sum(axis=1)) * np.linalg.norm(swung - y - mean, axis=-1).max(axis=1)
    assert old.max() > ply_search.EPOCH_SHARE * search.skin
    assert ply_search.grown_moves(swung - y - mean, reach).max() <= (
        ply_search.EPOCH_SHARE * search.skin
    )
    searches = search.searches
    near = search.near(p, swung)
    assert search.searches == searches  # kept
    np.testing.assert_array_equal(near, first)
    nearest = _brute_nearest(p, swung, reach, None)
    assert np.all(np.any(near == nearest[:, None], axis=1))


@pytest.mark.parametrize("seed", range(4))
def test_the_compiled_lists_move_is_the_grown_corners_largest(seed):
    """The compiled kept lists' move (``_moves``, the path the runs take) is numpy's
    ``grown_moves`` to the bit where outline triangles, grown past their open edges, move
    most: a move off the corners' mean by the corners alone (the growth dropped) would read
    them short and keep lists the bound does not cover."""
    rng = np.random.default_rng(seed)
    m = 40
    y = rng.normal(scale=5.0, size=(m, 3, 3))
    move = rng.normal(scale=0.01, size=(m, 3, 3))
    reach = np.zeros((m, 3))
    outline = rng.choice(m, size=8, replace=False)
    reach[outline] = np.where(rng.random((8, 3)) < 0.6, MARGIN, 0.0)
    move[outline] *= 20.0  # the outline triangles swing most
    epoch = y - move
    move = y - epoch  # as FacingSearch.near forms it (the rounding of y - (y - move))
    p = rng.normal(size=(5, 3))
    shift, drift = np.empty(3), np.empty(len(p))
    # y and p read-only, as the search hands them (the kernel's one build)
    moved = ply_search._moves_compiled(
        read_only(y), epoch, reach, read_only(p), p.copy(), np.zeros((5, 3)), np.zeros(5),
        shift, drift,
    )  # fmt: skip
    mean = move.reshape(-1, 3).mean(axis=0)
    grown = ply_search.grown_moves(move - mean, reach)
    assert moved == np.max(grown)
    # the premise: the triangle that moves most is grown, where the corners alone read less
    worst = int(np.argmax(grown))
    assert reach[worst].sum() > 0
    assert np.linalg.norm(move[worst] - mean, axis=-1).max() < grown[worst]


@pytest.mark.parametrize("cut", [False, True], ids=["grown", "cut"])
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_the_compiled_every_pair_search_lists_as_numpy(seed, cut):
    """The search over every pair by its compiled passes (elements/ply_search_pairs.py) and
    by numpy (its reference): the same lists and counts (the same arrays) over 12 calls of a
    crumpled sheet moved by a Newton iterate's jumps, and numpy's centroid distances, radii
    and nearest distances to the bit."""
    from elements import ply_search_pairs

    rng = np.random.default_rng(seed)
    nodes, triangles, _, _, _, search, p = _sheet_and_points(rng, 6, 100, cut)
    assert len(p) * len(triangles) <= ply_search.EVERY_PAIR
    for call in range(12):
        nodes = nodes + rng.normal(0.0, 2.0 / 3.0, nodes.shape)
        p = p + rng.normal(0.0, 2.0 / 3.0, p.shape)
        y = nodes[triangles]
        near, count = search._search(p, y, np.arange(len(p)))
        with pytest.MonkeyPatch.context() as patch:
            patch.setattr(FacingSearch, "_every_pair", lambda self, here, y, corners: None)
            near_numpy, count_numpy = search._search(p, y, np.arange(len(p)))
        assert np.array_equal(count, count_numpy), call
        assert np.array_equal(near, near_numpy), call
        assert near.dtype == near_numpy.dtype and count.dtype == count_numpy.dtype
        corners = ply_search.grown_corners(y, search.reach)
        _, _, loose, apart, radius = ply_search_pairs.bounded_pairs(p, y, corners, search.skin)
        centroids = y.mean(axis=1)
        assert np.array_equal(
            radius, np.sqrt(np.max(np.sum((corners - centroids[:, None]) ** 2, axis=-1), axis=1))
        )
        distances = np.linalg.norm(p[:, None, :] - centroids[None], axis=-1)
        assert np.array_equal(apart, distances)
        assert np.array_equal(loose, distances.min(axis=1))
