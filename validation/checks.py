"""A verification check: a computed value against a reference, with a stated tolerance."""

from __future__ import annotations

import math


def check(
    name: str,
    reference: float,
    value: float,
    tolerance: float,
    *,
    relative: bool = True,
    source: str = "",
) -> dict:
    """A JSON-ready check record.

    relative=True: passed when |value - reference| <= tolerance |reference|;
    otherwise when |value - reference| <= tolerance (absolute).
    """
    reference, value = float(reference), float(value)
    error = abs(value - reference)
    if relative:
        error = error / abs(reference) if reference != 0 else math.inf
    passed = bool(math.isfinite(error) and error <= tolerance)
    return {
        "name": name,
        "reference": reference,
        "value": value,
        "error": error,
        "tolerance": float(tolerance),
        "relative": relative,
        "passed": passed,
        "source": source,
    }
