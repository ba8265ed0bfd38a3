"""Parameter sweeps (fibreshell.sweep, ``fibreshell sweep``): dotted keys set into the case
file's tables, the product or the pairing of their values, every variant a Dask task whose
row holds the numbers of its run (checked against Euler-Bernoulli and against the same run in
this process), and a failed variant a row with its error, never a lost sweep."""

import copy
import csv
import json
import os
import re
import shutil
import signal

import numpy as np
import pytest
from shell_helpers import clamped_strip_tables

from femcore.writable import OutputError
from fibreshell import sweep as sweep_module
from fibreshell.case import case_from_data
from fibreshell.cli import main
from fibreshell.cluster import Failure, dask_client, map_tasks
from fibreshell.run import run_case
from fibreshell.sweep import apply_overrides, parse_vary, run_variant, sweep, variants
from materials import presets
from solvers.output import FrameStream

GRAVITY = 9810.0
LENGTH = 100.0
DENSITY = 8.154943934760449e-12  # t/mm^2: q = rho_A g = 8e-8 N/mm^2


def cantilever(bending: float = 10.0) -> dict:
    """A strip clamped at its left edge under its weight, as the tables of a case file: tip
    deflection q L^4 / (8 B) = 0.1 mm for B = 10 N mm (0.1 % of L: linear)."""
    return clamped_strip_tables(LENGTH, 20, bending, DENSITY, thickness=0.2, shear=1.0,
                                increments=1)  # fmt: skip


def euler_bernoulli_tip(bending: float) -> float:
    return DENSITY * GRAVITY * LENGTH**4 / (8.0 * bending)


# ------------------------------------------------------------------ keys and values
def test_values_are_read_as_toml_values_bare_words_as_strings():
    assert parse_vary("part.0.material.bending=10,2.5e1, 40") == (
        "part.0.material.bending", [10, 25.0, 40]
    )  # fmt: skip
    assert parse_vary("kinematics=fibrous,mindlin") == ("kinematics", ["fibrous", "mindlin"])
    key, values = parse_vary("contact.0.motion=[0.0, 0.0, -5.0],[0, 0, -10]")
    assert values == [[0.0, 0.0, -5.0], [0, 0, -10]]  # commas inside brackets stay
    assert parse_vary("a.b=linspace(1, 3, 3)")[1] == [1.0, 2.0, 3.0]
    assert parse_vary("a.b=geomspace(1, 100, 3)")[1] == pytest.approx([1.0, 10.0, 100.0])


@pytest.mark.parametrize(
    "text, message",
    [
        ("part.0.material.bending", "expected KEY=V1,V2"),
        ("=1,2", "expected KEY=V1,V2"),
        ("a.b=1,,2", "empty value"),
        ("a.b=linspace(1, 2)", "linspace(start, stop, count)"),
        ("a.b=geomspace(-1, 2, 3)", "one sign"),
    ],
)
def test_a_malformed_vary_is_a_value_error(text, message):
    with pytest.raises(ValueError, match=re.escape(message)):
        parse_vary(text)


def test_the_product_varies_the_first_key_slowest_and_zip_pairs():
    product = variants({"a": [1, 2], "b": ["x", "y", "z"]})
    assert product == [{"a": a, "b": b} for a in (1, 2) for b in "xyz"]
    assert variants({"a": [1, 2], "b": ["x", "y"]}, paired=True) == [
        {"a": 1, "b": "x"}, {"a": 2, "b": "y"}
    ]  # fmt: skip
    with pytest.raises(ValueError, match="as many values"):
        variants({"a": [1, 2], "b": [1]}, paired=True)
    with pytest.raises(ValueError, match="nothing to vary"):
        variants({})


def test_overrides_set_nested_keys_and_open_a_preset_to_change_one_value():
    data = cantilever()
    data["part"][0]["material"] = "paper_stack"
    original = copy.deepcopy(data)
    tables, options = apply_overrides(
        data, {"part.0.material.bending": 25.0, "mesh.rectangle.nx": 4, "kinematics": "mindlin"}
    )
    assert data == original  # the base tables are not touched
    assert tables["part"][0]["material"] == {"preset": "paper_stack", "bending": 25.0}
    assert tables["mesh"]["rectangle"]["nx"] == 4
    assert options == {"kinematics": "mindlin"}
    fabric = case_from_data(tables, "sweep.toml").parts[0]["element"].fabric
    stack = presets.paper_stack()
    assert fabric.bending.slope(np.array(0.0)).item() == 25.0
    assert fabric.thickness == stack.thickness
    assert fabric.tension.slope(np.array(0.0)) == stack.tension.slope(np.array(0.0))


def test_a_preset_takes_its_own_arguments_and_refuses_unknown_keys():
    data = cantilever()
    data["part"][0]["material"] = {"preset": "paper_stack", "sheets": 65}
    fabric = case_from_data(data, "c.toml").parts[0]["element"].fabric
    assert fabric.thickness == pytest.approx(presets.paper_stack(65).thickness)
    data["part"][0]["material"] = {"preset": "paper_stack", "bendng": 1.0}
    with pytest.raises(ValueError, match=r"c.toml: \[part\[0\].material.bendng\]: unknown key"):
        case_from_data(data, "c.toml")


@pytest.mark.parametrize(
    "key, message",
    [
        ("part.1.material.bending", "list of 1 tables; expected an index 0 to 0"),
        ("mesh.square.lx", "the case has no 'mesh.square'"),
        ("solver.kind.x", "is a value, not a table"),
        ("part..bending", "dotted path"),
    ],
)
def test_a_key_not_in_the_case_is_a_value_error(key, message):
    with pytest.raises(ValueError, match=message):
        apply_overrides(cantilever(), {key: 1.0})


def test_run_options_are_checked():
    with pytest.raises(ValueError, match="kinematics: expected one of fibrous, mindlin"):
        apply_overrides(cantilever(), {"kinematics": "kirchhoff"})
    with pytest.raises(ValueError, match="shear_ratio: expected a positive number"):
        apply_overrides(cantilever(), {"shear_ratio": -1})
    with pytest.raises(ValueError, match="calibration: expected one of laws, initial-slope"):
        apply_overrides(cantilever(), {"calibration": "abaqus"})
    _, options = apply_overrides(
        cantilever(), {"calibration": "laws", "bending_scale": 2.0, "transverse_shear": 5.0}
    )
    assert options == {"calibration": "laws", "bending_scale": 2.0, "transverse_shear": 5.0}


def test_a_swept_bending_scale_scales_the_mindlin_section(tmp_path):
    # The run options of the laws calibration reach the Mindlin shell: twice the bending law
    # halves a small-deflection cantilever's sag (q L^4 / (8 B), to the transverse shear's
    # q L^2 / (2 S) share, 3e-6 of it here).
    from fibreshell.sweep import run_variant

    rows = [
        run_variant(cantilever(), "c.toml", {"kinematics": "mindlin", "bending_scale": f}, None)[0]
        for f in (1.0, 2.0)
    ]
    ratio = rows[0]["displacement_right_z"] / rows[1]["displacement_right_z"]
    assert ratio == pytest.approx(2.0, rel=1e-4)


# ------------------------------------------------------------------ a sweep on Dask
@pytest.fixture(scope="module")
def paired_sweep(once_per_run):
    """Five paired variants on a LocalCluster of 1 worker that the sweep starts: B = 10 and 20
    fibrous, B = 10 Mindlin, B = -1 (refused by the case) and one whose solver may not
    iterate (it stops). Swept once per run of the suite, whichever pytest-xdist worker asks
    first (the cluster's start and the runs: seconds of CPU). One worker: a second cost its
    start (the package imported, the kernels loaded) and ran no variant sooner beside the
    suite's other processes; the README's sweep command runs its variants on two."""
    vary = {
        "part.0.material.bending": [10.0, 20.0, 10.0, -1.0, 10.0],
        "kinematics": ["fibrous", "fibrous", "mindlin", "fibrous", "fibrous"],
        "solver.max_iterations": [25, 25, 25, 25, 1],
    }
    return once_per_run(
        "paired_sweep",
        lambda out: sweep(cantilever(), vary, paired=True, out=out, workers=1, progress=False),
    )


@pytest.mark.waits  # on a LocalCluster
def test_every_variant_matches_euler_bernoulli(paired_sweep):
    # Closed form q L^4 / (8 B) (0.1 mm): 20 cells of the clamped-edge shell converge at
    # second order to 0.15 %; 1 % tolerance.
    _, table = paired_sweep
    for row in table.rows[:3]:
        assert row["converged"] and row["error"] == ""
        expected = euler_bernoulli_tip(row["part.0.material.bending"])
        assert -row["displacement_right_z"] == pytest.approx(expected, rel=0.01)
        # The clamp carries the weight: q L W.
        assert row["reaction_left_z"] == pytest.approx(DENSITY * GRAVITY * LENGTH * 10.0)


@pytest.mark.waits  # on a LocalCluster
def test_a_variant_runs_on_a_worker_as_it_runs_here(paired_sweep):
    out, table = paired_sweep
    tables, _ = apply_overrides(cantilever(), {"part.0.material.bending": 20.0})
    here = run_case(case_from_data(tables, "cantilever"), out / "here", progress=False)
    assert table.rows[1]["displacement_right_z"] == pytest.approx(
        here.summary["mean_displacements"]["right"][2], rel=1e-10
    )


@pytest.mark.waits  # on a LocalCluster
def test_a_failed_variant_is_a_row_with_its_error_and_the_others_run(paired_sweep):
    out, table = paired_sweep
    refused, stopped = table.rows[3], table.rows[4]
    assert not refused["converged"] and "B must be > 0" in refused["error"]
    assert not stopped["converged"] and "iteration" in stopped["error"]
    assert table.failed == [3, 4]
    assert table.summaries[3] is None and table.summaries[4] is not None
    # The stopped variant kept its last good state on disk.
    assert (out / "variant-004" / "summary.json").is_file()
    assert not (out / "variant-003").exists()
    # sweep.csv names the folder of a variant that has one, none for one refused before it
    assert refused["folder"] == "" and stopped["folder"] == "variant-004"


@pytest.mark.waits  # on a LocalCluster
def test_sweep_csv_has_a_row_per_variant_with_the_varied_values(paired_sweep):
    out, table = paired_sweep
    with open(out / "sweep.csv") as handle:
        rows = list(csv.DictReader(handle))
    assert len(rows) == 5
    assert rows[0]["part.0.material.bending"] == "10.0" and rows[2]["kinematics"] == "mindlin"
    assert float(rows[1]["displacement_right_z"]) == table.rows[1]["displacement_right_z"]
    assert rows[3]["converged"] == "False" and "B must be > 0" in rows[3]["error"]
    assert {"wall_time_s", "reaction_left_z", "max_fibre_strain"} <= set(rows[0])
    assert (out / "variant-000" / "variant.json").is_file()
    assert np.isnan(table.column("displacement_right_z")[3])


@pytest.mark.waits  # on a LocalCluster (the fixture's)
def test_a_sweep_in_process_gives_the_cluster_s_rows(paired_sweep, tmp_path, monkeypatch):
    # The same five variants run one after another here, without a cluster (none may be
    # started): the same values (each run's own solve: the same bits on one or two numba
    # threads, rel 1e-10 as the worker against here above), the same failures and files.
    _, table = paired_sweep

    def no_cluster(*_):
        raise AssertionError("a sweep in process started a cluster")

    monkeypatch.setattr(sweep_module, "dask_client", no_cluster)
    vary = {
        "part.0.material.bending": [10.0, 20.0, 10.0, -1.0, 10.0],
        "kinematics": ["fibrous", "fibrous", "mindlin", "fibrous", "fibrous"],
        "solver.max_iterations": [25, 25, 25, 25, 1],
    }
    here = sweep(cantilever(), vary, paired=True, out=tmp_path, progress=False, in_process=True)
    assert here.failed == table.failed == [3, 4]
    for mine, theirs in zip(here.rows, table.rows):
        assert mine["converged"] == theirs["converged"]
        for column in ("displacement_right_z", "reaction_left_z", "steps"):
            if column in theirs:
                assert mine[column] == pytest.approx(theirs[column], rel=1e-10, nan_ok=True)
    assert "B must be > 0" in here.rows[3]["error"] and "iteration" in here.rows[4]["error"]
    assert len((tmp_path / "sweep.csv").read_text().splitlines()) == 6
    assert (tmp_path / "variant-004" / "summary.json").is_file()


def test_a_sweep_into_a_used_folder_leaves_none_of_an_earlier_sweep_s_variants(tmp_path):
    """An earlier sweep's variant-000 to variant-002 (each with its variant.json, its run's
    files and a checkpoint its summary.json names) beside a sweep of one variant: the folder
    then holds that one variant; a user's own file keeps its folder (with that file alone),
    a folder the sweep did not write (no variant.json) stays as it was."""
    for k in range(3):
        old = tmp_path / f"variant-00{k}"
        old.mkdir()
        (old / "variant.json").write_text(json.dumps({"case": "x", "overrides": {"k": k}}))
        (old / "summary.json").write_text(json.dumps({"checkpoint": str(old / "saved.pkl")}))
        for name in ("result.pvd", "result_00000.vtu", "history.csv", "saved.pkl"):
            (old / name).write_text("old")
    (tmp_path / "variant-002" / "notes.txt").write_text("mine")
    (tmp_path / "variant-009").mkdir()
    (tmp_path / "variant-009" / "summary.json").write_text("mine")
    vary = {"part.0.material.bending": [20.0]}
    table = sweep(cantilever(), vary, out=tmp_path, progress=False, in_process=True)
    assert table.failed == []
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "sweep.csv", "sweep.json", "variant-000", "variant-002", "variant-009",
    ]  # fmt: skip
    record = json.loads((tmp_path / "variant-000" / "variant.json").read_text())
    assert record["overrides"] == {"part.0.material.bending": 20.0}
    assert not (tmp_path / "variant-000" / "saved.pkl").exists()
    assert [p.name for p in (tmp_path / "variant-002").iterdir()] == ["notes.txt"]
    assert (tmp_path / "variant-009" / "summary.json").read_text() == "mine"


def test_a_variant_without_a_folder_writes_no_frames_and_gives_the_same_row(tmp_path, monkeypatch):
    # A sweep without an output folder throws each variant's folder away: its static run
    # writes no frame series there (run_case(write_frames=False)), and its row is the row of
    # the same run writing them into a folder, to the bit (the frames are only written).
    written = []
    real_write = FrameStream.write
    monkeypatch.setattr(
        FrameStream, "write", lambda stream, frame: written.append(1) or real_write(stream, frame)
    )
    overrides = {"part.0.material.bending": 20.0}
    row, summary = run_variant(cantilever(), "strip", overrides, None)
    assert not written and summary is not None and row["converged"]
    kept, _ = run_variant(cantilever(), "strip", overrides, str(tmp_path / "kept"))
    assert written and (tmp_path / "kept" / "result.pvd").is_file()
    for column in set(row) | set(kept):
        if column != "wall_time_s":
            assert row[column] == kept[column], column
    tables, _ = apply_overrides(cantilever(), overrides)
    bare = tmp_path / "bare"
    bare.mkdir()
    run_case(case_from_data(tables, "strip"), bare, progress=False, write_frames=False)
    assert sorted(path.name for path in bare.iterdir()) == ["history.csv", "summary.json"]


def test_a_run_without_frames_asks_no_room_for_them(tmp_path, monkeypatch):
    # The folder check demands room for the first frames (femcore.writable.check_folder); a
    # run that writes none (run_case(write_frames=False)) starts on a disk with none free,
    # one that writes them is refused there before anything runs.
    import femcore.writable

    full = shutil._ntuple_diskusage(1_000_000_000, 1_000_000_000, 0)  # total, used, free
    monkeypatch.setattr(femcore.writable.shutil, "disk_usage", lambda _: full)
    case = case_from_data(cantilever(), "strip")
    bare = run_case(case, tmp_path / "bare", progress=False, write_frames=False)
    assert bare.status == "done" and (tmp_path / "bare" / "summary.json").is_file()
    with pytest.raises(OutputError, match="0 MB free on its disk, the frames need about"):
        run_case(case, tmp_path / "framed", progress=False)
    assert not (tmp_path / "framed" / "summary.json").exists()


def test_a_relaxation_without_frames_writes_no_series_and_the_same_rows(tmp_path):
    # The relaxation's frames are written after its run (run_case's relaxation branch): with
    # write_frames=False no result.pvd, and history.csv and summary.json those of the run that
    # writes it, to the bit but for the wall time and the checkpoint's path (the frames are
    # only written, never read back).
    tables = cantilever()
    tables["solver"] = {"kind": "relaxation"}
    case = case_from_data(tables, "strip")
    runs = {}
    for name, frames in (("bare", False), ("framed", True)):
        runs[name] = run_case(case, tmp_path / name, progress=False, write_frames=frames)
    assert not (tmp_path / "bare" / "result.pvd").exists()
    assert (tmp_path / "framed" / "result.pvd").is_file()
    assert runs["bare"].status == runs["framed"].status == "done"
    bare, framed = (
        (tmp_path / name / "history.csv").read_text().splitlines() for name in ("bare", "framed")
    )
    assert len(bare) > 1 and bare == framed
    summaries = [json.loads((tmp_path / name / "summary.json").read_text()) for name in runs]
    for summary in summaries:
        summary.pop("wall_time_s"), summary.pop("checkpoint")
    assert summaries[0] == summaries[1]


def test_a_sweep_in_process_takes_no_cluster_arguments():
    for arguments in ({"workers": 1}, {"scheduler": "tcp://127.0.0.1:1"}):
        with pytest.raises(ValueError, match="in_process runs the variants here"):
            sweep(cantilever(), {"part.0.material.bending": [10.0]}, in_process=True,
                  progress=False, **arguments)  # fmt: skip
    with pytest.raises(ValueError, match="in_process must be True or False, got 'no'"):
        sweep(cantilever(), {"part.0.material.bending": [10.0]}, in_process="no", progress=False)


def test_an_error_escaping_a_variant_in_process_is_its_row_as_on_a_cluster(monkeypatch):
    # On a cluster map_tasks makes any error a task raises its row's Failure; in process
    # the same (before, the second variant's error ended the sweep with no table).
    def run(data, path, overrides, folder):
        if overrides["part.0.material.bending"] == 20.0:
            raise RuntimeError("a variant's own error")
        return {"converged": True}, None

    monkeypatch.setattr(sweep_module, "run_variant", run)
    vary = {"part.0.material.bending": [10.0, 20.0, 30.0]}
    table = sweep(cantilever(), vary, in_process=True, progress=False)
    assert table.failed == [1] and table.rows[1]["error"] == "RuntimeError: a variant's own error"
    assert table.rows[0]["converged"] and table.rows[2]["converged"]


def test_a_sweep_stopped_by_ctrl_c_says_which_variants_did_not_end(monkeypatch, tmp_path):
    """Ctrl-C during the second variant: sweep.csv holds the first variant's row, and the
    rows of the others say they were interrupted (before: blank converged and error cells);
    the interrupt goes on up (``fibreshell sweep`` exits 130)."""

    def run(data, path, overrides, folder):
        if overrides["part.0.material.bending"] == 20.0:
            raise KeyboardInterrupt
        return {"converged": True, "error": "", "wall_time_s": 1.0}, None

    monkeypatch.setattr(sweep_module, "run_variant", run)
    vary = {"part.0.material.bending": [10.0, 20.0, 30.0]}
    with pytest.raises(KeyboardInterrupt):
        sweep(cantilever(), vary, out=tmp_path, in_process=True, progress=False)
    with open(tmp_path / "sweep.csv") as handle:
        rows = list(csv.DictReader(handle))
    said = [(row["converged"], row["error"].split(":")[0]) for row in rows]
    assert said == [("True", ""), ("False", "interrupted"), ("False", "interrupted")]


@pytest.mark.waits  # on a LocalCluster
def test_a_dead_worker_is_a_failed_task_not_a_lost_map():
    import dask

    with dask.config.set({"distributed.scheduler.allowed-failures": 0}):
        with dask_client(workers=1) as (client, _):
            results = map_tasks(client, os._exit, [(3,)], "crash", progress=False)
            again = map_tasks(client, abs, [(-2,)], "after", progress=False)
    assert isinstance(results[0], Failure) and "KilledWorker" in results[0].error
    assert again == [2]


def test_a_sweep_where_no_variant_builds_is_a_value_error():
    with pytest.raises(ValueError, match="no variant of the sweep could be built: .*B must be"):
        sweep(cantilever(), {"part.0.material.bending": [-1.0, -2.0]}, progress=False)


def test_workers_and_scheduler_are_checked():
    for bad in (0, 1.5, True):
        with pytest.raises(ValueError, match="workers must be a whole number >= 1"):
            with dask_client(workers=bad):
                pass
    with pytest.raises(ValueError, match="not both"):
        with dask_client("tcp://127.0.0.1:1", workers=2):
            pass


# ------------------------------------------------------------------ the command
@pytest.fixture
def case_file(tmp_path):
    text = (
        "[mesh]\nrectangle = { lx = 100.0, ly = 10.0, nx = 10, ny = 1 }\n"
        "[[part]]\nelement = \"fibrous\"\nmaterial = \"g986_ply\"\n"
        "options = { clamped = \"left\" }\n[[fix]]\nnodes = \"left\"\n"
        "[gravity]\nacceleration = [0.0, 0.0, -9810.0]\n"
        "[solver]\nkind = \"static\"\nincrements = 2\n"
        "[output]\nhistory = { displacements = [\"right\"] }\n"
    )  # fmt: skip
    path = tmp_path / "strip.toml"
    path.write_text(text)
    return path


@pytest.mark.slow
@pytest.mark.waits  # on a LocalCluster of its own
def test_the_command_writes_sweep_csv(case_file, tmp_path, capsys):
    out = tmp_path / "out"
    status = main(["sweep", str(case_file), "--vary", "part.0.material.bending=1.0,2.0",
                   "--workers", "1", "--out", str(out), "--quiet"])  # fmt: skip
    assert status == 0, capsys.readouterr()
    with open(out / "sweep.csv") as handle:
        rows = list(csv.DictReader(handle))
    assert [r["part.0.material.bending"] for r in rows] == ["1.0", "2.0"]
    # Stiffer, less sag (the heavy elastica's deflection falls with B).
    assert float(rows[1]["displacement_right_z"]) > float(rows[0]["displacement_right_z"])
    printed = capsys.readouterr().out
    assert "2 variants, 0 failed" in printed
    header, first, second = printed.splitlines()[:3]  # the table, a line per variant
    assert header.split()[:4] == ["variant", "part.0.material.bending", "converged",
                                  "wall_time_s"]  # fmt: skip
    assert header.split()[-2:] == ["displacement_right_z", "max_fibre_strain"]
    assert float(second.split()[-2]) == pytest.approx(float(rows[1]["displacement_right_z"]),
                                                      rel=1e-3)  # fmt: skip


@pytest.mark.parametrize(
    "arguments, message",
    [
        (["--vary", "part.3.material.bending=1"], "part is a list of 1 tables"),
        (["--vary", "solver.increments=1", "--vary", "solver.increments=2"], "twice"),
        (["--vary", "solver.increments"], "expected KEY=V1,V2"),
        (["--vary", "a.b=1", "--zip", "--vary", "c.d=1,2"], "as many values"),
    ],
)
def test_the_command_refuses_a_bad_sweep_with_status_2(case_file, tmp_path, capsys, arguments,
                                                       message):  # fmt: skip
    status = main(["sweep", str(case_file), *arguments, "--out", str(tmp_path / "o"), "--quiet"])
    assert status == 2
    assert message in capsys.readouterr().err


def test_the_report_s_sensitivity_study_sweeps_the_case_file_of_bai_6_1_1():
    # The sensitivity case builds its base from validation's constants; it must stay the case
    # file users run (cases/bai-6.1.1.toml), at the report's cell count.
    from pathlib import Path

    from fibreshell.case import read_case_data
    from validation.cases.bai_sensitivity import base_case

    shipped = read_case_data(Path(__file__).resolve().parents[1] / "cases" / "bai-6.1.1.toml")
    base = base_case(20)
    for table in ("mesh", "part", "fix", "displace", "gravity", "solver"):
        assert base[table] == shipped[table], table
    assert base["output"]["paths"]["side_1"] == shipped["output"]["paths"]["side_1"]


@pytest.mark.waits  # on a LocalCluster
def test_a_sweep_runs_against_a_scheduler_address():
    # A scheduler started apart (here in this process; on a cluster by `dask scheduler`):
    # the sweep connects to its address and its workers run the variants.
    from distributed import LocalCluster

    with LocalCluster(n_workers=1, threads_per_worker=1, dashboard_address=None) as cluster:
        table = sweep(cantilever(), {"part.0.material.bending": [10.0, 20.0]},
                      scheduler=cluster.scheduler_address, progress=False)  # fmt: skip
    for row in table.rows:
        expected = euler_bernoulli_tip(row["part.0.material.bending"])
        assert -row["displacement_right_z"] == pytest.approx(expected, rel=0.01)


def test_a_scheduler_that_does_not_answer_is_a_value_error():
    with pytest.raises(ValueError, match="no Dask scheduler answers at 'tcp://127.0.0.1:1'"):
        with dask_client("tcp://127.0.0.1:1", timeout=1.0):
            pass


def test_a_sweep_of_a_calibration_number_on_the_fibrous_kinematics_is_refused():
    # shear_ratio makes the Mindlin shell of the fabric: on the case's fibrous parts it was
    # ignored and every row came out the same. With kinematics = mindlin it is what it varies.
    with pytest.raises(ValueError, match="shear_ratio set how fibrous parts become Mindlin"):
        sweep(cantilever(), {"shear_ratio": [0.1, 0.5]}, in_process=True, progress=False)
    table = sweep(
        cantilever(),
        {"shear_ratio": [1e-3, 0.5], "kinematics": ["mindlin", "mindlin"]},
        paired=True,
        in_process=True,
        progress=False,
    )
    assert all(row["converged"] for row in table.rows)
    sag = table.column("displacement_right_z")  # the softer transverse shear sags more
    assert sag[0] < sag[1] < 0.0


def mindlin_cantilever() -> dict:
    """A Mindlin shell cantilever under a tip force (no fibrous part), as case tables."""
    return {
        "mesh": {"rectangle": {"lx": 100.0, "ly": 10.0, "nx": 4, "ny": 1}},
        "part": [{"element": "mindlin",
                  "material": {"E": 1e5, "nu": 0.0, "thickness": 1.0, "density": 1e-9}}],
        "fix": [{"nodes": "left"}],
        "force": [{"nodes": "right", "vector": [0.0, 0.0, -0.01]}],
        "solver": {"kind": "static", "increments": 1},
        "output": {"history": {"displacements": ["right"]}},
    }  # fmt: skip


def test_a_kinematics_the_case_has_no_part_of_is_refused(tmp_path):
    # kinematics = fibrous on a Mindlin-only case ran the Mindlin shell and named the row and
    # summary.json "fibrous"; now that variant is a row with its error, run_case refuses it,
    # and kinematics = mindlin (the case's own shell) runs.
    table = sweep(mindlin_cantilever(), {"kinematics": ["fibrous", "mindlin"]},
                  in_process=True, progress=False)  # fmt: skip
    assert table.failed == [0]
    assert "kinematics='fibrous' needs a part of element fibrous" in table.rows[0]["error"]
    assert "the case's parts are mindlin" in table.rows[0]["error"]
    assert table.rows[1]["converged"] and table.rows[1]["kinematics"] == "mindlin"
    case = case_from_data(mindlin_cantilever(), tmp_path / "cantilever.toml")
    with pytest.raises(ValueError, match="kinematics='fibrous' needs a part of element fibrous"):
        run_case(case, tmp_path / "run", kinematics="fibrous", progress=False)
    assert not (tmp_path / "run" / "summary.json").exists()


def test_a_sweep_terminated_by_sigterm_says_which_variants_did_not_end(monkeypatch, tmp_path):
    """SIGTERM during the second variant (a scheduler's kill, a shell's timeout): as Ctrl-C,
    sweep.csv holds the first variant's row and marks the others interrupted, and the
    interrupt goes on up. Before, SIGTERM's default ended the process with sweep.csv
    unwritten (here a stand-in handler says so instead of ending the test's process)."""

    def not_handled(number, frame):
        raise RuntimeError("SIGTERM reached the default handler")

    def run(data, path, overrides, folder):
        if overrides["part.0.material.bending"] == 20.0:
            os.kill(os.getpid(), signal.SIGTERM)
        return {"converged": True, "error": "", "wall_time_s": 1.0}, None

    previous = signal.signal(signal.SIGTERM, not_handled)
    try:
        monkeypatch.setattr(sweep_module, "run_variant", run)
        vary = {"part.0.material.bending": [10.0, 20.0, 30.0]}
        with pytest.raises(KeyboardInterrupt):
            sweep(cantilever(), vary, out=tmp_path, in_process=True, progress=False)
        assert signal.getsignal(signal.SIGTERM) is not_handled  # given back
    finally:
        signal.signal(signal.SIGTERM, previous)
    with open(tmp_path / "sweep.csv") as handle:
        rows = list(csv.DictReader(handle))
    said = [(row["converged"], row["error"].split(":")[0]) for row in rows]
    assert said == [("True", ""), ("False", "interrupted"), ("False", "interrupted")]


def test_a_sweep_started_with_sigint_ignored_still_stops_on_it(monkeypatch, tmp_path):
    """A shell starts a background job of a non-interactive script with SIGINT ignored, and
    Python keeps that: the sweep sets its own handler, as ``fibreshell run`` does, so that
    SIGINT during the second variant stops it as Ctrl-C does (sweep.csv marks the variants
    that did not end, the interrupt goes on up: status 130), and the ignoring is given back.
    Before, the sweep ran on through the signal."""

    def run(data, path, overrides, folder):
        if overrides["part.0.material.bending"] == 20.0:
            os.kill(os.getpid(), signal.SIGINT)
        return {"converged": True, "error": "", "wall_time_s": 1.0}, None

    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        monkeypatch.setattr(sweep_module, "run_variant", run)
        vary = {"part.0.material.bending": [10.0, 20.0, 30.0]}
        with pytest.raises(KeyboardInterrupt):
            sweep(cantilever(), vary, out=tmp_path, in_process=True, progress=False)
        assert signal.getsignal(signal.SIGINT) is signal.SIG_IGN  # given back
    finally:
        signal.signal(signal.SIGINT, previous)
    with open(tmp_path / "sweep.csv") as handle:
        rows = list(csv.DictReader(handle))
    said = [(row["converged"], row["error"].split(":")[0]) for row in rows]
    assert said == [("True", ""), ("False", "interrupted"), ("False", "interrupted")]
