"""Speed of the Mindlin shell: explicit steps per element, and a nonlinear static solve.

1. ``CentralDifference`` on a square plate of ``MindlinShell`` (E = 70 GPa, h = 1 mm) with
   about 1k, 10k and 100k triangles, pinned on its boundary and loaded by gravity from rest,
   over a fixed number of steps at 0.9 x the stable step: microseconds per element-step.
2. ``Static`` on a cantilever strip of 2560 triangles (200 x 20 mm, h = 1 mm, 80 x 16 cells)
   rolled to a quarter circle by an end moment: wall time, Newton iterations, tangent colours.
3. The nonlinear cantilever of the elastica test (100 x 5 x 1 mm, 20 x 1 cells, P L^2/EI = 3,
   5 increments): ``DynamicRelaxation`` against ``Static``, wall time and iterations.

Run from the project root:

    python benchmarks/mindlin_shell.py
    python benchmarks/mindlin_shell.py --sizes 1000,10000 --steps 50 --skip-static
"""

from __future__ import annotations

import argparse
import math
import platform
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install

from shell_sheet import print_explicit_table  # noqa: E402

from elements import MindlinShell  # noqa: E402
from femcore import Mesh, Model  # noqa: E402
from materials import ElasticShell  # noqa: E402
from solvers import Static  # noqa: E402

ALUMINIUM = dict(E=70e3, nu=0.3, thickness=1.0, density=2.7e-9)  # MPa, mm, t/mm^3


def roll_up() -> dict:
    length, width = 200.0, 20.0
    mesh = Mesh.rectangle(length, width, nx=80, ny=16)
    model = Model(mesh)
    material = ElasticShell(**ALUMINIUM)
    model.add(MindlinShell(material))
    model.fix("left")
    bending = material.plane_stress[0, 0] * (1 - 0.3**2) * width / 12  # E b h^3 / 12, h = 1
    moment = 0.25 * 2 * math.pi * bending / length
    tip = mesh.nodes("right")
    model.moment(tip, (0.0, -moment / len(tip), 0.0))
    started = time.perf_counter()
    result = Static(increments=4).solve(model)
    wall = time.perf_counter() - started
    return {
        "elements": len(mesh.triangles),
        "wall_s": wall,
        "iterations": result.info["iterations_per_increment"],
        "colours": result.info["tangent_colours"],
    }


def elastica_cantilever() -> list[dict]:
    from solvers import DynamicRelaxation

    length, width, thickness, young = 100.0, 5.0, 1.0, 1e5
    rows = []
    for solver in (DynamicRelaxation(increments=5, max_iterations=2_000_000), Static(increments=5)):
        mesh = Mesh.rectangle(length, width, nx=20, ny=1)
        model = Model(mesh)
        model.add(MindlinShell(ElasticShell(young, 0.0, thickness, 1e-9)))
        model.fix("left")
        load = 3.0 * young * width * thickness**3 / 12 / length**2
        tip = mesh.nodes("right")
        model.force(tip, (0.0, 0.0, -load / len(tip)), amplitude="linear")
        started = time.perf_counter()
        result = solver.solve(model)
        rows.append(
            {
                "solver": type(solver).__name__,
                "wall_s": time.perf_counter() - started,
                "iterations": result.steps,
                "tip_deflection": float(-result.displacements[tip, 2].mean()),
            }
        )
    return rows


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="1000,10000,100000")
    parser.add_argument("--steps", type=int, default=100)
    parser.add_argument("--skip-static", action="store_true")
    args = parser.parse_args(argv)
    print(f"python {platform.python_version()} on {platform.machine()} ({platform.system()})")
    sizes = [int(size) for size in args.sizes.split(",")]
    print_explicit_table(
        "MindlinShell, CentralDifference:",
        lambda: MindlinShell(ElasticShell(**ALUMINIUM)),
        sizes,
        args.steps,
    )
    if not args.skip_static:
        row = roll_up()
        print(
            f"Static, quarter-circle roll-up of a {row['elements']}-triangle strip: "
            f"{row['wall_s']:.1f} s, Newton iterations per increment {row['iterations']}, "
            f"{row['colours']} tangent colours"
        )


if __name__ == "__main__":
    main()
