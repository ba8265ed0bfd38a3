"""The gravity of a case file against its materials' system of units: 9.81 beside densities in
t/mm^2 is 9.81 mm/s^2, a thousandth of the Earth's gravity in mm, N, t, s (and 9810 beside
densities in kg/m^2 a thousand times it in m, N, kg, s). The materials' own checks
(femcore.checks.warn_implausible) say which system each material's values fit; this says when
the gravity fits the other one."""

from __future__ import annotations

import warnings
from collections.abc import Iterable
from typing import Any

import numpy as np

__all__ = ["warn_gravity_units"]

# Plausible magnitudes (the Moon's 1.62 m/s^2 to 10 g, with room): mm/s^2 and m/s^2.
_GRAVITY = {"mm": (100.0, 1e5), "si": (0.1, 100.0)}
# Plausible areal densities, as femcore.checks' ranges for Fabric: t/mm^2 and kg/m^2.
_AREAL_DENSITY = {"mm": (1e-12, 1e-6), "si": (1e-3, 1e3)}
_NAMES = {"mm": ("mm, N, t, s", "mm/s^2", 9810.0), "si": ("m, N, kg, s", "m/s^2", 9.81)}


def _systems(value: float, ranges: dict[str, tuple[float, float]]) -> set[str]:
    return {system for system, (low, high) in ranges.items() if low <= value <= high}


def warn_gravity_units(acceleration: Any, elements: Iterable[Any], where: str) -> None:
    """Warn (UserWarning) when the gravity's magnitude fits one system of units only and every
    material with an areal density fits the other one only.

    Parameters
    ----------
    acceleration : (3,) float
        The gravity, in the case's units of acceleration.
    elements : iterable
        The parts' elements; their ``fabric`` or ``material`` with an ``areal_density`` (mass
        per area) are compared; others are left out.
    where : str
        The case file and table, for the message.
    """
    magnitude = float(np.linalg.norm(np.asarray(acceleration, dtype=float)))
    gravity = _systems(magnitude, _GRAVITY)
    materials: set[str] = set()
    for element in elements:
        material = getattr(element, "fabric", None) or getattr(element, "material", None)
        density = getattr(material, "areal_density", None)
        if isinstance(density, int | float) and density > 0:
            fits = _systems(float(density), _AREAL_DENSITY)
            if len(fits) != 1:
                return  # a material that fits neither or both: no system to hold the gravity to
            materials |= fits
    if len(gravity) != 1 or len(materials) != 1 or gravity == materials:
        return
    (system,) = materials
    units, unit, earth = _NAMES[system]
    (other,) = gravity
    warnings.warn(
        f"{where}: gravity {magnitude:g} fits {_NAMES[other][1]}, but the materials' areal "
        f"densities are in {units}, where it is {magnitude:g} {unit} ({magnitude / earth:.3g} "
        f"of the Earth's {earth:g} {unit}): give the gravity in {unit}",
        UserWarning,
        stacklevel=2,
    )
