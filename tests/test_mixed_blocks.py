"""A strip whose clamped half is a fibrous block and whose free half is a Mindlin block (the
two kinematics in one model, sharing the nodes of their seam) is solved by Static and writes
both blocks' cell fields: a field of one name and two shapes (the fibrous block's three
fibre levels, the Mindlin block's one value) is kept as two fields, each NaN on the other
block's cells."""

import numpy as np

from elements import FibrousShell, MindlinShell
from femcore import Mesh, Model
from materials.presets import g986_stack
from solvers import Static

GRAVITY = 9810.0  # mm/s^2


def mixed_strip():
    fabric = g986_stack()
    mesh = Mesh.rectangle(100.0, 10.0, nx=10, ny=1)
    centres = mesh.points[mesh.triangles].mean(axis=1)[:, 0]
    near, far = np.flatnonzero(centres < 50.0), np.flatnonzero(centres >= 50.0)
    model = Model(mesh)
    model.add(FibrousShell(fabric, clamped="left"), cells=near)
    model.add(MindlinShell(fabric), cells=far)
    model.fix("left")
    model.gravity((0.0, 0.0, -GRAVITY))
    return model, near, far


def test_a_field_of_two_shapes_is_two_fields_each_on_its_own_block():
    model, near, far = mixed_strip()
    compiled = model.compile()
    cells = compiled.fields(compiled.initial_state())["triangle"]
    levels, one = cells["warp_strain"], cells["warp_strain_2"]
    assert levels.shape == (20, 3) and one.shape == (20,)
    assert np.isfinite(levels[near]).all() and np.isnan(levels[far]).all()
    assert np.isfinite(one[far]).all() and np.isnan(one[near]).all()
    # A field of one shape in both blocks stays one field, set on every cell.
    assert np.isfinite(cells["membrane_force"]).all() and "membrane_force_2" not in cells


def test_static_solves_a_strip_of_fibrous_and_mindlin_blocks_and_records_its_frames():
    model, near, far = mixed_strip()
    result = Static(increments=2, progress=False).solve(model)
    assert result.converged
    drop = -result.positions[:, 2].min()
    assert 0.0 < drop < 100.0  # mm: it sags, within its length
    assert len(result.frames) == 3
