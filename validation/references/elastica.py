"""Large-deflection cantilever under its own weight (the heavy elastica), by a boundary-value
solve independent of any finite element.

Inextensible strip of length L, clamped horizontally at s = 0, free at s = L, bending moment
M(kappa) per unit width (any monotonic law), weight q per unit length and unit width acting
downwards. With theta(s) the downward slope, the moment at s carries the weight beyond it:

    M(theta'(s)) = q * integral_s^L (x(t) - x(s)) dt,

and differentiating, d/ds M(theta') = -q (L - s) cos(theta), with theta(0) = 0, theta'(L) = 0.
For a linear law M = B kappa this is B theta'' = -q (L - s) cos(theta) (Frisch-Fay, Flexible
Bars, 1962, ch. 3; the small-deflection limit is the tip deflection q L^4 / (8 B)).

For any monotonic law, ``heavy_cantilever_law`` solves the first-order form with the moment as
unknown, dM/ds = -q (L - s) cos(theta), theta' = kappa(M) (``MomentCurvature`` inverts the law),
optionally shear-flexible; ``peirce_overhang`` is Peirce's cantilever test (J. Textile Inst. 21
(1930) T377; ASTM D1388) on it.
"""

from __future__ import annotations

import numbers

import numpy as np
from scipy.integrate import cumulative_trapezoid, solve_bvp
from scipy.optimize import brentq


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


def euler_cantilever(
    length: float, bending_stiffness: float, load: float | None = None, shortening=None
) -> dict:
    """The post-buckled Euler column clamped at one end, free at the other (the elastica of a
    dead axial end load P; Timoshenko & Gere, Theory of Elastic Stability, 2nd ed. (1961)
    §2.7), given the load or the end shortening.

    With k = sin(alpha / 2) (alpha the end's slope) and K(k), E(k) the complete elliptic
    integrals of the first and second kinds, L sqrt(P / EI) = K(k): P / P_cr = (2 K / pi)^2
    with P_cr = pi^2 EI / (4 L^2); the free end moves 2 k L / K sideways and lies
    L (2 E / K - 1) from the clamp along the load.

    length : L, mm; bending_stiffness : EI, N mm^2; load : P, N (above P_cr); shortening :
    L minus the free end's distance from the clamp along the load, mm (in (0, 2 L)): give one.
    Returns load, critical_load, modulus (k), tip_lateral, tip_axial (the end's distance from
    the clamp along the load), mm and N.
    """
    from scipy.special import ellipe, ellipk  # modulus squared m = k^2

    critical = np.pi**2 * bending_stiffness / (4.0 * length**2)
    if (load is None) == (shortening is None):
        raise ValueError("euler_cantilever takes either load or shortening")
    if load is not None:
        if not load > critical:
            raise ValueError(f"load {load!r} N must exceed the Euler load {critical:.6g} N")
        wanted = np.pi / 2.0 * np.sqrt(load / critical)  # K(k)
        modulus = brentq(lambda k: ellipk(k * k) - wanted, 0.0, 1.0 - 1e-15)
    else:
        if not 0.0 < shortening < 2.0 * length:
            raise ValueError(f"shortening {shortening!r} mm must lie in (0, 2 L = {2 * length})")
        ratio = 1.0 - shortening / length
        modulus = brentq(
            lambda k: 2.0 * ellipe(k * k) / ellipk(k * k) - 1.0 - ratio, 1e-12, 1.0 - 1e-15
        )
    first, second = ellipk(modulus**2), ellipe(modulus**2)
    return {
        "load": critical * (2.0 * first / np.pi) ** 2,
        "critical_load": critical,
        "modulus": modulus,
        "tip_lateral": 2.0 * modulus * length / first,
        "tip_axial": length * (2.0 * second / first - 1.0),
    }


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


# ---------------------------------------------------------------------------------------------
# Non-linear bending laws: the heavy cantilever with M(kappa), and Peirce's cantilever test.
# ---------------------------------------------------------------------------------------------

#: Peirce's chord angle (deg): the overhang at which the chord from the clamp to the tip makes
#: this angle below the horizontal (Peirce 1930; ASTM D1388, the 41.5 deg incline).
PEIRCE_ANGLE_DEG = 41.5


class MomentCurvature:
    """A monotonic bending law M(kappa) per unit width with its inverse kappa(M).

    Build it with :meth:`of` from a ``materials`` Law (a ``BendingLaw``), a number B (the
    linear law M = B kappa), or a pair of callables (moment, stiffness) of the curvature.

    Parameters
    ----------
    moment : callable
        M(kappa): curvature array (any shape, 1/mm) -> moment per unit width (N mm/mm = N),
        strictly increasing.
    stiffness : callable
        dM/dkappa (kappa), same shapes, N mm, > 0.
    knots : tuple of two numpy.ndarray, optional
        (kappa_k, M_k), shape (k,) each, of a piecewise-linear law extrapolated linearly
        beyond its ends: it is then inverted exactly, segment by segment. None: the inverse
        is found by a vectorised Newton iteration safeguarded by bisection.
    description : str
        How the law prints.
    """

    def __init__(self, moment, stiffness, knots=None, description: str = "M(kappa)") -> None:
        self.moment, self.stiffness = moment, stiffness
        self.description = description
        self._knots = None
        if knots is not None:
            kx, ky = (np.asarray(k, dtype=float) for k in knots)
            if np.any(np.diff(ky) <= 0.0):
                raise ValueError(
                    f"{description}: a piecewise-linear bending law needs strictly increasing "
                    f"moments to be inverted (a flat segment has no curvature for its moment), "
                    f"got {ky}"
                )
            left = (kx[1] - kx[0]) / (ky[1] - ky[0])
            right = (kx[-1] - kx[-2]) / (ky[-1] - ky[-2])
            self._knots = (kx, ky, left, right)

    @classmethod
    def of(cls, law) -> MomentCurvature:
        """The law as a MomentCurvature.

        Parameters
        ----------
        law : materials Law, float, (callable, callable) or MomentCurvature
            A ``BendingLaw`` (polynomial or piecewise linear), a linear stiffness B (N mm,
            > 0), or a pair (M(kappa), dM/dkappa(kappa)) of vectorised callables.

        Returns
        -------
        MomentCurvature

        Raises
        ------
        ValueError
            A non-positive stiffness, a law that is zero on one side (tension-only), or
            something that is none of the above.
        """
        if isinstance(law, MomentCurvature):
            return law
        if isinstance(law, (int, float)) and not isinstance(law, bool):
            stiffness = float(law)
            if not (np.isfinite(stiffness) and stiffness > 0.0):
                raise ValueError(f"a linear bending stiffness must be > 0 (N mm), got {law!r}")
            return cls(
                lambda k: stiffness * np.asarray(k, dtype=float),
                lambda k: np.full(np.shape(k), stiffness),
                description=f"M = {stiffness:g} kappa",
            )
        if hasattr(law, "value") and hasattr(law, "slope"):
            if not getattr(law, "compression", True):
                raise ValueError(f"{law!r} is zero for negative arguments: not a bending law")
            knots = getattr(law, "knots", None)
            return cls(law.value, law.slope, knots=knots, description=repr(law))
        if isinstance(law, tuple) and len(law) == 2 and all(callable(f) for f in law):
            return cls(law[0], law[1], description="M(kappa) from callables")
        raise ValueError(
            "the bending law must be a materials Law, a stiffness (N mm) or a pair of callables "
            f"(moment, stiffness) of the curvature, got {law!r}"
        )

    def curvature(self, moment: np.ndarray) -> np.ndarray:
        """The inverse of the law: kappa with M(kappa) = moment, elementwise.

        Parameters
        ----------
        moment : array_like
            Moments per unit width, N (any shape).

        Returns
        -------
        numpy.ndarray
            Curvatures, 1/mm, same shape.
        """
        m = np.asarray(moment, dtype=float)
        if self._knots is not None:
            kx, ky, left, right = self._knots
            # Each piece is linear, so interpolating kappa over M is its exact inverse.
            kappa = np.interp(m, ky, kx)
            kappa = np.where(m < ky[0], kx[0] + left * (m - ky[0]), kappa)
            return np.where(m > ky[-1], kx[-1] + right * (m - ky[-1]), kappa)
        return self._newton_inverse(m)

    def _newton_inverse(self, m: np.ndarray) -> np.ndarray:
        """Safeguarded Newton: a bracket [lo, hi] with M(lo) <= m <= M(hi) grown from the
        initial slope, Newton steps that stay inside it, bisection otherwise."""
        flat = m.ravel()
        slope0 = float(np.asarray(self.stiffness(np.zeros(1)))[0])
        if not slope0 > 0.0:
            raise ValueError(f"{self.description}: the stiffness at zero must be > 0")
        width = np.maximum(np.abs(flat) / slope0, 1e-300)
        lo, hi = -width, width.copy()
        for _ in range(200):  # doubling: a softening law needs a wider bracket than m / B0
            low_short = self.moment(lo) > flat
            high_short = self.moment(hi) < flat
            if not (low_short.any() or high_short.any()):
                break
            lo = np.where(low_short, 2.0 * lo, lo)
            hi = np.where(high_short, 2.0 * hi, hi)
        else:
            raise ValueError(f"{self.description}: no curvature reaches the moments {flat}")
        kappa = np.clip(flat / slope0, lo, hi)
        scale = np.maximum(np.abs(hi - lo), 1e-300)
        for _ in range(200):
            residual = self.moment(kappa) - flat
            lo = np.where(residual <= 0.0, kappa, lo)
            hi = np.where(residual >= 0.0, kappa, hi)
            with np.errstate(divide="ignore", invalid="ignore"):
                step = kappa - residual / self.stiffness(kappa)
            inside = np.isfinite(step) & (step > lo) & (step < hi)
            new = np.where(inside, step, 0.5 * (lo + hi))
            done = np.abs(new - kappa) <= 1e-15 * scale + 4e-16 * np.abs(new)
            kappa = new
            if done.all():
                break
        return kappa.reshape(m.shape)

    def __repr__(self) -> str:
        return f"MomentCurvature({self.description})"


def _small_deflection(law: MomentCurvature, length: float, weight: float, t: np.ndarray):
    """(theta, m, xi, zeta) on t = s / L in [0, 1] of the small-deflection solution with the
    law: M = q (L - s)^2 / 2, theta = integral of kappa(M), x = s, z = -integral of theta."""
    m = 0.5 * (1.0 - t) ** 2
    theta = length * cumulative_trapezoid(law.curvature(weight * length**2 * m), t, initial=0.0)
    theta = np.minimum(theta, 0.45 * np.pi)
    return np.vstack([theta, m, t, -cumulative_trapezoid(np.sin(theta), t, initial=0.0)])


def _heavy_bvp(law: MomentCurvature, length: float, weight: float, shear: float, guess, tol):
    """solve_bvp on t = s / L of y = (theta, m = M / (q L^2), xi = x / L, zeta = z / L):

        theta' = L kappa(q L^2 m),  xi' = cos(theta) - gamma sin(theta),
        zeta' = -sin(theta) - gamma cos(theta),  m' = -(1 - t) xi',
        theta(0) = 0, m(1) = 0, xi(0) = 0, zeta(0) = 0,

    gamma = g (1 - t) cos(theta) the transverse shear strain, g = q L / S (0: shear rigid).
    ``guess``: (4, n) on linspace(0, 1, n). Returns the scipy solution."""
    load = weight * length**2
    g = weight * length / shear if shear else 0.0

    def rhs(t, y):
        theta, m = y[0], y[1]
        c, s = np.cos(theta), np.sin(theta)
        gamma = g * (1.0 - t) * c
        dx = c - gamma * s
        return np.vstack([length * law.curvature(load * m), -(1.0 - t) * dx, dx, -s - gamma * c])

    def jac(t, y):
        theta, m = y[0], y[1]
        d = np.zeros((4, 4, t.size))
        # d kappa / d M = 1 / (dM / d kappa) at the curvature the moment gives.
        d[0, 1] = length * load / law.stiffness(law.curvature(load * m))
        d[2, 0] = -np.sin(theta) - g * (1.0 - t) * np.cos(2.0 * theta)
        d[1, 0] = -(1.0 - t) * d[2, 0]
        d[3, 0] = -np.cos(theta) + g * (1.0 - t) * np.sin(2.0 * theta)
        return d

    def bc(ya, yb):
        return np.array([ya[0], yb[1], ya[2], ya[3]])

    def bc_jac(ya, yb):
        a, b = np.zeros((4, 4)), np.zeros((4, 4))
        a[0, 0] = b[1, 1] = a[2, 2] = a[3, 3] = 1.0
        return a, b

    t = np.linspace(0.0, 1.0, guess.shape[1])
    return solve_bvp(rhs, bc, t, guess, fun_jac=jac, bc_jac=bc_jac, tol=tol, max_nodes=200000)


# solve_bvp's tolerance of ``heavy_cantilever_law`` and of Peirce's test (see ``tol`` there).
HEAVY_TOLERANCE = 1e-8


def heavy_cantilever_law(
    length: float,
    weight: float,
    law,
    points: int = 401,
    tol: float = HEAVY_TOLERANCE,
    shear_stiffness: float | None = None,
) -> dict:
    """Shape of a heavy inextensible cantilever with a non-linear bending law M(kappa).

    The strip is clamped horizontally at s = 0 and free at s = L; with theta(s) the downward
    slope and M(s) the bending moment per unit width,

        dM/ds = -q (L - s) cos(theta),   dtheta/ds = kappa(M),   theta(0) = 0,  M(L) = 0,

    kappa the inverse of the law (``MomentCurvature.curvature``: exact per segment for a
    piecewise-linear law, safeguarded Newton otherwise), and x' = cos(theta),
    z' = -sin(theta) from x(0) = z(0) = 0, all solved together by scipy's ``solve_bvp`` on
    s / L (so the shape is as accurate as the slope, not limited by a quadrature). The first
    guess is the small-deflection solution with the law (M = q (L - s)^2 / 2); when that does
    not converge, the load is raised in steps from the solution of a small fraction of it,
    each solution the guess of the next (continuation).

    Parameters
    ----------
    length : float
        L, mm.
    weight : float
        q, N/mm^2: weight per unit length per unit width (rho_A g).
    law : materials Law, float, (callable, callable) or MomentCurvature
        The bending law M(kappa), N (N mm/mm) against 1/mm, strictly increasing (see
        ``MomentCurvature.of``).
    points : int, optional
        Stations of the returned arrays, equally spaced in s.
    tol : float, optional
        ``solve_bvp``'s tolerance on the relative collocation residuals. A knee of a
        piecewise-linear law is a jump of theta'' that the collocation resolves within its
        node budget down to about 1e-8, not 1e-10; at 1e-8 the tip agrees with a shooting
        solution that stops at the knee to about 1e-10 (tests/test_nonlinear_bending.py).
    shear_stiffness : float, optional
        S, N/mm per unit width: a shear-flexible strip (Reissner's beam, the reference of a
        Mindlin section with that transverse shear stiffness). The sections turn by theta,
        the centre line leans from them by gamma = Q / S, Q = q (L - s) cos(theta) the
        shear force, so x' = cos(theta) - gamma sin(theta), z' = -sin(theta) -
        gamma cos(theta) and dM/ds = -q (L - s) x'. None: shear rigid (gamma = 0).

    Returns
    -------
    dict
        s, theta (rad, downward slope), moment (N per unit width), curvature (1/mm), x, z
        (mm, z <= 0): arrays of shape (points,); tip_deflection (mm, positive down), tip_x
        (mm), tip_slope (rad), root_moment (N), chord_angle (rad: atan(tip_deflection /
        tip_x), the angle of the chord from the clamp to the tip below the horizontal).

    Raises
    ------
    ValueError
        A non-positive length or weight, or an invalid law.
    RuntimeError
        When the solve does not converge even with continuation.
    """
    if not (np.isfinite(length) and length > 0.0):
        raise ValueError(f"length must be > 0 (mm), got {length!r}")
    if not (np.isfinite(weight) and weight > 0.0):
        raise ValueError(f"weight must be > 0 (N/mm^2), got {weight!r}")
    if shear_stiffness is not None and not (np.isfinite(shear_stiffness) and shear_stiffness > 0):
        raise ValueError(f"shear_stiffness must be > 0 (N/mm) or None, got {shear_stiffness!r}")
    response = MomentCurvature.of(law)
    solution = _heavy_solution(length, weight, response, shear_stiffness or 0.0, tol)
    return _sampled(solution, length, weight, response, points)


def _heavy_solution(length: float, weight: float, response: MomentCurvature, shear: float, tol):
    """``heavy_cantilever_law``'s scipy solution on t = s / L (``_heavy_bvp``): from the
    small-deflection guess, else by continuation in the load; a RuntimeError when neither
    converges."""
    t = np.linspace(0.0, 1.0, 201)
    start = _small_deflection(response, length, weight, t)
    solution = _heavy_bvp(response, length, weight, shear, start, tol)
    steps = 4
    while not solution.success and steps <= 64:
        # Continuation in the load from the linear solution of the initial slope at 1/steps
        # of it, where the strip barely bends.
        linear = MomentCurvature.of(float(response.stiffness(np.zeros(1))[0]))
        start = _small_deflection(linear, length, weight / steps, t)
        solution = _heavy_bvp(linear, length, weight / steps, shear, start, tol)
        for k in range(1, steps + 1):
            if not solution.success:
                break
            guess = solution.sol(t)
            solution = _heavy_bvp(response, length, weight * k / steps, shear, guess, tol)
        steps *= 4
    if not solution.success:
        raise RuntimeError(
            f"heavy cantilever with {response!r} did not converge: {solution.message}"
        )
    return solution


def _sampled(solution, length: float, weight: float, response: MomentCurvature, points: int):
    """``heavy_cantilever_law``'s dict from the scipy ``solution`` at ``points`` stations."""
    s = np.linspace(0.0, length, points)
    theta, m, xi, zeta = solution.sol(s / length)
    moment = weight * length**2 * m
    tip_deflection, tip_x = -length * zeta[-1], length * xi[-1]
    return {
        "s": s,
        "theta": theta,
        "moment": moment,
        "curvature": response.curvature(moment),
        "x": length * xi,
        "z": length * zeta,
        "tip_deflection": float(tip_deflection),
        "tip_x": float(tip_x),
        "tip_slope": float(theta[-1]),
        "root_moment": float(moment[0]),
        "chord_angle": float(np.arctan2(tip_deflection, tip_x)),
    }


def peirce_bending_length_ratio(angle_deg: float = PEIRCE_ANGLE_DEG) -> float:
    """Peirce's approximate relation c / l = (cos(theta / 2) / (8 tan theta))^(1/3).

    Peirce, J. Textile Inst. 21 (1930) T377: a linear strip of bending length
    c = (B / q)^(1/3) and overhang l has its chord at theta below the horizontal; at
    theta = 41.5 deg, c / l = 0.509, which ASTM D1388 rounds to c = l / 2.

    Parameters
    ----------
    angle_deg : float, optional
        The chord angle theta, deg.

    Returns
    -------
    float
        c / l (dimensionless).
    """
    theta = np.radians(angle_deg)
    return float((np.cos(theta / 2.0) / (8.0 * np.tan(theta))) ** (1.0 / 3.0))


def peirce_overhang(
    weight: float,
    law,
    angle_deg: float = PEIRCE_ANGLE_DEG,
    xtol: float = 1e-9,
) -> dict:
    """Peirce's cantilever test on the heavy elastica: the overhang whose chord makes
    ``angle_deg`` below the horizontal, and the stiffness the test would report.

    The chord angle atan(tip_deflection / tip_x) of ``heavy_cantilever_law`` grows with the
    overhang l; brentq finds the l at which it is ``angle_deg`` (41.5 deg: Peirce 1930, ASTM
    D1388). The test reports the bending length c = l / 2 and the flexural rigidity
    B_app = q c^3, exact for a linear law only to the accuracy of c = l / 2 (see
    ``peirce_bending_length_ratio``); for a softening law B_app lies between its final and
    initial slopes.

    Parameters
    ----------
    weight : float
        q, N/mm^2 (rho_A g).
    law : materials Law, float, (callable, callable) or MomentCurvature
        The bending law (see ``MomentCurvature.of``).
    angle_deg : float, optional
        The chord angle, deg, in (0, 90).
    xtol : float, optional
        Absolute tolerance of brentq on l, mm.

    Returns
    -------
    dict
        overhang (l, mm), bending_length (c = l / 2, mm), apparent_stiffness (B_app = q c^3,
        N mm per unit width), chord_angle (rad, at l), and solution (the
        ``heavy_cantilever_law`` dict at l).
    """
    if not 0.0 < angle_deg < 90.0:
        raise ValueError(f"angle_deg must be in (0, 90), got {angle_deg!r}")
    # (checked here: the kept solves below do not pass through heavy_cantilever_law's checks)
    if not (isinstance(weight, numbers.Real) and np.isfinite(weight) and weight > 0.0):
        raise ValueError(f"weight must be a real number > 0 (N/mm^2), got {weight!r}")
    response = MomentCurvature.of(law)
    target = np.radians(angle_deg)
    # Each overhang's solve kept: the bracket's search asks a point twice, brentq asks the
    # bracket's ends again and returns one of the points it tried, whose solution is then
    # sampled. Solves of about 50 ms are the test's cost: the G986 law's 15 -> 11, the linear
    # law's 9 -> 5, the same bits (benchmarks/paper_case_cost.py, "References").
    solved: dict[float, object] = {}

    def solution(overhang: float):
        if overhang not in solved:
            solved[overhang] = _heavy_solution(overhang, weight, response, 0.0, HEAVY_TOLERANCE)
        return solved[overhang]

    def miss(overhang: float) -> float:
        return _sampled(solution(overhang), overhang, weight, response, 3)["chord_angle"] - target

    # A first bracket from the linear law of the initial slope (q l^3 / B = 8 at 41.5 deg),
    # then widened: a softening law bends more, so its overhang is shorter.
    b0 = float(response.stiffness(np.zeros(1))[0])
    lo = hi = 2.0 * (b0 / weight) ** (1.0 / 3.0)
    while miss(lo) > 0.0:
        lo *= 0.7
    while miss(hi) < 0.0:
        hi *= 1.3
    overhang = brentq(miss, lo, hi, xtol=xtol, rtol=1e-12)
    shape = _sampled(solution(overhang), overhang, weight, response, 401)
    c = overhang / 2.0
    return {
        "overhang": overhang,
        "bending_length": c,
        "apparent_stiffness": weight * c**3,
        "chord_angle": shape["chord_angle"],
        "solution": shape,
    }


def buckled_cantilever_column(length: float, load: float, bending_stiffness: float) -> dict:
    """The elastica of an inextensible column clamped at s = 0 and free at s = L under a dead
    axial tip load P above its critical load Pcr = pi^2 EI / (4 L^2) (Timoshenko and Gere,
    Theory of Elastic Stability, 2nd ed. 1961, §2.7): with k = sin(alpha / 2), alpha the tip's
    turn, L sqrt(P / EI) = K(k), so sqrt(P / Pcr) = 2 K(k) / pi; the tip moves across by
    delta = 2 k L / K(k) and stands at x = L (2 E(k) / K(k) - 1) along the load's line (K, E
    the complete elliptic integrals of modulus k).

    length : L, mm; load : P, N (> Pcr); bending_stiffness : EI, N mm^2.
    Returns alpha (rad), lateral (delta, mm) and tip_x (mm).
    """
    from scipy.special import ellipe, ellipk

    critical = np.pi**2 * bending_stiffness / (4.0 * length**2)
    if not load > critical:
        raise ValueError(f"load must exceed the critical load {critical:.6g} N, got {load!r}")
    target = np.sqrt(load / critical)
    # scipy's ellipk and ellipe take the parameter m = k^2.
    k = brentq(lambda k: 2.0 / np.pi * ellipk(k**2) - target, 1e-12, 1.0 - 1e-15, xtol=1e-15)
    quarter = ellipk(k**2)
    return {
        "alpha": 2.0 * np.arcsin(k),
        "lateral": 2.0 * k * length / quarter,
        "tip_x": length * (2.0 * ellipe(k**2) / quarter - 1.0),
    }
