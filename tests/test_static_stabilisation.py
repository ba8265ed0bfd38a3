"""Static's viscous stabilisation (``stabilise``; solvers/stabilisation.py) and the moving tools
of a static run.

A stabilised increment is the minimum of the total potential plus the dashpots'
pseudo-potential D = 1/2 sum c m |x - x_n|^2 / dlambda (+ the directors'): the dashpot forces
are the gradient of D and their stiffness its Hessian, so Newton stays quadratic; the energy
they dissipate is reported against the strain energy, with a warning past 5 %. A tool's
prescribed motion places it at the load factor of the increment being solved, from the first
Newton iteration on: the converged state of an increment touches the tool where that
increment's load factor puts it.
"""

import warnings

import numpy as np
import pytest

from elements import MindlinShell, RigidPlane
from femcore import Mesh, Model
from materials import ElasticShell
from solvers import Static
from solvers.stabilisation import STABILISATION_BOUND, Dashpots

G = 9810.0  # mm/s^2
SIDE, THICKNESS, RISE = 20.0, 1.0, 2.0  # mm
EVERY_NODE = lambda x, y, z: np.ones_like(x, dtype=bool)  # noqa: E731


def plate_on_a_rising_plane(penalty: float = 1e3) -> Model:
    """A heavy SIDE x SIDE Mindlin plate (2 x 2 cells) lying on the plane z = 0, its in-plane
    motion held, the plane rising by RISE (linear amplitude)."""
    flat = Mesh.rectangle(SIDE, SIDE, nx=2, ny=2)
    model = Model(flat.with_points(flat.points + [0.0, 0.0, 0.5 * THICKNESS]))
    model.add(MindlinShell(ElasticShell(E=1000.0, nu=0.3, thickness=THICKNESS, density=1e-6)))
    model.fix(EVERY_NODE, ["ux", "uy"])
    model.contact(RigidPlane((0, 0, 0), (0, 0, 1), motion=(0.0, 0.0, RISE)), penalty=penalty)
    model.gravity((0.0, 0.0, -G))
    return model


def test_a_static_increment_sees_the_tool_where_its_load_factor_puts_it():
    """Each frame's plate rests on the plane at that frame's height (lambda RISE), sunk by its
    weight over the penalty (m g / k per node, below 1e-3 mm here), not on the plane of the
    increment before."""
    result = Static(increments=4, progress=False).solve(plate_on_a_rising_plane())
    assert result.converged
    for frame in result.frames[1:]:
        lift = frame.positions[:, 2] - 0.5 * THICKNESS
        np.testing.assert_allclose(lift, frame.load_factor * RISE, atol=1e-3)


def test_the_dashpot_forces_are_the_gradient_of_their_pseudo_potential():
    """Central differences of D along a random motion of the translations and directors match
    the dashpot forces' work (1e-6), and the diagonal stiffness is c m / dlambda."""
    model = plate_on_a_rising_plane().compile()
    reference = model.initial_state()
    mass, inertia = model.lumped_mass(reference)
    dashpots = Dashpots(300.0, mass, inertia, model.has_rotation, reference, 0.25)
    rng = np.random.default_rng(3)
    dofs = model.dofs
    base = dofs.advance(reference, 0.05 * rng.standard_normal((model.n_nodes, 5)))
    direction = rng.standard_normal((model.n_nodes, 5))
    frames = dofs.frames(base.directors)
    force, moment = dashpots.forces(base)
    work = float(np.sum(dofs.generalised(frames, force, moment) * direction))
    eps = 1e-6
    plus = dashpots.energy(dofs.advance(base, eps * direction, frames))
    minus = dashpots.energy(dofs.advance(base, -eps * direction, frames))
    assert -(plus - minus) / (2 * eps) == pytest.approx(work, rel=1e-6)
    diagonal = dashpots.diagonal(dofs.free_slots)
    translation = dofs.free_slots % 5 < 3
    nodes = dofs.free_slots[translation] // 5
    np.testing.assert_allclose(diagonal[translation], 300.0 * mass[nodes] / 0.25)


def test_a_light_stabilisation_leaves_the_answer_and_reports_what_it_dissipated():
    """c = 1e-3 1/s^2 on the plate: the same heights as without it (1e-6 mm), and
    info["stabilisation"] holds the dissipated energy, below 5 % of the strain energy (the
    plate rides up with the plane: its dashpots work against that rigid motion, c = 1 1/s^2
    dissipates 1.5 times the plate's small strain energy)."""
    plain = Static(increments=4, progress=False).solve(plate_on_a_rising_plane())
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        damped = Static(increments=4, stabilise=1e-3, progress=False).solve(
            plate_on_a_rising_plane()
        )
    np.testing.assert_allclose(damped.positions, plain.positions, atol=1e-6)
    report = damped.info["stabilisation"]
    assert report["coefficient_per_s2"] == 1e-3
    assert 0.0 < report["dissipated_N_mm"] < STABILISATION_BOUND * report["strain_energy_N_mm"]


def test_a_stabilisation_that_shapes_the_result_is_warned_about():
    """c = 10 1/s^2: the dashpots' work against the plate riding up with the plane is many
    times the plate's strain energy: a UserWarning says so."""
    with pytest.warns(UserWarning, match="viscous stabilisation dissipated") as caught:
        Static(increments=2, stabilise=10.0, progress=False).solve(plate_on_a_rising_plane())
    assert caught[0].filename == __file__  # it points at the caller's solve


@pytest.mark.parametrize("value", [-1.0, float("nan"), "10", True])
def test_stabilise_must_be_a_number_at_least_zero(value):
    with pytest.raises(ValueError, match="stabilise"):
        Static(stabilise=value)


def test_stabilise_needs_the_load_path():
    with pytest.raises(ValueError, match="path='load'"):
        Static(stabilise=10.0, path="arc_length")
