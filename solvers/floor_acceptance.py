"""Increments Static accepted at the round-off floor above its tolerance, counted and told
(docs/theory.md §6.5, "The round-off floor").

Why. Where a full Newton step moves nothing (solvers.newton.at_round_off_floor) and the
residual is already small, Newton ends: no update removes a residual made of the rounding of
nearly equal metrics. With frozen contact sets, the state is then accepted where the
unilateral contact law leaves a residual ratio up to 1e-3 (solvers.newton.settle_contacts with
``floor``): the frozen law Newton balanced and the return mapping's law differ by the
elastic slip and penetration they round differently. The frictional table at Static's
defaults was accepted at 4.5e-4 against a tolerance of 1e-8, and
``info["round_off_converged"]`` counted none of it. The answers there match their closed
forms, but the user is told: each such acceptance is counted, its ratio recorded, and the solve
warns once with the largest.
"""

from __future__ import annotations

import warnings

__all__ = ["note_floor_acceptance", "report_floor_acceptances"]


def note_floor_acceptance(info: dict, ratio: float, tol: float, load_factor: float) -> None:
    """Count a state accepted at the round-off floor at residual ratio ``ratio`` above ``tol``
    in ``info["round_off_converged"]`` and record (load factor, ratio) in
    ``info["floor_accepted"]``; nothing where ``ratio <= tol``."""
    if not ratio > tol:
        return
    info["round_off_converged"] += 1
    info["floor_accepted"].append((float(load_factor), float(ratio)))


def report_floor_acceptances(info: dict, tol: float) -> None:
    """Summarise ``info["floor_accepted"]`` in ``info["round_off_accepted"]`` (``count``,
    ``largest_ratio``, ``at_load_factor``, ``tol``) and warn once (UserWarning) naming the
    largest ratio and why; nothing where there is none."""
    accepted = info.get("floor_accepted") or []
    if not accepted:
        return
    at, largest = max(accepted, key=lambda pair: pair[1])
    info["round_off_accepted"] = {
        "count": len(accepted),
        "largest_ratio": largest,
        "at_load_factor": at,
        "tol": tol,
    }
    warnings.warn(
        f"{len(accepted)} Newton solve(s) accepted at the round-off floor above the tolerance "
        f"{tol:g}: residual ratios up to {largest:.3g} (load factor {at:.4g}; "
        "info['floor_accepted']), where a full Newton step moved nothing: the residual left "
        "is the rounding of the internal forces or, with contact, what the contact law's "
        "return mapping leaves against the frozen contact law Newton balanced. Check the "
        "answer against a looser load or, with contact, a finer contact tolerance (a larger "
        "penalty, augmentations) if it matters",
        UserWarning,
        stacklevel=2,
    )
