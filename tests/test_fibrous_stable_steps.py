"""The fibrous cells' critical steps in one compiled pass (elements/fibrous/stable_steps.py)
against the numpy formulas they replace (``FibrousShellBlock.cell_stable_dt_numpy``): the same
steps to the last bit, on one thread and on all of numba's."""

import numpy as np
import pytest

from elements import FibrousShell
from femcore import Mesh, Model, jit
from materials import Fabric
from tests.thread_runs import on_one_thread_and_on_all

pytestmark = pytest.mark.skipif(not jit.AVAILABLE, reason="numba is not installed")


@pytest.mark.parametrize("thickness", ["element", "nodal"])
def test_the_compiled_cell_steps_are_the_numpy_formulas_to_the_last_bit(thickness):
    """A 60 x 60 x 2 sheet (7200 cells, past the one-thread loop size) jittered by half its
    side and bent (cells of many shapes, sides crossing at every angle): the steps of the
    compiled pass equal numpy's, cell by cell, on one thread and on all; with the nodal
    normals' 10 % margin (thickness "nodal") and without ("element")."""
    mesh = Mesh.rectangle(100.0, 100.0, nx=60, ny=60)
    model = Model(mesh)
    fabric = Fabric(thickness=1.0, areal_density=1e-9, tension=500.0, shear=0.5, bending=2.0)
    model.add(FibrousShell(fabric, thickness=thickness))
    compiled = model.compile()
    block = compiled.blocks[0]
    state = compiled.initial_state()
    rng = np.random.default_rng(7)
    x = state.positions + rng.normal(scale=0.8, size=state.positions.shape)
    x[:, 2] += 0.01 * (x[:, 0] - 50.0) ** 2  # bent
    state.positions = x
    one, every = on_one_thread_and_on_all(lambda: block.cell_stable_dt(state))
    reference = block.cell_stable_dt_numpy(state)
    assert block.compiled and len(reference) == 7200
    assert reference.max() > 3.0 * reference.min()  # cells of many shapes
    np.testing.assert_array_equal(one, reference)
    np.testing.assert_array_equal(every, reference)
