"""A case file's material tables refused with what was wrong, where (the file, the table, the
key) and what to give (fibreshell/case_materials.py), never a constructor's traceback text."""

from __future__ import annotations

import pytest

from fibreshell import CaseError
from fibreshell.case import case_from_data

FABRIC = {"thickness": 0.3, "areal_density": 2.85e-10, "tension": 1200.0, "shear": 0.2}


def _case(material: dict, element: str = "fibrous"):
    data = {
        "mesh": {"rectangle": {"lx": 40.0, "ly": 20.0, "nx": 4, "ny": 2}},
        "part": [{"element": element, "material": material}],
        "solver": {"kind": "static"},
    }
    return case_from_data(data, "laws.toml")


BAD = {
    "unsorted weft table": (
        {**FABRIC, "bending": 7.5,
         "bending_weft": {"table": {"x": [0.0, 2e-3, 1e-3], "y": [0.0, 0.008, 0.0075]}}},
        "fibrous", r"\[part\[0\]\.material\.bending_weft\.table\]: .*strictly increasing",
    ),
    "thickness a boolean": (
        {**FABRIC, "bending": 7.5, "thickness": True}, "fibrous",
        r"\[part\[0\]\.material\.thickness\]: expected a finite number, got True",
    ),
    "no bending": (
        dict(FABRIC), "fibrous",
        r"\[part\[0\]\.material\]: missing key 'bending': a fabric needs",
    ),
    "a bilinear law without its knee": (
        {**FABRIC, "bending": {"bilinear": {"initial": 7.5, "final": 0.5}}}, "fibrous",
        r"\[part\[0\]\.material\.bending\.bilinear\]: missing key 'knee'",
    ),
    "a Mindlin fabric without tension and bending": (
        {"thickness": 0.3, "areal_density": 2.85e-10, "shear": 0.2, "bending_weft": 7.0},
        "mindlin", r"missing keys 'tension', 'bending': a Mindlin part of a fabric",
    ),
    "tension_only not a boolean": (
        {**FABRIC, "bending": 7.5, "tension": {"linear": 1200.0, "tension_only": "yes"}},
        "fibrous", r"\[part\[0\]\.material\.tension\.tension_only\]: expected true or false",
    ),
}  # fmt: skip


@pytest.mark.parametrize("material, element, message", BAD.values(), ids=list(BAD))
def test_a_bad_material_table_is_refused_naming_the_key(material, element, message):
    with pytest.raises(CaseError, match=message) as refused:
        _case(material, element)
    text = str(refused.value)
    assert "__init__" not in text and "positional argument" not in text
    assert "unknown option" not in text and "law table, got True" not in text
