"""elements/fibrous/tangent_kernels.py: the compiled loops of the fibrous shell's tangent give
the numbers of their numpy references in elements/fibrous/tangent.py and bending.py (the same
sums in another order: 1e-12 of the largest entry)."""

import dataclasses

import numpy as np

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


def test_the_structured_membrane_product_is_the_sparse_product():
    # J's node blocks are the identity on the diagonal plus dS/dx in rows 6-8, columns 0-2;
    # the compiled product uses that shape and must give scipy's J^T H J of the full blocks.
    import scipy.sparse as sp

    from elements.fibrous.tangent import CornerPairs
    from elements.fibrous.tangent_kernels import MembraneProduct

    mesh = Mesh.rectangle(30.0, 20.0, nx=4, ny=3)
    pairs = CornerPairs(mesh.triangles, len(mesh.points))
    rng = np.random.default_rng(2)
    count, n = pairs.indices.size, len(mesh.points)
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
