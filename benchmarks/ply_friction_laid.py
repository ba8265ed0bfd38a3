"""Static on a ply laid on a ply held whole with Coulomb friction (mu = 0.2): the stick
spring k_t = W''(g), the normal law's own stiffness (PlyContact's ``stick="normal law"``, the
default, elements/ply_friction.py), against k_t = k_p, the point's penalty, at any normal force
(``stick="penalty"``, the default before), side by side in one run.

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

Made the default once the explicit hemisphere-plies case was understood (validation/studies/
hemisphere_plies.py, coarse [0/45]; docs/hemisphere_plies.md, "The holder's penetration"). There
"normal law" put the top ply's face 0.45 mm through the holder (0.16 mm with k_p), past the 0.3
mm (one ply) of tests/test_hemisphere_plies.py. Found (the holder's contact forces recorded
every step): the holder contact's penalty penetration f / k at the top ply's corner node, a
wrinkle's crest thrown up at 2.6 m/s at t = 0.086-0.089 s carrying 10.1 N of the holder's 35-N
reaction on its automatic spring k = 13.3 N/mm (a light node's: 0.1 m (2 / dt)^2), 8.9 mm above
the bottom ply and in no ply contact, with no point of either ply contact pass on the normal
law's ramp, where alone the two springs differ (and past the outline, where W'' takes the
fade's w). The run is chaotic: with each spring scaled by 1, 1 +- 0.001, 0.002, 0.003 (one
thread, one run at a time, 42-51 s of CPU each, load 6-10) the largest rise through the holder
over the plies is 0.165, 0.181, 0.321, 0.342, 0.175, 0.247, 0.225 mm with k_p and 0.446, 0.206,
0.304, 0.159, 0.819, 0.222, 0.373 mm with W'' (the two largest at the same corner crest, t =
0.089 s; medians 0.23 and 0.30 mm): a ply thickness passed in 2 and 4 of the 7 runs, and seven
runs a spring do not tell them apart (rank sum p ~ 0.3); the holder's travel 8.35-10.56 and
9.76-10.67 mm. The check now bounds each node's rise by its spring's penetration under the
holder's whole force F / k (the largest share rise k / F: 0.27-0.60 with k_p, 0.28-0.54 with
W''), which a ply the holder does not hold fails (its 17.9 mm, 13 F / k, before the holder
pressed both plies). The report's coarse case before / after: docs/hemisphere_plies.md.

Measured (one thread, 2 cores shared, load 1.8 before, 3.3 after), stick "penalty" (the
default before, to the bit) | "normal law":
Newton iterations (per increment), cuts, CPU ("fails": the 1st increment, in 8 cuts)
    on top, Static()            fails, 7.8 s | 39 [11, 4, 3 x 8], no cut, 0.8 s
    on top, 100 iterations      150 [88, 24, 5 x 6, 4, 4], 2.7 s | 39 as above, 0.8 s; the
                                final positions 6.7e-7 mm apart
    overhang, Static()          71 [17, 12, 5, 5, 6, 6, 6, 5, 3, 6], 1.0 s | 63 [17, 4, 4, 6,
                                8, 5, 5, 4, 5, 5], 0.9 s; 2.4e-8 mm apart (100 iterations: the
                                same)
With k_t = W'' forced on every ply contact (load 4.8-5.9), benchmarks/ply_fade_hessian.py's
pulled 2 plies (penalty 1 N/mm, pressed past the ramp) and [0/45] layup holder: 13 and 6
iterations, the final positions the same to the bit. The on-top ply with friction rests
within 8.2e-7 mm of the frictionless one (39 iterations too), against a 6.1e-6 mm in-plane
motion of its lower face there (tests/test_ply_overhang.py).

The stick spring W'' as a potential (its normal force w W''' |s|^2 / 2 along dg/dz and
W'' |s|^2 / 2 dw/dz past the outline carried by the loads and the tangent: docs/theory.md,
"Friction between plies"), "normal law" before | after, the same run's two code trees side by
side (one thread, load 12): on top, Static() 39 [11, 4, 3 x 8] | 40 [11, 4, 4, 3 x 7], no
cut, 0.78 | 0.82 s, the final positions 9.2e-8 mm apart (within 9.1e-7 mm of the
frictionless ply, 8.2e-7 before); overhang, Static() 63 [17, 4, 4, 6, 8, 5, 5, 4, 5, 5] | 62
[17, 6, 4, 9, 3, 7, 5, 5, 3, 3], no cut, 0.69 | 0.76 s, 1.2e-12 mm apart (100 iterations: the
same). "penalty" adds nothing (E = k_p |s|^2 / 2 holds no g).

Run: python benchmarks/ply_friction_laid.py
"""

from __future__ import annotations

import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this tree's packages

from solvers import Static

sys.path.insert(0, str(Path(__file__).parent))
import ply_fade_hessian as others  # noqa: E402  (the kernels' warm-up)
import ply_overhang  # noqa: E402  (the two plies)


def two_plies(shift: float, stick: str, **settings):
    """The two plies with friction 0.2 (``shift`` as ply_overhang.two_plies) and the stick
    spring ``stick``, by Static with ``settings``."""
    model = ply_overhang.two_plies(shift, friction=0.2, stick=stick)[0]
    return Static(progress=False, **settings).solve(model)


def main() -> None:
    others._sag()  # the kernels compiled (or loaded from numba's cache) before any timing
    print(f"load before {os.getloadavg()[0]:.1f}", flush=True)
    cases = [
        ("on top, Static()", 5.0, {}),
        ("on top, 100 iterations", 5.0, {"max_iterations": 100}),
        ("overhang, Static()", -4.0, {}),
        ("overhang, 100 iterations", -4.0, {"max_iterations": 100}),
    ]
    for name, shift, settings in cases:
        finals = {}
        for label, stick in (("penalty", "penalty"), ("normal", "normal law")):
            start = time.process_time()
            try:
                result = two_plies(shift, stick, **settings)
                its = list(result.info["iterations_per_increment"])
                text = f"{sum(its)} iterations {its} cuts {result.info['cuts']}"
                finals[label] = result.positions
            except Exception as error:  # a failed solve is a figure too
                text = f"stopped: {error}"[:100]
            cpu = time.process_time() - start
            print(f"{name:26s} {label:6s} {text} CPU {cpu:.1f} s", flush=True)
        if len(finals) == 2:
            apart = float(np.abs(finals["penalty"] - finals["normal"]).max())
            print(f"{name:26s} final positions apart by {apart:.3g} mm", flush=True)
    print(f"load after {os.getloadavg()[0]:.1f}", flush=True)


if __name__ == "__main__":
    main()
