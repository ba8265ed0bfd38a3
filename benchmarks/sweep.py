"""A 16-variant sweep on Dask: 1 worker process against 2, and the cost of a task.

The case is the report's sensitivity base, the paper-stack corner test of bai-6.1.1 (paper
stack, clamp, its gripped corner patch lifted 40 mm, gravity, Static along the arc length) at
--cells cells, its bending stiffness swept over 16 values from 25 to 100 N mm. Measured in one
run, side by side:

1. the reference pass: the 16 variants one after another in this process (the same task
   function, ``fibreshell.sweep.run_variant``, called directly: no Dask);
2. the sweep on a LocalCluster of 1 worker process (numba threads: every core);
3. the sweep on a LocalCluster of 2 worker processes (one numba thread each);
4. the overhead of Dask alone: cluster start and stop, and the round trip of a task that does
   nothing (200 of them on 2 workers).

The reference pass runs before and after the sweeps (the machine is shared; their mean is
used). The per-variant overhead of a sweep is (sweep with 1 worker - reference pass) / 16:
cluster start and stop, shipping the case tables, checking every variant in the driver.

Dask's nannies start workers with MALLOC_TRIM_THRESHOLD_=65536, which made every run 25-40 %
slower than in the driver (2.4-2.9 s against 1.9-2.4 s a run here, measured side by side);
fibreshell.cluster starts its local workers without it.

Run: python benchmarks/sweep.py [--cells 10] [--variants 16]
"""

from __future__ import annotations

import argparse
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this tree's packages

from fibreshell.cluster import dask_client, map_tasks
from fibreshell.sweep import run_variant, sweep
from validation.cases.bai_sensitivity import base_case


def nothing(value: int) -> int:
    return value


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cells", type=int, default=10)
    parser.add_argument("--variants", type=int, default=16)
    args = parser.parse_args()
    os.environ["FIBRESHELL_PROGRESS"] = "0"
    case = base_case(args.cells)
    values = [float(v) for v in np.geomspace(25.0, 100.0, args.variants)]
    vary = {"part.0.material.bending": values}
    print(f"{platform.platform()}, {os.cpu_count()} cores, Python {platform.python_version()}")
    print(f"bai-6.1.1 corner test, {args.cells} cells, {args.variants} variants of B")

    run_variant(case, "warm-up", {"part.0.material.bending": 50.0}, None)  # numba caches

    def reference_pass() -> tuple[float, list]:
        started = time.perf_counter()
        runs = [run_variant(case, "serial", {"part.0.material.bending": v}, None) for v in values]
        return time.perf_counter() - started, runs

    reference, serial = reference_pass()
    print(f"reference pass, one after another here: {reference:7.2f} s")

    elapsed = {}
    for workers in (1, 2):
        started = time.perf_counter()
        table = sweep(case, vary, workers=workers, progress=False, name="bench")
        elapsed[workers] = time.perf_counter() - started
        key = "path_side_1_director_angle_max_deg"
        same = np.allclose(table.column(key), [ref[0][key] for ref in serial], rtol=1e-9)
        print(
            f"sweep, {workers} worker(s):                  {elapsed[workers]:7.2f} s "
            f"({len(table.failed)} failed; the reference's director angles: {same})"
        )
    again, _ = reference_pass()  # the machine is shared: the reference before and after
    print(f"reference pass again:                      {again:7.2f} s")
    reference = 0.5 * (reference + again)
    print(f"speed-up 2 workers / 1 worker:             {elapsed[1] / elapsed[2]:7.2f}")
    print(f"speed-up 2 workers / mean reference pass:  {reference / elapsed[2]:7.2f}")
    print(f"overhead per variant (1 worker - mean ref) / n: "
          f"{(elapsed[1] - reference) / args.variants:7.3f} s")  # fmt: skip

    started = time.perf_counter()
    with dask_client(workers=2) as (client, _):
        opened = time.perf_counter() - started
        map_tasks(client, nothing, [(i,) for i in range(20)], "warm", progress=False)
        started_tasks = time.perf_counter()
        map_tasks(client, nothing, [(i,) for i in range(200)], "nothing", progress=False)
        per_task = (time.perf_counter() - started_tasks) / 200
    total = time.perf_counter() - started
    print(f"LocalCluster of 2 workers: start {opened:.2f} s, start + stop {total:.2f} s")
    print(f"round trip of an empty task (200 on 2 workers): {1e3 * per_task:.2f} ms")


if __name__ == "__main__":
    main()
