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

Measured (one numba thread, warm caches, 2 cores shared with other jobs; see the report of
the change that added this script for the figures and the load): hemisphere-plies at the
default resolution, its four runs 86-87 s of CPU, spent outside them about 4-5 s before
(a model and a compile per gap measure, eight, and each run's history .csv read twice).
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
