"""Newton iterations of Static on the fibrous strips: the compression-free tangent far from
equilibrium (``Static(compression_free=1e-2)``, an option, off by default; docs/theory.md
§6.5) against the exact tangent at every iterate (``compression_free=0``, the default).

1. Peirce's cantilever of the fibrous shell (the G986 stack, the overhang whose chord dips
   41.5 deg, 20 x 1 cells, 3 increments; benchmarks/static_solver.py line 6).
2. The heavy fibrous cantilever of the validation case fibrous-heavy-cantilever (140 x 10 x
   6 mm, 3 increments) at 10, 20 and 40 cells.

Each line: the Newton iterations per increment, the cuts, the tangents and force evaluations,
the mode searches (eigen-solves of the downhill turns), the CPU time (best of ``--repeat``, one
thread) and the tip, the same to 1e-6 mm in both runs.

Measured on this 2-core machine (one thread, CPU time best of 3, 1-minute load 4.4-5.3
shared by other jobs), exact -> compression-free. The exact run is the same code with
compression_free=0, which takes the code path of the solver before the change: the same
iterations and evaluation counts as that solver (Peirce 7-14-11, 79 forces, 32 tangents;
heavy, 20 cells, 30-11-8, 129 forces, 49 tangents, measured on it). Tips equal to 1e-6 mm.

- Peirce fibrous: 7-14-11 -> 9-9-10 iterations, 32 -> 28 tangents, 79 -> 72 forces, 6 -> 2
  mode searches, 0.33 -> 0.26 s CPU;
- heavy cantilever, 10 cells: 25-9-8 and a cut (92 tangents) -> 26-9-7, no cut (42),
  0.73 -> 0.31 s;
- heavy cantilever, 20 cells: 30-11-8 (49 tangents) -> 25-9-8 (42), 0.49 -> 0.36 s;
- heavy cantilever, 40 cells: 47-27-19 (93 tangents) -> 49-11-9 (69), 3.75 -> 0.98 s.

The first increment (from the flat strip) stays at 25-49 iterations and Peirce's at 9-10: not
the 3-6 of the Mindlin strips; docs/theory.md §6.5 says what was measured and not kept.

Run: python benchmarks/fibrous_newton.py [--repeat 3]
"""

from __future__ import annotations

import argparse
import math
import os
import platform
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from materials.presets import g986_stack  # noqa: E402
from solvers import Static  # noqa: E402
from validation import specimens  # noqa: E402
from validation.cases.fibrous_heavy_cantilever import strip as heavy_strip  # noqa: E402
from validation.references.elastica import peirce_overhang  # noqa: E402

VARIANTS = (
    ("exact tangent at every iterate (compression_free=0)", 0.0),
    ("default (compression_free=None)", None),
)


def models():
    """(name, mesh, compiled model) of each line."""
    fabric = g986_stack()
    overhang = peirce_overhang(fabric.areal_density * specimens.GRAVITY, fabric.bending)
    mesh, model = specimens.fibrous_strip(overhang["overhang"], 10.0, fabric, 20)
    yield "Peirce's cantilever, fibrous, 20 cells", mesh, model.compile()
    for cells in (10, 20, 40):
        mesh, model = heavy_strip(cells)
        yield f"heavy fibrous cantilever, {cells} cells", mesh, model.compile()
    # A Mindlin strip (aluminium, 200 x 20 x 1 mm, 20 x 2 cells) under a tip load
    # P L^2 / EI = 3 (benchmarks/static_solver.py line 2, coarser): no fibrous block, so the
    # default keeps the exact tangent.
    length, width, thickness, young = 200.0, 20.0, 1.0, 70e3
    mesh, model = specimens.mindlin_strip(length, width, thickness, young, cells=20, across=2)
    tip = mesh.nodes("right")
    load = 3.0 * young * width * thickness**3 / 12 / length**2
    model.force(tip, (0.0, 0.0, -load / len(tip)), amplitude="linear")
    yield "Mindlin cantilever, 20 x 2 cells, tip load", mesh, model.compile()


def run(model, ratio: float | None, repeat: int):
    """(result, best CPU seconds) of ``repeat`` solves."""
    best, result = math.inf, None
    for _ in range(repeat):
        started = time.process_time()
        result = Static(increments=3, compression_free=ratio).solve(model)
        best = min(best, time.process_time() - started)
    return result, best


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3, help="solves per line (best CPU)")
    args = parser.parse_args(argv)
    print(f"python {platform.python_version()} on {platform.machine()} ({platform.system()})")
    for name, mesh, model in models():
        print(f"{name}:")
        for variant, ratio in VARIANTS:
            result, cpu = run(model, ratio, args.repeat)
            info = result.info
            counts = info["evaluations"]
            tip = result.positions[mesh.nodes("right")].mean(axis=0)
            print(
                f"  {variant}: iterations {info['iterations_per_increment']}, cuts "
                f"{info['cuts']}, {counts['tangent']} tangents, {counts['residual']} forces, "
                f"{info['mode_searches']} mode searches, {cpu:.2f} s CPU (best of "
                f"{args.repeat}), tip x {tip[0]:.6f} z {tip[2]:.6f} mm, load "
                f"{os.getloadavg()[0]:.1f}"
            )


if __name__ == "__main__":
    main()
