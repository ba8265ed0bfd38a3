"""The two-ply hemisphere's ply contact with one pass and with both (the mirrored pass at the
bottom ply's nodes, elements/ply_contact.py "Both ways"): CPU time of the first tenth of the
study's stroke (validation/studies/hemisphere_plies.py, fibrous [0/45], 8 cells, 20 N, t =
0.01 s), one thread, after a short warm-up run that compiles the kernels; prints the steps,
the CPU per step, the kinetic energy at the end (the same figure for the same model shows the
speed-ups change nothing) and the machine's load.

Measured (one thread, load 5.5-7.0, the same script on each code; 523 steps with both passes,
KE 221.363106381 N mm at the end on each): both passes with three points per triangle corner
(384 points, rule "vertices"), 18.44 s of CPU; one point per node (81 points, the corners'
shares summed: rule "nodes", elements/ply_block.py), 14.85 s; the nodal normals kept for the
last positions, 13.62 s; the facing kept for the last state, 9.90 s (18.9 ms per step). One
pass on the code before these, 470 steps, 9.57 s (20.4 ms per step). This script with all
three (load 6.0): one pass 470 steps, 7.06 s (15.0 ms per step); both ("vertices") 523
steps, 10.25 s (19.6 ms per step).

Run: python benchmarks/ply_both_ways.py
"""

from __future__ import annotations

import os
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this tree's packages

from solvers import CentralDifference
from validation.studies import hemisphere_plies_setup as setup


def _solve(lower_rule: str | None, duration: float):
    _, model = setup.model(8, setup.LAYUPS["0/45"], "fibrous", 20.0, lower_rule=lower_rule)
    solver = CentralDifference(
        duration=duration, damping=setup.DAMPING, progress=False, kinetic_bound=None
    )
    start = time.process_time()
    result = solver.solve(model)
    return result, time.process_time() - start


def main() -> None:
    _solve("nodes", 0.0005)  # compiles the kernels
    for lower_rule in (None, "vertices", "nodes"):
        load = os.getloadavg()[0]
        result, cpu = _solve(lower_rule, 0.01)
        print(
            f"lower_rule={lower_rule}: {result.steps} steps, {cpu:.2f} s CPU "
            f"({1e3 * cpu / result.steps:.1f} ms per step), KE at the end "
            f"{result.energies['kinetic'][-1]:.12g} N mm, load {load:.1f}"
        )


if __name__ == "__main__":
    main()
