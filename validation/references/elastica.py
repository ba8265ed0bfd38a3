"""Large-deflection cantilever under its own weight (the heavy elastica), by a boundary-value
solve independent of any finite element.

Inextensible strip of length L, clamped horizontally at s = 0, free at s = L, bending moment
M(kappa) per unit width (any monotonic law), weight q per unit length and unit width acting
downwards. With theta(s) the downward slope, the moment at s carries the weight beyond it:

    M(theta'(s)) = q * integral_s^L (x(t) - x(s)) dt,

and differentiating, d/ds M(theta') = -q (L - s) cos(theta), with theta(0) = 0, theta'(L) = 0.
For a linear law M = B kappa this is B theta'' = -q (L - s) cos(theta) (Frisch-Fay, Flexible
Bars, 1962, ch. 3; the small-deflection limit is the tip deflection q L^4 / (8 B)).
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import cumulative_trapezoid, solve_bvp


def _clamped_free(length: float, curvature_rate, guess, points: int, what: str) -> dict:
    """Solve theta'' = curvature_rate(s, theta) with theta(0) = 0 (clamped horizontally) and
    theta'(L) = 0 (free end) from ``guess`` = (theta, theta') at ``points`` stations, and
    integrate the shape: x = int cos(theta), z = -int sin(theta)."""
    s = np.linspace(0.0, length, points)

    def rhs(s, y):  # y = (theta, theta')
        return np.vstack([y[1], curvature_rate(s, y[0])])

    def bc(ya, yb):
        return np.array([ya[0], yb[1]])

    start = np.vstack(guess(s))
    start[0] = np.minimum(start[0], np.pi / 2 * 0.95)
    solution = solve_bvp(rhs, bc, s, start, tol=1e-10, max_nodes=100000)
    if not solution.success:
        raise RuntimeError(f"{what} did not converge: {solution.message}")
    theta = solution.sol(s)[0]
    x = cumulative_trapezoid(np.cos(theta), s, initial=0.0)
    z = -cumulative_trapezoid(np.sin(theta), s, initial=0.0)
    return {"s": s, "theta": theta, "x": x, "z": z, "tip_deflection": -z[-1], "tip_x": x[-1]}


def heavy_cantilever(length: float, weight: float, bending_stiffness: float, points: int = 401):
    """Shape of a cantilever under self-weight with M = B kappa.

    length : L, mm; weight : q, N/mm^2 (weight per unit length per unit width, rho_A g);
    bending_stiffness : B, N mm (per unit width).
    Returns a dict with s (arc length), theta (rad, downward slope), x, z (z <= 0), mm, and
    tip_deflection (mm, positive down) and tip_x.
    """
    load = weight / bending_stiffness
    return _clamped_free(
        length,
        lambda s, theta: -load * (length - s) * np.cos(theta),
        # The small-deflection solution: theta' = q (L - s)^2 / (2 B).
        lambda s: (load * (length**3 - (length - s) ** 3) / 6.0, load * (length - s) ** 2 / 2.0),
        points,
        "heavy elastica",
    )


def tip_loaded_cantilever(length: float, load: float, bending_stiffness: float, points: int = 401):
    """Inextensible cantilever, clamped horizontally, under a dead vertical tip load P.

    EI theta'' = -P cos(theta), theta(0) = 0, theta'(L) = 0 (the elastica; Bisshopp & Drucker,
    Q. Appl. Math. 3 (1945) 272: for P L^2 / EI = 1 the tip drops by 0.3017 L).
    Returns s, theta, x, z (z <= 0) and tip_deflection (positive down), tip_x.
    """
    k = load / bending_stiffness
    return _clamped_free(
        length,
        lambda s, theta: -k * np.cos(theta),
        lambda s: (k * (length * s - s**2 / 2), k * (length - s)),
        points,
        "elastica",
    )
