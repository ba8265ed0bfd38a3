"""The three models of every paper case and how the report names and draws them.

Each paper case (validation.paper.case) solves the same specimen three times: the fibrous shell
with the thickness along the director from the nodal normals (its default), the fibrous shell
with Bai's Eq. 15 as published (each element's own normal) and the Mindlin shell. This module
holds their keys (``KINEMATICS``, used in results.json and in the file names), the element and
thickness option each one builds, their labels, colours and markers in the figures and their
names in the checks, the defaults of the paper cases' solve, and how the report states the
Mindlin shell's calibration (``calibration_parameters``, ``calibration_title``).
"""

from __future__ import annotations

from typing import Any, Literal

import numpy as np

from fibreshell.calibration import Calibration
from materials import Fabric

__all__ = [
    "CHECK_NAMES",
    "COLOURS",
    "ELEMENT",
    "FIBROUS_THICKNESS",
    "INCREMENTS",
    "KINEMATICS",
    "LABELS",
    "MARKERS",
    "PAPER",
    "Kinematics",
    "calibration_parameters",
    "calibration_title",
]

PAPER = "Bai, Colmars, Naouar, Boisse, Composites Part A 139 (2020) 106135"
# The three models of every paper case, by their key in results.json and in the file names:
# the fibrous shell with the thickness along the director h_m = h / (V . N) from the
# area-weighted nodal normal N (its default), the fibrous shell with Bai's Eq. 15 as published
# (each element's own normal) and the Mindlin shell.
Kinematics = Literal["fibrous", "fibrous_element", "mindlin"]
KINEMATICS: tuple[Kinematics, ...] = ("fibrous", "fibrous_element", "mindlin")
ELEMENT: dict[Kinematics, str] = {
    "fibrous": "fibrous",
    "fibrous_element": "fibrous",
    "mindlin": "mindlin",
}  # the kinematics argument of validation.specimens.build
FIBROUS_THICKNESS: dict[Kinematics, str] = {"fibrous": "nodal", "fibrous_element": "element"}
COLOURS: dict[Kinematics, str] = {
    "fibrous": "tab:blue",
    "fibrous_element": "tab:green",
    "mindlin": "tab:orange",
}
MARKERS: dict[Kinematics, str] = {"fibrous": "o", "fibrous_element": "s", "mindlin": "^"}
LABELS: dict[Kinematics, str] = {
    "fibrous": "FibrousShell, nodal h_m (default)",
    "fibrous_element": "FibrousShell, Bai Eq. 15",
    "mindlin": "MindlinShell (S3-like kinematics)",
}
INCREMENTS = 10  # load increments of Static (each for gravity and the displacement), default
# The residual ratio at or below which an arc-length iteration of the paper cases' Static steps
# with its increment's last factorisation (Static's arc_chords, docs/theory.md §6.6 "Chord
# steps"): measured on the cases' runs (benchmarks/arc_chords.py).
ARC_CHORDS = 1e-3
# Names of the kinematics in the checks' names (the default fibrous run keeps the plain name).
CHECK_NAMES: dict[Kinematics, str] = {
    "fibrous": "fibrous",
    "fibrous_element": "fibrous Eq. 15",
    "mindlin": "Mindlin",
}


def _slope(law) -> float:
    return float(np.asarray(law.slope(np.array(0.0))))


def calibration_parameters(calibration: Calibration, fabric: Fabric) -> dict[str, Any]:
    """The rows of a paper case's parameters table that state how its Mindlin shell is made
    of the fabric (fibreshell.calibration): the rule's name and sentence and the numbers it
    chose, units in the names.

    Parameters
    ----------
    calibration : fibreshell.calibration.Calibration
    fabric : materials.Fabric
        The fibrous shell's fabric.

    Returns
    -------
    dict
        Row name -> value (str or float).
    """
    numbers = calibration.numbers(fabric)
    rows: dict[str, Any] = {
        "Mindlin calibration": f"{calibration.name}: {calibration.describe(None)['rule']}"
    }
    if calibration.name == "initial-slope":
        rows.update(
            {
                "Mindlin E1 = 12 B0 / h^3 (MPa)": numbers["E1_MPa"],
                "Mindlin E2 (MPa)": numbers["E2_MPa"],
                "Mindlin G13 / E": numbers["shear_ratio"],
                "Mindlin membrane E1 h (N/mm)": numbers["membrane_stiffness_warp_N_per_mm"],
            }
        )
        return rows
    rows.update(
        {
            "Mindlin tension law (warp)": numbers["tension_law_warp"],
            "Mindlin in-plane shear law": numbers["shear_law"],
            "Mindlin bending law (warp)": numbers["bending_law_warp"],
            "Mindlin bending law (weft)": numbers["bending_law_weft"],
            "Mindlin transverse shear S (N/mm)": numbers["transverse_shear_N_per_mm"],
            "Mindlin twisting D_t = B0 / 2 (N mm)": numbers["twisting_N_mm"],
        }
    )
    if calibration.bending_scale != 1.0:
        rows["Mindlin bending scale"] = calibration.bending_scale
    return rows


def calibration_title(calibration: Calibration, fabric: Fabric) -> str:
    """One line for a figure's title or a paragraph: which Mindlin section the case compares
    with and its numbers, e.g. "MindlinShell(fabric): the fabric's own laws, S = 1.48 N/mm,
    D_t = 25 N mm"."""
    numbers = calibration.numbers(fabric)
    if calibration.name == "initial-slope":
        return (
            f"Mindlin calibration 'initial-slope': E = 12 B0 / h^3 = {numbers['E1_MPa']:.3g} MPa "
            f"(membrane {numbers['membrane_stiffness_warp_N_per_mm']:.3g} N/mm, bending "
            f"{_slope(fabric.bending):.3g} N mm at every curvature), G13 / E = "
            f"{numbers['shear_ratio']:g}"
        )
    scale = (
        f", bending laws x {calibration.bending_scale:.3g}"
        if calibration.bending_scale != 1.0
        else ""
    )
    return (
        f"MindlinShell(fabric), calibration '{calibration.name}': the fabric's own laws{scale}, "
        f"S = {numbers['transverse_shear_N_per_mm']:.3g} N/mm, D_t = "
        f"{numbers['twisting_N_mm']:.3g} N mm"
    )
