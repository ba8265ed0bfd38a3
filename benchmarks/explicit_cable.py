"""Cost of one explicit time step per cable element: solvers.CentralDifference on cable nets.

What it measures: the wall time of ``CentralDifference.solve`` (compilation excluded) on a
square cable net of ``elements.Cable`` - an n x n grid of cells whose 2 n (n + 1) edges are
cables, pinned on its boundary and loaded by gravity from rest - for nets of about 1k, 10k and
100k elements, over a known number of steps (the time step is fixed to 0.9 x the stable step
of the compiled model and the duration is steps x dt). It reports elements, nodes, steps, wall
time and microseconds per element-step. Frames are written only at the start and the end so
that output costs stay out of the figure; the per-step energy bookkeeping of the solver is in.

Run from the project root:

    python benchmarks/explicit_cable.py                       # 1k, 10k, 100k elements
    python benchmarks/explicit_cable.py --sizes 1000,50000 --steps 100

Total run time with the defaults is well under two minutes on a laptop.
"""

from __future__ import annotations

import argparse
import math
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install

from elements import Cable  # noqa: E402
from femcore import Mesh, Model  # noqa: E402
from solvers import CentralDifference  # noqa: E402

SPACING = 10.0  # mm, cell size of the net
EA = 1.0e5  # N
MU = 1.0e-9  # t/mm (about 1 g/m)
GRAVITY = (0.0, 0.0, -9810.0)  # mm/s^2
SAFETY = 0.9


def cable_net(cells_per_side: int) -> Mesh:
    """Square net of (n+1)^2 nodes in z = 0 and 2 n (n+1) cable lines along x and y."""
    n = cells_per_side
    ids = np.arange((n + 1) ** 2).reshape(n + 1, n + 1)  # ids[j, i]: node at (i, j)
    x, y = np.meshgrid(np.arange(n + 1) * SPACING, np.arange(n + 1) * SPACING)
    points = np.column_stack([x.ravel(), y.ravel(), np.zeros(x.size)])
    along_x = np.column_stack([ids[:, :-1].ravel(), ids[:, 1:].ravel()])
    along_y = np.column_stack([ids[:-1, :].ravel(), ids[1:, :].ravel()])
    return Mesh(points, lines=np.vstack([along_x, along_y]))


def cells_for(elements: int) -> int:
    """Cells per side n whose net has about ``elements`` = 2 n (n + 1) cables."""
    return max(1, round((-1.0 + math.sqrt(1.0 + 2.0 * elements)) / 2.0))


def run(target_elements: int, steps: int, kernel: str = "compiled") -> dict:
    mesh = cable_net(cells_for(target_elements))
    model = Model(mesh)
    model.add(Cable(EA, MU, kernel=kernel))
    edge = SPACING * cells_for(target_elements)
    model.fix(mesh.nodes(lambda x, y, z: (x <= 0) | (y <= 0) | (x >= edge) | (y >= edge)))
    model.gravity(GRAVITY)

    started = time.perf_counter()
    compiled = model.compile()
    compile_time = time.perf_counter() - started
    dt = SAFETY * compiled.stable_dt(compiled.initial_state())
    duration = steps * dt
    solver = CentralDifference(duration=duration, dt=dt, output_interval=duration, progress=False)

    started = time.perf_counter()
    result = solver.solve(compiled)
    wall = time.perf_counter() - started
    elements = mesh.n_lines
    return {
        "elements": elements,
        "nodes": mesh.n_nodes,
        "steps": result.steps,
        "compile_s": compile_time,
        "wall_s": wall,
        "us_per_element_step": 1e6 * wall / (elements * result.steps),
    }


def cpu_name() -> str:
    """Processor model (from /proc/cpuinfo on Linux, else what platform knows)."""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--sizes",
        default="1000,10000,100000",
        help="comma-separated target element counts (default 1000,10000,100000)",
    )
    parser.add_argument("--steps", type=int, default=200, help="time steps per run (default 200)")
    args = parser.parse_args(argv)
    try:
        sizes = [int(s) for s in args.sizes.split(",") if s.strip()]
    except ValueError:
        parser.error(f"--sizes must be comma-separated integers, got {args.sizes!r}")
    if not sizes or min(sizes) < 4 or args.steps < 1:
        parser.error("--sizes needs element counts >= 4 and --steps a positive integer")

    print("explicit_cable: solvers.CentralDifference on square cable nets (elements.Cable),")
    print(f"  pinned edges, gravity from rest, dt = {SAFETY} x stable step (fixed)")
    print(f"machine: {platform.platform()}; {cpu_name()}, {os.cpu_count()} logical CPUs")
    print(f"python {platform.python_version()}, numpy {np.__version__}")
    header = (
        f"{'elements':>9} {'nodes':>8} {'kernel':>9} {'steps':>6} {'compile s':>10} "
        f"{'wall s':>8} {'us/elem-step':>13}"
    )
    print(header)
    print("-" * len(header))
    for size, kernel in [(size, kernel) for size in sizes for kernel in ("numpy", "compiled")]:
        row = run(size, args.steps, kernel)
        print(
            f"{row['elements']:>9d} {row['nodes']:>8d} {kernel:>9} {row['steps']:>6d} "
            f"{row['compile_s']:>10.3f} {row['wall_s']:>8.3f} {row['us_per_element_step']:>13.3f}",
            flush=True,
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
