"""Speed of the fibrous shell: explicit steps per element, and a dynamic-relaxation solve.

1. ``CentralDifference`` on a square sheet of ``FibrousShell`` (G986 stack of Bai Table 1)
   with about 1k, 10k and 100k triangles, pinned on its boundary and loaded by gravity from
   rest, over a fixed number of steps at 0.9 x the stable step: microseconds per
   element-step (compilation excluded; frames only at the start and the end).
2. ``DynamicRelaxation`` of a 40 x 10-cell cantilever strip (200 x 50 mm, G1151 laminate of
   Bai Table 2, clamped-edge option) under its own weight: wall time and iterations.

Run from the project root:

    python benchmarks/fibrous_shell.py
    python benchmarks/fibrous_shell.py --sizes 1000,10000 --steps 50
"""

from __future__ import annotations

import argparse
import math
import platform
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install

from elements import FibrousShell  # noqa: E402
from femcore import Mesh, Model  # noqa: E402
from materials import presets  # noqa: E402
from solvers import CentralDifference, DynamicRelaxation  # noqa: E402

GRAVITY = (0.0, 0.0, -9810.0)  # mm/s^2


def explicit(triangles: int, steps: int) -> dict:
    n = max(2, round(math.sqrt(triangles / 2)))
    mesh = Mesh.rectangle(5.0 * n, 5.0 * n, nx=n, ny=n)
    model = Model(mesh)
    model.add(FibrousShell(presets.g986_stack()))
    for edge in ("left", "right", "bottom", "top"):
        model.fix(edge, ["ux", "uy", "uz"])
    model.gravity(GRAVITY)
    compiled = model.compile()
    dt = 0.9 * compiled.stable_dt(compiled.initial_state())
    solver = CentralDifference(duration=steps * dt, dt=dt, output_interval=steps * dt)
    started = time.perf_counter()
    result = solver.solve(compiled)
    wall = time.perf_counter() - started
    elements = len(mesh.triangles)
    return {
        "elements": elements,
        "nodes": mesh.n_nodes,
        "steps": result.steps,
        "wall_s": wall,
        "us_per_element_step": 1e6 * wall / (elements * result.steps),
    }


def relaxation() -> dict:
    mesh = Mesh.rectangle(200.0, 50.0, nx=40, ny=10)
    model = Model(mesh)
    model.add(FibrousShell(presets.g1151_laminate(), clamped="left"))
    model.fix("left")
    model.gravity(GRAVITY)
    compiled = model.compile()
    started = time.perf_counter()
    result = DynamicRelaxation(max_iterations=1_000_000).solve(compiled)
    wall = time.perf_counter() - started
    tip = mesh.nodes("right")
    return {
        "elements": len(mesh.triangles),
        "iterations": result.steps,
        "wall_s": wall,
        "tip_deflection_mm": float(-result.displacements[tip, 2].mean()),
    }


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="1000,10000,100000")
    parser.add_argument("--steps", type=int, default=100)
    parser.add_argument("--skip-relaxation", action="store_true")
    args = parser.parse_args(argv)
    print(f"python {platform.python_version()} on {platform.machine()} ({platform.system()})")
    print("FibrousShell, CentralDifference:")
    print(f"{'elements':>9} {'nodes':>8} {'steps':>6} {'wall s':>8} {'us/elem-step':>13}")
    for size in (int(s) for s in args.sizes.split(",")):
        row = explicit(size, args.steps)
        print(
            f"{row['elements']:9d} {row['nodes']:8d} {row['steps']:6d} {row['wall_s']:8.2f} "
            f"{row['us_per_element_step']:13.3f}"
        )
    if not args.skip_relaxation:
        row = relaxation()
        print(
            f"DynamicRelaxation, 40 x 10-cell strip ({row['elements']} triangles, G1151, "
            f"self-weight): {row['wall_s']:.1f} s, {row['iterations']} iterations, tip "
            f"deflection {row['tip_deflection_mm']:.2f} mm"
        )


if __name__ == "__main__":
    main()
