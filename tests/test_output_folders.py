"""Output folders are checked before a run (a folder, writable, room for the first frames), a
write that fails during the run is one OutputError (an OSError) naming the path and what was
kept, the command line says it in one line on stderr with exit status 3 and no traceback, and
a reused output folder is cleaned of the files a run writes.

Running as root ignores file modes, so an unwritable folder is simulated by a path under a
regular file (ENOTDIR) and by writers made to raise ENOSPC or EACCES."""

import errno
import os
from collections import namedtuple
from pathlib import Path, PurePath

import pytest
from test_interrupts import CASE, STATIC, hanging_cable

import femcore.writable
import solvers.output
from femcore.writable import OutputError, check_folder
from fibreshell.case import CaseError, load_case
from fibreshell.cli import main
from fibreshell.run import run_case
from solvers import CentralDifference, DynamicRelaxation

Usage = namedtuple("Usage", "total used free")


def failing_on_call(patch, owner, name: str, call: int, code=errno.ENOSPC) -> None:
    """Make ``owner.name(self, ...)`` raise OSError(``code``) on its ``call``-th call, as a
    full (ENOSPC) or refused (EACCES) disk does, naming the file it was to write."""
    original = getattr(owner, name)
    calls = [0]

    def failing(self, *args, **kwargs):
        calls[0] += 1
        if calls[0] == call:
            raise OSError(code, os.strerror(code), str(getattr(self, "path", "result.vtu")))
        return original(self, *args, **kwargs)

    patch.setattr(owner, name, failing)


def case_file(tmp_path: Path, text: str = CASE) -> Path:
    path = tmp_path / "case.toml"
    path.write_text(text)
    return path


# ---------------------------------------------------------------------- before the run
def test_a_folder_under_a_regular_file_is_refused_before_anything_runs(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    with pytest.raises(ValueError, match="is a file, not a folder"):
        check_folder(blocker / "out", "--out")
    with pytest.raises(ValueError, match="'.*file' is a file"):
        run_case(load_case(case_file(tmp_path)), blocker / "out", progress=False)
    with pytest.raises(ValueError, match="is a file"):
        hanging_result().write(blocker / "x.pvd")


def test_a_disk_too_full_for_the_first_frames_is_refused_with_the_numbers(tmp_path, monkeypatch):
    monkeypatch.setattr(femcore.writable.shutil, "disk_usage", lambda _: Usage(1e9, 1e9, 1000))
    with pytest.raises(OutputError, match="MB free on its disk, the frames need about") as error:
        run_case(load_case(case_file(tmp_path)), tmp_path / "out", progress=False)
    assert error.value.errno == errno.ENOSPC and isinstance(error.value, OSError)
    assert not (tmp_path / "out" / "summary.json").exists()


def test_a_folder_that_cannot_be_written_is_refused(tmp_path, monkeypatch):
    def refuse(*args, **kwargs):
        raise PermissionError(errno.EACCES, "Permission denied")

    monkeypatch.setattr(femcore.writable.tempfile, "TemporaryFile", refuse)
    with pytest.raises(OutputError, match="is not writable: Permission denied"):
        check_folder(tmp_path, "--out")


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes into read-only folders")
def test_a_read_only_folder_is_refused(tmp_path):
    folder = tmp_path / "read-only"
    folder.mkdir(mode=0o500)
    with pytest.raises(OutputError, match="not writable"):
        check_folder(folder, "--out")


# ---------------------------------------------------------------------- during the run
def test_a_full_disk_during_an_explicit_run_says_the_file_and_the_frames_kept(
    tmp_path, monkeypatch
):
    failing_on_call(monkeypatch, solvers.output.FrameStream, "write", 4)
    solver = CentralDifference(duration=0.01, output_interval=0.001, output=tmp_path / "run.pvd",
                               progress=False)  # fmt: skip
    with pytest.raises(OutputError) as error:
        solver.solve(hanging_cable(), checkpoint=tmp_path / "run.ckpt")
    message = str(error.value)
    assert error.value.errno == errno.ENOSPC and "No space left on device" in message
    assert f"cannot write {str(tmp_path / 'run.pvd')!r}" in message
    assert "kept: the 3 frame(s) of" in message and "\n" not in message


def test_a_failed_write_of_result_write_names_the_file_and_the_frames_written(
    tmp_path, monkeypatch
):
    import meshio

    failing_on_call(monkeypatch, meshio.Mesh, "write", 2, errno.EACCES)
    with pytest.raises(OutputError, match="Permission denied; stopped, kept: the frame files "
                       "result_00000.vtu$"):  # fmt: skip
        hanging_result().write(tmp_path / "result.pvd")


def test_fibreshell_run_on_a_full_disk_gives_one_line_and_status_3(tmp_path, monkeypatch, capsys):
    failing_on_call(monkeypatch, solvers.output.FrameStream, "write", 3)
    out = tmp_path / "out"
    assert main(["run", str(case_file(tmp_path)), "--out", str(out), "--quiet"]) == 3
    said = capsys.readouterr().err
    assert said.count("\n") == 1 and "Traceback" not in said
    assert f"cannot write {str(out / 'result.pvd')!r}: No space left on device" in said
    assert "kept: the 2 frame(s)" in said


def test_fibreshell_run_sweep_and_report_refuse_an_out_under_a_file(tmp_path, capsys):
    blocker = tmp_path / "file"
    blocker.write_text("")
    case = str(case_file(tmp_path))
    assert main(["run", case, "--out", str(blocker / "out")]) == 2
    assert main(["sweep", case, "--vary", "solver.damping=1,2", "--out", str(blocker)]) == 2
    said = capsys.readouterr().err
    assert said.count("is a file") == 2 and "Traceback" not in said
    with pytest.raises(SystemExit) as exit_status:
        main(["report", "--out", str(blocker / "report")])
    assert exit_status.value.code == 2 and "is a file" in capsys.readouterr().err


# ---------------------------------------------------------------------- reused folders
def test_a_reused_output_folder_keeps_no_file_of_the_previous_run_and_every_file_of_the_user(
    tmp_path,
):
    """The files a run writes go by their exact names (the frames by their numbered
    pattern); a user's results_measured.vtu, result_scan.vtu and notes.part are not those."""
    out = tmp_path / "out"
    out.mkdir()
    stale = ["result_0009.vtu", "result_00012.vtu", "energies.csv", "checkpoint.pkl",
             "result.pvd.part", "checkpoint.pkl.part"]  # fmt: skip
    mine = ["notes.txt", "results_measured.vtu", "result_scan.vtu", "notes.part",
            "result_01.vtu", "result.vtu"]  # fmt: skip
    for name in stale + mine:
        (out / name).write_text("old")
    run_case(load_case(case_file(tmp_path, STATIC)), out, progress=False)
    left = sorted(path.name for path in out.iterdir())
    written = ["history.csv", "result.pvd", "result_00000.vtu", "result_00001.vtu",
               "result_00002.vtu", "result_00003.vtu", "summary.json"]  # fmt: skip
    assert left == sorted(written + mine)
    assert all((out / name).read_text() == "old" for name in mine)


# ---------------------------------------------------------------------- case files
def test_checkpoint_options_of_a_case_file(tmp_path):
    relaxation = CASE.replace(
        'kind = "explicit"\nduration = 0.004\noutput_interval = 0.001\ndamping = 100.0',
        'kind = "relaxation"\nincrements = 2\ncheckpoint = "saved/relax.pkl"',
    )
    case = load_case(case_file(tmp_path, relaxation))
    assert case.solver["checkpoint"] == "saved/relax.pkl"
    default = load_case(case_file(tmp_path, CASE)).solver
    assert default["checkpoint"] == "checkpoint.pkl" and default["checkpoint_interval"] == 60.0
    off = CASE.replace("damping = 100.0", "damping = 100.0\ncheckpoint = false")
    assert load_case(case_file(tmp_path, off)).solver["checkpoint"] is None
    for text, key in (
        (STATIC.replace("increments = 3", "increments = 3\ncheckpoint = 'x.pkl'"), "checkpoint"),
        (relaxation.replace("increments = 2", "increments = 2\ncheckpoint_interval = 5.0"),
         "checkpoint_interval"),
        (CASE.replace("damping = 100.0", "damping = 100.0\ncheckpoint_interval = -1"),
         "checkpoint_interval"),
        (CASE.replace("damping = 100.0", "damping = 100.0\ncheckpoint = 3"), "checkpoint"),
    ):  # fmt: skip
        with pytest.raises(CaseError, match=rf"\[solver\.{key}\]"):
            load_case(case_file(tmp_path, text))


@pytest.mark.parametrize(
    "name, taken",
    [("result.pvd", "result.pvd"), ("history.csv", "history.csv"),
     ("./summary.json", "summary.json"), ("energies.csv", "energies.csv"),
     ("result_00003.vtu", "result_00003.vtu"), ("sub/../result.pvd.part", "result.pvd.part"),
     ("variant.json", "variant.json")],
)  # fmt: skip
def test_a_checkpoint_named_as_a_file_the_run_writes_is_refused_naming_that_file(
    tmp_path, name, taken
):
    """A checkpoint named result.pvd turned the series into a pickle, one named history.csv
    was overwritten by the history while summary.json named it as the checkpoint."""
    text = CASE.replace("damping = 100.0", f"damping = 100.0\ncheckpoint = {name!r}")
    with pytest.raises(CaseError, match=rf"\[solver\.checkpoint\]: .* would overwrite '{taken}'"):
        load_case(case_file(tmp_path, text))


def test_a_checkpoint_path_that_lands_on_an_output_is_refused_before_the_run(tmp_path):
    out = tmp_path / "out"
    for name in (str(out / "history.csv"), "../out/result.pvd"):
        text = CASE.replace("damping = 100.0", f"damping = 100.0\ncheckpoint = {name!r}")
        with pytest.raises(ValueError, match=r"would overwrite '(history.csv|result.pvd)'"):
            run_case(load_case(case_file(tmp_path, text)), out, progress=False)
    assert not (out / "history.csv").exists() and not (out / "result.pvd").exists()


@pytest.mark.parametrize(
    "name", ["saved/result.pvd", "../a/history.csv", "../a/result_00002.vtu", "/far/summary.json",
             "../a/energies.csv"],
)  # fmt: skip
def test_a_checkpoint_named_as_a_runs_output_is_refused_in_any_folder(tmp_path, name):
    """'../a/result.pvd' beside a run writing into a: the second run removed a's series and
    wrote its pickle there, exit 0 (and 'saved/result.pvd' was let through). A file of a run's
    name in any folder is, or may become, a run's."""
    text = CASE.replace("damping = 100.0", f"damping = 100.0\ncheckpoint = {name!r}")
    taken = PurePath(name).name
    with pytest.raises(CaseError, match=rf"would overwrite '{taken}', which a run writes"):
        load_case(case_file(tmp_path, text))


def test_resume_without_a_checkpoint_is_refused(tmp_path, capsys):
    case = str(case_file(tmp_path))
    assert main(["run", case, "--out", str(tmp_path / "new"), "--resume", "--quiet"]) == 2
    assert "nothing to resume" in capsys.readouterr().err


def hanging_result():
    return DynamicRelaxation(increments=2, progress=False).solve(hanging_cable())


def test_python_m_validation_on_a_full_disk_gives_one_line_and_status_3(
    tmp_path, monkeypatch, capsys
):
    import validation.__main__ as report

    def full(names, resolution, out, jobs):
        (out / "bai-5.1.png").write_text("")
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(out / "results.json"))

    monkeypatch.setattr(report, "run_cases", full)
    assert report.main(["--cases", "bai-5.1", "--out", str(tmp_path / "report")]) == 3
    said = capsys.readouterr().err
    assert said.count("\n") == 1 and "results.json" in said and "No space left" in said
    assert "kept: 1 file(s) in" in said
