"""One command at a time in an output folder (fibreshell/folder_lock.py): a run, a comparison,
a sweep or a fit into a folder another command is writing in is refused at once, naming the
other (its pid, host, start and command line), and leaves that folder's files alone; the
lock goes when its holder returns, whatever the way out; a lock left by a killed process of
this host is taken over with a warning; one of another host is never.

Before the lock, a second ``fibreshell run`` into a folder in use removed the first run's
frames (its clean_run) and both exited 0: the read-only review found result.pvd listing
frames that were gone, and energies.csv with the rows of two runs, time going backwards."""

import json
import os
import socket
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest
from test_interrupts import CASE, STATIC

from fibreshell.case import CaseError, load_case
from fibreshell.cli import main
from fibreshell.folder_lock import (
    EMPTY_LOCK_AGE_S,
    LOCK_FILE,
    FolderInUse,
    folder_lock,
    holder,
)
from fibreshell.outputs import checkpoint_collision, remove_run_folder
from fibreshell.run import run_case

ROOT = Path(__file__).resolve().parents[1]
THE_FIRST_RUNS_FILES = ("result.pvd", "result_00000.vtu", "energies.csv", "checkpoint.pkl")


def case_file(tmp_path: Path, text: str = STATIC) -> Path:
    path = tmp_path / "case.toml"
    path.write_text(text)
    return path


def first_runs_files(out: Path) -> None:
    out.mkdir(parents=True, exist_ok=True)
    for name in THE_FIRST_RUNS_FILES:
        (out / name).write_text(f"the first run's {name}")


def kept_untouched(out: Path) -> bool:
    return all(
        (out / name).read_text() == f"the first run's {name}" for name in THE_FIRST_RUNS_FILES
    )


@pytest.fixture
def other_process(tmp_path):
    """Start a process that holds a folder's lock until its stdin closes: ``hold(folder)``
    returns it (subprocess.Popen) once it holds it."""
    children = []

    def hold(folder: Path) -> subprocess.Popen:
        folder.mkdir(parents=True, exist_ok=True)
        script = textwrap.dedent(
            f"""
            import sys
            from pathlib import Path
            from fibreshell.folder_lock import folder_lock
            with folder_lock(Path({str(folder)!r}), "the run of 'first.toml'"):
                print("held", flush=True)
                sys.stdin.read()
            """
        )
        child = subprocess.Popen(
            [sys.executable, "-c", script], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
            text=True, env=dict(os.environ, PYTHONPATH=str(ROOT)),
        )  # fmt: skip
        children.append(child)
        assert child.stdout.readline().strip() == "held"
        return child

    yield hold
    for child in children:
        if not child.stdin.closed:
            child.stdin.close()
        child.wait(timeout=60)


def a_dead_pid() -> int:
    child = subprocess.Popen([sys.executable, "-c", "pass"])
    child.wait()
    return child.pid


# ------------------------------------------------------------------ a folder in use
def test_fibreshell_run_into_a_folder_another_process_writes_in_is_refused_naming_it(
    tmp_path, other_process, capsys
):
    out = tmp_path / "out"
    first_runs_files(out)
    pid = other_process(out).pid
    status = main(["run", str(case_file(tmp_path)), "--out", str(out), "--quiet"])
    said = capsys.readouterr().err
    assert status == 2  # as the command line's other refusals
    assert "is in use by the run of 'first.toml'" in said and f"pid {pid} on host" in said
    assert str(out / LOCK_FILE) in said and said.count("\n") == 1
    assert kept_untouched(out)  # not cleaned, not resumed from, not appended to
    assert not (out / "summary.json").exists() and holder(out)["pid"] == pid


def test_the_folder_is_free_again_when_the_other_process_ends(tmp_path, other_process):
    out = tmp_path / "out"
    first = other_process(out)
    case = load_case(case_file(tmp_path))
    with pytest.raises(FolderInUse):
        run_case(case, out, progress=False)
    first.stdin.close()
    assert first.wait(timeout=60) == 0 and not (out / LOCK_FILE).exists()
    assert run_case(case, out, progress=False).status == "done"
    assert not (out / LOCK_FILE).exists()


def test_a_run_holds_its_folder_while_it_runs_and_releases_it_on_every_way_out(tmp_path):
    case = load_case(case_file(tmp_path))
    out = tmp_path / "out"
    seen = []
    import fibreshell.run as run_module

    real = run_module._run_locked

    def looking(*args):
        seen.append(holder(out))
        return real(*args)

    run_module._run_locked = looking
    try:
        run_case(case, out, progress=False)
    finally:
        run_module._run_locked = real
    assert seen[0]["pid"] == os.getpid() and seen[0]["host"] == socket.gethostname()
    assert seen[0]["task"] == f"the run of {str(case.path)!r}"
    assert not (out / LOCK_FILE).exists()
    with pytest.raises(ValueError, match="nothing to resume"):  # refused inside the lock
        run_case(case, out, progress=False, resume=True)
    assert not (out / LOCK_FILE).exists()


def test_a_second_thread_or_call_of_the_same_process_is_refused_too(tmp_path):
    case = load_case(case_file(tmp_path))
    out = tmp_path / "out"
    out.mkdir()
    with folder_lock(out, "the sweep of 'a.toml'"):
        with pytest.raises(FolderInUse, match=f"pid {os.getpid()} on host"):
            run_case(case, out, progress=False)
        assert holder(out)["task"] == "the sweep of 'a.toml'"  # the refused one left it
    assert not (out / LOCK_FILE).exists()


def test_compare_sweep_and_identify_refuse_a_folder_in_use_before_any_run(
    tmp_path, other_process, capsys
):
    from fibreshell.identify import identify
    from fibreshell.sweep import sweep

    path = case_file(tmp_path, CASE)
    out = tmp_path / "out"
    first_runs_files(out / "fibrous")
    other_process(out)
    with pytest.raises(FolderInUse, match="in use by the run of 'first.toml'"):
        sweep(path, {"part.0.material.bending": [5.0, 10.0]}, out=out, in_process=True)
    with pytest.raises(FolderInUse, match="in use by the run of 'first.toml'"):
        identify(path, {"displacement_tip_z": [-1.0]}, {"part.0.material.bending": None}, out=out)
    assert main(["compare", str(path), "--out", str(out), "--quiet"]) == 2
    assert "in use by the run of 'first.toml'" in capsys.readouterr().err
    assert kept_untouched(out / "fibrous")
    assert not (out / "sweep.json").exists() and not (out / "variant-000").exists()


def test_compare_does_not_empty_a_kinematics_folder_another_run_writes_in(tmp_path, other_process):
    from fibreshell.compare import compare_case

    out = tmp_path / "out"
    first_runs_files(out / "fibrous")
    other_process(out / "fibrous")  # fibreshell run --out out/fibrous, going on
    with pytest.raises(FolderInUse, match="in use by the run of 'first.toml'"):
        compare_case(load_case(case_file(tmp_path, CASE)), out, progress=False)
    assert kept_untouched(out / "fibrous")
    assert not (out / LOCK_FILE).exists()  # the comparison let go of its own folder


# ------------------------------------------------------------------ locks left behind
def test_a_lock_left_by_a_killed_process_of_this_host_is_taken_over_with_a_warning(tmp_path):
    out = tmp_path / "out"
    first_runs_files(out)
    dead = a_dead_pid()
    left = {"pid": dead, "host": socket.gethostname(), "started": "2026-01-01 00:00:00 UTC",
            "task": "the run of 'killed.toml'", "command": "fibreshell run k.toml"}  # fmt: skip
    (out / LOCK_FILE).write_text(json.dumps(left))
    taken = f"left by the run of 'killed.toml' \\(pid {dead}.* taken over by the run of"
    with pytest.warns(UserWarning, match=taken):
        run = run_case(load_case(case_file(tmp_path)), out, progress=False)
    assert run.status == "done" and (out / "summary.json").exists()
    assert sorted(p.name for p in out.iterdir() if "lock" in p.name) == []


def test_a_lock_of_a_pid_now_used_by_a_later_process_is_taken_over(tmp_path):
    if not Path(f"/proc/{os.getpid()}/stat").exists():
        pytest.skip("no /proc: a process's start cannot be read")
    out = tmp_path / "out"
    out.mkdir()
    left = {"pid": os.getppid(), "host": socket.gethostname(), "process_start": "1",
            "task": "the run of 'killed.toml'"}  # fmt: skip
    (out / LOCK_FILE).write_text(json.dumps(left))
    with pytest.warns(UserWarning, match="has ended"):
        with folder_lock(out, "the run of 'b.toml'") as lock:
            assert json.loads(lock.read_text())["task"] == "the run of 'b.toml'"


def test_a_lock_left_empty_by_a_command_killed_as_it_took_the_folder_is_taken_over(tmp_path):
    # Killed between creating the lock and writing its record: the empty file refused every
    # later command until deleted by hand. Older than EMPTY_LOCK_AGE_S it is taken over; a
    # fresh one (a command writing its record this instant) is still refused.
    out = tmp_path / "out"
    first_runs_files(out)
    lock = out / LOCK_FILE
    lock.write_text("")
    with pytest.raises(FolderInUse, match="cannot be read"):
        run_case(load_case(case_file(tmp_path)), out, progress=False)
    old = time.time() - 2 * EMPTY_LOCK_AGE_S
    os.utime(lock, (old, old))
    with pytest.warns(UserWarning, match="left empty .* taken over by the run of"):
        run = run_case(load_case(case_file(tmp_path)), out, progress=False)
    assert run.status == "done" and not lock.exists()


def _left_lock(kind: str) -> tuple[object, str]:
    """(a lock file's content, what the refusal must name) for ``kind``: another host's, a
    living process's of this host (this one), or one that cannot be read. Built inside the
    test: a pid in a parameter's id differs between the suite's worker processes."""
    if kind == "another host":
        return ({"pid": 1, "host": "another-machine", "task": "the run of 'far.toml'"},
                "host 'another-machine'")  # fmt: skip
    if kind == "living process":
        here = {"pid": os.getpid(), "host": socket.gethostname(), "task": "the run of 'here.toml'"}
        return here, f"pid {os.getpid()}"
    return "not json", "a lock file that cannot be read"


@pytest.mark.parametrize("kind", ["another host", "living process", "unreadable"])
def test_a_lock_of_another_host_a_living_process_or_unreadable_is_never_taken_over(tmp_path, kind):
    left, said = _left_lock(kind)
    out = tmp_path / "out"
    first_runs_files(out)
    (out / LOCK_FILE).write_text(left if isinstance(left, str) else json.dumps(left))
    with pytest.raises(FolderInUse, match="delete") as refused:
        run_case(load_case(case_file(tmp_path)), out, progress=False)
    assert said in str(refused.value) and kept_untouched(out)
    assert (out / LOCK_FILE).exists()


def test_a_checkpoint_may_not_be_named_as_the_lock(tmp_path):
    assert "lock" in checkpoint_collision(LOCK_FILE)
    text = STATIC.replace('kind = "static"', 'kind = "relaxation"') + "\n"
    text = text.replace("[output]", f'checkpoint = "{LOCK_FILE}"\n[output]')
    with pytest.raises(CaseError, match="lock"):
        load_case(case_file(tmp_path, text))


# ------------------------------------------------------------------ a lock being written
def test_the_lock_file_appears_with_its_whole_record(tmp_path, monkeypatch):
    """Linked into place once written: a reader never finds it empty (it was created, then
    written, and a reader in between found an empty file)."""
    import fibreshell.folder_lock as folder_lock_module

    out = tmp_path / "out"
    out.mkdir()
    seen = []
    real_link = os.link

    def link(source, target):
        seen.append(json.loads(Path(source).read_text())["task"])
        return real_link(source, target)

    monkeypatch.setattr(folder_lock_module.os, "link", link)
    with folder_lock(out, "the run of 'b.toml'") as lock:
        assert seen == ["the run of 'b.toml'"] and holder(out)["task"] == seen[0]
        assert sorted(p.name for p in out.iterdir()) == [lock.name]  # the staged file gone


def test_without_hard_links_the_lock_is_created_then_written(tmp_path, monkeypatch):
    import errno

    import fibreshell.folder_lock as folder_lock_module

    def no_link(source, target):
        raise OSError(errno.EPERM, "Operation not permitted")

    out = tmp_path / "out"
    out.mkdir()
    monkeypatch.setattr(folder_lock_module.os, "link", no_link)
    with folder_lock(out, "the run of 'a.toml'"):
        assert holder(out)["task"] == "the run of 'a.toml'"
        with pytest.raises(FolderInUse, match="in use by the run of 'a.toml'"):
            with folder_lock(out, "the run of 'b.toml'"):
                pass
    assert list(out.iterdir()) == []


@pytest.mark.parametrize("text", ["", '{\n "pid": 12'], ids=["empty", "partial"])
def test_a_lock_younger_than_its_age_limit_without_its_whole_record_is_held(tmp_path, text):
    """The window between the lock's O_CREAT and the write of its record (a file system
    without hard links, where the lock is created, then written): a command taking the folder
    this instant, refused as it is."""
    out = tmp_path / "out"
    out.mkdir()
    (out / LOCK_FILE).write_text(text)
    with pytest.raises(FolderInUse, match="a command taking it this instant"):
        with folder_lock(out, "the run of 'b.toml'"):
            pass
    assert (out / LOCK_FILE).read_text() == text


def test_a_partly_written_lock_older_than_its_age_limit_is_taken_over(tmp_path):
    """A command killed (or its disk full) in the middle of its record: refused forever, as an
    empty one was before it was taken over."""
    out = tmp_path / "out"
    out.mkdir()
    lock = out / LOCK_FILE
    lock.write_text('{\n "pid": 12')
    old = time.time() - 2 * EMPTY_LOCK_AGE_S
    os.utime(lock, (old, old))
    with pytest.warns(UserWarning, match="partly written .* taken over by the run of 'b.toml'"):
        with folder_lock(out, "the run of 'b.toml'"):
            assert json.loads(lock.read_text())["task"] == "the run of 'b.toml'"
    assert not lock.exists()


def test_a_link_reported_as_failed_on_nfs_that_was_made_is_the_lock_taken(tmp_path, monkeypatch):
    """NFS v2/3: the server made the link, the reply was lost, the client's retry reports
    EEXIST. The staged file then has two names (st_nlink 2): the lock is ours. Before, the
    command was refused naming itself as the holder."""
    import errno

    import fibreshell.folder_lock as folder_lock_module

    real_link = os.link

    def link_reply_lost(source, target):
        real_link(source, target)
        raise FileExistsError(errno.EEXIST, "File exists")

    out = tmp_path / "out"
    out.mkdir()
    monkeypatch.setattr(folder_lock_module.os, "link", link_reply_lost)
    with folder_lock(out, "the run of 'a.toml'") as lock:
        assert holder(out)["task"] == "the run of 'a.toml'"
        assert sorted(p.name for p in out.iterdir()) == [lock.name]  # the staged name gone
    assert list(out.iterdir()) == []


def _staged(out: Path, pid: int, host: str, text: str | None = None) -> Path:
    """A record written aside by a command ``pid`` of ``host`` and never linked (killed)."""
    record = {"pid": pid, "host": host, "task": "the run of 'killed.toml'", "token": "x"}
    path = out / f"{LOCK_FILE}.new-{pid}-0123abcd"
    path.write_text(json.dumps(record) if text is None else text)
    return path


def test_a_staged_record_of_a_killed_command_goes_when_the_folder_is_next_locked(tmp_path):
    """A command killed between writing its record aside and linking it left
    fibreshell.lock.new-<pid>-<hex>, which nothing removed: the sweep's variant folder could
    not be removed (rmdir: not empty). Now the next lock there removes it (its process has
    ended), and a living command's staged record, another host's, or a young partial one
    (a command writing it this instant) stay."""
    out = tmp_path / "out"
    out.mkdir()
    dead = _staged(out, a_dead_pid(), socket.gethostname())
    old_partial = _staged(out, a_dead_pid(), socket.gethostname(), text='{"pid": ')
    old = time.time() - 2 * EMPTY_LOCK_AGE_S
    os.utime(old_partial, (old, old))
    living = _staged(out, os.getpid(), socket.gethostname())
    far = _staged(out, 1, "another-machine")
    young_partial = out / f"{LOCK_FILE}.checkpoint.pkl.new-{a_dead_pid()}-0123abce"
    young_partial.write_text("")
    # a take-over's aside (a dead holder's lock renamed): gone once EMPTY_LOCK_AGE_S old
    old_aside = out / f"{LOCK_FILE}.stale-{a_dead_pid()}-0123abcf"
    old_aside.write_text(json.dumps({"pid": 12, "host": socket.gethostname()}))
    os.utime(old_aside, (old, old))
    young_aside = out / f"{LOCK_FILE}.stale-{os.getpid()}-0123abd0"
    young_aside.write_text(json.dumps({"pid": 12, "host": socket.gethostname()}))
    with folder_lock(out, "the run of 'b.toml'"):
        pass
    assert sorted(p.name for p in out.iterdir()) == sorted(
        p.name for p in (living, far, young_partial, young_aside)
    )
    assert not dead.exists() and not old_partial.exists() and not old_aside.exists()


def test_the_removal_of_a_variant_folder_removes_a_killed_commands_staged_record(tmp_path):
    """The reviewer's case: the variant folder held the staged record alone after a kill -9,
    and remove_run_folder left the folder behind."""
    folder = tmp_path / "variant-1"
    folder.mkdir()
    (folder / "summary.json").write_text("{}")
    _staged(folder, a_dead_pid(), socket.gethostname())
    remove_run_folder(folder)
    assert not folder.exists()


def test_a_lock_of_bytes_that_are_not_text_is_refused_not_a_crash(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / LOCK_FILE).write_bytes(b"\xff\xfe\x00garbage")  # was UnicodeDecodeError
    with pytest.raises(FolderInUse, match="a lock file that cannot be read"):
        with folder_lock(out, "the run of 'b.toml'"):
            pass


def test_a_lock_whose_record_cannot_be_written_is_not_left_behind(tmp_path, monkeypatch):
    """A full disk as the record is written: the empty lock stayed, refusing every command
    for 10 s, and the error was a bare OSError. Neither the lock nor its staged record stays."""
    import errno

    import fibreshell.folder_lock as folder_lock_module
    from femcore.writable import OutputError

    class Full:
        def __init__(self, descriptor, mode):
            os.close(descriptor)

        def __enter__(self):
            return self

        def __exit__(self, *exc):
            return False

        def write(self, text):
            raise OSError(errno.ENOSPC, "No space left on device", str(out / LOCK_FILE))

    out = tmp_path / "out"
    out.mkdir()
    monkeypatch.setattr(folder_lock_module.os, "fdopen", Full)
    with pytest.raises(OutputError, match="No space left on device"):
        with folder_lock(out, "the run of 'b.toml'"):
            pass
    assert list(out.iterdir()) == []


# ------------------------------------------------------------------ a checkpoint elsewhere
@pytest.mark.parametrize(
    "first, second",
    [("../shared.pkl", "../shared.pkl"), ("checkpoint.pkl", "../a/checkpoint.pkl"),
     (None, "../a/checkpoint.pkl")],
    ids=["outside both folders", "in the first's folder", "the default of a static first"],
)  # fmt: skip
def test_two_runs_naming_one_checkpoint_file_from_two_folders_refuse_each_other(
    tmp_path, first, second
):
    """The lock of the output folder did not reach a checkpoint outside it: the second run
    removed the first's checkpoint (its clean_run) and wrote its own over it. A static run
    (first = None: no checkpoint) held none, though its cleaning removes checkpoint.pkl from
    its folder: a second run's checkpoint there went."""
    import fibreshell.run as run_module

    relaxation = STATIC.replace('kind = "static"', 'kind = "relaxation"')

    def case(name: str, checkpoint: str | None):
        path = tmp_path / name
        if checkpoint is None:  # a static run: no checkpoint of its own
            path.write_text(STATIC)
        else:
            path.write_text(
                relaxation.replace("[output]", f'checkpoint = "{checkpoint}"\n[output]')
            )
        return load_case(path)

    refused = []

    def while_the_first_runs(*args):  # the first's run, stood in for: the second starts
        if not refused:
            refused.append(None)
            try:
                run_case(case("second.toml", second), tmp_path / "b", progress=False)
            except FolderInUse as error:
                refused.append(str(error))

    real = run_module._run_locked
    run_module._run_locked = while_the_first_runs
    try:
        run_case(case("first.toml", first), tmp_path / "a", progress=False)
    finally:
        run_module._run_locked = real
    checkpoint = Path(os.path.normpath(tmp_path / "b" / second))
    assert len(refused) == 2, "the second run was not refused"
    assert f"the checkpoint {str(checkpoint)!r} is in use by the run of" in refused[1]
    assert "first.toml" in refused[1] and not (tmp_path / "b" / "summary.json").exists()
    assert [p.name for p in checkpoint.parent.iterdir() if "lock" in p.name] == []


# ------------------------------------------------------------------ the validation report
@pytest.mark.parametrize("command", ["python -m validation", "fibreshell report"])
def test_a_report_into_a_folder_another_process_writes_in_is_refused_before_any_case_runs(
    tmp_path, other_process, capsys, monkeypatch, command
):
    """Two reports into one folder replaced each other's figures and results.json."""
    import validation.__main__ as report_main
    import validation.report as report_module
    from validation.cases import CASES

    ran = []
    monkeypatch.setattr(report_module, "_run_all", lambda *args: ran.append(args) or {})
    out = tmp_path / "report"
    other_process(out)
    argv = ["--cases", next(iter(CASES)), "--out", str(out), "--jobs", "1"]
    status = (
        report_main.main(argv) if command == "python -m validation" else main(["report", *argv])
    )
    said = capsys.readouterr().err
    assert status == 2 and not ran and not (out / "results.json").exists()
    assert "is in use by the run of 'first.toml'" in said and said.count("\n") == 1


def test_a_report_holds_its_folder_while_its_cases_run(tmp_path, monkeypatch):
    import validation.report as report_module
    from validation.cases import CASES

    out = tmp_path / "report"
    seen = []
    monkeypatch.setattr(report_module, "_run_all", lambda *args: seen.append(holder(out)) or {})
    report_module.run_cases([next(iter(CASES))], "coarse", out, echo=lambda *a, **k: None)
    assert seen[0]["pid"] == os.getpid() and "validation report" in seen[0]["task"]
    assert not (out / LOCK_FILE).exists()


def test_a_checkpoint_in_a_folder_another_command_writes_in_is_refused(
    tmp_path, other_process, capsys
):
    """The reviewer's case: run a going in a, run b with [solver] checkpoint = '../a/ck.pkl'
    exited 0 and wrote its pickle among a's files (and '../a/result.pvd' removed a's series
    and wrote it there). Both are refused now, exit status 2, a's files untouched."""
    a = tmp_path / "a"
    first_runs_files(a)
    pid = other_process(a).pid
    for name, said in (("../a/ck.pkl", f"lands in {str(a)!r}, which is in use by the run of "
                                       f"'first.toml' (pid {pid}"),
                       ("../a/result.pvd", "would overwrite 'result.pvd'")):  # fmt: skip
        text = CASE.replace("damping = 100.0", f"damping = 100.0\ncheckpoint = {name!r}")
        status = main(
            ["run", str(case_file(tmp_path, text)), "--out", str(tmp_path / "b"), "--quiet"]
        )
        assert status == 2 and said in capsys.readouterr().err
    assert kept_untouched(a) and not (a / "ck.pkl").exists()
    assert not (tmp_path / "b" / "summary.json").exists()


def test_the_removal_of_a_run_folder_leaves_a_checkpoint_another_run_holds_there(tmp_path):
    """A run whose [solver] checkpoint is '../variant-1/checkpoint.pkl' holds that file's lock;
    the removal of the sweep's variant folder (its clean_run removes checkpoint.pkl) removed
    it. Now it is refused, naming the holder, and the checkpoint stays."""
    folder = tmp_path / "variant-1"
    folder.mkdir()
    (folder / "summary.json").write_text("{}")
    (folder / "checkpoint.pkl").write_text("the other run's checkpoint")
    with folder_lock(folder, "the run of 'other.toml'", file="checkpoint.pkl"):
        with pytest.raises(FolderInUse, match="in use by the run of 'other.toml'"):
            remove_run_folder(folder)
    assert (folder / "checkpoint.pkl").read_text() == "the other run's checkpoint"
    assert (folder / "summary.json").exists() and not (folder / LOCK_FILE).exists()
