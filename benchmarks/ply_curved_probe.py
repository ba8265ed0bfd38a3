"""A trial, not the project's method: Static's curved steps (solvers/newton_curvature.py) on
the weight-carrying ply stacks with the ply contact's law held at its second-order expansion
about the iterate while the path's second derivative is probed, against the curved steps as
they are (``Static(curved_with_contact=True)``) and the cases' own straight steps, side by
side in this process; the Newton iterations per increment, tangents and CPU (one thread).

Why: the curved step probes the residual at +-h of the step (h = 1e-2) for D = d^2 r / dt^2.
The contact's share of D is W''' (grad g . delta)^2 grad g (the law's own curvature: on the
smoothed ramp W''' = -k / delta, and points that step on or off the ramp within the probe) +
2 W'' (grad g . delta) (d grad g / dt) + W' d^2 grad g / dt^2 (the geometry's: the faces turning
with the plies). The first is no part of the path's curvature that the step should follow,
and it dwarfs the rest (k / delta ~ 1e6-1e7 N/mm^2); held at W(g0) + W'(g0)(g - g0) +
W''(g0)(g - g0)^2 / 2 over the iterate's touching points, the probes see the geometry's
terms alone. Without the probes' law the contact is today's everywhere (the forces, the
tangent, the line search); the plies with their contact zeroed take 43 iterations curved
where the 4-ply heavy stack with today's contact takes 252 and 34 cut
(benchmarks/ply_newton_table.py ``--heavy-plies --curved``).

    python benchmarks/ply_curved_probe.py [--cases heavy,sag,bai] [--resolution coarse]

The flat faces' numpy loads (``ply_projection.COMPILED`` off inside the ply loads, on every
side alike); frictionless stacks only. The deck-of-cards' heavy stack (``sag``) takes no
curved step here (its solver is not given ``curved_with_contact``).

Measured (coarse, one thread, CPU, load 5.7-5.9; straight -> curved -> curved with the
probes' law held; tangents):

* heavy (the case's cap 0.03 rad): 125 (29-33-29-19-15) -> 316 (45-101-46-32-47, 42 cut) ->
  294 (32-99-46-33-50, 32 cut); without the cap, curved 252 + 34 cut (55-100-44-36-17) ->
  held 248 + 80 cut (35-35-44-37-17).
* bai: 271 (82-19-18-18-18-8-11-10-8-12 in the displacement phase) -> 599 (145-49-21-19-30-
  18-17-15-9-28, 187 cut) -> 462 (115-41-19-18-25-18-22-16-10-13, 106 cut); its gravity
  phase curved 23-4-4-3-3-3-3-3-3-3 either way (straight 21-5-4-4-4-3-3-3-3-3).
* The final positions within 6e-12 mm of the straight steps'.

Not kept: the held law takes a quarter of the curved steps' excess on bai and less on heavy,
and both stay at 2.3-1.7 x the straight steps' tangents. The law's own curvature in the
probes is not what spoils the curved steps with contact.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

import solvers.newton as newton_module  # noqa: E402
from benchmarks.ply_newton_table import CASE_RULES  # noqa: E402
from benchmarks.ply_simple_root import TODAY, use  # noqa: E402
from benchmarks.static_plies_case import solve_case  # noqa: E402
from elements import ply_block  # noqa: E402

PLAIN_PAIRS = ply_block.PlyContactBlock._pair_loads
PLAIN_CURVED = newton_module.curved_step
# per block: "capture" (record the law at this state) or (on, g0, W, W', W'') (the probes')
PROBE: dict = {}


def pair_loads(self, state, facing):
    """``PlyContactBlock._pair_loads`` with the law recorded at the iterate (``PROBE`` set to
    "capture") or held at its expansion about it (the probes'; module docstring)."""
    mode = PROBE.get(id(self))
    if mode is None:
        return PLAIN_PAIRS(self, state, facing)
    if isinstance(mode, str):
        out = PLAIN_PAIRS(self, state, facing)
        on, law = out[3], out[5]
        PROBE[id(self)] = (on, facing.gap[on].copy(), *(np.copy(part) for part in law))
        return out
    on, g0, w0, w1, w2 = mode
    change = facing.gap[on] - g0
    law = (w0 + w1 * change + 0.5 * w2 * change**2, w1 + w2 * change, w2.copy())
    n, lam = facing.normal[on], facing.weights[on]
    tri = facing.triangle[on]
    nodes = np.column_stack([self.above[on], self.cells[tri]])
    fade, fading = ply_block._fade(facing, on)
    on_face = (fade * law[1])[:, None] * n + law[0][:, None] * fading[:, 0]
    forces = np.concatenate(
        [
            self.shape[on][:, :, None] * on_face[:, None, :],
            -(fade * law[1])[:, None, None] * lam[:, :, None] * n[:, None, :]
            + law[0][:, None, None] * fading[:, 1:4],
        ],
        axis=1,
    )
    d = self.offset_directions(state)[nodes]
    offset = self.lever * np.column_stack([-self.upper_offset[on], self.corner_offset[tri]])
    moments = offset[:, :, None] * ply_block.cross(d, forces)
    return nodes, forces, moments, on, offset, law


def curved_step(run, equilibrium, state, frames, delta, r, factor):
    """solvers.newton_curvature.curved_step with the ply contact's law held in its probes."""
    blocks = [b for b in run.model.interactions if isinstance(b, ply_block.PlyContactBlock)]
    for block in blocks:
        PROBE[id(block)] = "capture"
    try:
        equilibrium.residual(state, frames)  # the law at the iterate, recorded
        return PLAIN_CURVED(run, equilibrium, state, frames, delta, r, factor)
    finally:
        PROBE.clear()


def held(on: bool) -> None:
    """The probes' law held (``on``) or today's (the curved steps as they are)."""
    ply_block.PlyContactBlock._pair_loads = pair_loads if on else PLAIN_PAIRS
    newton_module.curved_step = curved_step if on else PLAIN_CURVED


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cases", default="heavy,sag,bai")
    parser.add_argument("--resolution", default="coarse")
    args = parser.parse_args()
    print(f"load before (1, 5, 15 min): {np.round(os.getloadavg(), 2).tolist()}")
    use(TODAY, None)  # the numpy loads on every side
    for name in args.cases.split(","):
        stall, first_turn = CASE_RULES[name]
        sides = (("straight", None, False), ("curved", True, False), ("curved, held", True, True))
        results = {}
        for label, curved, hold in sides:
            held(hold)
            cpu = time.process_time()
            try:
                result = solve_case(name, args.resolution, stall, first_turn, "case", curved)
            except Exception as failure:  # a failed solve is a figure too
                print(f"{name} {label}: failed: {str(failure)[:200]}", flush=True)
                continue
            finally:
                held(False)
            cpu = time.process_time() - cpu
            info = result.info
            print(
                f"{name:5s} {args.resolution} {label:13s}: {info['iterations_per_increment']}, "
                f"{result.steps} + {info['iterations_cut']} cut, "
                f"{info['evaluations']['tangent']} tangents, {info['curved_steps']} curved, "
                f"{cpu:.1f} s CPU; load {np.round(os.getloadavg(), 2).tolist()}",
                flush=True,
            )
            results[label] = result
        if "straight" in results and "curved, held" in results:
            moved = np.abs(results["curved, held"].positions - results["straight"].positions)
            print(f"  final positions within {moved.max():.3g} mm of the straight steps'")


if __name__ == "__main__":
    main()
