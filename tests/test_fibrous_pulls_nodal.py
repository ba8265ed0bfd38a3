"""The fibrous force's one-thread pulls pass (elements/fibrous/pull_kernels.py ``pulls_nodal``:
each cell's corner forces, its pulls added, and its director moments added to its nodes as
the cell is done) against the pulls pass into the cells' forces and the nodes' pass that sums
them (elements/fibrous/kernels.py ``_pulls_pass``, ``_node_loads``: what runs on several
threads)."""

import numpy as np
import pytest

from elements import FibrousShell, kernels
from elements.fibrous import kernels as fibrous_kernels
from femcore import Mesh, Model
from femcore.rotation import rotate_about
from materials import presets

pytestmark = pytest.mark.skipif(not kernels.AVAILABLE, reason="needs numba")


def jittered_sheet(thickness):
    """A 6 x 5 G986 sheet clamped on its left edge, its nodes jittered and its directors
    tilted: every side folds, the clamped sides against their wall, and with nodal normals
    every node pulls."""
    mesh = Mesh.rectangle(60.0, 50.0, nx=6, ny=5)
    model = Model(mesh)
    model.add(FibrousShell(presets.g986_stack(), thickness=thickness, clamped="left"))
    model.fix("left")
    built = model.compile()
    state = built.initial_state()
    rng = np.random.default_rng(11)
    state.positions = state.positions + rng.normal(scale=0.8, size=state.positions.shape)
    turn = rng.normal(scale=0.3, size=state.positions.shape)
    state.directors = rotate_about(state.directors, np.cross(state.directors, turn))
    return built.blocks[0], state


@pytest.mark.parametrize("thickness", ["nodal", "element"])
def test_the_one_pass_gives_the_two_passes_loads_to_the_last_bit(thickness, monkeypatch):
    """Each node gets its corners' forces (each the cell's force plus its pull) and moments
    in cell order from 0.0 either way: equal bits, not a tolerance; and the energy with
    them is the same."""
    block, state = jittered_sheet(thickness)
    one_pass = block.internal_force_and_energy(state)
    monkeypatch.setattr(fibrous_kernels, "threads_for", lambda items: 2)  # the two passes
    two_passes = block.internal_force_and_energy(state)
    for ours, theirs in zip(one_pass[:2], two_passes[:2]):
        assert np.abs(theirs).max() > 0.0
        np.testing.assert_array_equal(ours, theirs)
    assert one_pass[2] == two_passes[2]
