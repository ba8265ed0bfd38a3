"""Verification checks (a computed value against a reference, with a stated tolerance) and the
refinement-sequence solve loop shared by the mesh-convergence cases."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

from solvers import Static
from validation.records import Check

__all__ = ["check", "solve_sequence"]


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
