"""Argument checks shared by the API boundary of every package (clear ValueErrors)."""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np

__all__ = ["check_positive", "warn_implausible"]


def check_positive(value: Any, name: str, unit: str) -> float:
    """A finite positive float, or ValueError naming the parameter and its unit.

    Parameters
    ----------
    value : Any
        The argument to check; anything ``float()`` accepts.
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
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a positive number ({unit}), got {value!r}") from None
    if not np.isfinite(number) or number <= 0.0:
        raise ValueError(f"{name} must be a positive finite number ({unit}), got {value!r}")
    return number


def warn_implausible(value: float, name: str, unit: str, low: float, high: float, hint: str):
    """Warn (UserWarning) when ``value`` lies outside [low, high], the range of the materials
    this project models in its units (mm, N, t, s): almost always a value given in other units.

    Parameters
    ----------
    value : float
        The checked value, in ``unit``.
    name, unit : str
        For the message, e.g. "Fabric areal_density", "t/mm^2".
    low, high : float
        The plausible range in ``unit``.
    hint : str
        The usual mistake and its conversion, e.g. "1 kg/m^2 = 1e-9 t/mm^2".
    """
    if not low <= value <= high:
        warnings.warn(
            f"{name} = {value:g} {unit} is outside the usual range {low:g}..{high:g} {unit} "
            f"(units mm, N, t, s): {hint}",
            UserWarning,
            stacklevel=3,
        )
