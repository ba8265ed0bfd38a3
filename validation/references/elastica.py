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


def heavy_strip_over_cylinder(
    half_length: float,
    weight: float,
    bending_stiffness: float,
    radius: float,
    points: int = 401,
) -> dict:
    """A heavy strip laid symmetrically over a horizontal frictionless cylinder: it wraps the
    cylinder from the top down to the lift-off angle theta_0, then hangs as a heavy elastica.

    The wrapped part follows the circle of ``radius`` (that of the strip's mid-surface, mm),
    so its curvature is 1 / radius; at lift-off the moment stays continuous (B / radius),
    and the free end carries no moment. With l = half_length - radius theta_0 the hanging
    length and theta(s) the downward slope from lift-off (s = 0) to the free end (s = l):

        B theta'' = -q (l - s) cos(theta),  theta(0) = theta_0,  theta'(0) = 1 / radius,
        theta'(l) = 0,

    three conditions for a second-order equation and the unknown theta_0 (the heavy elastica
    of ``heavy_cantilever`` with the cylinder's curvature at its root; the shear force may
    jump at lift-off, a line reaction of the cylinder there).

    half_length : mm, from the top to the free end along the strip; weight : q, N/mm^2;
    bending_stiffness : B, N mm per unit width; radius : mm.
    Returns a dict: lift_off (theta_0, rad from the top), hanging (l, mm), and the whole
    half-strip from the top: s (arc length), x (horizontal from the axis), z (height above
    the axis), mm; tip_x, tip_z.
    """
    load = weight / bending_stiffness

    def hanging(theta_0):
        return half_length - radius * theta_0

    def rhs(t, y, p):  # t = s / l in [0, 1], y = (theta, d theta / dt)
        length = hanging(p[0])
        return np.vstack([y[1], -load * length**3 * (1.0 - t) * np.cos(y[0])])

    def bc(ya, yb, p):
        return np.array([ya[0] - p[0], ya[1] - hanging(p[0]) / radius, yb[1]])

    t = np.linspace(0.0, 1.0, points)
    guess = np.vstack([0.2 + 1.2 * t, np.full_like(t, 1.0)])
    solution = solve_bvp(rhs, bc, t, guess, p=[0.2], tol=1e-10, max_nodes=100000)
    if not solution.success:
        raise RuntimeError(f"strip over a cylinder did not converge: {solution.message}")
    theta_0 = float(solution.p[0])
    length = hanging(theta_0)
    if not 0.0 < theta_0 < np.pi / 2 or length <= 0.0:
        raise RuntimeError(
            f"strip over a cylinder: lift-off at {theta_0!r} rad is outside (0, pi/2)"
        )
    theta = solution.sol(t)[0]
    wrapped = np.linspace(0.0, theta_0, points)
    x_hang = radius * np.sin(theta_0) + length * cumulative_trapezoid(np.cos(theta), t, initial=0)
    z_hang = radius * np.cos(theta_0) - length * cumulative_trapezoid(np.sin(theta), t, initial=0)
    s = np.concatenate([radius * wrapped, radius * theta_0 + length * t[1:]])
    x = np.concatenate([radius * np.sin(wrapped), x_hang[1:]])
    z = np.concatenate([radius * np.cos(wrapped), z_hang[1:]])
    return {
        "lift_off": theta_0,
        "hanging": length,
        "s": s,
        "x": x,
        "z": z,
        "tip_x": float(x[-1]),
        "tip_z": float(z[-1]),
    }
