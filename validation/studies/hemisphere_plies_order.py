"""The observed order of the two-ply hemisphere's results on three resolutions of one stack and
one kinematics (validation/studies/hemisphere_plies_run.py ``run``): per ply the rms of shear -
net over its cells in the die (deg), the draw-in of the edge middle and of the corner (mm), and
the punch's force at the end (N), with the observed order p and the Richardson value of each
(``validation.checks.observed_order``: f(h) = f0 + C h^p through the three, for unequal
ratios), h the blank's cell (1 / cells).

The three are in the asymptotic range for a quantity when its differences keep their sign
(f1 - f2 and f2 - f3 alike: a monotone sequence, p defined) and p is that of the
discretisation (about 1 for a faceted contact and a first-order shear error, 2 for the
smooth parts of the shells): an order far from those, or differences of both signs, say the
meshes are not yet where the leading error term rules (wrinkles that appear or move between
resolutions, the outline's contact). Run it with ``python -m
validation.studies.hemisphere_plies_order fibrous 0/90 20 8 10 12`` (kinematics, stack,
holder force N, three cell counts); each run prints as it ends, one at a time. A count given
as ``8@path/results.json`` takes that run's figures from a report's records (``python -m
validation --cases hemisphere-plies``, whose coarse and default resolutions run 8 cells)
instead of running it again.

Measured (docs/hemisphere_plies.md, "Three resolutions"; one thread, load 5-9): fibrous [0/90]
at 20 N on 8, 10 and 12 cells, 46.0, 74.8 and 114.9 s of CPU, every check passing; rms of shear
- net 3.462, 3.168, 2.832 deg (ply 1) and 3.507, 3.191, 2.842 (ply 2), p -1.68 and -1.50; the
draw-in of the edge middle 24.91, 27.35, 29.64 mm and 25.11, 27.51, 29.80, p -0.70 and -0.78;
the corner's 4.81, 6.06, 5.99 and 4.88, 6.11, 6.04 (no order); the punch's force 86.97, 89.49,
96.82 N, p -6.39: not in the asymptotic range. On 14 and 16 cells (150.6 and 194.3 s, load
1-9, every check passing): rms 2.347 and 2.115 deg (ply 1), the order of 12-14-16 about 4
(above any order of the discretisation); the draw-in of the edge middle 23.34 and 24.95 mm,
one of two states (24-25 or 27-30 mm) whichever the resolution, no order (docs/hemisphere_plies.md).

The per-cell rms changes its set of cells with the mesh, and the edge middle is one node of a
fibre that lifts or not into the flange's free annulus: validation/studies/
hemisphere_plies_convergence.py measures the shear field at fixed material points on the
punch, the fibres along the symmetry planes' state and the punch's work on 8 to 20 cells (22
and 24 stop before the end of the stroke), with the orders of every three consecutive
resolutions (docs/hemisphere_plies.md, "Converged results").
"""

from __future__ import annotations

import sys
import time
from typing import Any

from validation.checks import observed_order

__all__ = ["QUANTITIES", "measure", "orders"]

#: The quantities of a ply (the run's parameter after ``<run>_ply<k>_<angle>deg_``) and of the
#: run (after ``<run>_``) whose order is observed.
QUANTITIES = (
    "rms_shear_error_deg",
    "draw_in_edge_middle_mm",
    "draw_in_corner_mm",
)
RUN_QUANTITIES = ("punch_force_N", "holder_force_last_tenth_mean_N")


def measure(kinematics: str, name: str, force: float, cells: int) -> dict[str, Any]:
    """One run's figures: {quantity label: value}, its checks (label, passed), whether it
    stopped, its steps and CPU time (s)."""
    from validation.studies.hemisphere_plies_run import run, run_key
    from validation.studies.hemisphere_plies_setup import LAYUPS

    start = time.process_time()
    parameters, checks, *_ = run(cells, name, kinematics, force)
    cpu = time.process_time() - start
    key = run_key(name, kinematics, force).replace(" ", "_").replace("/", "-")
    values = _values(parameters, key, LAYUPS[name])
    return {
        "values": values,
        "checks": [(c.name, bool(c.passed)) for c in checks],
        "stopped": [v for k, v in parameters.items() if k.endswith("stopped")],
        "steps": parameters.get(f"{key}_steps"),
        "cpu_s": cpu,
    }


def recorded(kinematics: str, name: str, force: float, path: str, cells: int) -> dict[str, Any]:
    """``measure``'s figures of the run of a report's records (results.json at ``path``), whose
    run must be of ``cells`` across the blank."""
    import json

    from validation.studies.hemisphere_plies_run import NAME, run_key
    from validation.studies.hemisphere_plies_setup import LAYUPS

    with open(path) as file:
        case = json.load(file)["cases"][NAME]
    parameters = case["parameters"]
    made = [int(text.split()[0]) for text in parameters["cells"]]
    if made != [cells]:
        raise ValueError(f"{path} holds runs of {made} cells across the blank, not of {cells}")
    key = run_key(name, kinematics, force).replace(" ", "_").replace("/", "-")
    values = _values(parameters, key, LAYUPS[name])
    run = run_key(name, kinematics, force)
    checks = [(c["name"], bool(c["passed"])) for c in case["checks"] if c["name"].startswith(run)]
    stopped = [v for k, v in parameters.items() if k.startswith(run) and k.endswith("stopped")]
    return {
        "values": values,
        "checks": checks,
        "stopped": stopped,
        "steps": parameters.get(f"{key}_steps"),
        "cpu_s": float(parameters.get(f"{key}_cpu_time_s", float("nan"))),
    }


def _values(parameters: dict[str, Any], key: str, layup: Any) -> dict[str, float]:
    """{quantity label: value} of the run ``key`` read from its parameters, each ply's
    ``QUANTITIES`` and the run's ``RUN_QUANTITIES``."""
    values: dict[str, float] = {}
    for k, angle in enumerate(layup):
        ply = f"{key}_ply{k + 1}_{angle:g}deg"
        for quantity in QUANTITIES:
            values[f"ply {k + 1} ({angle:g} deg) {quantity}"] = float(
                parameters[f"{ply}_{quantity}"]
            )
    for quantity in RUN_QUANTITIES:
        values[quantity] = float(parameters[f"{key}_{quantity}"])
    return values


def orders(cells: list[int], runs: list[dict[str, Any]]) -> dict[str, tuple[float, float]]:
    """{quantity: (p, Richardson value)} over three runs at ``cells`` (increasing), h = 1 /
    cells (NaN where the differences change sign or vanish)."""
    sizes = [1.0 / c for c in cells]
    return {
        label: observed_order(sizes, [r["values"][label] for r in runs])
        for label in runs[0]["values"]
    }


def _arguments(argv: list[str] | None = None) -> Any:
    """The command line: kinematics, stack, holder force (N) and three increasing cell
    counts, each optionally ``count@results.json``."""
    import argparse

    from validation.studies.hemisphere_plies_run import RMS_TOLERANCE_DEG
    from validation.studies.hemisphere_plies_setup import LAYUPS

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("kinematics", choices=("fibrous", "mindlin"))
    parser.add_argument("stack", choices=tuple(LAYUPS))
    parser.add_argument("force", type=float, help="the holder's force, N")
    parser.add_argument(
        "cells", nargs=3, help="three increasing cell counts; count@results.json reads a report"
    )
    arguments = parser.parse_args(argv)
    counts = []
    for text in arguments.cells:
        count = text.split("@")[0]
        if not count.isdigit() or int(count) < 1:
            parser.error(
                f"a cell count must be a positive integer (count or count@path), got {text!r}"
            )
        counts.append(int(count))
    if not counts[0] < counts[1] < counts[2]:
        parser.error(f"the three cell counts must increase, got {counts}")
    checked = sorted(RMS_TOLERANCE_DEG)
    if arguments.kinematics == "fibrous" and not set(counts) <= set(checked):
        # a fibrous run's rms check needs its tolerance: found missing only after the solve
        parser.error(
            f"fibrous runs are checked at {checked} cells (RMS_TOLERANCE_DEG), got {counts}"
        )
    arguments.counts = counts
    return arguments


if __name__ == "__main__":
    arguments = _arguments()
    kinematics, name, force = arguments.kinematics, arguments.stack, arguments.force
    resolutions, given = arguments.counts, arguments.cells
    done = []
    for count, text in zip(resolutions, given):
        if "@" in text:
            outcome = recorded(kinematics, name, force, text.split("@", 1)[1], count)
        else:
            outcome = measure(kinematics, name, force, count)
        done.append(outcome)
        print(f"{count} cells: cpu {outcome['cpu_s']:.1f} s, steps {outcome['steps']}")
        print("  stopped:", outcome["stopped"] or "no")
        for label, passed in outcome["checks"]:
            print("  PASS" if passed else "  FAIL", label)
        for label, value in outcome["values"].items():
            print(f"  {label}: {value:.4f}")
        sys.stdout.flush()
    print("quantity: values (coarse to fine), observed order p, Richardson value")
    for label, (p, f0) in orders(resolutions, done).items():
        values = ", ".join(f"{r['values'][label]:.4f}" for r in done)
        print(f"  {label}: {values}; p = {p:.3f}, f0 = {f0:.4f}")
