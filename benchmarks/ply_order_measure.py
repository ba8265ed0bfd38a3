"""The hemisphere-plies case's measure of the plies' order (validation/studies/
hemisphere_plies_gaps.py ``least_gaps``: each top-ply node's gap to the bottom ply's curved
face at each of a run's 101 frames) with the curved face's compiled pass
(elements/ply_surface_kernels.py) and with the numpy reference (``ply_projection.COMPILED``
off), side by side in one process, alternating, best of ``--repeats``, one thread, CPU
(``time.process_time``), the machine's load printed; the two measures' figures compared.

One run of the case's model first (8 cells, 20 N, ``--kinematics``, ``--layup``; some 12-25 s
of CPU), then the measure on its frames.

    python benchmarks/ply_order_measure.py --kinematics fibrous --layup 0/90

Measured (one thread, 2 cores shared with other jobs, load 5-8): fibrous [0/90], 101 frames,
the projection's 809 calls of ``surface_point`` on 2304 rows: the measure with numpy's einsum
(main de923eb) 1.87-1.91 s, with the reference's sums spelled out 1.32 s, compiled 0.75 s;
the same figures to the bit all three ways. What is left of the 0.75 s: the projection's own
einsums (its 2 x 2 normal equations, 0.29 s profiled), the fresh lists' search of each frame
and the nodal normals.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(HERE))  # run from anywhere, no install


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--kinematics", default="fibrous", choices=("fibrous", "mindlin"))
    parser.add_argument("--layup", default="0/90", choices=("0/90", "0/45"))
    parser.add_argument("--repeats", type=int, default=3)
    arguments = parser.parse_args()

    from elements import ply_projection
    from validation.studies import hemisphere_plies_gaps as gaps
    from validation.studies import hemisphere_plies_setup as setup
    from validation.studies.hemisphere_plies_run import case_solver

    layup, model = setup.model(8, setup.LAYUPS[arguments.layup], arguments.kinematics, 20.0)
    result = case_solver(arguments.layup, arguments.kinematics, kinetic_bound=None).solve(
        model.compile()
    )
    print(f"{arguments.kinematics} [{arguments.layup}]: {len(result.frames)} frames")
    best = {True: float("inf"), False: float("inf")}
    figures = {}
    for _ in range(arguments.repeats):
        for compiled in (True, False):
            ply_projection.COMPILED = compiled
            start = time.process_time()
            figures[compiled] = gaps.least_gaps(layup, result, 8)
            best[compiled] = min(best[compiled], time.process_time() - start)
    ply_projection.COMPILED = True
    print(
        f"least_gaps: compiled {best[True]:.3f} s, numpy reference {best[False]:.3f} s CPU "
        f"(best of {arguments.repeats}; load {os.getloadavg()[0]:.1f})"
    )
    same = figures[True] == figures[False]
    print("the same figures to the bit" if same else f"FIGURES DIFFER: {figures}")


if __name__ == "__main__":
    main()
