"""What the stability count of each converged state costs Static (docs/theory.md §6.5, "The
stability of a converged state").

The count of negative eigenvalues of a converged state is the inertia of the exact tangent at
that state (solvers/static_run.py ``StaticRun.factor_at``): one more assembly and
factorisation an increment where the last one was made at an iterate before it. The reference
pass, in the same process and alternating with it, reads the count of the tangent last
factorised on the way instead (the solver before; ``factor_at`` patched to hand back the
factorisation it is given). Lines: the report's single-shell Static cases and those of
benchmarks/newton_iterations.py lines 1, 2 and 4:

1. the elastica (validation case mindlin-elastica: 100 x 5 x 1 mm, 20 cells, P L^2 / EI = 3
   in 5 increments);
2. the roll-up (mindlin-rollup: 100 x 10 x 1 mm, 20 cells, a quarter circle in 4 increments);
3. Peirce's cantilever (G986 stack, 20 x 1 cells, 3 increments), fibrous and
   MindlinShell(fabric);
4. the heavy fibrous cantilever (fibrous-heavy-cantilever, 20 cells).

Each prints, for the count at the state and for the reference pass: the CPU time (one thread,
best of ``--repeat``), the Newton tangents, the stability tangents, the increments and the
counts reported.

Measured (one thread, CPU best of 3, load 4.2-5.3, the two passes alternating): the elastica
0.056 / 0.055 s (23 tangents + 5), the roll-up 0.044 / 0.042 s (18 + 4), Peirce fibrous
0.085 / 0.083 s (17 + 3), Peirce MindlinShell(fabric) 0.045 / 0.044 s (15 + 3), the heavy
fibrous cantilever 0.089 / 0.087 s (14 + 3): 2 to 5 % more, one assembly and factorisation an
increment; the same counts (all 0) and the same iterations.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from materials.presets import g986_stack  # noqa: E402
from solvers import Static  # noqa: E402
from solvers.static_run import StaticRun  # noqa: E402
from validation import specimens  # noqa: E402
from validation.references.elastica import peirce_overhang  # noqa: E402


def _elastica():
    length, width, young = 100.0, 5.0, 1e5
    mesh, model = specimens.mindlin_strip(length, width, 1.0, young, 20, 1)
    tip = mesh.nodes("right")
    model.force(tip, (0.0, 0.0, -3.0 * young * width / 12 / length**2 / len(tip)))
    return model, 5


def _rollup():
    length, width, young = 100.0, 10.0, 1e5
    mesh, model = specimens.mindlin_strip(length, width, 1.0, young, cells=20)
    tip = mesh.nodes("right")
    moment = 0.5 * math.pi * young * width / 12 / length
    model.moment(tip, (0.0, -moment / len(tip), 0.0), amplitude="linear")
    return model, 4


def _peirce(kind: str):
    fabric = g986_stack()
    overhang = peirce_overhang(fabric.areal_density * specimens.GRAVITY, fabric.bending)
    build = specimens.fibrous_strip if kind == "fibrous" else specimens.mindlin_fabric_strip
    _, model = build(overhang["overhang"], 10.0, fabric, 20)
    return model, 3


def _heavy():
    from validation.cases.fibrous_heavy_cantilever import INCREMENTS, strip

    return strip(20)[1], INCREMENTS


LINES = {
    "1. elastica, 20 cells": _elastica,
    "2. roll-up, 20 cells": _rollup,
    "3. Peirce, fibrous": lambda: _peirce("fibrous"),
    "3. Peirce, MindlinShell(fabric)": lambda: _peirce("mindlin"),
    "4. heavy fibrous cantilever, 20 cells": _heavy,
}

OWN = StaticRun.factor_at


def _on_the_way(self, state, factor=None):
    """The reference pass: the factorisation made on the way, a new one only without one."""
    return factor if factor is not None else OWN(self, state, factor)


def _solve(compiled, increments: int, reference: bool):
    StaticRun.factor_at = _on_the_way if reference else OWN  # type: ignore[method-assign]
    try:
        start = time.process_time()
        result = Static(increments=increments, progress=False).solve(compiled)
        return time.process_time() - start, result.info
    finally:
        StaticRun.factor_at = OWN  # type: ignore[method-assign]


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3, help="solves per pass (best CPU)")
    options = parser.parse_args(argv)
    for name, build in LINES.items():
        model, increments = build()
        compiled = model.compile()
        best = {False: math.inf, True: math.inf}
        infos = {}
        _solve(compiled, increments, False)  # compile the kernels outside the timing
        for _ in range(options.repeat):
            for reference in (False, True):
                took, info = _solve(compiled, increments, reference)
                best[reference] = min(best[reference], took)
                infos[reference] = info
        print(name)
        for reference, label in ((False, "count at the state"), (True, "count on the way")):
            info = infos[reference]
            counts = info["evaluations"]
            print(
                f"  {label:20s} CPU {best[reference]:7.3f} s, tangents {counts['tangent']:3d}"
                f" + stability {counts['stability_tangents']:2d},"
                f" increments {len(info['load_factors'])},"
                f" negative {info['negative_eigenvalues']}"
            )
        print(f"  ratio {best[False] / best[True]:.3f}")


if __name__ == "__main__":
    main()
