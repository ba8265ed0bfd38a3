"""The stability search of Static (solvers.stability.lowest_modes; docs/theory.md §6.5): bounded
in its operator applications, and the modes it returns those of a dense eigen-solver."""

from __future__ import annotations

import numpy as np
import scipy.linalg as sl
import scipy.sparse as sp
from scipy.sparse.linalg import LinearOperator, splu

from solvers import stability
from solvers.stability import lowest_modes

# The spectrum of a tangent of the 16-cell hemisphere drape by Static on the smoothed die
# (benchmarks/hemisphere_static.py; c = 1200, load factor 0.3 -> 0.4): six negative
# eigenvalues, two of them far from zero, and positive ones from 5.6e-4 up to about 1e3.
NEGATIVE = np.array([-40.99, -12.41, -0.1549, -0.08459, -0.02197, -0.003818])


def drape_like_tangent(n: int = 400) -> sp.csc_matrix:
    """(n, n) sparse symmetric matrix with the drape's negative eigenvalues and n - 6 positive
    ones spread log-uniformly over 5.6e-4 .. 1e3, its eigenvectors mixed in 4 x 4 blocks by
    random rotations (a fixed seed)."""
    rng = np.random.default_rng(7)
    values = np.concatenate([NEGATIVE, np.geomspace(5.6e-4, 1e3, n - NEGATIVE.size)])
    values = values[rng.permutation(n)]
    blocks = [np.linalg.qr(rng.standard_normal((4, 4)))[0] for _ in range(n // 4)]
    rotation = sp.block_diag(blocks, format="csc")
    return (rotation @ sp.diags(values) @ rotation.T).tocsc()


def counted_inverse(k: sp.csc_matrix):
    """(LinearOperator applying k^-1 from its LU, the list holding its count of applications)."""
    lu, count = splu(k), [0]

    def apply(x):
        count[0] += 1
        return lu.solve(x)

    return LinearOperator(k.shape, matvec=apply, dtype=float), count


def test_the_search_is_bounded_where_the_shift_invert_hardly_separates_the_modes():
    # Shift-invert about 0 maps -41 and -12 to -0.024 and -0.081, among the images of the
    # positive eigenvalues (0 .. 1800): unbounded (the code before the bound), ARPACK ran
    # 38 309 solves into its default 4000 restarts and returned no mode at all. The bound:
    # NCV + restarts x NCV applications of the inverse (ARPACK applies its operator at most
    # NCV times per restart, NCV at the start).
    k = drape_like_tangent()
    inverse, count = counted_inverse(k)
    values, vectors = lowest_modes(k, NEGATIVE.size, inverse)
    bound = stability.NCV * (1 + stability.SHIFT_INVERT_RESTARTS)
    assert count[0] <= bound
    # All six found, equal to the dense solver's: the eigenvalues to 1e-8 relative (ARPACK's
    # Ritz residual RITZ_TOL = 1e-8 of the eigenvalue bounds the error of each), the vectors
    # to 1e-6 in angle (residual / gap, the gaps here >= 1e-3 of the spread of the spectrum
    # a search sees), and each an eigenvector of k to its residual.
    expected, modes = sl.eigh(k.toarray(), subset_by_index=[0, NEGATIVE.size - 1])
    assert values.size == NEGATIVE.size
    assert np.allclose(values, expected, rtol=1e-8, atol=0.0)
    assert np.all(np.abs(np.sum(vectors * modes, axis=0)) >= 1.0 - 1e-6)
    residual = np.linalg.norm(k @ vectors - vectors * values, axis=0)
    assert np.all(residual <= 1e-6 * np.abs(values))


def test_a_search_that_does_not_converge_returns_its_converged_modes_only():
    # No restart allowed: what the Lanczos converges in its first NCV vectors is returned,
    # each an exact mode of the dense solver's (to the tolerances above); nothing wrong is.
    k = drape_like_tangent()
    expected = sl.eigh(k.toarray(), eigvals_only=True, subset_by_index=[0, NEGATIVE.size - 1])
    restarts = stability.SHIFT_INVERT_RESTARTS, stability.PLAIN_RESTARTS
    stability.SHIFT_INVERT_RESTARTS = stability.PLAIN_RESTARTS = 1
    try:
        inverse, count = counted_inverse(k)
        values, vectors = lowest_modes(k, NEGATIVE.size, inverse)
    finally:
        stability.SHIFT_INVERT_RESTARTS, stability.PLAIN_RESTARTS = restarts
    assert count[0] <= 2 * stability.NCV
    assert values.size < NEGATIVE.size
    for value, phi in zip(values, vectors.T):
        assert np.min(np.abs(value - expected) / np.abs(expected)) <= 1e-8
        assert np.linalg.norm(k @ phi - value * phi) <= 1e-6 * abs(value)
