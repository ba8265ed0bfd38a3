"""femcore.assembly: the sparse tangent of element parts, and its cached pattern."""

import numpy as np

from femcore.assembly import CellTangent, FreeTangentAssembler, tangent_matrix
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
