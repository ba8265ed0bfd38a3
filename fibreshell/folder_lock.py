"""One command at a time in an output folder: the lock file ``fibreshell.lock``.

Two runs writing into one folder damage each other without a word: the second's cleaning
(fibreshell.outputs.clean_run) removes the first's frames while its ``result.pvd`` still
lists them, the second resumes from the first's checkpoint or appends to its
``energies.csv``, and both exit 0. So ``run_case``, ``compare_case``, ``sweep``,
``identify``, ``run_plies`` and the validation report (``validation.report.run_cases``) hold
the lock of the folder they write (``folder_lock``) from before they touch it until they
return, and a second command there is refused at once, naming the first. A run holds its
checkpoint file too (``folder_lock(..., file=name)``: the lock ``fibreshell.lock.<name>``
beside it), which ``[solver] checkpoint`` may put outside its output folder.

The lock is a file created with ``O_CREAT | O_EXCL`` (atomic on every local file system and
on NFS v3 and later), holding the holder's pid, host, start time and command as JSON. It is
removed when the holder leaves the ``with`` block, whatever the way out (an error, Ctrl-C,
SIGTERM through ``solvers.interruptible``). A holder killed outright (kill -9, a power cut)
leaves it behind: a later command on the same host takes it over, with a warning, when the
process it names has ended (or its pid now belongs to a process started at another time,
read from ``/proc`` where there is one). A lock of another host, or on a system where
whether a process lives cannot be asked without harming it (Windows: ``os.kill`` there ends
the process), is never taken over: the message says which file to delete once no such run
is going. The record is written before the lock file appears (linked into place: ``_create``);
a lock file found empty or partly written all the same (a file system without hard links, a
command killed by an earlier version between creating its lock and writing it) is held until
it is EMPTY_LOCK_AGE_S old, then taken over; a command whose record cannot be written (a full
disk) leaves no lock and raises OutputError. A command killed between writing its record aside
and linking it leaves that staged file (``fibreshell.lock.new-<pid>-<hex>``): the next command
to take a lock in the folder removes it once its process has ended, as it would take over the
lock (``remove_dead_staging``, which the removal of a sweep's variant folder calls too). On NFS
v2/3 a ``link`` whose reply was lost is retried by the client and reports EEXIST although the
link was made: the staged file's link count (2) tells it, and the lock is ours."""

from __future__ import annotations

import json
import os
import re
import socket
import sys
import time
import uuid
import warnings
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from femcore.writable import OutputError

__all__ = [
    "LOCK_FILE", "FolderInUse", "folder_lock", "holder", "refuse_if_held", "remove_dead_staging",
]  # fmt: skip

# The lock's file name in the folder it guards (fibreshell.outputs: never a run's output,
# never a checkpoint's name).
LOCK_FILE = "fibreshell.lock"


class FolderInUse(ValueError):
    """The output folder is held by another command (its lock names it): a refusal before
    anything is written, as a bad option is (``fibreshell`` exit status 2)."""


def _process_start(pid: int) -> str | None:
    """When process ``pid`` started, in clock ticks since boot (field 22 of
    ``/proc/<pid>/stat``), or None where there is no ``/proc`` or no such process: a pid
    reused by a later process has another start."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return None
    # The command name (field 2) is in parentheses and may hold spaces: split after it.
    fields = stat[stat.rfind(")") + 2 :].split()
    return fields[19] if len(fields) > 19 else None


def _alive(record: dict[str, Any]) -> bool | None:
    """Whether the process a lock names still runs: True, False, or None where it cannot be
    told (another host, no POSIX ``kill``, a record without a pid)."""
    pid = record.get("pid")
    if record.get("host") != socket.gethostname() or not isinstance(pid, int) or pid <= 0:
        return None
    if os.name != "posix":  # os.kill(pid, 0) ends the process on Windows
        return None
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # another user's process: it runs
        pass
    started = record.get("process_start")
    now = _process_start(pid)
    return not (started is not None and now is not None and now != started)


def holder(folder: Path) -> dict[str, Any] | None:
    """The record of the lock in ``folder`` (pid, host, started, command), or None when the
    folder is not locked; a lock file that cannot be read as one is ``{"unreadable": text}``."""
    return _read(Path(folder) / LOCK_FILE)


def _read(lock: Path) -> dict[str, Any] | None:
    """The record of the lock file ``lock``, None when there is none, ``{"unreadable": text}``
    when it cannot be read as one, with ``"unwritten": True`` when it is empty or the start
    of a record (a command writing it this instant, or killed as it did): bytes that are not
    text read as such too, never an error."""
    try:
        text = lock.read_bytes().decode("utf-8", errors="replace")
    except FileNotFoundError:
        return None
    except OSError as error:
        return {"unreadable": str(error)}
    try:
        record = json.loads(text)
    except ValueError:
        record = None
    if isinstance(record, dict):
        return record
    unwritten = record is None and (not text.strip() or text.lstrip().startswith("{"))
    return {"unreadable": text[:200], **({"unwritten": True} if unwritten else {})}


#: s after which a lock file without its whole record is a command's that was killed (or
#: failed to write, the disk full) between creating it and writing its record: a command
#: writes it at once, so a younger one is a command taking the folder this instant.
EMPTY_LOCK_AGE_S = 10.0


def _left_unwritten(lock: Path, record: dict[str, Any]) -> bool:
    """Whether ``lock`` (read as ``record``) is empty or partly written and older than
    EMPTY_LOCK_AGE_S."""
    if not record.get("unwritten"):
        return False
    try:
        return time.time() - lock.stat().st_mtime > EMPTY_LOCK_AGE_S
    except OSError:
        return False


def _describe(record: dict[str, Any]) -> str:
    if record.get("unwritten"):
        return (
            f"a command taking it this instant (its lock file cannot be read yet: "
            f"{record['unreadable']!r}; one left so by a killed command is taken over "
            f"{EMPTY_LOCK_AGE_S:g} s after it was created)"
        )
    if "unreadable" in record:
        return f"a lock file that cannot be read ({record['unreadable']!r})"
    return (
        f"{record.get('task', 'a command')} (pid {record.get('pid')} on host "
        f"{record.get('host')!r}, started {record.get('started')}, command line "
        f"{record.get('command')!r})"
    )


def _guarded(lock: Path) -> Path:
    """What the lock file ``lock`` guards: its folder (``fibreshell.lock``), or the file of
    that folder its name ends with (``fibreshell.lock.checkpoint.pkl``: ``checkpoint.pkl``)."""
    if lock.name == LOCK_FILE:
        return lock.parent
    return lock.with_name(lock.name[len(LOCK_FILE) + 1 :])


def _refusal(lock: Path, record: dict[str, Any], what: str) -> FolderInUse:
    other = "output folder" if lock.name == LOCK_FILE else "file name"
    return FolderInUse(
        f"{what} {str(_guarded(lock))!r} is in use by {_describe(record)}: two commands "
        "writing into one folder or one file remove and mix each other's files; wait for it "
        f"to end or give another {other} (if no such command is running any more, delete "
        f"{str(lock)!r})"
    )


def _take_over(lock: Path, stale: dict[str, Any]) -> bool:
    """Remove the lock file ``lock`` if it still holds the record ``stale`` (of an ended
    process): renamed aside first, so that of two commands taking it over at once only one
    removes it, and a lock taken meanwhile by a third is put back. True when removed."""
    aside = lock.with_name(f"{lock.name}.stale-{os.getpid()}-{uuid.uuid4().hex[:8]}")
    try:
        os.rename(lock, aside)
    except FileNotFoundError:  # another command took it over first: try to create it again
        return True
    moved = _read(aside)  # read as the stale one was
    if moved != stale:  # not the stale lock any more: another's, put back
        os.rename(aside, lock)
        return False
    aside.unlink(missing_ok=True)
    return True


def _write_new(path: Path, text: str) -> None:
    """Create the file ``path`` (FileExistsError if it exists) holding ``text``; removed
    again, and OutputError raised, when ``text`` cannot be written (a full disk)."""
    descriptor = os.open(path, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
    try:
        with os.fdopen(descriptor, "w") as handle:
            handle.write(text)
    except OSError as error:
        path.unlink(missing_ok=True)
        raise OutputError.from_error(error, "nothing (the lock was not taken)") from None


def _create(lock: Path, text: str) -> bool:
    """Create the lock file ``lock`` holding ``text``; False when it exists.

    The record is written to a file of its own first, then linked as ``lock`` (``link``
    fails when the name exists: atomic on local file systems and on NFS), so that a reader
    never finds the lock without its whole record. Where hard links are not to be had (FAT,
    some network shares) the lock is created, then written: a reader may then find it empty
    for an instant, which it takes as held (``_read``: "unwritten")."""
    staged = lock.with_name(f"{lock.name}.new-{os.getpid()}-{uuid.uuid4().hex[:8]}")
    _write_new(staged, text)
    try:
        os.link(staged, lock)
    except FileExistsError:
        # NFS v2/3: the server made the link, its reply was lost, the client's retry found
        # the name taken. Then the staged file has two names, and the lock is this record.
        try:
            return os.stat(staged).st_nlink == 2
        except OSError:
            return False
    except OSError:  # no hard links here
        try:
            _write_new(lock, text)
        except FileExistsError:
            return False
    finally:
        staged.unlink(missing_ok=True)
    return True


def refuse_if_held(folder: Path, what: str) -> None:
    """Refuse (FolderInUse) to write ``what`` into ``folder`` while another command holds that
    folder's lock: a run's checkpoint placed in another run's output folder, where that run's
    cleaning and its own files meet it. The folder is not taken (runs keeping their
    checkpoints side by side in one folder outside their own run together), only looked at:
    a lock of this process (a comparison or a sweep holding the folder its runs are in) or of
    an ended process lets it pass; a living one of another process, another host's, or one
    that cannot be read refuses it.

    Parameters
    ----------
    folder : pathlib.Path
        The folder ``what`` lands in.
    what : str
        It in the message ("the checkpoint '../a/ck.pkl'").
    """
    lock = Path(folder) / LOCK_FILE
    record = _read(lock)
    if record is None:
        return
    ours = record.get("pid") == os.getpid() and record.get("host") == socket.gethostname()
    if ours or ("unreadable" not in record and _alive(record) is False):
        return
    if record.get("unwritten") and _left_unwritten(lock, record):
        return
    raise FolderInUse(
        f"{what} lands in {str(folder)!r}, which is in use by {_describe(record)}: its run "
        "removes and writes its files there as it goes; wait for it to end or give a "
        f"checkpoint outside that folder (if no such command is running any more, delete "
        f"{str(lock)!r})"
    )


#: A record written aside before it is linked as a lock (``_create``): the lock's name, then
#: ``.new-<pid>-<8 hex>``.
STAGED_FILE = re.compile(re.escape(LOCK_FILE) + r"(\..+)?\.new-[0-9]+-[0-9a-f]{8}")
#: A dead holder's lock renamed aside by the command taking it over (``_take_over``), for the
#: microseconds before it is removed or put back: ``.stale-<pid>-<8 hex>``.
ASIDE_FILE = re.compile(re.escape(LOCK_FILE) + r"(\..+)?\.stale-[0-9]+-[0-9a-f]{8}")


def remove_dead_staging(folder: Path) -> list[Path]:
    """Remove from ``folder`` the staged lock records (STAGED_FILE) that their command left
    when it was killed before linking them: those whose record names a process of this host
    that has ended (``_alive``), and those left empty or partly written more than
    EMPTY_LOCK_AGE_S ago. A living command's, another host's, or an unreadable one stays.
    A lock renamed aside by a take-over (ASIDE_FILE) and still there EMPTY_LOCK_AGE_S later
    was left by a command killed in those microseconds: removed too.

    Returns
    -------
    list[pathlib.Path]
        The files removed.
    """
    removed: list[Path] = []
    try:
        names = [entry.name for entry in os.scandir(folder)]
    except OSError:
        return removed
    for name in names:
        if ASIDE_FILE.fullmatch(name) is not None:
            aside = Path(folder) / name
            try:
                left = time.time() - aside.stat().st_mtime > EMPTY_LOCK_AGE_S
            except OSError:
                continue
            if left:
                aside.unlink(missing_ok=True)
                removed.append(aside)
            continue
        if STAGED_FILE.fullmatch(name) is None:
            continue
        staged = Path(folder) / name
        record = _read(staged)
        if record is None:  # linked and removed by its command meanwhile
            continue
        if _left_unwritten(staged, record) or (
            "unreadable" not in record and _alive(record) is False
        ):
            staged.unlink(missing_ok=True)
            removed.append(staged)
    return removed


@contextmanager
def folder_lock(
    folder: Path, task: str, what: str = "the output folder", file: str | None = None
) -> Iterator[Path]:
    """Hold the lock of the existing folder ``folder`` (or of the file ``file`` in it) for
    the ``with`` block.

    Parameters
    ----------
    folder : pathlib.Path
        The folder the command writes into (it must exist).
    task : str
        What holds it ("the run of cases/a.toml"), in the lock and in the message of a
        command refused there, beside this process's command line.
    what : str
        The folder's (or the file's) name in messages ("the output folder", "--out", "the
        checkpoint").
    file : str, optional
        Lock this file of ``folder`` alone (a checkpoint a run may write outside its output
        folder), by the lock file ``fibreshell.lock.<file>`` beside it; by default the
        folder, by ``fibreshell.lock``.

    Yields
    ------
    pathlib.Path
        The lock file.

    Raises
    ------
    FolderInUse
        Another command holds the folder (a running process, one of another host, or a lock
        that cannot be read): the message names it and the lock file.
    """
    folder = Path(folder)
    lock = folder / (LOCK_FILE if file is None else f"{LOCK_FILE}.{file}")
    record = {
        "pid": os.getpid(),
        "host": socket.gethostname(),
        "started": time.strftime("%Y-%m-%d %H:%M:%S UTC", time.gmtime()),
        "task": task,
        "command": " ".join([sys.executable, *sys.argv]),
        "process_start": _process_start(os.getpid()),
        "token": uuid.uuid4().hex,
    }
    text = json.dumps(record, indent=1) + "\n"
    remove_dead_staging(folder)  # a killed command's record, which keeps the folder from rmdir
    for _ in range(3):  # a stale lock taken over, then created: a race lost twice is refused
        if not _create(lock, text):
            other = _read(lock)
            if other is None:  # released meanwhile
                continue
            if _left_unwritten(lock, other):
                if _take_over(lock, other):
                    warnings.warn(
                        f"{str(lock)!r} was left empty or partly written more than "
                        f"{EMPTY_LOCK_AGE_S:g} s ago (a command killed as it took the folder, "
                        f"or its disk full); taken over by {task}",
                        UserWarning,
                        stacklevel=3,
                    )
                continue
            if "unreadable" in other or _alive(other) is not False:
                raise _refusal(lock, other, what) from None
            if _take_over(lock, other):
                warnings.warn(
                    f"{str(lock)!r} was left by {_describe(other)}, which has ended (killed?); "
                    f"taken over by {task}",
                    UserWarning,
                    stacklevel=3,
                )
            continue
        break
    else:
        raise _refusal(lock, _read(lock) or {"unreadable": "(gone)"}, what)
    try:
        yield lock
    finally:
        # Only our own lock: a user who deleted it and started another command keeps theirs.
        if (_read(lock) or {}).get("token") == record["token"]:
            lock.unlink(missing_ok=True)
