"""The convergence test of the quasi-static solvers (Static, DynamicRelaxation): the
out-of-balance against a force reference (docs/theory.md §6.4, §6.6).

Both judge a residual by the ratio ||r_F|| / F_ref with

    F_ref = max(||F_ext||, ||F_int||, ||M_ext|| / L_e, ||M_int|| / L_e)

where the internal forces include the reactions (so a displacement-driven problem has a
non-zero reference) and the moments count as forces over one element L_e (the median element
edge; under end moments alone, pure bending, the nodal forces all tend to zero and ||F_int||
alone would judge round-off against round-off). The residual moments are judged the same way
against M_ref = F_ref L_e. ``Equilibrium`` holds the external loads of one load level and gives
both ratios of a residual; the solvers differ in details that are parameters here, so that each
keeps its numbers:

- ``moments``: whether moments enter at all (Static: always; DynamicRelaxation: only when the
  model has rotational DOFs);
- ``moment_reference``: "force" for M_ref = F_ref L_e (Static), "largest" for
  M_ref = max(||M_ext||, ||M_int||, F_ref L_e) (DynamicRelaxation; the same value up to the
  rounding of F_ref L_e);
- ``floor``: a least F_ref (Static: 1e-300; DynamicRelaxation: 0, a zero reference giving
  ratio 0).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["MOMENT_REFERENCES", "Equilibrium", "Ratios"]

MOMENT_REFERENCES = ("force", "largest")


@dataclass(frozen=True)
class Ratios:
    """The residual ratios of one state.

    force : ||r_F|| / F_ref (0 when F_ref is 0).
    moment : ||r_M|| / M_ref (0 without moments, or when M_ref is 0).
    largest : the larger of the two (``force`` without moments).
    force_reference : F_ref, N.
    moment_reference : M_ref, N mm (0 without moments).
    """

    force: float
    moment: float
    largest: float
    force_reference: float
    moment_reference: float

    def checked(self) -> float:
        """``largest``, or inf when it or F_ref is not finite: an overflowing state would
        otherwise divide its own residual by an infinite reference and pass as converged."""
        if not (np.isfinite(self.force_reference) and np.isfinite(self.largest)):
            return math.inf
        return self.largest


class Equilibrium:
    """The force-reference convergence test at one load level (module docstring).

    Parameters
    ----------
    f_ext, m_ext : (n, 3) float
        External forces (N) and moments (N mm).
    element_size : float
        L_e, mm: the length over which a moment counts as a force.
    moments : bool
        Moments enter the reference and are judged (default True).
    moment_reference : "force" or "largest"
        M_ref = F_ref L_e, or max(||M_ext||, ||M_int||, F_ref L_e).
    floor : float
        The least F_ref, N (default 0).
    """

    def __init__(
        self,
        f_ext: np.ndarray,
        m_ext: np.ndarray,
        element_size: float,
        *,
        moments: bool = True,
        moment_reference: str = "force",
        floor: float = 0.0,
    ):
        if moment_reference not in MOMENT_REFERENCES:
            raise ValueError(
                f"moment_reference must be one of {MOMENT_REFERENCES}, got {moment_reference!r}"
            )
        self.element_size = element_size
        self.moments = bool(moments)
        self.moment_reference = moment_reference
        self.floor = float(floor)
        self.f_ext_norm = float(np.linalg.norm(f_ext))
        self.m_ext_norm = float(np.linalg.norm(m_ext))

    def references(self, f_int: np.ndarray, m_int: np.ndarray) -> tuple[float, float]:
        """(F_ref N, M_ref N mm) with the internal forces f_int (n, 3) and moments m_int (n, 3)
        of a state (M_ref 0 without moments)."""
        force_ref = max(self.f_ext_norm, float(np.linalg.norm(f_int)))
        if not self.moments:
            return (max(force_ref, self.floor) if self.floor else force_ref), 0.0
        m_int_norm = float(np.linalg.norm(m_int))
        force_ref = max(force_ref, max(self.m_ext_norm, m_int_norm) / self.element_size)
        if self.floor:
            force_ref = max(force_ref, self.floor)
        moment_ref = force_ref * self.element_size
        if self.moment_reference == "largest":
            moment_ref = max(self.m_ext_norm, m_int_norm, moment_ref)
        return force_ref, moment_ref

    def ratios(
        self,
        force_residual: np.ndarray,
        moment_residual: np.ndarray,
        f_int: np.ndarray,
        m_int: np.ndarray,
    ) -> Ratios:
        """The ratios of a residual: ``force_residual`` (its norm against F_ref, N) and
        ``moment_residual`` (against M_ref, N mm; ignored without moments), any shapes, at a
        state with internal forces f_int (n, 3) and moments m_int (n, 3)."""
        force_ref, moment_ref = self.references(f_int, m_int)
        force = float(np.linalg.norm(force_residual)) / force_ref if force_ref > 0 else 0.0
        if not self.moments:
            return Ratios(force, 0.0, force, force_ref, 0.0)
        moment = float(np.linalg.norm(moment_residual)) / moment_ref if moment_ref > 0 else 0.0
        return Ratios(force, moment, max(force, moment), force_ref, moment_ref)
