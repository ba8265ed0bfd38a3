"""Arrays a block, a mesh, a topology or a tool keeps read-only stay read-only once the object
is unpickled, deep-copied or restored from a checkpoint (femcore/read_only_state.py): numpy
pickles an array without its ``writeable`` flag below pickle protocol 5 (the default protocol
4, which process pools use) and deep-copies it writeable, so without the list of read-only
arrays the copies took an edit in place (the fibrous bending patch's nodes, slots and fold,
which every later tangent reads). A checkpoint (protocol 5, solvers/output.py) kept the flag
already: checked that it still does."""

from __future__ import annotations

import copy
import pickle
from dataclasses import replace

import numpy as np
import pytest

from elements import FibrousShell, RigidPlane
from elements.fibrous.bending import _whole_patch
from femcore import Mesh, Model
from femcore.read_only_state import KEY, read_only_arrays
from materials import Fabric
from solvers.output import load_checkpoint, save_checkpoint
from validation.studies.ply_overhang_setup import two_plies


def _fibrous_block():
    """A 3 x 3 fibrous sheet's block with its bending patch made (read-only)."""
    model = Model(Mesh.rectangle(30.0, 30.0, nx=3, ny=3))
    model.add(
        FibrousShell(
            Fabric(thickness=1.0, areal_density=1e-9, tension=500.0, shear=0.5, bending=2.0)
        )
    )
    model.fix("left", ["ux", "uy", "uz"])
    block = model.compile().blocks[0]
    _whole_patch(block)
    return block


def _restored(value, how: str, tmp_path):
    if how == "pickle":  # the default protocol (4), as a process pool's
        return pickle.loads(pickle.dumps(value))
    if how == "deepcopy":
        return copy.deepcopy(value)
    path = tmp_path / "state.checkpoint"
    save_checkpoint(path, {"signature": "test", "value": value})
    return load_checkpoint(path)["value"]


def _refuses_a_write(array: np.ndarray) -> None:
    with pytest.raises(ValueError, match="read-only"):
        array.flat[0] = array.flat[0]


HOW = ["pickle", "deepcopy", "checkpoint"]


@pytest.mark.parametrize("how", HOW)
def test_a_restored_fibrous_blocks_bending_patch_is_read_only_and_kept(how, tmp_path):
    block = _fibrous_block()
    built = _whole_patch(block)
    restored = _restored(block, how, tmp_path)
    patch = _whole_patch(restored)
    # the tables kept beside the patch are the restored block's own: the patch is kept
    assert patch is restored.bending_patch[1]
    for array, original in zip(patch, built):
        np.testing.assert_array_equal(array, original)
        _refuses_a_write(array)
    assert restored.connectivity.flags.writeable == block.connectivity.flags.writeable


@pytest.mark.parametrize("how", HOW)
def test_a_restored_ply_blocks_kept_faces_and_facing_are_read_only(how, tmp_path):
    model, first, _ = two_plies(-4.0)
    compiled = model.compile()
    state = compiled.initial_state()
    positions = state.positions.copy()
    positions[first:, 2] -= 0.05
    block = compiled.interactions[0]
    block.internal_force(replace(state, positions=positions))
    kept = read_only_arrays(list(vars(block).values()))
    assert len(kept) >= 4  # the directions, the faces p and y, the facing's arrays
    restored = _restored(block, how, tmp_path)
    again = read_only_arrays(list(vars(restored).values()))
    assert len(again) == len(kept)
    for array in (restored._faces_at[2], restored._faces_at[3], *again):
        _refuses_a_write(array)


@pytest.mark.parametrize("how", HOW)
def test_a_restored_mesh_topology_and_tool_keep_their_arrays_read_only(how, tmp_path):
    mesh = Mesh.rectangle(20.0, 10.0, nx=2, ny=1)
    tool = RigidPlane(point=(0.0, 0.0, -1.0), normal=(0.0, 0.0, 1.0), motion=(0.0, 0.0, 2.0))
    restored_mesh, topology, restored_tool = _restored((mesh, mesh.topology, tool), how, tmp_path)
    _refuses_a_write(restored_mesh.points)
    _refuses_a_write(restored_mesh.cells("triangle"))
    _refuses_a_write(topology.edges)
    _refuses_a_write(restored_tool.motion)


def test_a_state_pickled_without_the_list_loads_with_writeable_arrays():
    """An object pickled before the list existed (no KEY in its state) loads as it did."""
    block = _fibrous_block()
    state = block.__getstate__()
    assert KEY in state
    del state[KEY]
    old = type(block).__new__(type(block))
    old.__setstate__(pickle.loads(pickle.dumps(state)))
    assert KEY not in vars(old)
    assert all(array.flags.writeable for array in old.bending_patch[1])
