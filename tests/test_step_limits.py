"""What holds an explicit run's step below its mass scaling's target (solvers/step_limits.py)
and the step in summary.json.

References: without springs and damping, mass scaling makes the cells' bound target /
safety, so the step is the target itself (to rounding; 1e-3 asked with springs of 1e-3 N/mm
left in). A holder of 1e-6 t on nine 100-N/mm springs puts at its node the bound K + S of
their omega^2 (elements/contact.py ``springs``: S = 9 k / m_t = 9e8 1/s^2 and K the largest
k / m of the plate's nodes), which the step cannot pass: the step falls short of the target,
held by the springs at the tool's node, and the run says so.
"""

import json
import warnings

import pytest

from fibreshell.case import load_case
from fibreshell.run import run_case
from solvers import CentralDifference
from tests.test_force_driven_tools import held_plate_and_holder

TARGET = 1e-5  # s; the plate's own stable step is 3.7e-6 s


def run(penalty: float):
    model = held_plate_and_holder(gap=0.0, force=1.0, mass=1e-6, penalty=penalty)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = CentralDifference(duration=1e-4, mass_scaling_dt=TARGET, kinetic_bound=None).solve(
            model
        )
    return result, [str(w.message) for w in caught if "mass_scaling_dt" in str(w.message)]


def test_a_stiff_light_holder_holds_the_step_below_the_target_and_is_named():
    result, said = run(100.0)
    limits = result.info["step_limits"]
    assert limits["reached_dt_s"] == result.info["dt"] < 0.95 * TARGET
    assert limits["cells_dt_s"] == pytest.approx(TARGET, rel=1e-12)
    assert limits["limited_by"] == "the contacts' penalty springs"
    assert limits["is_tool_node"] and limits["springs_by"] == {"tool1": 1.0}
    assert limits["springs_dt_s"] == pytest.approx(result.info["dt"], rel=1e-12)
    assert len(said) == 1
    assert (
        f"mass_scaling_dt = 1e-05 s is not reached: the step is {result.info['dt']:.4g} s"
        in said[0]
    )
    assert "a force-driven tool's node" in said[0] and "larger mass" in said[0]


def test_soft_springs_let_the_step_reach_the_target_and_nothing_is_said():
    result, said = run(1e-3)
    assert result.info["dt"] == pytest.approx(TARGET, rel=1e-3)
    assert said == []


CASE = """
title = "held plate, scaled"
[mesh]
rectangle = { lx = 20.0, ly = 20.0, nx = 2, ny = 2, origin = [0.0, 0.0, 0.5] }
[[part]]
element = "mindlin"
material = { E = 1000.0, nu = 0.3, thickness = 1.0, density = 1e-9 }
[[fix]]
nodes = { x_min = 0.0 }
[[contact]]
tool = "plane"
point = [0.0, 0.0, 1.0]
normal = [0.0, 0.0, -1.0]
penalty = 100.0
free = ["z"]
force = [0.0, 0.0, -1.0]
mass = 1e-6
[solver]
kind = "explicit"
duration = 1e-4
mass_scaling_dt = 1e-5
"""


def test_summary_json_holds_the_explicit_step_its_balance_and_what_held_it(tmp_path):
    path = tmp_path / "plate.toml"
    path.write_text(CASE)
    with pytest.warns(UserWarning, match="mass_scaling_dt = 1e-05 s is not reached"):
        done = run_case(load_case(path), tmp_path / "out", progress=False)
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    step = summary["explicit_step"]
    assert step["dt_s"] == done.result.info["dt"]
    assert step["energy_balance_error"] == done.result.info["energy_balance_error"]
    assert step["step_limits"]["limited_by"] == "the contacts' penalty springs"
