"""A verification check: a computed value against a reference, with a stated tolerance."""

from __future__ import annotations

import math

from solvers import Static


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


def solve_sequence(build, meshes, measure):
    """Solve a model on each mesh of a refinement sequence with Static (one increment).

    build(cells) -> (model, node); measure(result, node) -> the value checked.
    Returns the values (one per mesh), the last result, the summed wall time and Newton
    iterations, and whether every solve converged.
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
