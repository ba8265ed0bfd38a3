"""A tangent with a new sparsity pattern at most Newton iterations, as a ply contact gives it:
the assembly and the factorisation of another revision beside this tree's, in one process.

The tangents: the first ``--patterns`` tangents of plies-bai-5.1's plies solve (default
resolution: 30 x 2 cells, 8 Mindlin plies, 3528 unknowns free; the case's solver) whose parts
changed their structure from the tangent before (the ply contact's touching points and
facing triangles), recorded with their frames. The sequence is assembled
(femcore.assembly.FreeTangentAssembler: a new map each tangent) and factorised
(solvers.linear.LinearSolver, one for the sequence as in a solve: a new upper plan and band
plan each tangent) by the revision's modules (``--ref``, written beside this tree by
benchmarks/revision_modules.py) and by this tree's, in turns; then the last tangent assembled
again on its kept pattern.

Printed: whether every K_ff (data, indices, indptr) and the solution of K_ff x = 1 are the same
to the bit; the best CPU time over ``--rounds`` of each side, per tangent; the load before and
after.

Measured (one thread, CPU, best of 7 rounds of the first 40 new patterns; the machine
shared), ``--ref main`` (its assembly, linear solver and band those of 81b7828) beside the
compiled map, upper plan and band plan: the same K_ff and solutions to the bit each time; a
new pattern assembled and factorised 36.3 -> 15.3 ms a tangent (2.37 x; load 2.4-2.6; 35.4 ->
16.3 at 3.1-3.3 before K_fp's places were counted without a sort); the same tangent assembled
on its kept pattern 1.00 -> 0.97 ms (the passes reading the pairs' tables where they read
each entry's place: no slower).

The cases themselves (``python -m validation --cases plies-bai-5.1,plies-deck-of-cards,
plies-heavy-cantilever --jobs 1``, one numba thread, nice 5, each tree in turn; case CPU s;
results.json and the .vtu files the same but for times): at load 2.6-3.0, main 27.2 / 10.1 /
3.2 and 26.4 / 10.3 / 3.2, this tree 22.3 / 9.0 / 3.1 and 21.5 / 9.3 / 3.0 (plies-bai-5.1
-19 %); at load 5.8-8, three pairs, 29.1-29.9 / 11.3-13.0 / 3.4-3.7 -> 21.4-25.3 / 9.8-10.4
/ 3.2-3.4. A profile of plies-bai-5.1 after (cProfile, its 1167 tangents, 304 new maps, 319
band plans): the maps 0.96 s, the upper plans 0.76 s and the band plans 0.93 s of 24.8 s,
where before the maps alone took 10.7 of 52 s profiled; the numeric band LDL^T 3.1 s and
the ply contact's tangent and search (elements/ply_block.py) 4.5 and 3.2 s now lead.

Run from the project root: python benchmarks/assembly_rebuild.py [--ref main]
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this tree's packages

from revision_modules import revision_modules  # noqa: E402

from femcore import assembly as assembly_module  # noqa: E402
from fibreshell.plies import plies_solver, ply_stack, stack_model  # noqa: E402
from validation.cases.plies_bai_5_1 import CELLS, FILE, PLIES, PLIES_SOLVER  # noqa: E402
from validation.ground_truth import _case  # noqa: E402

MODULES = {
    "femcore/assembly.py": "femcore.assembly",
    "femcore/tangent_pattern.py": "femcore.tangent_pattern",
    "solvers/band.py": "solvers.band",
    "solvers/linear.py": "solvers.linear",
}


class _Recorded(BaseException):
    """Ends the solve once the tangents asked for are recorded."""


def tangents(count: int):
    """(the model, the first ``count`` tangents of plies-bai-5.1's plies solve (default
    resolution) whose parts changed their structure, each (its parts as (nodes, blocks), its
    frames))."""
    case = _case(FILE, CELLS["default"], {"solver": PLIES_SOLVER})
    stack = ply_stack(case, PLIES["default"])
    model = stack_model(case, stack)
    sequence: list = []
    original = assembly_module.FreeTangentAssembler.__call__

    def record(self, parts, frames):
        item = [(p.nodes.copy(), p.blocks.copy()) for p in parts]
        structure = [n for n, _ in item]
        if (
            not sequence
            or len(structure) != len(sequence[-1][2])
            or not all(np.array_equal(a, b) for a, b in zip(structure, sequence[-1][2]))
        ):
            sequence.append((item, frames, structure))
        if len(sequence) > count:
            raise _Recorded
        return original(self, parts, frames)

    assembly_module.FreeTangentAssembler.__call__ = record  # type: ignore[method-assign]
    try:
        plies_solver(case, False).solve(model)
    except _Recorded:
        pass
    finally:
        assembly_module.FreeTangentAssembler.__call__ = original  # type: ignore[method-assign]
    compiled = model.compile()
    return compiled, [(item, frames) for item, frames, _ in sequence[:count]]


def side(assembly, linear, model, sequence):
    """(a callable that assembles and factorises the sequence, appending each tangent's
    (K_ff, x) to its argument if given; one that assembles the last tangent again on its
    kept pattern)."""
    parts = [[assembly.CellTangent(n, b) for n, b in item] for item, _ in sequence]
    frames = [f for _, f in sequence]
    assemble = assembly.FreeTangentAssembler(model.dofs)
    solver = linear.LinearSolver()

    def run(keep=None):
        for item, at in zip(parts, frames):
            k_ff, _ = assemble(item, at)
            factor = solver.factorise(k_ff)
            if keep is not None:
                keep.append((k_ff, factor.solve(np.ones(k_ff.shape[0]))))

    return run, (lambda: assemble(parts[-1], frames[-1]))


def best(call, rounds: int) -> float:
    times = []
    for _ in range(rounds):
        started = time.process_time()
        call()
        times.append(time.process_time() - started)
    return min(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ref", default="main")
    parser.add_argument("--patterns", type=int, default=40)
    parser.add_argument("--rounds", type=int, default=5)
    args = parser.parse_args()
    print(f"load before: {os.getloadavg()[0]:.1f}")
    model, sequence = tangents(args.patterns)
    with tempfile.TemporaryDirectory() as folder:
        package, commit = revision_modules(args.ref, Path(folder), MODULES)
        sides = {}
        for name, prefix in (("old", package), ("new", None)):
            assembly = importlib.import_module(
                f"{prefix}.assembly" if prefix else "femcore.assembly"
            )
            linear = importlib.import_module(f"{prefix}.linear" if prefix else "solvers.linear")
            sides[name] = side(assembly, linear, model, sequence)
        found = {}
        for name, (run, _) in sides.items():
            found[name] = []
            run(found[name])  # compiles or loads the kernels, and keeps the results
        same = all(
            np.array_equal(a.data, b.data)
            and np.array_equal(a.indices, b.indices)
            and np.array_equal(a.indptr, b.indptr)
            and np.array_equal(x, y)
            for (a, x), (b, y) in zip(found["old"], found["new"])
        )
        print(f"{args.ref} ({commit}) beside this tree: K_ff and its solutions the same: {same}")
        times = {name: [float("inf"), float("inf")] for name in sides}
        for _ in range(args.rounds):  # the sides in turns
            for name, (run, again) in sides.items():
                times[name][0] = min(times[name][0], best(run, 1))
                times[name][1] = min(times[name][1], best(again, 3))
        per = 1e3 / args.patterns
        old, new = times["old"], times["new"]
        print(f"a new pattern each tangent, assembled and factorised: {per * old[0]:.1f} ms ->")
        print(f"  {per * new[0]:.1f} ms a tangent ({old[0] / new[0]:.2f} x)")
        print(f"the same tangent on its kept pattern, assembled: {1e3 * old[1]:.2f} ms ->")
        print(f"  {1e3 * new[1]:.2f} ms")
    print(f"load after: {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
