"""BLAS threads in a static solve: the README's G1151 strip (8 x 2 cells, Static, 3
increments; its stability check takes a dense eigh of its 120 free unknowns per increment)
solved with the solver's BLAS on OpenBLAS's default threads and on one thread
(solvers/blas_threads.py), in turns, best of ``--repeats``, with ``--busy`` processes spinning
on the cores meanwhile; beside it, the dense eigh of a 200 x 200 symmetric matrix alone, both
ways.

Printed: wall and CPU seconds each way, their ratio, OpenBLAS's default thread count, and
/proc/loadavg (what else the machine runs counts: this is a shared machine).

Run from the project root:

    python benchmarks/blas_threads.py
    python benchmarks/blas_threads.py --busy 0,1 --repeats 5
"""

from __future__ import annotations

import argparse
import multiprocessing
import sys
import time
from pathlib import Path

import numpy as np
from threadpoolctl import ThreadpoolController, threadpool_info

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from elements import FibrousShell  # noqa: E402
from femcore import Mesh, Model  # noqa: E402
from materials import presets  # noqa: E402
from solvers import Static  # noqa: E402


def spin(stop) -> None:  # a busy competitor
    while not stop.is_set():
        pass


def strip_model() -> Model:
    mesh = Mesh.rectangle(200.0, 60.0, nx=8, ny=2)
    model = Model(mesh)
    model.add(FibrousShell(presets.g1151_laminate(), clamped="left"))
    model.fix("left")
    model.gravity((0.0, 0.0, -9810.0))
    return model


def timed(function) -> tuple[float, float]:
    wall, cpu = time.perf_counter(), time.process_time()
    function()
    return time.perf_counter() - wall, time.process_time() - cpu


def load() -> str:
    try:
        return Path("/proc/loadavg").read_text().split(" ")[0]
    except OSError:  # pragma: no cover - not Linux
        return "?"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--busy", default="0,1", help="busy processes, comma-separated counts")
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    blas = [lib for lib in threadpool_info() if lib["user_api"] == "blas"]
    print("BLAS:", ", ".join(f"{lib['internal_api']} {lib['num_threads']} threads" for lib in blas))
    model = strip_model().compile()
    solver = Static(increments=3, progress=False)
    default_threads = type(solver).solve.__wrapped__.__wrapped__  # past keeps_writes, one thread
    matrix = np.random.default_rng(0).standard_normal((200, 200))
    matrix = matrix + matrix.T
    solver.solve(model)  # compile the kernels first

    def one_thread_eigh():
        with ThreadpoolController().limit(limits=1, user_api="blas"):
            np.linalg.eigh(matrix)

    runs = {
        "static, default BLAS threads": lambda: default_threads(solver, model),
        "static, one BLAS thread": lambda: solver.solve(model),
        "eigh 200, default BLAS threads": lambda: np.linalg.eigh(matrix),
        "eigh 200, one BLAS thread": one_thread_eigh,
    }
    for busy in (int(b) for b in args.busy.split(",")):
        stop = multiprocessing.Event()
        workers = [multiprocessing.Process(target=spin, args=(stop,)) for _ in range(busy)]
        for worker in workers:
            worker.start()
        try:
            best = {name: (np.inf, np.inf) for name in runs}
            for _ in range(args.repeats):
                for name, run in runs.items():
                    wall, cpu = timed(run)
                    best[name] = (min(best[name][0], wall), min(best[name][1], cpu))
        finally:
            stop.set()
            for worker in workers:
                worker.join()
        print(f"\n{busy} busy process(es), load average {load()}")
        for name, (wall, cpu) in best.items():
            print(f"  {name:32s} wall {wall * 1e3:9.1f} ms   CPU {cpu * 1e3:9.1f} ms")
        for what in ("static", "eigh 200"):
            ratio = best[f"{what}, default BLAS threads"][0] / best[f"{what}, one BLAS thread"][0]
            print(f"  {what}: default threads / one thread, wall: {ratio:.2f}")


if __name__ == "__main__":
    main()
