"""The explicit step on one thread with each of numba's two builds of the element kernels
(femcore/jit.py ``_Parallel``): the plain build (what a loop on one thread runs) and the
parallel build on one thread (``PLAIN_ON_ONE_THREAD = False``: what every loop ran before the
plain build was added), in turns in one process:
benchmarks/explicit_step.py's figures (µs of CPU per element-step) for each.

Measured (10082 triangles, one numba and BLAS thread, 2 cores shared with other jobs; µs of
CPU per element-step: the steady step, the force alone):

    element  round (load)   parallel build, one thread   plain build
    fibrous  1 (6-7)        1.110, force 0.998           1.201, force 1.080
    fibrous  2 (6.8-6.9)    1.205, force 0.966           1.155, force 0.806
    fibrous  3 (4.8-5.0)    1.212, force 0.756           0.877, force 0.798
    Mindlin  1 (4.8)        0.268, force 0.189           0.226, force 0.137

No difference beyond the machine's noise (the parallel compiler's hoisting of a loop's small
arrays, once measured 3 times faster per cell, buys nothing now that the cell loops keep their
vectors in scalars).

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

from femcore import jit  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--element", default="fibrous")
    parser.add_argument("--sizes", default="10000")
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    for _ in range(args.rounds):
        for plain in (False, True):
            jit.PLAIN_ON_ONE_THREAD = plain
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
