"""Speed of the fibrous shell: explicit steps per element, and a dynamic-relaxation solve.

1. ``CentralDifference`` on a square sheet of ``FibrousShell`` (G986 stack of Bai Table 1)
   with about 1k, 10k and 100k triangles, pinned on its boundary and loaded by gravity from
   rest, over a fixed number of steps at 0.9 x the stable step: microseconds per
   element-step (compilation excluded; frames only at the start and the end).
2. ``DynamicRelaxation`` of a 40 x 10-cell cantilever strip (200 x 50 mm, G1151 laminate of
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

from shell_sheet import print_explicit_table  # noqa: E402

from elements import FibrousShell  # noqa: E402
from materials import presets  # noqa: E402
from solvers import DynamicRelaxation  # noqa: E402
from validation.specimens import fibrous_strip  # noqa: E402

__all__ = ["main", "relaxation"]


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
    args = parser.parse_args(argv)
    print(f"python {platform.python_version()} on {platform.machine()} ({platform.system()})")
    sizes = [int(size) for size in args.sizes.split(",")]
    print_explicit_table(
        "FibrousShell, CentralDifference:",
        lambda: FibrousShell(presets.g986_stack()),
        sizes,
        args.steps,
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
