"""Static on a ply laid on a ply held whole: the line search's backtracking from an
increment's first iterate in a model with interactions down to 1e-9 of the step
(solvers/line_search.py, ``SMALLEST_FIRST_STEP``) against the code before (1/64, as from any
other iterate), side by side in one run.

The model (benchmarks/ply_fade_hessian.py's ``_overhang``, tests/test_ply_overhang.py): an
upper Mindlin ply (10 x 10 mm, 6 x 6 cells, h = 0.5 mm, bending 0.05 N mm, 1e-8 t/mm^2)
clamped at its edge of largest y, laid on a lower ply (20 x 20 mm, 4 x 4 cells) held whole,
mid-surfaces 0.5 mm apart (the faces touch, g = 0), under gravity; "overhang": 4 mm past the
lower ply's outline edge y = 0; "on top": wholly on it (its edge at y = 5).

Why the code before failed: the automatic penalty (0.1 m (2/dt)^2, dt = 4.30e-6 s the plies'
critical step) is 100-600 N/mm per upper node (corner, edge, inside), some 1e4 times the
ply's bending stiffness per node (D / L^2 ~ 0.02 N/mm). That is not wrong in itself: the
equilibrium's deepest points are 2.6e-5 mm (on top) and 7.8e-5 mm (overhang) into the lower
ply's face, and the solve converges with it once past the first step. Neither the fade band
nor the outline is the cause (the on-top model, no point near the outline, failed alike),
nor an indefinite tangent (no negative pivot in the failed attempts' tangents, on top at
1/2048 of the load). The smoothed penalty's ramp has W'' = 0 at g = 0, so the first Newton
step sees no contact and drops the upper ply by its free sag, 2.48 mm at the full load
(1.21e-3 mm at 1/2048 of it), through the lower ply, where the contact's forces are orders
of magnitude above the load. The watchdog keeps the increment's start as the best iterate
(residual 7e-7 N against 1.3 N after the step at 1/2048 of the load, on top), and its
backtracking, down to 1/64 of the step, stays far too deep: the line search failed, and
halving the load did not help (the sag falls as the load, the ramp's penetration as its
square root). The first increment's attempt at 1/2048 of the load, on top: residual ratios
0.168, 0.40, 0.40, 0.40, 0.40, the deepest point at each iterate 1.1e-3, 2.5e-4, 1.3e-4,
6.4e-5 mm (Newton halving it on the ramp's cubic energy), then "the line search found no
step". With penalty = 10 the overhang converged (67 iterations, 7 cuts) and the on-top model
did not.

Tried and not kept: (1) the tangent taking k at points laid on the face (0 <= g <= 1e-12 of
the model's size, where the ramp's W'' = 0): overhang 50 iterations [14, 4 x 9], on top 38,
no cut, but the 2-ply deck of cards 130 -> 235 iterations (115 in its first increment: plies
bent by their own moments open where the tangent held them laid) and the heavy stack 2 -> 3
cuts; over the band 1e-9 of the size it stalled the 4-ply sag (ratio 6.5e-4, a cut), and
with k on the penetrating side too (-1e-9 size <= g < 0) the sag failed (ratio 1e-3 after 8
cuts): frictionless plies sagging together sit at g ~ 0 with nearly no force, the reason for
the ramp (docs/theory.md). (2) smoothing = 0 (the plain penalty, laid points touching with k):
overhang 9 then 4 iterations per increment, on top 1, but the 4-ply sag needs the ramp. (3)
the backtracking to 1e-9 from every iterate: the same here, and the deck (130 -> 139, 1 -> 0
cuts) and the heavy stack (237 -> 274, 2 -> 0 cuts) changed paths; from the first iterate
alone, every case that converged before keeps its iterations to the bit.

Measured (one thread, 2 cores shared, load 2.4 before, 2.0 after), code before | now:
Newton iterations (per increment), cuts, CPU ("fails": the 1st increment, in 8 cuts)
    overhang, Static()          fails, 0.8 s | 53 [17, 4 x 9], no cut, 0.7 s
    on top, Static()            fails, 0.5 s | 39 [11, 4, 3 x 8], no cut, 0.3 s
    overhang, (*)               fails, 0.8 s | 46 [18, 4 x 7], no cut, 0.6 s
    on top, (*)                 fails, 0.6 s | 33 [11, 4, 3 x 6], no cut, 0.3 s
    overhang, (*), penalty 10   67 [40, 4, 4, 3, 4 x 4], 7 cuts, 1.3 s | 41 [14, ...], 0.5 s
    on top, (*), penalty 10     fails, 0.5 s | 33 [11, 4, 3 x 6], no cut, 0.3 s
    sag 4 plies, pulled 2 plies, layup holder, deck 2 plies, heavy stack 4 plies: 23, 13, 6,
    130 (1 cut), 237 (2 cuts) iterations | the same, the final positions the same to the bit
    bai-5.1 4 plies, coarse (ply_fade_hessian's ``_bai``, not in the run below: 24 s a pass):
    358 iterations, 6 cuts, 21.8 s | the same to the bit, 20.5 s
(*) benchmarks/ply_fade_hessian.py's settings: 8 increments, seek_stable=False, 100 iterations.
The overhang's tip hangs 0.090 mm below the upper ply's plane (lowest z 0.410246 mm), its
deepest point 7.8e-5 mm into the lower ply's face (5.5e-4 mm with penalty 10), within 8.9e-16
mm of the answer penalty 10 gave before for that penalty. First increment's residual ratios
now, overhang at Static's defaults: 0.17, 0.40, 0.40, 0.43, 0.58, 0.18, 0.94, 0.32, 0.40, 0.29,
0.23, 0.26, 0.058, 0.038, 0.012, 7.1e-4, 1.6e-5, 7.3e-9 (the first step backed off, then
Newton on the ramp's cubic energy, then quadratic).

Run: python benchmarks/ply_overhang.py
"""

from __future__ import annotations

import os
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this tree's packages

import solvers.line_search as line_search
from femcore import Model
from solvers import Static
from validation.studies import ply_overhang_setup as setup

sys.path.insert(0, str(Path(__file__).parent))
import ply_fade_hessian as others  # noqa: E402  (the other Static cases of the plies)

_deepest = line_search.SMALLEST_FIRST_STEP


def use(before: bool) -> None:
    """The code before (``before``: the first iterate's backtracking stops at 1/64 of the
    step too) or now."""
    line_search.SMALLEST_FIRST_STEP = line_search.SMALLEST_STEP if before else _deepest


def two_plies(
    shift: float, penalty: float | None = None, friction: float = 0.0, stick: str = "penalty"
) -> tuple[Model, int]:
    """The upper ply's edge of least y at ``shift`` mm (-4: overhanging, 5: on top); the
    penalty given, or the automatic one for None; the plies' Coulomb coefficient
    ``friction`` and stick spring ``stick``. Returns the model and the upper ply's first node."""
    options = {} if penalty is None else {"penalty": penalty}
    model, first, _ = setup.two_plies(shift, friction=friction, stick=stick, **options)
    return model, first


def solve_two_plies(shift: float, penalty: float | None, defaults: bool):
    model, first = two_plies(shift, penalty)
    compiled = model.compile()
    block = compiled.interactions[0]
    if defaults:
        solver = Static(progress=False)
    else:  # benchmarks/ply_fade_hessian.py's settings
        solver = Static(increments=8, seek_stable=False, max_iterations=100, progress=False)
    result = solver.solve(compiled)
    state = replace(
        compiled.initial_state(), positions=result.positions, directors=result.directors
    )
    facing = block.facing(state)
    depth = f", deepest point {-facing.gap[facing.touching].min():.2g} mm"
    k = block.node_stiffness
    lowest = result.positions[first:, 2].min()
    note = f"penalty {k.min():.0f}-{k.max():.0f} N/mm a node, lowest z {lowest:.6f}{depth}"
    return result, note


def _run(name, build):
    finals = {}
    for label, before in (("before", True), ("now", False)):
        use(before)
        start = time.process_time()
        note = ""
        try:
            built = build()
            result, note = built if isinstance(built, tuple) else (built, "")
            stopped = "" if result.converged else "not converged"
        except Exception as error:  # a failed solve is a figure too
            result, stopped = None, f"stopped: {error}"[:110]
        cpu = time.process_time() - start
        if result is None:
            print(f"{name:30s} {label:6s} {stopped} CPU {cpu:5.1f} s", flush=True)
            continue
        iterations = list(result.info["iterations_per_increment"])
        first = ", ".join(f"{r:.2g}" for r in result.info["residual_history"][0])
        finals[label] = result.positions
        print(
            f"{name:30s} {label:6s} {sum(iterations):4d} iterations {iterations} cuts "
            f"{result.info['cuts']} CPU {cpu:5.1f} s {stopped}\n{'':37s}first increment's "
            f"ratios [{first}]{'; ' + note if note else ''}",
            flush=True,
        )
    use(False)
    if len(finals) == 2:
        apart = float(np.abs(finals["before"] - finals["now"]).max())
        print(f"{name:30s} final positions apart by {apart:.3g} mm", flush=True)


def main() -> None:
    others._sag()  # the kernels compiled (or loaded from numba's cache) before any timing
    print(f"load before {os.getloadavg()[0]:.1f}", flush=True)
    cases = [
        ("overhang, Static()", lambda: solve_two_plies(-4.0, None, True)),
        ("on top, Static()", lambda: solve_two_plies(5.0, None, True)),
        ("overhang, 8 increments", lambda: solve_two_plies(-4.0, None, False)),
        ("on top, 8 increments", lambda: solve_two_plies(5.0, None, False)),
        ("overhang, 8 incr., k = 10", lambda: solve_two_plies(-4.0, 10.0, False)),
        ("on top, 8 incr., k = 10", lambda: solve_two_plies(5.0, 10.0, False)),
        ("sag 4 plies", others._sag),
        ("pulled 2 plies", others._pulled),
        ("layup holder", others._holder),
        ("deck 2 plies", others._deck),
        ("heavy stack 4 plies", others._heavy),
    ]
    for name, build in cases:
        _run(name, build)
    print(f"load after {os.getloadavg()[0]:.1f}", flush=True)


if __name__ == "__main__":
    main()
