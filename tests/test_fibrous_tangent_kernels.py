"""elements/fibrous/tangent_kernels.py: the compiled loops of the fibrous shell's tangent give
the numbers of their numpy references in elements/fibrous/tangent.py and bending.py (the same
sums in another order: 1e-12 of the largest entry)."""

import dataclasses

import numpy as np
import pytest

from elements import FibrousShell
from elements.fibrous.tangent import corner_normal_pull_tangent
from elements.fibrous.tangent_kernels import normal_pull_stiffness
from femcore import Mesh, Model
from femcore.rotation import rotate_about
from materials import presets


def test_the_compiled_normal_pull_stiffness_gives_the_numpy_one():
    # Random cells: obtuse, slender and nearly flat corners alike.
    rng = np.random.default_rng(0)
    x = rng.normal(size=(500, 3, 3))
    pull = rng.normal(size=(500, 3, 3))
    reference = corner_normal_pull_tangent(x, pull)
    compiled = normal_pull_stiffness(x, pull)
    assert np.abs(compiled - reference).max() <= 1e-12 * np.abs(reference).max()


def test_the_block_tangent_is_the_same_with_the_compiled_loops():
    # The fibrous sheet with nodal normals, jittered and its directors tilted: every part of
    # the tangent (the sparse membrane part and the cell blocks) as the numpy kernel gives it.
    mesh = Mesh.rectangle(40.0, 20.0, nx=6, ny=3)
    parts = {}
    for kernel in ("numpy", "compiled"):
        model = Model(mesh)
        model.add(FibrousShell(presets.g986_stack(), kernel=kernel))
        compiled = model.compile()
        state = compiled.initial_state()
        rng = np.random.default_rng(4)
        positions = state.positions + rng.normal(scale=0.4, size=state.positions.shape)
        turn = np.cross(state.directors, rng.normal(scale=0.2, size=state.positions.shape))
        state = dataclasses.replace(
            state, positions=positions, directors=rotate_about(state.directors, turn)
        )
        parts[kernel] = compiled.tangent_parts(state, [0])
    for reference, fast in zip(parts["numpy"], parts["compiled"]):
        expected = reference.matrix.toarray() if hasattr(reference, "matrix") else reference.blocks
        got = fast.matrix.toarray() if hasattr(fast, "matrix") else fast.blocks
        assert np.abs(got - expected).max() <= 1e-12 * np.abs(expected).max()


def test_the_compiled_share_stiffness_gives_the_numpy_one():
    from elements.fibrous.bending import share_tangent
    from elements.fibrous.tangent_kernels import share_stiffness

    rng = np.random.default_rng(1)
    x = rng.normal(size=(500, 3, 3))
    side_moment = rng.normal(size=(500, 3))
    reference = share_tangent(x, side_moment)
    compiled = share_stiffness(x, side_moment)
    assert np.abs(compiled - reference).max() <= 1e-12 * np.abs(reference).max()


@pytest.mark.parametrize("stray", [0, 3])
def test_the_structured_membrane_product_is_the_sparse_product(stray):
    # J's node blocks are the identity on the diagonal plus dS/dx in rows 6-8, columns 0-2;
    # the compiled product uses that shape and must give scipy's J^T H J of the full blocks.
    # ``stray`` nodes in no cell (a mesh's unused points, numbered among the others) have
    # empty rows and columns.
    import scipy.sparse as sp

    from elements.fibrous.tangent import CornerPairs
    from elements.fibrous.tangent_kernels import MembraneProduct

    mesh = Mesh.rectangle(30.0, 20.0, nx=4, ny=3)
    n = len(mesh.points) + stray
    renumbered = np.arange(len(mesh.points)) + (np.arange(len(mesh.points)) >= 7) * stray
    pairs = CornerPairs(renumbered[mesh.triangles], n)
    rng = np.random.default_rng(2)
    count = pairs.indices.size
    hessian = rng.normal(size=(count, 9, 9))
    jacobian = np.zeros((count, 9, 6))
    jacobian[:, 6:, :3] = rng.normal(size=(count, 3, 3))
    diagonal = pairs.indices == np.repeat(np.arange(n), np.diff(pairs.indptr))
    jacobian[diagonal, :6, :6] += np.eye(6)
    h = sp.bsr_matrix((hessian, pairs.indices, pairs.indptr), shape=(9 * n, 9 * n))
    j = sp.bsr_matrix((jacobian, pairs.indices, pairs.indptr), shape=(9 * n, 6 * n))
    expected = (j.T @ (h @ j)).toarray()
    got = MembraneProduct(pairs.indptr, pairs.indices, n)(hessian, jacobian[:, 6:, :3])
    assert np.abs(got.toarray() - expected).max() <= 1e-12 * np.abs(expected).max()


def _element_normal_block(kernel: str):
    """A jittered fibrous sheet with Bai's element normals (Eq. 15) and tilted directors:
    its compiled block and the corner positions and directors of its cells (m, 3, 3)."""
    mesh = Mesh.rectangle(40.0, 20.0, nx=6, ny=3)
    model = Model(mesh)
    model.add(FibrousShell(presets.g986_stack(), kernel=kernel, thickness="element"))
    compiled = model.compile()
    state = compiled.initial_state()
    rng = np.random.default_rng(5)
    positions = state.positions + rng.normal(scale=0.4, size=state.positions.shape)
    turn = np.cross(state.directors, rng.normal(scale=0.2, size=state.positions.shape))
    directors = rotate_about(state.directors, turn)
    block = compiled.blocks[0]
    state = dataclasses.replace(state, positions=positions, directors=directors)
    return compiled, state, block, positions[block.connectivity], directors[block.connectivity]


def test_the_compiled_cell_membrane_loads_are_the_numpy_ones_for_every_copy():
    # Element normals: the compiled passes on stacked copies of the cells give each copy the
    # tension + shear corner loads of membrane.py (the same sums in another order: 1e-12 of
    # the largest), and a copy moved elsewhere its own loads.
    from elements.fibrous.kernels import cell_membrane_loads
    from elements.fibrous.tangent import membrane_loads

    _, _, block, x, v = _element_normal_block("compiled")
    moved = x + np.random.default_rng(6).normal(scale=0.1, size=x.shape)
    force, moment = cell_membrane_loads(block, np.concatenate([x, moved]), np.concatenate([v, v]))
    m = len(x)
    for copy, corners in ((0, x), (1, moved)):
        expected_force, expected_moment = membrane_loads(block, corners, v)
        rows = slice(copy * m, (copy + 1) * m)
        assert np.abs(force[rows] - expected_force).max() <= 1e-12 * np.abs(expected_force).max()
        assert np.abs(moment[rows] - expected_moment).max() <= 1e-12 * np.abs(expected_moment).max()


def test_cell_membrane_loads_refuses_nodal_normals_and_a_partial_copy():
    import pytest

    from elements.fibrous.kernels import cell_membrane_loads

    _, _, block, x, v = _element_normal_block("compiled")
    with pytest.raises(ValueError, match="not copies"):
        cell_membrane_loads(block, x[:-1], v[:-1])
    model = Model(Mesh.rectangle(40.0, 20.0, nx=2, ny=2))
    model.add(FibrousShell(presets.g986_stack()))
    nodal = model.compile().blocks[0]
    with pytest.raises(ValueError, match="element normals only"):
        cell_membrane_loads(nodal, x[: len(nodal.connectivity)], v[: len(nodal.connectivity)])


def test_stacked_central_differences_are_local_tangents_to_the_bit():
    # The same perturbations and quotients in one call: with a force that treats each stacked
    # copy as local_tangent's cell_force treats the cells, the blocks are the same bits.
    from elements.base import local_tangent, stacked_local_tangent

    rng = np.random.default_rng(7)
    x = rng.normal(size=(40, 3, 3))
    v = rotate_about(
        np.tile([0.0, 0.0, 1.0], (40, 3, 1)).reshape(-1, 3), rng.normal(scale=0.3, size=(120, 3))
    ).reshape(40, 3, 3)

    def cell_force(xx, vv):  # a non-linear cell-local force and moment
        edges = xx - xx.mean(axis=1, keepdims=True)
        return np.sin(edges) * np.sum(vv * edges, axis=-1)[..., None], np.cross(vv, edges**2)

    reference = local_tangent(cell_force, x, v, 1e-6)
    stacked = stacked_local_tangent(cell_force, x, v, 1e-6)
    assert np.array_equal(stacked, reference)
    # In calls of 2 unknowns (160 cells; 18 unknowns), or of one unknown at a time.
    for cells_per_call in (160, 1):
        chunked = stacked_local_tangent(cell_force, x, v, 1e-6, cells_per_call=cells_per_call)
        assert np.array_equal(chunked, reference)


def test_stacked_central_differences_keep_local_tangents_bits_at_a_signed_zero():
    # local_tangent's + copy is x + shift, which turns a -0.0 coordinate into +0.0: a force
    # that sees the sign (arctan2 of a zero) must get the same blocks from the stacked copies.
    from elements.base import local_tangent, stacked_local_tangent

    x = np.array([[[1.0, -0.0, 0.0], [0.0, 1.0, -0.0], [-1.0, -0.0, 0.5]]])
    v = np.tile([0.0, 0.0, 1.0], (1, 3, 1))

    def cell_force(xx, vv):
        angle = np.arctan2(xx[..., 1:2], -np.ones_like(xx[..., :1]))  # pi or -pi at y = +-0
        return angle * xx, np.cross(vv, xx)

    reference = local_tangent(cell_force, x, v, 1e-6)
    assert np.array_equal(stacked_local_tangent(cell_force, x, v, 1e-6), reference)


def test_the_element_normal_tangent_is_the_numpy_kernels_within_the_differences_noise():
    # The compiled kernel's element-normal membrane stiffness is central differences of the
    # compiled loads, the numpy kernel's of the numpy loads: loads within 1e-15 of each other,
    # divided by 2 x 1e-6 of an element, leave about 1e-9 of the largest entry (measured
    # 4e-10).
    parts = {}
    for kernel in ("numpy", "compiled"):
        compiled, state, *_ = _element_normal_block(kernel)
        parts[kernel] = compiled.tangent_parts(state, [0])
    for reference, fast in zip(parts["numpy"], parts["compiled"]):
        expected = reference.matrix.toarray() if hasattr(reference, "matrix") else reference.blocks
        got = fast.matrix.toarray() if hasattr(fast, "matrix") else fast.blocks
        assert np.abs(got - expected).max() <= 1e-8 * np.abs(expected).max()


def test_the_bending_patch_is_made_once_and_again_for_new_side_tables():
    # bending.patch_nodes reads the whole block's patch made at its first call: the same
    # integers as made afresh from the side tables, for a slice or an index array of cells,
    # read-only; and when apply_supports sets new side tables (a clamped line: sides that no
    # longer couple two cells), the patch of the new tables, not the one kept.
    from elements.fibrous import bending
    from elements.fibrous.supports import apply_supports

    mesh = Mesh.rectangle(40.0, 20.0, nx=6, ny=3)
    model = Model(mesh)
    model.add(FibrousShell(presets.g986_stack()))
    block = model.compile().blocks[0]
    tables = lambda: (block.connectivity, block.interior_side, block.across_cell)  # noqa: E731
    nodes, slot = bending.patch_nodes(block)
    fresh_nodes, fresh_slot = bending._patch_of(*tables())
    assert np.array_equal(nodes, fresh_nodes) and np.array_equal(slot, fresh_slot)
    assert not nodes.flags.writeable and bending.patch_nodes(block)[0].base is nodes.base
    cells = np.array([5, 0, 17])
    assert np.array_equal(bending.patch_nodes(block, cells)[1], fresh_slot[cells])
    held = mesh.points[:, 0] <= 20.0 + 1e-9  # a clamped half: its sides couple nothing
    apply_supports(block, held)
    changed_nodes, changed_slot = bending._patch_of(*tables())
    assert not np.array_equal(changed_slot, fresh_slot)
    nodes, slot = bending.patch_nodes(block)
    assert np.array_equal(nodes, changed_nodes) and np.array_equal(slot, changed_slot)
