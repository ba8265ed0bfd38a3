"""The two-ply hemisphere's results against the plies' contact penalty (validation/studies/
hemisphere_plies_run.py ``run``): the automatic ply-on-ply penalty (elements/ply_contact.py,
"Penalty") multiplied by factors c after the model is compiled, the explicit step following
it (the penalty's springs enter the stable step, solvers/explicit.py), and per run each ply's
rms of shear - net over its cells in the die (deg), the draw-in of the edge middle and of the
corner (mm), the punch's and the holder's force (N), the top ply's least gap to the bottom
ply (its penetration, mm), the steps and the run's CPU.

The penalty converges to the contact's k -> infinity limit as O(1 / k) (a penetration g =
p / k under a pressure p, and the results smooth in g): where the results of three factors
c, 2c, 4c move monotonically, Richardson's extrapolation in 1 / k through them
(``validation.checks.observed_order`` with h = 1 / c) is the limit and its observed order
should be near 1. A quantity whose differences change sign, or whose change from c to 2c is
of the size of a run's sensitivity to a small perturbation (a factor 1.05, which moves the
penetration by 5 %), is not moved by the penalty but by the run's dynamics (the flange's
wrinkles, snaps): its scatter, not a bias.

Run it with ``python -m validation.studies.hemisphere_plies_penalty mindlin 0/90 --factors
0.25 0.5 1 2 4`` (kinematics, stack; ``--cells``, ``--force``; ``--tools`` the tools'
penalties times c too; ``--surface`` the plies' faces; ``--json`` to keep the figures); each
run prints as it ends, one at a time.

Measured (8 cells, 20 N; docs/hemisphere_plies.md, "The plies' penalty", has the tables): the
[0/90] penetration is O(1 / k) (fibrous -0.034 - 0.099 / c mm); fibrous [0/90] is at its limit
from the automatic penalty (c = 1 against 8: 0.03 deg, 0.13 mm, 2.2 % of the punch's force),
not at c = 0.5 (0.22 mm into each other, the bottom ply's cells in the die changed); Mindlin
[0/90] scatters more than it trends from c = 0.5 to 4 (its penalty within that scatter) and
stops at 88 % of the stroke at c = 8; [0/45], whose plies' meshes cross, has no limit at 8
cells (the flat-faceted faces cannot nest: held apart the stack is 0.4 mm thicker than its
plies, the punch's force grows with k); on the curved faces, which nest, fibrous [0/45] at c =
1 and 4 is within 0.07 deg and 0.3 mm.
"""

from __future__ import annotations

import functools
import json
import math
import sys
import time
from typing import Any

import numpy as np

from validation.checks import observed_order

__all__ = ["QUANTITIES", "RUN_QUANTITIES", "extrapolated", "measure", "penalty_per_area", "scaled"]

#: The quantities of a ply (the run's parameter after ``<run>_ply<k>_<angle>deg_``) and of the
#: run (after ``<run>_``) compared across penalties.
QUANTITIES = (
    "rms_shear_error_deg",
    "cells_in_die",
    "draw_in_edge_middle_mm",
    "draw_in_corner_mm",
)
RUN_QUANTITIES = (
    "punch_force_N",
    "holder_force_last_tenth_mean_N",
    "least_gap_in_die_mm",
    "least_gap_over_the_run_mm",
)


def scaled(factor: float, tools: bool = False):
    """A ``run`` instrument multiplying the automatic penalty of every ply contact pass of
    the compiled model by ``factor`` (> 0), the nodes' and the points' alike (the points'
    are the nodes' shared out by area, linear in them); ``tools``: the tools' contacts'
    (the die, the punch, the holder: elements/contact.py) too."""
    if not (math.isfinite(factor) and factor > 0.0):
        raise ValueError(f"the penalty's factor must be a positive number, got {factor!r}")

    def instrument(compiled: Any) -> None:
        for block in compiled.interactions:
            if hasattr(block, "node_stiffness"):  # a ply contact pass (elements/ply_block.py)
                block.node_stiffness = block.node_stiffness * factor
                block.stiffness = block.stiffness * factor
            elif tools and hasattr(block, "tool"):  # a rigid tool's (elements/contact.py)
                block.stiffness = block.stiffness * factor

    return instrument


def penalty_per_area(compiled: Any) -> list[float]:
    """Each ply contact pass's median penalty per unit area of its upper nodes, k_j / A_j
    (N/mm^3: the pressure per mm of penetration), A_j the node's lumped area of the upper
    ply's reference triangles."""
    out = []
    x = compiled.mesh.points
    for block in compiled.interactions:
        if not hasattr(block, "node_stiffness"):
            continue
        # the triangles of the ply that carries the pass's points (the mesh's whose corners
        # all lie on it)
        triangles = compiled.mesh.cells("triangle")
        above = triangles[np.isin(triangles, block.upper).all(axis=1)]
        sides = np.cross(x[above[:, 1]] - x[above[:, 0]], x[above[:, 2]] - x[above[:, 0]])
        area = np.repeat(0.5 * np.linalg.norm(sides, axis=1) / 3.0, 3)
        lumped = np.bincount(above.ravel(), area, len(x))[block.upper]
        out.append(float(np.median(block.node_stiffness / lumped)))
    return out


def measure(
    kinematics: str,
    name: str,
    force: float,
    cells: int,
    factor: float,
    tools: bool = False,
    surface: str | None = None,
) -> dict:
    """One run at ``factor`` times the automatic ply penalty (and the tools' with ``tools``),
    the plies' faces ``surface`` ("flat" or "curved", elements/ply_contact.py; None: the
    case's): {"factor", "values": {quantity label: value}, "checks": [(label, passed)],
    "stopped", "steps", "cpu_s", "penalty_per_area"}."""
    from validation.studies import hemisphere_plies_run
    from validation.studies.hemisphere_plies_run import run, run_key
    from validation.studies.hemisphere_plies_setup import LAYUPS, SURFACE, model

    instrument = scaled(factor, tools)
    seen: list[float] = []

    def hook(compiled: Any) -> None:
        instrument(compiled)
        seen.extend(penalty_per_area(compiled))

    start = time.process_time()
    try:
        # the run builds its model by the module's ``model``, the case's faces' unless given
        hemisphere_plies_run.model = functools.partial(model, surface=surface or SURFACE)
        parameters, checks, *_ = run(cells, name, kinematics, force, instrument=hook)
    finally:
        hemisphere_plies_run.model = model
    cpu = time.process_time() - start
    key = run_key(name, kinematics, force).replace(" ", "_").replace("/", "-")
    values: dict[str, float] = {}
    for k, angle in enumerate(LAYUPS[name]):
        ply = f"{key}_ply{k + 1}_{angle:g}deg"
        for quantity in QUANTITIES:
            values[f"ply {k + 1} {quantity}"] = float(parameters[f"{ply}_{quantity}"])
    for quantity in RUN_QUANTITIES:
        values[quantity] = float(parameters[f"{key}_{quantity}"])
    return {
        "factor": factor,
        "values": values,
        "checks": [(c.name, bool(c.passed)) for c in checks],
        "stopped": [v for k, v in parameters.items() if k.endswith("stopped")],
        "steps": parameters.get(f"{key}_steps"),
        "cpu_s": cpu,
        "penalty_per_area": seen,
    }


def extrapolated(runs: list[dict]) -> dict[str, tuple[float, float]]:
    """{quantity: (observed order p, value at k -> infinity)} through the three stiffest
    ``runs`` (by factor) that reached the end of the stroke, h = 1 / factor (NaN where the
    differences change sign or vanish, or a value is not finite); {} when fewer than three
    did."""
    ended = [r for r in runs if not r["stopped"]]
    stiffest = sorted(ended, key=lambda r: r["factor"])[-3:]
    if len(stiffest) < 3:
        return {}
    sizes = [1.0 / r["factor"] for r in stiffest]
    out = {}
    for label in stiffest[0]["values"]:
        values = [r["values"][label] for r in stiffest]
        # a ply with no cell left in the die has no rms (inf): no order
        finite = all(math.isfinite(v) for v in values)
        out[label] = observed_order(sizes, values) if finite else (math.nan, math.nan)
    return out


def _arguments(argv: list[str] | None = None) -> Any:
    import argparse

    from validation.studies.hemisphere_plies_run import RMS_TOLERANCE_DEG
    from validation.studies.hemisphere_plies_setup import HOLDER_FORCES, LAYUPS

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("kinematics", choices=("fibrous", "mindlin"))
    parser.add_argument("stack", choices=tuple(LAYUPS))
    parser.add_argument(
        "--factors",
        type=float,
        nargs="+",
        default=[0.25, 0.5, 1.0, 2.0, 4.0],
        help="the penalty's factors c (times the automatic penalty)",
    )
    parser.add_argument("--cells", type=int, default=8, choices=sorted(RMS_TOLERANCE_DEG))
    parser.add_argument("--force", type=float, default=HOLDER_FORCES[0], help="holder, N")
    parser.add_argument(
        "--tools", action="store_true", help="the tools' penalties times the factor too"
    )
    parser.add_argument(
        "--surface", choices=("flat", "curved"), help="the plies' faces (default: the case's)"
    )
    parser.add_argument("--json", help="a path to write the runs' figures to")
    arguments = parser.parse_args(argv)
    for factor in arguments.factors:
        if not (math.isfinite(factor) and factor > 0.0):
            parser.error(f"a factor must be a positive number, got {factor}")
    if len(set(arguments.factors)) != len(arguments.factors):
        # refused before the runs: the extrapolation's sizes 1 / c must differ
        parser.error(f"the factors must differ from each other, got {arguments.factors}")
    return arguments


if __name__ == "__main__":
    arguments = _arguments()
    done = []
    for factor in arguments.factors:
        outcome = measure(
            arguments.kinematics,
            arguments.stack,
            arguments.force,
            arguments.cells,
            factor,
            arguments.tools,
            arguments.surface,
        )
        done.append(outcome)
        per_area = ", ".join(f"{k:.4g}" for k in outcome["penalty_per_area"])
        print(
            f"c = {factor:g}: k / A {per_area} N/mm^3, steps {outcome['steps']}, "
            f"cpu {outcome['cpu_s']:.1f} s, stopped: {outcome['stopped'] or 'no'}"
        )
        for label, passed in outcome["checks"]:
            if not passed:
                print("  FAIL", label)
        for label, value in outcome["values"].items():
            print(f"  {label}: {value:.4f}")
        sys.stdout.flush()
        if arguments.json:
            with open(arguments.json, "w") as file:
                json.dump(done, file, indent=1)
    if extrapolated(done):
        print("quantity: values (by factor), observed order p in 1/k, value at k -> infinity")
        for label, (p, f0) in extrapolated(done).items():
            values = ", ".join(f"{r['values'][label]:.4f}" for r in done)
            print(f"  {label}: {values}; p = {p:.3f}, f0 = {f0:.4f}")
