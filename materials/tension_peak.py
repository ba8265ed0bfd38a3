"""Where a tension law's fibre force stops rising with the stretch (docs/theory.md §6.4d).

Why. A fibre of tension T(eps) per unit initial width, eps = ln(lambda), pulls its neighbours
with T / lambda per unit current width, whose derivative along the stretch is

    d(T / lambda) / d(lambda) = (T'(eps) - T(eps)) / lambda^2,

so the force rises while T' > T and falls past the first strain where T' - T turns negative
with T > 0: the linear law T = C eps at eps = 1 (lambda = e), a law that stiffens as
C (exp(eps) - 1) never (T' - T = C). Past that strain a fibre softens as it stretches, and a
state there is no state the law was meant for (solvers/acceptance.py). In compression
(T < 0) the force's magnitude falls with lambda where T' - T < 0 as well; a non-decreasing
law (every table, tension-only laws: T = 0) never does so.
"""

from __future__ import annotations

import math

import numpy as np

from materials.laws import Law

__all__ = ["softening_strains"]


def softening_strains(law: Law) -> tuple[float, float]:
    """The strains (ln lambda) past which ``law``'s force per unit reference width T / lambda falls.

    Parameters
    ----------
    law : Law
        A TensionLaw (T in N/mm per unit initial width of the logarithmic strain).

    Returns
    -------
    (lower, upper) : (float, float)
        ``upper`` > 0 the least strain beyond which T / lambda falls with the stretch (inf:
        never), ``lower`` < 0 the greatest strain below which the compressive force's
        magnitude falls as lambda falls (-inf: never; a tension-only law carries none).
    """
    if law.odd_coefficients is not None:
        return _polynomial(law)
    return -math.inf, _table_upper(law)


def _polynomial(law: Law) -> tuple[float, float]:
    """(lower, upper) of an odd polynomial T = sum c_k eps^k: the sign changes of the
    polynomial T' - T to negative, found among its real roots."""
    coefficients = law.odd_coefficients or ()
    degree = 2 * len(coefficients) - 1
    # g = T' - T, highest power first (numpy.roots' order)
    g = np.zeros(degree + 1)
    for i, c in enumerate(coefficients):
        k = 2 * i + 1
        g[degree - k] -= c
        g[degree - (k - 1)] += k * c
    roots = np.roots(np.trim_zeros(g, "f"))
    real = np.sort(roots[np.abs(roots.imag) <= 1e-12 * (1.0 + np.abs(roots.real))].real)

    def past(root: float, side: float) -> bool:
        # just past the root on ``side``: T' - T negative with T of that side's sign
        probe = root + side * 1e-6 * max(1.0, abs(root))
        return float(np.polyval(g, probe)) < 0.0 and side * float(law.value(probe)) > 0.0

    upper = next((float(r) for r in real if r > 0.0 and past(r, 1.0)), math.inf)
    lower = -math.inf
    if law.compression:
        lower = next((float(r) for r in real[::-1] if r < 0.0 and past(r, -1.0)), -math.inf)
    return lower, upper


def _table_upper(law: Law) -> float:
    """``upper`` of a piecewise-linear law, extrapolated linearly past its last knot: on a
    piece of slope s from eps = a, T' - T = s - T(a) - s (eps - a) reaches zero at
    a + (s - T(a)) / s."""
    kx, _ = law.knots if law.knots is not None else (np.zeros(0), np.zeros(0))
    starts = np.concatenate(([0.0], kx[kx > 0.0]))
    ends = np.concatenate((kx[kx > 0.0], [math.inf]))
    for a, b in zip(starts, ends):  # the pieces of eps >= 0, once per law (not per step)
        s, t = float(law.slope(a)), float(law.value(a))
        if t > 0.0 and s <= t:
            return float(a)  # T' - T <= 0 from this knot on
        if s > 0.0 and a < a + (s - t) / s < b:
            return float(a + (s - t) / s)
    return math.inf
