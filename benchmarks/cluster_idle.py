"""The CPU an idle local Dask cluster takes (fibreshell.cluster.dask_client's LocalCluster: 2
worker processes of one thread, no dashboard): Dask's default polling beside
fibreshell.cluster.IDLE_CONFIG, and each of its four settings alone, one cluster at a time in
this process, the CPU (user + system) of this process and its children over ``--seconds`` of
idling after one task. The machine's load is printed: other jobs on the cores do not add to
these processes' CPU, but they stretch it a little.

    python benchmarks/cluster_idle.py --seconds 30

Measured (2 cores, load 4.8 with other jobs, 30 s each), s of CPU a minute: Dask's defaults
5.20, 4.54, 5.26 (three clusters); the event loop's tick at 500 ms alone 3.66, the memory
monitor at 1 s alone 4.16, work stealing at 1 s alone 5.42, no profiler alone 4.04; all four
(IDLE_CONFIG) 0.98, 1.04. No one setting is the cost: each poll is about 1 s a minute, and
only all four together leave the cluster near silent (about 1.7 % of a core). Again (load
7.2 -> 5.1, 20 s each): defaults 5.10, IDLE_CONFIG 1.08, tick alone 4.26, memory monitor
alone 5.16, stealing alone 4.71, no profiler alone 3.87.
"""

from __future__ import annotations

import argparse
import logging
import os
import sys
import time
from pathlib import Path

import dask
import psutil

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this tree's packages

from fibreshell.cluster import IDLE_CONFIG

SETTINGS: dict[str, dict] = {
    "defaults": {},
    "IDLE_CONFIG": IDLE_CONFIG,
    **{f"{key} alone": {key: value} for key, value in IDLE_CONFIG.items()},
}


def cpu_seconds(processes: list[psutil.Process]) -> float:
    total = 0.0
    for process in processes:
        try:
            times = process.cpu_times()
        except psutil.Error:  # a process gone since it was listed
            continue
        total += times.user + times.system
    return total


def idle_cpu_per_minute(config: dict, seconds: float) -> float:
    from distributed import Client, LocalCluster

    with dask.config.set(config):
        cluster = LocalCluster(
            n_workers=2,
            threads_per_worker=1,
            processes=True,
            dashboard_address=None,
            scheduler_kwargs={"dashboard_address": "127.0.0.1:0"},
            silence_logs=logging.ERROR,
        )
    with cluster, Client(cluster) as client:
        client.submit(abs, -1).result()
        time.sleep(3.0)  # the workers' start-up settled
        here = psutil.Process()
        processes = [here, *here.children(recursive=True)]
        start, wall = cpu_seconds(processes), time.perf_counter()
        time.sleep(seconds)
        used, wall = cpu_seconds(processes) - start, time.perf_counter() - wall
    return 60.0 * used / wall


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seconds", type=float, default=30.0, help="idle time measured (s)")
    args = parser.parse_args()
    print(f"load {os.getloadavg()[0]:.1f}", flush=True)
    for name, config in SETTINGS.items():
        rate = idle_cpu_per_minute(config, args.seconds)
        print(f"{name:55s} {rate:5.2f} s of CPU a minute", flush=True)
    print(f"load {os.getloadavg()[0]:.1f}", flush=True)


if __name__ == "__main__":
    main()
