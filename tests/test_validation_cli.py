"""`python -m validation` (the README's main job) and the README itself."""

import json
import re
from concurrent.futures import Future
from pathlib import Path

import numpy as np
import pytest

from femcore import jit
from validation import report as report_module
from validation.__main__ import main, parse
from validation.cases import CASES, PAPER_CASES
from validation.cases.bai_5_1 import SPEC as SPEC_5_1
from validation.cases.bai_6_1_1 import SPEC as SPEC_6_1_1
from validation.cases.bai_6_1_2 import SPEC as SPEC_6_1_2
from validation.cases.bai_6_2_1 import SPEC as SPEC_6_2_1
from validation.cases.bai_6_2_2 import SPEC as SPEC_6_2_2
from validation.paper import KINEMATICS, LABELS
from validation.records import Outcome

ROOT = Path(__file__).resolve().parents[1]
PAPER_SPECS = {s.name: s for s in (SPEC_5_1, SPEC_6_1_1, SPEC_6_1_2, SPEC_6_2_1, SPEC_6_2_2)}


def test_list_names_every_case(capsys):
    assert main(["--list"]) == 0
    listed = capsys.readouterr().out.split()
    assert all(name in listed for name in CASES)


# coarse_report (tests/conftest.py): one coarse run of every case, the paper cases included,
# started in the background as the session starts.


@pytest.mark.slow
def test_a_coarse_run_writes_the_report_and_passes_its_checks(coarse_report):
    out, report = coarse_report
    assert set(report["cases"]) == set(CASES)
    for case in report["cases"].values():
        assert case["converged"] and case["checks"]
        assert all(check["passed"] for check in case["checks"]), case["checks"]
        for figure in case["figures"]:
            assert (out / figure["file"]).stat().st_size > 1000
    page = (out / "index.html").read_text()
    assert "FAIL" not in page
    # a reader's page: the summary as contents, captions, each case's checks collapsed with
    # their rule (tests/test_report_html.py checks the structure)
    assert '<nav id="summary"><h2>Summary</h2>' in page
    assert "<figcaption><b>Figure 1.</b>" in page
    assert page.count("<details class='checks'>") == len(report["cases"])
    assert "passes if |value - reference| / |reference| &lt;= tolerance" in page
    assert "(None" not in page and "None," not in page  # no Python reprs in cells
    # Strict JSON: no NaN or Infinity (an unbounded tolerance is written as null).
    json.loads((out / "results.json").read_text(), parse_constant=pytest.fail)


@pytest.mark.slow
@pytest.mark.parametrize("name", [case.name for case in PAPER_CASES])
def test_paper_case_invariants_hold_with_the_three_kinematics(coarse_report, name):
    # Bai's claims, per case: the three runs converge; the fibres of both fibrous variants do
    # not stretch (< 1 %); the thickness along their directors never drops below h (Eq. 10);
    # the Mindlin shell is made of the same fabric (calibration "laws", stated); where both
    # runs take the same shape (a case with a mid-surface tolerance) and the mid-surface is
    # strongly bent (slope > 20 deg) their directors differ from the Mindlin ones (which
    # follow the normal) by > 10 deg; the Eq. 15 directors keep the clamp's vertical
    # orientation; every side record states theta and the tilt.
    out, report = coarse_report
    case = report["cases"][name]
    elements = case["elements"]
    assert list(elements) == list(KINEMATICS)
    assert [e["label"] for e in elements.values()] == [LABELS[k] for k in KINEMATICS]
    h = case["parameters"]["thickness_mm"]
    for kinematics, record in elements.items():
        assert record["converged"]
        for side in ("side_1", "side_2"):
            if side not in elements["fibrous"]:
                continue
            data = record[side]
            n = len(data["s"])
            assert np.shape(data["midsurface"]) == (n, 3)
            for key in (
                "director_angle_deg",
                "thickness",
                "rotation_deg",
                "side_tilt_deg",
                "director_tilt_deg",
            ):
                assert len(data[key]) == n, key
            if kinematics != "mindlin":
                assert min(data["thickness"]) >= h * (1 - 1e-9)
            if kinematics == "fibrous_element":
                assert np.allclose(data["director_angle_deg"], 90.0, atol=1.0)
        if kinematics != "mindlin":
            assert record["max_fibre_strain_away_from_support"] < 0.01
        for ext in ("vtu", "xdmf"):
            assert (out / f"{name}-{kinematics}.{ext}").exists()
    assert case["parameters"]["Mindlin calibration"].startswith("laws: MindlinShell(fabric)")
    assert "MindlinShell(fabric), calibration 'laws'" in case["discussion"]
    same_shape = [c for c in case["checks"] if c["name"].startswith("fibrous vs Mindlin (laws)")]
    assert bool(same_shape) == (PAPER_SPECS[name].midsurface_tolerance is not None)
    for prefix in ("fibrous vs Mindlin director", "fibrous Eq. 15 vs Mindlin director"):
        gap = [c for c in case["checks"] if c["name"].startswith(prefix)]
        if same_shape:
            assert gap and gap[0]["value"] > 10.0, prefix
    assert {f"{k} side_1" for k in KINEMATICS} <= set(case["key_numbers"])
    # The paragraph on the directors and the thickness names the three kinematics.
    assert all(LABELS[k] in case["discussion"] for k in KINEMATICS)
    assert "atan(theta)" in case["discussion"]


@pytest.mark.slow
def test_the_paper_cases_check_the_slip_kinematics_and_the_eq15_directors(coarse_report):
    _, report = coarse_report
    for case in PAPER_CASES:
        names = [c["name"] for c in report["cases"][case.name]["checks"]]
        assert any(n.startswith("fibrous Eq. 15: largest director tilt") for n in names)
    slip = [
        c
        for case in report["cases"].values()
        for c in case["checks"]
        if "vs atan(theta)" in c["name"]
    ]
    assert slip and all(c["passed"] for c in slip)


@pytest.mark.parametrize(
    "argv, message",
    [
        (["--cases", "no-such-case"], "unknown case name"),
        (["--cases", "bai-5.1,mindlin-plate,bai-5.1"], "bai-5.1 given more than once"),
        (["--resolution", "huge"], "unknown resolution"),
        (["--jobs", "0"], "--jobs must be a whole number >= 1"),
        (["--out", str(ROOT / "README.md")], "is a file: give a folder"),
    ],
)
def test_bad_arguments_give_a_clear_error(argv, message, capsys):
    with pytest.raises(SystemExit) as stop:
        main(argv)
    assert stop.value.code == 2
    assert message in capsys.readouterr().err


def test_the_workers_start_the_longest_case_first(monkeypatch):
    # With several jobs the cases are started in decreasing order of their measured cost:
    # in report order the longest case started last and ran alone on one core at the end.
    names = list(CASES)
    for resolution in ("coarse", "default"):
        tasks = report_module.schedule_tasks(names, resolution)
        assert sorted({name for name, _ in tasks}) == sorted(names)
        whole = [name for name, key in tasks if key is None]
        costs = [report_module.expected_cost(name, resolution) for name in whole]
        assert costs == sorted(costs, reverse=True)
        assert all(0.0 < cost < float("inf") for cost in costs), "every case measured"
    # a case not measured yet may be the longest: it starts first
    monkeypatch.setitem(CASES, "not-measured", CASES["mindlin-plate"])
    tasks = report_module.schedule_tasks(["bai-5.1", "not-measured"], "default")
    assert tasks[0] == ("not-measured", None)


def _record_submissions(monkeypatch) -> list[str]:
    """Replace the report's worker pool by one that records the names of the cases it is
    given, in order, and runs nothing; the list it fills."""
    submitted: list[str] = []
    threads_asked = _record_submissions.threads = []  # type: ignore[attr-defined]

    class Pool:
        def __init__(self, jobs, mp_context, initializer=None, initargs=()):
            self.jobs = jobs

        def __enter__(self):
            return self

        def __exit__(self, *exc):
            return False

        def shutdown(self, wait=True, cancel_futures=False):
            pass

        def submit(self, function, name, resolution, out_dir, threads):
            submitted.append(name)
            threads_asked.append(threads)
            future = Future()
            future.set_result((Outcome.failed(RuntimeError("not run")), 0.0, 0.0))
            return future

    monkeypatch.setattr(report_module, "ProcessPoolExecutor", Pool)
    return submitted


def test_run_cases_submits_the_cases_to_the_workers_longest_first(tmp_path, monkeypatch):
    submitted = _record_submissions(monkeypatch)
    names = ["mindlin-plate", "plies-bai-5.1", "bar-wave", "bai-5.1"]
    report = report_module.run_cases(names, "default", tmp_path, echo=lambda *a, **k: None, jobs=2)
    assert submitted == [name for name, _ in report_module.schedule_tasks(names, "default")]
    assert submitted[0] == "plies-bai-5.1" and submitted != names
    assert list(report.cases) == names  # the report keeps its order


def test_a_report_folder_s_last_case_times_order_the_next_report(tmp_path, monkeypatch):
    # The hand-kept EXPECTED_CPU_S orders a first report; a folder that holds a report of the
    # same cases at the same resolution is ordered by the case times that report measured.
    names = ["mindlin-plate", "plies-bai-5.1", "bar-wave", "bai-5.1"]
    last = {"mindlin-plate": 90.0, "plies-bai-5.1": 1.0, "bar-wave": 50.0, "bai-5.1": 2.0}
    content = {
        "resolution": "default",
        "cases": {name: {"case_time_s": seconds} for name, seconds in last.items()},
    }
    (tmp_path / "results.json").write_text(json.dumps(content))  # fmt: skip
    submitted = _record_submissions(monkeypatch)
    report_module.run_cases(names, "default", tmp_path, echo=lambda *a, **k: None, jobs=2)
    assert submitted == ["mindlin-plate", "bar-wave", "bai-5.1", "plies-bai-5.1"]
    # that run wrote errors: the next one falls back on the table, as for another resolution
    # or a case the last report did not run
    assert report_module.measured_costs(tmp_path, names, "default") is None
    (tmp_path / "results.json").write_text(json.dumps(content))
    assert report_module.measured_costs(tmp_path, names, "coarse") is None
    assert report_module.measured_costs(tmp_path, [*names, "catenary"], "default") is None
    assert report_module.measured_costs(tmp_path, names, "default") == last
    submitted.clear()
    report_module.run_cases(names, "coarse", tmp_path, echo=lambda *a, **k: None, jobs=2)
    assert submitted == [name for name, _ in report_module.schedule_tasks(names, "coarse")]


def test_by_default_the_report_runs_as_many_cases_at_once_as_cores_are_free(monkeypatch):
    monkeypatch.setattr(jit, "_allowed_cores", lambda: 2)
    monkeypatch.setattr(jit.os, "cpu_count", lambda: 2)
    for attribute in ("wall", "cpu", "free"):  # free_cores's memory, restored after
        monkeypatch.setattr(jit._Load, attribute, getattr(jit._Load, attribute))
    for load, jobs in ((0.2, 2), (1.1, 1), (5.0, 1)):
        monkeypatch.setattr(jit.os, "getloadavg", lambda load=load: (load, load, load))
        monkeypatch.setattr(jit._Load, "wall", -float("inf"))  # looked at afresh
        assert parse(["--list"]).jobs == jobs
    assert parse(["--list", "--jobs", "2"]).jobs == 2


def readme_commands():
    return re.findall(r"```\n(apt-get update .*?)\n```", (ROOT / "README.md").read_text())


def test_the_readme_starts_with_the_two_setup_commands_and_ci_runs_the_second():
    commands = readme_commands()
    assert len(commands) == 2
    assert commands[0].endswith("python -m validation")
    assert commands[1].endswith("python -m pytest")
    assert commands[1] in (ROOT / ".ci" / "run").read_text()


def test_the_sensitivity_sweep_takes_the_cores_its_report_worker_was_given(monkeypatch):
    # A report worker at --jobs 2 on 2 cores runs on one numba thread; the sweep's Dask
    # cluster had one process per core beside it (three busy processes on two cores). On one
    # thread the variants run in the worker's own process, no cluster (``in_process``); on
    # more, a cluster of one worker per thread, at most one per variant.
    import numba

    from validation.cases import bai_sensitivity

    asked = []

    def sweep(*args, workers, in_process, **kwargs):
        asked.append(1 if in_process and workers is None else workers)
        raise RuntimeError("not run")

    monkeypatch.setattr(bai_sensitivity, "sweep", sweep)
    before = numba.get_num_threads()
    try:
        for threads in (1, numba.config.NUMBA_NUM_THREADS):
            numba.set_num_threads(threads)
            with pytest.raises(RuntimeError, match="not run"):
                bai_sensitivity.compute("coarse")
            assert asked[-1] == min(threads, len(bai_sensitivity.VARIANTS))
    finally:
        numba.set_num_threads(before)


def test_the_workers_never_ask_numba_for_more_threads_than_it_may_start(tmp_path, monkeypatch):
    # NUMBA_NUM_THREADS=1 on a 4-core machine: two workers, each one thread (numba refuses
    # more: "The number of threads must be between 1 and 1").
    monkeypatch.setattr(report_module.numba.config, "NUMBA_NUM_THREADS", 1)
    monkeypatch.setattr(report_module.os, "cpu_count", lambda: 4)
    _record_submissions(monkeypatch)
    names = ["mindlin-plate", "bar-wave"]
    report_module.run_cases(names, "default", tmp_path, echo=lambda *a, **k: None, jobs=2)
    assert _record_submissions.threads == [1, 1]


def test_a_single_case_runs_in_the_report_s_own_process(tmp_path, monkeypatch):
    # Nothing to share: asked for two jobs, one case runs without a worker pool.
    submitted = _record_submissions(monkeypatch)
    report = report_module.run_cases(
        ["mindlin-rollup"], "coarse", tmp_path, echo=lambda *a, **k: None, jobs=2
    )
    assert submitted == []
    assert report.cases["mindlin-rollup"].outcome.error is None
