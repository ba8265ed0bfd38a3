"""Cost of the fabric section: MindlinShell(fabric) against the elastic MindlinShell on the same
strip, side by side in one run.

The strip of benchmarks/mindlin_shell.py's tangent part (200 x 20 mm, 2 x cells x across
triangles) bent into a quarter circle, directors on the normals: best wall time (ms) of one
block's internal force, strain energy and analytic tangent for (a) the elastic section through
its numpy path (the reference pass over the same arithmetic form), (b) the elastic section's
compiled kernel (the default), (c) the fabric section (Bai Table 1's G986 stack laws: the
bilinear bending law), numpy only. Prints the machine's load before and after.

Run from the project root:

    python benchmarks/mindlin_fabric.py [--strips 80x16,160x32] [--repeats 10]
    NUMBA_NUM_THREADS=1 python benchmarks/mindlin_fabric.py
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install

from elements import MindlinShell  # noqa: E402
from femcore import Mesh, Model  # noqa: E402
from materials import ElasticShell  # noqa: E402
from materials.presets import g986_stack  # noqa: E402

LENGTH, WIDTH = 200.0, 20.0


def _bent_state(compiled):
    flat = compiled.initial_state()
    radius = 2.0 * LENGTH / np.pi
    angle = flat.positions[:, 0] / radius
    return dataclasses.replace(
        flat,
        positions=np.column_stack(
            [radius * np.sin(angle), flat.positions[:, 1], radius * (1.0 - np.cos(angle))]
        ),
        directors=np.column_stack([-np.sin(angle), np.zeros_like(angle), np.cos(angle)]),
    )


def times(element, cells: int, across: int, repeats: int) -> dict[str, float]:
    """Best wall times (ms) of force, energy and tangent of one block."""
    mesh = Mesh.rectangle(LENGTH, WIDTH, nx=cells, ny=across)
    model = Model(mesh)
    model.add(element)
    compiled = model.compile()
    block = compiled.blocks[0]
    state = _bent_state(compiled)
    runs = {
        "force": lambda: block.internal_force(state),
        "energy": lambda: block.strain_energy(state),
        "tangent": lambda: block.tangent(state),
    }
    for run in runs.values():  # compile and warm up
        run()
    best = dict.fromkeys(runs, np.inf)
    for _ in range(repeats):
        for name, run in runs.items():
            started = time.perf_counter()
            run()
            best[name] = min(best[name], 1e3 * (time.perf_counter() - started))
    best["triangles"] = len(block.connectivity)
    return best


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--strips", default="80x16,160x32", help="cells x across, comma list")
    parser.add_argument("--repeats", type=int, default=10)
    args = parser.parse_args(argv)
    print(f"python {platform.python_version()} on {platform.machine()} ({platform.system()})")
    print(f"load average before: {os.getloadavg()}")
    fabric = g986_stack()
    elastic = ElasticShell(70e3, 0.3, fabric.thickness, 2.7e-9)
    sections = {
        "elastic, numpy": lambda: MindlinShell(elastic, kernel="numpy"),
        "elastic, compiled": lambda: MindlinShell(elastic),
        "fabric (laws), numpy": lambda: MindlinShell(fabric),
    }
    print(f"{'triangles':>10} {'section':>22} {'force':>8} {'energy':>8} {'tangent':>8} ms")
    for strip in args.strips.split(","):
        cells, across = (int(v) for v in strip.split("x"))
        rows = {name: times(make(), cells, across, args.repeats) for name, make in sections.items()}
        reference = rows["elastic, numpy"]
        for name, t in rows.items():
            print(
                f"{t['triangles']:>10d} {name:>22} {t['force']:>8.2f} {t['energy']:>8.2f} "
                f"{t['tangent']:>8.2f}   (x{t['force'] / reference['force']:.2f} force, "
                f"x{t['tangent'] / reference['tangent']:.2f} tangent of the numpy elastic)"
            )
    print(f"load average after: {os.getloadavg()}")


if __name__ == "__main__":
    main()
