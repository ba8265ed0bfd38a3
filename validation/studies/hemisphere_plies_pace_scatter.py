"""The two-ply hemisphere's Mindlin [0/90] run (validation/studies/hemisphere_plies_run.py, 8
cells, holder 20 N) at several paces, each with its ply friction scaled by factors far below
any physical change (1 + 1e-6, ...): how far a run's measures scatter at one pace against how
far they move with the pace (tests/test_hemisphere_plies_pace.py compares single runs).

    python -m validation.studies.hemisphere_plies_pace_scatter [--slowings 2 4]
        [--mu-scales 0.999999 1 1.000001]

Per run, as the pace test takes them: the largest and the rms inter-ply slip at the end
(elements/ply_slip.py, mm), their median, each ply's draw-in of the edge middle and of the
corner (mm) and the punch's mean force over the last fifth of its travel (N); beside them the
largest slip's peak over the frames of the last 0.15 of the stroke's time, which shows a late
snap of the flange whether or not the run ends in it. Measured: the test's docstring.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from femcore.loads import smooth_step
from validation.studies import hemisphere_plies_run as study
from validation.studies import hemisphere_plies_setup as setup

LATE_WINDOW = 0.85  # the share of the stroke's time past which the late peak is taken


def measures(slowing: float, mu_scale: float) -> dict[str, float]:
    """The Mindlin [0/90] run with its stroke slowed ``slowing`` times past the case's 0.1 s
    and its ply friction ``mu_scale`` times the case's: its measures (module docstring)."""
    keep_slowing, keep_mu = study.STROKE_SLOWING, setup.MU
    study.STROKE_SLOWING = {**keep_slowing, ("0/90", "mindlin"): slowing}
    setup.MU = keep_mu * mu_scale  # setup.model reads it when the run builds its layup
    try:
        found, _, _, result, *_ = study.run(8, "0/90", "mindlin", setup.HOLDER_FORCES[0])
    finally:
        study.STROKE_SLOWING, setup.MU = keep_slowing, keep_mu
    prefix = f"0-90_mindlin_{setup.HOLDER_FORCES[0]:g}_N"
    times = np.array([frame.time for frame in result.frames]) / (study.DURATION * slowing)
    late = smooth_step(np.clip(times, 0.0, 1.0)) >= 0.8
    slips = np.abs([frame.fields["point"]["ply_slip"] for frame in result.frames])
    end = slips[-1][np.isfinite(slips[-1])]
    out = {
        "largest slip": found[f"{prefix}_interply_slip_max_mm"],
        "rms slip": found[f"{prefix}_interply_slip_rms_mm"],
        "median slip": float(np.median(end)),
        "late peak": float(np.nanmax(slips[times >= LATE_WINDOW])),
        "late force": float(np.mean(result.tool_forces[late, 1, 2])),
    }
    for k, angle in ((1, 0), (2, 90)):
        ply = f"{prefix}_ply{k}_{angle}deg"
        out[f"ply {k} edge"] = found[f"{ply}_draw_in_edge_middle_mm"]
        out[f"ply {k} corner"] = found[f"{ply}_draw_in_corner_mm"]
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--slowings", type=float, nargs="+", default=[2.0, 4.0])
    parser.add_argument("--mu-scales", type=float, nargs="+", default=[1 - 1e-6, 1.0, 1 + 1e-6])
    args = parser.parse_args()
    for slowing in args.slowings:
        for scale in args.mu_scales:
            start = time.process_time()
            found = measures(slowing, scale)
            cpu = time.process_time() - start
            row = ", ".join(f"{key} {value:.4f}" for key, value in found.items())
            print(f"x{slowing:g}, mu x {scale!r}: {row} ({cpu:.1f} s CPU)", flush=True)


if __name__ == "__main__":
    main()
