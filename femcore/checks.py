"""Argument checks shared by the API boundary of every package (clear ValueErrors)."""

from __future__ import annotations

import numpy as np


def check_positive(value, name: str, unit: str) -> float:
    """A finite positive float, or ValueError naming the parameter and its unit."""
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a positive number ({unit}), got {value!r}") from None
    if not np.isfinite(number) or number <= 0.0:
        raise ValueError(f"{name} must be a positive finite number ({unit}), got {value!r}")
    return number
