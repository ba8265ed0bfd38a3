"""The discretisation error of a quantity from its values on a sequence of meshes: the grid
convergence index of three of them, the observed order over every consecutive three (whether
they agree: the asymptotic range), and a least-squares power law through all of them.

Three meshes h1 > h2 > h3 give the observed order p and the Richardson value f0 through
f(h) = f0 + C h^p exactly (``validation.checks.observed_order``). Roache's grid convergence
index (Roache, J. Fluids Eng. 116 (1994) 405-413; Verification and Validation in
Computational Science and Engineering, Hermosa, 1998, ch. 5) states the fine mesh's error
band as GCI = Fs |f2 - f3| / (r^p - 1), r = h2 / h3, with the factor of safety Fs = 1.25 for
three or more meshes. Through three values that fit f0 + C h^p exactly, Roache's ratio check
(GCI of the coarser pair over r^p times the finer's, about 1 in the asymptotic range) holds
by construction, so it tests nothing: what shows the asymptotic range is a fourth mesh, the
orders of overlapping triplets agreeing with each other and lying among the orders the
discretisation can have (about 1 to 2 here). A field's order needs no limit: the norms of its
changes from each mesh to the next shrink as h^p does (``change_orders``). With more than
three meshes and scatter, Eca and Hoekstra (J. Comput. Phys. 262 (2014) 104-130) fit f0 +
C h^p to all of them by least squares and report the residuals' standard deviation beside
the change the fit explains: ``power_fit``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from validation.checks import observed_order

__all__ = [
    "SAFETY_FACTOR",
    "change_orders",
    "consecutive_orders",
    "grid_convergence_index",
    "power_fit",
]

#: Roache's factor of safety for an observed order from three or more meshes (1998, ch. 5).
SAFETY_FACTOR = 1.25


def _series(sizes: Sequence[float], values: Sequence[float], least: int) -> tuple:
    """(h, f) as float arrays, checked: at least ``least`` of each, sizes decreasing and
    positive, values finite."""
    h = np.asarray(sizes, dtype=float)
    f = np.asarray(values, dtype=float)
    if h.ndim != 1 or h.shape != f.shape or h.size < least:
        raise ValueError(
            f"give at least {least} sizes and as many values, got {h.shape} and {f.shape}"
        )
    if not (np.all(np.isfinite(h)) and h[-1] > 0.0 and np.all(np.diff(h) < 0.0)):
        raise ValueError(f"sizes must be positive and decreasing, got {h.tolist()}")
    if not np.all(np.isfinite(f)):
        raise ValueError(f"values must be finite, got {f.tolist()}")
    return h, f


def grid_convergence_index(
    sizes: Sequence[float], values: Sequence[float], safety: float = SAFETY_FACTOR
) -> dict[str, float]:
    """Roache's grid convergence index of the finest of three meshes (module docstring).

    Parameters
    ----------
    sizes : sequence of 3 float
        Mesh sizes h1 > h2 > h3 (any unit: only their ratios count).
    values : sequence of 3 float
        The quantity on each mesh (its unit is the index's).
    safety : float
        The factor of safety Fs, > 0.

    Returns
    -------
    dict
        ``order`` p and ``extrapolated`` f0 (``observed_order``; NaN when the differences
        change sign or vanish, or p lies outside its range; p < 0 where they grow, and then
        f0 is NaN), ``gci`` Fs |f2 - f3| / (r^p - 1) in the quantity's unit (NaN unless p >
        0: a sequence that does not converge has no band), ``relative`` that over |f3| (NaN
        where f3 is 0), ``ratio`` r = h2 / h3.

    Raises
    ------
    ValueError
        Sizes or values as ``observed_order`` refuses them, or a safety factor that is not
        positive.
    """
    if not (safety > 0.0 and math.isfinite(safety)):
        raise ValueError(f"the factor of safety must be positive, got {safety!r}")
    h, f = _series(sizes, values, 3)
    if h.size != 3:
        raise ValueError(f"give three sizes and values, got {h.size}")
    p, f0 = observed_order(h.tolist(), f.tolist())
    ratio = float(h[1] / h[2])
    if not p > 0.0:
        # A growing difference (p <= 0) or none: the sequence does not converge and
        # Roache's band is undefined (its r^p - 1 would be <= 0), as is the value at h = 0.
        p_band, f0 = math.nan, math.nan
    else:
        p_band = p
    index = safety * abs(f[1] - f[2]) / (ratio**p_band - 1.0) if math.isfinite(p_band) else math.nan
    relative = index / abs(f[2]) if f[2] != 0.0 else math.nan
    return {"order": p, "extrapolated": f0, "gci": index, "relative": relative, "ratio": ratio}


def consecutive_orders(sizes: Sequence[float], values: Sequence[float]) -> np.ndarray:
    """(m - 2,) the observed order of each three consecutive meshes of m (NaN where none):
    where they agree the meshes are in the asymptotic range. ``sizes`` decreasing, as
    ``observed_order``."""
    h, f = _series(sizes, values, 3)
    return np.array(
        [observed_order(h[i : i + 3].tolist(), f[i : i + 3].tolist())[0] for i in range(h.size - 2)]
    )


def change_orders(sizes: Sequence[float], changes: Sequence[float]) -> list[float]:
    """(m - 2) the observed order of a field from the sizes of its changes between m meshes
    (``sizes`` decreasing, ``changes`` (m - 1) the norms of f_i - f_(i+1)): for f = f0 +
    C h^p the changes are |C| (h_i^p - h_(i+1)^p), so each two consecutive ones solve
    ``observed_order``'s equation as the differences of the values (d1 + d2, d2, 0) do."""
    h = np.asarray(sizes, dtype=float)
    d = np.asarray(changes, dtype=float)
    if h.ndim != 1 or d.shape != (h.size - 1,) or h.size < 3:
        raise ValueError(f"give m >= 3 sizes and m - 1 changes, got {h.shape} and {d.shape}")
    return [
        observed_order(h[i : i + 3].tolist(), [d[i] + d[i + 1], d[i + 1], 0.0])[0]
        for i in range(d.size - 1)
    ]


def power_fit(
    sizes: Sequence[float], values: Sequence[float], order: float | None = None
) -> dict[str, float]:
    """The least-squares fit f(h) = f0 + C h^p to m >= 3 meshes (Eca and Hoekstra 2014).

    For a given p the fit is linear in (f0, C); p itself (when ``order`` is None) minimises
    the sum of squared residuals over 0.05 <= p <= 8, scanned in steps of 0.01 and then
    refined by golden sections about the best step.

    Parameters
    ----------
    sizes : sequence of float
        Mesh sizes, decreasing and positive.
    values : sequence of float
        The quantity on each mesh.
    order : float or None
        p held fixed (> 0), or None to fit it.

    Returns
    -------
    dict
        ``order`` p, ``extrapolated`` f0, ``coefficient`` C, ``residual`` the residuals'
        standard deviation sqrt(sum r^2 / (m - k)) (k the fitted parameters: 3, or 2 with
        ``order`` given; NaN when m = k) and ``change`` the fitted change over the meshes,
        |C| (h1^p - hm^p): the fit explains the sequence where ``residual`` is small beside it;
        ``bound`` True where the fitted p lies at an end of its range (no minimum inside it:
        no power law fits, as for a sequence whose steps grow).

    Raises
    ------
    ValueError
        Fewer than three meshes, sizes not decreasing and positive, values not finite, or an
        order that is not positive.
    """
    h, f = _series(sizes, values, 3)
    scale = h[0]  # h / h1 keeps h^p within range for any unit of h
    x = h / scale

    def solve(p: float) -> tuple[float, float, float]:
        basis = np.column_stack([np.ones_like(x), x**p])
        (f0, c), *_ = np.linalg.lstsq(basis, f, rcond=None)
        residual = f - basis @ np.array([f0, c])
        return float(f0), float(c), float(residual @ residual)

    if order is not None:
        if not (order > 0.0 and math.isfinite(order)):
            raise ValueError(f"a fixed order must be positive, got {order!r}")
        p = float(order)
        fitted = 2
    else:
        grid = np.arange(0.05, 8.0 + 1e-9, 0.01)
        sums = np.array([solve(p)[2] for p in grid])
        best = int(np.argmin(sums))
        low, high = grid[max(best - 1, 0)], grid[min(best + 1, grid.size - 1)]
        golden = 0.5 * (math.sqrt(5.0) - 1.0)
        for _ in range(60):
            a = high - golden * (high - low)
            b = low + golden * (high - low)
            if solve(a)[2] < solve(b)[2]:
                high = b
            else:
                low = a
        p = 0.5 * (low + high)
        fitted = 3
    f0, c, squares = solve(p)
    dof = h.size - fitted
    return {
        "order": p,
        "extrapolated": f0,
        "coefficient": c / scale**p,
        "residual": math.sqrt(squares / dof) if dof > 0 else math.nan,
        "change": abs(c) * (1.0 - x[-1] ** p),
        "bound": order is None and not (0.05 + 0.01 < p < 8.0 - 0.01),
    }
