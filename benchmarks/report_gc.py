"""The report's cases outside the two-ply hemisphere: what a worker's garbage collector and a
forming run's die lists cost, beside the code before, one numba thread, CPU time.

* ``--gc CASES``: the cases run one after another in a fresh process of this tree
  (``validation.report.run_case``), once with the worker's ``_settled`` (``gc.collect`` then
  ``gc.freeze`` after the imports) and once without, alternating, ``--rounds`` each: the
  cases' CPU and the full collections' count and time (``gc.callbacks``);
* ``--rows``: the die's candidate copies (elements/facet_search.py ``candidate_rows``), the
  compiled pass against numpy's gathers (the code before), on the hemisphere-forming die's
  facets and a list of 8200 candidates (a default run's mean), alternating, best of 7;
* ``--code A --code B --cases CASES``: ``python -m validation --cases CASES --jobs 2`` with
  each tree (``git archive`` of the code before, and this one; ``--cache`` each tree's
  NUMBA_CACHE_DIR, warmed before), alternating, ``--rounds`` each: the processes' CPU and
  wall, the cases' summed case_cpu_s, each case's, and whether results.json holds the same
  numbers but times.

    python benchmarks/report_gc.py --rows
    python benchmarks/report_gc.py --gc bai-5.1,bai-6.1.1,plies-bai-5.1 --rounds 2
    python benchmarks/report_gc.py --code /tmp/base --cache /tmp/nb_base --code . \\
        --cache /tmp/nb_this --cases bai-5.1,hemisphere-forming --rounds 2

Measured (one numba thread, 2 cores shared with other jobs; the base 7f9c3d5 from git
archive beside this tree, each with its own warm numba cache):

* ``--rows``: 0.450 ms compiled against 1.288 ms numpy (load 5.6), 1.459 against 6.429 (load
  8.7), the same bits; 280 and 518 searches in hemisphere-forming's fibrous and Mindlin runs:
  about 0.24 and 0.43 s of CPU a report at load 5.6.
* ``--gc bai-5.1,bai-6.2.2,plies-deck-of-cards,mindlin-pinched-cylinder,
  heavy-cantilever-nonlinear,cable-catenary,plies-heavy-cantilever`` (one round, load 7-9):
  settled 3 full collections, 0.18 s; as before 4, 0.53 s (the cases' CPU 40.7 and 36.7 s:
  the load's noise is ten times the collector's share). 137k objects frozen.
* ``--code /tmp/base --code . --cases hemisphere-forming --rounds 2`` (load 4.8-6.4): the
  case's CPU 38.7, 37.5 s before, 37.3, 34.1 s after (alternating; best 37.5 -> 34.1 s); the
  processes 45.1, 43.8 -> 41.4, 38.3 s; the same numbers. The 22 cases but hemisphere-plies
  in one report each (--jobs 2, load 7-11; the base's cache cold then): results.json the same
  numbers in every case apart from times.
"""

from __future__ import annotations

import argparse
import gc
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
import timeit
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))  # this tree first, run from anywhere
TIMES = ("_cpu_time_s", "_wall_time_s", "_cpu_s", "_wall_s")


def _load() -> str:
    return " ".join(f"{x:.1f}" for x in os.getloadavg())


def rows() -> None:
    """The candidate copies, compiled against numpy's gathers, on the die's arrays."""
    from elements.facet_search import candidate_rows
    from elements.rigid_surface import RigidSurface
    from validation.cases import hemisphere_forming

    _, built = hemisphere_forming.model(20, "fibrous")
    die = next(i.tool for i in built.interactions if isinstance(i.tool, RigidSurface))
    rng = np.random.default_rng(0)
    facets = np.sort(rng.integers(0, die.n_facets, 8200))
    args = (facets, die.corners, die.normals, die._centroids, die._radius)

    def gathers():
        copies = np.empty((len(facets), 4, 3))
        copies[:, :3] = die.corners[facets]
        copies[:, 3] = die.normals[facets]
        spheres = np.empty((len(facets), 4))
        spheres[:, :3] = die._centroids[facets]
        spheres[:, 3] = die._radius[facets]
        return copies, spheres

    same = all(a.tobytes() == b.tobytes() for a, b in zip(candidate_rows(*args), gathers()))
    best = {"compiled": np.inf, "numpy": np.inf}
    for _ in range(7):
        for name, call in (("compiled", lambda: candidate_rows(*args)), ("numpy", gathers)):
            best[name] = min(best[name], min(timeit.repeat(call, number=20, repeat=3)) / 20)
    print(
        f"candidate copies, {die.n_facets} facets, 8200 candidates: compiled "
        f"{best['compiled'] * 1e3:.3f} ms, numpy {best['numpy'] * 1e3:.3f} ms, the same "
        f"bits: {same} (load {_load()})"
    )


def gc_child(cases: list[str], settle: bool) -> dict[str, Any]:
    """(in a fresh process) the cases one after another, with or without ``_settled``."""
    from validation.report import _settled, run_case

    if settle:
        _settled()
    collections = {"count": 0, "time": 0.0}
    started = [0.0]

    def watch(phase: str, info: dict) -> None:
        if info["generation"] != 2:
            return
        if phase == "start":
            started[0] = time.process_time()
        else:
            collections["count"] += 1
            collections["time"] += time.process_time() - started[0]

    gc.callbacks.append(watch)
    cpu = 0.0
    with tempfile.TemporaryDirectory() as out:
        for name in cases:
            cpu += run_case(name, "default", Path(out)).case_cpu_s or 0.0
    return {"cpu": cpu, **collections}


def gc_runs(cases: str, rounds: int) -> None:
    for _ in range(rounds):
        for settle in (True, False):
            load = _load()
            command = [sys.executable, __file__, "--gc-child", cases]
            command += ["--settle"] if settle else []
            env = {**os.environ, "NUMBA_NUM_THREADS": "1", "FIBRESHELL_PROGRESS": "0"}
            done = subprocess.run(command, cwd=ROOT, env=env, capture_output=True, text=True)
            found = json.loads(done.stdout.strip().splitlines()[-1])
            print(
                f"{'settled' if settle else 'as before'}: cases {found['cpu']:.2f} s CPU, "
                f"{found['count']} full collections, {found['time']:.2f} s (load {load} -> "
                f"{_load()})",
                flush=True,
            )


def _children_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def _numbers(case: dict[str, Any]) -> Any:
    """A case's record without its times: what two codes must agree on."""
    parameters = {k: v for k, v in case.get("parameters", {}).items() if not k.endswith(TIMES)}
    # a run's wall, CPU and load: hemisphere-forming's "...: runtime", the plies' "... wall
    # time (s)", the sensitivity's "run as" (its sweep's elapsed time)
    for key in [k for k in parameters if "runtime" in k or "wall time" in k or k == "run as"]:
        parameters.pop(key)
    checks = [(c.get("name"), c.get("value"), c.get("passed")) for c in case.get("checks", [])]
    return parameters, checks, case.get("key_numbers")


def reports(codes: list[Path], caches: list[str], cases: str, rounds: int) -> None:
    seen: dict[Path, list[dict[str, Any]]] = {code: [] for code in codes}
    for _ in range(rounds):
        for code, cache in zip(codes, caches):
            with tempfile.TemporaryDirectory() as out:
                env = {**os.environ, "NUMBA_NUM_THREADS": "1", "NUMBA_CACHE_DIR": cache}
                before, started, load = _children_cpu(), time.perf_counter(), _load()
                command = [sys.executable, "-m", "validation", "--cases", cases]
                command += ["--jobs", "2", "--out", out]
                subprocess.run(command, cwd=code, env=env, check=False, capture_output=True)
                wall, cpu = time.perf_counter() - started, _children_cpu() - before
                results = json.loads((Path(out) / "results.json").read_text())["cases"]
            case_cpu = sum(c["case_cpu_s"] for c in results.values())
            print(
                f"{code}: process {cpu:.1f} s CPU, {wall:.1f} s wall; cases {case_cpu:.1f} s "
                f"CPU (load {load} -> {_load()})",
                flush=True,
            )
            print("  " + ", ".join(f"{n} {c['case_cpu_s']:.1f}" for n, c in results.items()))
            seen[code].append(results)
    first, *others = (runs[0] for runs in seen.values())
    for other in others:
        differ = [n for n in first if _numbers(first[n]) != _numbers(other[n])]
        print(f"cases whose numbers differ apart from times: {differ or 'none'}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rows", action="store_true")
    parser.add_argument("--gc", default=None, help="comma-separated case names")
    parser.add_argument("--gc-child", default=None, help=argparse.SUPPRESS)
    parser.add_argument("--settle", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--code", action="append", type=Path, default=[])
    parser.add_argument("--cache", action="append", default=[])
    parser.add_argument("--cases", default="hemisphere-forming")
    parser.add_argument("--rounds", type=int, default=1)
    args = parser.parse_args()
    if args.gc_child is not None:
        print(json.dumps(gc_child(args.gc_child.split(","), args.settle)))
        return
    if args.rows:
        rows()
    if args.gc is not None:
        gc_runs(args.gc, args.rounds)
    if args.code:
        if len(args.cache) != len(args.code):
            parser.error("give one --cache (a NUMBA_CACHE_DIR) for each --code")
        reports(args.code, args.cache, args.cases, args.rounds)


if __name__ == "__main__":
    main()
