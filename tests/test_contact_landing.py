"""A tool contact's friction dissipation counted from where a node touches (elements/contact.py,
"Friction"; docs/theory.md §9.2): a node that lands in a step is anchored, for that step, at
the point of its way where it touched the contact surface, so the tangential motion before
it touched is not counted as slip."""

from __future__ import annotations

import numpy as np
import pytest

from elements import MindlinShell, RigidPlane, RigidSurface
from elements.contact import Contact
from femcore import Body, Mesh, Model
from femcore.state import State
from materials import ElasticShell
from solvers import Static
from tests.explicit_runs import run_explicitly

MU = 0.3
PENALTY = 1.0e3  # N/mm per node
STEPS = 100
DURATION = 1.0e-4  # s
# A step, DURATION / STEPS = 1e-6 s, is within the cell's L / c = 4e-6 s and the springs'
# 2 sqrt(m / k) = 3e-5 s.
GAP = 0.1  # mm between the contact surface and the nodes at the start
RISE = 0.12  # mm the tool rises over the run: it reaches the nodes at 0.1 / 0.12 = 83 1/3 steps
SLIDE = 1.0  # mm the nodes are carried along x over the run


def tools():
    """The rising tool, analytic and meshed (a flat 60 x 60 mm surface below the plate)."""
    table = Mesh.rectangle(60.0, 60.0, nx=2, ny=2)
    meshed = RigidSurface(
        table.with_points(table.points - [20.0, 20.0, 0.0]),
        motion=(0.0, 0.0, RISE),
        amplitude="linear",
    )
    plane = RigidPlane((0, 0, 0), (0, 0, 1), motion=(0.0, 0.0, RISE), amplitude="linear")
    return {"plane": plane, "meshed": meshed}


def carried_plate(name: str):
    """(the flat mesh, the model): a 20 x 20 x 1 mm plate (one Mindlin cell) GAP above the
    contact surface of the tool ``name`` of ``tools``, which rises by RISE, its four nodes
    carried by SLIDE along x (both linear in the load factor)."""
    flat = Mesh.rectangle(20.0, 20.0, nx=1, ny=1)
    model = Model(flat.with_points(flat.points + [0.0, 0.0, 0.5 + GAP]))
    model.add(MindlinShell(ElasticShell(E=70e3, nu=0.3, thickness=1.0, density=2.7e-9)))
    model.contact(tools()[name], friction=MU, penalty=PENALTY)
    model.displace(np.arange(4), ux=SLIDE, uy=0.0, uz=0.0, amplitude="linear")
    return flat, model


@pytest.mark.parametrize("name", ["plane", "meshed"])
def test_a_node_carried_onto_a_rising_tool_dissipates_coulombs_work_after_it_touched(name):
    """A 1 mm plate (one cell) carried at a steady pace along x (1 mm over the run) while a
    frictional tool (mu = 0.3) rises onto it at a steady pace (0.12 mm, from 0.1 mm below its
    contact surface): each of its four nodes touches at t_c and then slides with the normal
    force k p(t), p rising linearly, so Coulomb's dissipation is the integral of mu k p dx
    less what the stick spring holds at the end, mu k p^2 / 2 x mu: D = 4 mu k p_end^2 / 2
    (SLIDE / RISE - mu) (p_end = 0.02 mm, D = 1.928 N mm). The gap is linear in time here and
    the force linear over each step, so the record is that integral to round-off (asserted
    1e-12 relative, the sum's round-off ~1e-15 a step). The touch falls 1/3 of the way
    through step 84; anchored where the nodes were at step 83 (the code before), the 1/3
    step's sliding before the touch counted as slip at half the landing step's limit force:
    4 mu k p_1 / 2 x SLIDE / 300 = 1.6e-3 N mm more (p_1 = 8e-4 mm), 8.3e-4 of D: it
    fails there."""
    flat, model = carried_plate(name)
    compiled, state = run_explicitly(model, STEPS, DURATION)
    assert state.load_factor == pytest.approx(1.0, rel=1e-12)
    np.testing.assert_allclose(state.positions[:, 0] - flat.points[:, 0], SLIDE, rtol=1e-12)
    penetration = RISE * state.load_factor - GAP
    coulomb = 4 * 0.5 * MU * PENALTY * penetration**2 * (SLIDE / RISE - MU)
    assert compiled.dissipated_energy(state) == pytest.approx(coulomb, rel=1e-12)


def test_a_landing_steps_exact_gaps_are_searched_once(monkeypatch):
    """The meshed tool's exact distances at the landing nodes' last places (a k-d search that
    widens with the distance) are asked by the step's forces, its history's update and its
    acceptance: the same history and nodes, searched once (twice before in this step)."""
    calls = []
    exact = RigidSurface.exact_distance

    def counted(tool, points, load_factor=0.0):
        calls.append(len(points))
        return exact(tool, points, load_factor)

    monkeypatch.setattr(RigidSurface, "exact_distance", counted)
    _, model = carried_plate("meshed")
    run_explicitly(model, STEPS, DURATION)
    assert calls == [4]  # the four nodes land in one step (step 84)


@pytest.mark.parametrize("increments", [3, 7, 10])
def test_static_counts_the_slip_of_a_landing_increment_from_the_touch(increments):
    """The same plate and rising plane by Static in 3, 7 or 10 increments: the nodes touch
    within an increment (at load factor 0.1 / 0.12) and slide from there, so each ends with
    the slip SLIDE (1 - 0.1 / 0.12) less the stick spring's mu p_end (k_t = k): 0.160667 mm
    (to 1e-12: the gap and the way are linear in the load factor, as the touching point takes
    them). Anchored where they were at the increment before, they slid the whole landing
    increment: 0.327, 0.280, 0.194 mm (fails there)."""
    _, model = carried_plate("plane")
    result = Static(increments=increments, progress=False).solve(model)
    assert result.converged
    slip = SLIDE * (1.0 - GAP / RISE) - MU * (RISE - GAP)
    np.testing.assert_allclose(result.field("contact_slip")[:4], slip, rtol=1e-12)


def test_a_node_landing_from_beyond_a_meshed_tools_search_distance_slips_from_the_touch():
    """A node 5 mm over a 20 x 20 mm meshed table (nx = 10: a search distance of some 3 mm),
    moved 0.5 mm along it at that height in one step, then in a Static-sized step 2 mm along
    and down to 0.05 mm into the contact surface (h / 2 = 0.5 mm): it touched at theta = g /
    (g + p) = 5 / 5.05 of its way, so it slips (1 - theta) 2 mm less the stick spring's mu p
    (k_t = k), 2 x 0.05 / 5.05 - 0.3 x 0.05 mm, as on the analytic plane the table lies in
    (both to 1e-12 mm, rounding: the way and the gap are exact, the table flat). The
    meshed tool's ``distance`` tells the node, past its search distance, a lower bound
    of its gap (the last search's less the move since, 4.5 mm): a theta from that
    slid it 0.006978 mm (fails there)."""
    table = Mesh.rectangle(20.0, 20.0, nx=10, ny=10)
    table = table.with_points(table.points - [10.0, 10.0, 0.0])
    far = [50.0, 0.0, 50.0]

    def at(position):
        zero = np.zeros((2, 3))
        return State(np.array([position, far], dtype=float), zero, zero.copy(), zero.copy())

    expected = 2.0 * 0.05 / 5.05 - MU * 0.05
    for tool in (RigidPlane((0, 0, 0), (0, 0, 1)), RigidSurface(table)):
        mesh = Mesh(np.array([[0.0, 0.0, 5.5], far]), lines=np.array([[0, 1]]))
        contact = Contact(tool, [0], offset=0.5, penalty=100.0, friction=MU)
        block = contact.bind(Body.bare(mesh))
        history = block.update_history(at((0.0, 0.0, 5.5)), block.initial_history())
        history = block.update_history(at((0.4, 0.3, 5.5)), history)
        if isinstance(tool, RigidSurface):
            assert tool.search_distance < 4.0  # the case's premise: beyond its search
        landed = block.update_history(at((2.4, 0.3, 0.45)), history)
        assert landed.slip[0] == pytest.approx(expected, abs=1e-12), type(tool).__name__


def test_a_meshed_tools_exact_distance_is_the_height_over_a_flat_table_at_any_height():
    """``exact_distance`` of the 20 x 20 mm table meshed 10 x 10 at points over its middle
    from 0.1 to 100 mm up (its search distance some 3 mm) is their height (the closest point
    is below them: to 1e-12 mm, rounding), its normal +z, and it keeps nothing: the tool's
    ``distance`` asked afterwards for other points answers as a fresh tool's does."""
    table = Mesh.rectangle(20.0, 20.0, nx=10, ny=10)
    table = table.with_points(table.points - [10.0, 10.0, 0.0])
    tool, fresh = RigidSurface(table), RigidSurface(table)
    heights = np.geomspace(0.1, 100.0, 9)
    points = np.column_stack([np.linspace(-5.0, 5.0, 9), np.linspace(4.0, -3.0, 9), heights])
    d, n = tool.exact_distance(points)
    np.testing.assert_allclose(d, heights, rtol=0.0, atol=1e-12)
    np.testing.assert_allclose(n, np.tile([0.0, 0.0, 1.0], (9, 1)), atol=1e-12)
    others = points[:4] * [1.0, 1.0, 0.01]
    for a, b in zip(tool.distance(others), fresh.distance(others), strict=True):
        np.testing.assert_array_equal(a, b)
