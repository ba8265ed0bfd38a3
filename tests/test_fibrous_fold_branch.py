"""The fibrous shell's fold angle past a flat fold (elements/fibrous/bending.py, kernels.py;
docs/theory.md §4): two cells folded about their common side through 180 deg.

A fold angle is taken on atan2's principal branch, (-pi, pi]: two cells folded onto each
other and a little further read a fold of -(2 pi - theta), so the bending energy falls past
the flat fold and its moment turns to close the fold further. In the 24-cell two-ply
hemisphere's flange fold (docs/hemisphere_plies.md, "The fold's sides") 21 steps of sides
crossing the branch added 35.4 N mm to the shells' energy with no work, and the run stopped
on its energy balance. The test below holds the energy to its closed form on the unwrapped
angle, the cells walked through the flat fold in 1-deg steps, each accepted (the block's
history, elements/fibrous/fold_branch.py); on the principal branch E(190) = E(170) (fails
before).
"""

import dataclasses
import gc
import pickle
import weakref

import numpy as np
import pytest

from elements import FibrousShell
from elements.fibrous.fold_branch import branch_view, initial_branch
from femcore import Mesh, Model
from materials import BendingLaw, presets


def _folded_energies(kernel: str, degrees: list[float]) -> list[float]:
    """The bending energy (N mm) of a 40 x 20 mm rectangle's two cells with the second
    turned about their common side (the diagonal) by each angle of ``degrees`` (whole
    degrees, ascending), under a linear bending law (B = 0.5 N mm, both families)."""
    fabric = dataclasses.replace(
        presets.g986_stack(), bending=BendingLaw.linear(0.5), bending_weft=BendingLaw.linear(0.5)
    )
    model = Model(Mesh.rectangle(40.0, 20.0, nx=1, ny=1))
    model.add(FibrousShell(fabric, kernel=kernel))
    compiled = model.compile()
    block, start = compiled.blocks[0], compiled.initial_state()
    x = start.positions
    a, b = x[1], x[2]  # the common side (cells (0, 1, 2) and (3, 2, 1))
    axis = (b - a) / np.linalg.norm(b - a)
    lever = x[3] - a
    energies, state = [], start
    # walked in 1-deg steps from the flat sheet, each state accepted (the folds' history)
    for phi in np.radians(np.arange(1.0, max(degrees) + 0.5, 1.0)):
        turned = x.copy()
        turned[3] = (
            a
            + lever * np.cos(phi)
            + np.cross(axis, lever) * np.sin(phi)
            + axis * (axis @ lever) * (1.0 - np.cos(phi))
        )
        state = compiled.commit(dataclasses.replace(state, positions=turned))
        if np.isclose(np.degrees(phi), degrees).any():
            energies.append(block.strain_energy_parts(state, state.history[0])["bending"])
    return energies


@pytest.mark.parametrize("kernel", ["numpy", "compiled"])
def test_the_fold_below_flat_follows_the_square_of_its_angle(kernel):
    # The cells' shapes do not change as one turns (c_as of §4.2 fixed), the reference fold
    # is 0 and the law linear: E = K theta^2. Below pi the principal branch is the angle.
    e90, e170 = _folded_energies(kernel, [90.0, 170.0])
    assert e170 / e90 == pytest.approx((170.0 / 90.0) ** 2, rel=1e-9)


@pytest.mark.parametrize("kernel", ["numpy", "compiled"])
def test_folding_past_flat_takes_more_work(kernel):
    # Turned on to 190 deg the cell's mirror image of 170 deg has the same c_as: the
    # unwrapped fold gives E(190) / E(170) = (190 / 170)^2 = 1.249; the principal branch
    # reads -170 deg there and gives 1 (the energy falling past the flat fold).
    e170, e190 = _folded_energies(kernel, [170.0, 190.0])
    assert e190 / e170 == pytest.approx((190.0 / 170.0) ** 2, rel=1e-9)


def test_the_watched_sides_folds_are_the_full_passes():
    # fold_branch.py takes the watched sides' folds by numpy between the passes over every
    # side (kernels.py): the same angles (the same formula, another order: 1e-12 rad).
    from elements.fibrous.fold_branch import side_folds, watched_folds

    model = Model(Mesh.rectangle(40.0, 20.0, nx=6, ny=3))
    model.add(FibrousShell(presets.g986_stack()))
    compiled = model.compile()
    block, start = compiled.blocks[0], compiled.initial_state()
    rng = np.random.default_rng(2)
    positions = start.positions + rng.normal(scale=2.0, size=start.positions.shape)
    sides = np.argwhere(block.interior_side)
    full = side_folds(block, positions)[sides[:, 0], sides[:, 1]]
    assert np.abs(full).max() > 0.5  # folds of a size
    assert np.abs(watched_folds(block, positions, sides) - full).max() <= 1e-12


def test_the_largest_move_is_numpys():
    # fold_branch.largest_move, the compiled measure of the motion since the last pass over
    # every side, against the numpy expression it replaced (a subset of the nodes, none, nan)
    from elements.fibrous.fold_branch import largest_move

    rng = np.random.default_rng(3)
    positions = rng.standard_normal((50, 3))
    nodes = np.flatnonzero(rng.random(50) < 0.6)
    last = positions[nodes] + 1e-3 * rng.standard_normal((len(nodes), 3))
    last[7, 1] += 0.5  # the largest, on one axis of one node
    assert largest_move(positions, last, nodes) == np.abs(positions[nodes] - last).max()
    assert largest_move(positions, last, nodes) == pytest.approx(0.5, abs=1e-2)
    assert largest_move(positions, last[:0], nodes[:0]) == 0.0
    last[3, 2] = np.nan
    assert np.isnan(largest_move(positions, last, nodes))


def _sheet_block():
    """A 2 x 2-cell fibrous rectangle's block (numpy kernel: the view is kernel-blind)."""
    model = Model(Mesh.rectangle(40.0, 20.0, nx=2, ny=2))
    model.add(FibrousShell(presets.g986_stack(), kernel="numpy"))
    return model.compile().blocks[0]


def test_a_branchs_turns_refuse_an_edit_in_place_new_or_from_a_checkpoint():
    """``branch_view`` keeps its answer while the turns are the same array: an edit in place
    would leave a turned side read unturned, so the turns refuse it (a branch is never
    mutated; a new one takes new turns)."""
    block = _sheet_block()
    branch = initial_branch(block)
    assert branch_view(block, branch) is block
    side = np.argwhere(block.interior_side)[0]
    for kept in (branch, pickle.loads(pickle.dumps(branch))):
        with pytest.raises(ValueError, match="read-only"):
            kept.turns[tuple(side)] = 1.0
    turns = branch.turns.copy()
    turns[tuple(side)] = 1.0
    view = branch_view(block, dataclasses.replace(branch, turns=turns))
    assert view is not block
    assert view.reference_fold[tuple(side)] == block.reference_fold[tuple(side)] - 2.0 * np.pi


def test_a_blocks_view_of_an_unturned_branch_does_not_keep_the_block_alive():
    """The kept answer "no side turned" holds no reference to the block itself: a deleted
    block is freed at once, not at the cyclic collector's next pass (a process that builds
    models in turns would hold the dead ones' arrays)."""
    block = _sheet_block()
    branch_view(block, initial_branch(block))
    gone = weakref.ref(block)
    enabled = gc.isenabled()
    gc.disable()
    try:
        del block
        assert gone() is None
    finally:
        if enabled:
            gc.enable()
