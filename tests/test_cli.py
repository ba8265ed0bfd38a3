"""The ``fibreshell`` command's surface, in this process (``main(argv)``): its version, every
subcommand's help under its own name, where --out goes by default, the calibration ``compare``
states before its runs, and a failed sweep variant's whole error in the printed table and in
sweep.csv."""

import contextlib
import csv
import json
from importlib.metadata import version
from pathlib import Path
from types import SimpleNamespace

import pytest

import fibreshell.compare
import fibreshell.sweep
from fibreshell.calibration import Calibration
from fibreshell.case import case_from_data, load_case
from fibreshell.cli import _out_folder, main
from fibreshell.cluster import Failure
from fibreshell.sweep import SweepTable, apply_overrides

CASES = Path(__file__).parents[1] / "cases"
STRIP = CASES / "g1151_strip.toml"
COMMANDS = ("run", "compare", "sweep", "identify", "report")


def exit_status(argv: list[str]) -> int:
    """The status ``main`` exits with when argparse ends it (--help, --version)."""
    with pytest.raises(SystemExit) as caught:
        main(argv)
    return caught.value.code


# ---------------------------------------------------------------------- version and help
def test_version_prints_the_installed_package_version_and_exits_0(capsys):
    assert exit_status(["--version"]) == 0
    assert capsys.readouterr().out.strip() == f"fibreshell {version('fibreshell')}"


@pytest.mark.parametrize("command", COMMANDS)
def test_every_subcommand_s_help_names_itself(command, capsys):
    assert exit_status([command, "--help"]) == 0
    said = capsys.readouterr().out
    assert said.startswith(f"usage: fibreshell {command} ")
    assert "python -m" not in said


def test_the_top_level_help_lists_every_subcommand_and_the_version_option(capsys):
    assert exit_status(["--help"]) == 0
    said = capsys.readouterr().out
    assert "--version" in said and all(command in said for command in COMMANDS)


def test_a_report_command_line_error_names_fibreshell_report(capsys):
    assert exit_status(["report", "--resolution", "huge"]) == 2
    assert capsys.readouterr().err.splitlines()[-1].startswith("fibreshell report: error: ")


@pytest.mark.parametrize(
    "command, suffix", [("run", ""), ("compare", "-compare"), ("sweep", "-sweep"),
                        ("identify", "-identify")],
)  # fmt: skip
def test_out_defaults_to_the_case_s_name_inside_the_working_folder_as_its_help_says(
    command, suffix, capsys, tmp_path, monkeypatch
):
    assert exit_status([command, "--help"]) == 0
    said = " ".join(capsys.readouterr().out.split())  # argparse wraps the help
    assert f"the case file's name{suffix} inside the working folder" in said
    monkeypatch.chdir(tmp_path)
    out = _out_folder(None, str(STRIP), suffix)
    assert out.absolute() == tmp_path / f"g1151_strip{suffix}"


# ---------------------------------------------------------------------- compare
def fake_compare(comparison: dict, order: list[str]):
    """A compare_case that runs nothing: it notes when it was called and writes
    ``comparison``, as the real one does, into its output folder."""

    def compare_case(case, out, progress, **options):
        order.append("runs")
        print("RUNS")
        out.mkdir(parents=True, exist_ok=True)
        (out / "comparison.json").write_text(json.dumps(comparison))
        run = SimpleNamespace(error=None, wall_time=1.0, result=SimpleNamespace(steps=3))
        return {"fibrous": run, "mindlin": run}

    return compare_case


DIFFERENCES = {"mindlin": {"paths": {"centre": {"z_max_mm": 0.8, "director_angle_max_deg": 42.8,
                                                "thickness_max_mm": 5.3}}}}  # fmt: skip


def test_compare_prints_its_calibration_and_its_numbers_before_the_runs(
    capsys, tmp_path, monkeypatch
):
    fabric = load_case(STRIP).parts[0]["element"].fabric
    comparison = {"calibration": {"kinematics": "mindlin", **Calibration().describe(fabric)},
                  "differences": DIFFERENCES}  # fmt: skip
    monkeypatch.setattr(fibreshell.compare, "compare_case", fake_compare(comparison, []))
    assert main(["compare", str(STRIP), "--out", str(tmp_path / "c"), "--quiet"]) == 0
    lines = capsys.readouterr().out.splitlines()
    runs = lines.index("RUNS")
    assert lines[0].startswith("calibration: laws: MindlinShell(fabric)")
    assert "  bending_law_warp = BendingLaw.linear(B=72)" in lines[:runs]
    assert "  bending_law_weft = BendingLaw.linear(B=68)" in lines[:runs]
    assert any(line.startswith("  transverse_shear_N_per_mm = ") for line in lines[:runs])
    after = lines[runs + 1 :]
    assert after[0].startswith("mindlin - fibrous along centre: height 0.8 mm")
    assert not any(line.startswith("calibration") for line in after)  # said once


def test_compare_initial_slope_states_its_moduli_before_the_runs(capsys, tmp_path, monkeypatch):
    comparison = {"calibration": {"name": "initial-slope"}, "differences": {}}
    monkeypatch.setattr(fibreshell.compare, "compare_case", fake_compare(comparison, []))
    argv = ["compare", str(STRIP), "--out", str(tmp_path / "c"), "--calibration",
            "initial-slope", "--shear-ratio", "0.25", "--quiet"]  # fmt: skip
    assert main(argv) == 0
    lines = capsys.readouterr().out.splitlines()
    before = lines[: lines.index("RUNS")]
    assert before[0].startswith("calibration: initial-slope: ElasticShell.equivalent")
    assert "  shear_ratio = 0.25" in before
    assert any(line.startswith("  E1_MPa = ") for line in before)


def test_compare_fit_states_its_rule_before_and_its_fitted_values_before_the_comparison(
    capsys, tmp_path, monkeypatch
):
    fit = {
        "path": "centre",
        "residual_rms_mm": 0.12,
        "evaluations": 7,
        "values": {"bending_scale": 1.25, "transverse_shear": 3.5},
        "confidence_95": {"bending_scale": [1.2, 1.3], "transverse_shear": [3.0, 4.0]},
    }
    numbers = {"bending_law_warp": "BendingLaw.linear(B=90)", "fit": fit}
    comparison = {"calibration": {"kinematics": "mindlin", "name": "fit", "rule": "fitted",
                                  "numbers": numbers}, "differences": DIFFERENCES}  # fmt: skip
    monkeypatch.setattr(fibreshell.compare, "compare_case", fake_compare(comparison, []))
    argv = ["compare", str(STRIP), "--out", str(tmp_path / "c"), "--calibration", "fit", "--quiet"]
    assert main(argv) == 0
    lines = capsys.readouterr().out.splitlines()
    runs = lines.index("RUNS")
    assert lines[0].startswith("calibration: fit: the laws section with its bending laws scaled")
    after = lines[runs + 1 :]
    assert after[:3] == ["calibration: fit: fitted", "  bending_law_warp = BendingLaw.linear(B=90)",
                         "  fitted along path 'centre': RMS height residual 0.12 mm in 7 "
                         "evaluations"]  # fmt: skip
    assert "    bending_scale = 1.25 (95 %: 1.2 to 1.3)" in after
    assert after.index("    transverse_shear = 3.5 (95 %: 3 to 4)") < next(
        i for i, line in enumerate(after) if line.startswith("mindlin - fibrous")
    )


def test_compare_fit_takes_its_evaluation_cap_and_a_fit_that_reached_it_says_one_thing(
    capsys, tmp_path, monkeypatch
):
    """The cap is an option of the command (--fit-evaluations, compare_case's
    fit_evaluations), and a fit stopped at it says one true sentence naming it (before: the
    option did not exist, and identify's "the values are the best evaluated: give more
    (max_evaluations)" was followed by "The values below are the last evaluated; give the fit
    more evaluations (fit_evaluations)")."""
    message = (
        "stopped at the cap of 12 model evaluations: 12 made, 4 by the optimiser (its next "
        "step would have passed its share, 8) and 8 for the Jacobian at the end; the values "
        "are the best evaluated"
    )
    fit = {
        "path": "centre",
        "residual_rms_mm": 0.12,
        "evaluations": 12,
        "success": False,
        "message": message,
        "values": {"bending_scale": 1.25, "transverse_shear": 3.5},
        "confidence_95": {"bending_scale": [1.2, 1.3], "transverse_shear": [3.0, 4.0]},
    }
    comparison = {
        "calibration": {
            "kinematics": "mindlin",
            "name": "fit",
            "rule": "fitted",
            "numbers": {"fit": fit},
        },
        "differences": DIFFERENCES,
    }
    given = {}
    fake = fake_compare(comparison, [])

    def noting(case, out, progress, **options):
        given.update(options)
        return fake(case, out, progress, **options)

    monkeypatch.setattr(fibreshell.compare, "compare_case", noting)
    argv = [
        "compare",
        str(STRIP),
        "--out",
        str(tmp_path / "c"),
        "--calibration",
        "fit",
        "--fit-evaluations",
        "12",
        "--quiet",
    ]
    assert main(argv) == 0
    assert given["fit_evaluations"] == 12
    said = [line for line in capsys.readouterr().out.splitlines() if "NOT CONVERGED" in line]
    assert said == [
        f"  NOT CONVERGED: {message}: give the fit more evaluations "
        "(fibreshell compare --fit-evaluations)"
    ]
    argv = ["compare", str(STRIP), "--out", str(tmp_path / "d"), "--fit-evaluations", "12"]
    assert main(argv) == 2  # the cap of a fit, without one
    assert "--fit-evaluations 12 is the cap of --calibration fit" in capsys.readouterr().err


def test_compare_without_a_mindlin_run_states_no_calibration_before_its_runs(
    capsys, tmp_path, monkeypatch
):
    comparison = {"calibration": {"kinematics": "mindlin", "name": None, "rule": "no Mindlin run",
                                  "numbers": {}}, "differences": {}}  # fmt: skip
    monkeypatch.setattr(fibreshell.compare, "compare_case", fake_compare(comparison, []))
    argv = ["compare", str(STRIP), "--out", str(tmp_path / "c"), "--kinematics", "fibrous"]
    assert main([*argv, "--quiet"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0] == "RUNS" and lines[1] == "calibration: none (no Mindlin run)"


def test_a_bad_calibration_number_stops_compare_before_any_run(capsys, tmp_path, monkeypatch):
    order: list[str] = []
    monkeypatch.setattr(fibreshell.compare, "compare_case", fake_compare({}, order))
    argv = ["compare", str(STRIP), "--out", str(tmp_path / "c"), "--calibration",
            "initial-slope", "--shear-ratio", "-1"]  # fmt: skip
    assert main(argv) == 2 and order == []
    assert "shear_ratio" in capsys.readouterr().err


# ---------------------------------------------------------------------- sweep errors
TINY = """title = "tiny plate"
[mesh]
rectangle = { lx = 20.0, ly = 10.0, nx = 2, ny = 1 }
[sets]
tip = { x_min = "100%" }
[[part]]
element = "mindlin"
material = { E = 1000.0, nu = 0.3, thickness = 1.0, density = 1e-9 }
[[fix]]
nodes = "left"
[gravity]
acceleration = [0.0, 0.0, -9810.0]
[solver]
kind = "static"
increments = 1
[output]
history = { reactions = ["left"], displacements = ["tip"] }
"""


@contextlib.contextmanager
def no_cluster(scheduler=None, workers=None):
    yield None, None


def in_this_process(client, function, arguments, label, progress=None, done=None):
    """map_tasks without Dask: every task here, one after another, a raise its Failure."""
    results = []
    for i, args in enumerate(arguments):
        try:
            result = function(*args)
        except Exception as error:
            result = Failure(f"{type(error).__name__}: {error}")
        results.append(result)
        if done is not None:
            done(i, result)
    return results


def test_a_failed_variant_s_whole_error_is_in_the_printed_table_and_in_sweep_csv(
    capsys, tmp_path, monkeypatch
):
    monkeypatch.setattr(fibreshell.sweep, "dask_client", no_cluster)
    monkeypatch.setattr(fibreshell.sweep, "map_tasks", in_this_process)
    case = tmp_path / "a-case-file-with-a-long-enough-name-to-make-its-messages-long.toml"
    case.write_text(TINY)
    out = tmp_path / "sweep"
    argv = ["sweep", str(case), "--vary", "part.0.material.thickness=1.0,-1.0", "--out", str(out)]
    assert main([*argv, "--quiet"]) == 1
    tables, _ = apply_overrides(fibreshell.case.read_case_data(case),
                                {"part.0.material.thickness": -1.0})  # fmt: skip
    with pytest.raises(ValueError) as caught:
        case_from_data(tables, case.resolve())
    whole = f"{type(caught.value).__name__}: {caught.value}"
    assert len(whole) > 160  # longer than the table once cut it
    printed = capsys.readouterr().out
    assert whole in printed
    assert "1 failed (variants 1: see the error column)" in printed
    with open(out / "sweep.csv", newline="") as handle:
        rows = list(csv.DictReader(handle))
    assert [row["converged"] for row in rows] == ["True", "False"]
    assert rows[1]["error"] == whole and rows[0]["error"] == ""
    assert float(rows[0]["displacement_tip_z"]) < 0.0  # the other variant ran


def test_an_error_of_several_lines_is_printed_whole_indented_under_its_first():
    error = "SolverError: the run stopped\n" + "x" * 300 + "\nlast line"
    table = SweepTable(keys=["solver.increments"], rows=[
        {"variant": 0, "solver.increments": 2, "converged": True, "error": "",
         "wall_time_s": 1.0, "displacement_tip_z": -1.5},
        {"variant": 1, "solver.increments": 4, "converged": False, "error": error},
    ])  # fmt: skip
    lines = table.text().splitlines()
    assert len(lines) == 5
    start = lines[2].index("SolverError")
    assert lines[3] == " " * start + "x" * 300 and lines[4] == " " * start + "last line"


def test_the_printed_sweep_shows_tool_forces_and_the_fibre_strain_not_tool_travels():
    """Three tools, two history sets: the driven tools' prescribed travel (the same in every
    variant) took two of the six slots and pushed out the holder's force and the largest
    fibre strain; sweep.csv keeps every column."""
    row = {
        "variant": 0, "layup.friction": 0.3, "converged": True, "error": "",
        "wall_time_s": 1.0, "reaction_edge_z": 1.0, "displacement_tip_z": -2.0,
        "tool1_force_z": 3.0, "tool1_displacement_z": 0.0, "tool2_force_z": 4.0,
        "tool2_displacement_z": -6.0, "tool3_force_z": 5.0, "max_fibre_strain": 0.01,
    }  # fmt: skip
    header = SweepTable(keys=["layup.friction"], rows=[row]).text().splitlines()[0].split()
    assert "tool3_force_z" in header and "max_fibre_strain" in header
    assert not any(name.endswith("displacement_z") and name.startswith("tool") for name in header)
