"""A report run with several jobs leaves no worker behind when it is killed: its worker
processes end with it, whatever ends it (a kill -9 runs no clean-up in the report's process);
interrupted (Ctrl-C), it ends at once, its queued tasks not run."""

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def _children(pid: int) -> list[int]:
    """The pids of the processes whose parent is ``pid`` (Linux /proc)."""
    found = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                fields = (entry / "stat").read_text().rsplit(")", 1)[1].split()
            except OSError:  # gone meanwhile
                continue
            if int(fields[1]) == pid:
                found.append(int(entry.name))
    return found


def _is_worker(pid: int) -> bool:
    try:
        command = Path(f"/proc/{pid}/cmdline").read_bytes()
    except OSError:
        return False
    return b"spawn_main" in command


def _cpu_s(pid: int) -> float:
    """The CPU time (s) process ``pid`` has used, 0 once it is gone."""
    try:
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except OSError:
        return 0.0
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def _alive(pid: int) -> bool:
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return False
    return state != "Z"


def _two_workers(report: subprocess.Popen, within_s: float, poll_s: float) -> list[int]:
    """The pids of ``report``'s two pool workers once both have started (fewer if it did
    not start them within ``within_s`` s or ended), looked for every ``poll_s`` s."""
    workers: list[int] = []
    deadline = time.monotonic() + within_s
    while len(workers) < 2 and time.monotonic() < deadline and report.poll() is None:
        time.sleep(poll_s)
        workers = [p for p in _children(report.pid) if _is_worker(p)]
    return workers


def _end(report: subprocess.Popen, workers: list[int]) -> None:
    """Kill ``report`` and its ``workers`` still running: a test never leaves one, whatever
    failed."""
    if report.poll() is None:
        report.kill()
    for pid in workers:
        if _alive(pid):
            os.kill(pid, signal.SIGKILL)


@pytest.mark.slow  # about 5 s of CPU: the report and two workers into their cases
@pytest.mark.waits  # for the report's workers to start
@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="reads Linux's /proc")
def test_killing_a_report_with_two_jobs_ends_its_workers(tmp_path):
    # Two cases that take 10-20 s of CPU each at the coarse resolution (hemisphere-forming's
    # two parts, plies-bai-5.1): still running at the kill.
    report = subprocess.Popen(
        [sys.executable, "-m", "validation", "--cases", "hemisphere-forming,plies-bai-5.1",
         "--resolution", "coarse", "--jobs", "2", "--out", str(tmp_path / "report")],
        cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
    )  # fmt: skip
    workers: list[int] = []
    try:
        workers = _two_workers(report, within_s=300.0, poll_s=0.5)
        assert len(workers) == 2, "the report did not start its two workers"
        # Past their initializer (report._end_with, which asks the kernel to kill them with
        # the report), so that the kill tests that request, not only the check a worker makes
        # of a parent gone before it asked. A spawned worker runs its initializer once it has
        # imported the modules the report's process imported before it started the pool (its
        # __main__'s), which costs it no more CPU than that process had spent by then (1.4-1.5
        # s; the bytecode and any kernel compiled on the way are cached by then); 0.5 s more
        # puts the kill into the workers' cases (each a minute or more of CPU). (2 s more cost
        # the run 3 s of CPU for nothing: the test fails with either when the workers outlive
        # the report, benchmarks/suite_item_cpu.py.)
        past_initializer = _cpu_s(report.pid) + 0.5
        deadline = time.monotonic() + 600.0
        while min(map(_cpu_s, workers)) < past_initializer and time.monotonic() < deadline:
            time.sleep(0.2)
        assert min(map(_cpu_s, workers)) >= past_initializer, "the workers did not start"
        os.kill(report.pid, signal.SIGKILL)
        report.wait()
        # Killed by the kernel with its parent (or, elsewhere, by a thread polling every 0.5
        # s): 20 s allows for a loaded machine.
        deadline = time.monotonic() + 20.0
        while any(_alive(p) for p in workers) and time.monotonic() < deadline:
            time.sleep(0.2)
        left = [p for p in workers if _alive(p)]
        assert not left, f"workers {left} outlived the killed report"
    finally:
        _end(report, workers)


# The report of a case of six parts that sleep 5 s each, run by two workers: 15 s to run all
INTERRUPTED = """
import sys
from pathlib import Path
sys.path.insert(0, {tests!r})
import parts_case
from validation.cases import CASES
from validation.report import run_cases
CASES["cheap-parts-sleeping"] = parts_case.SLEEPING
run_cases(["cheap-parts-sleeping"], "coarse", Path({out!r}), jobs=2)
"""


@pytest.mark.slow  # a few seconds of wall: two workers started and interrupted
@pytest.mark.waits  # for the report's workers to start
@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="reads Linux's /proc")
def test_an_interrupted_report_ends_at_once_and_its_workers_with_it(tmp_path):
    # Ctrl-C let the pool's exit wait for every queued task (the workers take a
    # KeyboardInterrupt as a task's result and go on with the next): 15 s here, not a few.
    code = INTERRUPTED.format(tests=str(ROOT / "tests"), out=str(tmp_path / "report"))
    report = subprocess.Popen(
        [sys.executable, "-c", code], cwd=ROOT, stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        # SIGINT handled as in a terminal's foreground (a background shell ignores it)
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )  # fmt: skip
    workers: list[int] = []
    try:
        workers = _two_workers(report, within_s=120.0, poll_s=0.2)
        assert len(workers) == 2, "the report did not start its two workers"
        time.sleep(3.0)  # into their first parts (a worker starts in about 1.5 s of CPU)
        os.kill(report.pid, signal.SIGINT)  # to the report alone, not its process group
        interrupted = time.monotonic()
        report.wait(timeout=60.0)
        took = time.monotonic() - interrupted
        # the workers end at once, the interpreter's exit a second or two on a loaded machine
        assert took < 6.0, f"the interrupted report took {took:.1f} s to end"
        assert report.returncode != 0
        left = [p for p in workers if _alive(p)]
        assert not left, f"workers {left} outlived the interrupted report"
    finally:
        _end(report, workers)
