"""One-dimensional constitutive laws y(x) as pure functions over arrays.

A law gives the generalised stress ``value(x)``, its tangent ``slope(x)`` and the stored energy
``energy(x)`` = integral of y from 0 to x, all elementwise over numpy arrays of any shape. Three
families use it (docs/theory.md §2-4, units per unit initial width or area):

* ``TensionLaw``: fibre tension T(eps), N/mm, against the logarithmic fibre strain;
* ``ShearLaw``: in-plane shear moment M_s(gamma), N/mm (per unit initial area), against the
  shear angle in rad; odd in gamma;
* ``BendingLaw``: bending moment M(chi), N (N mm/mm), against the curvature in 1/mm; odd in chi.

A law is either an odd polynomial (linear is its first term) or a piecewise-linear curve with
linear extrapolation beyond its last points. Laws are immutable; constructors validate inputs.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from femcore.checks import as_flag, as_number, as_reals

__all__ = ["BendingLaw", "Law", "ShearLaw", "TensionLaw"]


def _finite(value: Any, name: str) -> float:
    number = as_number(value, name, "a number")
    if not np.isfinite(number):
        raise ValueError(f"{name} must be finite, got {value!r}")
    return number


#: How far (relative to the table's largest |x| or |y|) a table given over both signs of an
#: odd law may be from odd: round-off of values typed or computed as -y(x), no more. A table
#: computed in single precision (float32, unit round-off 2**-24 = 6e-8, a few operations per
#: value) is odd only to some 1e-7 of its largest |y|; 1e-6 admits that (about eight float32
#: ulps) and is still four orders below the least asymmetry a law would mean (a few percent).
ODD_TOLERANCE = 1e-6


def _check_odd(x: np.ndarray, y: np.ndarray, what: str) -> None:
    """Refuse a table of an odd law given over both signs that is not odd: its range not
    symmetric, or y(-x_k) != -y_k at a knot x_k (within ODD_TOLERANCE). Such a law would
    make the answer depend on the sign convention of the strain (for the shell's shear angle
    and curvature, on the cells' winding and the fibres' orientation)."""
    scale_x, scale_y = float(np.abs(x).max()), float(np.abs(y).max())
    mirrored = -np.interp(-x, x, y)
    if abs(x[0] + x[-1]) > ODD_TOLERANCE * scale_x or np.any(
        np.abs(mirrored - y) > ODD_TOLERANCE * scale_y
    ):
        raise ValueError(
            f"{what} table given over both signs is not odd (y(-x) = -y(x) within "
            f"{ODD_TOLERANCE:g} of the largest |x| and |y|; got x from {x[0]} to {x[-1]}, "
            f"y {y}): the law is odd in its strain, whose sign is a convention (the cells' "
            f"winding, the fibres' orientation); give the table for x >= 0 only, it is "
            f"mirrored to x < 0"
        )


def _table(x: ArrayLike, y: ArrayLike, what: str, odd: bool) -> tuple[np.ndarray, np.ndarray]:
    """Validated knots of a piecewise-linear law; with ``odd`` a table given for x >= 0 is
    mirrored to negative x, and one given over both signs must be odd (``_check_odd``)."""
    x = as_reals(x, f"{what} table abscissae", "a sequence of numbers")
    y = as_reals(y, f"{what} table values", "a sequence of numbers")
    if x.ndim > 1 or y.ndim > 1:  # a nested list is a typo, not a table to flatten
        raise ValueError(
            f"{what} table needs two flat sequences of numbers, got arrays of shapes "
            f"{x.shape} and {y.shape}"
        )
    x, y = x.ravel(), y.ravel()
    if x.size != y.size or x.size < 2:
        raise ValueError(
            f"{what} table needs two sequences of equal length >= 2, got {x.size} and {y.size}"
        )
    if not (np.isfinite(x).all() and np.isfinite(y).all()):
        raise ValueError(f"{what} table has a non-finite entry")
    if np.any(np.diff(x) <= 0):
        raise ValueError(f"{what} table: the abscissae must be strictly increasing, got {x}")
    if np.any(np.diff(y) < 0):
        raise ValueError(
            f"{what} table: the values must be non-decreasing (a stable, monotonic law), got {y}"
        )
    if odd and x[0] >= 0.0:
        if x[0] != 0.0:
            x, y = np.concatenate(([0.0], x)), np.concatenate(([0.0], y))
        x = np.concatenate((-x[:0:-1], x))
        y = np.concatenate((-y[:0:-1], y))
    if not x[0] <= 0.0 <= x[-1]:
        raise ValueError(f"{what} table must span 0 (from {x[0]} to {x[-1]})")
    if odd:
        _check_odd(x, y, what)
    at_zero = float(np.interp(0.0, x, y))
    if abs(at_zero) > 1e-12 * max(1.0, float(np.abs(y).max())):
        raise ValueError(f"{what} table must give 0 at 0 (no stress in the reference state)")
    if np.all(np.diff(y) == 0):
        raise ValueError(f"{what} table has zero stiffness everywhere")
    return x, y


@dataclass(frozen=True, eq=False)
class Law:
    """A 1-D law: odd polynomial ``sum c_k x^k`` (k = 1, 3, 5, ...) or piecewise linear.

    Build laws with the family constructors (``TensionLaw.linear`` ...), not directly. The
    units of x and y are those of the family (see the module docstring).

    Parameters
    ----------
    family : str
        "TensionLaw", "ShearLaw" or "BendingLaw".
    description : str
        How the law prints, e.g. "TensionLaw.linear(stiffness C=1200)".
    odd_coefficients : tuple of float, optional
        (c1, c3, c5, ...) of an odd polynomial; None for a piecewise-linear law.
    knots : tuple of two numpy.ndarray, shape (k,) each, optional
        Abscissae (strictly increasing, spanning 0) and values of a piecewise-linear law;
        None for a polynomial.
    compression : bool
        False for a tension-only law (zero for x < 0).
    """

    family: str
    description: str
    odd_coefficients: tuple[float, ...] | None = None
    knots: tuple[np.ndarray, np.ndarray] | None = None
    compression: bool = True

    # ----------------------------------------------------------------- evaluation
    def value(self, x: ArrayLike) -> np.ndarray:
        """The generalised stress y(x), elementwise.

        Parameters
        ----------
        x : array_like
            Strain measure (any shape), in the family's unit.

        Returns
        -------
        numpy.ndarray
            y(x), same shape as ``x``, in the family's unit.
        """
        x = np.asarray(x, dtype=float)
        if self.odd_coefficients is not None:
            y = self._poly(x, 0)
        else:
            kx, ky = self._knots()
            y = np.interp(x, kx, ky)
            left, right = self._end_slopes()
            y = np.where(x < kx[0], ky[0] + left * (x - kx[0]), y)
            y = np.where(x > kx[-1], ky[-1] + right * (x - kx[-1]), y)
        return y if self.compression else np.where(x < 0.0, 0.0, y)

    def slope(self, x: ArrayLike) -> np.ndarray:
        """The tangent dy/dx (x), elementwise (right derivative at the knots).

        Parameters
        ----------
        x : array_like
            Strain measure (any shape).

        Returns
        -------
        numpy.ndarray
            dy/dx, same shape as ``x`` (unit of y per unit of x).
        """
        x = np.asarray(x, dtype=float)
        if self.odd_coefficients is not None:
            s = self._poly(x, 1)
        else:
            kx, ky = self._knots()
            segment = np.diff(ky) / np.diff(kx)
            i = np.clip(np.searchsorted(kx, x, side="right") - 1, 0, len(segment) - 1)
            s = segment[i]
        return s if self.compression else np.where(x < 0.0, 0.0, s)

    def energy(self, x: ArrayLike) -> np.ndarray:
        """Stored energy integral_0^x y dx, elementwise (>= 0 for a monotonic law).

        Parameters
        ----------
        x : array_like
            Strain measure (any shape).

        Returns
        -------
        numpy.ndarray
            The energy, same shape as ``x`` (unit of y times unit of x, e.g. N/mm for tension
            against a dimensionless strain: energy per unit initial area).
        """
        x = np.asarray(x, dtype=float)
        if self.odd_coefficients is not None:
            e = self._poly(x, -1)
        else:
            # y is linear on each piece, so the trapezoid rule from the nearest knot is exact.
            kx, ky = self._knots()
            integrals = self.knot_integrals()
            cumulative, e_zero = integrals[:-1], integrals[-1]
            i = np.clip(np.searchsorted(kx, x, side="right") - 1, 0, len(kx) - 1)
            e_raw = cumulative[i] + (x - kx[i]) * (ky[i] + self.value(x)) / 2.0
            e = e_raw - e_zero
        return e if self.compression else np.where(x < 0.0, 0.0, e)

    def max_slope(self) -> float:
        """Largest tangent stiffness, for stable time steps.

        Returns
        -------
        float
            max dy/dx over |x| <= 1 for a polynomial (strains, angles in rad and curvatures in
            1/mm all stay below that), over the tabulated pieces for a table; unit of y per
            unit of x.
        """
        if self.odd_coefficients is not None:
            # Over |x| <= 1 (strains, angles in rad, curvatures in 1/mm all stay below that).
            probe = np.linspace(0.0, 1.0, 201)
            return float(np.max(self._poly(probe, 1)))
        kx, ky = self._knots()
        return float(np.max(np.diff(ky) / np.diff(kx)))

    def scaled(self, factor: float) -> Law:
        """The law whose values, slopes and energies are ``factor`` times this one's.

        One ply of a stack of N equal plies carries 1/N of the stack's tension, shear and
        bending (``Fabric.plies``): its laws are the stack's scaled by 1/N.

        Parameters
        ----------
        factor : float
            The scale, > 0 (dimensionless).

        Returns
        -------
        Law
            Same family, same abscissae and same tension-only flag; the polynomial
            coefficients or the tabulated values times ``factor``.

        Raises
        ------
        ValueError
            A factor that is not a finite number > 0.
        """
        if isinstance(factor, bool) or not isinstance(factor, (int, float, np.number)):
            raise ValueError(f"Law.scaled: factor must be a number > 0, got {factor!r}")
        scale = _finite(factor, "Law.scaled: factor")
        if scale <= 0.0:
            raise ValueError(f"Law.scaled: factor must be > 0, got {factor!r}")
        description = f"{scale:g} x {self.description}"
        if self.odd_coefficients is not None:
            coefficients = tuple(scale * c for c in self.odd_coefficients)
            return Law(self.family, description, coefficients, compression=self.compression)
        kx, ky = self._knots()
        return Law(
            self.family, description, knots=(kx.copy(), scale * ky), compression=self.compression
        )

    def knot_integrals(self) -> np.ndarray:
        """A table law's integrals of y from its first knot to each knot, and to 0 last
        ((knots + 1,), unit of y times unit of x): the sums ``energy`` starts from, which the
        compiled fibrous kernels table once (elements/fibrous/packed_laws.py)."""
        kx, ky = self._knots()
        cumulative = np.concatenate(([0.0], np.cumsum(np.diff(kx) * (ky[1:] + ky[:-1]) / 2)))
        j = np.clip(np.searchsorted(kx, 0.0, side="right") - 1, 0, len(kx) - 1)
        return np.append(cumulative, cumulative[j] + (0.0 - kx[j]) * ky[j] / 2.0)

    def _knots(self) -> tuple[np.ndarray, np.ndarray]:
        if self.knots is None:
            raise ValueError(f"{self.description} has neither coefficients nor knots")
        return self.knots

    def _end_slopes(self) -> tuple[float, float]:
        kx, ky = self._knots()
        return (ky[1] - ky[0]) / (kx[1] - kx[0]), (ky[-1] - ky[-2]) / (kx[-1] - kx[-2])

    def _poly(self, x: np.ndarray, derivative: int) -> np.ndarray:
        """sum c_k x^k (derivative 0), its slope (1), or its integral from 0 (-1)."""
        out = np.zeros_like(x)
        for i, c in enumerate(self.odd_coefficients or ()):
            k = 2 * i + 1
            if derivative == 0:
                out = out + c * x**k
            elif derivative == 1:
                out = out + k * c * x ** (k - 1)
            else:
                out = out + c * x ** (k + 1) / (k + 1)
        return out

    def __repr__(self) -> str:
        return self.description


def _odd_polynomial(
    family: str,
    coefficients: Sequence[float],
    names: Sequence[str],
    unit: str,
    allow_zero: bool = False,
) -> Law:
    values = tuple(_finite(c, n) for c, n in zip(coefficients, names))
    if values[0] < 0 or (values[0] == 0 and not allow_zero):
        relation = ">= 0" if allow_zero else "> 0"
        raise ValueError(f"{family}: {names[0]} must be {relation} ({unit}), got {values[0]!r}")
    if len(values) > 1:
        # A stable law: dy/dx > 0 on |x| <= 1 (odd terms with negative coefficients may soften).
        probe = np.linspace(0.0, 1.0, 201)
        slope = np.zeros_like(probe)
        for i, c in enumerate(values):
            slope += (2 * i + 1) * c * probe ** (2 * i)
        if np.any(slope[1:] <= 0):
            bad = probe[1:][slope[1:] <= 0][0]
            raise ValueError(
                f"{family}: the slope {' + '.join(names)} terms becomes <= 0 at x = {bad:.3g}; "
                "the law must stiffen or stay monotonic"
            )
    description = f"{family}(" + ", ".join(f"{n}={v:g}" for n, v in zip(names, values)) + ")"
    return Law(family.split(".")[0], description, odd_coefficients=values)


class TensionLaw:
    """Fibre tension per unit initial width T(eps), N/mm, of the logarithmic strain."""

    @staticmethod
    def linear(stiffness: float, tension_only: bool = False) -> Law:
        """Linear tension T = C eps.

        Parameters
        ----------
        stiffness : float
            C, N/mm per unit width, > 0 (Bai Table 1: 1200, Table 2: 2300).
        tension_only : bool, optional
            Fibres buckle in compression and carry nothing (T = 0 for eps < 0).

        Returns
        -------
        Law
            The tension law.

        Raises
        ------
        ValueError
            C not a finite number > 0.
        """
        law = _odd_polynomial("TensionLaw.linear", (stiffness,), ("stiffness C",), "N/mm")
        compression = not as_flag(tension_only, "tension_only")
        return Law(law.family, law.description, law.odd_coefficients, compression=compression)

    @staticmethod
    def table(strain: ArrayLike, tension: ArrayLike, tension_only: bool = False) -> Law:
        """Piecewise-linear T(eps) through tabulated points, extrapolated linearly.

        Parameters
        ----------
        strain : array_like, shape (k,)
            Logarithmic strains (dimensionless), strictly increasing, k >= 2; the table must
            contain 0 -> 0 (or span it).
        tension : array_like, shape (k,)
            Tensions, N/mm per unit width, non-decreasing.
        tension_only : bool, optional
            T = 0 for eps < 0.

        Returns
        -------
        Law
            The tension law.

        Raises
        ------
        ValueError
            Non-numeric, non-finite, non-monotonic or too short tables, a table not through
            0 -> 0, or one with zero stiffness everywhere.
        """
        knots = _table(strain, tension, "TensionLaw", odd=False)
        return Law(
            "TensionLaw",
            f"TensionLaw.table({len(knots[0])} points)",
            knots=knots,
            compression=not as_flag(tension_only, "tension_only"),
        )


class ShearLaw:
    """In-plane shear moment per unit initial area M_s(gamma), N/mm, odd in gamma (rad)."""

    @staticmethod
    def linear(stiffness: float) -> Law:
        """Linear shear M_s = K gamma.

        Parameters
        ----------
        stiffness : float
            K, N/mm (per rad), >= 0; K = 0 leaves shear free.

        Returns
        -------
        Law
            The shear law.

        Raises
        ------
        ValueError
            K not a finite number >= 0.
        """
        return _odd_polynomial("ShearLaw.linear", (stiffness,), ("K",), "N/mm", allow_zero=True)

    @staticmethod
    def polynomial(k1: float, k3: float = 0.0, k5: float = 0.0) -> Law:
        """Odd polynomial shear M_s = K1 gamma + K3 gamma^3 + K5 gamma^5 (Boisse group).

        Parameters
        ----------
        k1, k3, k5 : float
            Coefficients, N/mm with gamma in rad; K1 > 0.

        Returns
        -------
        Law
            The shear law.

        Raises
        ------
        ValueError
            Non-finite coefficients, K1 <= 0, or a slope that becomes <= 0 for
            |gamma| <= 1 rad.
        """
        return _odd_polynomial("ShearLaw.polynomial", (k1, k3, k5), ("K1", "K3", "K5"), "N/mm")

    @staticmethod
    def table(gamma: ArrayLike, moment: ArrayLike) -> Law:
        """Piecewise-linear M_s(gamma) through tabulated points, extrapolated linearly.

        Parameters
        ----------
        gamma : array_like, shape (k,)
            Shear angles, rad, strictly increasing; given for gamma >= 0 they are mirrored to
            negative angles (or give them over both signs: then an odd table, the same
            range and y(-x) = -y(x) within ``ODD_TOLERANCE``).
        moment : array_like, shape (k,)
            Shear moments M_s, N/mm, non-decreasing.

        Returns
        -------
        Law
            The shear law (odd in gamma).

        Raises
        ------
        ValueError
            Invalid tables, as :meth:`TensionLaw.table`; a table over both signs that is
            not odd; an angle of pi/2 or more (degrees given for radians).
        """
        knots = _table(gamma, moment, "ShearLaw", odd=True)
        largest = float(np.abs(knots[0]).max())
        if largest >= 0.5 * np.pi:  # fibres at 90 deg to each other lie flat on each other
            raise ValueError(
                f"ShearLaw table: shear angles are in radians and below pi/2 (90 deg: the "
                f"fibres would lie flat on each other), got up to {largest:g}: degrees? give "
                f"them in radians (x pi / 180)"
            )
        return Law("ShearLaw", f"ShearLaw.table({np.size(gamma)} points)", knots=knots)


class BendingLaw:
    """Bending moment per unit initial width M(chi), N (N mm/mm), odd in chi (1/mm)."""

    @staticmethod
    def linear(stiffness: float) -> Law:
        """Linear bending M = B chi.

        Parameters
        ----------
        stiffness : float
            B, N mm per unit width, > 0 (Bai Table 2: 72 warp, 68 weft).

        Returns
        -------
        Law
            The bending law.

        Raises
        ------
        ValueError
            B not a finite number > 0.
        """
        return _odd_polynomial("BendingLaw.linear", (stiffness,), ("B",), "N mm")

    @staticmethod
    def bilinear(initial: float, final: float, knee: float) -> Law:
        """M = B1 chi for |chi| <= knee, then M = sign(chi) (B1 knee + B2 (|chi| - knee)).

        The continuous reading of Bai Table 1 (docs/theory.md §4.6): B1 = 7.5 N mm, B2 = 0.5 N mm,
        knee = 1e-3 1/mm. The table as printed jumps by 0.0005 N at the knee; this law does not.

        Parameters
        ----------
        initial : float
            B1, N mm per unit width, > 0.
        final : float
            B2, N mm per unit width, > 0.
        knee : float
            Curvature at the change of slope, 1/mm, > 0.

        Returns
        -------
        Law
            The bending law (piecewise linear, odd in chi).

        Raises
        ------
        ValueError
            A non-finite or non-positive argument.
        """
        b1 = _finite(initial, "BendingLaw.bilinear: initial stiffness B1")
        b2 = _finite(final, "BendingLaw.bilinear: final stiffness B2")
        chi_c = _finite(knee, "BendingLaw.bilinear: knee curvature")
        if b1 <= 0 or b2 <= 0 or chi_c <= 0:
            raise ValueError(
                "BendingLaw.bilinear needs B1 > 0, B2 > 0 (N mm) and knee > 0 (1/mm), got "
                f"B1={initial!r}, B2={final!r}, knee={knee!r}"
            )
        x = np.array([-2.0 * chi_c, -chi_c, 0.0, chi_c, 2.0 * chi_c])
        y = np.array(
            [-b1 * chi_c - b2 * chi_c, -b1 * chi_c, 0.0, b1 * chi_c, b1 * chi_c + b2 * chi_c]
        )
        return Law(
            "BendingLaw", f"BendingLaw.bilinear(B1={b1:g}, B2={b2:g}, knee={chi_c:g})", knots=(x, y)
        )

    @staticmethod
    def table(curvature: ArrayLike, moment: ArrayLike) -> Law:
        """Piecewise-linear M(chi) through tabulated points, e.g. a measured cantilever curve.

        Parameters
        ----------
        curvature : array_like, shape (k,)
            Curvatures chi, 1/mm, strictly increasing; given for chi >= 0 they are mirrored to
            negative curvature (or give them over both signs: then an odd table, the same
            range and y(-x) = -y(x) within ``ODD_TOLERANCE``).
        moment : array_like, shape (k,)
            Bending moments M, N (N mm/mm), non-decreasing.

        Returns
        -------
        Law
            The bending law (odd in chi).

        Raises
        ------
        ValueError
            Invalid tables, as :meth:`TensionLaw.table`; a table over both signs that is
            not odd.
        """
        return Law(
            "BendingLaw",
            f"BendingLaw.table({np.size(curvature)} points)",
            knots=_table(curvature, moment, "BendingLaw", odd=True),
        )
