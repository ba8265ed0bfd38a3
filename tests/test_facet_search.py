"""The closest-facet search of a meshed tool (elements/facet_search.py): the facets skipped by
the hint change nothing, to the last bit, whatever the hint."""

import numpy as np

from elements import RigidSurface
from elements.facet_search import SLACK, closest_facets, closest_facets_kept
from femcore.mesh import Mesh


def bumpy_surface(n: int = 12) -> Mesh:
    """A 20 x 20 mm sheet with a bump and a ridge, uneven facets of 2 to 3 mm."""
    flat = Mesh.rectangle(20.0, 20.0, n, n)
    x, y = flat.points[:, 0], flat.points[:, 1]
    rng = np.random.default_rng(3)
    jitter = rng.uniform(-0.3, 0.3, size=(len(x), 2)) * (20.0 / n)
    inner = (x > 0) & (x < 20) & (y > 0) & (y < 20)
    x = x + np.where(inner, jitter[:, 0], 0.0)
    y = y + np.where(inner, jitter[:, 1], 0.0)
    z = 3.0 * np.exp(-((x - 8.0) ** 2 + (y - 11.0) ** 2) / 10.0) + 0.2 * np.sin(0.9 * x)
    return flat.with_points(np.column_stack([x, y, z]))


def every_facet_a_candidate(tool: RigidSurface, points: np.ndarray):
    start = np.arange(len(points) + 1) * tool.n_facets
    return start, np.tile(np.arange(tool.n_facets), len(points))


def search(tool: RigidSurface, points, start, facets, hint):
    point = points.copy()
    facet = np.zeros(len(points), dtype=np.int64)
    gap = np.zeros(len(points))
    closest_facets(
        points, tool.corners, tool._centroids, tool._radius, SLACK * tool.reach,
        start, facets, np.asarray(hint, dtype=np.int64), point, facet, gap,
    )  # fmt: skip
    return point, facet, gap


def test_the_closest_facet_is_the_same_to_the_last_bit_whatever_the_hint():
    """Points above, below and on the surface, at its corners (ties between the facets that
    share a corner), each with all facets as candidates: with no hint (every candidate
    examined in order), the right facet as the hint, a random facet, or a facet not among the
    point's candidates, the closest points, facets and distances are identical, and the
    distance is the smallest over the facets."""
    tool = RigidSurface(bumpy_surface())
    rng = np.random.default_rng(5)
    corners = tool.corners.reshape(-1, 3)
    points = np.concatenate(
        [
            rng.uniform([-2, -2, -3], [22, 22, 6], size=(300, 3)),
            corners[rng.choice(len(corners), 100)],  # exactly at a corner of several facets
            tool._centroids[rng.choice(tool.n_facets, 50)],  # on a facet
        ]
    )
    start, facets = every_facet_a_candidate(tool, points)
    plain = search(tool, points, start, facets, np.full(len(points), -1))
    gaps = [search(tool, points, start, facets, np.full(len(points), f))[2] for f in range(3)]
    assert np.all(plain[2] <= np.min(gaps, axis=0))
    for hint in (plain[1], rng.integers(0, tool.n_facets, len(points))):
        for got, expected in zip(search(tool, points, start, facets, hint), plain):
            np.testing.assert_array_equal(got, expected)
    # The hint outside a point's candidates (here only the facets far from the nearest): the
    # candidates scanned again without skipping.
    few = [np.argsort(np.linalg.norm(tool._centroids - p, axis=1))[5:12] for p in points]
    start = np.arange(len(points) + 1) * 7
    facets = np.concatenate(few)
    plain = search(tool, points, start, facets, np.full(len(points), -1))
    for hint in (np.zeros(len(points)), [f[0] - 5 for f in few], plain[1]):
        hint = np.asarray(hint) % tool.n_facets
        for got, expected in zip(search(tool, points, start, facets, hint), plain):
            np.testing.assert_array_equal(got, expected)


def test_a_point_without_candidates_is_at_an_infinite_gap_and_left_untouched():
    tool = RigidSurface(bumpy_surface(4))
    points = np.array([[1.0, 1.0, 1.0], [5.0, 5.0, 5.0]])
    start = np.array([0, 0, 2])
    point, facet, gap = search(tool, points, start, np.array([0, 1]), [3, -1])
    assert gap[0] == np.inf and facet[0] == 0
    np.testing.assert_array_equal(point[0], points[0])
    assert np.isfinite(gap[1])


def test_a_meshed_tool_answers_the_same_with_and_without_the_last_facets_as_hints():
    """A cloud of points creeping over the surface for 30 calls, a few of them jumping: the
    signed distances and normals of RigidSurface.distance are identical to those of the same
    tool made to forget its hints before every call."""
    mesh = bumpy_surface()
    hinted, plain = RigidSurface(mesh), RigidSurface(mesh)
    rng = np.random.default_rng(8)
    x = rng.uniform([0, 0, -1], [20, 20, 5], size=(400, 3))
    for _ in range(30):
        x = x + rng.normal(scale=0.05, size=x.shape)
        jump = rng.random(len(x)) < 0.05
        x[jump] += rng.normal(scale=2.0, size=(jump.sum(), 3))
        plain._hint = np.zeros(0, dtype=np.int64)
        for got, expected in zip(hinted.distance(x), plain.distance(x)):
            np.testing.assert_array_equal(got, expected)


def test_the_compiled_signed_distance_is_numpys_to_the_last_bit():
    """RigidSurface._signed (one compiled pass, the points behind corrected after it) against
    its numpy reference ``_signed_numpy``: points above and below a bumpy open sheet, beyond
    its open edges (beside the tool: positive) and on its facets (the facet's normal)."""
    tool = RigidSurface(bumpy_surface())
    rng = np.random.default_rng(5)
    x = rng.uniform([-4, -4, -3], [24, 24, 6], size=(3000, 3))
    start, facets = every_facet_a_candidate(tool, x)
    point, facet, gap = search(tool, x, start, facets, np.full(len(x), -1))
    # Some points on the surface itself: the closest point is the point.
    x[:50], gap[:50] = point[:50], 0.0
    d, n = tool._signed(x, point, facet, gap)
    d_ref, n_ref = tool._signed_numpy(x, point, facet, gap)
    assert (d_ref < 0).sum() > 100 and (d_ref > 0).sum() > 100
    behind = np.sum((x - point) * tool.normals[facet], axis=1) < 0
    assert (behind & (d_ref > 0)).sum() > 10  # beside an open edge, below the sheet's plane
    np.testing.assert_array_equal(d, d_ref)
    np.testing.assert_array_equal(n, n_ref)


def test_a_kept_nearest_facet_gives_the_scans_answer_to_the_last_bit():
    """Points creeping over the bumpy sheet for 40 calls (0.01 mm a call, a few jumping 1 mm),
    each with every facet as a candidate: closest_facets_kept, which gives a point its last
    nearest facet alone while it lies within its room, returns the point, facet and gap of
    the plain scan (closest_facets, no hint) at every call, bit for bit; a third of the answers came
    from the kept facet (room to spare), the others from a scan."""
    tool = RigidSurface(bumpy_surface())
    rng = np.random.default_rng(6)
    x = rng.uniform([0, 0, -1], [20, 20, 4], size=(300, 3))
    x[:50] = tool._centroids[rng.choice(tool.n_facets, 50)]  # on the sheet
    start, facets = every_facet_a_candidate(tool, x)
    hint = np.full(len(x), -1)
    anchor, room = np.zeros((len(x), 3)), np.full(len(x), -1.0)
    kept = 0
    for _ in range(40):
        x = x + rng.uniform(-0.01, 0.01, size=x.shape)
        jump = rng.random(len(x)) < 0.02
        x[jump] += rng.normal(scale=1.0, size=(jump.sum(), 3))
        moved = np.linalg.norm(x - anchor, axis=1)
        kept += int(np.count_nonzero((hint >= 0) & (moved < room)))
        point, facet, gap = x.copy(), np.zeros(len(x), dtype=np.int64), np.zeros(len(x))
        closest_facets_kept(
            x, tool.corners, tool._centroids, tool._radius, SLACK * tool.reach,
            start, facets, hint, anchor, room, point, facet, gap,
        )  # fmt: skip
        for got, expected in zip(
            (point, facet, gap), search(tool, x, start, facets, [-1] * len(x))
        ):
            np.testing.assert_array_equal(got, expected)
        hint = facet
    assert kept > 0.2 * 40 * len(x)  # both ways taken: the kept facet (37 %) and the scan
    assert kept < 0.99 * 40 * len(x)


def test_the_largest_drift_is_numpys_largest_coordinate_move():
    """The compiled question RigidSurface asks at every call (has a point moved past the
    margin?) against the numpy passes it replaced: the same number, exactly (a max of the
    same differences)."""
    from elements.facet_search import largest_drift

    rng = np.random.default_rng(3)
    anchor = rng.normal(size=(500, 3))
    x = anchor + rng.normal(scale=1e-3, size=anchor.shape)
    x[123, 1] = anchor[123, 1] - 0.5  # the largest, a move down
    expected = np.abs(x - anchor).max(axis=1, initial=0.0).max()
    assert largest_drift(x, anchor) == expected == abs(x[123, 1] - anchor[123, 1])
    assert largest_drift(x[:0], anchor[:0]) == 0.0


def test_the_batched_search_is_numpys_to_the_last_bit_on_one_thread_and_on_all():
    """RigidSurface._closest (the batched searches of the candidate lists: the k-d tree's
    nearest centroids, then the closest point on each of their facets in one compiled pass,
    the tree's queries on the threads) against its numpy reference ``_closest_numpy``, with
    the 8 nearest facets, 3 and every facet: points above, below and beside the bumpy sheet,
    at its corners (equal gaps to the facets that share a corner: the first in the tree's
    order is kept, as numpy's argmin keeps it) and on its facets, identical on one thread
    and on all of numba's."""
    from tests.thread_runs import on_one_thread_and_on_all

    tool = RigidSurface(bumpy_surface())
    rng = np.random.default_rng(8)
    corners = tool.corners.reshape(-1, 3)
    x = np.concatenate(
        [
            rng.uniform([-4, -4, -3], [24, 24, 6], size=(3000, 3)),
            corners[rng.choice(len(corners), 300)],
            tool._centroids[rng.choice(tool.n_facets, 100)],
        ]
    )
    answers = on_one_thread_and_on_all(
        lambda: [tool._closest(x, count) for count in (8, 3, tool.n_facets)]
    )
    ties = 0
    for count, one, every in zip((8, 3, tool.n_facets), *answers):
        expected = tool._closest_numpy(x, count)
        for got, on_all, reference in zip(one, every, expected):
            np.testing.assert_array_equal(got, reference)
            np.testing.assert_array_equal(on_all, reference)
        if count == tool.n_facets:  # a corner's gap is 0 to each facet that shares it
            ties = int(np.count_nonzero(expected[2] == 0.0))
    assert ties >= 300


def test_a_short_list_gives_the_scans_answer_to_the_last_bit():
    """Points creeping over the bumpy sheet for 60 calls (0.003 mm a call, a few jumping 1
    mm), each with every facet as a candidate: closest_facets_listed, which gives a point its
    last nearest facet alone while it lies within its room, then its SHORT nearest facets of
    its last scan while the nearest must be among them, then a scan, returns the point, facet
    and gap of the plain scan (closest_facets, no hint) at every call, bit for bit, on one
    thread and on all; each of the three ways was taken many times. A list that leaves out
    the nearest (the lists' rooms made 100 times too long) is caught."""
    from elements.facet_search import SHORT, candidate_rows, closest_facets_listed
    from tests.thread_runs import on_one_thread_and_on_all

    tool = RigidSurface(bumpy_surface())
    start0, facets0 = every_facet_a_candidate(tool, np.zeros((300, 3)))
    rows = candidate_rows(facets0, tool.corners, tool.normals, tool._centroids, tool._radius)

    def creep(stretch: float = 1.0):
        rng = np.random.default_rng(6)
        x = rng.uniform([0, 0, -1], [20, 20, 4], size=(300, 3))
        x[:100] = tool._centroids[rng.choice(tool.n_facets, 100)]  # on the sheet
        k = len(x)
        hint = np.full(k, -1)
        anchor, room, corners = np.zeros((k, 3)), np.full(k, -1.0), np.zeros((k, 4, 3))
        near = (
            np.zeros((k, 3)), np.full(k, -1.0), np.zeros(k), np.full((k, SHORT), -1),
            np.zeros((k, SHORT + 1)), np.zeros((k, SHORT + 1), dtype=np.int64),
            np.zeros((k * SHORT, 4, 3)),
        )  # fmt: skip
        ways = [0, 0, 0]  # kept, listed, scanned
        answers, expected = [], []
        for call in range(60):
            x = x + rng.uniform(-0.003, 0.003, size=x.shape)
            jump = rng.random(len(x)) < 0.01
            x[jump] += rng.normal(scale=1.0, size=(jump.sum(), 3))
            kept = (hint >= 0) & (np.linalg.norm(x - anchor, axis=1) < room)
            listed = ~kept & (np.linalg.norm(x - near[0], axis=1) < near[1])
            if call > 0:  # (the first call scans every point)
                ways[0] += int(kept.sum())
                ways[1] += int(listed.sum())
                ways[2] += int((~kept & ~listed).sum())
            point, facet, gap = x.copy(), np.zeros(len(x), dtype=np.int64), np.zeros(len(x))
            closest_facets_listed(
                x, tool.corners, SLACK * tool.reach, start0, facets0, *rows, hint, anchor,
                room, corners, *near, point, facet, gap,
            )  # fmt: skip
            near[1][near[1] > 0] *= stretch
            answers.append((point, facet, gap))
            expected.append(search(tool, x, start0, facets0, [-1] * len(x)))
            hint = facet
        return answers, expected, ways

    one, every = on_one_thread_and_on_all(lambda: creep()[:2])
    ways = creep()[2]
    for runs in (one, every):
        for got_call, expected_call in zip(*runs):
            for got, expected in zip(got_call, expected_call):
                np.testing.assert_array_equal(got, expected)
    # Each way taken (measured: 65 % kept, 31 % listed, 4 % scanned after the first call).
    assert min(ways) > 0.01 * 59 * 300, ways
    answers, expected, _ = creep(stretch=100.0)
    wrong = sum(int(np.count_nonzero(got[1] != want[1])) for got, want in zip(answers, expected))
    assert wrong > 0  # the test sees a list that leaves the nearest out


def _kept_and_listed(listed, x):
    """(s,) bool each: the points ``x`` the tool ``listed`` answers from their kept facet,
    and those it answers from their short list (the others are scanned)."""
    kept = (listed._kept[0] >= 0) & (np.linalg.norm(x - listed._kept[1], axis=1) < listed._kept[2])
    short = ~kept & (np.linalg.norm(x - listed._near[0], axis=1) < listed._near[1])
    return kept, short


def _answers_as_without_short_lists(monkeypatch, listed, plain, x):
    """``listed``'s distances and normals at ``x`` with the short lists (SHORT_LISTS) are
    ``plain``'s without them, to the last bit."""
    from elements import rigid_surface

    monkeypatch.setattr(rigid_surface, "SHORT_LISTS", True)
    got = listed.distance(x)
    monkeypatch.setattr(rigid_surface, "SHORT_LISTS", False)
    expected = plain.distance(x)
    for a, b in zip(got, expected):
        np.testing.assert_array_equal(a, b)


def test_a_meshed_tool_answers_the_same_with_and_without_the_short_lists(monkeypatch):
    """A cloud of points creeping over the bumpy sheet for 40 calls (0.004 mm a call), a few
    jumping 2 mm (past the candidate lists' margin: their lists searched again, their short
    lists dropped): RigidSurface.distance with the short lists (SHORT_LISTS) gives the signed
    distances and normals of the same tool without them, to the last bit, the lists
    answering some of the points."""

    mesh = bumpy_surface()
    listed, plain = RigidSurface(mesh), RigidSurface(mesh)
    rng = np.random.default_rng(9)
    x = rng.uniform([0, 0, -1], [20, 20, 5], size=(400, 3))
    x[:150] = listed._centroids[rng.choice(listed.n_facets, 150)]  # on the sheet
    answered = 0
    for _ in range(40):
        x = x + rng.uniform(-0.004, 0.004, size=x.shape)
        jump = rng.random(len(x)) < 0.03
        x[jump] += rng.normal(scale=2.0, size=(jump.sum(), 3))
        if listed._near is not None:
            answered += int(np.count_nonzero(_kept_and_listed(listed, x)[1]))
        _answers_as_without_short_lists(monkeypatch, listed, plain, x)
    assert answered > 200


def test_the_candidates_copies_are_the_facets_rows_to_the_last_bit():
    """candidate_rows copies each candidate's corners and normal (m, 4, 3) and its bounding
    sphere's centre and radius (m, 4) from the tool's arrays, in the candidates' order, a
    facet listed several times, the same floats as numpy's gathers, on one thread and on all."""
    from elements.facet_search import candidate_rows
    from tests.thread_runs import on_one_thread_and_on_all

    tool = RigidSurface(bumpy_surface())
    rng = np.random.default_rng(3)
    facets = rng.integers(0, tool.n_facets, 5000)
    rows = np.concatenate([tool.corners[facets], tool.normals[facets][:, None]], axis=1)
    spheres = np.concatenate([tool._centroids[facets], tool._radius[facets][:, None]], axis=1)
    args = (facets, tool.corners, tool.normals, tool._centroids, tool._radius)
    for got in on_one_thread_and_on_all(lambda: candidate_rows(*args)):
        assert got[0].shape == (5000, 4, 3) and got[1].shape == (5000, 4)
        assert got[0].tobytes() == rows.tobytes()
        assert got[1].tobytes() == spheres.tobytes()


def test_a_point_sliding_round_a_vertex_of_six_facets_is_answered_from_its_short_list(
    monkeypatch,
):
    """Points 0.1 mm above a flat triangulated sheet (1 mm squares halved: six facets meet at
    each inner vertex, as on a structured die's or holder's face), each circling an inner
    vertex 0.03 mm from it, 0.005 mm a call for 60 calls: after their first scan they are
    answered by their kept facet or their short list at every call. The six facets round
    the vertex all lie within sqrt(0.1^2 + 0.03^2) = 0.1044 mm of such a point and every
    other facet beyond sqrt(0.1^2 + (0.707 - 0.03)^2) = 0.68 mm (the fan's hexagon is
    0.707 mm from the vertex at its nearest), so a list that holds the six has the room of
    half that difference, 0.29 mm, to let the point circle (at most 0.06 mm from where it
    was scanned). A list of four or five has one of the six for its cut, at most 4.4 um
    further than the nearest: a room of about 2 um, less than a call's move, sends the point
    back to a scan at every call, as the holder's nodes sliding over its vertices were sent
    in the two-ply fibrous hemisphere (benchmarks/ply_step.py). The answers stay those of
    the tool without the short lists, to the last bit."""

    sheet = Mesh.rectangle(10.0, 10.0, 10, 10)
    listed, plain = RigidSurface(sheet), RigidSurface(sheet)
    vertices = np.array([[3.0, 3.0], [5.0, 4.0], [6.0, 7.0], [4.0, 6.0]])
    scans = 0
    for call in range(60):
        turn = 0.005 / 0.03 * call  # rad: 0.005 mm a call along the circle
        x = np.column_stack(
            [
                vertices + 0.03 * np.array([np.cos(turn), np.sin(turn)]),
                np.full(len(vertices), 0.1),
            ]
        )
        if call > 0:
            kept, short = _kept_and_listed(listed, x)
            scans += int(np.count_nonzero(~kept & ~short))
        _answers_as_without_short_lists(monkeypatch, listed, plain, x)
    assert scans == 0
