"""The flat ply contact's tangent by its compiled passes (elements/ply_carry.py
``carried_blocks``, the point Hessians carried to the nodes; elements/ply_point_tangent.py
``point_blocks``, the touching points' whole part) gives numpy's blocks to the last bit."""

from dataclasses import replace

import numpy as np
import pytest

from elements import ply_carry, ply_point_tangent, ply_projection
from femcore.rotation import cross_matrix
from validation.studies.ply_overhang_setup import two_plies


def _inputs(count: int, nodes: int, seed: int = 0):
    """Symmetric point Hessians (count, Z, 3, Z, 3), the nodes' own maps (count, N, 3, 6) as
    the contact builds them (the identity on du, -c [d]x on dpsi) and shape functions."""
    rng = np.random.default_rng(seed)
    zs = nodes - 2
    points = rng.standard_normal((count, zs, 3, zs, 3))
    points = points + points.transpose(0, 3, 4, 1, 2)
    own = np.zeros((count, nodes, 3, 6))
    own[:, :, :, :3] = np.eye(3)
    offset = rng.standard_normal((count, nodes))
    own[:, :, :, 3:] = -offset[:, :, None, None] * cross_matrix(
        rng.standard_normal((count, nodes, 3))
    )
    return points, own, rng.random((count, 3))


@pytest.mark.parametrize("count", [0, 1, 3, 50])
@pytest.mark.parametrize("nodes", [6, 8])
def test_the_compiled_carry_gives_the_einsums_bits(count, nodes):
    points, own, shape = _inputs(count, nodes, seed=count + nodes)
    reference = ply_carry.carry_reference(points, own, shape)
    compiled = ply_carry.carried_blocks(points, own, shape)
    assert compiled.shape == reference.shape == (count, nodes, 6, nodes, 6)
    assert np.array_equal(compiled, reference)
    assert np.array_equal(np.signbit(compiled), np.signbit(reference))


def test_the_einsums_sum_in_index_order():
    """The reference's claim (module docstring): each entry is its products summed in their
    index order from 0.0, which the compiled pass keeps while leaving out the zero terms."""
    points, own, shape = _inputs(4, 6, seed=7)
    maps = ply_carry.point_maps(own, shape)
    zs, nodes = 4, 6
    carried = np.zeros((4, zs, 3, nodes, 6))
    for index in np.ndindex(carried.shape):
        t, z, i, c, b = index
        total = 0.0
        for s in range(zs):
            for j in range(3):
                total += points[t, z, i, s, j] * maps[t, s, j, c, b]
        carried[index] = total
    blocks = np.zeros((4, nodes, 6, nodes, 6))
    for index in np.ndindex(blocks.shape):
        t, r, a, c, b = index
        total = 0.0
        for z in range(zs):
            for i in range(3):
                total += maps[t, z, i, r, a] * carried[t, z, i, c, b]
        blocks[index] = total
    assert np.array_equal(ply_carry.carry_reference(points, own, shape), blocks)


def test_mismatched_shapes_are_refused():
    points, own, shape = _inputs(3, 6)
    with pytest.raises(ValueError, match="do not match"):
        ply_carry.carried_blocks(points[:, :3, :, :3], own, shape)
    with pytest.raises(ValueError, match="do not match"):
        ply_carry.carried_blocks(points, own, shape[:2])


def _same_tangents(block, state, history, monkeypatch) -> list:
    """The contact's tangent parts with the compiled passes and with numpy's (asserted the
    same to the bit); the compiled ones."""
    kernel = block.tangent(state, history)
    with monkeypatch.context() as patch:
        patch.setattr(ply_point_tangent, "point_blocks", ply_point_tangent.point_blocks_reference)
        patch.setattr(ply_carry, "carried_blocks", ply_carry.carry_reference)
        reference = block.tangent(state, history)
    with monkeypatch.context() as patch:  # numpy's whole path: the forces by _pair_loads
        patch.setattr(ply_projection, "COMPILED", False)
        numpy_path = block.tangent(state, history)
    assert len(kernel) == len(reference) == len(numpy_path)
    for ours, theirs, numpy_part in zip(kernel, reference, numpy_path):
        assert np.array_equal(ours.nodes, theirs.nodes)
        assert np.array_equal(ours.blocks, theirs.blocks)
        assert np.array_equal(ours.nodes, numpy_part.nodes)
        assert np.array_equal(ours.blocks, numpy_part.blocks)
    return kernel


def test_a_ply_contacts_tangent_to_the_bit(monkeypatch):
    """An overhanging upper ply pressed into the lower one and jittered: points fading past
    the lower ply's outline (both carries)."""
    model, first, _ = two_plies(-4.0)
    compiled = model.compile()
    start = compiled.initial_state()
    rng = np.random.default_rng(3)
    positions = start.positions.copy()
    positions[first:, 2] -= 0.05
    positions[first:] += rng.normal(scale=0.02, size=positions[first:].shape)
    state = replace(start, positions=positions)
    block = compiled.interactions[0]
    parts = _same_tangents(block, state, start.history[len(compiled.blocks)], monkeypatch)
    assert len(parts) >= 2 and all(len(part.blocks) for part in parts)  # the points', the fade's


def test_the_tangent_round_an_outline_vertex_to_the_bit(monkeypatch):
    """Faces round an outline vertex of a folded fan (tests/test_ply_fade_hessian.py), where
    touching points face the vertex (the search's Hessian there)."""
    from test_ply_fade_hessian import _fan, _placed, _round_the_vertex

    from femcore.state import State

    block, x, directors, low = _fan("folded")
    zero = np.zeros_like(x)
    faced = 0
    for face in _round_the_vertex(block, low, 0.05):
        state = State(_placed(x, face), directors, zero, zero)
        _same_tangents(block, state, None, monkeypatch)
        facing = block.facing(state, second=True)
        faced += int(np.any(facing.hessian[facing.touching] != 0.0))
    assert faced >= 1


def test_the_point_blocks_ask_for_forces_or_the_fades_gradient():
    points, own, shape = _inputs(2, 6)
    rng = np.random.default_rng(5)
    args = (
        rng.standard_normal(2), rng.standard_normal((2, 3)), rng.random((2, 3)),
        rng.standard_normal((2, 3, 3)), None, np.ones(2), (np.ones(2), np.ones(2), np.ones(2)),
        rng.standard_normal((2, 6, 3)), rng.standard_normal((2, 6)), shape,
    )  # fmt: skip
    for blocks in (ply_point_tangent.point_blocks, ply_point_tangent.point_blocks_reference):
        with pytest.raises(ValueError, match="forces or the fade"):
            blocks(*args)
