"""The compiled passes of a Newton iteration's tangent: the node blocks of the SparseTangent
parts (femcore/assembly.py ``_add_node_blocks``) give K_ff and K_fp as numpy's matmuls and
bincount do, and the upper triangle's split (solvers/linear.py ``_split_upper``) gives
numpy's, on a fibrous shell with nodal normals (a SparseTangent and cell blocks) and on a
Mindlin shell (cell blocks only), on one numba thread and on all.

Tolerances: the node blocks' products are sums in a fixed order without fused multiply-adds,
numpy's are BLAS's (rounded as the machine's kernel does), so the two agree to a few
roundings of the largest entry (1e-14 of it; measured 1.8e-16 on the 40-cell fibrous corner
of benchmarks/paper_cases.py); the cell blocks' pass is unchanged, and with no node blocks
K_ff is the same bits. The split's operations are numpy's: the same bits."""

import dataclasses

import numpy as np
import pytest
import scipy.sparse as sp

from elements import FibrousShell, MindlinShell
from femcore import Mesh, Model, assembly
from femcore.assembly import CellTangent, FreeTangentAssembler, SparseTangent
from femcore.dofs import DofManager
from femcore.rotation import rotate_about
from materials import ElasticShell, presets
from solvers.linear import LinearSolver
from tests.thread_runs import on_one_thread_and_on_all


def tilted_model(kind: str):
    """A clamped, edge-pulled sheet of the given shell, jittered, its directors tilted:
    (compiled model, state, frames)."""
    mesh = Mesh.rectangle(40.0, 20.0, nx=6, ny=3)
    model = Model(mesh)
    if kind == "fibrous":
        model.add(FibrousShell(presets.g986_stack()))
    else:
        model.add(MindlinShell(ElasticShell(1000.0, 0.3, 2.0, 1e-9)))
    model.fix(mesh.nodes(lambda x, y, z: x <= 1e-9))
    model.displace(mesh.nodes(lambda x, y, z: x >= 40.0 - 1e-9), uz=-2.0)
    compiled = model.compile()
    state = compiled.initial_state()
    rng = np.random.default_rng(4)
    positions = state.positions + rng.normal(scale=0.4, size=state.positions.shape)
    turn = np.cross(state.directors, rng.normal(scale=0.2, size=state.positions.shape))
    state = dataclasses.replace(
        state, positions=positions, directors=rotate_about(state.directors, turn)
    )
    return compiled, state, compiled.dofs.frames(state.directors)


def numpy_node_blocks(assemble, parts, frames, monkeypatch):
    """(K_ff, K_fp) with the node blocks by numpy's matmuls and bincount."""
    with monkeypatch.context() as patch:
        patch.setattr(assembly, "_add_node_blocks_compiled", None)
        return assemble(parts, frames)


def counted_node_pass(monkeypatch) -> list[int]:
    """Counts the calls of the compiled node-block pass from here on."""
    calls = []
    compiled = assembly._add_node_blocks_compiled

    def counting(*args):
        calls.append(1)
        return compiled(*args)

    monkeypatch.setattr(assembly, "_add_node_blocks_compiled", counting)
    return calls


@pytest.mark.parametrize("kind", ["fibrous", "mindlin"])
def test_the_compiled_tangent_assembly_gives_numpys_on_one_thread_and_on_all(kind, monkeypatch):
    model, state, frames = tilted_model(kind)
    parts = model.tangent_parts(state, [0])
    sparse = sum(isinstance(p, SparseTangent) for p in parts)
    assert sparse == (1 if kind == "fibrous" else 0)
    assemble = FreeTangentAssembler(model.dofs)
    reference_ff, reference_fp = numpy_node_blocks(assemble, parts, frames, monkeypatch)
    calls = counted_node_pass(monkeypatch)
    one, every = on_one_thread_and_on_all(lambda: assemble(parts, frames))
    assert len(calls) == 2 * sparse  # the compiled pass did add the node blocks
    scale = np.abs(reference_ff.data).max()
    for k_ff, k_fp in (one, every):
        assert np.array_equal(k_ff.indptr, reference_ff.indptr)
        assert np.array_equal(k_ff.indices, reference_ff.indices)
        if sparse:
            assert np.abs(k_ff.data - reference_ff.data).max() <= 1e-14 * scale
            assert np.abs((k_fp - reference_fp).toarray()).max() <= 1e-14 * scale
        else:
            assert np.array_equal(k_ff.data, reference_ff.data)
            assert np.array_equal(k_fp.toarray(), reference_fp.toarray())
    assert np.array_equal(one[0].data, every[0].data)  # serial: the same bits
    assert np.array_equal(one[1].toarray(), every[1].toarray())
    # The split of the upper triangle, by the compiled pass and by numpy's.
    k_ff = one[0]
    solver = LinearSolver()
    plan = solver._plan_for(k_ff)
    assert plan is not None
    asymmetry, upper = plan.split(k_ff.data)
    expected_asymmetry, expected = plan.split_numpy(k_ff.data)
    assert asymmetry == expected_asymmetry
    assert np.array_equal(upper.indptr, expected.indptr)
    assert np.array_equal(upper.indices, expected.indices)
    assert np.array_equal(upper.data, expected.data)


def test_several_sparse_parts_add_as_the_bincount_sums_them(monkeypatch):
    """Two SparseTangents and cell blocks on the same node pairs, tilted frames, fixed and
    prescribed unknowns: the compiled pass against numpy's, to round-off of the largest entry,
    and K_ff against the full matrix's (tangent_matrix)."""
    n = 6
    active = np.ones((n, 5), dtype=bool)
    fixed = np.zeros_like(active)
    fixed[0, :3] = True
    prescribed = np.zeros_like(active)
    prescribed[5, :2] = True
    dofs = DofManager(n, active, fixed, prescribed)
    rng = np.random.default_rng(7)
    directors = rng.normal(size=(n, 3))
    frames = dofs.frames(directors / np.linalg.norm(directors, axis=1)[:, None])
    mask = np.kron(rng.random((n, n)) < 0.5, np.ones((6, 6)))
    parts = [
        CellTangent(np.array([[0, 1, 2], [3, 4, 5]]), rng.normal(size=(2, 3, 6, 3, 6))),
        SparseTangent(sp.bsr_matrix(rng.normal(size=(6 * n, 6 * n)) * mask, blocksize=(6, 6))),
        SparseTangent(sp.bsr_matrix(rng.normal(size=(6 * n, 6 * n)) * mask, blocksize=(6, 6))),
    ]
    assemble = FreeTangentAssembler(dofs)
    reference_ff, reference_fp = numpy_node_blocks(assemble, parts, frames, monkeypatch)
    calls = counted_node_pass(monkeypatch)
    k_ff, k_fp = assemble(parts, frames)
    assert len(calls) == 2
    scale = np.abs(reference_ff.data).max()
    assert np.abs(k_ff.data - reference_ff.data).max() <= 1e-14 * scale
    assert np.abs((k_fp - reference_fp).toarray()).max() <= 1e-14 * scale
    full = assembly.tangent_matrix(dofs, parts, frames).toarray()
    free, moved = dofs.free_slots, dofs.prescribed_slots
    assert np.abs(k_ff.toarray() - full[np.ix_(free, free)]).max() <= 1e-13 * scale
    assert np.abs(k_fp.toarray() - full[np.ix_(free, moved)]).max() <= 1e-13 * scale


def test_the_compiled_split_reports_a_nan_and_keeps_the_zero_diagonal():
    """An entry that is not a number makes the asymmetry nan (as numpy's max), an exact zero
    off the diagonal is left out, a zero on it is kept (QDLDL needs it)."""
    # Every entry stored (explicit zeros at (0, 0), (0, 2) and (2, 0)), sorted CSC.
    rows, columns = np.divmod(np.arange(9), 3)
    values = np.array([0.0, 1.0, 0.0, 1.0, 2.0, 3.0, 0.0, 3.0, 4.0])
    k = sp.csc_matrix((values, (rows, columns)), shape=(3, 3))
    assert k.nnz == 9
    solver = LinearSolver()
    plan = solver._plan_for(k)
    asymmetry, upper = plan.split(k.data)
    expected_asymmetry, expected = plan.split_numpy(k.data)
    assert asymmetry == expected_asymmetry == 0.0
    assert np.array_equal(upper.toarray(), expected.toarray())
    assert upper.nnz == expected.nnz == 5  # (0, 0) zero kept; (0, 2) zero left out
    k.data[0] = np.nan
    assert np.isnan(plan.split(k.data)[0]) and np.isnan(plan.split_numpy(k.data)[0])
