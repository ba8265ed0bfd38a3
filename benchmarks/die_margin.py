"""The meshed tools' search margin (elements/rigid_surface.py ``MARGIN``) on the report's
two-ply hemisphere: whole runs at each margin given, alternating, in one process, one thread,
CPU (``time.process_time``), the machine's load printed beside each run.

Each run is hemisphere-plies' model and solver (validation/studies/hemisphere_plies_setup.py:
8 cells, 20 N); printed per run: its CPU, steps, ms a step, the die's and the other meshed
tools' searches (``RigidSurface._searched`` calls) and a hash of the final positions. The
margin only sets how long a point's kept facets serve, never what they answer (the proof's
distance plus twice the margin holds the closest facet while the point moves less than the
margin): every margin must give the same hash, which the script checks.

    python benchmarks/die_margin.py --kinematics mindlin --margins 0.25 0.5 --repeats 2

Measured (one thread, 2 cores shared with other jobs, load 5.6-6.4), Mindlin [0/90], 13939
steps: margin 0.25 1.500 and 1.467 ms a step (1002 searches), 0.5 1.438 and 1.384 (489
searches); the same final positions in every run. Adopted (elements/rigid_surface.py):
hemisphere-forming's default report beside main de923eb, both at once (load 4.5-5.9), 33.4
-> 32.7 s of CPU, its figures the same.
"""

from __future__ import annotations

import argparse
import hashlib
import os
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(HERE))  # run from anywhere, no install


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--kinematics", default="mindlin", choices=("fibrous", "mindlin"))
    parser.add_argument("--layup", default="0/90", choices=("0/90", "0/45"))
    parser.add_argument("--margins", type=float, nargs="+", default=[0.25, 0.5])
    parser.add_argument("--repeats", type=int, default=2)
    arguments = parser.parse_args()

    from elements import rigid_surface
    from validation.studies import hemisphere_plies_setup as setup
    from validation.studies.hemisphere_plies_run import case_solver

    searches = [0]
    surface = rigid_surface.RigidSurface
    searched = surface._searched

    def counted(self, *args, **kwargs):
        searches[0] += 1
        return searched(self, *args, **kwargs)

    surface._searched = counted  # type: ignore[method-assign]
    layup = setup.LAYUPS[arguments.layup]
    # compiled (or read from numba's cache) before the timing: a short run of the same model
    _, model = setup.model(8, layup, arguments.kinematics, 20.0)
    case_solver(
        arguments.layup, arguments.kinematics, 1 / 200, output_interval=None, kinetic_bound=None
    ).solve(model.compile())
    hashes = set()
    for _ in range(arguments.repeats):
        for margin in arguments.margins:
            rigid_surface.MARGIN = margin
            searches[0] = 0
            _, model = setup.model(8, layup, arguments.kinematics, 20.0)
            compiled = model.compile()
            solver = case_solver(
                arguments.layup, arguments.kinematics, output_interval=None, kinetic_bound=None
            )
            start = time.process_time()
            result = solver.solve(compiled)
            cpu = time.process_time() - start
            digest = hashlib.sha1(result.positions.tobytes()).hexdigest()[:16]
            hashes.add(digest)
            print(
                f"{arguments.kinematics} [{arguments.layup}] margin {margin}: {cpu:.2f} s CPU, "
                f"{result.steps} steps, {cpu / result.steps * 1e3:.3f} ms a step, "
                f"{searches[0]} searches, positions {digest} (load {os.getloadavg()[0]:.1f})",
                flush=True,
            )
    print("the same final positions in every run" if len(hashes) == 1 else "POSITIONS DIFFER")


if __name__ == "__main__":
    main()
