"""Speed of the Mindlin shell in explicit dynamics: microseconds per element-step.

``CentralDifference`` on a square plate of ``MindlinShell`` (E = 70 GPa, h = 1 mm) with about
1k, 10k and 100k triangles, pinned on its boundary and loaded by gravity from rest, over a fixed
number of steps at 0.9 x the stable step. The static solves of the Mindlin shell (the
2560-triangle cantilever and roll-up, Static against DynamicRelaxation) are timed by
``benchmarks/static_solver.py``.

Run from the project root:

    python benchmarks/mindlin_shell.py
    python benchmarks/mindlin_shell.py --sizes 1000,10000 --steps 50
"""

from __future__ import annotations

import argparse
import platform
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install

from shell_sheet import print_explicit_table  # noqa: E402

from elements import MindlinShell  # noqa: E402
from materials import ElasticShell  # noqa: E402

ALUMINIUM = dict(E=70e3, nu=0.3, thickness=1.0, density=2.7e-9)  # MPa, mm, t/mm^3


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="1000,10000,100000")
    parser.add_argument("--steps", type=int, default=100)
    args = parser.parse_args(argv)
    print(f"python {platform.python_version()} on {platform.machine()} ({platform.system()})")
    sizes = [int(size) for size in args.sizes.split(",")]
    print_explicit_table(
        "MindlinShell, CentralDifference:",
        lambda: MindlinShell(ElasticShell(**ALUMINIUM)),
        sizes,
        args.steps,
    )


if __name__ == "__main__":
    main()
