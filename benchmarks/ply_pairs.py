"""What every ply touching every ply below it costs (elements/ply_contact.py ``join_plies``,
``Layup(pairs=...)``): the CPU of an explicit run of a stack of N plies with the pairs of
neighbours alone ("neighbours", the stacks' contact before) and with every pair ("all"), side
by side in one process, by turns, best of ``--repeats``, one thread; the machine's load
printed. The stack: [0/90/...] plies of 40 x 40 mm at ``--cells`` cells, the bottom ply held,
a flat holder pressing the top ply with 2 N (force-driven, free along z), frictional plies
(mu 0.2), over ``--duration``. With 2 plies both settings build the same
contact, so the final states are compared bit for bit (positions, directors, velocities).

    NUMBA_NUM_THREADS=1 nice -n 5 python benchmarks/ply_pairs.py --plies 4
    NUMBA_NUM_THREADS=1 nice -n 5 python benchmarks/ply_pairs.py --plies 2

Measured (this script, one thread, nice 5, 8 cells, 0.005 s of run): 4 plies (6 pairs against
3), load 4.9, 1.537 -> 2.294 ms a step (1.49 times; 804 steps both, the stable step the same);
2 plies, load 7.0, 0.692 and 0.685 ms a step (one pair either way), the final states identical
to the bit.

The pairs that are not neighbours acting only where their points face none of the plies
between (elements/ply_between.py; probes asked only where a point of the pair touches, which
none does in this stack: the final states are still identical to the bit): 4 plies, 0.005 s of
run, the code before it 1.851 -> 2.573 ms a step (1.39 times; load 3.6-8.8), with it 2.063 ->
2.464 (1.19 times; load 8.4-7.0): no cost above the machine's noise under that load. Pressed
hard enough that those pairs' faces meet (``--force 640``, 0.4 MPa, 0.01 s of run; the final
states then differ from the neighbours' alone, whose springs do not bound the step), the probes
are asked: "all" 2.163 ms a step before, 2.413 with them (1.12 times; "neighbours", whose code
did not change, 1.430 and 1.517 in the same runs, load 4.5-5.0).
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this tree's packages

import numpy as np  # noqa: E402

from elements import RigidPlane  # noqa: E402
from elements.layup import Layup  # noqa: E402
from materials import Fabric  # noqa: E402
from solvers import CentralDifference  # noqa: E402

PLY = Fabric(thickness=0.3, areal_density=2.85e-10, tension=60.0, shear=0.2, bending=0.375)


def run(
    plies: int, cells: int, duration: float, pairs: str, force: float = 2.0
) -> tuple[float, Any]:
    """(CPU seconds of the solve, its result) for the stack with ``pairs``, the holder pressing
    with ``force`` N."""
    angles = tuple(0.0 if k % 2 == 0 else 90.0 for k in range(plies))
    layup = Layup(PLY, angles, 40.0, cells=cells, friction=0.2, pairs=pairs)
    model = layup.model()
    model.fix("ply_1")
    holder = RigidPlane(
        (0.0, 0.0, plies * PLY.thickness),
        (0.0, 0.0, -1.0),
        free="z",
        force=(0.0, 0.0, -force),
        amplitude="smooth",
        mass=1e-6,
    )
    model.contact(holder, nodes=f"ply_{plies}")
    start = time.process_time()
    result = CentralDifference(duration=duration, progress=False, kinetic_bound=None).solve(model)
    return time.process_time() - start, result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--plies", type=int, default=4)
    parser.add_argument("--cells", type=int, default=8)
    parser.add_argument("--duration", type=float, default=0.01, help="s")
    parser.add_argument("--repeats", type=int, default=2)
    parser.add_argument(
        "--force", type=float, default=2.0, help="N on the holder (160: 0.1 MPa on 40 x 40 mm)"
    )
    args = parser.parse_args()
    print(f"load {os.getloadavg()[0]:.2f}; {args.plies} plies, {args.cells} cells, "
          f"{args.duration} s, {args.force} N")  # fmt: skip
    for pairs in ("neighbours", "all"):  # the kernels compiled before the timing
        run(args.plies, args.cells, 1e-4, pairs, args.force)
    best = {"neighbours": np.inf, "all": np.inf}
    last = {}
    for _ in range(args.repeats):
        for pairs in ("neighbours", "all"):
            cpu, result = run(args.plies, args.cells, args.duration, pairs, args.force)
            best[pairs] = min(best[pairs], cpu)
            last[pairs] = result
    for pairs in ("neighbours", "all"):
        steps = last[pairs].steps
        print(
            f"  {pairs:>10}: {best[pairs]:.3f} s CPU (best of {args.repeats}), {steps} steps, "
            f"{1e3 * best[pairs] / steps:.3f} ms a step"
        )
    print(f"  all / neighbours: {best['all'] / best['neighbours']:.3f}")
    a, b = last["neighbours"], last["all"]
    same = all(
        np.array_equal(getattr(a, name), getattr(b, name), equal_nan=True)
        for name in ("positions", "directors", "velocities")
        if hasattr(a, name)
    )
    print(f"  final states identical to the bit: {same}; load {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
