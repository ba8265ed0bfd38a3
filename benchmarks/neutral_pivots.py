"""What telling neutral pivots from negative ones costs Static, and saves it (docs/theory.md
§6.5, "Neutral modes"; solvers/neutral_modes.py).

Where K_ff's LDL^T has a negative pivot, StaticRun.factorise factorises K_ff + rho W + nu I
once more (a linear solver of its own) and counts only its negative pivots; the mode searches
drop the neutral modes. The reference pass, in the same process and alternating with it, counts
every negative pivot and keeps every mode (``judge_pivots`` and ``unstable_modes`` patched to
hand back what they are given: the solver before). Lines:

1. the flat fibrous strip pulled 5 % along its warp (40 x 10 mm, 4 x 2 cells, weft 500 N/mm,
   4 increments; tests/test_static_neutral_modes.py), whose tilt modes are neutral;
2. the Mindlin strip of tests/test_static_stability.py under 1.5 P_cr in 4 dead-load
   increments, a genuine saddle left for the elastica: the second factorisation is its cost.

Each prints, for both passes: the CPU time (one thread, best of ``--repeat``), the Newton
iterations, cuts, mode searches, the shifted factorisations and the counts reported.

Measured on the code of c01b52c (one thread, CPU best of 2, load
7-9, other jobs running, the two passes alternating): the strip 0.020 s (1 iteration an
increment, no mode search, 8 shifted factorisations, no negative eigenvalue) against 0.767 s
(57 + 1 + 1 + 1 iterations, 8 cuts, 426 mode searches, one negative eigenvalue a frame, every
director tilted 51.2 deg); the Mindlin strip 0.167 against 0.150 s (the same 1 + 1 + 31 + 7
iterations and 32 mode searches, 9 shifted factorisations): 12 % more where every iterate of
a buckling increment is indefinite.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from elements import FibrousShell, MindlinShell  # noqa: E402
from femcore import Mesh, Model  # noqa: E402
from materials import ElasticShell, Fabric  # noqa: E402
from solvers import (  # noqa: E402
    ConvergenceError,
    Static,
    neutral_modes,
    newton,
    saddles,
    stability,
    static_run,
)


def _strip():
    mesh = Mesh.rectangle(40.0, 10.0, nx=4, ny=2)
    model = Model(mesh)
    model.add(FibrousShell(Fabric(1.0, 1e-12, 1200.0, 0.2, 7.5, tension_weft=500.0)))
    model.fix("left", ["ux", "uy", "uz"])
    model.displace("right", ux=2.0, uy=0.0, uz=0.0)
    return model


def _euler():
    length, width, young = 100.0, 5.0, 1e5
    critical = math.pi**2 * young * width / 12.0 / (4.0 * length**2)
    mesh = Mesh.rectangle(length, width, nx=20, ny=1)
    model = Model(mesh)
    model.add(MindlinShell(ElasticShell(E=young, nu=0.0, thickness=1.0, density=1e-9)))
    model.fix("left")
    tip = mesh.nodes("right")
    model.force(tip, (-1.5 * critical / len(tip), 0.0, 0.0), amplitude="linear")
    return model


LINES = {"1. flat fibrous strip in tension": _strip, "2. Mindlin strip at 1.5 P_cr": _euler}

# Where the two patched functions are used (imported by name into these modules).
PATCHED = {
    "judge_pivots": [static_run],
    "unstable_modes": [newton, saddles, stability],
}
OWN = {name: getattr(neutral_modes, name) for name in PATCHED}
REFERENCE = {
    "judge_pivots": lambda linear, k_ff, factor: factor,
    "unstable_modes": lambda k_ff, modes: modes,
}


def _use(reference: bool) -> None:
    for name, modules in PATCHED.items():
        for module in modules:
            setattr(module, name, REFERENCE[name] if reference else OWN[name])


def _solve(compiled, reference: bool):
    _use(reference)
    try:
        start = time.process_time()
        try:
            info = Static(increments=4, progress=False).solve(compiled).info
        except ConvergenceError as stop:
            info = stop.result.info if stop.result is not None else {}
        return time.process_time() - start, info
    finally:
        _use(False)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3, help="solves per pass (best CPU)")
    options = parser.parse_args(argv)
    for name, build in LINES.items():
        compiled = build().compile()
        best = {False: math.inf, True: math.inf}
        infos = {}
        _solve(compiled, False)  # compile the kernels outside the timing
        for _ in range(options.repeat):
            for reference in (False, True):
                took, info = _solve(compiled, reference)
                best[reference] = min(best[reference], took)
                infos[reference] = info
        print(name)
        for reference, label in ((False, "neutral pivots"), (True, "every pivot")):
            info = infos[reference]
            shifted = info.get("linear_solver", {}).get("neutral_factorisations", 0)
            print(
                f"  {label:15s} CPU {best[reference]:7.3f} s,"
                f" iterations {info.get('iterations_per_increment')}, cuts {info.get('cuts')},"
                f" mode searches {info.get('mode_searches')}, shifted {shifted},"
                f" negative {info.get('negative_eigenvalues')}"
            )
        print(f"  ratio {best[False] / best[True]:.3f}")


if __name__ == "__main__":
    main()
