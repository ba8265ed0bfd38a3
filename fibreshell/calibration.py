"""How a fibrous part becomes a Mindlin shell for a comparison: the calibration, stated.

Three rules (``fibreshell compare --calibration``):

* ``laws`` (default): the Mindlin shell's section is the fabric itself
  (``MindlinShell(fabric)``, docs/theory.md §5.7): the same tension, shear and bending laws,
  non-linear ones as given, a stated transverse shear S (default 5 B0 / h^2) and twisting
  stiffness. Only the kinematics differ.
* ``fit``: Bai's method (§6 of the paper: the Abaqus S3 properties "optimized so that the
  middle surface is in agreement"): the ``laws`` section with its bending laws scaled by a
  factor and its transverse shear stiffness fitted (``fibreshell.identify``, least squares)
  so that the Mindlin mid-surface matches the fibrous one along a path of the case; the
  directors and the thickness are then compared.
* ``initial-slope``: the homogeneous elastic section of ``ElasticShell.equivalent``
  (E = 12 B0 / h^3 from the initial bending slope, G12 = K0 / h, G13 = shear_ratio E): its
  membrane is 12 B0 / h^2, far softer than the fibres, and past the knee of a non-linear law it
  is too stiff in bending. Kept to show what that calibration does.

Every comparison states its calibration and the numbers it chose (``Calibration.describe``).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from elements import FibrousShell, MindlinShell
from elements.mindlin_fabric import NoDefaultStiffness, default_transverse_shear
from femcore.checks import check_positive
from materials import ElasticShell, Fabric

__all__ = ["CALIBRATIONS", "Calibration"]

CALIBRATIONS = ("laws", "fit", "initial-slope")
RULES = {
    "laws": "MindlinShell(fabric): the section is the fabric's own tension, shear and bending "
    "laws (non-linear as given), transverse shear S and twisting D_t stated (docs/theory.md "
    "§5.7)",
    "fit": "the laws section with its bending laws scaled (and the twisting D_t they give) and its "
    "transverse shear S fitted "
    "by least squares so that the Mindlin mid-surface matches the fibrous one along a path "
    "(Bai's calibration of Abaqus S3); then directors and thickness are compared",
    "initial-slope": "ElasticShell.equivalent: E = 12 B0 / h^3 per direction from the initial "
    "bending slope, nu12 = 0, G12 = K0 / h, G13 = G23 = shear_ratio x E (membrane 12 B0 / h^2)",
}


#: How a run in the Mindlin kinematics is given the section's numbers a fabric's bending laws
#: with a toe have no default for (``mindlin``; compare says its own options).
RUN_ROUTE = (
    "give them as the run's options transverse_shear and twisting (keys of a sweep or a fit: "
    "--vary twisting=D; run_case(..., transverse_shear=S, twisting=D) in Python)"
)


def _slope(law) -> float:
    return float(np.asarray(law.slope(np.array(0.0))))


@dataclass(frozen=True)
class Calibration:
    """A rule that turns a FibrousShell into a MindlinShell on the same cells.

    Parameters
    ----------
    name : str
        "laws", "fit" or "initial-slope" (module docstring).
    shear_ratio : float
        G13 / E of "initial-slope" (> 0).
    bending_scale : float
        Factor on both bending laws of "laws" and "fit" (> 0; 1 for "laws" as given).
    transverse_shear : float or None
        S, N/mm, of "laws" and "fit"; None: the default 5 B0 / h^2.
    twisting : float or None
        D_t, N mm, of "laws" and "fit"; None: the default B0 / 2 of the (scaled) laws. A
        fabric whose bending laws have a toe (B0 = 0) needs both numbers (``check_section``).
    fitted : dict
        What a "fit" found (values, confidence intervals, residual, path): stated in the
        comparison.
    """

    name: str = "laws"
    shear_ratio: float = 0.5
    bending_scale: float = 1.0
    transverse_shear: float | None = None
    twisting: float | None = None
    fitted: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        if self.name not in CALIBRATIONS:
            raise ValueError(
                f"calibration must be one of {', '.join(CALIBRATIONS)}, got {self.name!r}"
            )
        check_positive(self.shear_ratio, "calibration shear_ratio", "-")
        check_positive(self.bending_scale, "calibration bending_scale", "-")
        if self.transverse_shear is not None:
            check_positive(self.transverse_shear, "calibration transverse_shear", "N/mm")
        if self.twisting is not None:
            check_positive(self.twisting, "calibration twisting", "N mm")

    @classmethod
    def from_options(
        cls,
        calibration: Calibration | str | None = None,
        shear_ratio: float | None = None,
        bending_scale: float | None = None,
        transverse_shear: float | None = None,
        twisting: float | None = None,
    ) -> Calibration:
        """A calibration from a name and the run options of a sweep or a fit (None: the
        rule's default; an option the rule does not use is refused)."""
        if isinstance(calibration, Calibration):
            base = calibration
        elif calibration is None:  # a shear ratio alone names the rule it belongs to
            base = cls(name="initial-slope" if shear_ratio is not None else "laws")
        else:
            base = cls(name=str(calibration))
        changes: dict[str, Any] = {}
        if shear_ratio is not None:
            if base.name != "initial-slope":
                raise ValueError(
                    f"shear_ratio belongs to the initial-slope calibration, not {base.name!r}"
                )
            changes["shear_ratio"] = shear_ratio
        numbers = (
            ("bending_scale", bending_scale),
            ("transverse_shear", transverse_shear),
            ("twisting", twisting),
        )
        for key, value in numbers:
            if value is not None:
                if base.name == "initial-slope":
                    raise ValueError(
                        f"{key} belongs to the laws and fit calibrations, not initial-slope"
                    )
                changes[key] = value
        return cls(**{**base.__dict__, **changes})

    # ------------------------------------------------------------------ the Mindlin shell
    def section_fabric(self, fabric: Fabric) -> Fabric:
        """The fabric of the "laws" / "fit" section: bending laws scaled by bending_scale."""
        if self.bending_scale == 1.0:
            return fabric
        return fabric.replace(
            bending=fabric.bending.scaled(self.bending_scale),
            bending_weft=fabric.bending_weft.scaled(self.bending_scale),
        )

    def mindlin(self, element: FibrousShell) -> MindlinShell:
        """The Mindlin shell that replaces ``element`` (same fabric, warp and cells)."""
        fabric = element.fabric
        if self.name == "initial-slope":
            return MindlinShell(
                ElasticShell.equivalent(fabric, self.shear_ratio, warp=element.warp)
            )
        try:
            return MindlinShell(
                self.section_fabric(fabric),
                warp=element.warp,
                transverse_shear=self.transverse_shear,
                twisting=self.twisting,
            )
        except NoDefaultStiffness as error:  # a toe: said how a run is given both numbers
            raise ValueError(f"{error}; {RUN_ROUTE}") from None

    def check_section(self, fabric: Fabric, route: str) -> None:
        """Raise ValueError, ending with ``route`` (how the user gives the numbers from where
        they are: compare's options, a case file's), where the Mindlin section of ``fabric``
        cannot be made: bending laws with a toe (B0 = 0) and transverse_shear or twisting
        not given, whose defaults from B0 would be 0 (elements.mindlin_fabric)."""
        if self.name == "initial-slope":
            return
        try:
            MindlinShell(
                self.section_fabric(fabric),
                transverse_shear=self.transverse_shear,
                twisting=self.twisting,
            )
        except NoDefaultStiffness as error:
            raise ValueError(f"{error}; {route}") from None

    def numbers(self, fabric: Fabric) -> dict[str, Any]:
        """The numbers this calibration gives the Mindlin shell of ``fabric`` (units in the
        names)."""
        h = fabric.thickness
        if self.name == "initial-slope":
            section = ElasticShell.equivalent(fabric, self.shear_ratio)
            q = section.plane_stress
            return {
                "E1_MPa": float(q[0, 0]),
                "E2_MPa": float(q[1, 1]),
                "G12_MPa": float(q[2, 2]),
                "G13_MPa": float(section.transverse[0] / section.shear_factor),
                "shear_ratio": self.shear_ratio,
                "bending_stiffness_warp_N_mm": float(q[0, 0]) * h**3 / 12.0,
                "bending_stiffness_weft_N_mm": float(q[1, 1]) * h**3 / 12.0,
                "membrane_stiffness_warp_N_per_mm": float(q[0, 0]) * h,
                "fibre_tension_stiffness_N_per_mm": _slope(fabric.tension),
                "bending_law_warp": repr(fabric.bending),
            }
        laws = self.section_fabric(fabric)
        # the shell's own S and D_t, both from the scaled laws as ``mindlin`` builds it
        shell = MindlinShell(laws, transverse_shear=self.transverse_shear, twisting=self.twisting)
        out = {
            "bending_law_warp": repr(laws.bending),
            "bending_law_weft": repr(laws.bending_weft),
            "bending_scale": self.bending_scale,
            "tension_law_warp": repr(laws.tension),
            "shear_law": repr(laws.shear),
            "transverse_shear_N_per_mm": shell.transverse_shear,
            "twisting_N_mm": shell.twisting,
        }
        if self.fitted:
            out["fit"] = self.fitted
        return out

    def describe(self, fabric: Fabric | None) -> dict[str, Any]:
        """{"name", "rule" (a sentence), "numbers"} for comparison.json and the figures."""
        return {
            "name": self.name,
            "rule": RULES[self.name],
            "numbers": {} if fabric is None else self.numbers(fabric),
        }

    def label(self, fabric: Fabric | None = None) -> str:
        """A short line for figure titles: the rule and its key numbers."""
        if self.name == "initial-slope":
            text = (
                f"Mindlin calibration 'initial-slope' (E = 12 B0/h^3, G13/E = {self.shear_ratio:g})"
            )
            if fabric is not None:
                b0 = _slope(fabric.bending)
                text += f", B = {b0:.3g} N mm at every curvature"
            return text
        s = self.transverse_shear
        if s is None and fabric is not None:  # the default of the scaled laws, as the shell's
            s = default_transverse_shear(self.section_fabric(fabric))
        shear = f", S = {s:.3g} N/mm" if s is not None else ""
        if self.twisting is not None:
            shear += f", D_t = {self.twisting:.3g} N mm"
        scale = f", bending x {self.bending_scale:.3g}" if self.bending_scale != 1.0 else ""
        return f"Mindlin calibration '{self.name}' (the fabric's laws{scale}{shear})"
