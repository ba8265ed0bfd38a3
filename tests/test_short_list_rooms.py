"""The two steps of the short lists' proof (docs/theory.md §9.3, elements/facet_search.py
``closest_facets_listed``) that random creeping never puts to the test, each on a tool built
so that without the step a meshed tool (RigidSurface) names the wrong closest facet:

* a point answered from its short list sets its room to keep the nearest from the next
  distance, the facets off the list taken at their distance at the list's scan LESS the move
  since: a point that has walked towards an off-list facet keeps a room that this move has
  eaten, and walking on past it finds that facet the nearest;
* a point whose candidates are searched again (it moved past the candidate lists' margin)
  drops its short list and its room to keep its nearest (RigidSurface._forget_nearest):
  both proofs hold among the old candidates only, and a facet that was too far to be one of
  them can be the nearest now.

Each tool is a few free-standing equilateral facets, most of them facing the point's path,
so that the closest point on a facet is its centroid where the path passes through its
axis (the distance |point - centroid|): the wrong answer is a facet further than the right
one by a tenth of a millimetre or more, far beyond rounding. The reference
is the plain scan of every facet (``closest_facets`` without a hint) and a tool that has
kept nothing (made anew for each call), to the last bit."""

import numpy as np

from elements import RigidSurface
from elements.facet_search import SLACK, closest_facets
from femcore.mesh import Mesh


def facing_facets(centroids, normals, radii) -> Mesh:
    """Equilateral triangles (one per row of centroids (f, 3), mm) in the planes of unit
    ``normals`` (f, 3), their corners ``radii`` (f,) mm from the centroid, counter-clockwise
    about the normal: separate facets, three nodes each."""
    points = []
    for centroid, normal, radius in zip(
        np.asarray(centroids, float), np.asarray(normals, float), radii
    ):
        u = np.cross(normal, [0.0, 0.0, 1.0] if abs(normal[2]) < 0.9 else [1.0, 0.0, 0.0])
        u /= np.linalg.norm(u)
        v = np.cross(normal, u)
        for angle in (0.0, 2.0 * np.pi / 3.0, 4.0 * np.pi / 3.0):
            points.append(centroid + radius * (np.cos(angle) * u + np.sin(angle) * v))
    return Mesh(np.array(points), np.arange(len(points)).reshape(-1, 3))


def plain_scan(tool: RigidSurface, x: np.ndarray):
    """(point, facet, gap) of each point x (k, 3) by a scan of every facet, no hint."""
    start = np.arange(len(x) + 1) * tool.n_facets
    facets = np.tile(np.arange(tool.n_facets), len(x))
    point, facet, gap = x.copy(), np.zeros(len(x), dtype=np.int64), np.zeros(len(x))
    closest_facets(
        x, tool.corners, tool._centroids, tool._radius, SLACK * tool.reach,
        start, facets, np.full(len(x), -1), point, facet, gap,
    )  # fmt: skip
    return point, facet, gap


def answers_as_the_plain_scan(mesh: Mesh, path: list[np.ndarray]) -> list[list[int]]:
    """The points walked along ``path`` (calls of (k, 3), mm) on one tool that keeps its
    lists: at each call its distances and normals are those of a tool made anew, its facets
    and gaps those of the plain scan, to the last bit. Returns each call's closest facets."""
    tool = RigidSurface(mesh)
    facets = []
    for x in path:
        d, n = tool.distance(x)
        d_new, n_new = RigidSurface(mesh).distance(x)
        _, facet, gap = plain_scan(tool, x)
        np.testing.assert_array_equal(tool._last_facet, facet)
        np.testing.assert_array_equal(np.abs(d), gap)
        np.testing.assert_array_equal(d, d_new)
        np.testing.assert_array_equal(n, n_new)
        facets.append(facet.tolist())
    return facets


X = np.array([1.0, 0.0, 0.0])


def test_a_listed_point_keeps_its_nearest_only_for_the_room_its_move_has_left():
    """Five facets of circumradius 10 mm across the x axis, the point walking along it from
    0: facet 0 at x = -1 (the nearest), 1-3 at x = -2.8, -2.85, -2.9 (the rest of the short
    list), 4 at x = +3 (off the list, its distance the list's cut: 3 mm). Its scan at 0 gives
    it the room 0.5 (2.8 - 1) = 0.9 mm to keep facet 0 and 0.5 (3 - 1) = 1 mm to answer from
    the list. At 0.95 the list answers (facet 0, 1.95 mm), and facet 4 is now 3 - 0.95 =
    2.05 mm away: the room to keep facet 0 is 0.5 (2.05 - 1.95) = 0.05 mm (with the cut not
    less the move, 0.5 (3 - 1.95) = 0.525 mm). At 1.05 (0.1 mm on) facet 4 is the nearest,
    1.95 mm against facet 0's 2.05. The walk stays within the candidate lists' margin (0.29
    of the 10 mm reach along each axis): no search again between the calls."""
    centroids = [-1.0 * X, -2.8 * X, -2.85 * X, -2.9 * X, 3.0 * X]
    normals = [X, X, X, X, -X]
    mesh = facing_facets(centroids, normals, [10.0] * 5)
    path = [np.array([[0.0, 0.0, 0.0]]), np.array([[0.95, 0.0, 0.0]])]
    path.append(np.array([[1.05, 0.0, 0.0]]))
    assert answers_as_the_plain_scan(mesh, path) == [[0], [0], [4]]
    # The walk as told: the list answered at 0.95, no search but the first.
    tool = RigidSurface(mesh)
    for x in path[:2]:
        tool.distance(x)
    assert tool._cache.points[0, 0] == 0.0
    anchor, room = tool._kept[1][0], tool._kept[2][0]
    assert anchor[0] == 0.95 and 0.0 < room < 0.1


def test_a_point_searched_again_answers_from_its_new_candidates_not_its_old_lists():
    """Three points 0.75 mm along x from where they were searched (past the candidate lists'
    margin: 0.5 / sqrt(3) of the 1 mm reach along an axis), each towards a small facet (0.05
    mm circumradius) 1.3 mm ahead of its start, which was no candidate there (its centroid
    beyond the closest distance 0.2 mm plus twice the margin plus its own circumradius,
    1.25 mm) and is the nearest now (0.55 mm; the old nearest, 0.2 mm below the start, is
    0.73 mm away). The first point's short list at its start held four small facets 0.2-0.4
    mm away, its cut the distance 1.8 mm of a large facet (1 mm circumradius) behind it, so
    the list's room was 0.5 (1.8 - 0.2) = 0.8 mm; the second had two candidates, no cut, a
    list's room without end; the third one candidate, its room to keep it without end too.
    The old short lists would name the old nearest for the first two, the kept facet for
    the third."""
    z, y = np.array([0.0, 0.0, 1.0]), np.array([0.0, 1.0, 0.0])
    second, third = 100.0 * X, 200.0 * X
    centroids = [
        -0.2 * z, -0.3 * X, 0.35 * z, -0.4 * y, -1.8 * X, 1.3 * X,  # the first point's
        second - 0.2 * z, second - 0.3 * X, second + 1.3 * X,  # the second's
        third - 0.2 * z, third + 1.3 * X,  # the third's
    ]  # fmt: skip
    normals = [z, X, -z, y, X, -X, z, X, -X, z, -X]
    radii = [0.05, 0.05, 0.05, 0.05, 1.0] + [0.05] * 6
    mesh = facing_facets(centroids, normals, radii)
    start = np.array([[0.0, 0.0, 0.0], second, third])
    path = [start, start + 0.75 * X]
    assert answers_as_the_plain_scan(mesh, path) == [[0, 6, 9], [5, 8, 10]]
    # The walk as told: the new nearest no candidate at the start, the rooms reaching past
    # the move, the points searched again.
    tool = RigidSurface(mesh)
    tool.distance(start)
    cache = tool._cache
    for point, ahead in enumerate((5, 8, 10)):
        assert ahead not in cache.facets[cache.start[point] : cache.start[point + 1]]
    assert np.diff(cache.start).tolist() == [5, 2, 1]
    assert tool._near[1][0] > 0.75 and tool._near[1][1] == tool._near[1][2] == np.inf
    assert tool._kept[2][2] == np.inf
    tool.distance(path[1])
    np.testing.assert_array_equal(tool._cache.points, path[1])
