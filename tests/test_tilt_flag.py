"""A run whose directors end nearly in the surface says so: summary.json's
``tilted_directors`` and a warning naming the remedy (fibreshell/tilt_flag.py).

Reference: the fibrous shell's thickness guard, V.N >= 0.2 (docs/theory.md §1.4): a tilt from
the normal past acos(0.2) = 78.46 deg caps the thickness along the director at 5 h. A flat
fibrous strip pulled without a clamp has a zero-energy uniform tilt (docs/theory.md §1,
"Without a clamp the tilt is not decided"): Static's stability search used to turn along it
and left the directors 88-89 deg off the normal, at the cap; it no longer takes a neutral mode
for an unstable one (solvers/neutral_modes.py), so the strip ends normal and unflagged, and the
flag is read here on frames whose directors are tilted."""

import math
import warnings

import numpy as np
import pytest

from fibreshell.case import case_from_data
from fibreshell.run import run_case
from fibreshell.tilt_flag import say_tilted, tilted_directors

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


def test_a_strip_pulled_without_a_clamp_ends_normal_and_is_not_flagged(tmp_path):
    # The exact solution keeps a flat sheet's directors normal (nothing turns them); Static
    # left them 88-89 deg off before it told neutral modes from unstable ones.
    case = case_from_data(STRIP, tmp_path / "strip.toml")
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        run = run_case(case, tmp_path / "out", progress=False, write_frames=False)
    assert "tilted_directors" not in run.summary
    assert not [w for w in said if "tilted more than" in str(w.message)]
    assert run.summary["director_tilt_deg"]["max"] < math.degrees(1e-6)


def _frame(tilts_deg, guarded):
    return {
        "director_tilt_deg": np.asarray(tilts_deg, dtype=float),
        "thickness_guarded": np.asarray(guarded, dtype=float),
    }


def test_directors_tilted_past_the_guard_are_flagged_with_the_remedy():
    # Nodes 1 (80 deg, past acos(0.2) = 78.46) and 3 (at the cap) are flagged, node 0 (78 deg,
    # within) and node 2 (NaN: off the part) are not.
    point = _frame([78.0, 80.0, np.nan, 60.0], [0.0, 1.0, 0.0, 1.0])
    flag = tilted_directors(point)
    assert flag["nodes"] == 2 and flag["guarded"] == 2 and flag["first"] == [1, 3]
    assert flag["max_deg"] == pytest.approx(80.0)
    assert not flag["held_directors"]
    with pytest.warns(UserWarning, match="Hold the directors somewhere") as said:
        say_tilted(flag)
    assert any("tilted more than 78.5 deg" in str(w.message) for w in said)


def test_a_held_directors_tilt_is_not_flagged():
    point = _frame([85.0, 10.0], [1.0, 0.0])
    assert tilted_directors(point, held=np.array([0])) is None
    flag = tilted_directors(point)
    assert flag["nodes"] == 1 and flag["first"] == [0]


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
