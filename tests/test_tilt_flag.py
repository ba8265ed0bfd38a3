"""A run whose directors end nearly in the surface says so: summary.json's
``tilted_directors`` and a warning naming the remedy (fibreshell/tilt_flag.py).

Reference: the fibrous shell's thickness guard, V.N >= 0.2 (docs/theory.md §1.4): a tilt from
the normal past acos(0.2) = 78.46 deg caps the thickness along the director at 5 h. A flat
fibrous strip pulled without a clamp has a zero-energy uniform tilt (docs/theory.md §1,
"Without a clamp the tilt is not decided"): Static leaves its directors 88-89 deg off the
normal, at the cap."""

import math
import warnings

import numpy as np
import pytest

from fibreshell.case import case_from_data
from fibreshell.run import run_case

STRIP = {
    "mesh": {"rectangle": {"lx": 100.0, "ly": 20.0, "nx": 4, "ny": 2}},
    "part": [
        {
            "element": "fibrous",
            "material": {
                "thickness": 0.5,
                "areal_density": 5e-10,
                "tension": 1200.0,
                "shear": 0.5,
                "bending": 1.0,
            },
        }
    ],
    "fix": [
        {"nodes": "left", "dofs": ["ux", "uz"]},
        {"nodes": {"x_max": "0%", "y_max": "0%"}, "dofs": ["uy"]},
        {"nodes": "right", "dofs": ["uz"]},
    ],
    "displace": [{"nodes": "right", "ux": 10.0}],
    "solver": {"kind": "static", "increments": 2},
}


def test_the_bound_is_the_thickness_guard():
    from fibreshell.tilt_flag import TILT_BOUND_DEG

    assert TILT_BOUND_DEG == pytest.approx(math.degrees(math.acos(0.2)), abs=1e-12)


def test_a_strip_pulled_without_a_clamp_is_flagged_with_its_remedy(tmp_path):
    case = case_from_data(STRIP, tmp_path / "strip.toml")
    with pytest.warns(UserWarning, match="Hold the directors somewhere") as said:
        run = run_case(case, tmp_path / "out", progress=False, write_frames=False)
    flag = run.summary["tilted_directors"]
    assert flag["nodes"] == 15 and flag["guarded"] == 15  # every node of the 5 x 3 grid
    assert flag["max_deg"] > math.degrees(math.acos(0.2))
    assert not flag["held_directors"]
    assert any("tilted more than 78.5 deg" in str(w.message) for w in said)


def test_a_clamped_strip_pulled_is_not_flagged(tmp_path):
    data = dict(STRIP, fix=[{"nodes": "left"}, {"nodes": "right", "dofs": ["uy", "uz"]}])
    data["part"] = [dict(STRIP["part"][0], options={"clamped": "left"})]
    case = case_from_data(data, tmp_path / "strip.toml")
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        run = run_case(case, tmp_path / "out", progress=False, write_frames=False)
    assert "tilted_directors" not in run.summary
    assert not [w for w in said if "tilted more than" in str(w.message)]
    assert np.isfinite(run.summary["director_tilt_deg"]["max"])
