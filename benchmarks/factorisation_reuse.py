"""What keeping the symbolic factorisation between Newton iterations saves (solvers.linear).

solvers.linear.LinearSolver keeps, while K_ff's sparsity pattern holds, the map of its entries
to the symmetrised upper triangle, the ordering and band layout (or QDLDL's elimination tree)
and, for a new pattern, the choice between the band LDL^T and QDLDL. This script records every
K_ff a Static solve factorises (the same solve as benchmarks/static_solver.py's lines) and
factorises the sequence again twice, timed in the same run: with one LinearSolver (the
solve's own way: the analysis kept while the pattern holds) and with a new LinearSolver for
every matrix (the analysis redone each time). It prints the matrices, the symbolic analyses
each way and the CPU time of each pass (best of the repeats), and the solve's own CPU time.

Measured on this 2-core machine shared with other work, one thread, best of 3 of the
replays, load 6.5-7.7 (1-minute average before and after):

- Mindlin cantilever, 2560 triangles, 5 increments: 23 factorisations of 6800 unknowns (the
  solve 2.12 s CPU); the analysis kept: 2 analyses (the pattern changes once: the zero
  bending couplings of the flat strip are left out), 0.38 s; redone each time: 23 analyses,
  1.93 s. Kept, it saves 1.55 s, 73 % of the solve's CPU time (the band plan and the
  comparison with QDLDL's factor that chooses it are the bulk of an analysis).
- Bai 6.2.1 corner, fibrous, 20 x 20 cells, 4 increments: 16 factorisations of 1049
  unknowns (the solve 0.87 s); 2 analyses 0.22 s against 16 analyses 0.46 s: 0.25 s saved,
  28 % of the solve.
- Peirce's cantilever, fibrous, 20 x 1 cells, 3 increments: 32 factorisations of 200
  unknowns (the solve 0.23 s); 2 analyses 0.019 s against 32 analyses 0.108 s: 0.09 s saved,
  39 % of the solve.

Run: python benchmarks/factorisation_reuse.py [--repeats 3]
"""

from __future__ import annotations

import argparse
import platform
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from solvers import Static  # noqa: E402
from solvers import linear as linear_module  # noqa: E402
from solvers.linear import LinearSolver  # noqa: E402

__all__ = ["main", "recorded", "replay"]


def recorded(model, increments: int):
    """(the K_ff matrices a Static solve of ``model`` factorises, in order; its CPU time s)."""
    matrices = []
    original = LinearSolver.factorise

    def factorise(self, k_ff):
        matrices.append(k_ff.copy())
        return original(self, k_ff)

    LinearSolver.factorise = factorise  # type: ignore[method-assign]
    try:
        started = time.process_time()
        Static(increments=increments, progress=False).solve(model)
        cpu = time.process_time() - started
    finally:
        LinearSolver.factorise = original  # type: ignore[method-assign]
    return matrices, cpu


def replay(matrices, kept: bool) -> tuple[float, int]:
    """(CPU seconds to factorise ``matrices`` in order, symbolic analyses made): one
    LinearSolver for all (``kept``) or a new one for each."""
    solver = LinearSolver()
    analyses = 0
    started = time.process_time()
    for k in matrices:
        if not kept:
            solver = LinearSolver()
        solver.factorise(k)
        analyses += 0 if kept else solver.symbolic
    elapsed = time.process_time() - started
    return elapsed, solver.symbolic if kept else analyses


def cases():
    from benchmarks.static_solver import corner_model, strip
    from materials import presets
    from validation import specimens
    from validation.references.elastica import peirce_overhang

    model, _, _ = strip("force")
    yield "Mindlin cantilever, 2560 triangles, 5 increments", model, 5
    model, _ = corner_model(20)
    yield "Bai 6.2.1 corner, fibrous, 20 x 20 cells, 4 increments", model, 4
    fabric = presets.g986_stack()
    overhang = peirce_overhang(fabric.areal_density * specimens.GRAVITY, fabric.bending)
    _, model = specimens.fibrous_strip(overhang["overhang"], 10.0, fabric, 20)
    yield "Peirce's cantilever, fibrous, 20 x 1 cells, 3 increments", model, 3


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args(argv)
    print(f"python {platform.python_version()} on {platform.machine()} ({platform.system()})")
    print(f"band LDL^T available: {linear_module.BAND_AVAILABLE}")
    for name, model, increments in cases():
        compiled = model.compile()
        recorded(compiled, increments)  # compilations and caches settled
        matrices, solve_cpu = recorded(compiled, increments)
        n = matrices[0].shape[0]
        best = {True: (np.inf, 0), False: (np.inf, 0)}
        for _ in range(args.repeats):
            for kept in (True, False):
                elapsed, analyses = replay(matrices, kept)
                best[kept] = (min(best[kept][0], elapsed), analyses)
        (kept_s, kept_n), (fresh_s, fresh_n) = best[True], best[False]
        print(
            f"{name}: {len(matrices)} factorisations of {n} unknowns (the solve: "
            f"{solve_cpu:.2f} s CPU); analysis kept: {kept_n} analyses, {kept_s:.3f} s CPU; "
            f"redone each time: {fresh_n} analyses, {fresh_s:.3f} s CPU; saved "
            f"{fresh_s - kept_s:.3f} s = {(fresh_s - kept_s) / solve_cpu:.1%} of the solve",
            flush=True,
        )


if __name__ == "__main__":
    main()
