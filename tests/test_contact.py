"""Rigid tools and frictionless penalty contact (elements/tools.py, elements/contact.py,
Model.contact): a plate resting on a plane carries its weight as a pressure rho_A g with its
contact surface h / 2 below its mid-surface, and the contact tangent is the derivative of the
contact force on a sphere and a cylinder, outside and inside."""

import numpy as np
import pytest

from elements import FibrousShell, MindlinShell, RigidCylinder, RigidPlane, RigidSphere
from elements.contact import Contact
from femcore import Mesh, Model
from femcore.state import State
from materials import ElasticShell, presets
from solvers import DynamicRelaxation, Static

G = 9810.0  # mm/s^2


def resting_plate(element, thickness: float) -> tuple[Model, Mesh]:
    """A 100 x 100 mm plate laid on the plane z = 0 (its mid-surface h / 2 above it), its
    in-plane motion held, under gravity."""
    flat = Mesh.rectangle(100.0, 100.0, nx=4, ny=4)
    mesh = flat.with_points(flat.points + [0.0, 0.0, 0.5 * thickness])
    model = Model(mesh)
    model.add(element)
    model.fix(lambda x, y, z: np.ones_like(x, dtype=bool), ["ux", "uy"])
    model.contact(RigidPlane((0.0, 0.0, 0.0), (0.0, 0.0, 1.0)))
    model.gravity((0.0, 0.0, -G))
    return model, mesh


@pytest.mark.parametrize(
    "element, thickness, solver",
    [
        (MindlinShell(ElasticShell(E=70e3, nu=0.3, thickness=1.0, density=2.7e-9)), 1.0, "static"),
        (FibrousShell(presets.g986_stack()), 6.0, "static"),
        (FibrousShell(presets.g986_stack()), 6.0, "relaxation"),
    ],
)
def test_a_plate_resting_on_a_plane_carries_its_weight_as_a_uniform_pressure(
    element, thickness, solver
):
    """Statics of a flat plate on a flat floor: the floor's force at each node is the node's
    weight m_i g (so the pressure is rho_A g over each node's share of the area) and the
    total on the tool is the plate's weight (1e-6); the contact surface sits on the plane:
    mid-surface z - h / 2 within 1 % of h / 2 (the automatic penalty's sinking, g dt^2 / 0.4,
    is orders below)."""
    model, mesh = resting_plate(element, thickness)
    compiled = model.compile()
    run = (Static(increments=1) if solver == "static" else DynamicRelaxation(tol=1e-8)).solve(
        compiled
    )
    assert run.converged
    contact = compiled.blocks[1]
    state = compiled.initial_state()
    state.positions = run.positions.copy()
    weight = compiled.mass0.sum() * G
    assert contact.tool_force(state)[2] == pytest.approx(-weight, rel=1e-6)
    forces = run.field("contact_force")
    np.testing.assert_allclose(forces, compiled.mass0 * G, rtol=1e-6)
    gap = run.positions[:, 2] - 0.5 * thickness
    assert np.abs(gap).max() < 0.01 * 0.5 * thickness
    assert np.allclose(run.field("contact_gap"), gap)


@pytest.mark.parametrize(
    "tool",
    [
        RigidSphere((0.0, 0.0, -20.0), 20.0),
        RigidSphere((0.0, 0.0, 5.0), 6.0, side="inside"),
        RigidCylinder((0.0, 0.0, -20.0), (1.0, 0.2, 0.0), 20.0),
        RigidCylinder((0.0, 0.0, 5.0), (0.0, 1.0, 0.0), 6.0, side="inside"),
        RigidPlane((0.0, 0.0, 0.0), (0.2, 0.1, 1.0), motion=(0.0, 0.0, 0.3)),
    ],
)
def test_the_contact_tangent_is_the_derivative_of_its_force(tool):
    """Central differences of the contact force against the block's tangent (k n n^T - k p
    c (I - n n^T - a a^T)) at every node, penetrating or not: 1e-6 of the penalty."""
    rng = np.random.default_rng(3)
    mesh = Mesh.rectangle(4.0, 4.0, nx=2, ny=2)
    x = mesh.points + rng.normal(scale=0.3, size=mesh.points.shape) - [2.0, 2.0, 0.4]
    contact = Contact(tool, np.arange(mesh.n_nodes), offset=0.5, penalty=100.0)
    block = contact.bind(mesh, None, None)
    zero = np.zeros_like(x)
    state = State(positions=x, directors=zero, velocities=zero, angular_velocities=zero)
    state.load_factor = 0.5
    p, _, _ = block._touch(state)
    assert (p > 0).sum() >= 3  # some nodes penetrate
    part = block.tangent(state)[0]
    step = 1e-6
    for node in range(mesh.n_nodes):
        for j in range(3):
            plus, minus = x.copy(), x.copy()
            plus[node, j] += step
            minus[node, j] -= step
            state.positions = plus
            f_plus = block.internal_force(state)[0][node]
            state.positions = minus
            f_minus = block.internal_force(state)[0][node]
            numeric = (f_plus - f_minus) / (2 * step)
            exact = part.blocks[node, 0, :, 0, j]
            # truncation O(step^2 k / R^2) and rounding O(k p eps / step): both far below
            assert np.abs(numeric - exact).max() < 1e-6 * 100.0


def test_tools_and_contact_refuse_bad_input():
    with pytest.raises(ValueError, match="non-zero"):
        RigidPlane((0, 0, 0), (0, 0, 0))
    with pytest.raises(ValueError, match="radius"):
        RigidSphere((0, 0, 0), -1.0)
    with pytest.raises(ValueError, match="side"):
        RigidCylinder((0, 0, 0), (1, 0, 0), 1.0, side="above")
    with pytest.raises(ValueError, match="rigid tool"):
        Contact("floor", [0])
    with pytest.raises(ValueError, match="penalty"):
        Contact(RigidPlane((0, 0, 0), (0, 0, 1)), [0], penalty=-1.0)


def test_the_automatic_penalty_keeps_the_explicit_step_stable():
    """CentralDifference at its automatic step (the shell's) with the floor's automatic
    penalty: the run passes its energy checks (a blow-up would stop it) and, damped, settles
    with the floor carrying the plate's weight (1e-6)."""
    from solvers import CentralDifference

    model, _ = resting_plate(
        MindlinShell(ElasticShell(E=70e3, nu=0.3, thickness=1.0, density=2.7e-9)), 1.0
    )
    compiled = model.compile()
    run = CentralDifference(duration=0.005, damping=2e4, progress=False).solve(compiled)
    assert run.converged
    state = compiled.initial_state()
    state.positions = run.positions.copy()
    weight = compiled.mass0.sum() * G
    assert compiled.blocks[1].tool_force(state)[2] == pytest.approx(-weight, rel=1e-6)


def test_a_plate_slides_down_a_frictionless_slope_with_g_sin_phi():
    """Explicit: a plate laid on a plane inclined at 20 deg slides down it by 1/2 g sin(phi)
    t^2 (its centre of mass; frictionless, the plane carries g cos(phi)) and stays on it
    (normal motion below 1e-6 mm, the automatic penalty's sinking); measured 1e-12."""
    from solvers import CentralDifference

    phi, thickness, duration = np.radians(20.0), 1.0, 0.002
    flat = Mesh.rectangle(20.0, 20.0, nx=2, ny=2)
    c, s = np.cos(phi), np.sin(phi)
    normal = np.array([s, 0.0, c])
    x = flat.points
    tilted = np.column_stack([x[:, 0] * c, x[:, 1], -x[:, 0] * s]) + 0.5 * thickness * normal
    model = Model(flat.with_points(tilted))
    model.add(MindlinShell(ElasticShell(E=70e3, nu=0.3, thickness=thickness, density=2.7e-9)))
    model.contact(RigidPlane((0.0, 0.0, 0.0), normal))
    model.gravity((0.0, 0.0, -G))
    run = CentralDifference(duration=duration, progress=False).solve(model)
    assert run.converged
    mean = run.displacements.mean(axis=0)
    down_the_slope = np.array([c, 0.0, -s])
    assert mean @ down_the_slope == pytest.approx(0.5 * G * s * duration**2, rel=1e-6)
    assert abs(mean @ normal) < 1e-6
