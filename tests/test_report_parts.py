"""A case made of independent parts (``Case.parts``, ``Case.combine``): with several jobs the
report runs each part as a task of its own and combines them in its own process; its entry of
results.json is the same as when the parts run one after another in one process, but for the
times."""

import json
from dataclasses import replace

import numpy as np
import parts_case
import pytest

import validation.report as report_module
from validation.cases import CASES
from validation.records import Case, Outcome

QUIET = {"echo": lambda *args, **kwargs: None}
TIMES = ("case_time_s", "case_cpu_s", "parts", "wall_time_s")  # measured: never the same twice


# a case's parameters that hold its runs' measured times (hemisphere-forming's "fibrous:
# runtime", hemisphere-plies' "..._wall_time_s" and "..._cpu_time_s")
TIMED = ("runtime", "wall_time", "cpu_time")


def entry(folder, name: str) -> dict:
    """The case's entry of the report in ``folder``, without its times."""
    record = json.loads((folder / "results.json").read_text())["cases"][name]
    untimed = {key: value for key, value in record.items() if key not in TIMES}
    untimed["parameters"] = {
        key: value
        for key, value in record["parameters"].items()
        if not any(word in key for word in TIMED)
    }
    return untimed


def test_a_case_in_parts_gives_the_same_entry_split_and_in_one_process(tmp_path, monkeypatch):
    # and a part that raises fails its case with its error, both ways
    monkeypatch.setitem(CASES, "cheap-parts", parts_case.CASE)
    monkeypatch.setitem(CASES, "cheap-parts-broken", parts_case.BROKEN)
    names = ["cheap-parts", "cheap-parts-broken"]
    keys = list(parts_case.parts("coarse"))
    split = report_module.run_cases(names, "coarse", tmp_path / "split", jobs=2, **QUIET)
    alone = report_module.run_cases(names, "coarse", tmp_path / "alone", jobs=1, **QUIET)
    for name in names:
        assert entry(tmp_path / "split", name) == entry(tmp_path / "alone", name)
    # the parts combined in their own order (not the order they came back in), every bit
    assert split.cases["cheap-parts"].outcome.parameters["keys"] == keys
    assert split.cases["cheap-parts"].passed == 1
    for folder in ("split", "alone"):
        assert np.array_equal(
            np.loadtxt(tmp_path / folder / "cheap-parts.txt"), parts_case.compute("coarse").data
        )
    # each part timed; the case's CPU time the parts' and the combining step's
    for report, folder in ((split, "split"), (alone, "alone")):
        result = report.cases["cheap-parts"]
        assert list(result.parts) == keys
        assert result.case_cpu_s >= sum(cpu for _, cpu in result.parts.values())
        assert result.case_time_s >= sum(wall for wall, _ in result.parts.values())
        written = json.loads((tmp_path / folder / "results.json").read_text())
        assert list(written["cases"]["cheap-parts"]["parts"]) == keys
        failed = report.cases["cheap-parts-broken"].outcome
        assert failed.error == "ValueError: a part that fails, on purpose"
        assert failed.checks == []


def test_the_tasks_are_the_parts_longest_first_by_the_last_report_s_part_times(tmp_path):
    names = ["bai-5.1", "hemisphere-plies", "mindlin-plate"]
    keys = list(CASES["hemisphere-plies"].parts("default"))
    assert len(keys) == 4  # both layups, both kinematics
    # a first report: the case's expected cost shared among its parts by their weights
    tasks = report_module.schedule_tasks(names, "default")
    weights = {key: report_module.part_weight("hemisphere-plies", key) for key in keys}
    assert weights == dict(zip(keys, (6.5, 41.8, 9.0, 13.8)))  # [0/90] F, M, [0/45] F, M
    total = report_module.expected_cost("hemisphere-plies", "default")
    costs = {
        ("hemisphere-plies", key): total * w / sum(weights.values()) for key, w in weights.items()
    }
    costs |= {(n, None): report_module.expected_cost(n, "default") for n in names[::2]}
    assert sorted(tasks) == sorted(costs)
    assert [costs[task] for task in tasks] == sorted(costs.values(), reverse=True)
    # the [0/90] Mindlin run first, bai-5.1 (4.6 s) after the plies' runs (6.3-40.6 s)
    assert tasks[:5] == [("hemisphere-plies", keys[k]) for k in (1, 3, 2, 0)] + [("bai-5.1", None)]
    # every part of a case not listed weighs 1: shared evenly
    assert report_module.part_weight("cheap-parts", "seed 3") == 1.0
    assert report_module.part_weight("hemisphere-forming", "mindlin n = 20") == 16.1
    # the next: the part times the last report measured, read from its results.json
    last = dict(zip(keys, (3.0, 30.0, 1.0, 8.0)))
    content = {
        "resolution": "default",
        "cases": {
            "bai-5.1": {"case_time_s": 5.0},
            "mindlin-plate": {"case_time_s": 0.5},
            "hemisphere-plies": {
                "case_time_s": 43.0,
                "parts": {key: {"time_s": t, "cpu_s": t} for key, t in last.items()},
            },
        },
    }
    (tmp_path / "results.json").write_text(json.dumps(content))
    measured = report_module.measured_costs(tmp_path, names, "default")
    parts = report_module.measured_part_costs(tmp_path, names, "default")
    assert parts == {"hemisphere-plies": last}
    assert report_module.measured_part_costs(tmp_path, names, "coarse") == {}
    # without the case times (a case the last report did not run), not beside the table's CPU
    assert report_module.schedule_tasks(names, "default", None, parts) == tasks
    assert report_module.schedule_tasks(names, "default", measured, parts) == [
        ("hemisphere-plies", keys[1]),
        ("hemisphere-plies", keys[3]),
        ("bai-5.1", None),
        ("hemisphere-plies", keys[0]),
        ("hemisphere-plies", keys[2]),
        ("mindlin-plate", None),
    ]


def test_parts_come_with_the_step_that_combines_them():
    with pytest.raises(ValueError, match="parts and combine are given together"):
        Case("x", "t", "s", "d", "verification", 1, lambda r: Outcome.failed("no"),
             lambda d, o: [], parts=parts_case.parts)  # fmt: skip


@pytest.mark.slow  # the coarse forming case once in one process (~20 s of CPU)
def test_hemisphere_forming_gives_the_same_entry_split_and_in_one_process(tmp_path, coarse_report):
    # the coarse report (tests/conftest.py) ran it with --jobs 2, its two runs as tasks of
    # their own in the workers and combined in the report's process
    folder, results = coarse_report
    name = "hemisphere-forming"
    assert list(CASES[name].parts("coarse")) == ["fibrous", "mindlin"]
    assert set(results["cases"][name]["parts"]) == {"fibrous", "mindlin"}
    report = report_module.run_cases([name], "coarse", tmp_path, jobs=1, **QUIET)
    assert report.cases[name].outcome.error is None
    assert entry(folder, name) == entry(tmp_path, name)


def test_the_two_ply_layups_pickle_for_the_report_s_workers():
    # hemisphere-plies' parts send their layups back from the workers: a Mindlin layup kept
    # its element factory as a closure ("Can't pickle local object 'mindlin_ply.<locals>.ply'",
    # the case failed at the default resolution with two jobs)
    import pickle

    from validation.studies.hemisphere_plies_setup import LAYUPS, model

    for kinematics in ("fibrous", "mindlin"):
        layup, _ = model(8, LAYUPS["0/90"], kinematics, 20.0)
        again = pickle.loads(pickle.dumps(layup))
        assert np.array_equal(again.mesh.points, layup.mesh.points)
        assert [list(cells) for cells in again.ply_cells] == [
            list(cells) for cells in layup.ply_cells
        ]


@pytest.mark.parametrize("names", [["cheap-parts", "cheap-parts"], ["mindlin-rollup"] * 2])
def test_a_case_named_twice_is_refused_before_anything_runs(tmp_path, monkeypatch, names):
    # a case in parts named twice had its parts run and combined twice (a KeyError, no
    # results.json); a whole case named twice ran once for two entries
    monkeypatch.setitem(CASES, "cheap-parts", parts_case.CASE)
    with pytest.raises(ValueError, match=f"{names[0]} given more than once"):
        report_module.run_cases(names, "coarse", tmp_path, jobs=2, **QUIET)
    assert not (tmp_path / "results.json").exists()


def test_a_case_in_parts_without_parts_is_refused(tmp_path, monkeypatch):
    # it was never combined (a KeyError after every other case had run)
    empty = replace(parts_case.CASE, name="no-parts", parts=lambda resolution: {})
    monkeypatch.setitem(CASES, "no-parts", empty)
    with pytest.raises(ValueError, match="case 'no-parts' has no parts at resolution 'coarse'"):
        report_module.run_cases(["no-parts", "mindlin-rollup"], "coarse", tmp_path, jobs=2)
    with pytest.raises(ValueError, match="unknown case name"):
        report_module.run_cases(["no-such-case"], "coarse", tmp_path, **QUIET)


def test_a_worker_killed_fails_the_cases_not_done_and_the_report_is_written(tmp_path, monkeypatch):
    # A killed worker (kill -9, out of memory) broke the pool: BrokenProcessPool came out of
    # run_cases and the report was lost with every case done before it.
    monkeypatch.setitem(CASES, "cheap-parts", parts_case.CASE)
    monkeypatch.setitem(CASES, "cheap-parts-killing", parts_case.KILLING)
    # bai-5.1 (seconds at coarse) is queued after the parts (the cases not measured first)
    names = ["cheap-parts", "cheap-parts-killing", "bai-5.1"]
    report = report_module.run_cases(names, "coarse", tmp_path, jobs=2, **QUIET)
    assert report.cases["cheap-parts"].outcome.error is None
    assert report.cases["cheap-parts"].passed == 1
    for name in names[1:]:
        assert report.cases[name].outcome.error.startswith("its worker process died")
    written = json.loads((tmp_path / "results.json").read_text())["cases"]
    assert list(written) == names
    assert "its worker process died" in written["cheap-parts-killing"]["error"]
