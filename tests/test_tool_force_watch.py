"""An explicit run says when a force-driven tool does not press the body with its prescribed
force (solvers/tool_force_watch.py, docs/theory.md §6.3 "The force-driven tools").

A holder of mass m landing with a step force F on springs of total stiffness K rings
undamped: its contact force is F (1 - cos(omega t)), omega = sqrt(K / m), between 0 and 2 F.
Over the last half [T / 2, T] of the run the root mean square of the difference with F is
sqrt(<cos^2>) over that window (1 / sqrt(2) over whole periods): the closed form the solver's
per-step figures are held to. Critically damped (a dashpot c = 2 sqrt(K m) on the tool's node)
the difference is (1 + omega t) exp(-omega t) F, below 1e-9 F at omega T / 2 = 24.
"""

import json
import warnings
from pathlib import Path

import numpy as np
import pytest

from elements import MindlinShell, RigidPlane
from elements.dashpot import critical_damping
from femcore import Mesh, Model
from fibreshell.case import load_case
from fibreshell.run import run_case
from materials import ElasticShell
from solvers import CentralDifference
from solvers.tool_force_watch import TOOL_FORCE_SHARE
from tests.test_dashpot import FORCE, MASS, PENALTY, holder_on_a_held_plate

STIFFNESS = 9 * PENALTY  # the 3 x 3 nodes of the plate under the holder
OMEGA = np.sqrt(STIFFNESS / MASS)  # rad/s: a period of 6.6 ms
DURATION, DT = 0.05, 1e-4  # s: omega dt = 0.095, 3.8 periods judged
RINGING = "force-driven tool does not press the body"


def landed_holder(dashpot: bool = False) -> Model:
    """The plate and holder of tests/test_dashpot.py (FORCE, MASS and PENALTY the same), the
    holder resting on the plate's top face (no gap), pushed down by FORCE at once; with
    ``dashpot``, a critical dashpot on its node."""
    return holder_on_a_held_plate(critical_damping(MASS, STIFFNESS) if dashpot else None, gap=0.0)


def ringing_window() -> tuple[float, float]:
    """The closed form over [T / 2, T]: (mean of the push, N; rms of push - F over F)."""
    t = np.linspace(0.5 * DURATION, DURATION, 200_001)
    cosine = np.cos(OMEGA * t)
    return float(np.mean(FORCE * (1.0 - cosine))), float(np.sqrt(np.mean(cosine**2)))


def test_an_undamped_holder_under_a_step_force_rings_between_0_and_2f_and_the_run_warns():
    """The per-step figures against the closed form: the range 0 to 2 F (1e-2 F: the
    samples' phase, (omega dt)^2 / 2 = 4.5e-3), the mean and the departure over the last half
    (1e-2: the step's rectangle rule and the scheme's phase lag, (omega dt)^2 / 24 a period);
    one warning naming the tool, its range and mean against the prescribed force."""
    with pytest.warns(UserWarning, match=RINGING) as caught:
        run = CentralDifference(duration=DURATION, dt=DT).solve(landed_holder())
    (tool,) = run.info["quasi_static"]["driven_tools"]
    mean, departure = ringing_window()
    assert tool["tool"] == "tool1" and tool["axes"] == ["z"]
    assert tool["from_s"] == pytest.approx(0.5 * DURATION)
    assert tool["force_min"][0] == pytest.approx(-2.0 * FORCE, abs=1e-2 * FORCE)
    assert tool["force_max"][0] == pytest.approx(0.0, abs=1e-2 * FORCE)
    assert tool["force_mean"][0] == pytest.approx(-mean, abs=1e-2 * FORCE)
    assert tool["prescribed_mean"][0] == pytest.approx(-FORCE, rel=1e-12)
    assert tool["departure"] == pytest.approx(departure, abs=1e-2)
    assert departure > 0.6 > TOOL_FORCE_SHARE
    (message,) = [str(w.message) for w in caught if RINGING in str(w.message)]
    assert "tool1's contact force along z" in message and "Dashpot" in message


def test_a_critically_damped_holder_presses_with_its_force_and_the_run_is_silent():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        run = CentralDifference(duration=DURATION, dt=DT).solve(landed_holder(dashpot=True))
    (tool,) = run.info["quasi_static"]["driven_tools"]
    assert tool["departure"] < 1e-6
    assert tool["force_mean"][0] == pytest.approx(-FORCE, rel=1e-6)


def test_a_dynamic_run_reports_the_ringing_without_warning():
    """kinetic_bound=None (a run dynamic by intent) governs this warning too."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        run = CentralDifference(duration=DURATION, dt=DT, kinetic_bound=None).solve(landed_holder())
    assert run.info["quasi_static"]["driven_tools"][0]["departure"] > 0.6


def test_a_model_without_a_driven_tool_reports_none():
    flat = Mesh.rectangle(20.0, 20.0, nx=2, ny=2)
    model = Model(flat.with_points(flat.points + [0.0, 0.0, 0.5]))
    model.add(MindlinShell(ElasticShell(E=1000.0, nu=0.3, thickness=1.0, density=1e-9)))
    model.fix(lambda x, y, z: np.ones_like(x, dtype=bool))
    model.contact(RigidPlane((0.0, 0.0, 1.0), (0.0, 0.0, -1.0), motion=(0.0, 0.0, -0.01)))
    run = CentralDifference(duration=1e-3, dt=DT, kinetic_bound=None).solve(model)
    assert "driven_tools" not in run.info["quasi_static"]


def pullout(tmp_path: Path, damping: float | None, duration: float) -> tuple[dict, list[str]]:
    """cases/holder_pullout.toml run explicit over ``duration`` (s) with a 100-g holder, 1e-4
    t (its contact period about 0.5 ms), the holder's contact ``damping`` (None: none): the
    summary and the warnings' messages."""
    text = (Path(__file__).parents[1] / "cases" / "holder_pullout.toml").read_text()
    holder = "mass = 1e-4\n" + ("" if damping is None else f"damping = {damping}\n")
    text = text.replace('amplitude = "step"\n', 'amplitude = "step"\n' + holder)
    solver = text[text.index("[solver]") : text.index("[output]")]
    text = text.replace(solver, f'[solver]\nkind = "explicit"\nduration = {duration}\n\n')
    path = tmp_path / "case.toml"
    path.write_text(text)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        run_case(load_case(path), tmp_path / "out", progress=False)
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    return summary, [str(w.message) for w in caught]


def test_the_pullout_with_a_ringing_holder_warns_and_its_summary_says_how_much(tmp_path):
    """The holder rings on the strip between 0 and 2 x 100 N; summary.json's quasi_static
    block holds the range and the departure (about 1 / sqrt(2))."""
    summary, messages = pullout(tmp_path, None, 0.005)
    (tool,) = summary["quasi_static"]["driven_tools"]
    assert tool["tool"] == "tool2"
    assert tool["force_min"][0] < -180.0 and tool["force_max"][0] > -20.0
    assert tool["departure"] > 0.5
    assert any(RINGING in m and "tool2" in m for m in messages)


@pytest.mark.slow
def test_the_reviewers_damped_pullout_is_silent(tmp_path):
    """The holder's contact damping 0.2 over 0.02 s (the reviewer's run): its force still
    swings 71-128 N over the last half (0.124 measured), a ringing whose energy is 2 d^2 = 0.03
    of the springs' static energy, below the tenth TOOL_FORCE_SHARE stands for: reported, not
    warned. The fast counterpart: the critical dashpot above."""
    summary, messages = pullout(tmp_path, 0.2, 0.02)
    (tool,) = summary["quasi_static"]["driven_tools"]
    assert 0.05 < tool["departure"] < TOOL_FORCE_SHARE
    assert not any(RINGING in m for m in messages)
