"""The whole suite's wall time and how its two xdist workers share it: each git ref's tests
run from a fresh export of that ref (no numba cache, no bytecode, as CI starts), one after
the other in the same session, each worker's tests logged (start and end); the figures
printed side by side: the pytest wall, each worker's tests, busy seconds and end, and the
idle tail (the time one worker waited for the other at the end).

Measured (the same timeline on the working tree, tests/conftest.py before and after the slow
tests were ordered first, one whole run each, 1922 tests; load 0.9 -> 5.7 and 2.2 -> 5.5, the
run's own two workers and the coarse report's two jobs included):

    order                       pytest wall   gw0 end / busy    gw1 end / busy    idle tail
    collected (report last)       437.9 s     429.4 / 420.0 s   400.4 / 390.9 s     29.0 s
    slow first (report last)      365.9 s     364.5 / 355.9 s   365.2 / 357.4 s      0.7 s

Before, mypy's 29 s (tests/test_typecheck.py, collected late) started last on one worker with
1 s of tests left on the other. The busy seconds fell too (811 -> 713 s in all): one run
each on a shared machine, so part of that is noise; the tail is the ordering's.

Each ref's line also gives the CPU of pytest and of the processes it reaped (user + system,
``resource.RUSAGE_CHILDREN``: the background report's is counted only when the worker that
started it reaped it, so the figure is not comparable between orders of the report) and when
the background report started and ended (its folder's pid and status files).

Measured, the report started once six of its kernels were in numba's cache or a third of the
tests had run (fdcebfd) against at the session's start, its processes compiling under the
session's locks (4e26496), one whole run each, one after the other, on the 2-core machine
shared with other jobs (load 6.6 -> 5.5 and 5.5 -> 13 -> 9.1, the run's own four processes
included):

    ref        pytest wall   report start / end   gw0 end / busy      gw1 end / busy
    fdcebfd       758.8 s       195.0 / 719.8 s   748.1 / 729.6 s     747.2 / 722.3 s
    4e26496      1134.0 s        17.1 / 689.0 s   1110.5 / 1089.7 s   1119.1 / 1089.4 s

The second run met twice the other jobs' load (the walls measure it); the report, its
longest case on one process, ended 31 s earlier in it all the same. Not measured on a quiet
machine: the gain in wall there is not known.

Run: python benchmarks/suite_workers.py [--refs OLD NEW] [-- PYTEST_ARGS] (default refs
HEAD~1 and HEAD; the order before and after: --refs c820fce 8ad67d5; the README's ``pytest``
by default, about 7 min of both cores per ref).
"""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

PLUGIN = """
import os, sys, time
_started = {}
def pytest_runtest_logstart(nodeid, location):
    _started[nodeid] = time.time()
def pytest_runtest_logfinish(nodeid, location):
    worker = os.environ.get("PYTEST_XDIST_WORKER", "main")
    with open(os.path.join(os.environ["SUITE_TIMELINE"], worker + ".txt"), "a") as log:
        log.write(f"{_started.get(nodeid, 0.0):.3f} {time.time():.3f}\\n")
    # the background report's start and end (its folder's pid and status files)
    folder = getattr(sys.modules.get("conftest"), "_folder", {}).get("path")
    if folder is not None:
        for name in ("pid", "status"):
            try:
                stamp = os.stat(os.path.join(folder, name)).st_mtime
            except OSError:
                continue
            with open(os.path.join(os.environ["SUITE_TIMELINE"], "report_" + name), "w") as f:
                f.write(f"{stamp:.3f}")
"""


def run(ref: str, pytest_args: list[str], scratch: Path) -> dict:
    """The suite of ``ref`` from a fresh export: the pytest wall (s) and, per worker, its
    tests, busy seconds and end (s after the start)."""
    scratch = Path(tempfile.mkdtemp(dir=scratch))  # a ref may come twice
    tree, timeline = scratch / "tree", scratch / "timeline"
    tree.mkdir()
    timeline.mkdir()
    archive = subprocess.run(["git", "archive", ref], cwd=ROOT, capture_output=True, check=True)
    subprocess.run(["tar", "-x", "-C", str(tree)], input=archive.stdout, check=True)
    (scratch / "suite_timeline.py").write_text(PLUGIN)
    env = dict(os.environ, PYTHONPATH=f"{tree}{os.pathsep}{scratch}",
               SUITE_TIMELINE=str(timeline))  # fmt: skip
    started, before = time.time(), resource.getrusage(resource.RUSAGE_CHILDREN)
    done = subprocess.run([sys.executable, "-m", "pytest", "-p", "suite_timeline", *pytest_args],
                          cwd=tree, env=env, capture_output=True, text=True)  # fmt: skip
    wall = time.time() - started
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime
    report = {
        name: float((timeline / f"report_{name}").read_text()) - started
        for name in ("pid", "status")
        if (timeline / f"report_{name}").exists()
    }
    workers = {}
    for log in sorted(timeline.glob("*.txt")):
        spans = [tuple(map(float, line.split())) for line in log.read_text().splitlines()]
        workers[log.stem] = (
            len(spans),
            sum(end - start for start, end in spans),
            max(end for _, end in spans) - started,
        )
    if len(workers) > 1:  # xdist's main process logs every worker's tests too
        workers.pop("main", None)
    summary = done.stdout.strip().splitlines()[-1] if done.stdout.strip() else done.stderr
    return {"wall": wall, "cpu": cpu, "report": report, "workers": workers, "summary": summary}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--refs", nargs=2, default=["HEAD~1", "HEAD"], metavar=("OLD", "NEW"))
    parser.add_argument("pytest_args", nargs="*", help="after --: pytest's arguments")
    args = parser.parse_args()
    print(f"load before: {os.getloadavg()[0]:.2f}")
    with tempfile.TemporaryDirectory() as folder:
        for ref in args.refs:
            figures = run(ref, args.pytest_args, Path(folder))
            ends = [end for _, _, end in figures["workers"].values()]
            print(f"{ref}: {figures['summary']}")
            print(f"  wall {figures['wall']:.1f} s, idle tail {max(ends) - min(ends):.1f} s, "
                  f"CPU {figures['cpu']:.1f} s, load after {os.getloadavg()[0]:.2f}")  # fmt: skip
            report = figures["report"]
            print(f"  report: starts at {report.get('pid', float('nan')):.1f} s, "
                  f"ends at {report.get('status', float('nan')):.1f} s")  # fmt: skip
            for name, (tests, busy, end) in figures["workers"].items():
                print(f"  {name}: {tests} tests, busy {busy:.1f} s, ends at {end:.1f} s")


if __name__ == "__main__":
    main()
