"""Speed of the fibrous shell: explicit steps per element, and a dynamic-relaxation solve.

1. ``CentralDifference`` on a square sheet of ``FibrousShell`` (G986 stack of Bai Table 1)
   with about 1k, 10k and 100k triangles, pinned on its boundary and loaded by gravity from
   rest, over a fixed number of steps at 0.9 x the stable step: microseconds per
   element-step (compilation excluded; frames only at the start and the end).
2. The two thickness options side by side on the same sheet, interleaved: the internal force
   and the element tangent with nodal normals (the default) and with Bai's Eq. 15 element
   normals, microseconds per element and their ratio.
3. ``DynamicRelaxation`` of a 40 x 10-cell cantilever strip (200 x 50 mm, G1151 laminate of
   Bai Table 2, clamped-edge option) under its own weight: wall time and iterations (the
   strip builder of the validation case fibrous-heavy-cantilever, validation.specimens).

Run from the project root:

    python benchmarks/fibrous_shell.py
    python benchmarks/fibrous_shell.py --sizes 1000,10000 --steps 50
"""

from __future__ import annotations

import argparse
import platform
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install

import numpy as np  # noqa: E402
from shell_sheet import kernel_rows, print_explicit_table  # noqa: E402

from elements import FibrousShell  # noqa: E402
from femcore import Mesh, Model  # noqa: E402
from materials import presets  # noqa: E402
from solvers import DynamicRelaxation  # noqa: E402
from validation.specimens import fibrous_strip  # noqa: E402

__all__ = ["main", "relaxation", "thickness_options"]


def thickness_options(cells_per_side: int, repeats: int = 5) -> dict:
    """Internal force and tangent of one tilted, bent sheet with both thickness options,
    timed alternately (best of ``repeats``), microseconds per element."""
    mesh = Mesh.rectangle(100.0, 100.0, nx=cells_per_side, ny=cells_per_side)
    models = {}
    for option in ("nodal", "element"):
        model = Model(mesh)
        model.add(FibrousShell(presets.g986_stack(), thickness=option))
        models[option] = model.compile()
    state = models["nodal"].initial_state()
    x = mesh.points[:, 0]
    state.positions = state.positions + np.column_stack(
        [np.zeros_like(x), np.zeros_like(x), 0.002 * (x - 50.0) ** 2]
    )
    best = {(o, w): np.inf for o in models for w in ("force", "tangent")}
    for _ in range(repeats):
        for option, compiled in models.items():
            block = compiled.blocks[0]
            started = time.perf_counter()
            block.internal_force(state)
            best[option, "force"] = min(best[option, "force"], time.perf_counter() - started)
            started = time.perf_counter()
            block.tangent(state)
            best[option, "tangent"] = min(best[option, "tangent"], time.perf_counter() - started)
    elements = len(mesh.triangles)
    return {key: value / elements * 1e6 for key, value in best.items()} | {"elements": elements}


def relaxation() -> dict:
    """The G1151 strip of validation.specimens.fibrous_strip relaxed under its own weight."""
    mesh, model = fibrous_strip(200.0, 50.0, presets.g1151_laminate(), cells=40, across=10)
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
    parser.add_argument("--thickness-cells", type=int, default=70)
    args = parser.parse_args(argv)
    print(f"python {platform.python_version()} on {platform.machine()} ({platform.system()})")
    sizes = [int(size) for size in args.sizes.split(",")]
    print_explicit_table(
        "FibrousShell, CentralDifference (the numpy path, and the compiled loops on 1 and on "
        "all threads):",
        kernel_rows(lambda kernel: FibrousShell(presets.g986_stack(), kernel=kernel)),
        sizes,
        args.steps,
    )
    row = thickness_options(args.thickness_cells)
    print(f"Thickness options on a {row['elements']}-triangle sheet (us per element, best of 5):")
    for what in ("force", "tangent"):
        nodal, element = row["nodal", what], row["element", what]
        print(
            f"  {what:8s} nodal normals {nodal:8.2f}   element normals (Bai Eq. 15) "
            f"{element:8.2f}   ratio {nodal / element:5.2f}"
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
