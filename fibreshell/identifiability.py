"""What the data of an identification determine (``fibreshell identify``): the covariance of the
fitted parameters, their correlations, and which of them, or which combinations of them, the
data tell apart from zero change, each direction judged against the finite-difference
Jacobian's own error along it (docs/theory.md §10.2).

The fit is over p_j = ln(theta_j / theta_j0). The Jacobian analysed is the central difference
J_h = (r(p + h e_j) - r(p - h e_j)) / (2 h), J + C h^2 + (the solves' scatter) / h. The same
difference at 2 h is J + 4 C h^2 + (the scatter) / (2 h): D = J_2h - J_h is three times J_h's
truncation (Richardson) and of the order of its scatter, so |D v| bounds J_h's error along a
unit direction v with a margin of 3 on the truncation. Along a right singular vector v_k of
J_h, J_h v_k has length sigma_k; where the true J v_k is 0 it is J_h's error alone, so a
direction with sigma_k <= |D v_k| + (the round-off of a difference, eps |y| / h) cannot be
told from zero: the data do not determine the parameters' combination along it (two
parameters that enter only as a ratio). Each direction is judged by its own error: a
well-determined combination of small effect (a small sigma_k, a smaller error along it) is not
confused with a null one by the largest direction's error.

A parameter is determined alone only if its unit direction has no component along an
undetermined direction: along an exact null direction the data do not change at all, so any
component there, however small, makes the parameter's interval unbounded (Seber and Wild,
Nonlinear Regression, 1989, §3.4; Bates and Watts, Nonlinear Regression Analysis, 1988, ch.
2). What is measured of that component is the computed null space's error, which by Wedin's
sin-theta theorem is at most |J_h - J|_2 / sigma_r, sigma_r the least determined singular
value: a component up to that bound is the error of the measurement, a larger one is real.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = [
    "CORRELATION_BOUND",
    "WIDEST",
    "Determinacy",
    "combination_text",
    "determinacy",
    "reduced_combinations",
]

# |correlation| above which two parameters are reported as not separately determined: their
# joint confidence region is then an ellipse about 45 times longer than wide
# (sqrt((1 + 0.999) / (1 - 0.999)) = 44.7, the axes' ratio of the correlation matrix), and
# each one's interval is the other's uncertainty, not its own.
CORRELATION_BOUND = 0.999

# The widest 95 % interval, as a factor either way, of a combination the data determine: a
# combination known no better than to a factor of 10 (its linearised interval then spans
# orders of magnitude, where the Gauss-Newton linearisation it rests on no longer holds) is
# named undetermined by the data's scatter, though the Jacobian resolves it.
WIDEST = 10.0

# The largest whole exponent a combination is written with (B^1 * w^-1, B^1 * w^-3): a
# singular vector's entries within its error of such integers are that clean ratio or product.
SMALL_INTEGER = 9


@dataclass
class Determinacy:
    """What the data determine, in p = ln(theta / theta_0).

    Attributes
    ----------
    singular_values : (n,) float
        Of the central-difference Jacobian dr/dp (residual units), descending.
    direction_errors : (n,) float
        The Jacobian's estimated error along each right singular vector, |D v_k| plus the
        differences' round-off and the SVD's own, m eps sigma_1 (residual units).
    jacobian_error : float
        |D|_2 plus the same round-off: the spectral norm of the Jacobian's estimated error
        (residual units).
    vectors : (n, n) float
        The right singular vectors, as columns, in the order of ``singular_values``.
    resolved : (n,) bool
        The singular directions the data determine: sigma_k above its own error, and the
        combination's 95 % interval within a factor ``WIDEST`` either way.
    share_bound : float
        The largest component a parameter's unit direction may have in the undetermined
        directions and be determined alone: the bound of the computed null space's error
        (Wedin), ``jacobian_error`` over the least determined singular value.
    covariance_p : (n, n) float
        s^2 (J^T J)^+ over the determined singular vectors (NaN with no residual degree of
        freedom, m = n).
    correlation : (n, n) float
        The correlation matrix of the parameters with a finite variance (NaN in the rows
        and columns of the others, and where a variance is 0 or NaN).
    determined : (n,) bool
        Each parameter determined alone: no component in an undetermined direction beyond
        ``share_bound``, and correlated with no other beyond ``CORRELATION_BOUND``.
    correlated : list of (int, int, float)
        The pairs (i, j, correlation) beyond ``CORRELATION_BOUND``.
    """

    singular_values: np.ndarray
    direction_errors: np.ndarray
    jacobian_error: float
    vectors: np.ndarray
    resolved: np.ndarray
    share_bound: float
    covariance_p: np.ndarray
    correlation: np.ndarray
    determined: np.ndarray
    correlated: list[tuple[int, int, float]]

    @property
    def rank(self) -> int:
        """The number of determined combinations."""
        return int(np.count_nonzero(self.resolved))

    @property
    def all_determined(self) -> bool:
        return bool(np.all(self.determined))


def determinacy(
    central: np.ndarray,
    wide: np.ndarray,
    residual: np.ndarray,
    parameters: int,
    rounding: float = 0.0,
    scatter: float | None = None,
    confidence: float = 0.95,
) -> Determinacy:
    """The determinacy of a least-squares fit at its solution.

    Parameters
    ----------
    central, wide : (m, n) float
        The central-difference Jacobians dr/dp at the solution with steps h and 2 h
        (residual units per unit of ln theta).
    residual : (m,) float
        The residuals at the solution.
    parameters : int
        n, the number of fitted parameters.
    rounding : float
        The round-off of a Jacobian column's difference, eps |y| / h with y the model's
        values in residual units (residual units; 0: none).
    scatter : float or None
        The data's known scatter in residual units (1 where each residual is divided by its
        measurement's sigma): the statistical test of a direction takes the larger of it
        and the residuals' s. None: s alone.
    confidence : float
        The confidence level of the intervals the statistical test bounds.

    Returns
    -------
    Determinacy
    """
    central = np.asarray(central, dtype=float)
    wide = np.asarray(wide, dtype=float)
    residual = np.asarray(residual, dtype=float)
    if central.ndim != 2:
        raise ValueError(f"determinacy: expected a Jacobian of shape (m, n), got {central.shape}")
    m, n = central.shape
    if n != parameters or wide.shape != central.shape or residual.shape != (m,):
        raise ValueError(
            f"determinacy: expected Jacobians of shape (m, {parameters}) and residuals (m,), "
            f"got {central.shape}, {wide.shape}, {residual.shape}"
        )
    if scatter is not None and not (np.isfinite(scatter) and scatter > 0.0):
        raise ValueError(f"determinacy: scatter must be a number > 0 or None, got {scatter!r}")
    if not (np.isfinite(rounding) and rounding >= 0.0):
        raise ValueError(f"determinacy: rounding must be a number >= 0, got {rounding!r}")
    _, singular, vt = np.linalg.svd(central, full_matrices=False)
    vectors = vt.T
    difference = wide - central
    # The SVD's own round-off, m eps sigma_1 (numpy's rank tolerance), beside the
    # differences' error and their round-off.
    floor = rounding + m * np.finfo(float).eps * float(singular.max(initial=0.0))
    direction_errors = np.linalg.norm(difference @ vectors, axis=0) + floor
    resolved = singular > direction_errors
    if m > n:
        # The statistical test: the 95 % half-width of the combination as it is written,
        # its largest exponent 1 (v_k / max |v_kj|), t s / (sigma_k max |v_kj|) in ln,
        # within ln WIDEST (a stated scatter bounds s from below: residuals under the
        # measurement's precision do not make a combination better known).
        from scipy import stats

        s = float(np.sqrt(residual @ residual / (m - n)))
        s = max(s, scatter) if scatter is not None else s
        t = float(stats.t.ppf(0.5 + confidence / 2.0, m - n))
        with np.errstate(divide="ignore"):
            largest = np.abs(vectors).max(axis=0)
            resolved &= t * s / (singular * largest) < np.log(WIDEST)
    error = float(np.linalg.norm(difference, 2)) + floor
    least = float(singular[resolved].min()) if resolved.any() else 0.0
    share_bound = min(error / least, 1.0) if least > 0.0 else 1.0
    kept = vectors[:, resolved]
    if m > n and resolved.any():
        variance = float(residual @ residual) / (m - n)
        covariance = variance * (kept / singular[resolved] ** 2) @ kept.T
    else:
        covariance = np.full((n, n), np.nan)
    null_share = np.linalg.norm(vectors[:, ~resolved], axis=1)
    determined = null_share <= share_bound
    scale = np.sqrt(np.diag(covariance))
    with np.errstate(invalid="ignore", divide="ignore"):
        correlation = covariance / np.outer(scale, scale)
    # The pseudo-inverse gives a parameter with a null component a finite variance and
    # correlations: its true variance is infinite, and its correlations are not numbers.
    correlation[~determined, :] = np.nan
    correlation[:, ~determined] = np.nan
    correlation[~np.isfinite(correlation)] = np.nan
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
        direction_errors=direction_errors,
        jacobian_error=error,
        vectors=vectors,
        resolved=resolved,
        share_bound=share_bound,
        covariance_p=covariance,
        correlation=correlation,
        determined=determined,
        correlated=correlated,
    )


def reduced_combinations(vectors: np.ndarray, tolerance: float = 1e-9) -> np.ndarray:
    """A basis of the span of ``vectors`` (n, k) in reduced row-echelon form, rows (k, n):
    each row's pivot parameter in no other row, so that a span holding p1 - p2 and p3 gives
    those two and not the singular vectors' mixes of them. Each row scaled to its largest
    entry 1 in size, its first entry above ``tolerance`` positive."""
    rows = np.array(vectors, dtype=float).T.copy()
    k, n = rows.shape
    pivot_row = 0
    for column in range(n):
        if pivot_row == k:
            break
        below = np.abs(rows[pivot_row:, column])
        best = pivot_row + int(np.argmax(below))
        if below.max(initial=0.0) <= tolerance:
            continue
        rows[[pivot_row, best]] = rows[[best, pivot_row]]
        rows[pivot_row] /= rows[pivot_row, column]
        others = np.arange(k) != pivot_row
        rows[others] -= np.outer(rows[others, column], rows[pivot_row])
        pivot_row += 1
    rows = rows[np.abs(rows).max(axis=1) > tolerance]  # (none left from a dependent input)
    rows = rows / np.abs(rows).max(axis=1, keepdims=True)
    for row in rows:
        row[np.abs(row) <= tolerance] = 0.0
        row *= np.sign(row[np.flatnonzero(row)[0]])
    return rows


def combination_text(
    keys: list[str], vector: np.ndarray, tolerance: float = 1e-3
) -> tuple[str, np.ndarray]:
    """A direction in p = ln(theta / theta_0) as the product of powers of the parameters it is
    the logarithm of, its largest exponent 1 in size and its first positive:
    (-1/sqrt2, 1/sqrt2) over B and rho_A is "B^1 * rho_A^-1", B / rho_A. Exponents within
    ``tolerance`` (the direction's error) of zero are left out; where every other one is
    within it of a whole number up to SMALL_INTEGER after scaling the least to 1 (a clean
    ratio or product: B^1 * w^-3), they are written so.

    Returns
    -------
    (str, (n,) float)
        The text and the exponents (the whole numbers where clean).
    """
    exponents = np.asarray(vector, dtype=float) / np.max(np.abs(vector))
    exponents = np.where(np.abs(exponents) <= tolerance, 0.0, exponents)
    # The sign of a singular vector is arbitrary: the first parameter's exponent positive.
    exponents = exponents * np.sign(exponents[np.flatnonzero(exponents)[0]])
    present = exponents != 0.0
    whole = exponents / np.abs(exponents[present]).min()
    rounded = np.round(whole)
    relative = tolerance * np.abs(whole).max()
    if np.all(np.abs(whole - rounded) <= relative) and np.abs(rounded).max() <= SMALL_INTEGER:
        exponents = rounded
        terms = [f"{key}^{int(a)}" for key, a in zip(keys, exponents) if a != 0.0]
    else:
        terms = [f"{key}^{a:.3g}" for key, a in zip(keys, exponents) if a != 0.0]
    return " * ".join(terms), exponents
