"""Quasi-static honesty of an explicit run: the kinetic energy against the external work.

An explicit run of a slow process (forming, a drape) is quasi-static only when the inertia it
adds is small: the kinetic energy KE a small part of the work W done on the model. The
field's rule (Abaqus Analysis User's Guide, "Quasi-static analysis": the kinetic energy of the
deforming material should not exceed a small fraction, typically 5 % to 10 %, of its internal
energy over most of the process) is the default bound here, at its upper end: KE / W <= 0.1
(W >= the internal energy, damping and friction taking their share). Mass scaling (added
mass) and time scaling (a shorter duration than the process's) raise KE / W; the report states
both with the KE / W they produced.

Early in a run both energies are tiny and their ratio says nothing (a punch touching a blank
accelerates it before it stretches it: KE / W = 0.4-0.7 while W is below 1e-4 of the work at
the end): the ratio is judged from ``KINETIC_CHECK_FROM`` of the duration on, where the work
done has reached ``KINETIC_WORK_FLOOR`` of the run's work at its end.
"""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np

from solvers.common import outside_stacklevel

__all__ = [
    "KINETIC_BOUND",
    "KINETIC_CHECK_FROM",
    "KINETIC_SHARE",
    "KINETIC_WORK_FLOOR",
    "judged_records",
    "kinetic_over_work",
    "quasi_static_report",
]

#: The default largest KE / W of a quasi-static run (the upper end of the field's 5-10 %).
KINETIC_BOUND = 0.1
#: The part of the duration before which KE / W is not judged.
KINETIC_CHECK_FROM = 0.1
#: The largest share of the judged time during which KE / W may be above the bound (the solver's
#: warning and the forming cases' checks): the field's rule (Abaqus/Explicit) asks for a small KE /
#: W throughout the majority of the process; a tenth is stricter than a majority. A flange that
#: snaps over a die's rim releases a short burst of kinetic energy that this rule lets through and
#: the largest KE / W (reported beside it) shows.
KINETIC_SHARE = 0.1
#: Nor while the work done is below this part of the work at the end of the run.
KINETIC_WORK_FLOOR = 0.01


def kinetic_over_work(kinetic: np.ndarray, external_work: np.ndarray) -> np.ndarray:
    """KE / W_ext per record, 0 where no work has been done (W_ext <= 0: from rest the
    kinetic energy comes from the work, KE <= W up to the integration error).

    Parameters
    ----------
    kinetic, external_work : (k,) float, N mm

    Returns
    -------
    (k,) float, dimensionless.
    """
    kinetic = np.asarray(kinetic, dtype=float)
    work = np.asarray(external_work, dtype=float)
    return np.divide(kinetic, work, out=np.zeros_like(kinetic), where=work > 0.0)


def judged_records(time, work, duration: float, final_work: float | None = None) -> np.ndarray:
    """Where KE / W is judged: the records after the first KINETIC_CHECK_FROM of the
    ``duration`` (s) whose external work (N mm) is positive and at least KINETIC_WORK_FLOOR of
    the final work (``final_work``; the last of ``work`` when None). ``time`` and ``work``:
    (k,) arrays of the same records. Returns a (k,) boolean mask.

    Early in a run the work is a small fraction of its end and KE / W reads large on tiny
    energies; the floor keeps those records from deciding a quasi-static check."""
    time = np.asarray(time, dtype=float)
    work = np.asarray(work, dtype=float)
    final = float(work[-1]) if final_work is None else float(final_work)
    return (
        (time >= KINETIC_CHECK_FROM * duration)
        & (work >= KINETIC_WORK_FLOOR * final)
        & (work > 0.0)
    )


def quasi_static_report(
    energies: dict[str, np.ndarray],
    bound: float | None,
    duration: float,
    added_mass_ratio: float,
    process_duration: float | None = None,
    warn: bool = True,
    tool_note: str | None = None,
) -> dict[str, Any]:
    """What a run's inertia did, from its energy records, and one UserWarning (with the time,
    the ratio and the share) if KE / W stayed above ``bound`` for more than KINETIC_SHARE of
    the judged time (``bound`` None or ``warn`` False: reported, not warned). A shorter burst
    above the bound (a flange snapping over a die's rim) is reported (``exceeded_at_s``, the
    largest KE / W) without a warning: the rule the forming cases judge a run by is the
    warning's rule, so a run the report accepts is not one the solver warned about.

    Parameters
    ----------
    energies : the run's records: "time" (s), "kinetic" and "external_work" (N mm), (k,) each.
    bound : the largest KE / W of a quasi-static run, or None.
    duration : s, the run's.
    added_mass_ratio : the mass scaling's added mass over the elements' mass (the tools'
        masses aside).
    process_duration : s, the real process's duration when the run is shorter (time scaling).
    warn : False for a run that stopped (its error says more).
    tool_note : what the kinetic energy is where it is not the body's (force-driven tools
        flying loose, solvers/tool_force_watch.py ``kinetic_note``): said in the warning in
        place of the advice on the loading's pace.

    Returns
    -------
    dict
        ``kinetic_bound``; ``checked_from_s`` (KINETIC_CHECK_FROM of the duration);
        ``kinetic_over_work_final``; ``kinetic_over_work_largest`` where judged and when
        (``largest_at_s``); ``exceeded_at_s``, when it first passed the bound (None: never);
        ``exceeded_share``, the share of the judged time during which KE / W was above the
        bound (each record standing for the time since the one before; None without a bound
        or a judged record): the field's rule asks for a small KE / W "throughout the majority
        of the process" (Abaqus/Explicit's quasi-static guidance), which a short burst keeps
        where the largest value does not; ``added_mass_ratio``; ``duration_s``,
        ``process_duration_s`` and ``time_scaling`` (process_duration / duration, None
        without it).
    """
    time = np.asarray(energies["time"], dtype=float)
    work = np.asarray(energies["external_work"], dtype=float)
    ratio = kinetic_over_work(energies["kinetic"], work)
    judged = judged_records(time, work, duration)
    largest = largest_at = exceeded_at = share = None
    if judged.any():
        index = int(np.flatnonzero(judged)[np.argmax(ratio[judged])])
        largest, largest_at = float(ratio[index]), float(time[index])
        if bound is not None:
            above = judged & (ratio > bound)
            spans = np.diff(time, prepend=time[0])  # each record: the time since the one before
            total = float(spans[judged].sum())
            share = float(spans[above].sum()) / total if total > 0.0 else 0.0
            if above.any():
                first = int(np.flatnonzero(above)[0])
                exceeded_at = float(time[first])
        if exceeded_at is not None and share is not None and share > KINETIC_SHARE and warn:
            warnings.warn(
                f"the run is not quasi-static: at t = {exceeded_at:.6g} s the kinetic energy "
                f"is {ratio[first]:.3g} of the external work ({energies['kinetic'][first]:.4g} "
                f"of {work[first]:.4g} N mm; at most {largest:.3g}, at t = {largest_at:.6g} s), "
                f"more than kinetic_bound = {bound:g}, and is above it for {share:.3g} of "
                f"the judged time (more than KINETIC_SHARE = {KINETIC_SHARE:g}): "
                + (
                    "inertia shapes the answer. For a quasi-static process, slow the loading "
                    "(a longer duration), lower the mass scaling or damp it"
                    if tool_note is None
                    else tool_note
                )
                + "; for a dynamic run, set kinetic_bound=None",
                UserWarning,
                stacklevel=outside_stacklevel(),
            )
    return {
        "kinetic_bound": bound,
        "checked_from_s": KINETIC_CHECK_FROM * duration,
        "kinetic_over_work_final": float(ratio[-1]),
        "kinetic_over_work_largest": largest,
        "largest_at_s": largest_at,
        "exceeded_at_s": exceeded_at,
        "exceeded_share": share,
        "added_mass_ratio": added_mass_ratio,
        "duration_s": duration,
        "process_duration_s": process_duration,
        "time_scaling": None if process_duration is None else process_duration / duration,
    }
