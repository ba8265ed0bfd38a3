"""What mass and time scaling do to the hemisphere forming case's compared results
(validation/cases/hemisphere_forming.py ``run``): the rms shear error against the
pin-jointed net, the draw-in of the edge middle, the punch force at the end, the largest
kinetic energy over the work after the first tenth, the damping's share of the work, the
holder's lift, the steps and the CPU time, for each scaling beside the unscaled run at the
same resolution (the case's defaults are left as they are: the solver is given the scaling
for these runs only).

``--mass-scaling-dt`` targets (s) for the solver's selective mass scaling (cells whose step is
below it get their density raised to reach it); ``--time-scaling`` factors s: the stroke run
in DURATION / s (the punch s times faster, the damping c unchanged). Run from the project
root:

    python benchmarks/hemisphere_scaling.py --cells 20 --mass-scaling-dt none,2e-5
    python benchmarks/hemisphere_scaling.py --cells 20 --time-scaling 2

Time scaling measured at 20 cells on the case's 10-mm die (fibrous, one thread, CPU; load
5.5-6.8, the x4 run 5.4 -> 5.1), the stroke 1 / 2 / 4 times faster: 27677 / 13839 / 6921
steps (the step 1.03e-5 s in each), CPU 85 / 37 / 22 s; rms shear error against the net
2.138 / 2.147 / 2.148 deg, draw-in of the edge middle 28.54 / 28.71 / 24.28 mm, punch force
at the end 57.2 / 54.2 / 62.5 N, the largest KE / W after the first tenth 0.007 / 0.026 /
0.082 (none of the stroke above the 0.1 bound), 0.0015 / 0.0023 / 0.0062 at the end, the
damping 0.7 / 0.6 / 0.9 % of the work, the holder down (0 mm). Twice as fast changes the
compared results by 0.4 % (rms) and 0.6 % (draw-in); four times as fast leaves the rms but
draws the edge in 15 % less, with KE / W near its bound.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install
os.environ.setdefault("FIBRESHELL_PROGRESS", "0")

from validation.cases import hemisphere_forming as case  # noqa: E402


def measure(cells: int, scaling: float | None, speed: float) -> dict:
    """One run of the case at ``cells`` with the solver's ``mass_scaling_dt`` = ``scaling``
    and the stroke ``speed`` times faster (the case's own options); the case's ``run``
    record."""
    return case.run(cells, "fibrous", time_scaling=speed, mass_scaling_dt=scaling)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cells", type=int, default=20)
    parser.add_argument("--mass-scaling-dt", default="none", help='targets, s ("none": none)')
    parser.add_argument("--time-scaling", default="1", help="stroke speed-up factors")
    args = parser.parse_args()
    for target in args.mass_scaling_dt.split(","):
        for speed in (float(s) for s in args.time_scaling.split(",")):
            scaling = None if target.strip().lower() == "none" else float(target)
            start = time.process_time()
            out = measure(args.cells, scaling, speed)
            result = out["result"]
            info = result.info
            print(f"{args.cells} cells, mass_scaling_dt {scaling}, stroke x{speed:g} faster: "
                  f"converged {result.converged}, {result.steps} steps, dt {info['dt']:.3g} s, "
                  f"added mass {info['added_mass_ratio']:.3g}; rms {out['rms_deg']:.3f} deg, "
                  f"draw-in {out['draw_in_mm']:.2f} mm, punch {out['punch_force_N']:.1f} N, "
                  f"KE/W largest {out['largest_kinetic_over_work']:.3f} at end "
                  f"{out['kinetic_over_work']:.4f}, share above the bound "
                  f"{out['kinetic_exceeded_share']:.3f}, damping/W "
                  f"{out['damping_over_work']:.3f}, holder lift {out['holder_lift_mm']:.3f} mm; "
                  f"CPU {time.process_time() - start:.0f} s, wall {out['cost']['wall_s']:.0f} s, "
                  f"load {out['cost']['load'][0]:.1f} -> {out['cost']['load'][1]:.1f}",
                  flush=True)  # fmt: skip


if __name__ == "__main__":
    main()
