"""Argument checks shared by the API boundary of every package (clear ValueErrors)."""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["check_positive"]


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
