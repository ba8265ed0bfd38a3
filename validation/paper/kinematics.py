"""The three models of every paper case and how the report names and draws them.

Each paper case (validation.paper.case) solves the same specimen three times: the fibrous shell
with the thickness along the director from the nodal normals (its default), the fibrous shell
with Bai's Eq. 15 as published (each element's own normal) and the Mindlin shell. This module
holds their keys (``KINEMATICS``, used in results.json and in the file names), the element and
thickness option each one builds, their labels, colours and markers in the figures and their
names in the checks, and the defaults of the paper cases' solve.
"""

from __future__ import annotations

from typing import Literal

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
    "SHEAR_RATIO",
    "Kinematics",
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
    "mindlin": "MindlinShell (S3-like)",
}
INCREMENTS = 10  # load increments of Static (each for gravity and the displacement), default
SHEAR_RATIO = 0.5  # Mindlin G13 / E (stated parameter), default
# Names of the kinematics in the checks' names (the default fibrous run keeps the plain name).
CHECK_NAMES: dict[Kinematics, str] = {
    "fibrous": "fibrous",
    "fibrous_element": "fibrous Eq. 15",
    "mindlin": "Mindlin",
}
