"""A whole run's measured test durations replayed under pytest-xdist's ``load`` and
``worksteal`` schedulers (tests/xdist_replay.py: xdist's own scheduler classes, no test run),
beside the run's own workers: when each of the two workers would end, and the idle tail (the
time one waits for the other at the end).

The timeline comes from a run with this script's plugin (``--plugin FOLDER`` writes it as
``suite_timeline.py`` into FOLDER; run ``SUITE_TIMELINE=OUT PYTHONPATH=.:FOLDER python -m
pytest -p suite_timeline``: each worker writes ``gwN.txt``, a line ``start end nodeid`` per
test); the session's order is this tree's (``pytest --collect-only``, tests/conftest.py's
sort). A test's duration is its wall in the measured run, setup and teardown included: the
tests that read the coarse report carry their wait for it, which the replay keeps where the
run met it (their place in the order is the same under both schedulers, the last ones).

Why: the suite's order puts its 85 slow tests first (tests/conftest.py); xdist's ``load``
hands the first worker a run of a quarter of its share at the start (514 of 4118 tests, every
slow one among them) and never takes back what it has sent, so where those 514 tests take
longer than half the run the other worker, done with everything else, waits at the end;
``worksteal`` (pyproject.toml since a78168a) takes half of the unstarted tests of a busy
worker for an idle one. On a session of that shape (tests/test_suite_setup.py: 10 tests of
10 s, then 400 of 0.1 s) the replay ends load's workers at 104.1 and 35.9 s, worksteal's at
70.0 and 70.0 s.

Measured, a whole run of a78168a (``--dist worksteal``; a fresh clone, an empty numba cache,
``python -m pytest``, the 2-core machine shared with other jobs at a load of 10-18: the walls
measure those jobs, mypy alone 532 s against about 25 s in CI): 4113 passed, 5 skipped in
56:25 of pytest, 857.7 s of CPU (user + system of pytest and the processes it reaped); the
first worker ran 78 tests (the slow ones) and ended at 3201.5 s, the other 4040 (its half
and what it took from the first's) at 3235.7 s. Its durations replayed: ``load`` ends the
workers at 3162.9 s (the first, its 515 tests) and 3072.8 s, an idle tail of 90.2 s;
``worksteal`` at 3117.9 and 3117.8 s: 45 s (1.4 %) of wall at these durations, none of CPU.
The run of 432e668 under ``load`` an hour before it (load 9-18): 61.8 min of wall, 845 s of
CPU, its per-test log lost.

Run: python benchmarks/suite_schedule.py TIMELINE_FOLDER
     python benchmarks/suite_schedule.py --plugin FOLDER
"""

import argparse
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

from xdist_replay import ends, replay  # noqa: E402

PLUGIN = """
import os, time
_started = {}
def pytest_runtest_logstart(nodeid, location):
    _started[nodeid] = time.time()
def pytest_runtest_logfinish(nodeid, location):
    worker = os.environ.get("PYTEST_XDIST_WORKER", "main")
    with open(os.path.join(os.environ["SUITE_TIMELINE"], worker + ".txt"), "a") as log:
        log.write(f"{_started.get(nodeid, 0.0):.3f} {time.time():.3f} {nodeid}\\n")
"""


def session_order() -> list[str]:
    """This tree's test ids in the session's order (one process, no test run)."""
    listed = subprocess.run(
        [sys.executable, "-m", "pytest", "--collect-only", "-q", "-n", "0"],
        cwd=ROOT, capture_output=True, text=True, env=dict(os.environ, PYTHONPATH=str(ROOT)),
    )  # fmt: skip
    return [line for line in listed.stdout.splitlines() if "::" in line]


def measured(folder: Path) -> tuple[dict[str, float], dict[str, tuple[int, float, float]]]:
    """Each test's wall (s) in the run of ``folder``, and per worker its tests, busy
    seconds and end (s after the run's first test started)."""
    spans = {}
    for log in sorted(folder.glob("gw*.txt")):
        for line in log.read_text().splitlines():
            start, end, nodeid = line.split(" ", 2)
            spans[nodeid] = (log.stem, float(start), float(end))
    zero = min(start for _, start, _ in spans.values())
    workers: dict[str, tuple[int, float, float]] = {}
    for worker, start, end in spans.values():
        tests, busy, last = workers.get(worker, (0, 0.0, 0.0))
        workers[worker] = (tests + 1, busy + end - start, max(last, end - zero))
    return {nodeid: end - start for nodeid, (_, start, end) in spans.items()}, workers


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("timeline", nargs="?", type=Path, help="a run's timeline folder")
    parser.add_argument("--plugin", type=Path, help="write the timeline plugin into a folder")
    args = parser.parse_args()
    if args.plugin is not None:
        args.plugin.mkdir(parents=True, exist_ok=True)
        (args.plugin / "suite_timeline.py").write_text(PLUGIN)
        print(f"wrote {args.plugin / 'suite_timeline.py'}")
        return
    if args.timeline is None:
        parser.error("give a timeline folder (or --plugin FOLDER)")
    durations, workers = measured(args.timeline)
    order = session_order()
    missing = [nodeid for nodeid in order if nodeid not in durations]
    print(f"{len(order)} tests in the session's order, {len(durations)} timed "
          f"({len(missing)} not in the timeline: replayed at 0 s)")  # fmt: skip
    for name, (tests, busy, end) in sorted(workers.items()):
        print(f"  measured {name}: {tests} tests, busy {busy:.1f} s, ends at {end:.1f} s")
    walls = [durations.get(nodeid, 0.0) for nodeid in order]
    print(f"  sum of the tests' walls {sum(walls):.1f} s, longest {max(walls):.1f} s")
    for dist in ("load", "worksteal"):
        ran = replay(dist, walls)
        end = ends(ran)
        figures = ", ".join(
            f"{name} {len(ran[name])} tests ends at {end[name]:.1f} s" for name in sorted(end)
        )
        print(f"  replayed --dist {dist}: {figures}; "
              f"idle tail {max(end.values()) - min(end.values()):.1f} s")  # fmt: skip


if __name__ == "__main__":
    main()
