"""A fitted value and its confidence interval as printed text (``fibreshell identify`` and the
"fit" calibration of ``fibreshell compare``): enough digits that the interval reads, its ends
apart from each other and from the value, as they are in the numbers."""

from __future__ import annotations

import math

__all__ = ["below_zero", "interval_text"]

# The most significant digits a float64 needs to be read back exactly.
_EXACT = 17


def interval_text(value: float, low: float, high: float, digits: int = 4) -> tuple[str, str, str]:
    """``low``, ``value`` and ``high`` with one number of significant digits, at least
    ``digits`` and as many more as make the printed ends differ from the printed value where
    the numbers do (low < value < high): "1.002 (95 %: 1.001 to 1.003)", not "1.002 (95 %: 1
    to 1)". Rounding to one number of digits keeps their order, so the printed interval
    holds the printed value.

    Parameters
    ----------
    value, low, high : float
        The value and its interval's ends, finite (any unit: the text is the numbers').
    digits : int
        The fewest significant digits, >= 1.

    Returns
    -------
    (str, str, str)
        The texts of low, value and high.
    """
    numbers = (float(low), float(value), float(high))
    if not all(map(math.isfinite, numbers)):
        raise ValueError(f"interval_text: expected finite numbers, got {numbers!r}")
    apart = numbers[0] < numbers[1] < numbers[2]
    for count in range(max(1, digits), _EXACT + 1):
        texts = tuple(f"{x:.{count}g}" for x in numbers)
        read = [float(t) for t in texts]
        if not apart or read[0] < read[1] < read[2]:
            break
    return texts[0], texts[1], texts[2]


def below_zero(ends) -> str:
    """The note printed after an interval (low, high) whose low end is at or below zero: the
    interval is the fit's linearisation, theta +- t sigma (fibreshell/identify.py), and a
    stiffness or a density, fitted as ln(theta / theta_0) and so positive, is then not
    determined by the data; "" otherwise."""
    return (
        " (it reaches zero: the data do not determine this value; the linearised interval "
        "is not to be read as a bound)"
        if float(ends[0]) <= 0.0
        else ""
    )
