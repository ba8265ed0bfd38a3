"""What the data of an identification determine (``fibreshell identify``): the covariance of the
fitted parameters, their correlations, and which of them, or which combinations of them, the
data tell apart from zero change, judged against the finite-difference Jacobian's own error
(docs/theory.md §10.2).

The fit is over p_j = ln(theta_j / theta_j0). The Jacobian J = dr/dp is taken by central
differences, (r(p + h e_j) - r(p - h e_j)) / (2 h); the half difference of the forward and the
backward ones, E = (r(p + h e_j) - 2 r(p) + r(p - h e_j)) / (2 h), is the measured error of
the forward difference: its truncation (h / 2) d2r/dp2 and the scatter of the model's solves
(each solve's tolerance) over h. By Weyl's inequality a singular value of J moves by at most
the spectral norm of J's error, so a singular value at or below |E|_2 cannot be told from
zero: the data do not determine the parameters' combination along its singular vector (two
parameters that enter only as a ratio give a singular value of order h |J|, the truncation
error itself). The combinations along the other singular vectors are determined.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["CORRELATION_BOUND", "NULL_SHARE", "Determinacy", "combination_text", "determinacy"]

# |correlation| above which two parameters are reported as not separately determined: their
# joint confidence region is then an ellipse over 22 times longer than wide
# (sqrt((1 + 0.999) / (1 - 0.999)) = 44.7 for the axes' ratio of the correlation matrix), and
# each one's interval is the other's uncertainty, not its own.
CORRELATION_BOUND = 0.999

# A parameter whose unit direction has more than this share (its length) in the undetermined
# singular vectors is not determined alone (0.1: its direction is more than 5.7 deg out of the
# determined subspace).
NULL_SHARE = 0.1


@dataclass
class Determinacy:
    """What the data determine, in p = ln(theta / theta_0).

    Attributes
    ----------
    singular_values : (n,) float
        Of the central-difference Jacobian dr/dp (residual units), descending.
    jacobian_error : float
        |E|_2, the spectral norm of the forward difference's measured error (residual units).
    vectors : (n, n) float
        The right singular vectors, as columns, in the order of ``singular_values``.
    rank : int
        The singular values above ``jacobian_error``: the combinations the data determine.
    covariance_p : (n, n) float
        s^2 (J^T J)^+ over the determined singular vectors (NaN with no residual degree of
        freedom, m = n).
    correlation : (n, n) float
        The correlation matrix of the fitted parameters (NaN where a variance is 0 or NaN).
    determined : (n,) bool
        Each parameter determined alone: out of every undetermined singular vector
        (``NULL_SHARE``) and correlated with no other beyond ``CORRELATION_BOUND``.
    correlated : list of (int, int, float)
        The pairs (i, j, correlation) beyond ``CORRELATION_BOUND``.
    """

    singular_values: np.ndarray
    jacobian_error: float
    vectors: np.ndarray
    rank: int
    covariance_p: np.ndarray
    correlation: np.ndarray
    determined: np.ndarray
    correlated: list[tuple[int, int, float]]

    @property
    def all_determined(self) -> bool:
        return bool(np.all(self.determined))


def determinacy(
    forward: np.ndarray, backward: np.ndarray, residual: np.ndarray, parameters: int
) -> Determinacy:
    """The determinacy of a least-squares fit at its solution.

    Parameters
    ----------
    forward, backward : (m, n) float
        The forward (r(p + h e_j) - r(p)) / h and backward (r(p) - r(p - h e_j)) / h
        difference Jacobians dr/dp at the solution (residual units per unit of ln theta).
    residual : (m,) float
        The residuals at the solution.
    parameters : int
        n, the number of fitted parameters.

    Returns
    -------
    Determinacy
    """
    m, n = forward.shape
    if n != parameters or backward.shape != forward.shape or residual.shape != (m,):
        raise ValueError(
            f"determinacy: expected Jacobians of shape (m, {parameters}) and residuals (m,), "
            f"got {forward.shape}, {backward.shape}, {residual.shape}"
        )
    central = 0.5 * (forward + backward)
    error = float(np.linalg.norm(0.5 * (forward - backward), 2))
    _, singular, vt = np.linalg.svd(central, full_matrices=False)
    vectors = vt.T
    rank = int(np.sum(singular > error))
    kept = vectors[:, :rank]
    if m > n and rank > 0:
        variance = float(residual @ residual) / (m - n)
        covariance = variance * (kept / singular[:rank] ** 2) @ kept.T
    else:
        covariance = np.full((n, n), np.nan)
    scale = np.sqrt(np.diag(covariance))
    with np.errstate(invalid="ignore", divide="ignore"):
        correlation = covariance / np.outer(scale, scale)
    correlation[~np.isfinite(correlation)] = np.nan
    null_share = np.linalg.norm(vectors[:, rank:], axis=1)
    determined = null_share <= NULL_SHARE
    correlated = [
        (i, j, float(correlation[i, j]))
        for i in range(n)
        for j in range(i + 1, n)
        if abs(correlation[i, j]) > CORRELATION_BOUND
    ]
    for i, j, _ in correlated:
        determined[i] = determined[j] = False
    return Determinacy(
        singular_values=singular,
        jacobian_error=error,
        vectors=vectors,
        rank=rank,
        covariance_p=covariance,
        correlation=correlation,
        determined=determined,
        correlated=correlated,
    )


def combination_text(keys: list[str], vector: np.ndarray) -> tuple[str, np.ndarray]:
    """A singular vector in p = ln(theta / theta_0) as the product of powers of the parameters
    it is the logarithm of, its largest exponent 1 in size and its first positive:
    (-1/sqrt2, 1/sqrt2) over B and rho_A is "B^1 * rho_A^-1", B / rho_A. Exponents under
    1e-3 of the largest are left out.

    Returns
    -------
    (str, (n,) float)
        The text and the exponents.
    """
    exponents = vector / np.max(np.abs(vector))
    # The sign of a singular vector is arbitrary: the first parameter's exponent positive.
    exponents = exponents * np.sign(exponents[np.abs(exponents) >= 1e-3][0])
    terms = [f"{key}^{a:.3g}" for key, a in zip(keys, exponents) if abs(a) >= 1e-3]
    return " * ".join(terms), exponents
