"""Static's Newton on curved faces where ply contact points land within increments: the
friction's tangent with each landing point's anchor moving with the state (exact,
elements/ply_curved_friction.py ``landing_anchor``) beside the tangent that held it fixed
(the code before: the landing rows' motion left out), side by side in one process.

The model (tests/ply_pair.py ``capped_plies``): a 6-mm cap of a ply (3 x 3 cells, rotations
held) brought down 0.25 mm (its face's apex 0.01 mm clear at the start) and along x onto a
12-mm lower ply (4 x 4 cells, clamped at its outline) on a 20-mm sphere, Mindlin, E = 70 GPa,
0.2 mm thick, curved faces, Gauss points, penalty 50 N/mm a point, the normal law's ramp
0.02 mm; the contact zone spreads from the apex, its points landing over the first
increments, sliding along x. Two lines: 1 mm along x in 8 increments and 3 mm in 6.

Printed for each tangent: the Newton iterations per increment, the points landing in each
increment (no anchor at its start, anchored at its end), and each increment's residual
ratios with r_k+1 / r_k^2 of its steps from r_k <= 1e-2 whose r_k+1 lies clear of the
round-off floor (1e-10): bounded for a quadratic iteration, growing as r_k falls for a linear
one. Iteration counts, not times.

Measured (mu 0.3), iterations per increment [landing points]:

    1 mm in 8  held  4 4 3 3 3 3 3 3 (26)  exact  3 3 3 3 3 3 3 3 (24)  [18 16 9 2 2 0 0 0]
    3 mm in 6  held  4 4 3 3 3 3 (20)      exact  3 3 3 3 3 3 (18)      [22 9 0 0 0 0]

the landing increments' last steps r_k+1 / r_k^2 0.08-1.3 held (linear: 2.9e-4 -> 1.2e-8,
5.9e-4 -> 2.9e-8 -> 4.6e-12, 7.7e-5 -> 7.7e-9), 0.001-0.02 exact (2.9e-4 -> 1.0e-10, 5.9e-4
-> 2.1e-9, 2.0e-3 -> 9.6e-9); the final positions the same to 1e-15 mm. The code before (the
main tree, run apart) gives the held line's figures to the digit.

Run: python benchmarks/ply_curved_landing_newton.py [mu]
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install

from elements import ply_curved_friction
from solvers import Static
from tests.ply_pair import MU, capped_plies, counted_landings

LINES = ((1.0, 8), (3.0, 6))  # mm along x, increments
DOWN = -0.25  # mm
FLOOR = 1e-10  # residual ratios near the round-off floor show no order


def _held_landing(original):
    """``_frictional_points`` with the landing points' anchors held fixed (the code before)."""

    def held(block, state, sliding, history, facing, surface, found=None):
        return original(block, state, sliding, history, facing, surface)

    return held


def solve(along: float, increments: int, mu: float, exact: bool):
    """(result, landing points per increment) of Static on ``capped_plies``."""
    original = ply_curved_friction._frictional_points
    if not exact:
        ply_curved_friction._frictional_points = _held_landing(original)
    try:
        model = capped_plies(along, DOWN, mu)
        with counted_landings() as landings:
            result = Static(increments=increments, progress=False).solve(model)
    finally:
        ply_curved_friction._frictional_points = original
    return result, landings


def quadratic_constants(ratios: list[float]) -> list[float]:
    """r_k+1 / r_k^2 of the steps from 0 < r_k <= 1e-2 with r_k+1 above ``FLOOR``."""
    return [b / a**2 for a, b in zip(ratios[:-1], ratios[1:]) if 0 < a <= 1e-2 and b > FLOOR]


def main(argv: list[str]) -> None:
    mu = float(argv[0]) if argv else MU
    for along, increments in LINES:
        print(f"{along} mm along x, {DOWN} down, {increments} increments, mu {mu}")
        finals = []
        for label, exact in (("anchor held (before)", False), ("anchor moving (exact)", True)):
            result, landings = solve(along, increments, mu, exact)
            counts = result.info["iterations_per_increment"]
            print(f"  {label}: converged {result.converged}, iterations {counts} (total "
                  f"{sum(counts)}), landing points per increment {landings}")  # fmt: skip
            for k, ratios in enumerate(result.info["residual_history"], start=1):
                constants = " ".join(f"{c:.2g}" for c in quadratic_constants(ratios))
                print(f"    increment {k}: ratios {' '.join(f'{r:.1e}' for r in ratios)}"
                      f" | r_k+1 / r_k^2 {constants}")  # fmt: skip
            finals.append(result.frames[-1].positions)
        print(f"  the final positions {np.abs(finals[0] - finals[1]).max():.2e} mm apart")


if __name__ == "__main__":
    main(sys.argv[1:])
