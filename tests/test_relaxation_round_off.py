"""DynamicRelaxation's force reference never falls below the rounding of the internal forces
(solvers.force_floor, docs/theory.md §6.4): a rigid rotation prescribed on every node, whose
answer carries no force, converges; loads below that floor are judged as round-off, with a
warning. Before the floor the rotation did not converge (residual ratio 0.08 after 20 000
iterations): round-off judged against round-off."""

import warnings

import numpy as np
import pytest

from elements import MindlinShell
from femcore import Mesh, Model
from materials import ElasticShell
from solvers import DynamicRelaxation

EPS = float(np.finfo(float).eps)


def test_a_prescribed_rigid_rotation_relaxes_to_no_force_with_the_directors_turned():
    angle, axis = np.radians(60.0), np.array([1.0, 2.0, 3.0]) / np.sqrt(14.0)
    k = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    turn = np.eye(3) + np.sin(angle) * k + (1.0 - np.cos(angle)) * (k @ k)
    modulus, thickness = 1e3, 1.0
    mesh = Mesh.rectangle(40.0, 20.0, nx=4, ny=2)
    moved = mesh.points @ turn.T - mesh.points
    model = Model(mesh)
    model.add(MindlinShell(ElasticShell(E=modulus, nu=0.3, thickness=thickness, density=1e-9)))
    model.displace(np.arange(len(moved)), ux=moved[:, 0], uy=moved[:, 1], uz=moved[:, 2])
    result = DynamicRelaxation(increments=4, max_iterations=20_000).solve(model)
    extent = float(np.abs(mesh.points).max())
    # Closed form: the normals R e_z (the relaxation stops within tol 1e-4 of the floor's force,
    # a turn of about 1e-14 rad here; 1e-12 allowed) and no reaction beyond 1e3 times the
    # rounding E t eps X (4e-12 N measured).
    np.testing.assert_allclose(result.directors, np.tile(turn[:, 2], (len(moved), 1)), atol=1e-12)
    assert np.abs(result.reactions).max() <= 1e3 * EPS * modulus * thickness * extent


def test_loads_below_the_rounding_of_the_forces_are_relaxed_with_a_warning():
    mesh = Mesh.rectangle(100.0, 10.0, nx=20, ny=2)
    model = Model(mesh)
    model.add(MindlinShell(ElasticShell(E=1e4, nu=0.0, thickness=1.0, density=1e-9)))
    model.fix("left")
    model.force(mesh.nodes("right"), (0.0, 0.0, -1e-11))
    with pytest.warns(UserWarning, match="below the rounding of the internal forces"):
        DynamicRelaxation(increments=1).solve(model)


def test_a_load_taken_off_by_its_amplitude_is_relaxed_without_the_rounding_warning():
    # sin(pi lambda) leaves 1e-16 of the load at lambda = 1, below the rounding of the forces:
    # the unloaded strip is what is asked, not loads too small to resolve.
    mesh = Mesh.rectangle(100.0, 10.0, nx=20, ny=2)
    model = Model(mesh)
    model.add(MindlinShell(ElasticShell(E=1e4, nu=0.0, thickness=1.0, density=1e-9)))
    model.fix("left")
    tip = mesh.nodes("right")
    model.force(tip, (0.0, 0.0, -1.0 / len(tip)), amplitude=lambda lam: np.sin(np.pi * lam))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        result = DynamicRelaxation(increments=4, progress=False).solve(model)
    assert abs(result.frames[-1].positions[tip, 2].mean()) < 1e-3
