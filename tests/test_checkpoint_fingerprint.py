"""A checkpoint knows the model it was written for: another model's (other loads, stiffness,
amplitude, tool, solver settings) is refused naming what differs, a damaged file is refused
naming the file, the streamed series and history must hold what the checkpoint counted, and
the same model resumed ends where a run never interrupted ends, to the last bit."""

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import solvers.explicit
from elements import Cable, RigidPlane
from femcore import Mesh, Model
from femcore.fingerprint import Uncalled, digest, fingerprint
from solvers import (
    CentralDifference,
    DynamicRelaxation,
    Interrupted,
    interruptible,
)

N = 12  # cable elements


def ramp(rate: float):
    """An amplitude whose code is the same for every rate: only its captured value differs."""
    return lambda tau: min(1.0, rate * tau)


def cable(
    gravity=-9810.0, stiffness=1e3, amplitude=None, plane=-500.0, motion=(0.0, 0.0, 0.0)
) -> Model:
    """A cable fixed at both ends sagging under gravity, over a plane far below it."""
    points = np.column_stack([np.linspace(0, 100.0, N + 1), np.zeros(N + 1), np.zeros(N + 1)])
    model = Model(Mesh(points, lines=np.column_stack([np.arange(N), np.arange(1, N + 1)])))
    model.add(Cable(axial_stiffness=stiffness, mass_per_length=1e-9))
    model.fix([0, N])
    model.gravity((0.0, 0.0, gravity), amplitude=ramp(1.0) if amplitude is None else amplitude)
    model.contact(RigidPlane((0.0, 0.0, plane), (0.0, 0.0, 1.0), motion=motion))
    return model


def explicit(**options) -> CentralDifference:
    return CentralDifference(
        **{"duration": 2e-4, "progress": False, "kinetic_bound": None, **options}
    )


def relaxation(**options) -> DynamicRelaxation:
    return DynamicRelaxation(**{"increments": 2, "progress": False, **options})


# What changes, and the part (and item) the refusal must name.
OTHER_MODELS = {
    "twice the gravity": (dict(gravity=-2 * 9810.0), {}, r"its loads differ \(gravity 0\)"),
    "ten times EA": (dict(stiffness=1e4), {}, r"its elements differ \(.*axial_stiffness\)"),
    "another amplitude": (dict(amplitude=ramp(2.0)), {}, r"its loads differ \(gravity 0\)"),
    "the tool elsewhere": (dict(plane=-400.0), {}, r"its tools differ \(interaction 0 .*tool\)"),
    "a moving tool": (dict(motion=(0, 0, 1.0)), {}, r"its tools differ"),
}


@pytest.fixture(scope="module")
def explicit_checkpoint(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("explicit") / "run.ckpt"
    explicit().solve(cable(), checkpoint=path)
    return path


@pytest.fixture(scope="module")
def relaxation_checkpoint(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("relaxation") / "run.ckpt"
    relaxation().solve(cable(), checkpoint=path)
    return path


@pytest.mark.parametrize("change", OTHER_MODELS)
def test_an_explicit_checkpoint_of_another_model_is_refused_naming_what_differs(
    explicit_checkpoint, change
):
    model, _, names = OTHER_MODELS[change]
    with pytest.raises(ValueError, match=f"written for another model: {names}.*delete it"):
        explicit().solve(cable(**model), checkpoint=explicit_checkpoint)


@pytest.mark.parametrize("change", OTHER_MODELS)
def test_a_relaxation_checkpoint_of_another_model_is_refused_naming_what_differs(
    relaxation_checkpoint, change
):
    model, _, names = OTHER_MODELS[change]
    with pytest.raises(ValueError, match=f"written for another model: {names}"):
        relaxation().solve(cable(**model), checkpoint=relaxation_checkpoint)


@pytest.mark.parametrize(
    "settings", [dict(damping=10.0), dict(duration=3e-4), dict(safety=0.5), dict(dt=1e-6)]
)
def test_an_explicit_checkpoint_of_other_solver_settings_is_refused(explicit_checkpoint, settings):
    (name,) = settings
    expected = rf"other solver settings: its solver settings differ \({name}"
    with pytest.raises(ValueError, match=expected):
        explicit(**settings).solve(cable(), checkpoint=explicit_checkpoint)


@pytest.mark.parametrize("settings", [dict(increments=3), dict(tol=1e-3), dict(damping="viscous")])
def test_a_relaxation_checkpoint_of_other_solver_settings_is_refused(
    relaxation_checkpoint, settings
):
    (name,) = settings
    with pytest.raises(ValueError, match=rf"solver settings differ \({name}"):
        relaxation(**settings).solve(cable(), checkpoint=relaxation_checkpoint)


def test_a_checkpoint_of_another_solver_kind_is_refused_naming_both_kinds_first(
    explicit_checkpoint, relaxation_checkpoint
):
    # Every setting of two kinds differs: the kind is what the user has to hear.
    with pytest.raises(
        ValueError,
        match=r"written by another solver, CentralDifference \(this run is DynamicRelaxation\): ",
    ):
        relaxation().solve(cable(), checkpoint=explicit_checkpoint)
    with pytest.raises(
        ValueError,
        match=r"written by another solver, DynamicRelaxation \(this run is CentralDifference\): ",
    ):
        explicit().solve(cable(), checkpoint=relaxation_checkpoint)


def test_the_same_model_built_again_has_the_same_fingerprint():
    assert fingerprint(cable().compile()) == fingerprint(cable().compile())


def test_another_process_gives_the_same_fingerprint():
    """What a resume relies on: the digests depend on the model alone, not on the process
    (hash seeds, object addresses, the module a lambda was defined in)."""
    here = Path(__file__).resolve().parent
    child = (
        "import json, sys\n"
        f"sys.path.insert(0, {str(here)!r})\n"
        "from test_checkpoint_fingerprint import cable\n"
        "from femcore.fingerprint import fingerprint\n"
        "print(json.dumps(fingerprint(cable().compile()).parts))\n"
    )
    env = dict(os.environ, PYTHONPATH=str(here.parent), PYTHONHASHSEED="12345")
    output = subprocess.run(
        [sys.executable, "-c", child], env=env, capture_output=True, text=True, check=True
    ).stdout
    assert json.loads(output) == fingerprint(cable().compile()).parts


def test_every_part_of_a_model_counts_in_its_fingerprint():
    base = fingerprint(cable().compile())
    given = cable().mesh
    shifted = Model(Mesh(given.points + np.array([0.0, 0.0, 1e-9]), lines=given.lines))
    shifted.add(Cable(axial_stiffness=1e3, mass_per_length=1e-9))
    shifted.fix([0, N])
    shifted.gravity((0.0, 0.0, -9810.0), amplitude=ramp(1.0))
    shifted.contact(RigidPlane((0.0, 0.0, -500.0), (0.0, 0.0, 1.0)))
    assert base.differences(fingerprint(shifted.compile())) == [
        "its mesh differs (node coordinates)"
    ]
    held = cable()
    held.fix([1], "uy")
    assert base.differences(fingerprint(held.compile())) == ["its supports differ (fixed DOFs)"]
    pushed = cable()
    pushed.force([3], (0.0, 0.0, 1.0))
    assert base.differences(fingerprint(pushed.compile())) == ["its loads differ (force 0)"]
    assert base.differences(fingerprint(cable().compile(), {"tol": 1e-4})) == [
        "its solver settings differ (tol)"
    ]


def test_an_amplitude_is_known_by_its_captured_values_and_the_globals_it_reads():
    assert digest(ramp(1.0)) == digest(ramp(1.0))
    assert digest(ramp(1.0)) != digest(ramp(1.0 + 1e-15))
    namespace = {"np": np, "RATE": 1.0}
    exec("def amplitude(tau):\n    return np.minimum(1.0, RATE * tau)", namespace)
    before = digest(namespace["amplitude"])
    namespace["RATE"] = 2.0
    assert digest(namespace["amplitude"]) != before


def test_a_section_counts_among_the_materials():
    from elements import MindlinShell
    from materials import ElasticShell

    def plate(modulus: float) -> Model:
        model = Model(Mesh.rectangle(20.0, 10.0, nx=2, ny=1))
        model.add(MindlinShell(ElasticShell(E=modulus, nu=0.3, thickness=1.0, density=2.7e-9)))
        model.fix("left")
        return model

    stiffer = fingerprint(plate(7e4 + 1).compile())
    differences = fingerprint(plate(70e3).compile()).differences(stiffer)
    assert differences == ["its materials differ (block 0 (MindlinShell) material)"]


def test_every_flipped_bit_of_a_checkpoint_is_refused_naming_the_file(tmp_path):
    """60 single-bit flips spread through a real checkpoint (its header, checksum, length and
    payload): each is refused with a ValueError naming the file, none resumes."""
    path = tmp_path / "run.ckpt"
    explicit(output=tmp_path / "run.pvd", history=tmp_path / "run.csv").solve(
        cable(), checkpoint=path
    )
    original = path.read_bytes()
    positions = np.unique(np.linspace(0, 8 * len(original) - 1, 60).astype(int))
    positions = np.unique(np.r_[positions, np.arange(0, 8 * 72, 37)])  # the header too
    assert len(positions) >= 60
    for bit in positions:
        damaged = bytearray(original)
        damaged[bit // 8] ^= 1 << (bit % 8)
        path.write_bytes(bytes(damaged))
        with pytest.raises(ValueError, match=str(path)):
            explicit(output=tmp_path / "run.pvd", history=tmp_path / "run.csv").solve(
                cable(), checkpoint=path
            )


def test_a_checkpoint_cut_short_is_refused(explicit_checkpoint, tmp_path):
    path = tmp_path / "short.ckpt"
    path.write_bytes(explicit_checkpoint.read_bytes()[:-100])
    with pytest.raises(ValueError, match="is damaged: its checksum does not match"):
        explicit().solve(cable(), checkpoint=path)


def streamed(tmp: Path, **options) -> CentralDifference:
    return explicit(
        output=tmp / "run.pvd",
        history=tmp / "run.csv",
        history_nodes=[N // 2],
        output_interval=2e-5,
        frame_summary=lambda frame: {"time": frame.time, "sag": frame.positions[N // 2, 2]},
        **options,
    )


def test_a_history_cut_short_is_refused_on_resume(tmp_path):
    checkpoint = tmp_path / "run.ckpt"
    streamed(tmp_path).solve(cable(), checkpoint=checkpoint)
    lines = (tmp_path / "run.csv").read_text().splitlines()
    assert len(lines) > 3
    (tmp_path / "run.csv").write_text("\n".join(lines[:2]) + "\n")
    with pytest.raises(ValueError, match=rf"run.csv' has 1 whole rows where the checkpoint "
                       rf"counted {len(lines) - 1} rows"):  # fmt: skip
        streamed(tmp_path).solve(cable(), checkpoint=checkpoint)
    (tmp_path / "run.csv").unlink()
    with pytest.raises(ValueError, match="run.csv' is missing"):
        streamed(tmp_path).solve(cable(), checkpoint=checkpoint)


def test_a_series_that_lacks_frames_the_checkpoint_counted_is_refused_on_resume(tmp_path):
    checkpoint = tmp_path / "run.ckpt"
    streamed(tmp_path).solve(cable(), checkpoint=checkpoint)
    frames = sorted(tmp_path.glob("run_*.vtu"))
    assert len(frames) == 11
    frames[5].unlink()
    with pytest.raises(ValueError, match=r"run.pvd' lists 11 frames where the checkpoint "
                       r"counted 11 \(the file 'run_00005.vtu' is missing\)"):  # fmt: skip
        streamed(tmp_path).solve(cable(), checkpoint=checkpoint)
    index = tmp_path / "run.pvd"
    lines = index.read_text().splitlines()
    index.write_text("\n".join(line for line in lines if "run_00007" not in line))
    with pytest.raises(ValueError, match="run.pvd' lists 10 frames where the checkpoint counted"):
        streamed(tmp_path).solve(cable(), checkpoint=checkpoint)


def test_an_explicit_run_stopped_and_resumed_ends_as_one_never_stopped(tmp_path, monkeypatch):
    """Interrupted (SIGINT) at its 25th step after checkpoints every 10 steps, then resumed
    with the same model and settings."""
    stopped, whole = tmp_path / "stopped", tmp_path / "whole"
    stopped.mkdir(), whole.mkdir()
    checkpoint = stopped / "run.ckpt"
    original, calls = solvers.explicit.explicit_step, [0]

    def interrupted_at_25(*args, **kwargs):
        calls[0] += 1
        if calls[0] == 25:
            os.kill(os.getpid(), signal.SIGINT)
        return original(*args, **kwargs)

    with monkeypatch.context() as patch, interruptible():
        patch.setattr(solvers.explicit, "explicit_step", interrupted_at_25)
        with pytest.raises(Interrupted):
            streamed(stopped).solve(cable(), checkpoint=checkpoint, checkpoint_interval=0.0)
    resumed = streamed(stopped).solve(cable(), checkpoint=checkpoint, checkpoint_interval=0.0)
    reference = streamed(whole).solve(cable())
    assert resumed.steps == reference.steps > 25
    np.testing.assert_array_equal(resumed.positions, reference.positions)
    np.testing.assert_array_equal(resumed.velocities, reference.velocities)
    for key in reference.energies:
        np.testing.assert_array_equal(resumed.energies[key], reference.energies[key])
    assert (stopped / "run.csv").read_text() == (whole / "run.csv").read_text()
    assert (stopped / "run.pvd").read_text() == (whole / "run.pvd").read_text()
    summaries = resumed.info["frame_summaries"]
    assert summaries == reference.info["frame_summaries"] and len(summaries) == 11


def test_a_relaxation_stopped_and_resumed_ends_as_one_never_stopped(tmp_path, monkeypatch):
    """Stopped in its third increment (as a kill would stop it), then resumed."""
    checkpoint = tmp_path / "run.ckpt"
    reference = relaxation(increments=3).solve(cable())
    relax = DynamicRelaxation._relax

    def killed_in_the_third(
        self, model, state, load_factor, masses, progress, increment, *rest, **kw
    ):
        if increment == 3:
            raise KeyboardInterrupt
        return relax(self, model, state, load_factor, masses, progress, increment, *rest, **kw)

    monkeypatch.setattr(DynamicRelaxation, "_relax", killed_in_the_third)
    with pytest.raises(KeyboardInterrupt):
        relaxation(increments=3).solve(cable(), checkpoint=checkpoint)
    monkeypatch.setattr(DynamicRelaxation, "_relax", relax)
    resumed = relaxation(increments=3).solve(cable(), checkpoint=checkpoint)
    assert resumed.info["iterations_per_increment"] == reference.info["iterations_per_increment"]
    np.testing.assert_array_equal(resumed.positions, reference.positions)
    assert len(resumed.frames) == len(reference.frames) == 4


PAUSE = 0.6  # s of wall time spent in the part of a run before its stop


def test_an_explicit_run_resumed_counts_the_wall_time_before_its_stop(tmp_path, monkeypatch):
    """A run that spent PAUSE seconds before its stop (at its 25th step, saved every 10):
    the resumed result's wall time counts them, and says how much came before."""
    original, calls = solvers.explicit.explicit_step, [0]

    def slow_then_interrupted(*args, **kwargs):
        calls[0] += 1
        if calls[0] == 20:
            time.sleep(PAUSE)
        if calls[0] == 25:
            os.kill(os.getpid(), signal.SIGINT)
        return original(*args, **kwargs)

    checkpoint = tmp_path / "run.ckpt"
    with monkeypatch.context() as patch, interruptible():
        patch.setattr(solvers.explicit, "explicit_step", slow_then_interrupted)
        with pytest.raises(Interrupted) as stopped:
            explicit().solve(cable(), checkpoint=checkpoint, checkpoint_interval=0.0)
    resumed = explicit().solve(cable(), checkpoint=checkpoint, checkpoint_interval=0.0)
    before = resumed.info["wall_time_before_resume"]
    # the time up to the checkpoint, within the stopped run's, and counted in the resumed
    # run's (the resumed steps' own time is not compared with the stopped run's steps past
    # the checkpoint: on a loaded machine either may be the longer)
    assert PAUSE <= before <= stopped.value.result.wall_time
    assert before <= resumed.wall_time
    assert explicit().solve(cable()).info["wall_time_before_resume"] == 0.0


def test_a_relaxation_resumed_counts_the_wall_time_of_its_increments_before_the_stop(
    tmp_path, monkeypatch
):
    checkpoint = tmp_path / "run.ckpt"
    relax = DynamicRelaxation._relax

    def slow_then_killed(self, model, state, load_factor, masses, progress, increment, *rest, **kw):
        if increment == 2:
            time.sleep(PAUSE)
        if increment == 3:
            raise KeyboardInterrupt
        return relax(self, model, state, load_factor, masses, progress, increment, *rest, **kw)

    monkeypatch.setattr(DynamicRelaxation, "_relax", slow_then_killed)
    with pytest.raises(KeyboardInterrupt):
        relaxation(increments=3).solve(cable(), checkpoint=checkpoint)
    monkeypatch.setattr(DynamicRelaxation, "_relax", relax)
    resumed = relaxation(increments=3).solve(cable(), checkpoint=checkpoint)
    assert resumed.wall_time >= PAUSE
    assert resumed.info["wall_time_before_resume"] >= PAUSE
    assert resumed.wall_time >= resumed.info["wall_time_before_resume"]


def sag_at(node: int):
    """A frame summary whose code is the same for every node: only its captured value
    differs."""
    return lambda frame: {"time": frame.time, "sag": frame.positions[node, 2]}


def test_a_checkpoint_of_another_frame_summary_is_refused(tmp_path):
    """The rows kept before a stop were made by the checkpoint's frame_summary: a resume with
    another (other columns, or the same columns of other nodes) would mix them."""
    checkpoint = tmp_path / "run.ckpt"
    explicit(frame_summary=sag_at(N // 2)).solve(cable(), checkpoint=checkpoint)
    for other in (sag_at(N // 3), lambda frame: {"time": frame.time}, None):
        with pytest.raises(ValueError, match=r"solver settings differ \(frame_summary\)"):
            explicit(frame_summary=other).solve(cable(), checkpoint=checkpoint)
    resumed = explicit(frame_summary=sag_at(N // 2)).solve(cable(), checkpoint=checkpoint)
    assert len(resumed.info["frame_summaries"]) == 21


def test_a_frame_summary_is_never_called_by_the_fingerprint():
    """An amplitude is sampled at load factors; a frame summary (a function of a Frame) is
    read, never called: a summary that keeps what it is given sees frames only."""
    seen: list = []

    def keeping(frame):
        seen.append(frame)
        return {}

    compiled = cable().compile()
    first = fingerprint(compiled, {"frame_summary": Uncalled(keeping)})
    again = fingerprint(compiled, {"frame_summary": Uncalled(keeping)})
    assert seen == [] and first == again
