"""Static's Newton where a ply contact point lands on an edge of a folded lower ply within an
increment: the friction's tangent with the edge point's landing anchor moving with the state
(exact, elements/ply_edge_landing.py ``crossing_motion``) beside the tangent that held it fixed
(the code before: the edge rows' motion 0), side by side in one process.

The model (tests/ply_pair.py ``folded_plies`` with ``free``): a lower ply 6 x 6 mm in 3 x 3
cells held fixed, its nodes on x = 2 0.5 mm below the rest (a valley); an upper ply of one
triangle at its nodes whose low node's contact point starts 0.0213 mm over the valley's edge
line, its two other nodes carried 0.1 mm down and ``along`` mm along the edge over the run, the
low node free in translation (it follows through the shell), rotations held; Mindlin, E = 70
GPa, 0.2 mm thick, mu 0.3, penalty 50 N/mm, no smoothing. The point lands on the edge (its gap
g = +-|p - q| along nu = +z) at 0.213 of the run.

Printed for each tangent: the Newton iterations per increment, and the landing increment's
residual ratios with r_k+1 / r_k^2 of its steps from r_k <= 1e-2 (bounded for a quadratic
iteration, growing as r_k falls for a linear one). Iteration counts, not times.

Measured: iterations per increment held -> exact, and the landing increment's last ratios:

    along 1.2,  3 incr.: [3, 2, 4] -> [3, 2, 2]; 1.6e-4 -> 3.3e-9 / 2.0e-4 -> 5.4e-12
    along 0.3,  3 incr.: [4, 2, 2] -> [3, 2, 2]; 1.9e-4 -> 1.7e-7 -> 1.4e-10 / -> 5.8e-12
    along 0.05, 3 incr.: [4, 2, 2] -> [3, 2, 2]; 1.4e-3 -> 7.1e-6 -> 3.5e-8 / 1.8e-4 -> 8.1e-12
    along 0.05, 7 incr.: [1, 4, 2, 2, 2, 2, 2] -> [1, 3, 2, ...]; 1.1e-3 -> 4.3e-6 -> 1.6e-8 /
                         1.1e-4 -> 4.5e-12
    along 0.01, 3 incr.: [5, 2, 2] -> [3, 2, 2]; 1.8e-3 -> 1.9e-5 -> 1.9e-7 -> 2.0e-9 /
                         1.7e-4 -> 2.3e-12

r_k+1 / r_k^2 held 0.13-5.9 and growing (linear), exact 7.7e-5 to 3.8e-4; the final positions
the same to 3e-14 mm. The increments after the landing differ by chance in places (along 1.2:
[3, 2, 4] held, and 7 increments [.., 2, 2] held against [.., 4, 3] exact): the point slides
there, and at each converged state its stick spring holds exactly mu N, so round-off decides
whether the next increment's first tangent is the stick one (a step 0.5 off) or the slip one,
whichever tangent led there. Along 0.3 in 6, 7 or 14 increments Static stops at a load factor
0.138-0.1395, before the touch, on this code and the code before alike (not the landing's).

Run: python benchmarks/ply_edge_landing_newton.py
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install

from elements import ply_landing
from solvers import Static
from tests.ply_pair import counted_landings, folded_plies

G0 = 0.0213  # mm over the edge line at the start (tests/test_ply_edge_crossing.py)
DOWN = -0.1  # mm over the run
DIP = 0.5  # mm, the valley
LINES = ((1.2, 3), (0.3, 3), (0.05, 3), (0.05, 7), (0.01, 3))  # mm along the edge, increments


def _held(crossing, hessian, tilt_floor):
    """The edge rows' anchor motion held at 0 (the code before)."""
    return np.zeros((len(crossing.point), 3, 4, 3))


def solve(along: float, increments: int, exact: bool):
    """(result, landing points per increment) of Static on the free folded pair."""
    original = ply_landing.crossing_motion
    if not exact:
        ply_landing.crossing_motion = _held
    try:
        model = folded_plies(G0, along, DOWN, DIP, free=True)
        with counted_landings() as landings:
            result = Static(increments=increments, progress=False).solve(model)
    finally:
        ply_landing.crossing_motion = original
    return result, landings


def quadratic_constants(ratios: list[float]) -> list[float]:
    """r_k+1 / r_k^2 of the steps from 0 < r_k <= 1e-2."""
    return [b / a**2 for a, b in zip(ratios[:-1], ratios[1:]) if 0 < a <= 1e-2]


def main() -> None:
    for along, increments in LINES:
        print(f"{along} mm along the edge, {DOWN} down, {increments} increments")
        finals = []
        for label, exact in (("anchor held (before)", False), ("anchor moving (exact)", True)):
            result, landings = solve(along, increments, exact)
            counts = result.info["iterations_per_increment"]
            landing = landings.index(1)
            ratios = result.info["residual_history"][landing]
            constants = " ".join(f"{c:.2g}" for c in quadratic_constants(ratios))
            print(f"  {label}: iterations {counts} (total {sum(counts)}), landing in "
                  f"increment {landing + 1}: ratios {' '.join(f'{r:.1e}' for r in ratios)} "
                  f"| r_k+1 / r_k^2 {constants}")  # fmt: skip
            finals.append(result.frames[-1].positions)
        print(f"  the final positions {np.abs(finals[0] - finals[1]).max():.2e} mm apart")


if __name__ == "__main__":
    main()
