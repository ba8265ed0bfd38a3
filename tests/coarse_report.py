"""The coarse validation report run in the background beside the tests
(tests/conftest.py, the ``coarse_report`` fixture): ``python -m validation`` in a process group
of its own, started once per session in a folder the session's processes share (the pytest
process, or each of pytest-xdist's workers: the first of them to ask starts it, the others
read the same run), its processes compiling numba's kernels under the same locks as the
tests' (femcore/compile_lock.py: a kernel that a test compiles beside them is compiled once)."""

import fcntl
import json
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

# The report's command wrapped so that its exit status lands in a file, where a process that
# did not start it (another xdist worker) can read it: os.replace makes the file whole or absent.
_RECORD_STATUS = (
    "import os, subprocess, sys\n"
    "status = subprocess.call(sys.argv[2:])\n"
    "with open(sys.argv[1] + '.part', 'w') as f:\n"
    "    f.write(str(status))\n"
    "os.replace(sys.argv[1] + '.part', sys.argv[1])\n"
)


class CoarseReport:
    """``python -m validation --resolution coarse --jobs 2`` (the README's main job) running
    in its own process group, writing into ``folder``: ``out`` the report, ``log`` its
    printed lines, ``status`` its exit status once it has ended, ``pid`` its process group.

    Use ``CoarseReport.start_once(folder)``: the first call in a folder starts the run (under a
    file lock), the later ones, in this process or another, attach to it."""

    def __init__(self, folder: Path) -> None:
        self.folder = Path(folder)
        self.out = self.folder / "report"
        self.log = self.folder / "report.log"
        self.status = self.folder / "status"
        self.pid = self.folder / "pid"
        self.process: subprocess.Popen | None = None  # where this process started it

    @classmethod
    def start_once(cls, folder: Path, command: list[str] | None = None) -> "CoarseReport":
        """The run in ``folder``: started here if no process has started it yet. ``command``
        replaces the report's (a test's stand-in: it writes ``out``/results.json, whose path
        it is given as its last argument)."""
        report = cls(folder)
        report.folder.mkdir(parents=True, exist_ok=True)
        with open(report.folder / "lock", "w") as lock:
            fcntl.flock(lock, fcntl.LOCK_EX)
            if not report.pid.exists():
                with open(report.log, "wb") as log:
                    report.process = subprocess.Popen(
                        [sys.executable, "-c", _RECORD_STATUS, str(report.status),
                         *(command or [sys.executable, "-m", "validation", "--resolution",
                                       "coarse", "--jobs", "2", "--out"]), str(report.out)],
                        cwd=ROOT, stdout=log, stderr=subprocess.STDOUT, start_new_session=True,
                    )  # fmt: skip
                report.pid.write_text(str(report.process.pid))
        return report

    def _running(self) -> bool:
        """Whether a process of the run's group is still there (this process's own child
        reaped first, so that it does not linger as a zombie of the group)."""
        if self.process is not None:
            self.process.poll()
        try:
            os.killpg(int(self.pid.read_text()), 0)
        except ProcessLookupError:
            return False
        return True

    def result(self) -> tuple[Path, dict]:
        """The report folder and its results.json, once the run has ended."""
        while not self.status.exists():
            if not self._running() and not self.status.exists():
                raise AssertionError("the coarse report stopped without its status (killed?):\n"
                                     + self.log.read_text()[-4000:])  # fmt: skip
            time.sleep(0.5)
        status = int(self.status.read_text())
        assert status == 0, self.log.read_text()[-4000:]
        return self.out, json.loads((self.out / "results.json").read_text())

    def stop(self) -> None:
        """The run and its workers ended (asked to stop, as Ctrl-C would: each finishes its
        step; killed if still there after 30 s), the folder removed. A run that has written
        its status has ended (its wrapper may linger as a zombie of an xdist worker)."""
        if self.pid.exists() and not self.status.exists():
            group = int(self.pid.read_text())
            if self._running():
                os.killpg(group, signal.SIGTERM)
            for _ in range(300):
                if not self._running():
                    break
                time.sleep(0.1)
            else:
                os.killpg(group, signal.SIGKILL)
        shutil.rmtree(self.folder, ignore_errors=True)
