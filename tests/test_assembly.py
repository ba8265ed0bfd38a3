"""femcore.assembly: the sparse tangent of element parts, and its cached pattern."""

import numpy as np
import pytest
import scipy.sparse as sp

from femcore.assembly import CellTangent, FreeTangentAssembler, SparseTangent, tangent_matrix
from femcore.dofs import DofManager

N = 4


def translation_dofs() -> DofManager:
    active = np.zeros((N, 5), dtype=bool)
    active[:, :3] = True
    fixed = np.zeros_like(active)
    fixed[0, :3] = True
    prescribed = np.zeros_like(active)
    prescribed[3, 0] = True
    return DofManager(N, active, fixed, prescribed)


def one_rotation_prescribed() -> DofManager:
    """Five DOFs a node (translations and two rotations), node 0's translations fixed, one
    rotation of node 3 prescribed."""
    active = np.ones((N, 5), dtype=bool)
    fixed = np.zeros_like(active)
    fixed[0, :3] = True
    prescribed = np.zeros_like(active)
    prescribed[3, 1] = True
    return DofManager(N, active, fixed, prescribed)


def springs(pairs, rng) -> list[CellTangent]:
    """Random symmetric 6 x 6 blocks on node pairs (like a contact that pairs nodes)."""
    pairs = np.asarray(pairs)
    a = rng.normal(size=(len(pairs), 6, 6))
    blocks = (a + a.transpose(0, 2, 1)).reshape(len(pairs), 2, 3, 2, 3)
    return [CellTangent(pairs, blocks)]


def test_the_free_assembler_matches_the_full_matrix_and_follows_a_changing_pattern():
    dofs = translation_dofs()
    assemble = FreeTangentAssembler(dofs)
    rng = np.random.default_rng(0)
    free, moved = dofs.free_slots, dofs.prescribed_slots
    for pairs in ([[0, 1], [1, 2]], [[0, 1], [1, 2]], [[2, 3]], [[1, 3], [0, 2], [2, 3]]):
        parts = springs(pairs, rng)
        full = tangent_matrix(dofs, parts, None).toarray()
        k_ff, k_fp = assemble(parts, None)
        assert np.array_equal(k_ff.toarray(), full[np.ix_(free, free)])
        assert np.array_equal(k_fp.toarray(), full[np.ix_(free, moved)])
    # Built once for the first two (same pairs), then once per change of pairs.
    assert assemble.builds == 3


def test_sparse_parts_assemble_from_their_node_blocks_with_the_cached_pattern():
    """A SparseTangent (6 x 6 node blocks, BSR, or any scipy format) with cell parts, in the
    frames of tilted directors: K_ff and K_fp equal the full matrix's, the pattern is built
    once while the structure stays and again when it changes."""
    active = np.ones((N, 5), dtype=bool)
    fixed = np.zeros_like(active)
    fixed[0] = True
    prescribed = np.zeros_like(active)
    prescribed[3, :2] = True
    dofs = DofManager(N, active, fixed, prescribed)
    rng = np.random.default_rng(1)
    directors = rng.normal(size=(N, 3))
    frames = dofs.frames(directors / np.linalg.norm(directors, axis=1)[:, None])
    free, moved = dofs.free_slots, dofs.prescribed_slots
    assemble = FreeTangentAssembler(dofs)
    mask = np.kron(rng.random((N, N)) < 0.6, np.ones((6, 6)))
    for fmt in ("bsr", "bsr", "csr"):
        matrix = sp.csr_matrix(rng.normal(size=(6 * N, 6 * N)) * mask)
        matrix = sp.bsr_matrix(matrix, blocksize=(6, 6)) if fmt == "bsr" else matrix
        cells = CellTangent(np.array([[0, 2], [1, 3]]), rng.normal(size=(2, 2, 6, 2, 6)))
        parts = [SparseTangent(matrix), cells]
        full = tangent_matrix(dofs, parts, frames).toarray()
        k_ff, k_fp = assemble(parts, frames)
        assert np.allclose(k_ff.toarray(), full[np.ix_(free, free)], rtol=0, atol=1e-12)
        assert np.allclose(k_fp.toarray(), full[np.ix_(free, moved)], rtol=0, atol=1e-12)
    # The second matrix has the first one's blocks (the same mask); the CSR one too, once
    # converted to blocks.
    assert assemble.builds == 1


def test_the_compiled_scatter_adds_the_generalised_blocks_where_the_bincount_does():
    """The assembler's compiled pass (T_a^T K_ab T_b with T's shape used, added at positions
    found once) against generalised_blocks and a bincount, on 6-node patches in the frames of
    tilted directors, with a node twice in a patch and a prescribed unknown."""
    from femcore import assembly

    dofs = one_rotation_prescribed()
    rng = np.random.default_rng(2)
    directors = rng.normal(size=(N, 3))
    maps = dofs.node_maps(dofs.frames(directors / np.linalg.norm(directors, axis=1)[:, None]))
    nodes = np.array([[0, 1, 2, 3, 1, 2], [3, 2, 1, 0, 0, 3]])
    part = CellTangent(nodes, rng.normal(size=(2, 6, 6, 6, 6)))
    assemble = FreeTangentAssembler(dofs)
    assemble([part], dofs.frames(np.tile([0.0, 0.0, 1.0], (N, 1))))  # builds the positions
    ff, fp = np.zeros(assemble.ff_rows.size), np.zeros(assemble.fp_rows.size)
    pairs, tables = assemble._pairs[0], assemble._tables
    assembly._add_cell_blocks(part.blocks, nodes, maps, pairs, *tables, ff, fp)
    flat = assembly.generalised_blocks(part, maps).ravel()
    expected_ff = np.bincount(assemble.ff_map, flat[assemble.ff_select], minlength=ff.size)
    expected_fp = np.bincount(assemble.fp_map, flat[assemble.fp_select], minlength=fp.size)
    assert np.allclose(ff, expected_ff, rtol=1e-14, atol=1e-13)
    assert np.allclose(fp, expected_fp, rtol=1e-14, atol=1e-13)


def test_the_pattern_counted_per_node_pair_is_the_sorted_union_of_the_entries():
    """K_ff's CSC structure and K_fp's CSR structure, counted per node pair (FreeTangentAssembler
    ._build), equal scipy's canonical structure of every part's entries on the free rows and
    free / prescribed columns (the np.unique over the entries it replaced), and the values
    the full matrix's: translation-only and full parts on overlapping pairs, a node twice in a
    part, a SparseTangent, unknowns fixed, prescribed and inactive; again after the pairs
    change."""
    n = 7
    active = np.ones((n, 5), dtype=bool)
    active[6, 3:] = False  # a translation-only node
    fixed = np.zeros_like(active)
    fixed[0, :3] = True
    fixed[4, 4] = True
    prescribed = np.zeros_like(active)
    prescribed[3, 1] = True
    prescribed[5, :] = True
    dofs = DofManager(n, active, fixed, prescribed)
    rng = np.random.default_rng(3)
    directors = rng.normal(size=(n, 3))
    frames = dofs.frames(directors / np.linalg.norm(directors, axis=1)[:, None])
    free, moved = dofs.free_slots, dofs.prescribed_slots
    assemble = FreeTangentAssembler(dofs)
    for shift in range(3):
        pairs = (np.array([[0, 6], [6, 2], [1, 3]]) + shift) % n
        patches = (np.array([[0, 1, 2, 1], [4, 5, 3, 2]]) + shift) % n
        mask = np.kron(rng.random((n, n)) < 0.2, np.ones((6, 6)))
        parts = [
            CellTangent(pairs, rng.normal(size=(3, 2, 3, 2, 3))),
            CellTangent(patches, rng.normal(size=(2, 4, 6, 4, 6))),
            SparseTangent(sp.bsr_matrix(rng.normal(size=(6 * n, 6 * n)) * mask, blocksize=(6, 6))),
        ]
        k_ff, k_fp = assemble(parts, frames)
        full = tangent_matrix(dofs, parts, frames)
        ones = full.copy()
        ones.data[:] = 1.0  # every entry stored, also those whose values cancel
        expected_ff = ones[free][:, free].tocsc()
        expected_ff.sum_duplicates()
        expected_fp = ones[free][:, moved].tocsr()
        expected_fp.sum_duplicates()
        assert np.array_equal(k_ff.indptr, expected_ff.indptr)
        assert np.array_equal(k_ff.indices, expected_ff.indices)
        k_fp.sum_duplicates()
        assert np.array_equal(k_fp.indptr, expected_fp.indptr)
        assert np.array_equal(k_fp.indices, expected_fp.indices)
        dense = full.toarray()
        assert np.allclose(k_ff.toarray(), dense[np.ix_(free, free)], rtol=0, atol=1e-12)
        assert np.allclose(k_fp.toarray(), dense[np.ix_(free, moved)], rtol=0, atol=1e-12)
    assert assemble.builds == 3


def test_the_assembler_gives_scipy_its_structure_in_the_index_type_scipy_keeps():
    # K_ff's and K_fp's structure is kept in the index type scipy stores it in (int32 while
    # every index fits), so that each assembly hands scipy arrays it takes as they are; given
    # int64 ones it scanned and copied them to int32 at every call (0.35 ms for 320 000
    # entries). The matrices are the ones the int64 structure gives.
    dofs = one_rotation_prescribed()
    rng = np.random.default_rng(4)
    nodes = np.array([[0, 1, 2, 3, 1, 2], [3, 2, 1, 0, 0, 3]])
    part = CellTangent(nodes, rng.normal(size=(2, 6, 6, 6, 6)))
    assemble = FreeTangentAssembler(dofs)
    k_ff, k_fp = assemble([part], dofs.frames(np.tile([0.0, 0.0, 1.0], (N, 1))))
    assert k_ff.indices.dtype == assemble.ff_rows.dtype == assemble.ff_indptr.dtype
    assert k_fp.indices.dtype == assemble.fp_cols.dtype == assemble.fp_indptr.dtype
    wide = sp.csc_matrix(
        (k_ff.data, assemble.ff_rows.astype(np.int64), assemble.ff_indptr.astype(np.int64)),
        shape=k_ff.shape,
    )
    assert wide.indices.dtype == k_ff.indices.dtype
    assert np.array_equal(wide.indices, k_ff.indices) and np.array_equal(wide.indptr, k_ff.indptr)
    # The matrices share the assembler's structure (scipy does not copy it), so a change of
    # one's structure in place is refused rather than carried into the next assembly.
    before = assemble.ff_rows.copy()
    k_ff.data[:] = 0.0
    with pytest.raises(ValueError, match="read-only"):
        k_ff.eliminate_zeros()
    assert np.array_equal(assemble.ff_rows, before)


def test_a_kept_structure_serves_parts_within_it_and_grows_to_the_union_of_their_pairs():
    """FreeTangentAssembler(superset=True) on contact-like parts whose pairs come and go: K_ff
    and K_fp hold the same values as the exact structure's (the entries it adds are stored
    zeros), the structure is built once per pair outside it (the union then) and kept for
    parts within it; parts reaching less than 1 / SUPERSET_SLACK of its pairs get their own.
    Reference: the full matrix (tangent_matrix) and the exact structure (superset=False)."""
    from femcore import assembly

    n = 7
    active = np.ones((n, 5), dtype=bool)
    active[6, 3:] = False
    fixed = np.zeros_like(active)
    fixed[0, :3] = True
    prescribed = np.zeros_like(active)
    prescribed[5, :] = True
    dofs = DofManager(n, active, fixed, prescribed)
    rng = np.random.default_rng(4)
    directors = rng.normal(size=(n, 3))
    frames = dofs.frames(directors / np.linalg.norm(directors, axis=1)[:, None])
    free = dofs.free_slots
    kept, exact = FreeTangentAssembler(dofs, superset=True), FreeTangentAssembler(dofs)
    shell = CellTangent(np.array([[0, 1, 2], [2, 3, 4]]), rng.normal(size=(2, 3, 6, 3, 6)))
    contacts = ([[1, 5], [3, 6]], [[1, 5]], [[4, 6], [1, 5]], [[3, 6]], [[1, 5]])
    builds = []
    for pairs in contacts:
        parts = [shell, springs(pairs, rng)[0]]
        k_ff, k_fp = kept(parts, frames)
        e_ff, e_fp = exact(parts, frames)
        assert np.array_equal(k_ff.toarray(), e_ff.toarray())
        assert np.array_equal(k_fp.toarray(), e_fp.toarray())
        dense = tangent_matrix(dofs, parts, frames).toarray()
        assert np.allclose(k_ff.toarray(), dense[np.ix_(free, free)], rtol=0, atol=1e-12)
        builds.append(kept.builds)
    # (4, 6) comes outside the first structure: the union; the rest lie within it
    assert builds == [1, 1, 2, 2, 2]
    assert exact.builds == 5
    # the cells' 2 x 9 node pairs, (2, 2) in both; the springs' 3 x 4, less (1, 1), (3, 3),
    # (4, 4) (the cells') and (6, 6) (twice)
    assert kept._pair_rows.size == 17 + 8
    # parts reaching too few of the kept pairs: built on their own
    small = [CellTangent(np.array([[1, 2]]), rng.normal(size=(1, 2, 6, 2, 6)))]
    assert kept._pair_rows.size > assembly.SUPERSET_SLACK * 4
    kept(small, frames)
    assert kept.builds == 3 and kept._pair_rows.size == 4


def test_the_pairs_within_a_structure_are_found_by_bisection():
    """tangent_pattern.pairs_within against a dictionary of the structure's pairs: the index
    of each node pair, the count of distinct pairs reached, and -1 where a pair is missing
    or wider than its structure's."""
    from femcore import tangent_pattern

    rng = np.random.default_rng(5)
    n = 30
    pairs = sorted({(int(c), int(r)) for r, c in rng.integers(0, n, (200, 2))})
    columns = np.array([c for c, _ in pairs])
    rows = np.array([r for _, r in pairs])
    wide = rng.random(rows.size) < 0.5
    start = np.concatenate([[0], np.cumsum(np.bincount(columns, minlength=n))])
    index = {(r, c): q for q, (c, r) in enumerate(pairs)}
    pick = rng.integers(0, rows.size, 500)
    asked_wide = wide[pick] & (rng.random(500) < 0.5)
    inverse, distinct = tangent_pattern.pairs_within(
        rows[pick], columns[pick], asked_wide, start, rows, wide
    )
    assert [index[(r, c)] for r, c in zip(rows[pick], columns[pick])] == list(inverse)
    assert distinct == np.unique(pick).size
    missing = next((r, c) for r in range(n) for c in range(n) if (r, c) not in index)
    assert (
        tangent_pattern.pairs_within(
            np.array([missing[0]]), np.array([missing[1]]), np.array([False]), start, rows, wide
        )[1]
        == -1
    )
    narrow = int(np.flatnonzero(~wide)[0])
    assert (
        tangent_pattern.pairs_within(
            rows[[narrow]], columns[[narrow]], np.array([True]), start, rows, wide
        )[1]
        == -1
    )
    found = tangent_pattern._pairs_within(  # the loops without numba: the same
        rows[pick], columns[pick], asked_wide, start, rows, wide
    )
    assert np.array_equal(found[0], inverse) and found[1] == distinct


@pytest.mark.parametrize("superset", [False, True])
def test_a_part_naming_a_node_outside_the_model_is_refused(superset):
    """A node index past n_nodes (or negative) in a cell part: a ValueError naming the part
    and the index, in both modes, after a first assembly of valid pairs (the kept
    structure's lookup would read past its arrays)."""
    dofs = translation_dofs()
    assemble = FreeTangentAssembler(dofs, superset=superset)
    rng = np.random.default_rng(6)
    assemble(springs([[1, 2]], rng), None)
    with pytest.raises(ValueError, match=r"part 0: node index 7 outside \[0, 4\)"):
        assemble(springs([[1, 7]], rng), None)
    with pytest.raises(ValueError, match=r"node index -1 outside"):
        assemble(springs([[-1, 2]], rng), None)
    k_ff, _ = assemble(springs([[1, 2]], rng), None)  # still usable
    assert k_ff.shape == (dofs.free_slots.size,) * 2


def shell_dofs(n=5):
    """n nodes of 5 unknowns each, node 0's translations fixed, node n - 1's prescribed."""
    active = np.ones((n, 5), dtype=bool)
    fixed = np.zeros_like(active)
    fixed[0, :3] = True
    prescribed = np.zeros_like(active)
    prescribed[n - 1, :] = True
    return DofManager(n, active, fixed, prescribed)


def test_a_wide_part_on_a_pair_the_kept_structure_holds_narrow_rebuilds_it():
    """A 3-component part on nodes (0, 1) and (1, 4), then a 6-component one on the same
    pairs: the kept structure holds those pairs' translations only, so it must be grown to
    the rotations' entries. K_ff and K_fp equal superset=False's bit for bit and the dense
    tangent_matrix's (reference) to round-off."""
    dofs = shell_dofs()
    rng = np.random.default_rng(7)
    frames = dofs.frames(np.tile([0.0, 0.0, 1.0], (5, 1)))
    free, moved = dofs.free_slots, dofs.prescribed_slots
    kept, exact = FreeTangentAssembler(dofs, superset=True), FreeTangentAssembler(dofs)
    narrow = springs([[0, 1], [1, 4]], rng)
    wide = [CellTangent(np.array([[0, 1], [1, 4]]), rng.normal(size=(2, 2, 6, 2, 6)))]
    for parts in (narrow, wide, narrow):
        k_ff, k_fp = kept(parts, frames)
        e_ff, e_fp = exact(parts, frames)
        for got, expected in ((k_ff, e_ff), (k_fp, e_fp)):
            assert np.array_equal(got.toarray(), expected.toarray())
        dense = tangent_matrix(dofs, parts, frames).toarray()
        assert np.allclose(k_ff.toarray(), dense[np.ix_(free, free)], rtol=0, atol=1e-12)
        assert np.allclose(k_fp.toarray(), dense[np.ix_(free, moved)], rtol=0, atol=1e-12)
    # the narrow structure, the wide one (the union), kept for the narrow part again
    assert kept.builds == 2
    assert np.abs(k_ff.toarray()).max() > 0.0


def spd_springs(pairs, rng, components=3) -> list[CellTangent]:
    """Symmetric positive definite blocks (A A^T + 2 I) on node pairs."""
    pairs = np.asarray(pairs)
    size = 2 * components
    a = rng.normal(size=(len(pairs), size, size))
    blocks = a @ a.transpose(0, 2, 1) + 2.0 * np.eye(size)
    return [CellTangent(pairs, blocks.reshape(len(pairs), 2, components, 2, components))]


def test_a_union_reaching_too_few_of_its_pairs_is_built_on_the_parts_alone():
    """A kept structure of five springs' 16 pairs, then one spring (5, 6) outside it: the
    union (19 pairs) holds more than SUPERSET_SLACK times the 4 pairs the spring reaches, so
    the structure is built again on the spring's alone (two builds: the union, then its
    own). Reference: the exact structure (superset=False), bit for bit."""
    from femcore import assembly

    dofs = shell_dofs(n=7)
    rng = np.random.default_rng(8)
    frames = dofs.frames(np.tile([0.0, 0.0, 1.0], (7, 1)))
    kept, exact = FreeTangentAssembler(dofs, superset=True), FreeTangentAssembler(dofs)
    chain = spd_springs([[0, 1], [1, 2], [2, 3], [3, 4], [4, 5]], rng)
    alone = spd_springs([[5, 6]], rng)
    for parts in (chain, alone):
        k_ff, k_fp = kept(parts, frames)
        e_ff, e_fp = exact(parts, frames)
        assert np.array_equal(k_ff.toarray(), e_ff.toarray())
        assert np.array_equal(k_fp.toarray(), e_fp.toarray())
    assert 19 > assembly.SUPERSET_SLACK * 4
    assert kept.builds == 3 and kept._pair_rows.size == 4
    assert np.array_equal(k_ff.indices, e_ff.indices)  # the spring's own structure


def test_the_kept_structures_stored_zeros_factorise_as_the_exact_structure():
    """K_ff of a kept structure (a union holding pairs the parts leave out: stored zeros)
    and of the exact one: the linear solver's split of the upper triangle leaves the zeros
    out, so both give the same triangle, the same negative pivots and the same solution,
    bit for bit (the premise of the kept structure), and numpy's solution to 1e-10
    relative (condition number below 1e3 on these SPD springs)."""
    from solvers.linear import LinearSolver

    dofs = shell_dofs(n=7)
    rng = np.random.default_rng(9)
    frames = dofs.frames(np.tile([0.0, 0.0, 1.0], (7, 1)))
    kept, exact = FreeTangentAssembler(dofs, superset=True), FreeTangentAssembler(dofs)
    base = [[0, 1], [1, 2], [2, 3], [3, 4], [4, 5], [5, 6]]
    stiff = spd_springs(base, rng, components=6)
    contacts = ([[1, 4], [2, 5]], [[1, 5]], [[2, 5]])  # the third lies within the union
    for pairs in contacts:
        parts = stiff + spd_springs(pairs, rng)
        k_ff, _ = kept(parts, frames)
        e_ff, _ = exact(parts, frames)
        assert np.array_equal(k_ff.toarray(), e_ff.toarray())
        solutions = []
        for matrix in (k_ff, e_ff):
            solver = LinearSolver()
            _, upper = solver._plan_for(matrix).split(matrix.data)
            factor = solver.factorise(matrix)
            rhs = np.linspace(-1.0, 1.0, matrix.shape[0])
            solutions.append((upper, factor.negative, factor.kind, factor.solve(rhs)))
        (ku, kn, kk, kx), (eu, en, ek, ex) = solutions
        assert np.array_equal(ku.indptr, eu.indptr) and np.array_equal(ku.indices, eu.indices)
        assert np.array_equal(ku.data, eu.data)
        assert kn == en == 0 and kk == ek == "ldlt"
        assert np.array_equal(kx, ex)
        expected = np.linalg.solve(e_ff.toarray(), rhs)
        assert np.max(np.abs(kx - expected)) <= 1e-10 * np.max(np.abs(expected))
    assert kept.builds == 2 and exact.builds == 3
    assert k_ff.nnz > e_ff.nnz  # the last K_ff holds stored zeros


def test_the_compiled_passes_are_built_once_for_read_only_and_writable_nodes():
    """A block's connectivity is kept read-only, a contact's or a patch's nodes are fresh and
    writable: the assembler's scatter and the Gershgorin bound's pair sums take both as one
    type (femcore/assembly.py ``kernel_nodes``), so numba builds each kernel once for them
    (a read-only and a writable build of each before: benchmarks/suite_signatures.py on a
    whole run's cache). Reference: numba's record of its builds; no tolerance."""
    from femcore import assembly, gershgorin

    scatter, sums = assembly._add_cell_blocks_compiled, gershgorin._pair_sums
    if scatter is None or not hasattr(sums, "signatures"):
        pytest.skip("numba is not installed")
    dofs = one_rotation_prescribed()
    maps = dofs.node_maps(dofs.frames(np.tile([0.0, 0.0, 1.0], (N, 1))))
    blocks = np.random.default_rng(4).normal(size=(2, 3, 3, 6, 6))
    kept = np.array([[0, 1, 2], [3, 2, 1]])
    kept.setflags(write=False)
    before = len(scatter.signatures), len(sums.signatures)
    for nodes in (kept, kept.copy()):
        assert nodes.flags.writeable == (nodes is not kept)
        part = CellTangent(nodes, blocks)
        FreeTangentAssembler(dofs)([part], dofs.frames(np.tile([0.0, 0.0, 1.0], (N, 1))))
        gershgorin._piece_sums(part, maps, N, lambda keys: np.zeros((len(keys), 5, 5)))
    added = len(scatter.signatures) - before[0], len(sums.signatures) - before[1]
    assert added[0] <= 1 and added[1] <= 1, added
