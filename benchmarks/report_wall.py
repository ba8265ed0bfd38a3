"""The validation report's wall time with several jobs against its CPU time over the jobs.

``walls``: ``python -m validation --jobs J`` run as a user runs it, with the code of each
``--code`` folder (a copy of the code before, and this one), alternating, back to back, on the
same warm numba cache; per run: the wall time, the CPU time of every process of the run (the
report's, its workers', from the children's rusage), the sum of the cases' ``case_cpu_s``,
that sum over the jobs (the ideal wall, were the tasks spread evenly and free of overhead),
the largest task (a whole case, or a part of a case in parts: ``Case.parts``) and the
machine's load before and after; the report's printed lines kept beside its folder. Each
code's report folder is kept between rounds, so that a later round orders its tasks by the
times the earlier one measured (as a user's ``--out report`` does); its results.json is
compared with the first run's, number by number, the times aside (those in texts too).

``overheads``: the fixed costs in the wall, each in a fresh process of this tree: the report
process's imports, a spawned worker's start and imports (up to its first task), a case
part's first run against its second in the same process (numba's cached kernels loaded at
their first call, and the nets and meshes made again) and the HTML page and results.json
written from a report's results.

Usage::

    python benchmarks/report_wall.py walls --code /tmp/before --code . --out /tmp/walls
    python benchmarks/report_wall.py overheads --results /tmp/walls/1/results.json

Measured (``walls``, default resolution, ``--jobs 2``, one numba thread, a warm cache, the
code before (main 3228ca0: a case is one task) and this (hemisphere-plies' four runs and
hemisphere-forming's two are tasks of their own) alternating, two rounds; 2 cores shared with
other jobs, load 6.6-13.7, which sets the walls, 386-585 s: no figure of the report's):

    round 2        every process   cases' CPU   / 2    largest task              packed
    before         183.0 s         176.5 s      88.2   hemisphere-plies 64.3 s   88.3 s
    this           188.5 s         183.2 s      91.6   plies Mindlin [0/90] 27.8 90.4 s

187 of 187 checks both; every number of results.json the same (the times aside), the split
cases' too. At today's CPU the packed wall is already the CPU over the jobs (the rest of the
cases fill the other core beside hemisphere-plies); what changes is its floor: a case's CPU
(hemisphere-plies 48-64 s) before, a run's (its Mindlin [0/90] run, 19-28 s) now, so that the
cases' CPU cuts bring the wall down with them. The parts' price: hemisphere-plies 64.3 ->
70.1 s of case CPU (68.7 in its parts, 1.4 s combining and drawing in the report's process),
hemisphere-forming 35.7 -> 34.5 (1.1 s combining), at this load's scatter; its source is the
kernels' cache loaded by both workers where one did (below) and the parent's matplotlib.

``overheads`` (load 10-11.5, CPU; the least of one fresh process): the report process's
imports 1.20 s, a spawned worker's start and imports 1.26 s (each worker once: the pool keeps
its processes for all their tasks), a hemisphere-plies part's first run 12.17 s against 11.02
s for its second in the same process (1.15 s of numba's cached kernels loaded once per
worker), results.json and index.html written 0.02 s. So about 2.5 s of wall before the first
task starts (the report's imports, then the workers'), about 1 s per kernel family a worker
meets, and nothing to speak of at the end.

Where the parts are combined: a part's data pickled in its worker is 2.2 MB (hemisphere-forming's
fibrous run, coarse) and 1.7 MB (its Mindlin run); a three-frame two-ply run's 0.26-0.33 MB
pickles in 1 ms. Combined and drawn in the report's process (1.1-1.4 s of CPU, above) they
overlap the workers' tasks; as one more task of the pool it would start after every task
submitted before it (the pool takes them in order), at the end of the report.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import resource
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this tree's packages
TIMES = ("case_time_s", "case_cpu_s", "parts", "wall_time_s", "generated")
# parameters that hold a measured time (the runs' wall and CPU, their load): not compared
TIMED_WORDS = ("wall_time", "wall time", "cpu_time", "runtime", "_wall_s", "_cpu_s")
# a time in a text ("..., 33.2 s" in a paper case's solver line, "15.7 s elapsed")
SECONDS = re.compile(r"\d+(\.\d+)? s\b")


def _children_cpu() -> float:
    """User + system CPU time (s) of this process's reaped children and theirs."""
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def _numbers(value, path: str = ""):
    """(path, number or text) of every leaf of a results.json value, the times aside."""
    if isinstance(value, dict):
        for key, item in value.items():
            if key in TIMES or any(word in key for word in TIMED_WORDS):
                continue
            yield from _numbers(item, f"{path}/{key}")
    elif isinstance(value, list):
        for i, item in enumerate(value):
            yield from _numbers(item, f"{path}/{i}")
    else:
        yield path, SECONDS.sub("(time) s", value) if isinstance(value, str) else value


def differences(first: dict, second: dict) -> list[str]:
    """The paths of the leaves of two reports' cases that differ (the times aside)."""
    a = dict(_numbers(first["cases"]))
    b = dict(_numbers(second["cases"]))
    return sorted(p for p in a.keys() | b.keys() if a.get(p, "missing") != b.get(p, "missing"))


def tasks(content: dict) -> list[tuple[str, float]]:
    """The report's tasks and their CPU (s): a case, or a part of a case in parts."""
    found = []
    for name, case in content["cases"].items():
        if "parts" in case:
            found += [(f"{name}: {key}", part["cpu_s"]) for key, part in case["parts"].items()]
        else:
            found.append((name, case.get("case_cpu_s") or 0.0))
    return found


def largest_task(content: dict) -> tuple[str, float]:
    """The task of the report with the most CPU (s): a case, or a part of a case in parts."""
    return max(tasks(content), key=lambda task: task[1])


def packed(content: dict, jobs: int) -> float:
    """The report's tasks' CPU times packed on ``jobs`` free cores, the longest first, each
    to the core free first (s): its wall on a quiet machine, the overheads and the combining
    steps aside; a figure the machine's load does not move."""
    ends = [0.0] * jobs
    for _, cpu in sorted(tasks(content), key=lambda task: -task[1]):
        ends[ends.index(min(ends))] += cpu
    return max(ends)


def walls(codes: list[str], out: Path, rounds: int, jobs: int, resolution: str) -> None:
    """``python -m validation`` with the code of each folder of ``codes``, alternating,
    ``rounds`` times; a line per run (see the module's docstring)."""
    first = None
    env = {**os.environ, "NUMBA_NUM_THREADS": os.environ.get("NUMBA_NUM_THREADS", "1")}
    print(f"python -m validation --resolution {resolution} --jobs {jobs}, one numba thread")
    for round_ in range(rounds):
        for i, code in enumerate(codes):
            folder = out / str(i)
            ordered = "last report" if (folder / "results.json").exists() else "table"
            load, started, cpu = os.getloadavg(), time.perf_counter(), _children_cpu()
            run = subprocess.run(
                [sys.executable, "-m", "validation", "--resolution", resolution,
                 "--jobs", str(jobs), "--out", str(folder)],
                cwd=code, env=env, capture_output=True, text=True,
            )  # fmt: skip
            wall, used = time.perf_counter() - started, _children_cpu() - cpu
            (out / f"{i}-round{round_ + 1}.log").write_text(run.stdout + run.stderr)
            content = json.loads((folder / "results.json").read_text())
            cases = content["cases"].values()
            case_cpu = sum(case.get("case_cpu_s") or 0.0 for case in cases)
            checks = [c for case in cases for c in case["checks"]]
            name, largest = largest_task(content)
            first = content if first is None else first
            moved = differences(first, content)
            print(
                f"round {round_ + 1}, code {code} (tasks ordered by the {ordered}): "
                f"wall {wall:.1f} s, every process {used:.1f} s CPU, cases {case_cpu:.1f} s CPU, "
                f"/ {jobs} = {case_cpu / jobs:.1f} s, wall - that {wall - case_cpu / jobs:.1f} s; "
                f"largest task {name} {largest:.1f} s; the tasks packed on {jobs} free "
                f"cores {packed(content, jobs):.1f} s; "
                f"{sum(c['passed'] for c in checks)}/{len(checks)} checks, exit {run.returncode}; "
                f"{len(moved)} numbers differ from the first run{': ' if moved else ''}"
                f"{', '.join(moved[:5])}; load {load[0]:.1f} -> {os.getloadavg()[0]:.1f}",
                flush=True,
            )


_WORKER = """
import time, multiprocessing, concurrent.futures as cf
import validation.report as report
started = time.perf_counter()
with cf.ProcessPoolExecutor(1, mp_context=multiprocessing.get_context("spawn")) as pool:
    pool.submit(report.expected_cost, "bai-5.1", "default").result()
    wall = time.perf_counter() - started
    cpu = pool.submit(time.process_time).result()
print(f"{wall:.2f} {cpu:.2f}")
"""

_IMPORTS = """
import time
started, cpu = time.perf_counter(), time.process_time()
import validation.__main__
print(f"{time.perf_counter() - started:.2f} {time.process_time() - cpu:.2f}")
"""

_PART = """
import sys, time
from validation.cases import CASES
case = CASES["hemisphere-plies"]
for _ in range(2):
    run = case.parts("default")[sys.argv[1]]
    cpu = time.process_time()
    run()
    print(f"{time.process_time() - cpu:.2f}", end=" ")
"""


def overheads(results: Path | None, part: str, repeat: int) -> None:
    """The report's fixed costs, each the least of ``repeat`` fresh processes (see the
    module's docstring)."""

    def least(script: str, *args: str) -> list[float]:
        runs = [
            [float(v) for v in subprocess.run(
                [sys.executable, "-c", script, *args], cwd=ROOT, capture_output=True,
                text=True, check=True, env={**os.environ, "NUMBA_NUM_THREADS": "1"},
            ).stdout.split()]
            for _ in range(repeat)
        ]  # fmt: skip
        return [min(column) for column in zip(*runs)]

    print(f"load {os.getloadavg()[0]:.1f}; the least of {repeat} fresh processes")
    wall, cpu = least(_IMPORTS)
    print(f"the report process's imports (validation.__main__): {wall:.2f} s wall, {cpu:.2f} CPU")
    wall, cpu = least(_WORKER)
    print(f"a spawned worker, started and its imports done: {wall:.2f} s wall, {cpu:.2f} s CPU")
    first, second = least(_PART, part)
    print(
        f"hemisphere-plies' part {part!r}: first run {first:.2f} s CPU, second in the same "
        f"process {second:.2f} s: {first - second:.2f} s a worker spends once on it"
    )
    if results is not None:
        from validation.report import _strict, render_html

        content = json.loads(results.read_text())
        times = []
        for _ in range(repeat):
            cpu = time.process_time()
            text = json.dumps(_strict(content), indent=2, allow_nan=False)
            render_html(content)
            times.append(time.process_time() - cpu)
        print(f"results.json and index.html made again: {min(times):.2f} s CPU ({len(text)} B)")
    print(f"load {os.getloadavg()[0]:.1f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    commands = parser.add_subparsers(dest="command", required=True)
    wall = commands.add_parser("walls")
    wall.add_argument("--code", action="append", required=True, help="a code folder (repeat)")
    wall.add_argument("--out", type=Path, required=True)
    wall.add_argument("--rounds", type=int, default=1)
    wall.add_argument("--jobs", type=int, default=2)
    wall.add_argument("--resolution", default="default")
    over = commands.add_parser("overheads")
    over.add_argument("--results", type=Path, default=None)
    over.add_argument("--part", default="8 cells 0/45 fibrous 20 N")
    over.add_argument("--repeat", type=int, default=2)
    args = parser.parse_args()
    if args.command == "walls":
        walls(args.code, args.out, args.rounds, args.jobs, args.resolution)
    else:
        overheads(args.results, args.part, args.repeat)


if __name__ == "__main__":
    main()
