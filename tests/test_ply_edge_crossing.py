"""A ply contact point whose gap is to an edge of the lower face lands where its way crossed
that gap's zero (elements/ply_landing.py ``edge_crossing``), and one that faces an edge once it
has left slid up to where its way left the face it touched (elements/ply_departure.py; docs/
theory.md §9.3a, "A point's landing step" and "A point's departure step").

The model (tests/ply_pair.py ``folded_plies``): a lower ply held fixed whose nodes on x = 2 lie
0.5 mm below (a valley) or above (a ridge) the rest, and one point of an upper ply carried
straight, along the fold's edge by VY and across it by VZ, in the plane normal to the faces
through the edge line. Below a valley's edge line, and above a ridge's, the point faces the
edge: g = +-|p - q| along nu = +z, q sliding along the edge; above a valley and below a ridge
it faces a face's plane. Landing on the valley's edge, its gap is linear in time and passes
zero on the edge line, its tangential way along the edge; leaving the ridge, it slides on the
face B it touches (normal n_B at alpha = 13.97 deg to z) until it leaves that face on the
ridge's line. Coulomb's work of the ply landing and departure tests (mu = 0.3, plain penalty:
N = k_p pen, k_t = k_p), with the way's normal and tangential rates V_n and V_t on the face
the point slides on,

    landing:    D = mu k_p V_n (V_t - mu V_n) (1 - t_c)^2 / 2,   slip (V_t - mu V_n)(1 - t_c),
    departure:  D = mu k_p V_n (V_t + mu V_n) (t_l - t_s)^2 / 2, slip V_t t_l,

holds to round-off (the normal force linear over each step, the stick's end at a step's end:
the record's midpoint rule is exact; asserted 1e-12 relative). Before the rule such points
landed anchored at their projections once the step was accepted, and left with no slip
counted.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from elements import (
    ply_departure,
    ply_departure_kernels,
    ply_friction_kernels,
    ply_landing,
    ply_landing_kept,
)
from elements.ply_friction import PlyFrictionHistory
from elements.ply_friction_pass import history_pass
from elements.ply_sides import TOUCHING, PlySides
from tests.explicit_runs import run_explicitly
from tests.ply_pair import MU, folded_plies, moved_plies, static_histories
from tests.test_ply_landing import curved_landing_plies, landing_plies

# the departure runs start PEN0 into the ridge's face on purpose (the point lifts off): the
# start check's overlap warning (elements/ply_start.py) is expected
pytestmark = pytest.mark.filterwarnings("ignore:.*the plies start overlapping")

VALLEY, RIDGE = 0.5, -0.5  # mm, the fold line's dip
VZ = 0.1  # mm over the run
STEPS = 40
DURATION = 1.0e-4  # s

G0 = 0.0213  # mm over the edge line at the start of the landing run: t_c = 0.213
VY_LANDING = 1.2  # mm along the edge over the landing run

T_STICK, T_LIFT = 0.2, 0.713  # the departure run's shares: sliding from t_s, off at t_l
PEN0 = VZ * T_LIFT  # mm below the ridge's line at the start of the departure run


def landing_run(dip: float, unknown: bool = True):
    """The point carried from G0 over the fold's line, down through it."""
    return folded_plies(G0, VY_LANDING, -VZ, dip, unknown)


def ridge_face() -> np.ndarray:
    """The unit normal n_B of the ridge's face the departure run's point touches."""
    model = folded_plies(-PEN0, 0.0, VZ, RIDGE)
    block, row = carried_point(model)
    return block.facing(model.compile().initial_state()).normal[row]


def departure_rates() -> tuple[float, float, float]:
    """(VY, V_n, V_t) of the departure run: V_n = VZ cos(alpha) along n_B and VY such that
    the stick ends at t_s = T_STICK, V_t = mu V_n (t_l / t_s - 1)."""
    normal = ridge_face()
    rate_n = VZ * normal[2]
    rate_t = MU * rate_n * (T_LIFT / T_STICK - 1.0)
    return float(np.sqrt(rate_t**2 - (VZ * normal[0]) ** 2)), rate_n, rate_t


def departure_run(unknown: bool = True):
    """The point carried from PEN0 under the ridge's line, up through it."""
    return folded_plies(-PEN0, departure_rates()[0], VZ, RIDGE, unknown)


def carried_point(model) -> tuple[object, int]:
    """(block, row): the model's ply contact and its carried point's row (the upper ply's low
    node, the only point that touches)."""
    block = model.compile().interactions[0]
    faces, _ = block._faces(model.compile().initial_state())
    return block, int(np.argmin(faces[:, 2]))


def landing_coulomb(k: float) -> tuple[float, float]:
    after = 1.0 - G0 / VZ
    return MU * k * VZ * (VY_LANDING - MU * VZ) * after**2 / 2, (VY_LANDING - MU * VZ) * after


def departure_coulomb(k: float) -> tuple[float, float]:
    _, rate_n, rate_t = departure_rates()
    sliding = T_LIFT - T_STICK
    return MU * k * rate_n * (rate_t + MU * rate_n) * sliding**2 / 2, rate_t * T_LIFT


def test_the_carried_point_faces_the_edge_where_the_rule_is_asked_for():
    """The premise: below the valley's edge line and above the ridge's the point faces the
    edge, nu = +z and the gap its height over the line; below the ridge's it faces a face."""
    for dip, shares in ((VALLEY, (0.3, 1.0)), (RIDGE, (0.0, 0.1))):
        model = landing_run(dip)
        block, row = carried_point(model)
        state = model.compile().initial_state()
        upper = np.unique(block.above)
        for share in shares:
            positions = state.positions.copy()
            positions[upper] += np.array([0.0, VY_LANDING, -VZ]) * share
            facing = block.facing(dataclasses.replace(state, positions=positions))
            assert facing.on_edge is not None and facing.on_edge[row]
            np.testing.assert_allclose(facing.normal[row], [0.0, 0.0, 1.0], atol=1e-12)
            assert facing.gap[row] == pytest.approx(G0 - VZ * share, abs=1e-12)
    model = departure_run()
    block, row = carried_point(model)
    facing = block.facing(model.compile().initial_state())
    assert facing.on_edge is not None and not facing.on_edge[row] and facing.touching[row]
    assert facing.gap[row] == pytest.approx(-PEN0 * ridge_face()[2], rel=1e-12)


def test_an_explicit_run_onto_an_edge_dissipates_coulombs_work_after_the_touch():
    """40 explicit steps onto the valley's edge, the touch 0.52 of the way through step 9.
    Before, the landing step took no friction (anchored at the projection once accepted):
    0.5433567 against 0.5434963 N mm (fails)."""
    model = landing_run(VALLEY, unknown=False)
    compiled, state = run_explicitly(model, STEPS, DURATION)
    block, row = carried_point(model)
    dissipation = landing_coulomb(block.stiffness[row])[0]
    assert compiled.dissipated_energy(state) == pytest.approx(dissipation, rel=1e-12)


@pytest.mark.parametrize("increments", [3, 7])
def test_static_counts_the_slip_of_an_increment_landing_on_an_edge(monkeypatch, increments):
    """Static in 3 and 7 increments onto the valley's edge: the point slid (VY - mu VZ)(1 -
    t_c) = 0.92079 mm and dissipated Coulomb's work. Before: 0.77639 / 0.83353 mm, 0.529236 /
    0.538385 against 0.543496 N mm (fails)."""
    model = landing_run(VALLEY)
    block, row = carried_point(model)
    last = static_histories(monkeypatch, model, increments)[-1]
    dissipation, slip = landing_coulomb(block.stiffness[row])
    assert last.slip[row] == pytest.approx(slip, rel=1e-12)
    assert last.dissipated == pytest.approx(dissipation, rel=1e-12)


@pytest.mark.parametrize(
    "fused, compiled",
    [(True, True), (False, True), (True, False)],
    ids=["in the fused pass", "compiled apart", "numpy"],
)
def test_an_explicit_run_off_a_ridge_dissipates_coulombs_work_to_the_lift_off(
    monkeypatch, fused, compiled
):
    """40 explicit steps from PEN0 under the ridge's line, the lift-off 0.52 of the way
    through step 29, after which the point faces the ridge's edge: the departure's kernel in
    the fused history pass (elements/ply_friction_pass.py), called apart, and its numpy
    reference alike. Before, the departure step counted no slip (fails)."""
    monkeypatch.setattr(ply_friction_kernels, "FUSED", fused)
    monkeypatch.setattr(ply_departure_kernels, "COMPILED", compiled)
    model = departure_run(unknown=False)
    compiled, state = run_explicitly(model, STEPS, DURATION)
    block, row = carried_point(model)
    dissipation = departure_coulomb(block.stiffness[row])[0]
    assert compiled.dissipated_energy(state) == pytest.approx(dissipation, rel=1e-12)


@pytest.mark.parametrize("increments", [5, 10])
def test_static_counts_the_slip_of_an_increment_leaving_a_ridges_edge(monkeypatch, increments):
    """Static in 5 and 10 increments off the ridge: the point slid V_t t_l and dissipated
    Coulomb's work (before, the departure increment counted none: fails)."""
    model = departure_run()
    block, row = carried_point(model)
    last = static_histories(monkeypatch, model, increments)[-1]
    dissipation, slip = departure_coulomb(block.stiffness[row])
    assert last.triangle[row] < 0
    assert last.slip[row] == pytest.approx(slip, rel=1e-12)
    assert last.dissipated == pytest.approx(dissipation, rel=1e-12)


def test_the_landing_slip_lies_along_the_way_after_the_crossing():
    """The landing step onto the valley's edge (the history accepted before the touch, the
    state a share 0.3 of the run on): theta is the crossing's share of the step, and the
    point's offset from its landing anchor, across nu, is its way's part after the crossing
    (along the edge: cosine 1 with the way's tangential part). The landing kept for the state
    (elements/ply_landing_kept.py, the one the loads and the history take) anchors the edge
    row at its crossing's place."""
    model = landing_run(VALLEY)
    block, row = carried_point(model)
    state = model.compile().initial_state()
    upper = np.unique(block.above)
    history = block.initial_history()
    move = np.array([0.0, VY_LANDING, -VZ])

    def at(share):
        positions = state.positions.copy()
        positions[upper] += move * share
        return dataclasses.replace(state, positions=positions)

    history = block.update_history(at(0.2), history)  # clear: 0.0013 mm over the line
    now = at(0.3)
    facing = block.facing(now)
    # as the loads, the energy, the tangent and the accepted history take it: kept per state
    found, landed = ply_landing_kept.kept_landing(block, now, history, facing)
    assert found is not None and list(found.rows) == [row] and found.edge is not None
    assert found.edge[0] and found.theta[0] == pytest.approx(0.13, rel=1e-9)
    assert found.place is not None and np.array_equal(landed.anchor[row], found.place[0])
    assert ply_landing_kept.kept_landing(block, now, history, facing)[1] is landed
    sliding = block.friction_state(now, landed, facing)
    way = move * 0.1 * (1.0 - found.theta[0])
    offset = sliding.offset[row]
    across = offset - offset[2] * np.array([0.0, 0.0, 1.0])
    np.testing.assert_allclose(across, [0.0, way[1], 0.0], atol=1e-12)


def test_face_points_land_as_before_beside_edge_points():
    """Rows whose gap is to a plane keep their theta and anchor to the bit when other rows
    face an edge (the jittered plies of tests/test_ply_landing.py, every third touching point
    flagged ``on_edge``); the flagged rows take ``edge_crossing``'s."""
    block, state, history = landing_plies(0.05, "normal law")
    facing = block.facing(state)
    plain = ply_landing.landing(block, state, history, facing)
    edge = np.zeros(len(facing.gap), dtype=bool)
    edge[np.flatnonzero(facing.touching)[::3]] = True
    flagged = dataclasses.replace(facing, on_edge=edge)
    found = ply_landing.landing(block, state, history, flagged)
    assert plain is not None and found is not None and found.edge is not None
    np.testing.assert_array_equal(found.rows, plain.rows)
    face = ~found.edge
    np.testing.assert_array_equal(found.theta[face], plain.theta[face])
    before = ply_landing.landed(block, state, history, facing, plain).anchor
    after = ply_landing.landed(block, state, history, flagged, found).anchor
    np.testing.assert_array_equal(after[found.rows[face]], before[found.rows[face]])
    rows = found.rows[found.edge]
    _, y = block._faces(state)
    assert facing.on_growth is not None and not facing.on_growth[rows].any()
    theta, place = ply_landing.edge_crossing(
        history.sides.corners[facing.triangle[rows]], y[facing.triangle[rows]],
        history.sides.faces[rows], facing.face[rows], facing.weights[rows],
        facing.normal[rows], facing.normal[rows],
    )  # fmt: skip
    np.testing.assert_array_equal(found.theta[found.edge], theta)
    np.testing.assert_array_equal(after[rows], place)


def test_beside_a_growth_the_gaps_zero_is_the_triangles_plane():
    """A point beside a growth's edge, whose gap T's normal signs (g = sign(h) |p - q|),
    crosses that gap's zero where it passes T's plane: T the triangle z = 0 with corners
    (0, 0), (1, 0), (0, 1), q on its edge y = 0 grown past it, the point coming from 0.01 mm
    over the plane 0.3 mm off the edge to 0.03 mm under it (nu 84 deg from T's normal):
    theta = 0.01 / 0.04, the anchor at the crossing's place on the plane (the places' share)."""
    corners = np.array([[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]])
    then, point = np.array([[0.4, -0.3, 0.01]]), np.array([[0.45, -0.3, -0.03]])
    q = np.array([[0.45, 0.0, 0.0]])
    nu = (point - q) / -np.linalg.norm(point - q)
    feature = np.array([[0.55, 0.45, 0.0]])
    up = np.array([[0.0, 0.0, 1.0]])
    theta, place = ply_landing.edge_crossing(corners, corners, then, point, feature, nu, up)
    assert theta[0] == pytest.approx(0.25, rel=1e-14)
    crossing = then + 0.25 * (point - then)
    np.testing.assert_allclose(place @ corners[0], crossing * [1.0, 1.0, 0.0], atol=1e-14)


@pytest.mark.parametrize(
    "departure", [ply_departure.departure, ply_departure_kernels.departure_slip]
)
def test_a_point_leaving_beside_a_growths_edge_slips_by_its_offset_across_nu(departure):
    """A point beside a growth's edge (``Facing.on_growth``: T's normal signs its gap) touched
    with its spring across the edge gap's normal nu, nearly in T's plane: its departure slip
    is the offset's part across nu. The flat plies of tests/ply_pair.py, every point anchored
    v = (3, 4, 0) um behind its projection, 0.02 mm under T's plane then and 0.01 over it now
    (no way along the face): on T's plane the slip is |v| = 5 um; flagged beside a growth's
    edge with nu = x it is 4 um, with nu along v 0. The numpy departure and the compiled one
    alike, and the fused history pass's records (elements/ply_friction_pass.py)."""
    compiled = moved_plies(0.01, 0.0, 0.0).compile()
    block, state = compiled.interactions[0], compiled.initial_state()
    facing = block.facing(state)
    _, y = block._faces(state)
    count = len(facing.gap)
    corners = y[facing.triangle]
    plane = np.einsum("rk,rki->ri", facing.weights, corners)  # the projections
    v = np.array([0.003, 0.004, 0.0])
    anchor = facing.weights - np.einsum("rki,i->rk", facing.gradients, v)
    sides = PlySides(
        np.full(count, TOUCHING, dtype=np.int8), plane - 0.02 * facing.normal, y.copy()
    )
    history = PlyFrictionHistory(
        facing.triangle.copy(), anchor, np.zeros(count), np.ones(count), 0.0, sides
    )
    off = np.zeros(count, dtype=bool)
    now = dataclasses.replace(facing, touching=off, face=plane + 0.01 * facing.normal)
    rows, slip = departure(block, y, history, now)
    assert len(rows) == count
    np.testing.assert_allclose(slip, 0.005, rtol=1e-12)
    for nu, expected in (([1.0, 0.0, 0.0], 0.004), ([0.6, 0.8, 0.0], 0.0)):
        beside = dataclasses.replace(
            now, on_edge=~off, on_growth=~off, joined=off, normal=np.tile(nu, (count, 1))
        )
        rows, slip = departure(block, y, history, beside)
        assert len(rows) == count
        np.testing.assert_allclose(slip, expected, atol=1e-15)
        # the fused history pass writes those slips into the accepted records
        last = (history.triangle, history.anchor, history.slip, history.pressing)
        leaving = ply_departure.leaving(block, history, beside)
        _, moved, _ = history_pass(block, beside, y, last, None, leaving, sides)
        np.testing.assert_allclose(moved[2], expected, atol=1e-15)
        # and with the rows and their flags chosen in the pass (``select``): the same bits
        _, chosen, _ = history_pass(block, beside, y, last, None, None, sides, select=True)
        assert [a.tobytes() for a in chosen] == [a.tobytes() for a in moved]


def test_curved_faces_mark_no_point_facing_an_edge():
    """The edge rule never reaches the curved faces' landing tangent
    (elements/ply_curved_friction.py ``landing_anchor``, which makes the face rule's anchor
    again): their facing marks no point's gap to an edge or a vertex, so every curved landing
    row is a face row (the [0/45] pair on the 50-mm sphere, every touching point landing)."""
    block, state, history = curved_landing_plies(smoothing=0.05)
    facing = block.facing(state)
    assert block.curved and facing.on_edge is None
    found = ply_landing.landing(block, state, history, facing)
    assert found is not None and len(found.rows) >= 40
    assert found.edge is None and found.place is None


UNIT = np.array([[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]])  # T on z = 0, mm


def test_a_way_straight_through_an_edge_of_a_moving_face_crosses_at_its_share_of_the_step():
    """T carried by u over the step, a point's way straight through T's edge y = 0 relative to
    T, crossing it at the share t_c of the step: the gap along nu (no part along the edge) is
    linear in time, so theta = t_c exactly (docs/theory.md §9.3a). g_0 is taken to the edge's
    point on T's corners then: on T's corners now it gives 0.4436 for 0.37."""
    u, way, t_c = np.array([0.01, -0.02, 0.003]), np.array([0.02, -0.03, -0.05]), 0.37
    crossing = np.array([0.4, 0.0, 0.0])  # on the edge, relative to T
    then, now = crossing - t_c * way, crossing + u + (1.0 - t_c) * way
    closest = np.array([crossing[0] + (1.0 - t_c) * way[0], 0.0, 0.0])  # on the edge, T then
    feature = np.array([[1.0 - closest[0], closest[0], 0.0]])
    nu = -(now - (closest + u)) / np.linalg.norm(now - (closest + u))  # g < 0: through
    theta, _ = ply_landing.edge_crossing(
        UNIT, UNIT + u, then[None], now[None], feature, nu[None], nu[None]
    )
    assert abs(theta[0] - t_c) <= 1e-12


def test_an_edge_points_anchor_lies_on_the_face_off_its_crossing_only_along_nu():
    """A way passing beside an edge's line (m = nu tilted 37 deg from T's normal): the anchor
    lies on T's plane and differs from the way's crossing p_c = p_0 + theta (p - p_0) only
    along nu, so that the slip the friction measures across nu is the way's after the crossing
    (docs/theory.md §9.3a). Without the move along nu onto T's plane it is 1.4e-3 mm across."""
    q, nu = np.array([0.5, 0.0, 0.0]), np.array([0.0, -0.6, 0.8])
    then = q + np.array([0.05, -0.01, 0.03])
    now = q + np.array([0.1, 0.0, 0.0]) - 0.02 * nu
    theta, place = ply_landing.edge_crossing(
        UNIT, UNIT, then[None], now[None], np.array([[0.5, 0.5, 0.0]]), nu[None], nu[None]
    )
    anchor = place[0] @ UNIT[0]
    offset = anchor - (then + theta[0] * (now - then))
    assert abs(anchor[2]) <= 1e-12
    assert np.linalg.norm(offset - (offset @ nu) * nu) <= 1e-12
    assert 0.0 < theta[0] < 1.0


def test_beside_a_growths_edge_the_gaps_zero_is_the_faces_plane():
    """Points landing beside a growth's edge (``Facing.on_growth``, not joined), whose gap's
    sign is T's normal's: the zero their way crossed is T's plane, theta = h_0 / (h_0 - h)
    from their heights over it then and now (docs/theory.md §9.3a), whatever nu (here 80 deg
    from T's normal). With m = nu it is off by up to 0.3."""
    block, state, history = landing_plies(0.05, "normal law")
    facing = block.facing(state)
    rows = ply_landing.landing_rows(block, history, facing)
    flag = np.zeros(len(facing.gap), dtype=bool)
    flag[rows] = True
    tilted = np.array([np.sin(np.radians(80.0)), 0.0, np.cos(np.radians(80.0))])
    beside = dataclasses.replace(
        facing,
        on_edge=flag,
        on_growth=flag,
        joined=np.zeros_like(flag),
        normal=np.where(flag[:, None], tilted, facing.normal),
    )
    found = ply_landing.landing(block, state, history, beside)
    assert found is not None and len(found.rows) >= 10

    def height(corners, points):
        normal = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
        normal /= np.linalg.norm(normal, axis=1)[:, None]
        return np.einsum("ri,ri->r", normal, points - corners[:, 0])

    _, y = block._faces(state)
    triangle = facing.triangle[found.rows]
    assert history.sides is not None
    h0 = np.maximum(height(history.sides.corners[triangle], history.sides.faces[found.rows]), 0)
    h = height(y[triangle], facing.face[found.rows])
    expected = np.where(h < 0.0, h0 / (h0 - h), 1.0)
    assert np.abs(found.theta - expected).max() <= 1e-9
