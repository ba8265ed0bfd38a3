"""Static (Newton) against DynamicRelaxation on quasi-static problems: wall time, iterations.

1. Bai §6.2.1: the G1151 laminate (200 x 150 x 15 mm, Table 2) with the free triangle
   beyond the clamped diagonal, its corner lowered by 40 mm, under gravity; fibrous shell.
2. A Mindlin cantilever strip of 2560 triangles (200 x 20 x 1 mm, 80 x 16 cells, aluminium,
   nu = 0) under a tip load P L^2 / EI = 3: the tip drops by 0.603 L (elastica).
3. The same strip rolled up into a quarter circle by an end moment: Static with the element's
   own tangent against the coloured finite-difference tangent.

Run: python benchmarks/static_solver.py [--cells 20] [--dr-limit 400000] [--skip-dr]
Prints one line per run; one core (set OMP_NUM_THREADS=1 to be sure).
"""

from __future__ import annotations

import argparse
import math
import platform
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from femcore import Model  # noqa: E402
from materials.presets import g1151_laminate  # noqa: E402
from solvers import ConvergenceError, DynamicRelaxation, Static  # noqa: E402
from validation import specimens  # noqa: E402
from validation.references.elastica import tip_loaded_cantilever  # noqa: E402

__all__ = ["corner_model", "describe", "main", "strip", "timed"]


def corner_model(cells: int) -> tuple[Model, specimens.Specimen]:
    """The bai-6.2.1 specimen (validation.specimens), its corner lowered by 40 mm."""
    specimen = specimens.corner(*specimens.G1151_SIZE, cells)
    model = specimens.build(specimen, "fibrous", g1151_laminate(), (None, None, -40.0))
    return model, specimen


def strip(load_kind: str) -> tuple[Model, np.ndarray, float]:
    length, width, thickness, young = 200.0, 20.0, 1.0, 70e3  # aluminium, nu = 0
    mesh, model = specimens.mindlin_strip(length, width, thickness, young, cells=80, across=16)
    bending = young * width * thickness**3 / 12
    tip = mesh.nodes("right")
    if load_kind == "force":
        load = 3.0 * bending / length**2
        model.force(tip, (0.0, 0.0, -load / len(tip)), amplitude="linear")
        reference = tip_loaded_cantilever(length, load, bending)["tip_deflection"]
    else:
        moment = 0.25 * 2 * math.pi * bending / length
        model.moment(tip, (0.0, -moment / len(tip), 0.0), amplitude="linear")
        reference = bending / moment  # radius of the quarter circle
    return model, tip, reference


def timed(solver, model):
    started = time.perf_counter()
    try:
        result = solver.solve(model)
        converged = True
    except ConvergenceError as error:
        result, converged = error.result, False
    return result, time.perf_counter() - started, converged


def describe(name, result, wall, converged, extra=""):
    if name.startswith("Static"):
        its = f"Newton iterations per increment {result.info['iterations_per_increment']}"
    else:
        its = f"{result.steps} iterations"
    status = "" if converged else " (NOT converged: iteration limit)"
    print(f"  {name}: {wall:.1f} s, {its}{status}{extra}")


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cells", type=int, default=20, help="corner specimen: n x n cells")
    parser.add_argument("--dr-limit", type=int, default=400_000, help="DR iteration limit")
    parser.add_argument("--skip-dr", action="store_true")
    args = parser.parse_args(argv)
    print(f"python {platform.python_version()} on {platform.machine()} ({platform.system()})")

    model, specimen = corner_model(args.cells)
    n_tri = len(specimen.mesh.triangles)
    print(f"1. Bai 6.2.1 G1151 corner bending, fibrous shell, {n_tri} triangles:")
    static, wall, ok = timed(Static(increments=4), model)
    describe("Static", static, wall, ok)
    if not args.skip_dr:
        relaxed, wall, ok = timed(DynamicRelaxation(tol=1e-5, max_iterations=args.dr_limit), model)
        gap = np.abs(relaxed.positions - static.positions).max()
        travel = np.abs(static.displacements).max()
        describe(
            "DynamicRelaxation",
            relaxed,
            wall,
            ok,
            f"; largest position difference to Static {gap:.3g} mm = {gap / travel:.2e} of the "
            f"largest displacement",
        )

    model, tip, reference = strip("force")
    print(f"2. Mindlin cantilever, 2560 triangles, tip load (elastica: drop {reference:.2f} mm):")
    static, wall, ok = timed(Static(increments=5), model)
    drop = -static.displacements[tip, 2].mean()
    describe("Static", static, wall, ok, f"; tip drop {drop:.2f} mm ({drop / reference - 1:+.2%})")
    if not args.skip_dr:
        relaxed, wall, ok = timed(
            DynamicRelaxation(increments=5, tol=1e-5, max_iterations=args.dr_limit), model
        )
        drop = -relaxed.displacements[tip, 2].mean()
        describe(
            "DynamicRelaxation",
            relaxed,
            wall,
            ok,
            f"; tip drop {drop:.2f} mm ({drop / reference - 1:+.2%})",
        )

    model, tip, radius = strip("moment")
    print(f"3. Mindlin roll-up to a quarter circle, 2560 triangles (radius {radius:.2f} mm):")
    for tangent in ("element", "finite_difference"):
        result, wall, ok = timed(Static(increments=4, tangent=tangent), model)
        x, _, z = result.positions[tip].mean(axis=0)
        describe(
            f"Static, {tangent} tangent",
            result,
            wall,
            ok,
            f"; tip at x = {x:.2f} ({x / radius - 1:+.2%}), z = {z:.2f} ({z / radius - 1:+.2%})",
        )


if __name__ == "__main__":
    main()
