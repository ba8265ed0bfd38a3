"""Static on a ply laid on a ply held whole with Coulomb friction (mu = 0.2): the stick
spring k_t = W''(g), the normal law's own stiffness (elements/ply_friction.py,
``stick_spring``), against the code before (k_t = k_p, the point's penalty, at any normal
force), side by side in one run.

The model: benchmarks/ply_overhang.py's two plies (tests/test_ply_overhang.py), an upper
Mindlin ply clamped at one edge laid on a lower ply held whole, pressed by its weight, with
friction 0.2 between them; "on top" wholly on the lower ply, "overhang" 4 mm past its
outline.

Why the code before failed (on top, the first increment, Static's defaults: residual ratio
0.022 after 50 iterations, 8 cuts; with 100 iterations 88, 24, 5, ... per increment). The
plies start laid at g = 0, where every point is anchored with N = 0. At the equilibrium they
are 3e-5 mm deep, on the smoothed penalty's ramp (delta = 5e-4 mm), with N = k_p g^2 /
(2 delta) ~ 1e-5 N: the stick cone's radius mu N / k_p is ~1e-8 mm, while the face points'
in-plane motion from the directors' turn near the clamp is 6e-6 mm and a Newton iterate's
slips 1e-7 mm. Recorded per iteration (the friction tangent's calls, first increment): the
72 laid points all touching and anchored throughout (no point in or out of contact past the
3rd iteration bar one), 31 switching stick -> slip at the 3rd iteration, then 2-32 switches
every iteration for 85 iterations, 0-45 stuck, the sliding points' N 1e-6-3e-5 N and |s|
1e-7 mm: the slip force mu N s / |s| turns with s at |s| ~ 1e-7 mm, and each turn moves the
directors (moments a F) and so s by more than |s|. With k_t = W''(g) = k_p |g| / delta on the
ramp, the cone's radius is mu |g| / 2 ~ 3e-6 mm: the laid points stick, and the increment is
Newton on the normal law's own smoothing.

Before here emulates the code before by ``stick_spring`` -> (k_p, 0); past the outline it
then takes w k_p where the code before took k_p (the overhang's points in the fade band).

Measured (one thread, 2 cores shared, load 4.8 before, 5.9 after), code before | now:
Newton iterations (per increment), cuts, CPU ("fails": the 1st increment, in 8 cuts)
    on top, Static()            fails, 8.2 s | 39 [11, 4, 3 x 8], no cut, 0.8 s
    on top, 100 iterations      150 [88, 24, 5 x 6, 4, 4], 2.8 s | 39 as above, 0.8 s; the
                                final positions 6.7e-7 mm apart
    overhang, Static()          73 [17, 12, 5, 5, 5, 8, 3, 7, 5, 6], 1.0 s | 63 [17, 4, 4, 6,
                                8, 5, 5, 4, 5, 5], 0.9 s; 2.4e-8 mm apart (100 iterations: the
                                same). The code before itself (its commit, not emulated):
                                71 [17, 12, 5, 5, 6, 6, 6, 5, 3, 6], 2.4e-8 mm from now
    pulled 2 plies, layup holder [0/45]: 13 and 6 iterations | the same, to the bit
The on-top ply with friction rests within 8.2e-7 mm of the frictionless one (39 iterations
too), against a 6.1e-6 mm in-plane motion of its lower face there (tests/test_ply_overhang.py).

Run: python benchmarks/ply_friction_laid.py
"""

from __future__ import annotations

import os
import sys
import time
from pathlib import Path

import numpy as np

import elements.ply_friction as ply_friction
from solvers import Static

sys.path.insert(0, str(Path(__file__).parent))
import ply_fade_hessian as others  # noqa: E402  (the plies with friction of the tests)
import ply_overhang  # noqa: E402  (the two plies)

_now = ply_friction.stick_spring


def _penalty(gap, stiffness, smoothing):
    return np.array(stiffness, dtype=float), np.zeros(len(gap))


def use(before: bool) -> None:
    """The stick spring before (``before``: k_p) or now (W'')."""
    ply_friction.stick_spring = _penalty if before else _now


def two_plies(shift: float, **settings):
    """The two plies with friction 0.2 (``shift`` as ply_overhang.two_plies), by Static with
    ``settings``."""
    model = ply_overhang.two_plies(shift, friction=0.2)[0]
    return Static(progress=False, **settings).solve(model)


def main() -> None:
    others._sag()  # the kernels compiled (or loaded from numba's cache) before any timing
    print(f"load before {os.getloadavg()[0]:.1f}", flush=True)
    cases = [
        ("on top, Static()", lambda: two_plies(5.0)),
        ("on top, 100 iterations", lambda: two_plies(5.0, max_iterations=100)),
        ("overhang, Static()", lambda: two_plies(-4.0)),
        ("overhang, 100 iterations", lambda: two_plies(-4.0, max_iterations=100)),
        ("pulled 2 plies", others._pulled),
        ("layup holder [0/45]", others._holder),
    ]
    for name, build in cases:
        finals = {}
        for label, before in (("before", True), ("now", False)):
            use(before)
            start = time.process_time()
            try:
                result = build()
                its = list(result.info["iterations_per_increment"])
                text = f"{sum(its)} iterations {its} cuts {result.info['cuts']}"
                finals[label] = result.positions
            except Exception as error:  # a failed solve is a figure too
                text = f"stopped: {error}"[:100]
            cpu = time.process_time() - start
            print(f"{name:26s} {label:6s} {text} CPU {cpu:.1f} s", flush=True)
        use(False)
        if len(finals) == 2:
            apart = float(np.abs(finals["before"] - finals["now"]).max())
            print(f"{name:26s} final positions apart by {apart:.3g} mm", flush=True)
    print(f"load after {os.getloadavg()[0]:.1f}", flush=True)


if __name__ == "__main__":
    main()
