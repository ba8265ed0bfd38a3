"""The Mindlin shell's one-thread force pass (elements/mindlin_cell_loads.py ``mindlin_nodal``:
each cell's loads added to its nodes as the cell is done) against the cells' pass with its
buffer and the nodes' pass that sums it (elements/kernels.py ``_mindlin_cells``,
``_node_sums6``: what runs on several threads), and against the numpy reference."""

import numpy as np
import pytest

from elements import MindlinShell, kernels
from femcore import Mesh, Model, jit
from femcore.rotation import rotate_about
from materials import ElasticShell

pytestmark = pytest.mark.skipif(not kernels.AVAILABLE, reason="needs numba")


def jittered_patch(kernel, points=2, seed=7):
    """An orthotropic 6 x 5 patch (60 triangles, interior nodes of six cells) and a jittered,
    tilted state of it: every strain measure and every load non-zero."""
    mesh = Mesh.rectangle(60.0, 50.0, nx=6, ny=5)
    material = ElasticShell.orthotropic(
        70e3, 20e3, 0.3, 5e3, 4e3, 3e3, 1.0, 2.7e-9, warp=(1.0, 1.0, 0.0)
    )
    model = Model(mesh)
    model.add(MindlinShell(material, thickness_points=points, kernel=kernel))
    compiled = model.compile()
    state = compiled.initial_state()
    rng = np.random.default_rng(seed)
    state.positions = state.positions + rng.normal(scale=0.5, size=state.positions.shape)
    turn = np.cross(state.directors, rng.normal(scale=0.3, size=state.positions.shape))
    state.directors = rotate_about(state.directors, turn)
    return compiled, state


def buffered(block, state):
    """The loads by the cells' pass into its (m, 3, 6) buffer and the nodes' pass over it."""
    m = len(block.connectivity)
    loads, energy = np.empty((m, 3, 6)), np.empty(m)
    kernels._mindlin_cells(
        state.positions, state.directors, block.connectivity, block.zeta, 0.5 * block.h,
        block.reference_measures, block.level_stiffness, block.tying_n, True, loads, energy,
    )  # fmt: skip
    force, moment = kernels._nodal(block, loads)
    return force, moment, energy


def one_pass(block, state):
    """The loads by the one pass that adds each cell's to its nodes."""
    force, moment = np.zeros((block.n_nodes, 3)), np.zeros((block.n_nodes, 3))
    energy = np.empty(len(block.connectivity))
    kernels.mindlin_nodal(
        state.positions, state.directors, block.connectivity, block.zeta, 0.5 * block.h,
        block.reference_measures, block.level_stiffness, block.tying_n, True, True, force, moment,
        energy,
    )  # fmt: skip
    return force, moment, energy


@pytest.mark.parametrize("points", [2, 3, 5])
def test_the_one_pass_gives_the_buffered_passes_loads_to_the_last_bit(points):
    """Each node gets its corners' loads in cell order from 0.0 either way, the same
    operations in the same order: equal bits, not a tolerance."""
    compiled, state = jittered_patch("compiled", points)
    block = compiled.blocks[0]
    for ours, theirs in zip(one_pass(block, state), buffered(block, state)):
        assert np.abs(theirs).max() > 0.0
        np.testing.assert_array_equal(ours, theirs)


def test_the_one_pass_gives_the_numpy_forces_and_energy():
    """The one-thread path of ``internal_force_and_energy`` against the vectorised numpy
    reference: the same sums in another order, so agreement to 1e-12 of the largest value
    (the tolerance of the compiled kernel's own test in tests/test_mindlin.py)."""
    compiled, state = jittered_patch("compiled")
    reference, _ = jittered_patch("numpy")
    assert jit.threads_for(len(compiled.blocks[0].connectivity)) == 1  # the one pass runs
    force, moment, energy = compiled.internal_force_and_energy(state)
    ref_force, ref_moment, ref_energy = reference.internal_force_and_energy(state)
    for value, expected in ((force, ref_force), (moment, ref_moment)):
        assert np.abs(value - expected).max() <= 1e-12 * np.abs(expected).max()
    assert energy == pytest.approx(ref_energy, rel=1e-12)


@pytest.mark.parallel
def test_the_force_and_moment_are_contiguous_on_any_thread_count():
    """Both paths give (n, 3) C-contiguous arrays, which the step's node passes
    (solvers/dynamics.py, turning.py) take without a copy (the buffered path gave the two
    halves of one (n, 6) array, which each of them copied at every step)."""
    compiled, state = jittered_patch("compiled")
    block = compiled.blocks[0]
    arrays = [*compiled.internal_force(state), *buffered(block, state)[:2]]
    for array in arrays:
        assert array.shape == (block.n_nodes, 3)
        assert array.flags.c_contiguous


def test_the_force_without_its_energy_is_the_force_with_it():
    """A step that does not check the energy balance asks for the loads alone, and the one
    pass then leaves out the sums e . sigma: the loads are those of the pass with the energy,
    to the last bit."""
    compiled, state = jittered_patch("compiled")
    block = compiled.blocks[0]
    alone = kernels.mindlin_loads(block, state.positions, state.directors)
    with_energy = kernels.mindlin_loads_and_energy(block, state.positions, state.directors)
    assert with_energy[2] > 0.0
    for ours, theirs in zip(alone, with_energy[:2]):
        np.testing.assert_array_equal(ours, theirs)
