"""Where each validation case's CPU goes outside its solves: per case of the report, the
case's CPU (as results.json's ``case_cpu_s`` counts it: ``Case.compute`` then
``Case.render``), split into the solvers' ``solve`` calls (CentralDifference,
DynamicRelaxation, Static: the outermost call counted), the rest of the computation (model
building, numba's cache loads, the measures of the results, the references) and the render
(figures and result files), with the render's parts apart (``PARTS``: the figures' drawing
and PNG in ``Figure.savefig``, the constrained layout validation.plots.save runs before it,
the XDMF/HDF5 series, the VTU files), largest outside first.

The cases run one after the other in this process (one numba thread), after the imports
every report worker makes (timed apart, first line), so a case's numba cache loads count in
its computation as in the report's first case of a worker.

Usage (from the root of the tree measured; run a ``git archive`` of the code before from its
own root beside it)::

    NUMBA_NUM_THREADS=1 python benchmarks/case_outside_solves.py --resolution default \
        [--cases a,b] [--out DIR] [--json FILE]

Measured (main f56c093 from git archive with its numba cache warm, one numba thread, one
process, 2 cores shared, load 2.6 -> 6.7; CPU s; before the layout and VTU columns were
added): 151.7 s of case CPU, 133.9 in the solves, 17.8 outside them: 4.7 in the rest of the
computations, 13.1 in the renders (5.3 in savefig, 1.7 in the XDMF series). Largest outside:
hemisphere-plies 3.60 (its build and gap measures 2.66, render 0.94), the five paper cases
1.36-2.12 each (their renders 1.35-2.10: four figures and three XDMF series, 0.28-0.45 s of
XDMF), hemisphere-forming 1.29 (0.56 + 0.74), heavy-cantilever-nonlinear 1.19 (0.98 of it
the heavy elastica's references, scipy's solve_bvp, and numba's cache loads), plies-bai-5.1
0.69, the 17 others 0.06-0.46 each. The worker's imports 0.92 s.

With femcore.xdmf's creation properties made once per shape (load 5.5 -> 7.0): 151.2 s,
133.3 in the solves, 17.9 outside: 5.0 in the computations, 13.0 in the renders (savefig 5.5,
the constrained layout before it 4.3, XDMF 1.69 -> 1.67, VTU 1.0): this run did not measure the
change. The script did not put its own tree first then, so run from the tree with the change
it imported the installed checkout's packages (main's femcore.xdmf, f56c093's until the change
was merged) as the run before did.
Measured again, one tree (55729eb) with femcore/xdmf.py of f56c093 or of 55729eb swapped in
(the only library file the two differ in), this script run from it with its packages first,
one numba thread, CPU s of the XDMF column: bai-6.1.2 alone, in turns (load 8.0-9.5), 0.28,
0.29 -> 0.13, 0.15; the five paper cases, one turn each (load 6.9-8.6), 1.56 -> 0.80 (bai-5.1
0.30 -> 0.13, bai-6.1.1 0.34 -> 0.26, bai-6.1.2 0.27 -> 0.11, bai-6.2.1 0.35 -> 0.17, bai-6.2.2
0.31 -> 0.13), the same halving as the series written again in one process (0.10 -> 0.045 s
each, bai-5.1's three, back to back; 0.61 -> 0.27 s for six series from pickled results).

The whole default report, ``--jobs 1``, f56c093 then this tree back to back (load 12.3 ->
8.3, then 8.3 -> 7.0): case CPU 151.62 -> 151.00 s (the paper cases 38.34 -> 35.62,
hemisphere-plies 45.23 -> 47.04, the rest within +-0.4), results.json's 6,298 numbers
identical, every PNG, VTU, XDMF and HDF5 file byte-identical.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import time
from collections import defaultdict
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this tree's packages


# The render's parts in the table (figures: savefig's drawing and PNG, and the constrained
# layout validation.plots.save runs before it; the result files).
PARTS = ("savefig", "layout", "xdmf", "vtu")
# Timed callables: label -> (module, attribute path). Outermost calls only, per label.
TIMED = {
    "solve": (
        ("solvers.explicit", "CentralDifference.solve"),
        ("solvers.relaxation", "DynamicRelaxation.solve"),
        ("solvers.static", "Static.solve"),
    ),
    "savefig": (("matplotlib.figure", "Figure.savefig"),),
    "layout": (("matplotlib.layout_engine", "ConstrainedLayoutEngine.execute"),),
    "xdmf": (("femcore.xdmf", "write_xdmf"),),
    "vtu": (("femcore.results", "write_vtu"),),
}


def _load() -> str:
    """The machine's load averages (1, 5, 15 min)."""
    return " ".join(f"{x:.2f}" for x in os.getloadavg())


def _instrument(times: dict[str, float]) -> None:
    """Wrap every callable of ``TIMED`` so that its CPU adds to ``times[label]`` (the
    outermost call of a label only: a solve inside a solve counts once)."""
    import importlib

    for label, targets in TIMED.items():
        depth = [0]
        for module_name, path in targets:
            module = importlib.import_module(module_name)
            owner: Any = module
            *outer, attribute = path.split(".")
            for part in outer:
                owner = getattr(owner, part)
            original = getattr(owner, attribute)

            def wrapped(*a, __original=original, __label=label, __depth=depth, **k):
                __depth[0] += 1
                start = time.process_time()
                try:
                    return __original(*a, **k)
                finally:
                    __depth[0] -= 1
                    if __depth[0] == 0:
                        times[__label] += time.process_time() - start

            setattr(owner, attribute, wrapped)
            if owner is module:  # the callers that imported the function by name
                for other in list(sys.modules.values()):
                    if getattr(other, attribute, None) is original:
                        setattr(other, attribute, wrapped)


def measure(names: list[str] | None, resolution: str, out: Path) -> dict[str, Any]:
    """Run each case as the report's worker does and time its parts (CPU s)."""
    started = time.process_time()
    import numba

    import validation.report  # noqa: F401  (the worker's imports)
    from validation.cases import CASES
    from validation.report import schedule

    numba.set_num_threads(1)
    os.environ["FIBRESHELL_PROGRESS"] = "0"
    imports = time.process_time() - started
    times: dict[str, float] = defaultdict(float)
    _instrument(times)
    rows = {}
    for name in schedule(names or list(CASES), resolution):
        times.clear()
        cpu = time.process_time()
        outcome = CASES[name].compute(resolution)
        compute = time.process_time() - cpu
        solve = times["solve"]
        list(CASES[name].render(outcome.data, out))
        total = time.process_time() - cpu
        rows[name] = {
            "total": total,
            "solve": solve,
            "compute_outside": compute - solve,
            "render": total - compute,
            **{label: times[label] for label in PARTS},
            "converged": outcome.converged,
        }
        print(
            f"  {name:28s} {total:7.2f} s (converged {outcome.converged})",
            file=sys.stderr,
            flush=True,
        )
    return {"imports": imports, "cases": rows}


def table(result: dict[str, Any]) -> str:
    """The measure as a table, largest CPU outside the solves first."""
    rows = result["cases"]
    lines = [f"worker imports {result['imports']:.2f} s CPU"]
    head = (
        f"{'case':28s} {'total':>7s} {'solves':>7s} {'outside':>7s} {'build+':>7s} "
        f"{'render':>7s}" + "".join(f" {label[:7]:>7s}" for label in PARTS)
    )
    lines += [head, "-" * len(head)]
    order = sorted(rows, key=lambda n: -(rows[n]["total"] - rows[n]["solve"]))
    sums: dict[str, float] = defaultdict(float)
    for name in order:
        row = rows[name]
        outside = row["total"] - row["solve"]
        lines.append(
            f"{name:28s} {row['total']:7.2f} {row['solve']:7.2f} {outside:7.2f} "
            f"{row['compute_outside']:7.2f} {row['render']:7.2f}"
            + "".join(f" {row[label]:7.2f}" for label in PARTS)
        )
        for key in ("total", "solve", "compute_outside", "render", *PARTS):
            sums[key] += row[key]
    lines.append("-" * len(head))
    lines.append(
        f"{'all':28s} {sums['total']:7.2f} {sums['solve']:7.2f} "
        f"{sums['total'] - sums['solve']:7.2f} {sums['compute_outside']:7.2f} "
        f"{sums['render']:7.2f}" + "".join(f" {sums[label]:7.2f}" for label in PARTS)
    )
    return "\n".join(lines)


def main() -> None:
    """Measure, print the table (and keep it as JSON with ``--json``)."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--resolution", default="default")
    parser.add_argument("--cases", default="", help="comma-separated names (default: all)")
    parser.add_argument("--out", default="", help="the figures' folder (default: a temporary)")
    parser.add_argument("--json", default="", help="keep the measure in this JSON file")
    args = parser.parse_args()
    names = args.cases.split(",") if args.cases else None
    print(f"{Path.cwd()}  load {_load()}", flush=True)
    with tempfile.TemporaryDirectory() as scratch:
        out = Path(args.out or scratch)
        out.mkdir(parents=True, exist_ok=True)
        result = measure(names, args.resolution, out)
    result["load"] = _load()
    print(table(result))
    print(f"load {result['load']}")
    if args.json:
        Path(args.json).write_text(json.dumps(result, indent=1))


if __name__ == "__main__":
    main()
