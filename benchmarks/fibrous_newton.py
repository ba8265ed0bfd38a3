"""Newton iterations of Static on the fibrous strips: the compression-free tangent far from
equilibrium (``Static(compression_free=None)``, the default: 1e-2 on a fibrous model without
interactions; docs/theory.md §6.5) against the exact tangent at every iterate
(``compression_free=0``, the default before, on the code path of the solver before the change).

1. Peirce's cantilever of the fibrous shell (the G986 stack, the overhang whose chord dips
   41.5 deg, 20 x 1 cells, 3 increments; benchmarks/static_solver.py line 6).
2. The heavy fibrous cantilever of the validation case fibrous-heavy-cantilever (140 x 10 x
   6 mm, 3 increments) at 10, 20 and 40 cells.
3. A Mindlin cantilever (aluminium, 200 x 20 x 1 mm, 20 x 2 cells, tip load P L^2 / EI = 3 in
   3 increments): no fibrous block, the default keeps the exact tangent.

Each line: the Newton iterations per increment, the cuts, the tangents and force evaluations,
the mode searches (eigen-solves of the downhill turns), the CPU time (best of ``--repeat``, one
thread) and the tip, the same to 1e-6 mm in both runs.

Measured on this 2-core machine (one thread, CPU time best of 3), the old code's default
(``Static()`` before the change, run from a worktree of it, load 7.1-7.4: the same counts and
tips as ``compression_free=0`` now, and its times within the load's noise) -> the default now
(load 4.8-5.5, both variants in the same run). The default takes the exact tangent at the
first iterate of each increment (a converged state). Tips equal to 1e-6 mm:

- Peirce fibrous: 7-14-11 -> 10-9-10 iterations, 32 -> 29 tangents, 79 -> 75 forces, 6 -> 2
  mode searches, 0.35 -> 0.25 s CPU (compression_free=0 and the default, same run);
- heavy cantilever, 10 cells: 47-9-8 -> 26-9-7, 64 -> 42 tangents, 173 -> 117 forces, 19 -> 6
  mode searches, 0.51 -> 0.31 s;
- heavy cantilever, 20 cells: 30-11-8 -> 25-9-8, 49 -> 42 tangents, 129 -> 116 forces, 12 -> 7
  mode searches, 0.56 -> 0.43 s;
- heavy cantilever, 40 cells: 47-27-19 -> 49-11-9, 93 -> 69 tangents, 261 -> 200 forces, 22 ->
  8 mode searches, 3.53 -> 0.96 s;
- Mindlin cantilever: 6-13-8 both, 27 tangents, 81 forces, 0.16-0.18 s (unchanged).

The validation cases with a fibrous Static and no contact at coarse resolution
(fibrous-heavy-cantilever, heavy-cantilever-nonlinear, fibrous-deck-of-cards, bai-5.1,
bai-6.1.1, bai-6.1.2, bai-6.2.1, bai-6.2.2), old code -> now: every check's value the same to
1.1e-7 (relative; a round-off check of 2e-16 -> 1e-16 aside; the heavy cantilever's tip
deflection 117.5210592 mm to 6e-10 mm), Newton iterations 64 -> 42, 230 -> 201, 33 -> 32, 1450,
536, 645 -> 646, 507, 589 (the paper cases run the arc length, where the option does not act,
and load steps only beyond a limit point).

Why not 3-6 (docs/theory.md §6.5, "Where the iterations of the fibrous strips go"; scripts of
the measurements not kept): the tangent is exact (heavy cantilever, 10 cells, at the iterates of
the first increment: |K - K_fd| / max |K| = 1e-7 to 6e-7, the central differences' own asymmetry
1e-7 to 6e-7); the steps are whole except the third to fifth of the first increment (director
turns of 1.5 to 35 rad asked; 10 cells: scales 0.67, 0.013, then back to the best iterate) and
one more there. The residual ratio sits at 0.3-1.0 for 22 of the 25 iterations of the heavy
cantilever's first increment (20 cells) and 6-7 of Peirce's 9-10, then falls quadratically in
2-4 (9.3e-3 -> 2.1e-8): the plateau is the fibres' stretch by each step's remainder, their
tension stiffness per element 7800 times the bending's (a fibre strain of 1e-6 across the heavy
strip is 0.012 N, half the weight of an increment). The first increment's first step is the
linear bending solution from the flat strip, 8.6 (10 cells) to 12 (20 cells) elements of
deflection with no director turn. Finer load steps shorten the increments but not the solve
(heavy, 20 cells, exact tangent: 6 increments 12-12-10-8-8-6, 130 forces; 12 increments 4-11,
191; 24 increments 4-7, 272; against 129 at 3), and Peirce's bilinear law has a knee that single
increments of 12 or 24 meet with 15-27 iterations. The arc length (``path="arc_length"``, 3
increments to start, the default tangent) keeps its increments at 3-11 iterations but takes
18-35 of them: heavy 10 / 20 cells and Peirce 148 / 142 / 188 tangents, 0.9 / 1.2 / 1.7 s CPU
against 42 / 42 / 29 tangents on the load path (load 5-6).

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
