"""A run whose directors end tilted nearly into the surface: flagged in summary.json
(``tilted_directors``) and warned, so that a user reading the summary or a sweep's table sees
that the thickness and tilt there are not the shell's answer.

The bound is the fibrous shell's thickness guard (docs/theory.md §1.4): where V . N falls below
GUARD = 0.2, a tilt of acos(0.2) = 78.5 deg from the normal, the thickness along the director
h / (V . N) is capped at 5 h (``thickness_guarded`` = 1). The most common cause is a fibrous
body whose directors nothing holds: a uniform tilt of every director over a flat region
stretches no fibre, a zero-energy mode the quasi-static solvers leave wherever their path
puts it (docs/theory.md §1, "Without a clamp the tilt is not decided"). A flat strip pulled
10 % without a clamp ended 88-89 deg off the normal at the cap while Static's stability search
turned along that mode; it no longer does (solvers/neutral_modes.py), and the flag stays for
the paths that may still leave such a tilt."""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping
from typing import Any

import numpy as np

from elements.shell_geometry import GUARD
from femcore.field_names import parts_fields

__all__ = ["TILT_BOUND_DEG", "say_tilted", "tilted_directors"]

#: The tilt from the normal past which a director is flagged, deg: that of the thickness guard.
TILT_BOUND_DEG = math.degrees(math.acos(GUARD))


def tilted_directors(point: Mapping[str, Any], held: np.ndarray | None = None) -> dict | None:
    """The nodes of a frame whose directors are tilted past TILT_BOUND_DEG from the normal or
    whose thickness is at the guard's cap, those whose directors a support holds left out.

    Parameters
    ----------
    point : mapping
        A frame's node fields (``director_tilt_deg``, ``thickness_guarded`` and their
        ``_2``, ... of later parts; NaN off a part).
    held : (k,) int, optional
        The nodes whose directors a clamp holds (their tilt is imposed).

    Returns
    -------
    dict or None
        ``bound_deg``, ``nodes`` (how many are past the bound or guarded), ``guarded`` (how
        many at the cap), ``max_deg`` (the largest tilt of those), ``first`` (their first ten
        node ids), ``held_directors`` (whether a support holds any director); None when no
        node is flagged.
    """
    tilts = [np.asarray(v, dtype=float) for v in parts_fields(point, "director_tilt_deg")]
    guards = [np.asarray(v, dtype=float) for v in parts_fields(point, "thickness_guarded")]
    if not tilts and not guards:
        return None
    n = len((tilts or guards)[0])
    tilt = np.vstack(tilts) if tilts else np.full((1, n), np.nan)
    guard = np.vstack(guards) if guards else np.zeros((1, n))
    past = np.any(np.nan_to_num(tilt, nan=0.0) > TILT_BOUND_DEG, axis=0)
    guarded = np.any(np.nan_to_num(guard, nan=0.0) > 0.0, axis=0)
    free = np.ones(n, dtype=bool)
    if held is not None and len(held):
        free[np.asarray(held, dtype=np.int64)] = False
    flagged = np.flatnonzero((past | guarded) & free)
    if not flagged.size:
        return None
    largest = tilt[:, flagged]
    return {
        "bound_deg": TILT_BOUND_DEG,
        "nodes": int(flagged.size),
        "guarded": int(np.count_nonzero(guarded & free)),
        "max_deg": float(np.nanmax(largest)) if np.isfinite(largest).any() else None,
        "first": [int(i) for i in flagged[:10]],
        "held_directors": bool(held is not None and len(held)),
    }


def say_tilted(flag: dict | None) -> None:
    """Warn once about ``tilted_directors``'s flag, naming the remedy."""
    if flag is None:
        return
    largest = "" if flag["max_deg"] is None else f" (up to {flag['max_deg']:.1f} deg)"
    remedy = (
        "Nothing holds a director in this model: a fibrous body's uniform tilt is then a "
        "zero-energy mode the quasi-static solvers leave where their path puts it "
        "(docs/theory.md §1, 'Without a clamp the tilt is not decided'). Hold the directors "
        "somewhere (a clamp: the part's options clamped = ..., with a [[fix]] of every DOF or "
        "of alpha and beta there), or read the tilt and thickness from an explicit run"
        if not flag["held_directors"]
        else "Check what holds the body's directors (a clamp, a tool), or refine where they turn"
    )
    warnings.warn(
        f"{flag['nodes']} node(s) end with directors tilted more than "
        f"{flag['bound_deg']:.1f} deg from the normal{largest}, {flag['guarded']} with the "
        "thickness along the director at the 5 h cap (thickness_guarded = 1; nodes "
        f"{', '.join(map(str, flag['first']))}; summary.json tilted_directors): the tilt and "
        f"thickness there are not the shell's answer. {remedy}",
        UserWarning,
        stacklevel=2,
    )
