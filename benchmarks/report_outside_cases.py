"""What a validation report spends outside its cases, and a case outside its runs, the code
before beside this one.

Runs ``python -m validation --cases NAMES --jobs J --out TMP`` in a fresh process for each
``--code`` folder (a ``git archive`` of the code before, and this tree), alternating, one
numba thread, and prints per report:

- the process's CPU (user + system of it and its workers, ``RUSAGE_CHILDREN``) and wall;
- the sum of the cases' ``case_cpu_s`` (results.json: each case's computation and figures)
  and what the process spent beside them (imports, numba's cache loads outside the cases,
  the workers' start, results.json and index.html);
- per case that records its runs' CPU (parameters ending ``_cpu_time_s``: hemisphere-plies
  records each run's solve), the case's CPU outside its runs (building the models, the
  measures after the runs, the figures);

and whether the two codes' results.json hold the same numbers apart from times (the
parameters' and the outcome's times left out).

Usage::

    git archive main | tar -x -C /tmp/main   # the code before, its numba cache warmed once
    python benchmarks/report_outside_cases.py --code /tmp/main --code . \
        --cases hemisphere-plies --jobs 1

Measured (one numba thread, warm caches, 2 cores shared; main 2536977 from git archive
beside this tree, one report each, back to back): hemisphere-plies at the default
resolution, the case outside its four runs 5.45 -> 5.22 s of CPU (case 59.78 / 58.77 s, runs
54.33 / 53.55, load 1.1-2.8), and 5.65 -> 5.37 in a second pair (load 4.3-6.1), each run's
history .csv read once instead of twice (and the gap probe then kept across runs, since
dropped as below); results.json's numbers the same, the three figures the same pixels. What
the 5.2 s are, timed apart in one process on the fibrous [0/90] run (load 2.7): the gap
measure over the run's 101 frames 0.65 s a run (2.6 s for the four: the node-to-surface
probe's curved facing at each frame, elements/ply_block.py, a measure the report prints),
the model's build and compile 0.7 s for the first run (numba's cache loads included), the
figures about 1.1 s (benchmarks/report_overhead.py), a history .csv read 0.04 s, the gap
probe's model 0.003-0.01 s once its kernels are loaded (not worth keeping across runs).

The whole default report, the code before: --jobs 1 (load 4.5 -> 1.6), the process 157.7 s of
CPU and 184.4 s of wall, the 23 cases 156.1 s of CPU and 180.2 s of wall: 1.7 s of CPU and
4.2 s of wall outside the cases (the interpreter, the imports, results.json and index.html);
--jobs 2 (load 3.4 -> 5.3, other jobs on both cores), the process and its workers 177.6 s of
CPU, the cases 172.6: 5.0 s of CPU outside them (three processes' imports, about 1.5 s
each), 338.8 s of wall against 330.3 for half the cases' summed walls.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

TIMES = ("_cpu_time_s", "_wall_time_s")


def _children_cpu() -> float:
    """User + system CPU (s) of every waited-for descendant of this process so far."""
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def _load() -> str:
    """The machine's load averages (1, 5, 15 min)."""
    return " ".join(f"{x:.2f}" for x in os.getloadavg())


def report(code: Path, cases: str, jobs: int, resolution: str) -> dict[str, Any]:
    """One report of ``cases`` run with the code in ``code``: its results.json, the process's
    CPU and wall (s) and the load before and after."""
    with tempfile.TemporaryDirectory() as out:
        env = {**os.environ, "NUMBA_NUM_THREADS": "1"}
        before, started, load = _children_cpu(), time.perf_counter(), _load()
        command = [sys.executable, "-m", "validation", "--cases", cases, "--jobs", str(jobs)]
        command += ["--resolution", resolution, "--out", out]
        subprocess.run(command, cwd=code, env=env, check=False, capture_output=True)
        wall = time.perf_counter() - started
        cpu = _children_cpu() - before
        results = json.loads((Path(out) / "results.json").read_text())
    return {"results": results, "cpu": cpu, "wall": wall, "load": (load, _load())}


def _cases(results: dict[str, Any]) -> dict[str, dict[str, Any]]:
    """results.json's cases by name."""
    cases = results["cases"]
    return cases if isinstance(cases, dict) else {c["name"]: c for c in cases}


def _numbers(case: dict[str, Any]) -> Any:
    """A case's record without its times: what two codes must agree on."""
    parameters = {k: v for k, v in case.get("parameters", {}).items() if not k.endswith(TIMES)}
    checks = [(c.get("name"), c.get("value"), c.get("passed")) for c in case.get("checks", [])]
    return parameters, checks


def main() -> None:
    """Run the reports and print the table."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--code", action="append", required=True, type=Path)
    parser.add_argument("--cases", default="hemisphere-plies")
    parser.add_argument("--jobs", type=int, default=1)
    parser.add_argument("--resolution", default="default")
    parser.add_argument("--rounds", type=int, default=1)
    args = parser.parse_args()
    seen: dict[Path, list[dict[str, Any]]] = {code: [] for code in args.code}
    for _ in range(args.rounds):
        for code in args.code:
            seen[code].append(report(code.resolve(), args.cases, args.jobs, args.resolution))
    for code, runs in seen.items():
        for run in runs:
            cases = _cases(run["results"])
            case_cpu = sum(c["case_cpu_s"] for c in cases.values())
            print(
                f"{code}: process {run['cpu']:.2f} s CPU, {run['wall']:.2f} s wall; cases "
                f"{case_cpu:.2f} s CPU; outside the cases {run['cpu'] - case_cpu:.2f} s CPU "
                f"(--jobs {args.jobs}; load {run['load'][0]} -> {run['load'][1]})"
            )
            for name, case in cases.items():
                runs_cpu = [
                    v for k, v in case.get("parameters", {}).items() if k.endswith(TIMES[0])
                ]
                if runs_cpu:
                    print(
                        f"  {name}: case {case['case_cpu_s']:.2f} s CPU, its {len(runs_cpu)} "
                        f"runs {sum(runs_cpu):.2f}, outside them "
                        f"{case['case_cpu_s'] - sum(runs_cpu):.2f}"
                    )
    first, *others = (_cases(runs[0]["results"]) for runs in seen.values())
    for other in others:
        same = all(_numbers(first[n]) == _numbers(other[n]) for n in first)
        print(f"the same numbers apart from times: {same}")


if __name__ == "__main__":
    main()
