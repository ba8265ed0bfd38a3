"""Speed of the Mindlin shell: explicit dynamics and the Newton tangent.

1. ``CentralDifference`` on a square plate of ``MindlinShell`` (E = 70 GPa, h = 1 mm) with about
   1k, 10k and 100k triangles, pinned on its boundary and loaded by gravity from rest, over a
   fixed number of steps at 0.9 x the stable step: microseconds per element-step.
2. The element tangent on the aluminium strip of the static benchmarks (200 x 20 x 1 mm,
   nu = 0; 2560 and 10240 triangles): milliseconds for one internal-force evaluation, for the
   analytic tangent (docs/theory.md §5.5) and for the central-difference tangent it replaced
   (36 evaluations of the element loads), side by side in one run; the best of ``--repeats``
   interleaved runs, so that the ratios hold on a busy machine.

The static solves of the Mindlin shell (the 2560-triangle cantilever and roll-up, Static against
DynamicRelaxation) are timed by ``benchmarks/static_solver.py``.

Run from the project root:

    python benchmarks/mindlin_shell.py
    python benchmarks/mindlin_shell.py --sizes 1000,10000 --steps 50 --strips 80x16
    python benchmarks/mindlin_shell.py --part tangent
"""

from __future__ import annotations

import argparse
import dataclasses
import platform
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install

from shell_sheet import kernel_rows, print_explicit_table  # noqa: E402

from elements import MindlinShell  # noqa: E402
from materials import ElasticShell  # noqa: E402
from validation.specimens import mindlin_strip  # noqa: E402

ALUMINIUM = dict(E=70e3, nu=0.3, thickness=1.0, density=2.7e-9)  # MPa, mm, t/mm^3


def tangent_times(cells: int, across: int, repeats: int) -> dict:
    """Best wall times (ms) of one block's internal force, analytic tangent and
    central-difference tangent on a strip of 2 x cells x across triangles, and the largest
    difference between the two tangents relative to their largest entry.

    The state is the strip bent about y into a quarter circle with its directors on the
    normals, so that every strain measure and stress is non-zero."""
    length = 200.0
    mesh, model = mindlin_strip(length, 20.0, 1.0, 70e3, cells=cells, across=across)
    compiled = model.compile()
    block = compiled.blocks[0]
    flat = compiled.initial_state()
    radius = 2.0 * length / np.pi
    angle = flat.positions[:, 0] / radius
    state = dataclasses.replace(
        flat,
        positions=np.column_stack(
            [radius * np.sin(angle), flat.positions[:, 1], radius * (1.0 - np.cos(angle))]
        ),
        directors=np.column_stack([-np.sin(angle), np.zeros_like(angle), np.cos(angle)]),
    )
    runs = {
        "force": lambda: block.internal_force(state),
        "analytic": lambda: block.tangent(state),
        "differences": lambda: block.difference_tangent(state),
    }
    best = dict.fromkeys(runs, np.inf)
    for _ in range(repeats):
        for name, run in runs.items():
            started = time.perf_counter()
            run()
            best[name] = min(best[name], 1e3 * (time.perf_counter() - started))
    analytic = block.tangent(state)[0].blocks
    reference = block.difference_tangent(state)[0].blocks
    best["agreement"] = np.abs(analytic - reference).max() / np.abs(reference).max()
    best["triangles"] = len(block.connectivity)
    return best


def print_tangent_table(strips: list[tuple[int, int]], repeats: int) -> None:
    print(f"MindlinShell tangent, ms (best of {repeats}):")
    print(
        f"{'triangles':>10} {'force':>8} {'analytic':>9} {'ratio':>6} "
        f"{'differences':>12} {'ratio':>6} {'|K-K_fd|/max':>13}"
    )
    for cells, across in strips:
        t = tangent_times(cells, across, repeats)
        print(
            f"{t['triangles']:>10d} {t['force']:>8.1f} {t['analytic']:>9.1f} "
            f"{t['analytic'] / t['force']:>6.1f} {t['differences']:>12.1f} "
            f"{t['differences'] / t['force']:>6.1f} {t['agreement']:>13.1e}"
        )


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--part", choices=("all", "explicit", "tangent"), default="all")
    parser.add_argument("--sizes", default="1000,10000,100000")
    parser.add_argument("--steps", type=int, default=100)
    parser.add_argument("--strips", default="80x16,160x32", help="cells x across, comma list")
    parser.add_argument("--repeats", type=int, default=10)
    args = parser.parse_args(argv)
    print(f"python {platform.python_version()} on {platform.machine()} ({platform.system()})")
    if args.part in ("all", "tangent"):
        pairs = [strip.split("x") for strip in args.strips.split(",")]
        print_tangent_table([(int(c), int(a)) for c, a in pairs], args.repeats)
    if args.part in ("all", "explicit"):
        sizes = [int(size) for size in args.sizes.split(",")]
        print_explicit_table(
            "MindlinShell, CentralDifference (the numpy path, and the compiled kernel on 1 and "
            "on all threads):",
            kernel_rows(lambda kernel: MindlinShell(ElasticShell(**ALUMINIUM), kernel=kernel)),
            sizes,
            args.steps,
        )


if __name__ == "__main__":
    main()
