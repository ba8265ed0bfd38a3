"""Ctrl-C and SIGTERM inside ``solvers.interruptible()``: the solver finishes the step (the
relaxation iteration, the static increment) in progress, saves its checkpoint, and raises
``Interrupted`` with every good frame; the same solve then resumes to the same bits as a run
never interrupted. ``fibreshell run`` writes its outputs and summary.json (status
"interrupted"), prints one line and exits 130; ``--resume`` goes on from the checkpoint.

The signal is sent by the process to itself from inside the N-th step (a wrapped step
function), so that the run stops at a known step."""

import csv
import json
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import solvers.explicit
import solvers.static
import solvers.static_run
from elements import Cable
from femcore import Mesh, Model
from femcore.fingerprint import Uncalled, digest
from fibreshell.cli import main
from fibreshell.run import FrameRows
from solvers import CentralDifference, DynamicRelaxation, Interrupted, interruptible
from solvers.interrupts import STOP

ROOT = Path(__file__).resolve().parents[1]


def hanging_cable() -> Model:
    """A slack cable between two fixed ends dropping under gravity (tests/test_explicit.py)."""
    n = 20
    points = np.column_stack([np.linspace(0, 100.0, n + 1), np.zeros(n + 1), np.zeros(n + 1)])
    model = Model(Mesh(points, lines=np.column_stack([np.arange(n), np.arange(1, n + 1)])))
    model.add(Cable(axial_stiffness=1e3, mass_per_length=1e-9))
    model.fix([0, n])
    model.gravity((0.0, 0.0, -9810.0))
    return model


def signal_on_call(patch, owner, name: str, call: int, number=signal.SIGINT) -> None:
    """Make ``owner.name`` send ``number`` to this process on its ``call``-th call."""
    original = getattr(owner, name)
    calls = [0]

    def counted(*args, **kwargs):
        calls[0] += 1
        if calls[0] == call:
            os.kill(os.getpid(), number)
        return original(*args, **kwargs)

    patch.setattr(owner, name, counted)


def explicit(folder: Path) -> CentralDifference:
    return CentralDifference(duration=0.01, output_interval=0.001, output=folder / "run.pvd",
                             history=folder / "run.csv", history_nodes=[10],
                             progress=False)  # fmt: skip


def test_an_interrupted_explicit_run_stops_after_the_step_and_resumes_to_the_same_bits(
    tmp_path, monkeypatch
):
    (tmp_path / "whole").mkdir()
    (tmp_path / "cut").mkdir()
    reference = explicit(tmp_path / "whole").solve(hanging_cable())
    checkpoint = tmp_path / "cut" / "run.ckpt"
    with monkeypatch.context() as patch:
        signal_on_call(patch, solvers.explicit, "explicit_step", 700)
        with interruptible(), pytest.raises(Interrupted) as stopped:
            explicit(tmp_path / "cut").solve(hanging_cable(), checkpoint=checkpoint)
    error = stopped.value
    assert error.signal == "SIGINT" and error.checkpoint == checkpoint and checkpoint.exists()
    assert error.result.steps == 700 and not error.result.converged
    assert 0.0 < error.result.frames[-1].time < 0.01
    assert "interrupted by SIGINT after step 700" in str(error)

    resumed = explicit(tmp_path / "cut").solve(hanging_cable(), checkpoint=checkpoint)
    np.testing.assert_array_equal(resumed.positions, reference.positions)
    np.testing.assert_array_equal(resumed.velocities, reference.velocities)
    assert resumed.steps == reference.steps
    for name in ("run.csv", "run.pvd"):  # every energy record and frame, to the last digit
        assert (tmp_path / "cut" / name).read_text() == (tmp_path / "whole" / name).read_text()


def test_an_interrupted_relaxation_keeps_its_converged_increments_and_resumes_to_the_same_bits(
    tmp_path, monkeypatch
):
    solver = DynamicRelaxation(increments=3, progress=False)
    reference = solver.solve(hanging_cable())
    checkpoint = tmp_path / "relax.ckpt"
    with monkeypatch.context() as patch:  # the signal as the second increment starts
        signal_on_call(patch, DynamicRelaxation, "_relax", 2)
        with interruptible(), pytest.raises(Interrupted) as stopped:
            solver.solve(hanging_cable(), checkpoint=checkpoint)
    error = stopped.value
    assert [frame.load_factor for frame in error.result.frames] == pytest.approx([0.0, 1 / 3])
    assert error.checkpoint == checkpoint and "increment 2/3" in str(error)
    resumed = solver.solve(hanging_cable(), checkpoint=checkpoint)
    np.testing.assert_array_equal(resumed.positions, reference.positions)
    assert resumed.info["iterations_per_increment"] == reference.info["iterations_per_increment"]


def test_a_relaxation_interrupted_inside_its_first_increment_counts_the_iterations_taken(
    monkeypatch,
):
    # the signal at the 40th force evaluation: the iterations before the stop are the run's
    # steps, not 0 (no increment converged)
    import femcore.compiled

    with monkeypatch.context() as patch:
        signal_on_call(patch, femcore.compiled.CompiledModel, "internal_force", 40)
        with interruptible(), pytest.raises(Interrupted) as stopped:
            DynamicRelaxation(increments=3, progress=False).solve(hanging_cable())
    error = stopped.value
    assert "increment 1/3" in str(error) and len(error.result.frames) == 1
    taken = int(str(error).split("(iteration ")[1].split(")")[0]) - 1
    assert 30 <= taken <= 40 and error.result.steps == taken


def test_a_second_signal_during_the_wind_down_raises_keyboard_interrupt():
    with interruptible() as stop:
        os.kill(os.getpid(), signal.SIGTERM)
        time.sleep(0.01)  # the handler runs in the main thread between bytecodes
        assert stop.signal == "SIGTERM"
        with pytest.raises(KeyboardInterrupt):
            os.kill(os.getpid(), signal.SIGINT)
            time.sleep(1.0)


def test_the_previous_handlers_and_the_flag_come_back_after_the_block():
    before = signal.getsignal(signal.SIGINT), signal.getsignal(signal.SIGTERM)
    with interruptible():
        assert signal.getsignal(signal.SIGINT) is not before[0]
    assert (signal.getsignal(signal.SIGINT), signal.getsignal(signal.SIGTERM)) == before
    assert STOP.signal is None


def test_off_the_main_thread_the_block_changes_nothing():
    seen = []

    def worker():
        with interruptible():
            seen.append(signal.getsignal(signal.SIGINT))

    before = signal.getsignal(signal.SIGINT)
    thread = threading.Thread(target=worker)
    thread.start()
    thread.join()
    assert seen == [before]


# ---------------------------------------------------------------------- fibreshell run
CASE = """
title = "falling cantilever"
[mesh]
rectangle = { lx = 100.0, ly = 10.0, nx = 20, ny = 2 }
[sets]
tip = { x_min = 100.0 }
[[part]]
element = "fibrous"
options = { clamped = "left" }
[part.material]
thickness = 0.2
areal_density = 8e-9
tension = 1000.0
shear = 1.0
bending = 10.0
[[fix]]
nodes = "left"
[gravity]
acceleration = [0.0, 0.0, -9810.0]
[solver]
kind = "explicit"
duration = 0.004
output_interval = 0.001
damping = 100.0
[output]
history = { reactions = ["left"], displacements = ["tip"] }
"""


STATIC = CASE.replace(
    'kind = "explicit"\nduration = 0.004\noutput_interval = 0.001\ndamping = 100.0',
    'kind = "static"\nincrements = 3',
)


def run(case: Path, out: Path, *options: str) -> int:
    return main(["run", str(case), "--out", str(out), "--quiet", *options])


def test_fibreshell_run_interrupted_writes_its_outputs_says_one_line_and_resumes(
    tmp_path, monkeypatch, capsys
):
    case = tmp_path / "case.toml"
    case.write_text(CASE)
    assert run(case, tmp_path / "whole") == 0
    capsys.readouterr()
    with monkeypatch.context() as patch:
        signal_on_call(patch, solvers.explicit, "explicit_step", 200, signal.SIGTERM)
        assert run(case, tmp_path / "cut") == 130
    said = capsys.readouterr()
    assert said.out.count("\n") == 1 and "INTERRUPTED by SIGTERM" in said.out
    assert f"--out {tmp_path / 'cut'} --resume" in said.out and "checkpoint.pkl" in said.out
    summary = json.loads((tmp_path / "cut" / "summary.json").read_text())
    assert summary["status"] == "interrupted" and summary["steps"] == 200
    assert summary["checkpoint"] == str(tmp_path / "cut" / "checkpoint.pkl")
    assert 0.0 < summary["final_time"] < 0.004
    frames = (tmp_path / "cut" / "result.pvd").read_text().count("<DataSet")
    assert frames >= 2  # the first and those written up to 200 steps (a frame per ms)
    with open(tmp_path / "cut" / "history.csv") as handle:
        assert len(list(csv.DictReader(handle))) == frames  # a row per frame of the series

    assert run(case, tmp_path / "cut", "--resume") == 0
    for name in ("history.csv", "energies.csv", "result.pvd"):
        assert (tmp_path / "cut" / name).read_text() == (tmp_path / "whole" / name).read_text()
    final = sorted((tmp_path / "whole").glob("result_*.vtu"))[-1].name
    assert (tmp_path / "cut" / final).read_bytes() == (tmp_path / "whole" / final).read_bytes()
    summary = json.loads((tmp_path / "cut" / "summary.json").read_text())
    assert summary["status"] == "done"


# How [output] history may change between a stop and a resume (the rectangle's "right" set is
# its own; "tip" the case's).
HISTORY_CHANGES = {
    "a reactions set added": ('reactions = ["left"]', 'reactions = ["left", "right"]'),
    "a reactions set removed": ('reactions = ["left"], ', ""),
    "a set redefined under its name": ("tip = { x_min = 100.0 }", "tip = { x_min = 95.0 }"),
}


@pytest.fixture(scope="module")
def interrupted_folder(tmp_path_factory) -> Path:
    """The falling cantilever stopped by SIGTERM at its 200th step (checkpoint, 2 frames)."""
    folder = tmp_path_factory.mktemp("history")
    case = folder / "case.toml"
    case.write_text(CASE)
    with pytest.MonkeyPatch.context() as patch:
        signal_on_call(patch, solvers.explicit, "explicit_step", 200, signal.SIGTERM)
        assert run(case, folder / "cut") == 130
    return folder / "cut"


@pytest.mark.parametrize("change", HISTORY_CHANGES)
def test_a_resume_after_the_history_sets_changed_is_refused_naming_them(
    interrupted_folder, tmp_path, capsys, change
):
    """The rows kept before the stop carry the old sets' columns: the resume is refused
    before it runs, naming [output] history, and leaves the folder as the stop left it."""
    before = {p.name: p.read_bytes() for p in interrupted_folder.iterdir()}
    old, new = HISTORY_CHANGES[change]
    assert old in CASE
    case = tmp_path / "case.toml"
    case.write_text(CASE.replace(old, new))
    capsys.readouterr()
    assert run(case, interrupted_folder, "--resume") == 2
    said = capsys.readouterr().err
    assert "[output.history]: changed since the checkpoint was written" in said
    assert "run without --resume" in said
    assert {p.name: p.read_bytes() for p in interrupted_folder.iterdir()} == before


def test_a_resume_after_the_model_changed_says_the_case_file_s_way_out(
    interrupted_folder, tmp_path, capsys
):
    """The fabric's bending changed: refused naming what differs, and, from the command line,
    the case to give back or the run without --resume (before: only the Python API's
    "delete it or point checkpoint= elsewhere")."""
    case = tmp_path / "case.toml"
    case.write_text(CASE.replace("bending = 10.0", "bending = 12.0"))
    capsys.readouterr()
    assert run(case, interrupted_folder, "--resume") == 2
    said = capsys.readouterr().err
    assert "was written for another model" in said
    assert f"the case {str(case)!r} changed since the checkpoint was written" in said
    assert "run without --resume to start again" in said


def test_the_rows_of_a_frame_are_known_by_their_sets_names_and_nodes():
    """What a checkpoint reads of fibreshell's frame summary (FrameRows): a reactions set
    redefined under its name (other nodes, the energy records' nodes unchanged) is another."""
    origins = np.zeros((1, 3))
    rows = [
        FrameRows(reactions=(("left", np.array(nodes)),), displacements=(("tip", [9], origins),))
        for nodes in ([0, 1], [0, 1], [0, 2])
    ]
    first, same, other = (digest(Uncalled(r)) for r in rows)
    assert first == same != other
    renamed = FrameRows(
        reactions=(("held", np.array([0, 1])),), displacements=rows[0].displacements
    )
    assert digest(Uncalled(renamed)) != first


def test_an_interrupted_static_run_keeps_its_converged_increments(tmp_path, monkeypatch, capsys):
    case = tmp_path / "case.toml"
    case.write_text(STATIC)
    with monkeypatch.context() as patch:  # frames: the reference state, then one per increment
        signal_on_call(patch, solvers.static_run, "make_frame", 2)
        assert run(case, tmp_path / "out") == 130
    said = capsys.readouterr().out
    assert "INTERRUPTED by SIGINT after" in said and "load factor 0.333333" in said
    assert "run it again" in said
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary["status"] == "interrupted" and summary["frames"] == 2
    assert (tmp_path / "out" / "result.pvd").read_text().count("<DataSet") == 2
    assert run(case, tmp_path / "out", "--resume") == 2  # nothing to resume: said, not run
    assert "a static run has no checkpoint" in capsys.readouterr().err


RELAXATION = STATIC.replace('kind = "static"', 'kind = "relaxation"')


@pytest.mark.parametrize(
    "text, stopped_in, call, said",
    [
        # an explicit run told to keep no checkpoint, stopped at its 50th step
        (CASE.replace("damping = 100.0", "damping = 100.0\ncheckpoint = false"),
         "explicit_step", 50, "no checkpoint asked for ([solver] checkpoint = false)"),
        # a relaxation stopped at its 20th force evaluation, inside its first increment: its
        # checkpoint is written as an increment converges, and none has
        (RELAXATION, "internal_force", 20, "no increment converged yet"),
    ],
    ids=["explicit without checkpoint", "relaxation inside its first increment"],
)  # fmt: skip
def test_an_interrupt_with_nothing_to_resume_says_why_for_its_solver(
    tmp_path, monkeypatch, capsys, text, stopped_in, call, said
):
    """The line names the reason there is no checkpoint (before: "no checkpoint (static run)"
    for every solver, also for the explicit and relaxation runs that are not static)."""
    import femcore.compiled

    owner = solvers.explicit if stopped_in == "explicit_step" else femcore.compiled.CompiledModel
    case = tmp_path / "case.toml"
    case.write_text(text)
    with monkeypatch.context() as patch:
        signal_on_call(patch, owner, stopped_in, call)
        assert run(case, tmp_path / "out") == 130
    line = capsys.readouterr().out
    assert "INTERRUPTED by SIGINT" in line and said in line and "run it again" in line
    assert "static" not in line and "--resume" not in line
    assert json.loads((tmp_path / "out" / "summary.json").read_text())["checkpoint"] is None


def test_a_static_run_writes_each_increment_as_it_converges(tmp_path, monkeypatch):
    """A kill (no chance to write at the end) leaves the converged increments: the series
    lists each frame once its increment converged."""
    case = tmp_path / "case.toml"
    case.write_text(STATIC)
    listed = []
    original = solvers.static.StaticRun.frame

    def frame(self, *args):
        listed.append((tmp_path / "out" / "result.pvd").read_text().count("<DataSet"))
        return original(self, *args)

    monkeypatch.setattr(solvers.static.StaticRun, "frame", frame)
    assert run(case, tmp_path / "out") == 0
    assert listed == [1, 2, 3]  # before each increment's frame: those converged before it


@pytest.mark.slow
def test_sigterm_from_outside_stops_fibreshell_run_without_a_traceback(tmp_path):
    case = tmp_path / "case.toml"
    case.write_text(CASE.replace("duration = 0.004", "duration = 0.2"))
    out = tmp_path / "out"
    child = subprocess.Popen(
        [sys.executable, "-c", "import sys; from fibreshell.cli import main; sys.exit(main())",
         "run", str(case), "--out", str(out), "--quiet"],
        env=dict(os.environ, PYTHONPATH=str(ROOT)), stdout=subprocess.PIPE,
        stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    deadline = time.monotonic() + 120.0
    energies = out / "energies.csv"
    while time.monotonic() < deadline and child.poll() is None:
        if energies.exists() and energies.read_text().count("\n") > 20:
            break
        time.sleep(0.05)
    assert child.poll() is None, "the run ended before it could be interrupted"
    child.send_signal(signal.SIGTERM)
    said, errors = child.communicate(timeout=120.0)
    assert child.returncode == 130 and "Traceback" not in errors
    assert said.count("\n") == 1 and "--resume" in said
    assert json.loads((out / "summary.json").read_text())["status"] == "interrupted"
