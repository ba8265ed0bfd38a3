"""Quasi-static honesty of an explicit run: the kinetic energy against the external work.

An explicit run of a slow process (forming, a drape) is quasi-static only when the inertia it
adds is small: the kinetic energy KE a small part of the work W done on the model. The
field's rule (Abaqus Analysis User's Guide, "Quasi-static analysis": the kinetic energy of the
deforming material should not exceed a small fraction, typically 5 % to 10 %, of its internal
energy over most of the process) is the default bound here, at its upper end: KE / W <= 0.1
(W >= the internal energy, damping and friction taking their share). Mass scaling (added
mass) and time scaling (a shorter duration than the process's) raise KE / W; the report states
both with the KE / W they produced.

Early in a run both energies are tiny and their ratio says nothing (a punch in the air, the
first waves through the blank): the ratio is watched from ``KINETIC_CHECK_FROM`` of the
duration on.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = ["KINETIC_BOUND", "KINETIC_CHECK_FROM", "QuasiStaticWatch", "kinetic_over_work"]

#: The default largest KE / W of a quasi-static run (the upper end of the field's 5-10 %).
KINETIC_BOUND = 0.1
#: The part of the duration before which KE / W is not watched (both energies tiny).
KINETIC_CHECK_FROM = 0.1


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


@dataclass
class QuasiStaticWatch:
    """Watches KE / W over a run of ``duration`` s and warns once (UserWarning, with the
    time and the ratio) when it exceeds ``bound`` after ``KINETIC_CHECK_FROM`` of the
    duration; ``bound`` None watches without warning. Kept in a checkpoint with the run."""

    bound: float | None
    duration: float
    largest: float = 0.0  # the largest KE / W watched, and when (s)
    largest_at: float | None = None
    exceeded_at: float | None = None  # when KE / W first passed the bound (s)
    final: float = 0.0

    def observe(self, time: float, kinetic: float, external_work: float) -> None:
        """One energy record at ``time`` (s): KE and W_ext (N mm)."""
        ratio = kinetic / external_work if external_work > 0.0 else 0.0
        self.final = ratio
        if time < KINETIC_CHECK_FROM * self.duration:
            return
        if ratio > self.largest:
            self.largest, self.largest_at = ratio, time
        if self.bound is not None and ratio > self.bound and self.exceeded_at is None:
            self.exceeded_at = time
            warnings.warn(
                f"the run is not quasi-static: at t = {time:.6g} s the kinetic energy is "
                f"{ratio:.3g} of the external work ({kinetic:.4g} of {external_work:.4g} N mm), "
                f"more than kinetic_bound = {self.bound:g}: inertia shapes the answer. For a "
                "quasi-static process, slow the loading (a longer duration), lower the mass "
                "scaling or damp it; for a dynamic run, set kinetic_bound=None",
                UserWarning,
                stacklevel=4,
            )

    def report(
        self, added_mass_ratio: float, process_duration: float | None = None
    ) -> dict[str, Any]:
        """What the run's inertia did, for ``result.info["quasi_static"]``: the bound, the
        final and largest KE / W (after ``checked_from_s``) and when, when it first passed the
        bound (None: never), the mass scaling (added mass over the model's mass) and the time
        scaling (``process_duration`` / duration, None when the process's duration is not
        given)."""
        return {
            "kinetic_bound": self.bound,
            "checked_from_s": KINETIC_CHECK_FROM * self.duration,
            "kinetic_over_work_final": self.final,
            "kinetic_over_work_largest": self.largest,
            "largest_at_s": self.largest_at,
            "exceeded_at_s": self.exceeded_at,
            "added_mass_ratio": added_mass_ratio,
            "duration_s": self.duration,
            "process_duration_s": process_duration,
            "time_scaling": None if process_duration is None else process_duration / self.duration,
        }
