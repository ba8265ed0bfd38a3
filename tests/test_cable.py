"""The cable element: conformance checks of DESIGN §5 (rigid motions, energy gradient, mass,
stable step)."""

import numpy as np
import pytest

from elements import Cable
from femcore import Mesh, Model
from femcore.state import State


def net_mesh(nx=4, ny=3, size=10.0) -> Mesh:
    """A square cable net: every grid edge of an nx x ny grid is a cable, plus the diagonals."""
    i, j = np.meshgrid(np.arange(nx + 1), np.arange(ny + 1), indexing="xy")
    points = np.column_stack([i.ravel() * size, j.ravel() * size, np.zeros(i.size)])
    ids = np.arange(points.shape[0]).reshape(ny + 1, nx + 1)
    lines = np.vstack(
        [
            np.column_stack([ids[:, :-1].ravel(), ids[:, 1:].ravel()]),
            np.column_stack([ids[:-1, :].ravel(), ids[1:, :].ravel()]),
            np.column_stack([ids[:-1, :-1].ravel(), ids[1:, 1:].ravel()]),
        ]
    )
    return Mesh(points, lines=lines)


def compiled(mesh, **options):
    model = Model(mesh)
    model.add(Cable(axial_stiffness=2.0e4, mass_per_length=3.0e-9, **options))
    return model.compile()


def state_at(model, positions):
    n = model.n_nodes
    return State(positions, np.zeros((n, 3)), np.zeros((n, 3)), np.zeros((n, 3)))


def rotation_matrix(axis, angle):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


def test_rigid_translation_and_rotation_give_no_strain_and_no_force():
    mesh = net_mesh()
    model = compiled(mesh)
    rotation = rotation_matrix((1.0, 2.0, 0.5), np.pi / 2)
    moved = mesh.points @ rotation.T + np.array([3.0, -7.0, 11.0])
    state = state_at(model, moved)
    force, moment = model.internal_force(state)
    assert moment is not None and not moment.any()
    assert np.abs(force).max() < 1e-10 * 2.0e4
    assert model.strain_energy(state) < 1e-20
    strain = model.fields(state)["line"]["axial_strain"]
    assert np.abs(strain).max() < 1e-14


@pytest.mark.parametrize("tension_only", [False, True])
def test_internal_force_is_the_gradient_of_the_strain_energy(tension_only):
    rng = np.random.default_rng(3)
    mesh = net_mesh()
    model = compiled(mesh, tension_only=tension_only)
    positions = mesh.points + rng.normal(scale=0.5, size=mesh.points.shape)
    force, _ = model.internal_force(state_at(model, positions))
    step = 1e-6
    numeric = np.zeros_like(positions)
    for node in range(mesh.n_nodes):
        for axis in range(3):
            plus, minus = positions.copy(), positions.copy()
            plus[node, axis] += step
            minus[node, axis] -= step
            numeric[node, axis] = (
                model.strain_energy(state_at(model, plus))
                - model.strain_energy(state_at(model, minus))
            ) / (2 * step)
    assert np.abs(force - numeric).max() < 1e-6 * np.abs(force).max()


def test_tension_only_cable_goes_slack_in_compression():
    mesh = Mesh(np.array([[0.0, 0, 0], [10, 0, 0]]), lines=np.array([[0, 1]]))
    model = compiled(mesh, tension_only=True)
    squeezed = state_at(model, np.array([[0.0, 0, 0], [9.0, 0, 0]]))
    assert not model.internal_force(squeezed)[0].any()
    assert model.strain_energy(squeezed) == 0.0


def test_lumped_mass_sums_to_the_total_mass():
    mesh = net_mesh()
    model = compiled(mesh)
    mass, inertia = model.lumped_mass(model.initial_state())
    lengths = np.linalg.norm(np.diff(mesh.points[mesh.lines], axis=1)[:, 0], axis=1)
    assert mass.sum() == pytest.approx(3.0e-9 * lengths.sum(), rel=1e-13)
    assert not inertia.any()


def test_stable_step_halves_when_the_element_size_halves():
    coarse = compiled(net_mesh(4, 3, size=10.0))
    fine = compiled(net_mesh(8, 6, size=5.0))
    dt_coarse = coarse.stable_dt(coarse.initial_state())
    dt_fine = fine.stable_dt(fine.initial_state())
    assert dt_coarse / dt_fine == pytest.approx(2.0, rel=1e-12)
    # and it is the two-mass bar value L/c on the shortest cable
    assert dt_fine == pytest.approx(5.0 / np.sqrt(2.0e4 / 3.0e-9), rel=1e-12)


@pytest.mark.parametrize(
    "arguments, message",
    [
        ((0.0, 1e-9), "axial_stiffness"),
        ((-5.0, 1e-9), "axial_stiffness"),
        ((1.0, 0.0), "mass_per_length"),
        ((1.0, -1e-9), "mass_per_length"),
        ((np.nan, 1e-9), "axial_stiffness"),
        (("stiff", 1e-9), "axial_stiffness"),
    ],
)
def test_bad_cable_parameters_are_named(arguments, message):
    with pytest.raises(ValueError, match=message):
        Cable(*arguments)
