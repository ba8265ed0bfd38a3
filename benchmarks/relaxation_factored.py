"""DynamicRelaxation on the stiff-fibre strip over the cylinder: the Gershgorin masses, the
default (Gershgorin, going on with the factored masses where the progress watch stalls) and
the factored masses from the start, side by side in one run.

The problem: cases/strip_over_cylinder.toml with kind = "relaxation" at the solver's defaults
(50 cells; fibres 1000 N/mm against a bending of 0.833 N mm: omega_max / omega_min of the
Gershgorin masses 1.6e4, docs/theory.md §6.4a). The reference pass is the Gershgorin masses
without the progress watch (``plateau_iterations=None``), which converge in the end; with the
watch, as before this change, the default run stopped as stalled. Each run prints its
iterations, seconds, estimates of the masses and its tip against the heavy elastica
(validation/references/elastica.py).

Run: python benchmarks/relaxation_factored.py [--nx 50] [--only reference,default,factored]
One core (NUMBA_NUM_THREADS=1).

Measured (python 3.11.7, x86_64, one job of mine on 2 cores shared with other jobs, load 11-21,
so the seconds are loose; the three runs one after another in one process):

    run                        iterations   wall     ms/iter   estimates   tip x, z (mm)
    reference (no watch)       127 814      590 s    4.6       95          45.63, -61.81
    default (switch at stall)   68 433      380 s    5.5       94          45.63, -61.81
    factored from the start     47 814      188 s    3.9       81          45.63, -61.81

The heavy elastica puts the tip at (45.63, -61.80). The default's switch came at 40 000
iterations (the watch's second check), where the Gershgorin masses with the watch stopped as
stalled before this change.
"""

from __future__ import annotations

import argparse
import platform
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))  # run from anywhere, no install

from fibreshell.case import case_from_data, read_case_data  # noqa: E402
from fibreshell.sweep import apply_overrides  # noqa: E402
from solvers import DynamicRelaxation, SolverError  # noqa: E402
from validation.references.elastica import heavy_strip_over_cylinder  # noqa: E402

__all__ = ["RUNS", "main", "run"]

#: name -> DynamicRelaxation options
RUNS = {
    "reference": {"plateau_iterations": None},  # Gershgorin masses throughout
    "default": {},
    "factored": {"masses": "factored"},
}


def run(name: str, nx: int) -> str:
    """One relaxation of the case at ``nx`` cells along; a line of its figures."""
    path = ROOT / "cases" / "strip_over_cylinder.toml"
    tables, _ = apply_overrides(read_case_data(path), {"mesh.rectangle.nx": nx})
    case = case_from_data(tables, path)
    solver = DynamicRelaxation(progress=False, **RUNS[name])
    started = time.perf_counter()
    try:
        result = solver.solve(case.model())
    except SolverError as error:
        seconds = time.perf_counter() - started
        return f"{name:10s} stopped after {error.steps} iterations, {seconds:.1f} s: {error}"[:300]
    seconds = time.perf_counter() - started
    tip = result.positions[case.mesh.nodes("tip")].mean(axis=0)
    reference = heavy_strip_over_cylinder(100.0, 1.66e-9 * 9810.0, 0.833, 20.5)
    info = result.info
    return (
        f"{name:10s} {result.steps:8d} iterations {seconds:7.1f} s  "
        f"{1e3 * seconds / result.steps:.3f} ms/iteration  estimates {info['mass_estimates']:4d}  "
        f"recoveries {info['recoveries']}  factored after stall {info['factored_after_stall']}  "
        f"tip ({tip[0]:.2f}, {tip[2]:.2f}) against ({reference['tip_x']:.2f}, "
        f"{reference['tip_z']:.2f}) mm"
    )


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--nx", type=int, default=50)
    parser.add_argument("--only", default=",".join(RUNS))
    options = parser.parse_args(argv)
    print(f"python {platform.python_version()}, {platform.machine()}, nx = {options.nx}")
    for name in options.only.split(","):
        print(run(name, options.nx), flush=True)


if __name__ == "__main__":
    main()
