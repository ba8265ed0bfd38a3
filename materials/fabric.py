"""Fabric: the material of the fibrous shell (docs/theory.md §2-4), one stack of fibres as one
shell.

All constitutive quantities are per unit initial width (tension, bending) or per unit initial
area (in-plane shear), so that a stack of plies is described by its measured stack behaviour
(Bai §5: the bending stiffness of the stack, friction included, not the sum of the plies).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from femcore.checks import Plausible, check_positive, warn_implausible
from materials.laws import BendingLaw, Law, ShearLaw, TensionLaw

__all__ = ["Fabric"]


def _law(value: Any, family: type[TensionLaw | ShearLaw | BendingLaw], name: str, unit: str) -> Law:
    """A law of the given family from a law or a plain number (a linear law)."""
    if isinstance(value, Law):
        if value.family != family.__name__:
            raise ValueError(
                f"{name} must be a {family.__name__} (or a number for a linear law), got {value!r}"
            )
        return value
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise ValueError(f"{name} must be a {family.__name__} or a number ({unit}), got {value!r}")
    return family.linear(float(value))


@dataclass(frozen=True, init=False)
class Fabric:
    """A fibrous reinforcement (one ply or a stack of plies modelled as one shell).

    Parameters
    ----------
    thickness : float
        h, mm, measured along the normal to the mid-surface (conserved, Bai §3.2).
    areal_density : float
        rho_A, t/mm^2 (1 kg/m^2 = 1e-9 t/mm^2).
    tension : Law or float
        Warp tension law T(eps) (N/mm per unit width), or a number C for T = C eps.
    shear : Law or float
        In-plane shear law M_s(gamma) (N/mm), or a number K for M_s = K gamma.
    bending : Law or float
        Warp bending law M(chi) (N per unit width), or a number B for M = B chi.
    tension_weft, bending_weft : Law or float, optional
        Weft laws; None means the same as warp.
    ply_count : int, optional
        The number of plies (or sheets) of the stack this fabric describes, where it has one
        (the presets say): the default of ``fibreshell compare --kinematics plies``. None: not
        stated.

    To change some laws of a fabric use ``fabric.replace(...)``, not ``dataclasses.replace``:
    the latter keeps the old weft laws when the warp laws change.

    Units mm, N, t, s: a thickness or an areal density far outside the range of real fabrics
    (usually one given in m or kg/m^2) draws a UserWarning.

    Raises
    ------
    ValueError
        A non-positive or non-finite thickness or density, a law of the wrong family, or a
        number that is not a valid linear stiffness.
    """

    thickness: float
    areal_density: float
    tension: Law
    shear: Law
    bending: Law
    tension_weft: Law
    bending_weft: Law
    ply_count: int | None

    def __init__(
        self,
        thickness: float,
        areal_density: float,
        tension: Law | float,
        shear: Law | float,
        bending: Law | float,
        tension_weft: Law | float | None = None,
        bending_weft: Law | float | None = None,
        ply_count: int | None = None,
    ) -> None:
        set_ = object.__setattr__
        set_(self, "thickness", check_positive(thickness, "Fabric thickness", "mm"))
        set_(self, "areal_density", check_positive(areal_density, "Fabric areal_density", "t/mm^2"))
        # Plausible in either consistent system: 1 g/m^2 (lighter than any veil) to 1000
        # kg/m^2 (a 100 mm steel plate); 1 micrometre to 1 m thick in mm, 10 micrometres to
        # 50 mm in m (a fabric 0.3 m thick is a thickness in mm beside a density in kg/m^2).
        warn_implausible(
            Plausible("Fabric areal_density", self.areal_density, ("t/mm^2", 1e-12, 1e-6),
                      ("kg/m^2", 1e-3, 1e3), "a mass per area in kg/m^2 is 1e-9 of it in t/mm^2"),
            Plausible("Fabric thickness", self.thickness, ("mm", 1e-3, 1e3), ("m", 1e-5, 0.05),
                      "a thickness in m is 1e3 of it in mm"),
        )  # fmt: skip
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
        if ply_count is not None and (
            isinstance(ply_count, bool)
            or not isinstance(ply_count, (int, np.integer))
            or ply_count < 1
        ):
            raise ValueError(f"Fabric ply_count must be an integer >= 1 or None, got {ply_count!r}")
        set_(self, "ply_count", None if ply_count is None else int(ply_count))
        set_(
            self,
            "bending_weft",
            self.bending
            if bending_weft is None
            else _law(bending_weft, BendingLaw, "Fabric bending_weft", "N mm"),
        )

    def replace(self, **changes: Any) -> Fabric:
        """A copy with some fields changed, the weft laws following the warp laws they were.

        Parameters
        ----------
        **changes
            Any of the constructor's arguments. A weft law (tension_weft, bending_weft) that
            was the warp law and is not given becomes the new warp law.

        Returns
        -------
        Fabric
        """
        unknown = sorted(set(changes) - set(self.__dataclass_fields__))
        if unknown:
            raise ValueError(
                f"Fabric.replace: unknown field(s) {unknown}; fields are "
                f"{', '.join(self.__dataclass_fields__)}"
            )
        fields = {name: getattr(self, name) for name in self.__dataclass_fields__}
        for warp, weft in (("tension", "tension_weft"), ("bending", "bending_weft")):
            if (
                warp in changes
                and weft not in changes
                and self.__dict__[weft] is self.__dict__[warp]
            ):
                fields[weft] = None  # follows the new warp law
        fields.update(changes)
        return Fabric(**fields)

    def plies(self, count: int) -> Fabric:
        """The fabric of ONE ply when this stack is split into ``count`` equal plies.

        Thickness h / count, areal density rho_A / count, and every law (tension,
        tension_weft, shear, bending, bending_weft) scaled by 1 / count (``Law.scaled``): the
        plies of one stack share its stiffnesses and its mass equally, so that ``count``
        plies that bend together (stuck) carry the stack's tension and in-plane shear, and
        frictionless plies each carry 1/count of the bending (docs/theory.md, "The stack as
        plies"). A weft law that was the warp law stays the (scaled) warp law.

        Parameters
        ----------
        count : int
            N >= 1, the number of plies (``count = 1``: this fabric, equal in every field).

        Returns
        -------
        Fabric
            The ply's fabric: mm, t/mm^2, N/mm, N mm as this one.

        Raises
        ------
        ValueError
            ``count`` not an integer >= 1 (a bool, a float, 0 or negative).
        """
        if isinstance(count, bool) or not isinstance(count, (int, np.integer)) or count < 1:
            raise ValueError(f"Fabric.plies: count must be an integer >= 1, got {count!r}")
        factor = 1.0 / int(count)
        if count == 1:
            return self
        weft_tension = (
            None if self.tension_weft is self.tension else self.tension_weft.scaled(factor)
        )
        weft_bending = (
            None if self.bending_weft is self.bending else self.bending_weft.scaled(factor)
        )
        return Fabric(
            thickness=self.thickness * factor,
            areal_density=self.areal_density * factor,
            tension=self.tension.scaled(factor),
            shear=self.shear.scaled(factor),
            bending=self.bending.scaled(factor),
            tension_weft=weft_tension,
            bending_weft=weft_bending,
            # each of the count plies holds ply_count / count of the stack's plies
            ply_count=(
                self.ply_count // count
                if self.ply_count is not None and self.ply_count % count == 0
                else None
            ),
        )

    @property
    def density(self) -> float:
        """Volume density rho = rho_A / h, t/mm^3."""
        return self.areal_density / self.thickness
