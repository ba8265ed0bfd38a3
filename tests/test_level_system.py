"""The penalty system of the level-strain projection's sweeps (solvers.level_system).

K + rho J^T diag(held) J and J^T diag(held) e, with rho the penalty times the ratio of the
largest diagonals of K and J^T diag(held) J, are scipy's sparse products of the same matrices
(the reference), to round-off of the sums' order (1e-12 of the largest entry), on a J whose
rows come in runs of one column list (a cell's measures), runs of one row and rows of
different lengths, with rows not held; the system is exactly symmetric, its pattern holds
K's and J^T J's entries, and a K of another pattern is placed on a new one.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from solvers.level_system import PenaltySystem

SIZE = 40


def _jacobian(rng) -> sp.csr_matrix:
    rows = []
    for run, length in [(3, 7), (1, 5), (4, 9), (2, 3), (1, 11), (3, 7)]:
        columns = rng.choice(SIZE, length, replace=False)
        rows += [columns] * run
    indptr = np.r_[0, np.cumsum([len(r) for r in rows])]
    indices = np.concatenate(rows)
    return sp.csr_matrix((rng.normal(size=indices.size), indices, indptr), shape=(len(rows), SIZE))


def _stiffness(seed: int) -> sp.csc_matrix:
    k = sp.random(SIZE, SIZE, 0.1, random_state=seed)
    return (k + k.T + 4.0 * sp.eye(SIZE)).tocsc()


def test_system_and_pull_are_the_sparse_products():
    rng = np.random.default_rng(7)
    jacobian = _jacobian(rng)
    held = (rng.random(jacobian.shape[0]) > 0.3).astype(float)
    error = rng.normal(size=jacobian.shape[0])
    system = PenaltySystem(SIZE)
    for seed in (1, 1, 2):  # the same K's pattern, then another
        k = _stiffness(seed)
        assembled = system.assemble(k, jacobian, held, 100.0)
        assert assembled is not None
        matrix, rho = assembled
        scaled = sp.diags(held) @ jacobian
        normal = scaled.T @ scaled
        expected_rho = 100.0 * abs(k.diagonal()).max() / abs(normal.diagonal()).max()
        assert abs(rho - expected_rho) <= 1e-12 * expected_rho
        expected = (k + expected_rho * normal).toarray()
        scale = np.abs(expected).max()
        assert np.abs(matrix.toarray() - expected).max() <= 1e-12 * scale
        assert np.array_equal(matrix.toarray(), matrix.toarray().T)
        pull = system.pull(jacobian, held, error)
        reference = scaled.T @ error
        assert np.abs(pull - reference).max() <= 1e-12 * np.abs(reference).max()


def test_no_held_row_gives_no_system():
    rng = np.random.default_rng(3)
    jacobian = _jacobian(rng)
    held = np.zeros(jacobian.shape[0])
    assert PenaltySystem(SIZE).assemble(_stiffness(1), jacobian, held, 100.0) is None
