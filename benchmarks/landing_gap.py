"""The cost of a landing node's exact gap (elements/contact_history.py, docs/theory.md §9.2)
on hemisphere forming's friction variant (coarse, fibrous, mu = 0.2 on the meshed die and the
holder: validation/cases/hemisphere_forming.py ``model(12, "fibrous", rim=DIE_RIM,
friction=0.2)``, the case's explicit solver): one whole run, one thread, with the tools'
``exact_distance`` timed where it is called (CPU, ``time.process_time``): printed beside the
run's CPU, its steps, the calls and the nodes they were asked for (the landing nodes, each
asked three times in its landing step: at the step's force, at its history's update and when
the step is accepted; a Static iteration asks at its force and three times at its tangent),
and the machine's load.

    python benchmarks/landing_gap.py

Measured (one thread, 2 cores shared with other jobs, load 8.0 -> 6.9): the run 16.29 s of
CPU over 16563 steps, exact_distance 0.005 s of it (0.03 %) in 152 calls for 200 nodes: the
landings are few, and each asks the k-d tree for a handful of points.
"""

from __future__ import annotations

import os
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(HERE))  # run from anywhere, no install


def main() -> None:
    from elements.rigid_surface import RigidSurface
    from elements.tools import RigidTool
    from solvers import CentralDifference
    from validation.cases import hemisphere_forming as case

    spent = {"cpu": 0.0, "calls": 0, "rows": 0}

    def timed(original):
        def exact_distance(self, x, load_factor=0.0):
            start = time.process_time()
            answer = original(self, x, load_factor)
            spent["cpu"] += time.process_time() - start
            spent["calls"] += 1
            spent["rows"] += len(x)
            return answer

        return exact_distance

    RigidSurface.exact_distance = timed(RigidSurface.exact_distance)  # type: ignore[method-assign]
    RigidTool.exact_distance = timed(RigidTool.exact_distance)  # type: ignore[method-assign]
    _, built = case.model(12, "fibrous", rim=case.DIE_RIM, friction=0.2)
    solver = CentralDifference(duration=case.DURATION, damping=case.DAMPING, progress=False)
    load = os.getloadavg()[0]
    start = time.process_time()
    result = solver.solve(built)
    total = time.process_time() - start
    steps = result.steps
    print(
        f"run {total:.2f} s CPU (steps {steps}); exact_distance {spent['cpu']:.3f} s CPU "
        f"({100 * spent['cpu'] / total:.2f} %), {spent['calls']} calls, {spent['rows']} nodes; "
        f"load {load:.1f} -> {os.getloadavg()[0]:.1f}"
    )


if __name__ == "__main__":
    main()
