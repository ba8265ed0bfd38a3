"""femcore.tangent_pattern: the compiled pattern of K_ff and K_fp against its numpy reference,
on parts whose pairs change from call to call as a ply contact's do."""

import numpy as np
import pytest
import scipy.sparse as sp

from femcore import assembly, tangent_pattern
from femcore.assembly import CellTangent, FreeTangentAssembler, SparseTangent
from femcore.dofs import DofManager


def stack_dofs(columns: int, layers: int) -> tuple[DofManager, np.ndarray]:
    """A stack of ``layers`` strips of 2 x ``columns`` triangles on (columns + 1) x 2 nodes
    each: the first layer's first two nodes clamped, every layer's last two moved along x
    and y, one node of each layer translation-only, one with a fixed rotation. Returns the
    DofManager and the layers' triangles (layers, 2 columns, 3)."""
    per_layer = 2 * (columns + 1)
    n = layers * per_layer
    active = np.ones((n, 5), dtype=bool)
    fixed = np.zeros_like(active)
    prescribed = np.zeros_like(active)
    fixed[:2] = True
    cells = []
    for layer in range(layers):
        first = layer * per_layer
        low, high = first + 2 * np.arange(columns), first + 2 * np.arange(columns) + 1
        cells.append(
            np.concatenate(
                [np.column_stack([low, low + 2, high]), np.column_stack([high, low + 2, high + 2])]
            )
        )
        prescribed[first + per_layer - 2 :, :2] = True
        active[first + 3, 3:] = False
        fixed[first + 4, 4] = True
    return DofManager(n, active, fixed, prescribed), np.array(cells)


def contact_parts(cells: np.ndarray, rng: np.random.Generator) -> list[CellTangent]:
    """One part of 6-node blocks per interface: a random subset of the upper layer's triangles
    (the touching ones), each with a random triangle of the layer below (the one it faces)."""
    parts = []
    for upper, lower in zip(cells[:-1], cells[1:]):
        touching = np.flatnonzero(rng.random(len(upper)) < 0.7)
        facing = rng.integers(0, len(lower), touching.size)
        nodes = np.concatenate([upper[touching], lower[facing]], axis=1)
        parts.append(CellTangent(nodes, rng.normal(size=(len(nodes), 6, 6, 6, 6))))
    return parts


def model_parts(dofs: DofManager, cells: np.ndarray, rng: np.random.Generator) -> list:
    """The layers' element parts (translation-only on the first, full on the others), the
    contact's changing parts and a SparseTangent of random node blocks."""
    parts: list = [CellTangent(cells[0], rng.normal(size=(len(cells[0]), 3, 3, 3, 3)))]
    parts += [CellTangent(c, rng.normal(size=(len(c), 3, 6, 3, 6))) for c in cells[1:]]
    parts += contact_parts(cells, rng)
    n = dofs.n_nodes
    mask = np.kron(rng.random((n, n)) < 0.05, np.ones((6, 6)))
    parts.append(
        SparseTangent(sp.bsr_matrix(rng.normal(size=(6 * n, 6 * n)) * mask, blocksize=(6, 6)))
    )
    return parts


def test_the_compiled_pattern_is_numpys_to_the_bit_while_the_contact_pairs_change():
    """Every array of the pattern (K_ff's CSC and K_fp's CSR structure, the places of each
    pair's entries, each part's pairs and so each entry's place), compiled against numpy,
    over calls whose contact parts change their touching triangles and the triangles they
    face."""
    dofs, cells = stack_dofs(columns=6, layers=4)
    rng = np.random.default_rng(4)
    compiled, reference = FreeTangentAssembler(dofs), FreeTangentAssembler(dofs)
    for _ in range(5):
        parts = model_parts(dofs, cells, rng)
        cell_parts = [p for p in parts if isinstance(p, CellTangent)]
        blocks = [sp.bsr_matrix(p.matrix, blocksize=(6, 6)) for p in parts[len(cell_parts) :]]
        compiled._build(cell_parts, blocks, compiled=True)
        reference._build(cell_parts, blocks, compiled=False)
        for name in ("ff_indptr", "ff_rows", "fp_indptr", "fp_rows", "fp_cols"):
            new, old = getattr(compiled, name), getattr(reference, name)
            assert new.dtype == old.dtype and np.array_equal(new, old), name
        for new, old in zip(compiled._tables, reference._tables):
            assert np.array_equal(new, old)
        assert len(compiled._pairs) == len(reference._pairs) == len(parts)
        for new, old in zip(compiled._pairs, reference._pairs):
            assert np.array_equal(new, old)
        for new, old in zip(compiled._destinations, reference._destinations):
            assert np.array_equal(new[0], old[0]) and np.array_equal(new[1], old[1])
        assert compiled.ff_indptr[-1] > 0 and compiled.fp_rows.size > 0  # both matrices hold


def test_the_assembled_tangent_is_the_same_with_either_pattern(monkeypatch):
    """K_ff and K_fp assembled through the compiled pattern and through numpy's: the same
    data, indices and pointers (np.array_equal), over changing contact parts; and so by the
    compiled passes reading the pairs' tables and by numpy's bincounts over each entry's
    place (the sums in another order: equal to rounding)."""
    dofs, cells = stack_dofs(columns=5, layers=3)
    rng = np.random.default_rng(5)
    directors = rng.normal(size=(dofs.n_nodes, 3))
    frames = dofs.frames(directors / np.linalg.norm(directors, axis=1)[:, None])
    calls = [model_parts(dofs, cells, rng) for _ in range(4)]
    compiled = FreeTangentAssembler(dofs)
    new = [compiled(parts, frames) for parts in calls]
    monkeypatch.setattr(tangent_pattern, "pattern", tangent_pattern.pattern_numpy)
    reference = FreeTangentAssembler(dofs)
    old = [reference(parts, frames) for parts in calls]
    assert compiled.builds == reference.builds == 4
    for (ff, fp), (ff_old, fp_old) in zip(new, old):
        for a, b in ((ff, ff_old), (fp, fp_old)):
            assert np.array_equal(a.data, b.data)
            assert np.array_equal(a.indices, b.indices)
            assert np.array_equal(a.indptr, b.indptr)
    monkeypatch.setattr(assembly, "_add_cell_blocks_compiled", None)
    monkeypatch.setattr(assembly, "_add_node_blocks_compiled", None)
    by_bincount = FreeTangentAssembler(dofs)
    for parts, (ff, fp) in zip(calls, new):
        ff_sum, fp_sum = by_bincount(parts, frames)
        for a, b in ((ff, ff_sum), (fp, fp_sum)):
            assert np.array_equal(a.indices, b.indices) and np.array_equal(a.indptr, b.indptr)
            scale = np.abs(a.data).max()
            assert np.allclose(a.data, b.data, rtol=0, atol=1e-13 * scale)  # rounding alone


@pytest.mark.parametrize("moved", [False, True])
def test_no_pairs_give_empty_matrices(moved):
    """No parts: K_ff and K_fp with no entries, either way, with and without prescribed
    unknowns."""
    dofs, _ = stack_dofs(columns=2, layers=1)
    n = dofs.n_nodes
    free = np.full((n, 5), -1)
    free.ravel()[dofs.free_slots] = np.arange(dofs.free_slots.size)
    prescribed = np.full((n, 5), -1)
    if moved:
        prescribed.ravel()[dofs.prescribed_slots] = np.arange(dofs.prescribed_slots.size)
    empty = np.zeros(0, dtype=np.int64)
    n_moved = dofs.prescribed_slots.size if moved else 0
    args = (empty, empty, np.zeros(0, dtype=bool), free, prescribed, dofs.free_slots.size, n_moved)
    for found in (tangent_pattern.pattern(*args), tangent_pattern.pattern_numpy(*args)):
        assert found.ff_rows.size == 0 and found.fp_rows.size == 0
        assert np.array_equal(found.ff_indptr, np.zeros(dofs.free_slots.size + 1))
