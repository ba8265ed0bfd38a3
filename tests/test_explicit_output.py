"""Explicit runs that write as they go and survive a kill: the frames as a VTU series with its
ParaView index, the histories as CSV rows, and checkpoints that a killed run resumes from to the
same final state, bit for bit, as a run never interrupted."""

import textwrap
import warnings
from pathlib import Path
from xml.etree import ElementTree

import meshio
import numpy as np
import pytest
from kill_helpers import kill_when

from solvers import CentralDifference

# A slack cable between two fixed ends dropping under gravity (tests/test_explicit.py): 20
# elements, about 4,400 steps over 0.02 s at 0.9 of the stable step.
CABLE = textwrap.dedent(
    """
    import numpy as np
    from elements import Cable
    from femcore import Mesh, Model

    def hanging_cable():
        n = 20
        points = np.column_stack([np.linspace(0, 100.0, n + 1), np.zeros(n + 1), np.zeros(n + 1)])
        model = Model(Mesh(points, lines=np.column_stack([np.arange(n), np.arange(1, n + 1)])))
        model.add(Cable(axial_stiffness=1e3, mass_per_length=1e-9))
        model.fix([0, n])
        model.gravity((0.0, 0.0, -9810.0))
        return model
    """
)
namespace: dict = {}
exec(CABLE, namespace)
hanging_cable = namespace["hanging_cable"]


def solver(tmp: Path, duration=0.02, **options) -> CentralDifference:
    return CentralDifference(
        duration=duration,
        output_interval=duration / 50,
        output=tmp / "run.pvd",
        history=tmp / "run.csv",
        history_nodes=[10],
        progress=False,
        **options,
    )


@pytest.fixture(scope="module")
def streamed(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("streamed")
    return tmp, solver(tmp).solve(hanging_cable())


@pytest.fixture(scope="module")
def in_memory():
    return CentralDifference(duration=0.02, output_interval=0.02 / 50, progress=False).solve(
        hanging_cable()
    )


def listed(pvd: Path) -> list[tuple[float, str]]:
    entries = ElementTree.parse(pvd).getroot().iter("DataSet")
    return [(float(e.get("timestep")), e.get("file")) for e in entries]


def test_every_frame_is_on_disk_and_only_the_first_and_last_in_memory(streamed, in_memory):
    tmp, result = streamed
    entries = listed(tmp / "run.pvd")
    assert len(entries) == len(in_memory.frames) == 51
    assert len(result.frames) == 2
    assert [t for t, _ in entries] == [f.time for f in in_memory.frames]
    np.testing.assert_array_equal(result.positions, in_memory.positions)


def test_a_frame_read_back_from_the_series_is_the_one_computed(streamed, in_memory):
    tmp, _ = streamed
    _, name = listed(tmp / "run.pvd")[25]
    written = meshio.read(tmp / name)
    frame = in_memory.frames[25]
    np.testing.assert_allclose(
        written.point_data["displacement"],
        frame.positions - in_memory.frames[0].positions,
        rtol=1e-12,
        atol=1e-15,
    )


def test_writing_a_streamed_result_says_it_holds_two_frames_and_where_every_one_is(
    streamed, in_memory, tmp_path
):
    """A streamed result holds the first and the last frame; a series written from it gets
    those two, and says so, naming the streamed series that holds every one."""
    tmp, result = streamed
    for name in ("again.xdmf", "again.pvd"):
        with pytest.warns(UserWarning, match=r"the 2 frames this result holds of the 51 .*run.pvd"):
            result.write(tmp_path / name)
    assert result.info["streamed_frames"] == 51 and result.info["output"] == str(tmp / "run.pvd")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        result.write(tmp_path / "last.vtu")  # one frame asked for: the last, as it is
        in_memory.write(tmp_path / "every.xdmf")  # every frame in memory


def test_the_history_has_a_row_per_energy_record(streamed):
    tmp, result = streamed
    rows = np.loadtxt(tmp / "run.csv", delimiter=",", skiprows=1)
    header = (tmp / "run.csv").read_text().splitlines()[0].split(",")
    assert header[:5] == [
        "time", "energy_kinetic", "energy_internal", "energy_external_work", "energy_damping"
    ]  # fmt: skip
    assert header[-3:] == [f"displacement_node10_{axis}" for axis in "xyz"]
    np.testing.assert_array_equal(rows[:, 0], result.energies["time"][1:])
    np.testing.assert_array_equal(rows[:, 1], result.energies["kinetic"][1:])
    assert rows[-1, -1] < 0.0  # the middle node has dropped
    assert rows[-1, 8] > 0.0  # and the supports hold the cable up (after the friction column)


def test_bad_output_paths_are_refused(tmp_path):
    with pytest.raises(ValueError, match="must be a .pvd path"):
        CentralDifference(duration=1.0, output=tmp_path / "run.vtu")
    with pytest.raises(ValueError, match="does not exist"):
        CentralDifference(duration=1.0, history=tmp_path / "missing" / "run.csv")
    with pytest.raises(ValueError, match="node indices"):
        CentralDifference(duration=1.0, history_nodes=[1.5])


@pytest.mark.slow
def test_a_run_killed_halfway_resumes_to_the_same_state_bit_for_bit(tmp_path):
    """The child process writes a checkpoint at every chance (every 10 steps) and is killed
    with SIGKILL once one past half the run is on disk; the same call then resumes."""
    duration = 0.02  # about 4,400 steps, 440 checkpoints
    killed = tmp_path / "killed"
    killed.mkdir()
    script = killed / "run.py"
    script.write_text(
        CABLE
        + textwrap.dedent(
            f"""
            from pathlib import Path
            from solvers import CentralDifference
            here = Path({str(killed)!r})
            CentralDifference(
                duration={duration}, output_interval={duration / 50}, output=here / "run.pvd",
                history=here / "run.csv", history_nodes=[10], progress=False,
            ).solve(hanging_cable(), checkpoint=here / "run.ckpt", checkpoint_interval=0.0)
            """
        )
    )
    checkpoint = killed / "run.ckpt"
    kill_when(script, checkpoint, lambda p: p["run"].state.time > 0.5 * duration, 120.0)

    resumed = solver(killed, duration).solve(
        hanging_cable(), checkpoint=checkpoint, checkpoint_interval=0.0
    )
    whole = tmp_path / "whole"
    whole.mkdir()
    reference = solver(whole, duration).solve(hanging_cable())
    assert resumed.converged and resumed.steps == reference.steps
    np.testing.assert_array_equal(resumed.positions, reference.positions)
    np.testing.assert_array_equal(resumed.velocities, reference.velocities)
    for key in reference.energies:
        np.testing.assert_array_equal(resumed.energies[key], reference.energies[key])
    assert listed(killed / "run.pvd") == listed(whole / "run.pvd")
    assert (killed / "run.csv").read_text() == (whole / "run.csv").read_text()


def test_a_checkpoint_of_another_model_is_refused(tmp_path):
    checkpoint = tmp_path / "run.ckpt"
    CentralDifference(duration=1e-4, progress=False).solve(hanging_cable(), checkpoint=checkpoint)
    with pytest.raises(ValueError, match="other solver settings: its solver settings differ"):
        CentralDifference(duration=2e-4, progress=False).solve(
            hanging_cable(), checkpoint=checkpoint
        )


def test_a_diverged_run_leaves_on_disk_only_the_frames_that_passed_the_checks(tmp_path):
    """Above the critical step (tests/test_explicit.py) the series ends, on disk as in the
    result, with the last state that passed the energy checks."""
    from solvers import DivergenceError

    compiled = hanging_cable().compile()
    dt = 1.05 * compiled.stable_dt(compiled.initial_state())
    solver = CentralDifference(
        duration=0.02, dt=dt, output_interval=50 * dt, output=tmp_path / "run.pvd", progress=False
    )
    with pytest.raises(DivergenceError) as error:
        solver.solve(hanging_cable())
    result = error.value.result
    entries = listed(tmp_path / "run.pvd")
    assert entries[-1][0] == result.frames[-1].time
    assert all(t <= result.frames[-1].time for t, _ in entries)
    assert sorted(p.name for p in tmp_path.glob("run_*.vtu")) == sorted(n for _, n in entries)


def test_a_summary_per_frame_of_the_series_also_when_the_run_diverges(tmp_path):
    """frame_summary is called on every frame the series keeps: after a divergence, the
    summaries end with the last state that passed the checks, as the series on disk does."""
    from solvers import DivergenceError

    compiled = hanging_cable().compile()
    dt = 1.05 * compiled.stable_dt(compiled.initial_state())
    solver = CentralDifference(
        duration=0.02,
        dt=dt,
        output_interval=50 * dt,
        output=tmp_path / "run.pvd",
        progress=False,
        frame_summary=lambda frame: {"time": frame.time},
    )
    with pytest.raises(DivergenceError) as error:
        solver.solve(hanging_cable())
    summaries = error.value.result.info["frame_summaries"]
    assert [s["time"] for s in summaries] == [t for t, _ in listed(tmp_path / "run.pvd")]
    with pytest.raises(ValueError, match="frame_summary must be a function"):
        CentralDifference(duration=1.0, frame_summary="rows")


def test_a_file_that_is_not_a_checkpoint_is_refused(tmp_path):
    path = tmp_path / "run.ckpt"
    path.write_text("not a checkpoint")
    with pytest.raises(ValueError, match="not a checkpoint this program wrote"):
        CentralDifference(duration=1e-4, progress=False).solve(hanging_cable(), checkpoint=path)


@pytest.mark.parametrize("older", [2, 3, 4, 5, 6, 7, 8, 9])
def test_a_checkpoint_of_an_older_format_is_refused_naming_both_formats(tmp_path, older):
    """Format 2 recorded "internal" as the internal forces' work, friction included (format 3:
    the stored energy, docs/theory.md §6.1); format 3 anchored a tool contact's landing node
    where it was at the step before (format 4: where its way touched the surface, docs/
    theory.md §9.2); format 4 dissipated nothing for a node's slip in the step it left a tool
    (format 5: up to where it left, its history keeping each anchored node's place); format 5
    gave a ply contact's landing point no friction in its landing step (format 6: anchored
    where its way crossed the lower face, §9.3a); format 6 dissipated nothing for a ply
    contact point's slip in the step it left the lower face (format 7: up to where it left,
    §9.3a); format 7 gave a ply contact's point whose gap is to an edge or a vertex no friction
    in its landing step and no slip in its departure step (format 8: §9.3a); format 8 dropped
    such a point's anchor along T's normal where its gap's normal lay within TILT of T's plane,
    and re-expressed a sliding point's moved anchor along T's normal wherever nu . n <= 0.1, nu
    below T's plane included (format 9: the
    continuous blend, the same rule for both, §9.3a); format 9 knew a frame_summary only as
    given or not (format 10: by what it is made of, so that the rows kept before a stop match
    the rest): a run resumed from any would change the meaning of its records, its friction
    or its rows midway, so it is refused, whole and checksummed as it is."""
    from solvers.output import CHECKPOINT_FORMAT, CHECKPOINT_MAGIC, save_checkpoint

    assert CHECKPOINT_FORMAT == 10
    path = tmp_path / "run.ckpt"
    save_checkpoint(path, {"signature": "any"})
    data = path.read_bytes()
    header = f"fibreshell checkpoint {older}\n".encode()
    path.write_bytes(header + data[len(CHECKPOINT_MAGIC) :])
    with pytest.raises(ValueError, match=f"checkpoint of format {older}, .* reads format 10"):
        CentralDifference(duration=1e-4, progress=False).solve(hanging_cable(), checkpoint=path)


def test_history_rows_wait_in_memory_until_a_flush_writes_them_as_rows_written_one_by_one(
    tmp_path,
):
    """solvers.output.HistoryWriter keeps its rows until ``flush`` (the solver flushes at
    each frame, before a checkpoint and at the end): the file then holds the bytes the csv
    module writes for each row appended alone, and ``rows`` counts only rows on disk (what a
    checkpoint counts)."""
    import csv

    from solvers.output import HistoryWriter

    rng = np.random.default_rng(3)
    writer = HistoryWriter(tmp_path / "buffered.csv", np.array([1]), tools=1)
    writer.start()
    rows = []
    for k in range(5):
        energies = tuple(rng.normal(size=6))
        reactions, moved = rng.normal(size=(4, 3)), rng.normal(size=(3, 3))
        tool, travel = rng.normal(size=(1, 3)), rng.normal(size=(1, 3))
        writer.append(energies, reactions, moved, tool, travel)
        values = [*energies, *reactions.sum(axis=0), *tool[0], *travel[0], *moved[1]]
        rows.append([repr(float(v)) for v in values])
        if k == 2:
            assert writer.rows == 0  # nothing on disk before the flush
            writer.flush()
            assert writer.rows == 3
    writer.flush()
    writer.flush()  # nothing pending: nothing written twice
    assert writer.rows == 5
    reference = tmp_path / "reference.csv"
    with open(reference, "w", newline="") as handle:
        csv.writer(handle).writerow(writer.header())
    for row in rows:  # one open per row, as the rows were written before
        with open(reference, "a", newline="") as handle:
            csv.writer(handle).writerow(row)
    assert (tmp_path / "buffered.csv").read_bytes() == reference.read_bytes()


def _diverging_with_history(history):
    """A central difference on the hanging cable at 1.05 times its stable step, recording its
    history in ``history``: it diverges before its first frame after the start (0.01 s)."""
    compiled = hanging_cable().compile()
    dt = 1.05 * compiled.stable_dt(compiled.initial_state())
    return CentralDifference(
        duration=0.02, dt=dt, output_interval=0.01, history=history, progress=False
    )


def test_a_diverged_run_keeps_its_history_and_energy_records_to_its_last_good_state(tmp_path):
    """The records of the steps after the last state that passed the checks are the
    blow-up's (kinetic energy 7.9e3 times the work done): the result's energies and the
    history end where the frames end, and the rows held in memory since the last frame are
    written when the run stops (the run diverges before its first frame after the start, so
    no frame flushed them): a row per energy record of the result."""
    from solvers import DivergenceError

    solver = _diverging_with_history(tmp_path / "run.csv")
    with pytest.raises(DivergenceError) as error:
        solver.solve(hanging_cable())
    result = error.value.result
    energies = result.energies
    rows = np.loadtxt(tmp_path / "run.csv", delimiter=",", skiprows=1, ndmin=2)
    good = result.frames[-1].time
    assert 0.0 < good < 0.01 and "the last state that passed the checks" in str(error.value)
    assert energies["time"][-1] == good and rows[-1, 0] == good
    assert all(len(values) == len(energies["time"]) for values in energies.values())
    assert len(rows) == len(energies["time"]) - 1 > 10
    np.testing.assert_array_equal(rows[:, 0], energies["time"][1:])
    np.testing.assert_array_equal(rows[:, 1], energies["kinetic"][1:])


def test_a_history_writes_its_rows_itself_once_its_queue_is_full(tmp_path):
    """A run whose frames are far apart (or that is killed where Python cannot finish it)
    does not hold its whole history in memory: ``append`` writes the queue once
    solvers.output.PENDING_ROWS rows wait, so the file is at most that many rows behind."""
    from solvers import output

    writer = output.HistoryWriter(tmp_path / "queued.csv", np.array([0]))
    writer.start()
    for k in range(output.PENDING_ROWS + 3):
        writer.append(tuple(np.full(6, float(k))), np.zeros((1, 3)), np.zeros((1, 3)))
    assert writer.rows == output.PENDING_ROWS  # on disk without a flush
    rows = np.loadtxt(tmp_path / "queued.csv", delimiter=",", skiprows=1, ndmin=2)
    np.testing.assert_array_equal(rows[:, 0], np.arange(output.PENDING_ROWS))
    writer.flush()
    assert writer.rows == output.PENDING_ROWS + 3


def test_a_history_write_that_fails_is_not_repeated_by_the_next_flush(tmp_path, monkeypatch):
    """A write that fails part way (a full disk, an interrupt) leaves its rows off the queue:
    the next flush writes the rows appended since, never those again (a file with rows twice
    would not resume), and ``rows`` counts only the rows written whole."""
    import builtins

    from solvers import output

    writer = output.HistoryWriter(tmp_path / "failing.csv", np.array([0]))
    writer.start()
    for k in range(3):
        writer.append(tuple(np.full(6, float(k))), np.zeros((1, 3)), np.zeros((1, 3)))
    real_open = builtins.open

    def full_disk(path, mode="r", *args, **kwargs):
        if "a" in mode:
            raise OSError(28, "No space left on device")
        return real_open(path, mode, *args, **kwargs)

    monkeypatch.setattr(builtins, "open", full_disk)
    with pytest.raises(OSError, match="No space left"):
        writer.flush()
    monkeypatch.setattr(builtins, "open", real_open)
    writer.append(tuple(np.full(6, 9.0)), np.zeros((1, 3)), np.zeros((1, 3)))
    writer.flush()
    assert writer.rows == 1
    rows = np.loadtxt(tmp_path / "failing.csv", delimiter=",", skiprows=1, ndmin=2)
    np.testing.assert_array_equal(rows[:, 0], [9.0])


def test_a_failing_history_write_does_not_hide_why_the_run_stopped(tmp_path, monkeypatch):
    """A run that diverges while its history cannot be written still raises its
    DivergenceError with its result (the last good state); the failed write is a note on it."""
    from solvers import DivergenceError, output

    def full_disk(self):
        raise OSError(28, "No space left on device")

    solver = _diverging_with_history(tmp_path / "run.csv")
    monkeypatch.setattr(output.HistoryWriter, "flush", full_disk)
    with pytest.raises(DivergenceError) as error:
        solver.solve(hanging_cable())
    assert error.value.result is not None
    assert any("history's last rows were not written" in note for note in error.value.__notes__)
