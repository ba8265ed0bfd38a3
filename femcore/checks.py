"""Argument checks shared by the API boundary of every package (clear ValueErrors)."""

from __future__ import annotations

import os
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

__all__ = [
    "UNIT_SYSTEMS",
    "Plausible",
    "as_flag",
    "as_number",
    "as_path",
    "as_reals",
    "check_positive",
    "warn_implausible",
]


def as_number(value: Any, name: str, expected: str) -> float:
    """``float(value)`` for a real number, or ValueError naming the parameter.

    Strings, booleans and None are refused even though ``float()`` takes "1" and True: a
    quoted number in a script or a case file, or a flag where a quantity is meant, is a
    mistake to report, not a value to guess.

    Parameters
    ----------
    value : Any
        The argument: an int, a float, a numpy scalar or a 0-d numeric array.
    name : str
        Parameter name used in the message.
    expected : str
        What the parameter must be, for the message, e.g. "a positive number (mm)".

    Returns
    -------
    float
        The value as a float (possibly NaN or inf: range checks are the caller's).

    Raises
    ------
    ValueError
        ``value`` is a string, bytes, a boolean, None or anything else not a real number.
    """
    if isinstance(value, (str, bytes, bool, np.bool_)) or value is None:
        raise ValueError(f"{name} must be {expected}, got {value!r}")
    if isinstance(value, np.ndarray) and (value.ndim != 0 or value.dtype.kind not in "iuf"):
        raise ValueError(f"{name} must be {expected}, got {value!r}")
    try:
        return float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be {expected}, got {value!r}") from None


def as_reals(value: Any, name: str, expected: str) -> np.ndarray:
    """``value`` as a float array, or ValueError naming the parameter when it holds strings,
    booleans, None or other objects (``np.asarray(["1", "0", "0"], dtype=float)`` would
    take the strings; range and shape checks are the caller's).

    Parameters
    ----------
    value : Any
        A number or a (nested) sequence of numbers.
    name, expected : str
        For the message, e.g. "RigidPlane normal", "3 finite numbers".

    Returns
    -------
    numpy.ndarray of float64
        The values, in the shape given.
    """
    if isinstance(value, (str, bytes)) or value is None:
        raise ValueError(f"{name} must be {expected}, got {value!r}")
    try:
        array = np.asarray(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be {expected}, got {value!r}") from None
    if array.dtype.kind not in "iuf":
        raise ValueError(f"{name} must be {expected}, got {value!r}")
    return array.astype(float)


def as_flag(value: Any, name: str) -> bool:
    """True or False, or ValueError naming the option: ``bool("no")`` would be True.

    Parameters
    ----------
    value : Any
        The option's value.
    name : str
        Option name for the message.
    """
    if not isinstance(value, (bool, np.bool_)):
        raise ValueError(f"{name} must be True or False, got {value!r}")
    return bool(value)


def as_path(value: Any, name: str) -> Path:
    """``value`` as a Path, or ValueError naming the parameter when it is not a str or an
    os.PathLike (a number or None where a file name is meant) or is empty.

    Parameters
    ----------
    value : Any
        The file or folder name.
    name : str
        Parameter name for the message, e.g. "Result.write path".
    """
    if not isinstance(value, (str, os.PathLike)) or str(value) == "":
        raise ValueError(f"{name} must be a file name (str or path), got {value!r}")
    return Path(value)


def check_positive(value: Any, name: str, unit: str) -> float:
    """A finite positive float, or ValueError naming the parameter and its unit.

    Parameters
    ----------
    value : Any
        The argument to check: a real number (strings, booleans and None are refused).
    name : str
        Parameter name used in the message, e.g. "Fabric thickness".
    unit : str
        Unit shown in the message, e.g. "mm".

    Returns
    -------
    float
        ``float(value)``, in the unit ``unit``.

    Raises
    ------
    ValueError
        ``value`` is not a number, not finite, or not > 0.
    """
    in_unit = f" ({unit})" if unit else ""  # a ratio or a count has none: no empty brackets
    number = as_number(value, name, f"a positive number{in_unit}")
    if not np.isfinite(number) or number <= 0.0:
        raise ValueError(f"{name} must be a positive finite number{in_unit}, got {value!r}")
    return number


@dataclass(frozen=True)
class Plausible:
    """A value of a material and where it is plausible in each system of units.

    Attributes
    ----------
    name : str
        For the message, e.g. "Fabric areal_density".
    value : float
        The value as given.
    mm : tuple (unit, low, high)
        Its unit and plausible range in mm, N, t, s, e.g. ("t/mm^2", 1e-12, 1e-6).
    si : tuple (unit, low, high)
        Its unit and plausible range in m, N, kg, s, e.g. ("kg/m^2", 1e-3, 1e3).
    hint : str
        The usual mistake and its conversion, e.g. "1 kg/m^2 = 1e-9 t/mm^2".
    """

    name: str
    value: float
    mm: tuple[str, float, float]
    si: tuple[str, float, float]
    hint: str


UNIT_SYSTEMS = {"mm": "mm, N, t, s", "si": "m, N, kg, s"}


def _outside(quantity: Plausible, system: str) -> str | None:
    unit, low, high = getattr(quantity, system)
    if low <= quantity.value <= high:
        return None
    return (
        f"{quantity.name} = {quantity.value:g} {unit} is outside the usual range "
        f"{low:g}..{high:g} {unit}"
    )


def warn_implausible(*quantities: Plausible) -> None:
    """Warn (UserWarning) when a material's values do not all fit one consistent system of
    units, mm, N, t, s or m, N, kg, s: almost always a value given in the other one (a
    density in kg/m^3 beside lengths in mm). Values that all fit one system are quiet: any
    consistent set of units is a valid model (a whole material in the other system than its
    mesh is the mesh's check, femcore.mesh_checks.check_thickness_scale).

    Parameters
    ----------
    *quantities : Plausible
        The material's values, each with its plausible range in both systems.
    """
    if any(all(_outside(q, system) is None for q in quantities) for system in UNIT_SYSTEMS):
        return
    said = [f"{text} (units mm, N, t, s): {q.hint}"
            for q in quantities if (text := _outside(q, "mm")) is not None]  # fmt: skip
    other = [text for q in quantities if (text := _outside(q, "si")) is not None]
    warnings.warn(
        "; ".join(said) + f"; nor do they fit m, N, kg, s together ({'; '.join(other)}): "
        "the values mix two systems of units",
        UserWarning,
        stacklevel=3,
    )
