"""Where a static validation case's CPU goes, phase by phase: the case's ``compute`` run
once to load numba's cached kernels, then under cProfile, and its ``render`` after it; the
cumulative CPU of the functions that make each phase, with its share of the profiled
compute (cProfile adds its own cost to every Python call, so the shares, not the seconds,
are what to read; the last line gives the case's CPU without the profiler).

The phases (cumulative: a phase holds what its functions call): the models' compile
(``Static.__init__``), the tangents (assembly and the elements' tangents), the
factorisations (the split of K_ff, the choice of an ordering for a new pattern, the numeric
LDL^T), the solves (with their accuracy checks and refinement), the residuals (internal
forces), the frames (``Static``'s converged frames with their fields and reactions).

Usage (from this tree's root)::

    NUMBA_NUM_THREADS=1 python benchmarks/static_case_phases.py bai-6.1.1 [plies-bai-5.1 ...]

Measured (this tree, one thread, 2 cores shared, load 5.5-6.8; shares of the profiled
compute): bai-6.1.1 (compute 8.03 s and render 1.60 s without the profiler): tangents 41.5
%, factorisations 33.2 % (the split of K_ff 3.9 %, a new pattern's ordering and QDLDL
measure 6.3 %; the rest the numeric supernodal LDL^T), solves 8.1 %, residuals 4.5 %, frames
2.4 %, the models' compile 1.0 % (numba's cache loaded by the first run); plies-bai-5.1
(compute 11.62 s, render 0.58 s): tangents 32.5 %, factorisations 28.5 % (split 4.1 %, new
patterns 1.1 %), solves 6.5 %, residuals 2.9 %, frames 4.3 %. An earlier profile of
bai-6.1.1 (load 14): the fibrous Hessian's kernel 9 % of the compute, its rows' product 4 %,
the assembler's scatters 6 %, the supernodal factorisation's kernel 15 %; its refinement runs
on two more meshes (four solves) 62 % of the compute.
"""

from __future__ import annotations

import cProfile
import os
import pstats
import sys
import tempfile
import time
from pathlib import Path

# This tree first (not an installed checkout): the figures are this tree's.
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from validation.cases import CASES  # noqa: E402

# phase -> (file ending, function name) of the functions whose cumulative time it is
PHASES = {
    "models' compile": [("solvers/static_run.py", "__init__")],
    "tangents": [("solvers/static_run.py", "tangent")],
    "factorisations": [("solvers/linear.py", "factorise")],
    "  split of K_ff": [("solvers/linear.py", "split_and_norm")],
    "  new pattern's choice": [("solvers/linear.py", "_choose_band")],
    "solves": [("solvers/linear.py", "solve")],
    "residuals": [("solvers/newton.py", "residual")],
    "frames": [("solvers/static_run.py", "frame")],
}


def phase_times(stats: pstats.Stats) -> dict[str, float]:
    """The cumulative seconds of each phase's functions in ``stats``."""
    found = dict.fromkeys(PHASES, 0.0)
    for (filename, _, function), entry in stats.stats.items():  # type: ignore[attr-defined]
        for phase, functions in PHASES.items():
            if any(filename.endswith(f) and function == name for f, name in functions):
                found[phase] += entry[3]
    return found


def main() -> None:
    names = sys.argv[1:] or ["bai-6.1.1"]
    os.environ.setdefault("FIBRESHELL_PROGRESS", "0")
    print(f"load {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    for name in names:
        case = CASES[name]
        started = time.process_time()
        outcome = case.compute("default")  # numba's cached kernels loaded
        plain = time.process_time() - started
        profile = cProfile.Profile()
        profile.enable()
        case.compute("default")
        profile.disable()
        with tempfile.TemporaryDirectory() as folder:
            started = time.process_time()
            list(case.render(outcome.data, Path(folder)))
            render = time.process_time() - started
        stats = pstats.Stats(profile)
        total = stats.total_tt  # type: ignore[attr-defined]
        print(f"{name}: profiled compute {total:.2f} s")
        for phase, seconds in phase_times(stats).items():
            print(f"  {phase:24s} {seconds:7.2f} s {100 * seconds / total:5.1f} %")
        print(f"  without the profiler: compute {plain:.2f} s, render {render:.2f} s")
    print(f"load {' '.join(f'{x:.2f}' for x in os.getloadavg())}")


if __name__ == "__main__":
    main()
