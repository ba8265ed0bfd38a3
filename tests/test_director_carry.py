"""Directors carried with a body that nothing holds (femcore/director_carry.py, docs/theory.md
§1.7): the rotation fitted to a body's motion, and which bodies get it."""

import numpy as np
from scipy.spatial.transform import Rotation

from elements import FibrousShell
from femcore import Mesh, Model
from femcore.director_carry import DirectorCarrier, fitted_rotation
from materials import presets


def test_the_fitted_rotation_is_the_rigid_motion_that_moved_the_points():
    # Closed form: points moved by x -> R x + c give back R (to rounding), flat ones too.
    rng = np.random.default_rng(3)
    turn = Rotation.from_rotvec([0.3, -1.1, 0.7]).as_matrix()
    for points in (
        rng.normal(size=(12, 3)),
        np.column_stack([rng.normal(size=(12, 2)), np.zeros(12)]),
    ):
        moved = points @ turn.T + [5.0, -2.0, 1.0]
        assert np.abs(fitted_rotation(points, moved) - turn).max() < 1e-12


def test_points_on_a_line_fix_no_rotation():
    line = np.outer(np.arange(5.0), [1.0, 0.0, 0.0])
    assert np.array_equal(fitted_rotation(line, line[:, [1, 0, 2]]), np.eye(3))


def strip(thickness="nodal"):
    mesh = Mesh.rectangle(100.0, 10.0, nx=10, ny=2)
    model = Model(mesh)
    model.add(FibrousShell(presets.g1151_laminate(), thickness=thickness))
    return mesh, model


def test_a_free_fibrous_body_is_carried_and_a_clamped_one_is_not():
    mesh, model = strip()
    carrier = DirectorCarrier.of(model.compile())
    assert carrier is not None and len(carrier.bodies) == 1
    assert len(carrier.bodies[0]) == mesh.n_nodes and carrier.carried.all()
    mesh, model = strip()
    model.fix("left")  # the clamp holds the directors there: it decides the tilt
    assert DirectorCarrier.of(model.compile()) is None


def test_bai_element_thickness_is_not_carried():
    # Eq. 15's element keeps its directors' orientation as published (docs/theory.md §1.4).
    _, model = strip("element")
    assert DirectorCarrier.of(model.compile()) is None


def test_only_the_body_without_a_held_director_is_carried():
    # Two strips in one mesh, 20 mm apart: the first clamped at x = 0, the second free.
    one = Mesh.rectangle(100.0, 10.0, nx=10, ny=2)
    points = np.vstack([one.points, one.points + [0.0, 20.0, 0.0]])
    triangles = np.vstack([one.triangles, one.triangles + one.n_nodes])
    mesh = Mesh(points, triangles)
    model = Model(mesh)
    model.add(FibrousShell(presets.g1151_laminate()))
    model.fix(mesh.nodes(lambda x, y, z: (x <= 0.0) & (y <= 10.0)))
    carrier = DirectorCarrier.of(model.compile())
    assert carrier is not None and len(carrier.bodies) == 1
    assert np.array_equal(np.flatnonzero(carrier.carried), np.arange(one.n_nodes, mesh.n_nodes))
    # The carried directors turn with the fitted rotation, the others stay as given.
    turn = Rotation.from_rotvec([0.0, 0.4, 0.0]).as_matrix()
    after = points.copy()
    after[carrier.carried] = points[carrier.carried] @ turn.T
    directors = np.tile([0.0, 0.0, 1.0], (mesh.n_nodes, 1))
    out = carrier.carry(directors, points, after)
    assert np.abs(out[carrier.carried] - turn[:, 2]).max() < 1e-12
    assert np.array_equal(out[~carrier.carried], directors[~carrier.carried])
