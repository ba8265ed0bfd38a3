"""Rigid tools driven by a force along their free axes (elements/tools.py ``free``, ``force``,
``mass``; elements/contact.py; Model.rigid_node): the blank holder.

A holder (a RigidPlane free along z, pushed down by F) presses a flat plate onto a fixed die
plane. Statics: the plate carries the holder's force to the die, so that the force on the die
is F plus the plate's weight (and the holder's, when it has a mass under gravity) to 1e-6
(Newton's residual tolerance is far below). Explicit dynamics: the holder's node obeys
m a = F - (contact forces): in the air it travels F t^2 / (2 m) (central differences integrate
a constant acceleration exactly: to rounding), and once landed, damped, it rests where the
contact springs balance F, F / (s k) into the plate (s springs of k N/mm each). The contact's
tangent, with the coupling to the tool's node, is the derivative of its forces (the interaction
conformance kit).
"""

import csv
import json

import numpy as np
import pytest

from elements import FibrousShell, MindlinShell, RigidPlane, RigidSphere, RigidSurface
from elements.contact import Contact, FrictionHistory
from femcore import Body, Mesh, Model
from femcore.interaction_checks import (
    check_energy,
    check_force_is_energy_gradient,
    check_tangent,
)
from femcore.state import State
from fibreshell.case import CaseError, load_case
from fibreshell.run import run_case
from materials import ElasticShell, presets
from solvers import CentralDifference, DynamicRelaxation, Static

G = 9810.0  # mm/s^2
SIDE = 20.0  # mm, the plate's side
EVERY_NODE = lambda x, y, z: np.ones_like(x, dtype=bool)  # noqa: E731


def mindlin(thickness: float = 1.0) -> MindlinShell:
    return MindlinShell(ElasticShell(E=1000.0, nu=0.3, thickness=thickness, density=1e-9))


def pressed_plate(element, thickness, force, mass=None, gravity=False, penalty=None, gap=0.0):
    """A SIDE x SIDE plate (2 x 2 cells) lying on the die plane z = 0 (its mid-surface h / 2
    above), its in-plane motion held (the contacts are frictionless), the holder's plane
    ``gap`` above its top face, free along z and pushed down by ``force`` (N), ramped."""
    flat = Mesh.rectangle(SIDE, SIDE, nx=2, ny=2)
    mesh = flat.with_points(flat.points + [0.0, 0.0, 0.5 * thickness])
    model = Model(mesh)
    model.add(element)
    model.fix(EVERY_NODE, ["ux", "uy"])
    model.contact(RigidPlane((0.0, 0.0, 0.0), (0.0, 0.0, 1.0)), penalty=penalty)
    holder = RigidPlane(
        (0.0, 0.0, thickness + gap),
        (0.0, 0.0, -1.0),
        free="z",
        force=(0.0, 0.0, -force),
        amplitude="linear",
        mass=mass,
    )
    model.contact(holder, penalty=penalty)
    if gravity:
        model.gravity((0.0, 0.0, -G))
    return model


@pytest.mark.parametrize(
    "element, thickness",
    [(mindlin(), 1.0), (FibrousShell(presets.g986_stack()), 6.0)],
    ids=["mindlin", "fibrous"],
)
def test_a_holder_carries_its_force_through_the_plate_to_the_die_in_statics(element, thickness):
    """F = 50 N: the die takes F, the holder feels F back (1e-6); the holder went down.
    Without the stability search: the pinched fibrous stack's directors are free to slip
    (its tangent is indefinite there, as the plies' is: README "Comparing kinematics")."""
    model = pressed_plate(element, thickness, 50.0)
    run = Static(increments=2, seek_stable=False).solve(model)
    assert run.converged
    die, holder = run.tool_forces[-1]
    np.testing.assert_allclose(die, [0.0, 0.0, -50.0], atol=1e-6 * 50.0)
    np.testing.assert_allclose(holder, [0.0, 0.0, 50.0], atol=1e-6 * 50.0)
    travel = run.tool_displacements[-1]
    assert travel[0, :].tolist() == [0.0, 0.0, 0.0]  # the die does not move
    assert travel[1, 2] < 0.0 and travel[1, :2].tolist() == [0.0, 0.0]


def test_under_gravity_the_die_carries_the_holder_force_and_both_weights():
    """The plate's weight rho h A g and the holder's stated mass m g add to F on the die (1e-6);
    a holder without a stated mass has no weight (its nominal mass is for the solvers)."""
    rho_h = 1e-9 * 1.0  # t/mm^2
    plate = rho_h * SIDE**2 * G
    for mass, weight in ((None, 0.0), (2e-3, 2e-3 * G)):
        model = pressed_plate(mindlin(), 1.0, 50.0, mass=mass, gravity=True)
        run = Static(increments=2).solve(model)
        assert run.converged
        expected = 50.0 + plate + weight
        assert run.tool_forces[-1, 0, 2] == pytest.approx(-expected, rel=1e-6)


def holder_face(tilt: float = 0.0) -> Mesh:
    """A meshed holder face over the plate, SIDE x SIDE in plan at z = 1 (the plate's top
    face), its facets' normals up (RigidSurface flips them down), tilted about y by ``tilt``
    rad (through its edge x = SIDE)."""
    face = Mesh.rectangle(SIDE, SIDE, nx=4, ny=4)
    x = face.points.copy()
    x[:, 2] = 1.0 + np.tan(tilt) * (x[:, 0] - SIDE)
    return face.with_points(x)


def test_a_meshed_holder_pressed_at_p_pushes_with_p_times_its_face_area():
    """p = 0.125 N/mm^2 on a 20 x 20 mm face: 50 N on the plate and the die (1e-6)."""
    flat = Mesh.rectangle(SIDE, SIDE, nx=2, ny=2)
    model = Model(flat.with_points(flat.points + [0.0, 0.0, 0.5]))
    model.add(mindlin())
    model.fix(EVERY_NODE, ["ux", "uy"])
    model.contact(RigidPlane((0.0, 0.0, 0.0), (0.0, 0.0, 1.0)))
    holder = RigidSurface(holder_face(), flip=True, free="z", pressure=0.125)
    np.testing.assert_allclose(holder.force, [0.0, 0.0, -50.0], rtol=1e-12)
    model.contact(holder)
    run = Static(increments=2).solve(model)
    assert run.converged
    assert run.tool_forces[-1, 0, 2] == pytest.approx(-50.0, rel=1e-6)


def test_a_tilted_face_pushes_along_its_free_axis_with_p_times_its_area_across_it():
    """The same face tilted 0.3 rad: its area grows by 1 / cos, its resultant turns, and
    along z (free) the force stays p x the area in plan, 0.125 x 400 = 50 N; the guides take
    the rest."""
    holder = RigidSurface(holder_face(tilt=0.3), flip=True, free="z", pressure=0.125)
    np.testing.assert_allclose(holder.force, [0.0, 0.0, -50.0], rtol=1e-12)


@pytest.mark.parametrize(
    "options, words",
    [
        ({"pressure": 0.1}, "no free axis"),
        ({"free": "z", "pressure": 0.1, "force": (0, 0, -1.0)}, "both given"),
        ({"free": "z", "pressure": -0.1}, "pressure"),
        ({"free": "x", "pressure": 0.1}, "no component along the free axes"),
    ],
)
def test_a_pressure_needs_free_axes_it_pushes_along_and_no_force(options, words):
    with pytest.raises(ValueError, match=words):
        RigidSurface(holder_face(), flip=True, **options)


def test_dynamic_relaxation_finds_the_same_holder_equilibrium():
    model = pressed_plate(mindlin(), 1.0, 50.0, penalty=200.0)
    run = DynamicRelaxation(tol=1e-8).solve(model)
    assert run.converged
    assert run.tool_forces[-1, 0, 2] == pytest.approx(-50.0, rel=1e-6)
    # Every node of the flat plate takes 50 / 9 N on each side: each spring sinks that / k.
    sink = 50.0 / 9.0 / 200.0
    assert run.tool_displacements[-1, 1, 2] == pytest.approx(-2.0 * sink, rel=1e-5)


def test_pulling_a_plate_from_under_a_holder_takes_twice_mu_times_its_force():
    """The plate slid 1 mm along x between the die and the holder (F = 50 N, mu = 0.2 on both
    faces): the supports pull it with mu F per face, 2 mu F in all (1e-6); the holder's guide
    (its node held along x) holds the holder against the plate's drag, mu F, and the holder
    does not move along x."""
    flat = Mesh.rectangle(SIDE, SIDE, nx=2, ny=2)
    model = Model(flat.with_points(flat.points + [0.0, 0.0, 0.5]))
    model.add(mindlin())
    model.fix(EVERY_NODE, ["uy"])
    model.displace(EVERY_NODE, ux=1.0, amplitude="linear")
    mu, force = 0.2, 50.0
    model.contact(RigidPlane((0.0, 0.0, 0.0), (0.0, 0.0, 1.0)), friction=mu)
    holder = RigidPlane(
        (0.0, 0.0, 1.0), (0.0, 0.0, -1.0), free="z", force=(0, 0, -force), amplitude="step"
    )
    model.contact(holder, friction=mu)
    run = Static(increments=4).solve(model)
    assert run.converged
    plate = np.arange(flat.n_nodes)
    pull = run.reactions[plate].sum(axis=0)
    assert pull[0] == pytest.approx(2.0 * mu * force, rel=1e-6)
    guide = run.reactions[model.rigid_nodes[0].node]
    assert guide[0] == pytest.approx(-mu * force, rel=1e-6)
    np.testing.assert_allclose(run.tool_forces[-1, :, 0], [mu * force, mu * force], rtol=1e-6)
    assert run.tool_displacements[-1, 1, 0] == 0.0


def held_plate_and_holder(gap: float, force: float, mass: float, penalty: float) -> Model:
    """The plate held still (every DOF), the holder ``gap`` above its top face, pushed down
    by ``force`` at once (amplitude step)."""
    flat = Mesh.rectangle(SIDE, SIDE, nx=2, ny=2)
    mesh = flat.with_points(flat.points + [0.0, 0.0, 0.5])
    model = Model(mesh)
    model.add(mindlin())
    model.fix(EVERY_NODE)
    holder = RigidPlane(
        (0.0, 0.0, 1.0 + gap), (0.0, 0.0, -1.0), free="z", force=(0, 0, -force), mass=mass,
        amplitude="step",
    )  # fmt: skip
    model.contact(holder, penalty=penalty)
    return model


def test_a_free_holder_in_the_air_travels_f_t2_over_2m_exactly():
    """F = 1 N on m = 1e-3 t: a = 1000 mm/s^2, 0.05 mm in 0.01 s, short of the 1 mm gap;
    every frame on the parabola to rounding (1e-12 mm)."""
    model = held_plate_and_holder(gap=1.0, force=1.0, mass=1e-3, penalty=100.0)
    run = CentralDifference(duration=0.01, dt=1e-4, kinetic_bound=None).solve(model)
    times = np.array([frame.time for frame in run.frames])
    travel = run.tool_displacements[:, 0, :]
    np.testing.assert_allclose(travel[:, 2], -1.0 * times**2 / (2.0 * 1e-3), rtol=0, atol=1e-12)
    assert np.abs(travel[:, :2]).max() == 0.0
    assert np.abs(run.tool_forces).max() == 0.0  # it never touched


def test_a_landed_damped_holder_rests_where_the_contact_springs_balance_its_force():
    """9 springs of 100 N/mm under F = 1 N: the holder rests F / 900 into the plate's top
    face, 0.01 mm below where it started (damping 2 omega of its mode: settled to 1e-9)."""
    stiffness, mass, gap = 9 * 100.0, 1e-3, 0.01
    model = held_plate_and_holder(gap=gap, force=1.0, mass=mass, penalty=100.0)
    damping = 2.0 * np.sqrt(stiffness / mass)
    run = CentralDifference(duration=0.05, dt=1e-4, damping=damping).solve(model)
    assert run.tool_displacements[-1, 0, 2] == pytest.approx(-(gap + 1.0 / stiffness), rel=1e-9)
    assert run.tool_forces[-1, 0, 2] == pytest.approx(1.0, rel=1e-9)


def test_a_bouncing_holder_keeps_the_energy_balance():
    """Undamped, the holder falls 0.01 mm, lands on the springs and bounces: its kinetic
    energy and the springs' add up to the work of its force (the tool's node is a node like
    any other: its force is external work, its motion kinetic energy), to 1e-3 of the work."""
    model = held_plate_and_holder(gap=0.01, force=1.0, mass=1e-3, penalty=100.0)
    run = CentralDifference(duration=0.05, dt=1e-4, kinetic_bound=None).solve(model)
    e = run.energies
    balance = e["kinetic"] + e["internal"] + e["damping"] - e["external_work"]
    assert e["external_work"].max() >= 0.01  # F x gap: it landed
    assert np.abs(balance).max() < 1e-3 * e["external_work"].max()


def test_the_holder_mass_and_its_springs_bound_the_explicit_step():
    """A light holder on stiff springs: the chosen step stays below 2 / omega of the holder's
    own mode, omega^2 = s k / m."""
    model = held_plate_and_holder(gap=0.0, force=1.0, mass=1e-9, penalty=1e4)
    run = CentralDifference(duration=1e-6, kinetic_bound=None).solve(model)
    assert run.info["dt"] < 2.0 / np.sqrt(9 * 1e4 / 1e-9)


# ---------------------------------------------------------------------- the coupled tangent
def driven_contact(friction: float):
    """A jittered 3 x 3 grid of nodes against a sphere free along x and z whose node (the
    last) has moved by (0.05, 0, 0.1) mm: some nodes penetrate, some do not; with friction,
    even nodes stick and odd ones slip."""
    rng = np.random.default_rng(3)
    grid = Mesh.rectangle(4.0, 4.0, nx=2, ny=2)
    x = grid.points + rng.normal(scale=0.3, size=grid.points.shape) - [2.0, 2.0, -0.5]
    tool = RigidSphere((0.0, 0.0, -20.0), 20.0, free=("x", "z"), mass=1.0)
    mesh = Mesh(np.vstack([x, tool.reference_point()]), triangles=grid.triangles)
    nodes = np.arange(len(x))
    block = Contact(tool, nodes, 0.5, 100.0, friction, tool_node=len(x)).bind(Body.bare(mesh))
    positions = mesh.points.copy()
    positions[-1] += [0.05, 0.0, 0.1]
    zero = np.zeros_like(positions)
    state = State(positions, zero, zero.copy(), zero.copy(), load_factor=0.5)
    history = None
    if friction:
        spread = np.where(nodes % 2, 0.3, 0.01)[:, None]
        anchor = x + spread * rng.normal(size=x.shape)
        history = FrictionHistory(anchor, np.zeros(len(x)), np.full(len(x), 0.1), 0.0)
    return block, state, history


def test_the_driven_contact_force_is_the_energy_gradient_at_the_nodes_and_the_tool():
    block, state, _ = driven_contact(0.0)
    p, _, touching = block.touch(state)
    assert (p > 0).sum() >= 3 and (~touching).sum() >= 1
    check_force_is_energy_gradient(block, state)
    force, _ = block.internal_force(state)
    np.testing.assert_allclose(force.sum(axis=0), 0.0, atol=1e-12)  # the reaction on the tool


@pytest.mark.parametrize("friction", [0.0, 0.4], ids=["frictionless", "friction"])
def test_the_driven_contact_tangent_is_the_force_derivative_with_the_tool_coupling(friction):
    block, state, history = driven_contact(friction)
    assert check_tangent(block, state, history)
    check_energy(block, state, history)


# ---------------------------------------------------------------------- bad input
@pytest.mark.parametrize(
    "options, words",
    [
        ({"free": "z", "force": (1.0, 0.0, -5.0)}, "acts along x"),
        ({"free": ("z",), "motion": (0.0, 0.0, -1.0)}, "free along"),
        ({"mass": 1e-3}, "no free axis"),
        ({"free": ("w",)}, "'x', 'y', 'z'"),
        ({"free": ("z", "z")}, "twice"),
        ({"free": "z", "mass": -1.0}, "tool mass"),
    ],
)
def test_a_driven_tool_refuses_what_it_cannot_do(options, words):
    with pytest.raises(ValueError, match=words):
        RigidPlane((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), **options)


def test_a_driven_tool_needs_its_own_node_and_explicit_dynamics_needs_its_mass():
    holder = RigidPlane((0, 0, 1.0), (0, 0, -1.0), free="z", force=(0, 0, -1.0))
    with pytest.raises(ValueError, match=r"model.contact\(tool"):
        Contact(holder)
    with pytest.raises(ValueError, match="no free axis"):
        Contact(RigidPlane((0, 0, 0), (0, 0, 1.0)), tool_node=3)
    model = held_plate_and_holder(gap=0.0, force=1.0, mass=None, penalty=100.0)
    with pytest.raises(ValueError, match="without a stated mass"):
        CentralDifference(duration=1e-3).solve(model)


@pytest.mark.parametrize(
    "position, mass, free, words",
    [
        ((0.0, 0.0), None, "uz", "3 finite numbers"),
        ((0.0, 0.0, 1.0), -1.0, "uz", "positive number of t"),
        ((0.0, 0.0, 1.0), None, "alpha", "translations only"),
        ((0.0, 0.0, 1.0), None, "wz", "unknown DOF name"),
    ],
)
def test_a_rigid_node_refuses_a_bad_position_mass_or_freedom(position, mass, free, words):
    model = Model(Mesh.rectangle(SIDE, SIDE, nx=2, ny=2))
    with pytest.raises(ValueError, match=words):
        model.rigid_node(position, mass, free)
    assert model.mesh.n_nodes == 9 and not model.rigid_nodes


def test_a_tool_in_two_contacts_has_one_node_and_the_given_mesh_is_unchanged():
    flat = Mesh.rectangle(SIDE, SIDE, nx=2, ny=2)
    model = Model(flat)
    model.add(mindlin())
    holder = RigidPlane((0, 0, 1.0), (0, 0, -1.0), free="z", force=(0, 0, -1.0))
    model.contact(holder, nodes=[0, 1, 2])
    model.contact(holder, nodes=[3, 4])
    assert flat.n_nodes == 9 and model.mesh.n_nodes == 10
    assert [r.node for r in model.rigid_nodes] == [9]
    compiled = model.compile()
    assert [block.tool_node for block in compiled.interactions] == [9, 9]
    assert compiled.dofs.free[9].tolist() == [False, False, True, False, False]


def test_a_predicate_selects_the_body_not_the_tool_node_where_it_lies():
    """The holder's node lies at (0, 0, 1), inside the box x <= 5: a support or a load
    written as a predicate afterwards holds the plate's nodes only (the holder stays free)."""
    flat = Mesh.rectangle(SIDE, SIDE, nx=2, ny=2)
    model = Model(flat)
    model.add(mindlin())
    model.contact(RigidPlane((0, 0, 1.0), (0, 0, -1.0), free="z", force=(0, 0, -1.0)))
    model.fix(lambda x, y, z: x <= 5.0)
    assert model.fixes[-1].nodes.tolist() == [0, 3, 6]
    assert model.compile().dofs.free[9, 2]


def test_a_rigid_node_mass_is_part_of_the_model_fingerprint():
    """A checkpoint of a run with one holder mass is not resumed with another."""
    from femcore.fingerprint import fingerprint

    def tools_part(mass):
        model = Model(Mesh.rectangle(SIDE, SIDE, nx=2, ny=2))
        model.add(mindlin())
        model.rigid_node((0.0, 0.0, 1.0), mass, "uz")
        return fingerprint(model.compile()).parts["tools"]

    assert tools_part(1e-3) == tools_part(1e-3) != tools_part(2e-3)


# ---------------------------------------------------------------------- case files
CASE = """
title = "holder"
[mesh]
rectangle = {{ lx = 20.0, ly = 20.0, nx = 2, ny = 2 }}
[[part]]
element = "mindlin"
material = {{ E = 1000.0, nu = 0.3, thickness = 1.0, density = 1e-9 }}
[[fix]]
nodes = {{ x_min = 0.0 }}
dofs = ["ux", "uy"]
[[contact]]
tool = "plane"
point = [0.0, 0.0, -0.5]
normal = [0.0, 0.0, 1.0]
[[contact]]
tool = "plane"
point = [0.0, 0.0, 0.5]
normal = [0.0, 0.0, -1.0]
{holder}
[solver]
{solver}
"""


def test_a_case_file_drives_a_holder_and_its_history_has_its_force_and_travel(tmp_path):
    path = tmp_path / "holder.toml"
    holder = 'free = ["z"]\nforce = [0.0, 0.0, -50.0]\namplitude = "linear"'
    path.write_text(CASE.format(holder=holder, solver='kind = "static"\nincrements = 2'))
    run = run_case(load_case(path), tmp_path / "out", progress=False)
    assert run.result.converged
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary["tool_forces"]["tool1"][2] == pytest.approx(-50.0, rel=1e-6)
    with open(tmp_path / "out" / "history.csv") as handle:
        rows = list(csv.DictReader(handle))
    travel = float(rows[-1]["tool2_displacement_z"])
    assert travel < 0.0
    assert travel == pytest.approx(summary["tool_displacements"]["tool2"][2], rel=1e-12)


def test_the_shipped_pullout_case_pulls_twice_mu_times_the_holder_force(tmp_path):
    """cases/holder_pullout.toml: a fibrous strip pulled 5 mm from under a 100 N holder, mu =
    0.3 on both faces: the pulled end's reaction is 2 mu F = 60 N, the die carries F, both
    tools are dragged by mu F (1e-6); the holder went down."""
    from pathlib import Path

    case = load_case(Path(__file__).parents[1] / "cases" / "holder_pullout.toml")
    run = run_case(case, tmp_path, progress=False)
    assert run.result.converged
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["reactions"]["end"][0] == pytest.approx(60.0, rel=1e-6)
    die, holder = summary["tool_forces"]["tool1"], summary["tool_forces"]["tool2"]
    np.testing.assert_allclose([die[0], die[2]], [30.0, -100.0], rtol=1e-6)
    np.testing.assert_allclose([holder[0], holder[2]], [30.0, 100.0], rtol=1e-6)
    assert summary["tool_displacements"]["tool2"][2] < 0.0


def test_a_case_file_presses_a_meshed_holder_at_a_pressure(tmp_path):
    face = Mesh.rectangle(SIDE, SIDE, nx=4, ny=4)
    face.with_points(face.points + [0.0, 0.0, 0.5]).write(tmp_path / "face.vtu")
    text = CASE.format(holder="", solver='kind = "static"\nincrements = 2')
    text = text.replace(
        'tool = "plane"\npoint = [0.0, 0.0, 0.5]\nnormal = [0.0, 0.0, -1.0]',
        'tool = "surface"\nfile = "face.vtu"\nflip = true\nfree = ["z"]\npressure = 0.125',
    )
    path = tmp_path / "holder.toml"
    path.write_text(text)
    run = run_case(load_case(path), tmp_path / "out", progress=False)
    assert run.result.converged
    assert run.result.tool_forces[-1, 0, 2] == pytest.approx(-50.0, rel=1e-6)


@pytest.mark.parametrize(
    "holder, solver, key",
    [
        ('free = ["z"]\nforce = [0.0, 0.0, -50.0]', 'kind = "explicit"\nduration = 1e-3', "mass"),
        ('free = ["z"]\nforce = [5.0, 0.0, -50.0]', 'kind = "static"', "force"),
        ('free = "q"', 'kind = "static"', "free"),
        ("mass = 0.001", 'kind = "static"', "mass"),
        ('free = ["z"]\npressure = 0.2', 'kind = "static"', "pressure"),
    ],
)
def test_a_case_file_names_the_key_of_a_bad_holder(tmp_path, holder, solver, key):
    path = tmp_path / "holder.toml"
    path.write_text(CASE.format(holder=holder, solver=solver))
    with pytest.raises(CaseError, match=rf"contact\[1\]\.{key}|contact\[1\].*{key}"):
        load_case(path)


def test_sweep_csv_spreads_each_tool_force_and_travel():
    from fibreshell.sweep import summary_row

    summary = {
        "converged": True,
        "wall_time_s": 1.0,
        "steps": 2,
        "final_load_factor": 1.0,
        "tool_forces": {"tool1": [0.0, 0.0, -50.0]},
        "tool_displacements": {"tool1": [0.0, 0.0, -0.25]},
    }
    row = summary_row(summary)
    assert row["tool1_force_z"] == -50.0 and row["tool1_displacement_z"] == -0.25


def test_holder_ring_covers_its_annulus_with_facets_facing_down():
    """The blank holder mesh of the forming cases: its facets tile the annulus (area
    pi (R^2 - r^2) within the polygon error of its rings, 1e-3) and face -z."""
    from validation.specimens import holder_ring

    ring = holder_ring(51.2, 145.0, 4.0)
    corners = ring.points[ring.triangles]
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    assert (normals[:, 2] < 0).all()
    area = 0.5 * np.linalg.norm(normals, axis=1).sum()
    assert area == pytest.approx(np.pi * (145.0**2 - 51.2**2), rel=1e-3)
    with pytest.raises(ValueError, match="inner < outer"):
        holder_ring(10.0, 5.0, 1.0)


def test_mass_scaling_reports_its_added_mass_as_a_share_of_the_plate_not_of_the_holder():
    """A 100-times-heavier holder on the plate: mass scaling scales the plate's cells alone,
    so its added mass is a share of the plate's rho h A (closed form, to round-off 1e-12),
    and ``max_added_mass`` is judged against that share; a ratio over the model's mass with
    the holder would read a hundred times smaller and let a run through that adds more than
    the cap allows."""
    plate = 1e-9 * 1.0 * SIDE**2  # t, rho h A
    model = pressed_plate(mindlin(), 1.0, 50.0, mass=100.0 * plate)
    target = 8.0 * model.compile().stable_dt(model.compile().initial_state())
    solver = CentralDifference(
        duration=20.0 * target,
        mass_scaling_dt=target,
        max_added_mass=1000.0,
        progress=False,
        kinetic_bound=None,
    )
    run = solver.solve(model)
    added = run.info["added_mass"]
    assert added > 10.0 * plate
    assert run.info["added_mass_ratio"] == pytest.approx(added / plate, rel=1e-12)
    capped = CentralDifference(
        duration=20.0 * target,
        mass_scaling_dt=target,
        max_added_mass=0.5 * added / plate,
        progress=False,
    )
    with pytest.raises(ValueError, match=r"times the elements' mass .*max_added_mass"):
        capped.solve(model)


def test_an_unstated_tool_mass_is_the_mean_nodal_mass_of_the_plate_whatever_the_holder_weighs():
    """Beside a holder of 1e12 plates, a second free tool without a stated mass gets the
    mean nodal mass of the plate's 9 nodes, rho h A / 9 (the docstring of
    ``Model.rigid_node``'s nominal mass; closed form, to round-off), not a mean over the
    heavy holder's node too; and the elements' mass is the plate's rho h A, the holder's
    digits not in it (a difference of the totals lost 7.6e-6 of it)."""
    plate = 1e-9 * 1.0 * SIDE**2  # t, rho h A
    model = pressed_plate(mindlin(), 1.0, 50.0, mass=1e12 * plate)
    model.contact(RigidPlane((0.0, 0.0, 5.0), (0.0, 0.0, -1.0), free="z", force=(0.0, 0.0, -1.0)))
    compiled = model.compile()
    assert compiled.element_mass == pytest.approx(plate, rel=1e-12)
    (unstated,) = compiled.nominal_mass_nodes
    assert compiled.mass0[unstated] == pytest.approx(plate / 9.0, rel=1e-12)
