"""The cores a whole run of the suite leaves idle: the run's processes (pytest, its xdist
workers, the coarse report's jobs and Dask workers, the tests' subprocesses) sampled every
half second from /proc, each runnable (state R or D) or asleep (its kernel wait channel: a
sleep in ``hrtimer_nanosleep`` is mostly a process polling a kernel's compile lock,
femcore/compile_lock.py, or a test's own wait; ``do_wait`` a parent waiting for a child; a
``futex`` or ``epoll`` wait a thread or an event loop). Where fewer of them are runnable than
the machine has cores, a quiet machine would have a core idle: the run's idle core-seconds
are the integral of max(0, cores - runnable), the wall it could save at most that over the
cores. The run's tests from a fresh export of ``--ref`` (no numba cache, no bytecode, as CI
starts); its CPU (user + system of the processes it reaped, ``resource.RUSAGE_CHILDREN``) and
the machine's load are printed beside it. On a shared machine the figures stay meaningful:
a process another job keeps from a core is still runnable, so the count sees the run's own
waits, not the other jobs'.

Measured (this sampling, every 0.5 s, on one whole run of d92ef8d, ``python -m pytest`` from a
fresh clone: two xdist workers beside the coarse report; 2259 passed, 15:21 of pytest on the
2-core machine shared with other jobs, load 4-7; CPU of the sampled processes 598 s): 61
idle core-seconds (at most ~30 s of a quiet run's wall), 57 s with one process runnable.
Where: 13 core-s at 60-90 s, both xdist workers and a report job polling compile locks
(``hrtimer_nanosleep``) while one process compiled the fibrous kernels every one of them
needed first; 29 core-s at 420-480 s, after the report had ended, a Dask fit (the README's
``fibreshell identify``: its worker processes idle in ``epoll`` between the least-squares
rounds, the xdist worker waiting on the fit in a ``futex``) beside the other worker alone;
10 core-s in the last 30 s, one worker ending before the other. The rest of the run kept both
cores busy: the suite's wall on a quiet machine is its CPU over the cores, within ~30 s.

Measured again, the same sampling (each xdist worker's tests logged too), a fresh clone of each
ref, ``python -m pytest``, the 2-core machine shared with other jobs (the walls measure them;
idle core-seconds weighted by the time between samples, which grows with the load):

    388ef6d (slow tests first), load 0.1 -> 7.4: 875.6 s of pytest, 64.4 idle core-s: 21.1 in
        the first 300 s (compile-lock waits), 30 at 300-420 s (the README's Dask sweep and
        fit and the report's kill test, after the report had ended), 9 at the end.
    3d026ad (mypy, then the tests that wait for processes they start, then the other slow
        ones: tests/conftest.py), load 5.3 -> 10.8: 1047.3 s, 38.5 idle core-s: 26.3 in the
        first 300 s (24 at 180-240 s: the fit calibration's Dask worker compiling the fibrous
        kernels, the bias extension's test and the report's jobs waiting on its locks), none
        after the report had ended, the two workers ending 0.1 s apart.
    35ffee8 (the same order; 2472 passed, 7 skipped), load 1.2 -> 11 (other jobs from the
        second minute on): tests done at about 1230 s, 57 idle core-s until then: 37 at
        120-180 s (the compile-lock waits of the start, as before), 13 at 510-600 s, 4 in the
        last 30 s. CPU of pytest's processes 730 s, the coarse report's cases 191 s of it
        (``case_cpu_s``; hemisphere-plies 91, bai-6.1.1-sensitivity 30 and its Dask workers,
        hemisphere-forming 19). The suite's wall on a quiet machine is its CPU over the
        cores: a shorter run needs less CPU, not better packing.

Tried and not kept (the first 300 s of a run only, then stopped): mypy first of the second
worker's run (xdist's ``load`` hands the first worker a run of consecutive tests, a quarter of
its share), load 4-7: 36.0 idle core-s; that and the bias extension's arc-length test (the
compilation of the fibrous kernels) first of the first worker's run, load 7-12: 29.8. The
start's idle is the compile-lock waits whatever the order; these differences are within what
the load moves them.

Run: python benchmarks/suite_idle.py [--ref HEAD] [--cores 2] [-- PYTEST_ARGS]
"""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def tree_of(root: int) -> dict[int, tuple[str, str]]:
    """The processes descending from ``root`` (itself included): pid -> (state, wait channel)."""
    parents, states = {}, {}
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            fields = open(f"/proc/{entry}/stat").read().rsplit(")", 1)[1].split()
        except OSError:
            continue
        parents[int(entry)], states[int(entry)] = int(fields[1]), fields[0]
    members, grown = {root}, True
    while grown:
        grown = False
        for pid, parent in parents.items():
            if parent in members and pid not in members:
                members.add(pid)
                grown = True
    found = {}
    for pid in members & states.keys():
        try:
            channel = open(f"/proc/{pid}/wchan").read()
        except OSError:
            channel = ""
        found[pid] = (states[pid], channel)
    return found


def run(ref: str, pytest_args: list[str], cores: int, period: float) -> dict:
    """The suite of ``ref`` from a fresh export, sampled: wall, CPU, idle core-seconds, the
    seconds spent at each count of runnable processes, the idle core-seconds per 30-s window
    and the wait channels of the sleepers while a core was idle."""
    with tempfile.TemporaryDirectory() as scratch:
        tree = Path(scratch) / "tree"
        tree.mkdir()
        archive = subprocess.run(["git", "archive", ref], cwd=ROOT, capture_output=True, check=True)
        subprocess.run(["tar", "-x", "-C", str(tree)], input=archive.stdout, check=True)
        # pytest's output into a file, read once it has ended: a pipe read only then fills at
        # 64 KiB (a run with --durations=0 prints more) and pytest, blocked writing its last
        # lines, never ends.
        printed = Path(scratch) / "pytest.out"
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        started = time.time()
        with open(printed, "w") as sink:
            process = subprocess.Popen(
                [sys.executable, "-m", "pytest", *pytest_args],
                cwd=tree,
                stdout=sink,
                stderr=subprocess.STDOUT,
                text=True,
            )
        idle, at_count, windows, waits = 0.0, Counter(), Counter(), Counter()
        last = started
        while process.poll() is None:
            found = tree_of(process.pid)
            now = time.time()
            step, last = now - last, now
            runnable = sum(1 for state, _ in found.values() if state in "RD")
            at_count[runnable] += step
            missing = max(0, cores - runnable) * step
            idle += missing
            windows[int((now - started) // 30) * 30] += missing
            if missing:
                for state, channel in found.values():
                    if state == "S":
                        waits[channel] += missing / max(1, len(found))
            time.sleep(period)
        output = printed.read_text()
        wall = time.time() - started
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime
    summary = output.strip().splitlines()[-1] if output.strip() else ""
    return {
        "wall": wall,
        "cpu": cpu,
        "idle": idle,
        "at_count": at_count,
        "windows": windows,
        "waits": waits,
        "summary": summary,
        "output": output,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--ref", default="HEAD")
    parser.add_argument("--cores", type=int, default=os.cpu_count() or 2)
    parser.add_argument("--period", type=float, default=0.5, help="s between samples")
    parser.add_argument("--log", type=Path, help="where to write pytest's whole output")
    parser.add_argument("pytest_args", nargs="*", help="after --: pytest's arguments")
    args = parser.parse_args()
    print(f"load before: {os.getloadavg()}")
    figures = run(args.ref, args.pytest_args, args.cores, args.period)
    if args.log is not None:
        args.log.write_text(figures["output"])
    print(f"{args.ref}: {figures['summary']}")
    print(
        f"  wall {figures['wall']:.1f} s, CPU {figures['cpu']:.1f} s "
        f"(CPU / cores {figures['cpu'] / args.cores:.1f} s), load after {os.getloadavg()}"
    )
    print(
        f"  idle core-seconds {figures['idle']:.1f} (at most {figures['idle'] / args.cores:.1f}"
        " s of wall on a quiet machine)"
    )
    counts = ", ".join(f"{k}: {v:.0f} s" for k, v in sorted(figures["at_count"].items()))
    print(f"  seconds at each count of runnable processes: {counts}")
    print(
        "  idle core-seconds per 30 s of the run: "
        + ", ".join(f"{k}-{k + 30}: {v:.1f}" for k, v in sorted(figures["windows"].items()) if v)
    )
    print("  while a core was idle, the sleepers' wait channels (core-seconds shared among them):")
    for channel, share in figures["waits"].most_common(6):
        print(f"    {channel or '?'}: {share:.1f}")


if __name__ == "__main__":
    main()
