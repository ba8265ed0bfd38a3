"""ElasticShell: plane-stress elasticity with transverse shear for the Mindlin shell (THEORY
§5.2), isotropic or orthotropic in a material axis given by a warp direction."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from femcore.checks import check_positive

__all__ = ["ElasticShell"]


@dataclass(frozen=True, init=False)
class ElasticShell:
    """Linear elastic shell section (St Venant-Kirchhoff in the lamina frame).

    E, nu : Young's modulus (N/mm^2, MPa) and Poisson's ratio (isotropic form).
    thickness : h, mm. density : rho, t/mm^3.
    G13, G23 : transverse shear moduli, MPa (default E / (2 (1 + nu))).
    shear_factor : kappa (5/6 for a homogeneous section, the Abaqus value).
    Orthotropic sections: ``ElasticShell.orthotropic(...)``.

    Attributes used by the element: ``plane_stress`` (3, 3) Q in material axes (1 = warp),
    ``transverse`` (2,) kappa (G13, G23), ``warp`` (3,) material axis or None,
    ``wave_speed`` (mm/s) the fastest membrane wave, sqrt(max Q_ii / rho).
    """

    thickness: float
    density: float
    plane_stress: np.ndarray
    transverse: np.ndarray
    shear_factor: float
    warp: np.ndarray | None
    poisson: float

    def __init__(self, E, nu, thickness, density, G13=None, G23=None, shear_factor=5 / 6):
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
        )

    @classmethod
    def orthotropic(
        cls,
        E1,
        E2,
        nu12,
        G12,
        G13,
        G23,
        thickness,
        density,
        warp=(1.0, 0.0, 0.0),
        shear_factor=5 / 6,
    ) -> ElasticShell:
        """Orthotropic lamina: 1 = warp direction (projected on each element), 2 = in-plane
        normal to it. Moduli in MPa; nu12 the major Poisson ratio (nu21 = nu12 E2 / E1)."""
        E1 = check_positive(E1, "ElasticShell E1", "MPa")
        E2 = check_positive(E2, "ElasticShell E2", "MPa")
        G12 = check_positive(G12, "ElasticShell G12", "MPa")
        nu12 = _poisson(nu12, "ElasticShell nu12")
        nu21 = nu12 * E2 / E1
        if nu12 * nu21 >= 1:
            raise ValueError(f"ElasticShell: nu12^2 E2/E1 must be < 1, got {nu12 * nu21:.4g}")
        d = 1 - nu12 * nu21
        q = np.array([[E1 / d, nu12 * E2 / d, 0], [nu12 * E2 / d, E2 / d, 0], [0, 0, G12]])
        axis = np.array(warp, dtype=float).ravel()
        if axis.shape != (3,) or not np.isfinite(axis).all() or np.linalg.norm(axis) == 0:
            raise ValueError(f"ElasticShell warp must be a non-zero 3-vector, got {warp!r}")
        self = cls.__new__(cls)
        self._set(thickness, density, q, G13, G23, shear_factor, axis / np.linalg.norm(axis), nu12)
        return self

    def _set(self, thickness, density, q, g13, g23, kappa, warp, nu):
        set_ = object.__setattr__
        set_(self, "thickness", check_positive(thickness, "ElasticShell thickness", "mm"))
        set_(self, "density", check_positive(density, "ElasticShell density", "t/mm^3"))
        g13 = check_positive(g13, "ElasticShell G13", "MPa")
        g23 = check_positive(g23, "ElasticShell G23", "MPa")
        kappa = check_positive(kappa, "ElasticShell shear_factor", "-")
        set_(self, "plane_stress", q)
        set_(self, "transverse", kappa * np.array([g13, g23]))
        set_(self, "shear_factor", kappa)
        set_(self, "warp", warp)
        set_(self, "poisson", nu)

    @property
    def wave_speed(self) -> float:
        """Fastest membrane wave speed sqrt(max Q_ii / rho), mm/s (THEORY §6.2 B1)."""
        return float(np.sqrt(np.max(np.diag(self.plane_stress)) / self.density))

    @property
    def areal_density(self) -> float:
        return self.density * self.thickness


def _poisson(value, name: str) -> float:
    try:
        nu = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number in (-1, 0.5), got {value!r}") from None
    if not -1.0 < nu < 0.5:
        raise ValueError(f"{name} must be in (-1, 0.5), got {value!r}")
    return nu
