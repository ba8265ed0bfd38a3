"""The explicit step on one thread with each of numba's two builds of the element kernels
(elements/jit.py ``_Parallel``): the plain build (``SERIAL_ON_ONE_THREAD = True``, what a loop
on one thread runs) and the parallel build run on one thread (``False``, what every loop ran
before the plain build was added), in turns in one process: benchmarks/explicit_step.py's
figures (µs of CPU per element-step) for each.

Measured: see the figures below (updated with each measurement).

Run: python benchmarks/suite_builds.py [--element fibrous] [--sizes 10000] [--rounds 2]
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import explicit_step  # noqa: E402

from elements import jit  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--element", default="fibrous")
    parser.add_argument("--sizes", default="10000")
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    for _ in range(args.rounds):
        for plain in (False, True):
            jit.SERIAL_ON_ONE_THREAD = plain
            label = "plain build" if plain else "parallel build on one thread"
            print(f"--- {label}; load {os.getloadavg()[0]:.2f}", flush=True)
            explicit_step.main(
                [
                    "--element",
                    args.element,
                    "--sizes",
                    args.sizes,
                    "--threads",
                    "1",
                    "--repeats",
                    str(args.repeats),
                ]  # fmt: skip
            )


if __name__ == "__main__":
    main()
