"""The compiled derivatives of the fibrous shell's level measures (elements/fibrous/
level_kernels.py) against their numpy reference (level_jacobian.py ``level_strain_gradient``,
itself checked against central differences in tests/test_level_projection.py):

* on a jittered, bent and twisted sheet with nodal normals (wall nodes at the clamp, their
  sums held) and with element normals, one corner's director tilted past the thickness guard,
  every piece equal to 1e-12 of its largest entry (the two forms differ by the order of a few
  sums: rounding of 1e-16 relative, amplified by no cancellation worse than 1e4). Not for a
  corner whose V . n lies within an ulp of the guard: the two forms' last bits may then take
  opposite sides of it with element normals (one zeroes ds/dc, the other not);
* the same bits on one thread as on all of numba's threads (each cell's numbers from its own
  corners only).
"""

from __future__ import annotations

import numpy as np
import pytest

from elements import FibrousShell
from elements.fibrous import level_jacobian, level_kernels
from femcore import Mesh, Model
from femcore.rotation import rotate_about
from materials.presets import g986_stack

pytestmark = pytest.mark.skipif(not level_kernels.AVAILABLE, reason="numba is not installed")


def _sheet(thickness: str, nx: int = 6, ny: int = 4):
    """A 60 x 40 mm sheet of the G986 stack clamped at x = 0, and a state away from its
    reference: nodes moved by up to 1 mm in each direction and bent out of plane, directors
    turned by up to 0.3 rad and one turned by 1.45 rad (V . N below the guard 0.2)."""
    mesh = Mesh.rectangle(60.0, 40.0, nx=nx, ny=ny)
    model = Model(mesh)
    model.add(FibrousShell(g986_stack(), clamped="left", thickness=thickness))
    model.fix("left")
    compiled = model.compile()
    state = compiled.initial_state()
    rng = np.random.default_rng(11)
    points = mesh.points
    positions = points + rng.uniform(-1.0, 1.0, points.shape)
    positions[:, 2] += 0.004 * points[:, 0] ** 2 + 0.002 * points[:, 0] * points[:, 1]
    turn = rng.uniform(-0.3, 0.3, points.shape)
    turn[mesh.n_nodes // 2] = (1.45, 0.0, 0.0)
    directors = rotate_about(state.directors, turn)
    block = compiled.blocks[0]
    return block, positions, directors


@pytest.mark.parametrize("thickness", ["nodal", "element"])
def test_the_compiled_gradient_is_the_numpy_one(thickness):
    block, positions, directors = _sheet(thickness)
    assert block.compiled
    reference = level_jacobian.level_strain_gradient(block, positions, directors, compiled=False)
    loop = level_jacobian.level_strain_gradient(block, positions, directors, compiled=True)
    geo = level_jacobian.cell_geometry(
        block,
        positions[block.connectivity],
        directors[block.connectivity],
        False,
        level_jacobian.normal_sums(block, positions)[block.connectivity]
        if block.nodal_normals
        else None,
    )
    assert geo["guarded"].any() and not geo["guarded"].all()  # both branches of h_m
    assert (reference[2] is None) == (thickness == "element")
    for ours, theirs in zip(loop, reference):
        if theirs is None:
            assert ours is None
            continue
        assert ours.shape == theirs.shape
        scale = np.abs(theirs).max()
        assert scale > 0.0
        assert np.abs(ours - theirs).max() <= 1e-12 * scale


@pytest.mark.parallel
def test_the_compiled_gradient_has_the_same_bits_on_any_thread_count():
    import numba

    # (the parallel mark runs every loop on the threads, tests/conftest.py)
    block, positions, directors = _sheet("nodal")
    runs = []
    for threads in (1, numba.config.NUMBA_NUM_THREADS):
        numba.set_num_threads(threads)
        runs.append(level_jacobian.level_strain_gradient(block, positions, directors, True))
    if numba.config.NUMBA_NUM_THREADS > 1:
        assert level_kernels._gradient_cells._parallel is not None  # the parts on threads
    for one, every in zip(*runs):
        np.testing.assert_array_equal(every, one)
