"""The responses a fit compares (fibreshell/identify.py): the unit of each data column, the
warning where columns of different units are fitted without their measurement uncertainty,
and the residual of each column apart.

Why. The fit minimises the sum of the squared residuals over every response, each divided by
its sigma (1 where none is given). A deflection in mm and a clamp reaction in N then weigh by
their numbers: Peirce's tips of 9 to 63 mm against reactions of about 0.002 N, the reactions
carry nothing, and a fit of B alone with the areal density left wrong reported B with a tight
interval and success while its reactions were off by 3 times (a review). Only the
measurement uncertainties (``sigma``) make such columns comparable; the residual of each
column apart shows which one the fit does not follow.
"""

from __future__ import annotations

import re
import warnings

import numpy as np

__all__ = ["UNITS", "mixed_units_warning", "response_residuals", "unit_of"]

#: The unit of a data column by its name (fibreshell.sweep.summary_row's columns, and a
#: profile's x and z), first match first.
UNITS = (
    (r"x|z", "mm"),
    (r"reaction_.*|.*_force_[xyz]", "N"),
    (r"displacement_.*|.*_displacement_[xyz]", "mm"),
    (r".*_deg", "deg"),
    (r"max_fibre_strain|final_load_factor", "1"),
    (r"wall_time_s", "s"),
    (r"steps|tilted_directors", "count"),
)


def unit_of(column: str) -> str | None:
    """The unit of the response column ``column`` ("mm", "N", "deg", "1", "s", "count"), or
    None for a name the table ``UNITS`` does not know."""
    for pattern, unit in UNITS:
        if re.fullmatch(pattern, column):
            return unit
    return None


def mixed_units_warning(columns: list[str], sigma: dict[str, float]) -> None:
    """Warn (UserWarning) where the response ``columns`` without a ``sigma`` are of different
    units (or of units unknown beside others): their residuals are summed as plain numbers,
    so the column with the larger numbers decides the fit alone."""
    bare = [c for c in columns if c not in sigma]
    units = {c: unit_of(c) for c in bare}
    if len(set(units.values())) < 2:
        return
    listed = ", ".join(f"{c} ({u or 'unit unknown'})" for c, u in units.items())
    warnings.warn(
        f"responses in different units are fitted without their measurement uncertainty: "
        f"{listed}; their residuals are added as plain numbers, so the column with the larger "
        "numbers decides the fit and the others weigh next to nothing. Give each its sigma "
        "(fibreshell identify --sigma COLUMN=VALUE,...; identify's sigma) in its own unit; "
        "the residual of each response is reported apart (residual_rms_by_response)",
        UserWarning,
        stacklevel=3,
    )


def response_residuals(
    columns: list[str], residuals: np.ndarray, measured: np.ndarray, sigma: dict[str, float]
) -> dict[str, dict[str, float | str]]:
    """Per response column: ``rms`` of its residuals over its sigma (model minus measured,
    divided by sigma, 1 where none is given: then in the column's unit), and ``measured_rms``,
    the RMS of its measured values over the same sigma, the scale it is read against;
    ``unit``: "sigma" where the column has one, else its data unit (``unit_of``).

    Parameters
    ----------
    columns : list of str
        The response columns, in the order they repeat within each data row.
    residuals : numpy.ndarray, shape (m,)
        Model minus measured over sigma, row by row, ``columns`` inside each row.
    measured : numpy.ndarray, shape (m,)
        The measured values (data units), in the same order.
    sigma : dict
        Column -> its measurement uncertainty (data units); 1 where absent.
    """
    k = len(columns)
    table: dict[str, dict[str, float | str]] = {}
    for j, column in enumerate(columns):
        scale = float(sigma.get(column, 1.0))
        table[column] = {
            "rms": float(np.sqrt(np.mean(np.asarray(residuals)[j::k] ** 2))),
            "measured_rms": float(np.sqrt(np.mean((np.asarray(measured)[j::k] / scale) ** 2))),
            "unit": "sigma" if column in sigma else (unit_of(column) or "data unit"),
        }
    return table
