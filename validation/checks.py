"""Verification checks (a computed value against a reference, with a stated tolerance), the
refinement-sequence solve loop shared by the mesh-convergence cases and the observed order of
convergence of a quantity on three meshes (``observed_order``)."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
from scipy.optimize import brentq

from solvers import Static
from validation.records import Check

__all__ = ["ORDER_RANGE", "bound", "check", "observed_order", "reported", "solve_sequence"]

# The orders ``observed_order`` looks for; outside them a sequence is reported as having none.
ORDER_RANGE = (-8.0, 8.0)


def check(
    name: str,
    reference: float,
    value: float,
    tolerance: float,
    *,
    relative: bool = True,
    source: str = "",
) -> Check:
    """A check record.

    Parameters
    ----------
    name : str
        What is checked, with its unit.
    reference, value : float
        The reference and the computed value.
    tolerance : float
        The largest error that passes.
    relative : bool, optional
        True: passed when |value - reference| <= tolerance |reference|; False: when
        |value - reference| <= tolerance (absolute).
    source : str, optional
        Where the reference comes from.

    Returns
    -------
    Check
        The record, with its error and verdict.
    """
    reference, value = float(reference), float(value)
    error = abs(value - reference)
    if relative:
        error = error / abs(reference) if reference != 0 else math.inf
    passed = bool(math.isfinite(error) and error <= tolerance)
    return Check(
        name=name,
        reference=reference,
        value=value,
        error=error,
        tolerance=float(tolerance),
        relative=relative,
        passed=passed,
        source=source,
    )


def bound(name: str, reference: float, value: float, *, at_least: bool, source: str = "") -> Check:
    """A one-sided check: passed when ``value >= reference`` (``at_least``) or ``value <=
    reference``.

    Parameters
    ----------
    name : str
        What is checked, with its unit and the bound (e.g. "(deg, > 10)").
    reference : float
        The bound.
    value : float
        The computed value.
    at_least : bool
        True: the value must not fall below the bound; False: not rise above it.
    source : str, optional
        Where the bound comes from.

    Returns
    -------
    Check
        The record: ``comparison`` "at least" or "at most", ``tolerance`` 0 and ``error`` how
        far the value lies past the bound (0 when it passes).
    """
    reference, value = float(reference), float(value)
    short = reference - value if at_least else value - reference
    error = max(short, 0.0) if math.isfinite(short) else math.inf
    return Check(
        name=name,
        reference=reference,
        value=value,
        error=error,
        tolerance=0.0,
        relative=False,
        passed=bool(math.isfinite(short) and short <= 0.0),
        source=source,
        comparison="at least" if at_least else "at most",
    )


def reported(name: str, value: float, *, reference: float = math.nan, source: str = "") -> Check:
    """A number shown among the checks without a verdict (``comparison`` "reported"): the
    report neither passes nor fails it and leaves it out of the checks passed.

    Parameters
    ----------
    name : str
        What the number is, with its unit.
    value : float
        The computed value.
    reference : float, optional
        A value to read it beside (NaN: none).
    source : str, optional
        Where the reference comes from.

    Returns
    -------
    Check
        The record, with ``error`` |value - reference| (NaN without a reference).
    """
    reference, value = float(reference), float(value)
    return Check(
        name=name,
        reference=reference,
        value=value,
        error=abs(value - reference),
        tolerance=math.inf,
        relative=False,
        passed=True,
        source=source,
        comparison="reported",
    )


def solve_sequence(
    build: Callable[[int], tuple[Any, Any]],
    meshes: Sequence[int],
    measure: Callable[[Any, Any], float],
) -> tuple[list[float], Any, float, int, bool]:
    """Solve a model on each mesh of a refinement sequence with Static (one increment).

    Parameters
    ----------
    build : callable
        ``build(cells) -> (model, node)``.
    meshes : sequence of int
        The cells argument of each mesh, coarsest first.
    measure : callable
        ``measure(result, node) -> value`` checked.

    Returns
    -------
    values : list of float
        One per mesh.
    result : Result
        The result on the last mesh.
    wall : float
        Summed wall time.
    steps : int
        Summed Newton iterations.
    converged : bool
        Whether every solve converged.
    """
    values, wall, steps, converged = [], 0.0, 0, True
    for cells in meshes:
        model, node = build(cells)
        result = Static(increments=1).solve(model)
        values.append(measure(result, node))
        wall += result.wall_time
        steps += result.steps
        converged &= bool(result.converged)
    return values, result, wall, steps, converged


def observed_order(sizes: Sequence[float], values: Sequence[float]) -> tuple[float, float]:
    """The observed order of convergence p of a quantity on three meshes and its extrapolated
    value (Richardson), for any refinement ratios.

    With f(h) = f0 + C h^p on the three meshes, p solves
    (f1 - f2) / (f2 - f3) = (h1^p - h2^p) / (h2^p - h3^p), which for a constant ratio
    r = h1 / h2 = h2 / h3 is p = log((f1 - f2) / (f2 - f3)) / log(r); then
    f0 = f3 - (f2 - f3) / ((h2 / h3)^p - 1).

    Parameters
    ----------
    sizes : sequence of 3 float
        Mesh sizes h1 > h2 > h3 (any length unit: only their ratios count).
    values : sequence of 3 float
        The quantity on each mesh, f1, f2, f3.

    Returns
    -------
    order : float
        p; NaN when the differences change sign (the sequence oscillates) or vanish, or when
        p is outside ``ORDER_RANGE``. A negative p: the differences grow (no convergence).
    extrapolated : float
        f0, the value at h = 0; NaN with p, and f3 when the last two values are equal and
        the first differs (converged to round-off on the two finer meshes).

    Raises
    ------
    ValueError
        For other than three sizes and values, sizes not decreasing and positive, or values
        not finite.
    """
    h = np.asarray(sizes, dtype=float)
    f = np.asarray(values, dtype=float)
    if h.shape != (3,) or f.shape != (3,):
        raise ValueError(f"give three sizes and three values, got {h.shape} and {f.shape}")
    if not (np.all(np.isfinite(h)) and h[2] > 0.0 and h[0] > h[1] > h[2]):
        raise ValueError(f"sizes must be positive and decreasing, got {h.tolist()}")
    if not np.all(np.isfinite(f)):
        raise ValueError(f"values must be finite, got {f.tolist()}")
    coarse, fine = f[0] - f[1], f[1] - f[2]
    if coarse == 0.0 or coarse * fine < 0.0:
        return math.nan, math.nan
    if fine == 0.0:
        return math.inf, float(f[2])
    target = math.log(coarse / fine)

    def gap(p: float) -> float:
        # log of the ratio of the differences of h^p, minus the measured one; at p = 0 the
        # ratio's limit is log(h1 / h2) / log(h2 / h3). Increasing in p.
        if abs(p) < 1e-12:
            ratio = math.log(h[0] / h[1]) / math.log(h[1] / h[2])
        else:
            ratio = (h[0] ** p - h[1] ** p) / (h[1] ** p - h[2] ** p)
        return math.log(ratio) - target

    low, high = ORDER_RANGE
    if gap(low) * gap(high) > 0.0:
        return math.nan, math.nan
    p = float(brentq(gap, low, high, xtol=1e-12))
    return p, float(f[2] - fine / ((h[1] / h[2]) ** p - 1.0))
