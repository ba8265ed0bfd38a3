"""ElasticShell: plane-stress elasticity with transverse shear for the Mindlin shell
(docs/theory.md §5.2), isotropic or orthotropic in a material axis given by a warp direction."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from femcore.checks import Plausible, as_number, as_reals, check_positive, warn_implausible

if TYPE_CHECKING:  # a type only: materials.fabric needs nothing from here
    from materials.fabric import Fabric

__all__ = ["ElasticShell"]


@dataclass(frozen=True, init=False)
class ElasticShell:
    """Linear elastic shell section (St Venant-Kirchhoff in the lamina frame), isotropic.

    Orthotropic sections: ``ElasticShell.orthotropic(...)``.

    Parameters
    ----------
    E : float
        Young's modulus, N/mm^2 (MPa), > 0.
    nu : float
        Poisson's ratio, in (-1, 0.5).
    thickness : float
        h, mm, > 0.
    density : float
        rho, t/mm^3, > 0.
    G13, G23 : float, optional
        Transverse shear moduli, MPa (default E / (2 (1 + nu))).
    shear_factor : float, optional
        kappa (5/6 for a homogeneous section, the Abaqus value).

    Attributes
    ----------
    plane_stress : numpy.ndarray, shape (3, 3)
        Q in material axes (1 = warp), MPa; used by the element.
    transverse : numpy.ndarray, shape (2,)
        kappa (G13, G23), MPa.
    warp : numpy.ndarray, shape (3,), or None
        Unit material axis 1 (orthotropic sections), None for isotropic ones.
    poisson : float
        nu (isotropic) or nu12 (orthotropic).
    wave_speed : float
        The fastest membrane wave sqrt(max Q_ii / rho), mm/s.

    Raises
    ------
    ValueError
        A non-positive or non-finite modulus, thickness, density or shear factor, or a
        Poisson's ratio outside (-1, 0.5).
    """

    thickness: float
    density: float
    plane_stress: np.ndarray
    transverse: np.ndarray
    shear_factor: float
    warp: np.ndarray | None
    poisson: float

    def __init__(
        self,
        E: float,
        nu: float,
        thickness: float,
        density: float,
        G13: float | None = None,
        G23: float | None = None,
        shear_factor: float = 5 / 6,
    ) -> None:
        E = check_positive(E, "ElasticShell E", "MPa")
        nu = _poisson(nu, "ElasticShell nu")
        g = E / (2 * (1 + nu))
        q = E / (1 - nu**2) * np.array([[1, nu, 0], [nu, 1, 0], [0, 0, (1 - nu) / 2]])
        self._set(
            thickness,
            density,
            q,
            G13 if G13 is not None else g,
            G23 if G23 is not None else g,
            shear_factor,
            None,
            nu,
            ("E", E),
        )

    @classmethod
    def orthotropic(
        cls,
        E1: float,
        E2: float,
        nu12: float,
        G12: float,
        G13: float,
        G23: float,
        thickness: float,
        density: float,
        warp: ArrayLike = (1.0, 0.0, 0.0),
        shear_factor: float = 5 / 6,
    ) -> ElasticShell:
        """Orthotropic lamina section.

        Material axis 1 is the warp direction (projected on each element), 2 the in-plane
        normal to it.

        Parameters
        ----------
        E1, E2 : float
            Young's moduli along 1 and 2, MPa, > 0.
        nu12 : float
            Major Poisson's ratio (nu21 = nu12 E2 / E1), with nu12 nu21 = nu12^2 E2 / E1 < 1
            (the lamina's positive definiteness; not the isotropic bound (-1, 0.5)).
        G12, G13, G23 : float
            In-plane and transverse shear moduli, MPa, > 0.
        thickness : float
            h, mm, > 0.
        density : float
            rho, t/mm^3, > 0.
        warp : array_like, shape (3,), optional
            Material axis 1 in global coordinates (normalised here), default +x.
        shear_factor : float, optional
            kappa (5/6 for a homogeneous section).

        Returns
        -------
        ElasticShell
            The orthotropic section.

        Raises
        ------
        ValueError
            Invalid moduli, Poisson's ratio, thickness, density or warp axis.
        """
        E1 = check_positive(E1, "ElasticShell E1", "MPa")
        E2 = check_positive(E2, "ElasticShell E2", "MPa")
        G12 = check_positive(G12, "ElasticShell G12", "MPa")
        # The lamina's plane-stress stiffness is positive definite (E1, E2, G12 > 0) iff
        # nu12 nu21 = nu12^2 E2 / E1 < 1: |nu12| < sqrt(E1 / E2), not the isotropic (-1, 0.5)
        # (E1 = 10000, E2 = 1000, nu12 = 0.6 is a valid lamina).
        nu12 = as_number(nu12, "ElasticShell nu12", "a number with nu12^2 E2 / E1 < 1")
        nu21 = nu12 * E2 / E1
        if not nu12 * nu21 < 1:
            raise ValueError(
                f"ElasticShell nu12: the lamina is positive definite when nu12 nu21 = nu12^2 "
                f"E2 / E1 < 1, i.e. |nu12| < sqrt(E1 / E2) = {np.sqrt(E1 / E2):.4g}; got "
                f"nu12 = {nu12!r}, nu12^2 E2 / E1 = {nu12 * nu21:.4g}"
            )
        d = 1 - nu12 * nu21
        q = np.array([[E1 / d, nu12 * E2 / d, 0], [nu12 * E2 / d, E2 / d, 0], [0, 0, G12]])
        axis = as_reals(warp, "ElasticShell warp", "a non-zero 3-vector").ravel()
        if axis.shape != (3,) or not np.isfinite(axis).all() or np.linalg.norm(axis) == 0:
            raise ValueError(f"ElasticShell warp must be a non-zero 3-vector, got {warp!r}")
        self = cls.__new__(cls)
        larger = ("E1", E1) if E1 >= E2 else ("E2", E2)  # the modulus the user wrote
        unit = axis / np.linalg.norm(axis)
        self._set(thickness, density, q, G13, G23, shear_factor, unit, nu12, larger, G12)
        return self

    @classmethod
    def equivalent(
        cls, fabric: Fabric, shear_ratio: float = 0.5, warp: ArrayLike = (1.0, 0.0, 0.0)
    ) -> ElasticShell:
        """The Mindlin section that bends like a fabric: Bai's calibration of Abaqus S3.

        A homogeneous section of the fabric's thickness h whose plate bending stiffness
        E h^3 / 12 is the fabric's bending stiffness B per unit width, in each direction:
        E1 = 12 B_warp / h^3 along the warp and E2 = 12
        B_weft / h^3 (the initial slope of a non-linear bending law); nu12 = 0 (fibres do
        not contract each other); G12 = K / h from the initial in-plane shear slope K (so that
        G12 h gamma is the fabric's shear moment); transverse shear G13 = G23 = ``shear_ratio``
        x max(E1, E2), a stated parameter (0.5 is the isotropic value at nu = 0); density
        rho = rho_A / h, so that the mass per area is the fabric's.

        What it cannot match: its membrane stiffness E h = 12 B / h^2 is that of the bending
        calibration, orders of magnitude below the fibres' tension stiffness, and its normals
        stay normal up to the transverse shear. That is the comparison the two kinematics are
        built for (docs/theory.md §5.1).

        Parameters
        ----------
        fabric : materials.Fabric
            Units mm, N, t: B in N mm / mm (N), K in N/mm, h in mm, rho_A in t/mm^2.
        shear_ratio : float, optional
            G13 / E, > 0.
        warp : array_like, shape (3,), optional
            The warp direction, as given to the FibrousShell (default +x).

        Returns
        -------
        ElasticShell
            Orthotropic, E in MPa, rho in t/mm^3.

        Raises
        ------
        ValueError
            Not a Fabric, a non-positive shear ratio, or a law with no stiffness at zero.
        """
        from materials.fabric import Fabric

        if not isinstance(fabric, Fabric):
            raise ValueError(f"ElasticShell.equivalent needs a materials.Fabric, got {fabric!r}")
        ratio = check_positive(shear_ratio, "ElasticShell.equivalent shear_ratio", "-")
        h = fabric.thickness
        slopes = {
            name: float(np.asarray(law.slope(np.array(0.0))))
            for name, law in (
                ("bending", fabric.bending),
                ("bending_weft", fabric.bending_weft),
                ("shear", fabric.shear),
            )
        }
        for name, slope in slopes.items():
            if not slope > 0.0:
                raise ValueError(
                    f"ElasticShell.equivalent: the fabric's {name} law has no stiffness at zero "
                    f"(slope {slope!r}); the calibration takes the initial slope"
                )
        e1 = 12.0 * slopes["bending"] / h**3
        e2 = 12.0 * slopes["bending_weft"] / h**3
        transverse = ratio * max(e1, e2)
        return cls.orthotropic(
            E1=e1,
            E2=e2,
            nu12=0.0,
            G12=slopes["shear"] / h,
            G13=transverse,
            G23=transverse,
            thickness=h,
            density=fabric.areal_density / h,
            warp=warp,
        )

    def _set(
        self,
        thickness: Any,
        density: Any,
        q: np.ndarray,
        g13: Any,
        g23: Any,
        kappa: Any,
        warp: np.ndarray | None,
        nu: float,
        modulus: tuple[str, float],
        g12: float | None = None,
    ) -> None:
        """Set the section's fields; ``modulus`` (name, value) the largest Young's modulus as
        the user gave it (E, E1 or E2, MPa), judged for its units (not an entry of q, E / (1
        - nu^2), which the user never wrote), and so is ``g12`` (MPa), the in-plane shear
        modulus of an orthotropic lamina as the user gave it (None: isotropic, from E)."""
        set_ = object.__setattr__
        set_(self, "thickness", check_positive(thickness, "ElasticShell thickness", "mm"))
        set_(self, "density", check_positive(density, "ElasticShell density", "t/mm^3"))
        g13 = check_positive(g13, "ElasticShell G13", "MPa")
        g23 = check_positive(g23, "ElasticShell G23", "MPa")
        kappa = check_positive(kappa, "ElasticShell shear_factor", "-")
        set_(self, "plane_stress", q)
        # Plausible in either consistent system. In MPa up to 1e9: a metal or a composite in
        # Pa (1e10 to 1e12) is caught, while the classic shell benchmarks in their own
        # consistent units (Scordelis-Lo: 4.32e8 psf) are not; in Pa from 1e5 (a soft rubber)
        # up. Up to 1e-6 t/mm^3 (1e6 kg/m^3): any density in kg/m^3 (1 to 2e4) is caught
        # beside lengths in mm. Up to 0.5 m thick in m.
        # G12 as E, above (5e9 Pa among moduli in MPa is caught), with no lower bound: a
        # calibrated lamina's G12 is its fabric's shear slope over h (ElasticShell.equivalent,
        # elements/plies.py: down to 1e-6 E1), far below any solid's.
        shear = [] if g12 is None else [
            Plausible("ElasticShell modulus G12", g12, ("MPa", 0.0, 1e9), ("Pa", 0.0, 1e15),
                      "a modulus in Pa is 1e6 of it in MPa")
        ]  # fmt: skip
        warn_implausible(
            Plausible(f"ElasticShell modulus {modulus[0]}", modulus[1], ("MPa", 1e-3, 1e9),
                      ("Pa", 1e5, 1e15), "a modulus in Pa is 1e6 of it in MPa"),
            Plausible("ElasticShell density", self.density, ("t/mm^3", 1e-14, 1e-6),
                      ("kg/m^3", 1e-2, 1e6), "a density in kg/m^3 is 1e-12 of it in t/mm^3"),
            Plausible("ElasticShell thickness", self.thickness, ("mm", 0.0, np.inf),
                      ("m", 1e-6, 0.5), "a thickness in mm is 1e3 of it in m"),
            *shear,
        )  # fmt: skip
        set_(self, "transverse", kappa * np.array([g13, g23]))
        set_(self, "shear_factor", kappa)
        set_(self, "warp", warp)
        set_(self, "poisson", nu)

    @property
    def wave_speed(self) -> float:
        """Fastest membrane wave speed sqrt(max Q_ii / rho), mm/s (docs/theory.md §6.2 B1)."""
        return float(np.sqrt(np.max(np.diag(self.plane_stress)) / self.density))

    @property
    def areal_density(self) -> float:
        """Mass per unit area rho h, t/mm^2."""
        return self.density * self.thickness


def _poisson(value: Any, name: str) -> float:
    nu = as_number(value, name, "a number in (-1, 0.5)")
    if not -1.0 < nu < 0.5:
        raise ValueError(f"{name} must be in (-1, 0.5), got {value!r}")
    return nu
