"""A tool contact's friction dissipation up to where a node leaves the tool (elements/
contact_history.py ``departure``; docs/theory.md §9.2): a node touching at the last accepted
step and off the tool at the end of a step slid, in that step, from where it was to the point
of its way where it left the contact surface, under a normal force falling to 0, and Coulomb
friction dissipated on that slip (the midpoint rule: the mean of the penetrations p_0 and 0)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from elements import MindlinShell, RigidCylinder, RigidPlane, RigidSurface
from elements.contact import Contact
from femcore import Body, Mesh, Model
from femcore.state import State
from materials import ElasticShell
from solvers import Static
from solvers.dynamics import EnergyAccount
from solvers.step import LumpedMasses, explicit_step
from tests.explicit_runs import run_explicitly

MU = 0.3
PENALTY = 1.0e3  # N/mm per node
STEPS = 100
DURATION = 1.0e-4  # s
DT = DURATION / STEPS  # within the cell's L / c = 4e-6 s (the nodes' motion is prescribed)
SLIDE = 1.0  # mm the nodes are carried along x over the run, at a steady pace
GAP = 0.01  # mm between the nodes and the contact surface at the start
DEPTH = 0.02  # mm into the contact surface at half the run
LIFT = 0.035  # mm the nodes rise over the second half, from DEPTH below the surface
TOUCH = 0.5 * GAP / (GAP + DEPTH)  # 1/6 of the run: 2/3 of the way through step 17
LEAVE = 0.5 + 0.5 * DEPTH / LIFT  # 0.785714 of the run: 4/7 of the way through step 79


def dip(depth: float, lift: float, gap: float):
    """The height over the contact surface of nodes ``gap`` over it at the start, less that
    gap, at progress tau: down to ``depth`` into it at tau = 0.5, then up by ``lift`` at a
    steady pace (piecewise linear, its kink at half the run: a step's and every even number
    of increments' end)."""

    def height(tau):
        tau = np.asarray(tau, dtype=float)
        down = -(gap + depth) * 2.0 * np.minimum(tau, 0.5)
        return down + lift * 2.0 * np.maximum(tau - 0.5, 0.0)

    return height


def tools(rise=None):
    """The frictional plane z = 0, analytic and meshed (a flat 60 x 60 mm surface), at rest
    or, with ``rise`` a(tau), moved by a(tau) along z."""
    table = Mesh.rectangle(60.0, 60.0, nx=2, ny=2)
    table = table.with_points(table.points - [20.0, 20.0, 0.0])
    moved = {} if rise is None else {"motion": (0.0, 0.0, 1.0), "amplitude": rise}
    return {
        "plane": RigidPlane((0, 0, 0), (0, 0, 1), **moved),
        "meshed": RigidSurface(table, **moved),
    }


def dipped_plate(name: str, gap: float = GAP, lift: float = LIFT, tool_moves: bool = True):
    """A 20 x 20 x 1 mm plate (one Mindlin cell) ``gap`` over the contact surface of the tool
    ``name`` of ``tools``, its four nodes carried SLIDE along x at a steady pace while they
    dip DEPTH into the surface at half the run and rise by ``lift`` over the second half
    relative to the tool (``dip``: the tool moving, or the plate; a static solver ramps a
    prescribed displacement with the load factor, a tool's motion follows its amplitude):
    each node touches at TOUCH, slides while the tool presses it and leaves at LEAVE."""
    flat = Mesh.rectangle(20.0, 20.0, nx=1, ny=1)
    model = Model(flat.with_points(flat.points + [0.0, 0.0, 0.5 + gap]))
    model.add(MindlinShell(ElasticShell(E=70e3, nu=0.3, thickness=1.0, density=2.7e-9)))
    height = dip(DEPTH, lift, gap)
    if tool_moves:
        model.contact(tools(lambda tau: -height(tau))[name], friction=MU, penalty=PENALTY)
        model.displace(np.arange(4), ux=SLIDE, uy=0.0, uz=0.0, amplitude="linear")
    else:
        model.contact(tools()[name], friction=MU, penalty=PENALTY)
        model.displace(np.arange(4), ux=SLIDE, uy=0.0, amplitude="linear")
        model.displace(np.arange(4), uz=1.0, amplitude=height)
    return model


def coulomb() -> float:
    """Coulomb's dissipation of the four nodes, from the motion: mu k p over the slip while
    they touch. Each slides from its touch to where it leaves (the plate's pace SLIDE is far
    above mu times the rate of p), its stick spring holding mu p (k_t = k): the slip rate is
    SLIDE - mu dp/dtau, so D = mu k (SLIDE int p dtau - mu [p^2 / 2]), and p = 0 at both
    ends: D = 4 mu k SLIDE DEPTH (LEAVE - TOUCH) / 2, p a triangle of height DEPTH."""
    return 4 * MU * PENALTY * SLIDE * DEPTH * (LEAVE - TOUCH) / 2.0


@pytest.mark.parametrize("name", ["plane", "meshed"])
def test_a_plate_lifted_off_a_frictional_tool_dissipates_coulombs_work_until_it_left(name):
    """The dipped plate by the explicit step (STEPS of DT): the record is ``coulomb``'s closed
    form, 7.428571 N mm, to 1e-12 (the penetration linear over each step, its kink at a
    step's end, so the midpoint rule is exact, the touch and the departure each counted from
    the point of the step's way where it happened). The departure step's slip, 4/7 of a
    step's way from a penetration p_i = 4e-4 mm plus the stick spring's mu p_i, was not
    counted: 4 mu k p_i / 2 (mu p_i + 4/7 SLIDE / STEPS) = 1.40e-3 N mm less, 7.427171
    (1.9e-4 of it; fails there)."""
    compiled, state = run_explicitly(dipped_plate(name), STEPS, DURATION)
    assert state.load_factor == pytest.approx(1.0, rel=1e-12)
    tool = compiled.tool_displacements(state)[0, 2]
    clear = state.positions[:4, 2] - tool - 0.5  # off the tool's contact surface at the end
    np.testing.assert_allclose(clear, LIFT - DEPTH, rtol=1e-9)
    assert compiled.dissipated_energy(state) == pytest.approx(coulomb(), rel=1e-12)


@pytest.mark.parametrize("increments", [2, 4, 10])
def test_static_counts_the_slip_and_the_dissipation_of_a_departing_increment(increments):
    """The dipped plate on the plane by Static in 2, 4 or 10 increments (the kink of the dip at
    an increment's end; the tool's motion follows its amplitude under Static): each node
    ends with the slip SLIDE (LEAVE - TOUCH) = 0.619048 mm, its tangential way while
    touching (the stick spring holds nothing where it touched or where it left), and the
    dissipation is ``coulomb``'s, both to 1e-12 (p and the way linear over each increment).
    Static's result records the dissipation of each frame ("friction").
    The departure's increment was not counted: the slip ended at that increment's start less
    the stick spring's mu p there, 0.327333, 0.582583 and 0.531533 mm (fails there)."""
    result = Static(increments=increments, progress=False).solve(dipped_plate("plane"))
    assert result.converged
    np.testing.assert_allclose(
        result.field("contact_slip")[:4], SLIDE * (LEAVE - TOUCH), rtol=1e-12
    )
    friction = result.energies["friction"]  # one record per frame, the last the run's end
    assert len(friction) == len(result.frames)
    assert friction[0] == 0.0 and np.all(np.diff(friction) >= 0.0)
    assert friction[-1] == pytest.approx(coulomb(), rel=1e-12)


@pytest.mark.parametrize("share", [0.25, 0.5, 0.8])
def test_the_explicit_energy_balance_after_a_departure_is_the_midpoint_rules_closed_form(share):
    """The plate starting on the plane's contact surface (touching, p = 0: no first touch),
    carried along x at v = SLIDE / DURATION, dipped DEPTH and lifted at w so that it leaves a
    share ``share`` of a step after t(i) (p_i = share w dt). Until then the scheme is exact
    (the forces linear over each step; the dissipation is Coulomb's); in the step it leaves,
    the contact forces at t(i) are charged over the half step after it, (1 - share) of
    which was off the tool, and the slip to where it left is dissipated at the mean limit
    force mu k p_i / 2. The balance at t(i + 1) (docs/theory.md §6.1) is then, per node,
    k p_i w dt / 2 - mu k p_i v dt / 2 less the normal and stick springs' 1/2 k p_i^2
    (1 + mu^2) plus the dissipation mu k p_i / 2 (mu p_i + share v dt):
    (1 - share) k p_i dt (w - mu v) / 2 (to 1e-9, round-off, as at a first touch:
    tests/test_explicit_first_touch.py): 8.40e-4, 1.118e-3 and 7.13e-4 N mm for the three
    shares. Without the departure's slip the dissipation of that step was 0 and the balance
    4 mu k p_i / 2 (mu p_i + share v dt) further off: 1.389e-3, 3.272e-3 and 6.112e-3 N mm
    (fails there)."""
    leave_step = 64
    # w: the node leaves at (leave_step + share) dt, DEPTH below the surface at STEPS / 2 dt.
    rise = DEPTH / ((leave_step + share) / STEPS - 0.5)  # mm over the unit of progress
    model = dipped_plate("plane", gap=0.0, lift=0.5 * rise, tool_moves=False)
    compiled = model.compile()
    state = compiled.initial_state()
    masses = LumpedMasses.of(compiled, state)
    account = EnergyAccount(thin=1)
    previous = 0.0
    for step in range(leave_step + 2):
        checking = step == leave_step + 1
        outcome = explicit_step(
            compiled, state, DT, masses, dt_prev=previous, duration=DURATION, checking=checking
        )
        account.accept(*outcome.energy)
        if checking:
            break
        if step == leave_step:  # the last state touching
            p_i = 0.5 - (state.positions[0, 2])
        state, previous = compiled.commit(outcome.state), DT
    w, v = rise / DURATION, SLIDE / DURATION
    assert p_i == pytest.approx(share * w * DT, rel=1e-9)
    assert outcome.strain_energy is not None
    friction = compiled.dissipated_energy(state)
    balance, _ = account.check(outcome.energy, outcome.strain_energy, friction)
    expected = 4 * (1.0 - share) * PENALTY * p_i * DT * (w - MU * v) / 2.0
    assert balance * account.largest == pytest.approx(abs(expected), rel=1e-9)


def test_a_node_leaving_a_cylinder_slips_to_where_its_way_crossed_the_surface():
    """One node sliding on a cylinder (R = 10 mm, h / 2 = 0.5 mm) at its friction limit, some
    0.05 mm into its contact surface near the top, carried 0.2 mm along x and up to 0.1 mm
    clear of the contact surface in one step: its way crossed the surface at theta = p_0 /
    (p_0 + g) of it (g its gap at the end, both to the cylinder's contact surface), and its
    slip is its offset from its anchor there in the tangent plane of that point (the
    limit's spring mu p_0 behind it at the start, nothing held at p = 0), dissipated at mu k
    p_0 / 2: the geometry's figures to 1e-12 (a slip of 0.0785 mm, 0.0583 N mm; 0 before),
    and its anchor and place forgotten as it leaves."""
    radius, offset, penalty = 10.0, 0.5, 100.0
    far = [50.0, 0.0, 50.0]
    tool = RigidCylinder((0, 0, 0), (0, 1, 0), radius)
    mesh = Mesh(np.array([[0.0, 0.0, radius + offset + 1.0], far]), lines=np.array([[0, 1]]))
    contact = Contact(tool, [0], offset=offset, penalty=penalty, friction=MU)
    block = contact.bind(Body.bare(mesh))
    top = np.array([0.0, 0.0, radius + offset - 0.05])
    history = block.update_history(at(top, far), block.initial_history())  # lands straight down
    # slid 0.1 mm along x: at its limit, its anchor where the spring holds mu k p
    start = top + [0.1, 0.0, 0.0]
    history = block.update_history(at(start, far), history)
    anchor = history.anchor[0].copy()
    end = start + np.array([0.2, 0.0, 0.15])
    left = block.update_history(at(end, far), history)
    gap = np.linalg.norm(end[[0, 2]]) - radius - offset
    depth = radius + offset - np.linalg.norm(start[[0, 2]])
    theta = depth / (depth + gap)
    point = start + theta * (end - start)
    normal = point * [1.0, 0.0, 1.0] / np.linalg.norm(point[[0, 2]])
    r = point - anchor
    slip = np.linalg.norm(r - (r @ normal) * normal)
    assert left.slip[0] - history.slip[0] == pytest.approx(slip, rel=1e-12)
    dissipated = MU * penalty * 0.5 * depth * slip
    assert left.dissipated - history.dissipated == pytest.approx(dissipated, rel=1e-12)
    assert np.isnan(left.anchor[0]).all() and np.isnan(left.place[0]).all()


def test_an_augmented_node_leaves_the_surface_its_multiplier_moves_out():
    """An augmented contact's node (Static's Uzawa passes, elements/augmented_contact.py) with
    the multiplier lambda_N = 2 N (k = 100 N/mm: its contact surface lambda_N / k = 0.02 mm
    further out, z = 0.52 mm over the plane) sliding 0.05 mm into the plain surface (p_0 =
    0.07 mm to its own, the normal force lambda_N + k p = 7 N), its anchor mu p_0 behind it;
    carried 0.2 mm along x and up to 0.1 mm clear of its surface (z = 0.62 mm) in one step:
    it left at theta = 0.07 / 0.17 of its way, so it slipped mu p_0 + 0.2 theta mm under a
    limit falling from mu 7 N, dissipating mu k p_0 / 2 times that (the plane's figures, to
    1e-12; 0 before; measured to the plain surface, theta = 0.05 / 0.17, it would slip 0.0235
    mm less)."""
    plane = RigidPlane((0, 0, 0), (0, 0, 1))
    far = [50.0, 0.0, 50.0]
    mesh = Mesh(np.array([[0.0, 0.0, 1.0], far]), lines=np.array([[0, 1]]))
    contact = Contact(plane, [0], offset=0.5, penalty=100.0, friction=MU, augmented=True)
    block = contact.bind(Body.bare(mesh))
    history = replace(block.initial_history(), multiplier=np.array([2.0]))
    history = block.update_history(at([0.0, 0.0, 0.45], far), history)  # lands straight down
    history = block.update_history(at([0.1, 0.0, 0.45], far), history)  # slides to its limit
    assert history.anchor[0, 0] == pytest.approx(0.1 - MU * 0.07, rel=1e-12)
    left = block.update_history(at([0.3, 0.0, 0.62], far), history)
    slip = MU * 0.07 + 0.2 * 0.07 / 0.17
    assert left.slip[0] - history.slip[0] == pytest.approx(slip, rel=1e-12)
    dissipated = MU * 100.0 * 0.5 * 0.07 * slip
    assert left.dissipated - history.dissipated == pytest.approx(dissipated, rel=1e-12)


def test_an_augmented_node_leaving_after_a_uzawa_pass_dissipates_the_force_it_left_with():
    """An augmented node held on the plain surface by its multiplier alone (lambda_N = 2 N, k =
    100 N/mm: the converged Uzawa state, p = 0, the normal force 2 N, so p_0 = lambda_N / k =
    0.02 mm to its moved surface), at its friction limit, carried 0.2 mm along x and 0.1 mm
    clear of the plain surface in one increment, whose Uzawa pass (Static's, at the
    increment's end, before it is accepted) takes its multiplier away: it left at theta =
    0.02 / 0.12 of its way, slipping mu p_0 + 0.2 theta mm and dissipating mu k p_0 / 2 times
    that, the plane's figures to 1e-12, as without the pass (measured to the surface after the
    pass it slipped 0.006 mm, the traction's lambda_T / k_t, and dissipated nothing)."""
    far = [50.0, 0.0, 50.0]
    mesh = Mesh(np.array([[0.0, 0.0, 1.0], far]), lines=np.array([[0, 1]]))
    contact = Contact(
        RigidPlane((0, 0, 0), (0, 0, 1)),
        [0],
        offset=0.5,
        penalty=100.0,
        friction=MU,
        augmented=True,
    )
    block = contact.bind(Body.bare(mesh))
    history = replace(block.initial_history(), multiplier=np.array([2.0]))
    history = block.update_history(at([0.0, 0.0, 0.5], far), history)  # on the plain surface
    history = block.update_history(at([0.1, 0.0, 0.5], far), history)  # slides to its limit
    end = at([0.3, 0.0, 0.62], far)
    passed, _ = block.augment(end, history)
    assert passed.multiplier[0] == 0.0  # the premise: the pass took it away
    slip = MU * 0.02 + 0.2 * 0.02 / 0.12
    dissipated = MU * 100.0 * 0.5 * 0.02 * slip
    for before in (history, passed):
        left = block.update_history(end, before)
        assert left.slip[0] - history.slip[0] == pytest.approx(slip, rel=1e-12)
        assert left.dissipated - history.dissipated == pytest.approx(dissipated, rel=1e-12)


def at(position, far):
    """A state of a two-node line: node 0 at ``position``, node 1 at ``far``, at rest."""
    zero = np.zeros((2, 3))
    return State(np.array([position, far], dtype=float), zero, zero.copy(), zero.copy())


def test_a_node_leaving_for_beyond_a_meshed_tools_search_distance_slips_to_where_it_left():
    """A node sliding 0.05 mm into the contact surface of a 20 x 20 mm table meshed 10 x 10 (a
    search distance of some 3 mm), its anchor mu p_0 behind it along x, moved in one step 2 mm
    along x and up to 5 mm clear of the surface: it left at theta = 0.05 / 5.05 of its way,
    so it slipped mu p_0 + 2 theta mm, dissipated at mu k p_0 / 2, as on the analytic plane
    the table lies in (both to 1e-12: the way and the gaps exact, the table flat): the
    departure asks the tool's exact distances, which keep nothing (the meshed tool's
    ``distance`` keeps its last search for the nodes' next step)."""
    table = Mesh.rectangle(20.0, 20.0, nx=10, ny=10)
    table = table.with_points(table.points - [10.0, 10.0, 0.0])
    far = [50.0, 0.0, 50.0]
    slip = MU * 0.05 + 2.0 * 0.05 / 5.05
    for tool in (RigidPlane((0, 0, 0), (0, 0, 1)), RigidSurface(table)):
        mesh = Mesh(np.array([[0.0, 0.0, 1.0], far]), lines=np.array([[0, 1]]))
        contact = Contact(tool, [0], offset=0.5, penalty=100.0, friction=MU)
        block = contact.bind(Body.bare(mesh))
        history = block.update_history(at([0.0, 0.0, 0.45], far), block.initial_history())
        history = block.update_history(at([0.4, 0.0, 0.45], far), history)  # at its limit
        if isinstance(tool, RigidSurface):
            assert tool.search_distance < 4.0  # the case's premise: it leaves beyond it
        left = block.update_history(at([2.4, 0.0, 5.5], far), history)
        name = type(tool).__name__
        assert left.slip[0] - history.slip[0] == pytest.approx(slip, abs=1e-12), name
        dissipated = MU * 100.0 * 0.5 * 0.05 * slip
        assert left.dissipated - history.dissipated == pytest.approx(dissipated, rel=1e-12)
