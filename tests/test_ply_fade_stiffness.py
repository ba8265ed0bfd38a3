"""The stiffness of the ply contact's faded energy w W(g) near the lower ply's outline, which
the explicit step's springs take in (elements/ply_fade.py, "Stiffness").

Reference: the energy's Hessian in the contact point p, the central difference of its exact
force (the contact's force is the gradient of its energy: tests/test_ply_outline_fade.py),
against the closed-form bound c_p k of ``stiffness_factor``. The lower ply is 2 x 2 cells of
1 mm, its middle node lifted 0.1 mm (the inner edges are folds), faces 0.1 mm from the
mid-surfaces (the plies reach 0.2 mm); one upper triangle (its centroid the contact point,
0.02 mm across, moved rigidly, the directors along z) is placed around the outline vertex
(1, 0), where a triangle meets the outline at that vertex only (the growths of the two outline
triangles there cut, elements/ply_wedge.py), the ply's corner (2, 0) and
the outline edge's middle (1.5, 0), behind the lower face down to the plies' reach.
"""

import numpy as np
import pytest

from elements import ply_springs
from elements.ply_contact import PlyContact
from elements.ply_fade import SIDEWAYS, SIDEWAYS_STIFFNESS, stiffness_factor
from femcore import Body, Mesh
from femcore.state import State

PENALTY = 100.0  # N/mm
STEP = 1e-6  # mm, the central difference of the force


def _block():
    lower = Mesh.rectangle(2.0, 2.0, nx=2, ny=2)
    low = lower.points.copy()
    low[4, 2] = 0.1  # the middle node: the inner edges are folds
    side = 0.02
    tiny = np.array([[0.0, 0.0, 0.0], [side, 0.0, 0.0], [0.0, side, 0.0]])
    tiny -= tiny.mean(axis=0)
    points = np.vstack([low, tiny])
    mesh = Mesh(
        points,
        triangles=np.vstack([lower.triangles, [[9, 10, 11]]]),
        node_sets={"upper": np.array([9, 10, 11])},
        element_sets={"lower": np.arange(len(lower.triangles))},
    )
    n = len(points)
    directors = np.tile([0.0, 0.0, 1.0], (n, 1))
    active = np.zeros((n, 6), dtype=bool)
    active[:, :5] = True
    # the plain penalty k/2 min(g, 0)^2, the stiffest the ramp's W can be (W <= k g^2 / 2)
    contact = PlyContact(
        "upper", "lower", 0.1, 0.1, penalty=PENALTY, rule="centroid", smoothing=0.0
    )
    return contact.bind(Body(mesh, (), directors, active)), points, directors


def _state(points, directors, face):
    """The state whose contact point (the upper face's centroid, 0.1 mm below the mid-surface)
    is at ``face``."""
    x = points.copy()
    x[9:] += np.asarray(face) + [0.0, 0.0, 0.1]
    zero = np.zeros_like(x)
    return State(x, directors, zero, zero)


def _hessian(block, points, directors, face):
    """(3, 3) d2E/dp2 by central differences of the exact force on the upper triangle."""
    columns = []
    for axis in range(3):
        pair = []
        for sign in (1.0, -1.0):
            moved = np.array(face, dtype=float)
            moved[axis] += sign * STEP
            force = block.internal_force(_state(points, directors, moved))[0]
            pair.append(force[9:].sum(axis=0))
        columns.append((pair[0] - pair[1]) / (2.0 * STEP))
    hessian = np.array(columns)
    return 0.5 * (hessian + hessian.T)


def _samples(block, points):
    """Contact points around the outline vertex (0, 1), the ply's corner (2, 0) and the edge's
    middle (1.5, 0): at 0.06 and 0.18 mm (within the plies' 0.2 mm) from the offset face's
    vertex, on 8 sides in the plane of each triangle there, at angles from 0.3 to 60 deg
    behind that plane; and a fan beside the vertex (1, 0)."""
    offset = points + [0.0, 0.0, 0.1]  # the lower face: the mid-surface + 0.1 mm along z
    faces = []
    for centre in ((0.0, 1.0), (2.0, 0.0), (1.5, 0.0)):
        at = offset[np.argmin(np.linalg.norm(points[:, :2] - centre, axis=1))]
        if centre == (1.5, 0.0):
            at = 0.5 * (offset[1] + offset[2])
        for corners in offset[block.cells[np.isclose(offset[block.cells], at).all(-1).any(1)]]:
            normal = np.cross(corners[1] - corners[0], corners[2] - corners[0])
            normal /= np.linalg.norm(normal)
            first = np.cross(normal, [0.0, 1.0, 0.0]) + np.cross(normal, [1.0, 0.0, 0.0])
            first /= np.linalg.norm(first)
            second = np.cross(normal, first)
            for radius in (0.06, 0.18):
                for azimuth in np.radians(np.arange(0.0, 360.0, 45.0) + 7.0):
                    side = np.cos(azimuth) * first + np.sin(azimuth) * second
                    for dip in np.radians([0.3, 1.0, 3.0, 10.0, 30.0, 60.0]):
                        faces.append(at + radius * (np.cos(dip) * side - np.sin(dip) * normal))
    # beside the outline vertex (1, 0) in the gap between the growths' cuts (elements/
    # ply_wedge.py; triangle 2's plane), 0.005 mm from it (the past factor still ~1 there),
    # 1 to 4 deg across triangle 2's cut (its closest point on the cut), 0.01 to 0.3 deg
    # behind the plane: where the angle's fade is stiffest
    corners = offset[block.cells[2]]
    normal = np.cross(corners[1] - corners[0], corners[2] - corners[0])
    normal /= np.linalg.norm(normal)
    along = block.cuts.ends[2, 0] @ corners - corners[0]  # v = node 1 is its corner 0
    along /= np.linalg.norm(along)
    across = np.cross(normal, along)
    # out of the cut growth: the side where the cut's line l(lambda) falls
    lam = np.linalg.lstsq(corners.T, corners[0] + across, rcond=None)[0]
    if block.cuts.lines[2, 0] @ lam > 0.0:
        across = -across
    for turn in np.radians([1.0, 2.0, 3.0, 4.0]):
        side = np.cos(turn) * along + np.sin(turn) * across
        for dip in np.radians([0.01, 0.03, 0.1, 0.3]):
            faces.append(offset[1] + 0.005 * (np.cos(dip) * side - np.sin(dip) * normal))
    return np.array(faces)


def test_the_angle_fades_largest_stiffness_is_s2_of_0_over_2_sideways_squared():
    """The largest eigenvalue of the polar Hessian bound [[w, |w'| / 2], [|w'| / 2, w +
    max(w'', 0) / 2]] of the module docstring over the angle theta, sampled every 1e-4 deg, is
    the closed form S''(0) / (2 SIDEWAYS^2) (to 1e-12), S''(0) taken from the smoothstep S(u)
    = 3 u^2 - 2 u^3 itself (6; 3 at SIDEWAYS = 1), and ``SIDEWAYS_STIFFNESS`` is that figure."""
    smoothstep = np.poly1d([-2.0, 3.0, 0.0, 0.0])
    closed_form = smoothstep.deriv(2)(0.0) / (2.0 * SIDEWAYS**2)
    theta = np.radians(np.linspace(0.0, 90.0, 900001))
    u = np.cos(theta) / SIDEWAYS
    inside = (u > 0.0) & (u < 1.0)
    v = np.clip(u, 0.0, 1.0)
    w = smoothstep(v)
    slope = np.where(inside, smoothstep.deriv(1)(v), 0.0)
    bend = np.where(inside, smoothstep.deriv(2)(v), 0.0)
    first = -slope * np.sin(theta) / SIDEWAYS
    second = bend * np.sin(theta) ** 2 / SIDEWAYS**2 - slope * np.cos(theta) / SIDEWAYS
    a, b, d = w, 0.5 * np.abs(first), w + 0.5 * np.maximum(second, 0.0)
    largest = 0.5 * (a + d) + np.sqrt(0.25 * (a - d) ** 2 + b * b)
    assert largest.max() == pytest.approx(closed_form, rel=1e-12)
    assert SIDEWAYS_STIFFNESS == pytest.approx(closed_form, rel=1e-12)


def test_the_fades_stiffness_stays_under_its_bound_and_above_the_penalty():
    """At every sample (496, 306 of them in the fade's band) the largest eigenvalue of the Hessian
    in p is at most c_p k_p (1e-3 allowed for the central difference, whose error at 1e-6 mm is
    ~1e-8 relative; measured 1 + 4e-11 at most), c_p ``stiffness_factor`` of the point's facing
    (1 off the band); and the angle's term is not slack where it matters: beside the cut of
    triangle 2's growth at the vertex (1, 0) (the fan, 0.005 mm from the vertex) the largest
    sampled stiffness, 4 deg across the cut and 0.03 deg off the triangle's plane, is 2.95 k_p
    (over 0.85 x the closed form S''(0) / (2 SIDEWAYS^2) = 3 k_p asked), so the springs' k_p
    alone did not bound it. The largest of all samples, 3.38 k_p, lies 0.18 mm from the outline
    vertex (0, 1), 60 deg behind a triangle's plane, where the past factor's terms add to the
    bound (13.3 k_p there). With the plain penalty, the stiffest W."""
    block, points, directors = _block()
    k = float(block.stiffness[0])
    ratios, stiff = [], []
    samples = _samples(block, points)
    for face in samples:
        state = _state(points, directors, face)
        facing = block.facing(state)
        past = ((facing.reach > 0.0) & (facing.weights < 0.0)).any(axis=1)
        bound = stiffness_factor(past, facing.on_growth, block.depth, block.fade_length)[0] * k
        largest = np.linalg.eigvalsh(_hessian(block, points, directors, face)).max()
        ratios.append(largest / bound)
        stiff.append(largest / k)
    assert max(ratios) <= 1.0 + 1e-3
    fan = len(samples) - 16  # the 4 x 4 samples beside the vertex (1, 0), last in ``_samples``
    assert max(stiff[fan:]) > 0.85 * SIDEWAYS_STIFFNESS  # the closed form (the test above)


def test_the_springs_take_the_bound_in_the_band_and_nothing_elsewhere():
    """``springs_at`` gives each point's nodes c_p times ``springs``' share (times (2 + 3
    delta) / 2 for the move of lambda until the next evaluation, delta = ``FLOOR`` at rest,
    elements/ply_springs.py): beside the outline vertex (1, 0) (a sample of the fan) c_p >
    ``SIDEWAYS_STIFFNESS`` (3; 13.6 measured, the past factor's terms at the plies' depth with
    it); past the outline edge's middle (1.5, -0.05), in the band, c_p > 1 (the beside figure:
    it lies within its reach of the vertex, but below the first); over an outline triangle
    inside the outline (1.5, 0.2, farther from it than its gap and the slide) and over an inner
    triangle (0.6, 0.6), where w = 1, c_p = 1."""
    block, points, directors = _block()
    nodes, plain = block.springs()
    upper = np.isin(nodes, block.upper)
    fan = _samples(block, points)[-11]  # 2 deg across the cut, 0.03 deg behind the plane
    factors = []
    for face, low, high in (
        (fan, SIDEWAYS_STIFFNESS, np.inf),
        ([1.5, -0.05, 0.09], 1.0, np.inf),
        ([1.5, 0.2, 0.09], 1.0, 1.0),
        ([0.6, 0.6, 0.09], 1.0, 1.0),
    ):
        state = _state(points, directors, face)
        at_nodes, springs = block.springs_at(state)
        assert np.array_equal(at_nodes, nodes)
        factor = springs[upper] / plain[upper]
        np.testing.assert_allclose(factor, factor[0], rtol=1e-12)
        factors.append(factor[0])
        if low == high:
            assert factor[0] == pytest.approx(1.0 + 1.5 * ply_springs.FLOOR, rel=1e-12)
        else:
            assert low < factor[0] < high
    assert block.facing(_state(points, directors, fan)).on_growth[0]
    assert factors[1] < factors[0]


def test_the_springs_bound_a_point_deeper_than_the_plies_past_the_outline_by_its_depth():
    """Points held by the growth's plane past the outline edge's middle (1.5, 0), 0.01 to
    0.05 mm past it (their projections on the tilted triangle's plane 0.06 to 0.149 past it
    in barycentric units, within the fade's 0.15), 0.5 and 1 mm behind the lower face
    (deeper than the plies' 0.2 mm): they touch, faded (elements/ply_projection.py, "Past the
    outline, deeper than the plies"; the code before made them beside the ply), and the
    largest eigenvalue of the Hessian in p is at most the ``springs_at`` factor times k_p
    (1e-3 allowed for the central difference; measured 0.70 at most). The bound needs the
    point's own depth: with the plies' depth for r (the bound of before) a sample's stiffness
    is 11.4 times the bound."""
    block, points, directors = _block()
    k = float(block.stiffness[0])
    nodes, plain = block.springs()
    upper = np.isin(nodes, block.upper)
    ratios, beyond_old = [], []
    for depth in (0.5, 1.0):
        for past in (0.01, 0.03, 0.05):
            face = [1.5, -past, 0.1 - depth]
            state = _state(points, directors, face)
            facing = block.facing(state)
            assert facing.touching[0] and facing.gap[0] < -block.depth  # the premise
            factor = block.springs_at(state)[1][upper][0] / plain[upper][0]
            largest = np.linalg.eigvalsh(_hessian(block, points, directors, face)).max()
            ratios.append(largest / (factor * k))
            band = np.ones(1, dtype=bool)
            old = stiffness_factor(band, facing.on_growth, block.depth, block.fade_length)[0]
            beyond_old.append(largest / (old * k))
    assert max(ratios) <= 1.0 + 1e-3
    assert max(beyond_old) > 1.0
