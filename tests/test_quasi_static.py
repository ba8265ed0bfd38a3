"""Quasi-static honesty of explicit runs (solvers/quasi_static.py): CentralDifference records
the kinetic energy over the external work KE / W over time, warns once when it is above its
bound for more than KINETIC_SHARE of the time judged (after the first tenth of the run, where
the work done is 1 % of the run's or more), and
reports the mass and time scaling with the KE / W
they produced, in the Result and in a fibreshell run's summary.json.

The model: a bar of 10 cable elements fixed at one end, its other end pulled 1 mm along the
bar (smooth amplitude). Its slowest mode has the period 4 L / c = 4e-4 s: pulled over 40
periods the bar follows the end (quasi-static: KE / W ~ 1e-4); pulled over a fifth of one it
rings (KE / W ~ 1).
"""

import json
import warnings

import numpy as np
import pytest

from elements import Cable, RigidPlane
from femcore import Mesh, Model
from fibreshell.case import load_case
from fibreshell.run import run_case
from solvers import CentralDifference
from solvers.quasi_static import (
    KINETIC_BOUND,
    KINETIC_CHECK_FROM,
    KINETIC_SHARE,
    KINETIC_WORK_FLOOR,
    judged_records,
    quasi_static_report,
)

LENGTH, N = 1000.0, 10  # mm, elements
EA, MU = 1.0e6, 1.0e-8  # N, t/mm: c = 1e7 mm/s
PERIOD = 4.0 * LENGTH / np.sqrt(EA / MU)  # s, the slowest mode's


def pulled_bar(tool: bool = False) -> Model:
    model = Model(Mesh.line((0.0, 0.0, 0.0), (LENGTH, 0.0, 0.0), N))
    model.add(Cable(EA, MU))
    model.fix([0])
    model.fix(np.arange(1, N + 1), ("uy", "uz"))
    model.displace([N], ux=1.0, amplitude="smooth")
    if tool:  # a table 10 mm under the bar, never touched: the run is a forming run
        model.contact(RigidPlane((0.0, 0.0, -10.0), (0.0, 0.0, 1.0)))
    return model


def solve_quietly(solver: CentralDifference, tool: bool = False):
    """The result and the quasi-static warnings the run gave."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = solver.solve(pulled_bar(tool))
    return result, [w for w in caught if "not quasi-static" in str(w.message)]


@pytest.fixture(scope="module")
def fast():
    return solve_quietly(
        CentralDifference(duration=0.2 * PERIOD, kinetic_bound=KINETIC_BOUND, progress=False)
    )


@pytest.fixture(scope="module")
def slow():
    return solve_quietly(
        CentralDifference(duration=40.0 * PERIOD, kinetic_bound=KINETIC_BOUND, progress=False)
    )


def test_the_kinetic_over_work_record_is_KE_over_W_of_the_energy_records(fast, slow):
    for result, _ in (fast, slow):
        energies = result.energies
        work, kinetic = energies["external_work"], energies["kinetic"]
        assert len(energies["kinetic_over_work"]) == len(energies["time"])
        done = work > 0.0
        assert done[1:].all()  # the pull works on the bar from the first step
        np.testing.assert_allclose(
            energies["kinetic_over_work"][done], kinetic[done] / work[done], rtol=1e-14
        )
        assert energies["kinetic_over_work"][0] == 0.0  # at rest, no work yet
        report = result.info["quasi_static"]
        assert report["kinetic_over_work_final"] == pytest.approx(kinetic[-1] / work[-1], 1e-14)
        watched = energies["time"] >= KINETIC_CHECK_FROM * result.frames[-1].time
        watched &= work >= KINETIC_WORK_FLOOR * work[-1]
        largest = energies["kinetic_over_work"][watched].max()
        assert report["kinetic_over_work_largest"] == pytest.approx(largest, rel=1e-14)


def test_a_fast_pull_warns_once_with_the_time_and_the_ratio(fast):
    result, caught = fast
    assert len(caught) == 1
    report = result.info["quasi_static"]
    assert report["kinetic_bound"] == KINETIC_BOUND
    assert report["kinetic_over_work_largest"] > 0.3  # the bar rings
    at = report["exceeded_at_s"]
    assert KINETIC_CHECK_FROM * 0.2 * PERIOD <= at <= 0.2 * PERIOD
    assert caught[0].filename == __file__  # it points at the caller's solve
    message = str(caught[0].message)
    assert f"t = {at:.6g} s" in message and "kinetic_bound = 0.1" in message
    (first,) = np.flatnonzero(result.energies["time"] == at)
    assert f"{result.energies['kinetic_over_work'][first]:.3g} of the external work" in message
    assert result.energies["external_work"][first] >= KINETIC_WORK_FLOOR * work_at_end(result)


def work_at_end(result) -> float:
    return float(result.energies["external_work"][-1])


def test_the_early_records_where_little_work_is_done_are_not_judged(fast):
    """Before 1 % of the run's work is done, KE / W may be large (the bar starts moving
    before it stretches) without a warning: the largest judged ratio is at or after it."""
    result, _ = fast
    report = result.info["quasi_static"]
    (index,) = np.flatnonzero(result.energies["time"] == report["largest_at_s"])
    assert result.energies["external_work"][index] >= KINETIC_WORK_FLOOR * work_at_end(result)


def test_a_slow_pull_is_quasi_static_and_does_not_warn(slow):
    result, caught = slow
    assert caught == []
    report = result.info["quasi_static"]
    assert report["exceeded_at_s"] is None
    assert report["kinetic_over_work_largest"] < 0.2 * KINETIC_BOUND
    assert report["kinetic_over_work_final"] < 0.01 * KINETIC_BOUND


def test_the_share_above_the_bound_is_the_time_the_burst_lasted_over_the_judged_time():
    """Records every 0.01 s over 1 s, work growing linearly, KE / W 0.02 except 0.5 from
    t = 0.50 to 0.54 (5 records, each standing for the 0.01 s before it): judged from the
    record at 0.1 s (91 records, 0.91 s), the burst is 0.05 s of it; the largest value alone
    would call the run dynamic."""
    time = np.linspace(0.0, 1.0, 101)
    work = 1.0 + 100.0 * time
    ratio = np.where((time >= 0.495) & (time <= 0.545), 0.5, 0.02)
    energies = {"time": time, "external_work": work, "kinetic": ratio * work}
    report = quasi_static_report(energies, KINETIC_BOUND, 1.0, 0.0, warn=False)
    assert report["kinetic_over_work_largest"] == pytest.approx(0.5)
    assert report["exceeded_share"] == pytest.approx(0.05 / 0.91, rel=1e-12)
    quiet = quasi_static_report(
        {**energies, "kinetic": 0.02 * work}, KINETIC_BOUND, 1.0, 0.0, warn=False
    )
    assert quiet["exceeded_share"] == 0.0
    assert quasi_static_report(energies, None, 1.0, 0.0)["exceeded_share"] is None


def burst(start: float, end: float) -> dict[str, np.ndarray]:
    """Records every 0.01 s over 1 s, work growing linearly, KE / W 0.02 except 0.5 on the
    records from ``start`` to ``end`` (s)."""
    time = np.linspace(0.0, 1.0, 101)
    work = 1.0 + 100.0 * time
    ratio = np.where((time >= start - 0.005) & (time <= end + 0.005), 0.5, 0.02)
    return {"time": time, "external_work": work, "kinetic": ratio * work}


def test_a_burst_shorter_than_the_share_is_reported_and_a_longer_one_warned():
    """The warning's rule is the forming cases' (a small KE / W over the majority of the
    process, at most KINETIC_SHARE of the judged 0.91 s above the bound): a burst of 0.05 s
    (a flange snapping over a rim) is reported with its time and largest ratio but not
    warned; one of 0.15 s is warned, with its share in the message."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # any warning fails the short burst
        short = quasi_static_report(burst(0.50, 0.54), KINETIC_BOUND, 1.0, 0.0)
    assert short["exceeded_share"] == pytest.approx(0.05 / 0.91, rel=1e-12)
    assert short["exceeded_share"] < KINETIC_SHARE
    assert short["exceeded_at_s"] == pytest.approx(0.50)
    assert short["kinetic_over_work_largest"] == pytest.approx(0.5)
    with pytest.warns(UserWarning, match="not quasi-static") as caught:
        long = quasi_static_report(burst(0.50, 0.64), KINETIC_BOUND, 1.0, 0.0)
    assert long["exceeded_share"] == pytest.approx(0.15 / 0.91, rel=1e-12)
    assert long["exceeded_share"] > KINETIC_SHARE
    assert f"above it for {0.15 / 0.91:.3g} of the judged time" in str(caught[0].message)


def test_without_a_bound_the_ratio_is_watched_but_not_warned():
    result, caught = solve_quietly(
        CentralDifference(duration=0.2 * PERIOD, kinetic_bound=None, progress=False)
    )
    assert caught == []
    assert result.info["quasi_static"]["kinetic_over_work_largest"] > 0.3


def test_by_default_a_run_with_rigid_tools_is_judged_and_one_without_is_not():
    """The default bound "auto": a model with a rigid tool (a forming run, quasi-static by
    intent) is warned about past KINETIC_BOUND; the same ringing bar without a tool (a wave:
    dynamic by intent) is reported only."""
    solver = CentralDifference(duration=0.2 * PERIOD, progress=False)
    without, quiet = solve_quietly(solver)
    with_tool, warned = solve_quietly(solver, tool=True)
    assert quiet == [] and without.info["quasi_static"]["kinetic_bound"] is None
    assert without.info["quasi_static"]["kinetic_over_work_largest"] > 0.3
    assert len(warned) == 1 and with_tool.info["quasi_static"]["kinetic_bound"] == KINETIC_BOUND


def test_the_bound_must_be_a_positive_number():
    with pytest.raises(ValueError, match="kinetic_bound"):
        CentralDifference(duration=1.0, kinetic_bound=-0.1)
    with pytest.raises(ValueError, match='"auto", None or a positive ratio'):
        CentralDifference(duration=1.0, kinetic_bound="always")
    with pytest.raises(ValueError, match="process_duration"):
        CentralDifference(duration=1.0, process_duration=0.0)


def test_mass_scaling_reports_the_mass_it_added_and_the_kinetic_energy_it_raised(slow):
    """Each cell of the bar has the stable step L_e / c; a target of 2.7 L_e / c at safety 0.9
    scales every cell's density by (2.7 / 0.9)^2 = 9: eight times the model's mass is added,
    and the slow pull's KE / W grows with the heavier bar."""
    cell_dt = LENGTH / N / np.sqrt(EA / MU)
    solver = CentralDifference(
        duration=40.0 * PERIOD, mass_scaling_dt=2.7 * cell_dt, progress=False
    )
    scaled, _ = solve_quietly(solver)
    compiled_mass = MU * LENGTH
    added = scaled.info["added_mass"]
    assert added == pytest.approx(8.0 * compiled_mass, rel=1e-9)
    report = scaled.info["quasi_static"]
    assert report["added_mass_ratio"] == pytest.approx(added / compiled_mass, rel=1e-12)
    assert slow[0].info["quasi_static"]["added_mass_ratio"] == 0.0
    assert (
        report["kinetic_over_work_final"]
        > 3.0 * slow[0].info["quasi_static"]["kinetic_over_work_final"]
    )


def test_a_process_shorter_than_its_time_scaled_run_is_refused():
    # Accepted, it reported a time scaling of 0.5: a run slower than the process it speeds up.
    with pytest.raises(ValueError, match="process_duration = 0.5 s is shorter than the run's"):
        CentralDifference(duration=1.0, process_duration=0.5)
    assert CentralDifference(duration=1.0, process_duration=1.0).process_duration == 1.0


def test_time_scaling_is_the_process_duration_over_the_run_duration():
    solver = CentralDifference(duration=0.2 * PERIOD, process_duration=2.0 * PERIOD)
    result, _ = solve_quietly(solver)
    report = result.info["quasi_static"]
    assert report["time_scaling"] == pytest.approx(10.0, rel=1e-12)
    assert report["duration_s"] == 0.2 * PERIOD and report["process_duration_s"] == 2.0 * PERIOD


CASE = """title = "strip dropped under its own weight"
[mesh]
rectangle = {{ lx = 100.0, ly = 20.0, nx = 4, ny = 1 }}
[[part]]
element = "mindlin"
material = {{ E = 1000.0, nu = 0.3, thickness = 1.0, density = 1e-9 }}
[[fix]]
nodes = {{ x_max = 0.0 }}
[gravity]
acceleration = [0.0, 0.0, -9810.0]
[solver]
kind = "explicit"
duration = {duration}
kinetic_bound = 0.1                     # judged although it has no tool
"""


def test_the_run_summary_reports_the_quasi_static_account(tmp_path):
    """A cantilever strip under sudden gravity swings (not quasi-static): summary.json holds
    the solver's report, which says so."""
    path = tmp_path / "drop.toml"
    path.write_text(CASE.format(duration=0.002))
    with pytest.warns(UserWarning, match="not quasi-static"):
        run = run_case(load_case(path), tmp_path / "out", progress=False)
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    report = summary["quasi_static"]
    assert report == pytest.approx(run.result.info["quasi_static"])
    assert report["exceeded_at_s"] is not None and report["added_mass_ratio"] == 0.0


def test_the_judged_records_start_after_the_first_tenth_where_the_work_has_reached_its_floor():
    """One window for every KE / W check: a record is judged when its time is past
    KINETIC_CHECK_FROM of the duration, its work is positive and at least KINETIC_WORK_FLOOR
    of the final work (the run's own unless another is given)."""
    time = np.array([0.0, 0.05, 0.1, 0.2, 0.5, 1.0])
    work = np.array([0.0, 5.0, 0.5, 2.0, 50.0, 100.0])  # the floor: 1 N mm of 100
    assert KINETIC_CHECK_FROM == 0.1 and KINETIC_WORK_FLOOR == 0.01
    judged = judged_records(time, work, duration=1.0)
    assert judged.tolist() == [False, False, False, True, True, True]
    # a final work given from elsewhere (the run's, for records taken at other times)
    assert judged_records(time, work, 1.0, final_work=300.0).tolist() == [
        False, False, False, False, True, True
    ]  # fmt: skip
    negative = judged_records(time, -work, 1.0, final_work=100.0)
    assert not negative.any()  # no positive work, nothing to judge
