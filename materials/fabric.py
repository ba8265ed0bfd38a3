"""Fabric: the material of the fibrous shell (THEORY §2-4), one stack of fibres as one shell.

All constitutive quantities are per unit initial width (tension, bending) or per unit initial
area (in-plane shear), so that a stack of plies is described by its measured stack behaviour
(Bai §5: the bending stiffness of the stack, friction included, not the sum of the plies).
"""

from __future__ import annotations

from dataclasses import dataclass

from femcore.checks import check_positive
from materials.laws import BendingLaw, Law, ShearLaw, TensionLaw

__all__ = ["Fabric"]


def _law(value, family: type, name: str, unit: str) -> Law:
    """A law of the given family from a law or a plain number (a linear law)."""
    if isinstance(value, Law):
        if value.family != family.__name__:
            raise ValueError(
                f"{name} must be a {family.__name__} (or a number for a linear law), got {value!r}"
            )
        return value
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ValueError(f"{name} must be a {family.__name__} or a number ({unit}), got {value!r}")
    return family.linear(value)


@dataclass(frozen=True, init=False)
class Fabric:
    """A fibrous reinforcement (one ply or a stack of plies modelled as one shell).

    thickness : h, mm, measured along the normal to the mid-surface (conserved, Bai §3.2).
    areal_density : rho_A, t/mm^2 (1 kg/m^2 = 1e-9 t/mm^2).
    tension : warp tension law T(eps) (N/mm per unit width), or a number C for T = C eps.
    shear : in-plane shear law M_s(gamma) (N/mm), or a number K for M_s = K gamma.
    bending : warp bending law M(chi) (N per unit width), or a number B for M = B chi.
    tension_weft, bending_weft : weft laws; None means the same as warp.
    """

    thickness: float
    areal_density: float
    tension: Law
    shear: Law
    bending: Law
    tension_weft: Law
    bending_weft: Law

    def __init__(
        self,
        thickness,
        areal_density,
        tension,
        shear,
        bending,
        tension_weft=None,
        bending_weft=None,
    ):
        set_ = object.__setattr__
        set_(self, "thickness", check_positive(thickness, "Fabric thickness", "mm"))
        set_(self, "areal_density", check_positive(areal_density, "Fabric areal_density", "t/mm^2"))
        set_(self, "tension", _law(tension, TensionLaw, "Fabric tension", "N/mm"))
        set_(self, "shear", _law(shear, ShearLaw, "Fabric shear", "N/mm"))
        set_(self, "bending", _law(bending, BendingLaw, "Fabric bending", "N mm"))
        set_(
            self,
            "tension_weft",
            self.tension
            if tension_weft is None
            else _law(tension_weft, TensionLaw, "Fabric tension_weft", "N/mm"),
        )
        set_(
            self,
            "bending_weft",
            self.bending
            if bending_weft is None
            else _law(bending_weft, BendingLaw, "Fabric bending_weft", "N mm"),
        )

    @property
    def density(self) -> float:
        """Volume density rho = rho_A / h, t/mm^3."""
        return self.areal_density / self.thickness
