"""DynamicRelaxation with the physical lumped masses against the Gershgorin fictitious masses.

The same problems, solved both ways, side by side: wall time, iterations per increment and the
error against the closed form where there is one.

1. A Mindlin strip rolled up by an end moment into a quarter circle: 120 x 8 x 1 mm (L/h =
   120), 32 x 2 cells, E = 70 GPa, nu = 0, M = (pi/2) E I / L on the end nodes, 4 increments;
   the tip lands on the circle of radius EI/M (x = z = EI/M).
2. The README's fibrous example: the G1151 laminate (Bai Table 2) as a 200 x 60 mm strip of
   8 x 2 cells, clamped at one end, sagging under its own weight (no closed form: the two runs
   are compared with each other).
3. A 40-triangle Mindlin cantilever (100 x 5 x 1 mm, 20 cells, E = 100 GPa) under a tip load
   P L^2 / EI = 3 in one increment: the tip drops by 0.603 L (the elastica,
   validation.references.elastica).

The lumped runs get ``--lumped-limit`` iterations per increment (the roll-up does not converge
in 200 000); a run that stops there is reported as not converged with its residual ratio.

Run: python benchmarks/relaxation.py [--lumped-limit 200000] [--only rollup,fibrous,elastica]
One core (set OMP_NUM_THREADS=1 to be sure).

Measured (python 3.11, x86_64, one core; iterations, wall time):

    problem     lumped masses                gershgorin masses
    roll-up     158 040 [47k 45k 26k 40k]    68 759 [16k 23k 15k 15k], 103 s, tip -0.06 %/+0.05 %
    fibrous     23 232, 51 s                 12 748, 35 s (tip 126.29 mm against 126.30)
    elastica    24 723, 26 s (+0.01 %)       11 124, 15 s (+0.07 %)

The lumped roll-up took 635 s with another job on the machine. Before the force reference
took the moments in (docs/theory.md §6.4, Convergence), the lumped runs needed 371 778
iterations for the roll-up [112k 105k 77k 78k] and 33 952 for the elastica.
"""

from __future__ import annotations

import argparse
import math
import platform
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install

from elements import FibrousShell  # noqa: E402
from femcore import Mesh, Model  # noqa: E402
from materials import presets  # noqa: E402
from solvers import ConvergenceError, DynamicRelaxation  # noqa: E402
from validation import specimens  # noqa: E402
from validation.references.elastica import tip_loaded_cantilever  # noqa: E402

__all__ = ["PROBLEMS", "elastica", "fibrous", "main", "roll_up", "run"]


def roll_up():
    """(model, increments, tip nodes, check(result) -> text) of the quarter-circle roll-up."""
    length, width, thickness, young = 120.0, 8.0, 1.0, 70e3
    mesh, model = specimens.mindlin_strip(length, width, thickness, young, cells=32, across=2)
    inertia = width * thickness**3 / 12
    moment = 0.5 * math.pi * young * inertia / length
    radius = young * inertia / moment
    tip = mesh.nodes("right")
    model.moment(tip, (0.0, -moment / len(tip), 0.0), amplitude="linear")

    def check(result) -> str:
        x, _, z = result.positions[tip].mean(axis=0)
        return f"tip x/R - 1 = {x / radius - 1:+.2%}, z/R - 1 = {z / radius - 1:+.2%}"

    return model, 4, check


def fibrous():
    """The README's fibrous example: the G1151 strip sagging under its weight."""
    mesh = Mesh.rectangle(200.0, 60.0, nx=8, ny=2)
    model = Model(mesh)
    model.add(FibrousShell(presets.g1151_laminate(), clamped="left"))
    model.fix("left")
    model.gravity((0.0, 0.0, -9810.0))
    tip = mesh.nodes("right")

    def check(result) -> str:
        return f"tip deflection {-result.displacements[tip, 2].mean():.3f} mm"

    return model, 1, check


def elastica():
    """The 40-triangle Mindlin cantilever under a tip load P L^2 / EI = 3."""
    length, width, thickness, young = 100.0, 5.0, 1.0, 1e5
    mesh, model = specimens.mindlin_strip(length, width, thickness, young, cells=20)
    bending = young * width * thickness**3 / 12
    load = 3.0 * bending / length**2
    tip = mesh.nodes("right")
    model.force(tip, (0.0, 0.0, -load / len(tip)), amplitude="linear")
    reference = tip_loaded_cantilever(length, load, bending)["tip_deflection"]

    def check(result) -> str:
        drop = -result.displacements[tip, 2].mean()
        return f"tip drop {drop:.3f} mm, elastica {reference:.3f} mm ({drop / reference - 1:+.2%})"

    return model, 1, check


PROBLEMS = {"rollup": roll_up, "fibrous": fibrous, "elastica": elastica}


def run(problem: str, masses: str, limit: int) -> str:
    """One solve; a line with the wall time, iterations per increment and the check."""
    model, increments, check = PROBLEMS[problem]()
    solver = DynamicRelaxation(increments=increments, masses=masses, max_iterations=limit)
    started = time.perf_counter()
    try:
        result = solver.solve(model)
        status = "converged"
    except ConvergenceError as error:
        result = error.result
        status = f"NOT converged ({str(error).split(':')[1].strip()[:60]}...)"
    wall = time.perf_counter() - started
    counts = result.info["iterations_per_increment"]
    done = f"{sum(counts)} iterations {counts}" if counts else "no increment converged"
    extra = check(result) if result.converged else ""
    return f"  {masses:10s} {wall:8.1f} s  {done}  {status}  {extra}"


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--lumped-limit", type=int, default=200_000)
    parser.add_argument("--limit", type=int, default=200_000, help="gershgorin runs")
    parser.add_argument("--only", default=",".join(PROBLEMS))
    args = parser.parse_args(argv)
    print(f"python {platform.python_version()} on {platform.machine()} ({platform.system()})")
    for problem in args.only.split(","):
        print(f"{problem}:", flush=True)
        for masses, limit in (("lumped", args.lumped_limit), ("gershgorin", args.limit)):
            print(run(problem, masses, limit), flush=True)


if __name__ == "__main__":
    main()
