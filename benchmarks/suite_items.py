"""The CPU of the test suite's items whose set-up was made cheaper, old set-up beside new, in
one process on numba's warm cache (run it twice in a fresh checkout: the first pass compiles).

* tests/test_bias_extension.py, the pin-jointed net's pull (10-cell bias specimen, fibres of
  1.2e5 N/mm): Static along the arc length at its default 10 increments (the old set-up)
  against the load path in 4 increments (the new one), both without the stability check; the
  largest relative error of the shear angle of zones A and B against the net (the tests'
  tolerance 2e-3) shows that both reach the same state.
* tests/test_forming_shortcuts_change_nothing.py: one explicit run of the 12-cell forming case
  (``formed``); the module made 6 of them, then 4 (the run with every shortcut on shared), now
  2 (benchmarks/suite_item_cpu.py).

Measured (one numba and BLAS thread, 2 cores shared with other jobs, load 4.2): the pull
0.96 s of CPU along the arc length (10 + 1 increments, 4 Newton iterations each) against
0.31 s by the load path (4 increments, 3 iterations each), errors 1.78e-4 (A) and 1.25e-4
(B) for both; one forming run 5.2 s (the module's 6 runs 30.9 s, 4 runs 20.6 s). Side by
side in one pytest process (load 2.8-3.9): the bias module 2.13 s of CPU old, 0.88 s new;
the forming module 28.0 s old, 21.4 s new; the rotated sliding plate of tests/test_contact.py
7.3 s over 1 ms, 3.6 s over 0.5 ms (load 3.7).

Where the time of these items goes in a fresh checkout is numba's compilation, not the
tests: the augmented-contact plate (tests/test_augmented_contact.py, first test) took 114.3 s
of CPU on a cold cache, 0.04 s warm (load 7); the fibrous rigid-motion conformance check
152.8 s cold, all of it compiling, 0.01-0.03 s warm. In a run of the tests not marked slow
(without the report's) on an empty cache, two workers at a load of 4-5, the pin-jointed net's
pull (load path) took 351.9 s of CPU, 351.6 s of it compiling the fibrous tangent's kernels,
while the other worker waited 460 s for them on the compile lock (femcore/compile_lock.py) in
a test of tests/test_compare.py (31.7 s of CPU in 494 s); of the workers' 720 s of CPU,
470 s were numba's compilations.

Run: python benchmarks/suite_items.py
"""

import os
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from materials import Fabric, ShearLaw  # noqa: E402
from solvers import Static  # noqa: E402
from tests.test_bias_extension import LENGTH, PULL, WIDTH, bias_specimen  # noqa: E402
from tests.test_forming_shortcuts_change_nothing import formed  # noqa: E402
from validation import specimens  # noqa: E402

FABRIC = Fabric(
    thickness=0.3, areal_density=2.85e-10, tension=1.2e5, shear=ShearLaw.linear(0.2), bending=7.5
)


def pull(**options) -> tuple[float, float, float, list[int]]:
    """The bias pull by Static(**options): (CPU s, zone A's and zone B's largest relative
    error against the net, Newton iterations per increment)."""
    mesh, model = bias_specimen(FABRIC)
    started = time.process_time()
    result = Static(seek_stable=False, progress=False, **options).solve(model)
    cpu = time.process_time() - started
    centres = mesh.points[mesh.triangles].mean(axis=1)
    x, off_axis = centres[:, 0], np.abs(centres[:, 1] - WIDTH / 2)
    clamped = (x < WIDTH / 2 - off_axis) | (x > LENGTH - WIDTH / 2 + off_axis)
    central = np.abs(x - LENGTH / 2) < WIDTH / 2 - off_axis
    shear = np.abs(result.frames[-1].fields["triangle"]["shear_angle_deg"]).mean(axis=1)
    net = np.degrees(specimens.pin_jointed_shear(LENGTH, WIDTH, PULL))
    error_a = float(np.abs(shear[central] / net - 1).max())
    error_b = float(np.abs(shear[~central & ~clamped] / (net / 2) - 1).max())
    return cpu, error_a, error_b, result.info["iterations_per_increment"]


def main() -> None:
    print(f"load before: {os.getloadavg()[0]:.1f}")
    pull(increments=1)  # numba's kernels loaded (or compiled) outside the timings
    for label, options in (
        ("arc length, 10", {"path": "arc_length"}),
        ("load, 4", {"increments": 4}),
    ):
        cpu, error_a, error_b, iterations = pull(**options)
        print(f"bias pull, {label:14s}: CPU {cpu:5.2f} s, error A {error_a:.2e}, "
              f"B {error_b:.2e} (tolerance 2e-3), iterations {iterations}")  # fmt: skip
    started = time.process_time()
    formed()
    one = time.process_time() - started
    print(
        f"forming run: CPU {one:.1f} s; the module: 6 runs {6 * one:.1f} s, 4 runs {4 * one:.1f} s"
    )
    print(f"load after: {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
