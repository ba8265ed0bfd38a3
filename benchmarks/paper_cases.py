"""The paper cases' cost (validation/cases/bai_*.py): where each run's CPU time goes, and the
element-normal membrane tangent (Bai Eq. 15, the "fibrous_element" run of every paper case)
by the compiled passes against the numpy loads it replaced, on each case's default mesh.

Part 1, ``--tangent`` (default): for each case, the fibrous shell with element normals on its
default mesh, jittered (0.05 mm) with tilted directors (0.05 rad): the CPU time of one
membrane tangent by central differences of the numpy loads (elements/base.py
``local_tangent`` of tangent.py ``membrane_loads``, the reference pass) and of the compiled
loads, the 36 perturbed copies of the cells in one call (``stacked_local_tangent`` of
kernels.py ``cell_membrane_loads``), best of ROUNDS; and the largest difference of the two
tangents over the largest entry (the differences' noise: loads within 1e-15, divided by 2 x
1e-6 of an element).

Part 3, ``--assembly``: one Newton iteration's tangent on bai-6.1.1's 40-cell corners
(``assembly_line``): the element parts, their assembly into K_ff and K_fp with the
SparseTangent's node blocks by numpy's matmuls and a bincount (the reference pass, the code
before) and by the compiled pass (femcore/assembly.py ``_add_node_blocks``), the upper
triangle's split by numpy (``_UpperPlan.split_numpy``, the code before) and compiled
(solvers/linear.py ``_split_upper``), and the factorisation.

Part 2, ``--solve CASE``: the case's seven Static runs (three kinematics on its default mesh,
the fibrous and the Mindlin on the two other meshes of its orders) one after the other in
this process, each run's CPU time, the part of it in the tangents and the factorisations,
its increments, Newton iterations and cuts.

Measured (one numba thread, CPU, 2 cores shared with other jobs):

Part 1 (load 14-15, best of 5), ms a tangent, numpy loads -> compiled loads, and the
largest difference of the two tangents over the largest entry:
  bai-5.1    120 cells  15.0 -> 1.6   3.3e-09
  bai-6.1.1  400 cells  28.5 -> 6.6   1.6e-09   (30 -> 3.8 at load 8-12)
  bai-6.1.2  144 cells  15.7 -> 2.0   1.5e-09
  bai-6.2.1  400 cells  28.3 -> 3.6   1.5e-09
  bai-6.2.2  144 cells  15.3 -> 2.0   1.4e-09
The whole cases, case_cpu_s of ``python -m validation --cases NAME --jobs 1`` (one thread,
a warm numba cache), main 05b57d7 beside each in fresh processes, load 13-17: bai-5.1 21.8
-> 16.5 s, bai-6.1.1 21.2 -> 19.2, bai-6.1.2 14.7 -> 12.9, bai-6.2.1 20.5 -> 18.6 (20.8 ->
40.2 in a run that recompiled a cache changed under it, not counted), bai-6.2.2 13.7 ->
12.4 and 13.6 -> 12.6: 91.9 -> 79.5 s for the five. Every check passes; the same
increments, Newton iterations and cuts in every run; the fibrous and the Mindlin runs'
results.json numbers the same bits, the Eq. 15 runs' within 3e-13 (mm, deg; the checks
comparing them with the others' within 3e-14), the same bits from one run to the next.
From an empty numba cache (a fresh copy of each tree, load 15 -> 11): bai-6.1.1 71.9 -> 69.4
s (user + system 74.5 -> 72.4 s): about 50 s of it compiling, which this does not touch (the
element-normal tangent reuses the force pass's compiled build).

Part 2 before (main 05b57d7, load 8-12; CPU s: run / tangents / factorisations):
  bai-6.1.1 (19.3 s of solves): fibrous 20 cells 2.30 / 1.13 / 0.39, fibrous Eq. 15 3.29 /
  2.73 / 0.29, Mindlin 0.71 / 0.29 / 0.09; orders: fibrous 10 0.44, Mindlin 10 0.29, fibrous
  40 9.48 / 3.62 / 4.74, Mindlin 40 2.76 / 0.98 / 0.75. 19-20 increments, 71-77 Newton
  iterations each, no cut: one tangent and one factorisation per iteration (75 per run).
  bai-5.1 (21.9 s): fibrous 30 2.80 / 1.48 / 0.23, fibrous Eq. 15 7.69 / 6.65 / 0.37,
  Mindlin 1.97; orders fibrous 15 2.02, Mindlin 15 1.09, fibrous 60 4.03, Mindlin 60 2.32.
  48-56 increments of 5 iterations (Crisfield's rule aims at DESIRED_ITERATIONS = 5), 6-11
  cuts, 316-405 tangents a run.
  bai-6.1.2 (13.7 s): fibrous 12 1.85, fibrous Eq. 15 2.99 / 2.56, Mindlin 0.56; orders
  fibrous 6 0.44, Mindlin 6 0.19, fibrous 24 5.94 / 3.42 / 1.70, Mindlin 24 1.73.
After (load 8-9): bai-6.1.2 10.3 s of solves, its fibrous Eq. 15 run 0.82 / 0.47 / 0.15
(before 2.99 / 2.56 / 0.17), the same increments, iterations and cuts in every run.
In a profile of bai-6.1.1 (wall, load 7-9): the band LDL^T 9.3 s of the 529 factorisations'
11.7, the tangents 16.9 (the fibrous Eq. 15 central differences 4.75, the nodal-normal
membrane Hessians 5.2, the assembly 3.7), the figures and files 7.3 s (matplotlib's layout),
the residuals 2.0; from an empty numba cache the first case spends most of its time
compiling (bai-6.1.1: 216 of 275 s in a profile).

Per tangent and factorisation of the 40-cell fibrous corner of bai-6.1.1 (4025 unknowns,
band 536, 6.4e8 envelope operations; load 12-16): 107 ms, the band LDL^T 52, the tangent 46
(the membrane Hessians 12, the assembly's node blocks 15, J^T H J 6, the upper triangle's
split 6).

Part 3 (one thread, best of 20, CPU ms, load 13-15), numpy -> compiled:
  fibrous  4025 unknowns: parts 27.9 (the membrane Hessians 13.6, the compiled J^T H J 6.4),
           assembly 8.7 -> 3.7, split 5.4 -> 1.8 (2.4 in a first version's two passes),
           factorise 49.8 (the split included; at load 2: assembly 8.6 -> 3.7, split 5.1
           -> 1.1); K_ff within 1.8e-16 of its largest entry
           (the node blocks' sums without BLAS's fused multiply-adds: 4 % of the entries
           differ), the splits the same bits.
  mindlin  4025 unknowns: parts 11.9, assembly 0.8 -> 0.7 (cell blocks only: the same
           bits), split 0.4 -> 0.2, factorise 8.8.
One tangent and factorisation of the 40-cell fibrous corner: about 8.6 ms less of its ~100.
The whole case, case_cpu_s of ``python -m validation --cases bai-6.1.1 --jobs 1`` (one
thread, a warm numba cache), main 5781687 from ``git archive`` beside it, alternately in
fresh processes, load 5-14: 18.57 / 17.99 / 17.14 -> 16.67 / 16.05 / 16.44 s (15.93 with
NUMBA_NUM_THREADS=2); load 2-3: 17.96 / 17.56 -> 15.92 / 16.33 s. The same increments
and Newton iterations (fibrous 19 / 74, Eq. 15 19 / 73, Mindlin 20 / 73), every check
passing; the Mindlin and the Eq. 15 runs' numbers
the same bits, the nodal-normal fibrous runs' within 1.1e-13 (mm, deg; the observed
orders within 1.2e-12); the same bits from one run to the next and on two threads. The
Static cantilever of benchmarks/kratos_cantilever.py (Mindlin: cell blocks only), best of
3, alternately: 0.865 / 0.863 / 0.841 / 0.824 -> 0.821 / 0.847 / 0.823 s CPU (load
12-16): within the noise; the same iterations [4, 5, 5, 5, 4] and tip drop
(120.65558875188611 mm) to the bit.

The linear solver (solvers/band.py by panels, solvers/supernodal.py; solvers/linear.py's
choice), Part 2 (``--solve``) of main de923eb beside this tree, alternately in fresh
processes, one thread, load 5.0-5.6: seconds of solves 16.73 -> 12.57 (bai-6.1.1), 16.01 -> 12.63
(bai-6.2.1), 8.57 -> 7.55 (bai-6.1.2), 8.07 -> 7.14 (bai-6.2.2), 11.17 -> 10.81 (bai-5.1, whose
strips keep the band: the same bits), 60.55 -> 50.70 for the five; the 40-cell fibrous runs'
factorisations 4.94 -> 2.16 and 4.66 -> 2.29 s (75-76 each), the 40-cell Mindlin runs' 0.79 ->
0.44 and 0.70 -> 0.41; the same increments, Newton iterations and cuts in every run. Their
results.json (``python -m validation`` on the six paper cases, every check passing) within
2.5e-11 of main's (mm, deg; bai-6.2.2's extrapolated order), 1.7e-11 relative; bai-5.1 the
same bits. What is left of the 40-cell fibrous run (6.1 s): the tangents 3.0 s, the
factorisations 2.2, the residuals and the rest 0.9.

Tried and not kept:
- A modified Newton in the arc-length corrector (the factorisation kept while the residual
  ratio fell by at least rho an iteration): on bai-6.1.1, fibrous 40 cells, rho 0.1: 19 ->
  24 increments, 73 -> 118 iterations, 75 -> 65 factorisations, 9.48 -> 9.71 s; rho 0.3: 29
  increments, 153 iterations, 10.75 s (Mindlin 20 cells 0.71 -> 0.92 s). Crisfield's rule
  shortens the steps of the increments that take more iterations, and eats the gain.
- The reverse Cuthill-McKee ordering from 34 other starting nodes (the 40-cell fibrous
  corner): none has fewer envelope operations than scipy's (6.43e8).
- LAPACK's band Cholesky (scipy.linalg.lapack.dpbtrf, one BLAS thread) where K_ff is
  positive definite: 29.5 against the envelope LDL^T's 49 ms on the 40-cell fibrous corner
  (made definite by a diagonal shift), 2.4 against 2.7-3.3 on 20 cells, 7.1 against 7.9 on
  the 40-cell Mindlin one, the same on the smaller: about 1.5 s of bai-6.1.1's and
  bai-6.2.1's fibrous 40-cell runs, at the cost of the BLAS's round-off (machine dependent)
  in every band solve, and of a wasted attempt on each indefinite K_ff. Not taken.

Run: python benchmarks/paper_cases.py [--rounds 5] [--solve bai-6.1.1 | --assembly]
"""

from __future__ import annotations

import argparse
import importlib
import os
import time

os.environ.setdefault("NUMBA_NUM_THREADS", "1")
os.environ["FIBRESHELL_PROGRESS"] = "0"

import sys
from pathlib import Path

import numpy as np  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this tree's packages

import solvers.static as static  # noqa: E402
from elements.base import local_tangent, stacked_local_tangent  # noqa: E402
from elements.fibrous import kernels  # noqa: E402
from elements.fibrous.tangent import membrane_loads  # noqa: E402
from femcore.rotation import rotate_about  # noqa: E402
from validation.paper.case import solve  # noqa: E402
from validation.paper.kinematics import KINEMATICS  # noqa: E402
from validation.paper.orders import ORDER_KINEMATICS  # noqa: E402

MODULES = {
    "bai-5.1": "bai_5_1",
    "bai-6.1.1": "bai_6_1_1",
    "bai-6.1.2": "bai_6_1_2",
    "bai-6.2.1": "bai_6_2_1",
    "bai-6.2.2": "bai_6_2_2",
}


def spec_of(name: str):
    return importlib.import_module(f"validation.cases.{MODULES[name]}").SPEC


def build(spec, kinematics: str, cells: int):
    return spec.model(spec.make_specimen(cells), kinematics)


def best(function, rounds: int) -> float:
    """The least CPU time (s) of ``rounds`` calls."""
    times = []
    for _ in range(rounds):
        started = time.process_time()
        function()
        times.append(time.process_time() - started)
    return min(times)


def tangent_line(name: str, rounds: int) -> str:
    """Part 1 of the docstring for case ``name``: its line of the table."""
    spec = spec_of(name)
    compiled = build(spec, "fibrous_element", spec.cells["default"]).compile()
    block = compiled.blocks[0]
    state = compiled.initial_state()
    rng = np.random.default_rng(0)
    positions = state.positions + rng.normal(scale=0.05, size=state.positions.shape)
    turn = np.cross(state.directors, rng.normal(scale=0.05, size=state.positions.shape))
    directors = rotate_about(state.directors, turn)
    x, v = positions[block.connectivity], directors[block.connectivity]
    step = 1e-6 * float(np.sqrt(np.median(block.reference_area)))

    def numpy_pass():
        return local_tangent(lambda xx, vv: membrane_loads(block, xx, vv), x, v, step)

    def compiled_pass():
        return stacked_local_tangent(
            lambda xs, vs: kernels.cell_membrane_loads(block, xs, vs), x, v, step
        )

    reference, fast = numpy_pass(), compiled_pass()
    difference = np.abs(fast - reference).max() / np.abs(reference).max()
    times = best(numpy_pass, rounds), best(compiled_pass, rounds)
    return f"{name:10s} {len(x):5d} {1e3 * times[0]:9.1f} {1e3 * times[1]:12.1f} {difference:11.2e}"


def tangents(rounds: int) -> None:
    print(f"{'case':10s} {'cells':>5s} {'numpy ms':>9s} {'compiled ms':>12s} {'difference':>11s}")
    for name in MODULES:
        print(tangent_line(name, rounds), flush=True)


def assembly_line(kinematics: str, rounds: int) -> str:
    """Part 3 of the docstring: one Newton iteration's tangent on bai-6.1.1's 40-cell corner
    of ``kinematics``, jittered with tilted directors, best of ``rounds`` (ms, CPU): the
    element parts, their assembly into K_ff and K_fp with the node blocks by numpy's matmuls
    and bincount (the reference pass) and by the compiled pass, the upper triangle's split by
    numpy and compiled, the factorisation (the compiled split and the band LDL^T); and the
    largest difference of the two K_ff over its largest entry, whether the splits agree to
    the bit."""
    from dataclasses import replace

    from femcore import assembly
    from solvers.linear import LinearSolver
    from solvers.newton import Tangent

    model = build(spec_of("bai-6.1.1"), kinematics, 40).compile()
    state = model.initial_state()
    rng = np.random.default_rng(0)
    positions = state.positions + rng.normal(scale=0.05, size=state.positions.shape)
    turn = np.cross(state.directors, rng.normal(scale=0.05, size=state.positions.shape))
    state = replace(state, positions=positions, directors=rotate_about(state.directors, turn))
    tangent = Tangent(model, list(range(len(model.blocks))), [])
    frames = model.dofs.frames(state.directors)
    parts = model.tangent_parts(state, tangent.own)
    compiled = assembly._add_node_blocks_compiled

    def numpy_assembly():
        assembly._add_node_blocks_compiled = None
        try:
            return tangent.assemble(parts, frames)
        finally:
            assembly._add_node_blocks_compiled = compiled

    k_ff = tangent.assemble(parts, frames)[0]
    reference = numpy_assembly()[0]
    difference = np.abs(k_ff.data - reference.data).max() / np.abs(reference.data).max()
    linear = LinearSolver()
    linear.factorise(k_ff)
    plan = linear._plan_for(k_ff)
    fast, slow = plan.split(k_ff.data)[1], plan.split_numpy(k_ff.data)[1]
    same = np.array_equal(fast.data, slow.data) and np.array_equal(fast.indices, slow.indices)
    figures = [
        best(lambda: model.tangent_parts(state, tangent.own), rounds),
        best(numpy_assembly, rounds),
        best(lambda: tangent.assemble(parts, frames), rounds),
        best(lambda: plan.split_numpy(k_ff.data), rounds),
        best(lambda: plan.split(k_ff.data), rounds),
        best(lambda: linear.factorise(k_ff), rounds),
    ]
    ms = [1e3 * f for f in figures]
    return (
        f"{kinematics:8s} {k_ff.shape[0]} unknowns: parts {ms[0]:.1f}, assembly {ms[1]:.1f} -> "
        f"{ms[2]:.1f}, split {ms[3]:.1f} -> {ms[4]:.1f}, factorise {ms[5]:.1f} ms; K_ff within "
        f"{difference:.1e}, the splits the same bits: {same}"
    )


def runs(name: str) -> None:
    """Part 2 of the docstring for case ``name``."""
    spec = spec_of(name)
    spent = {"tangent": 0.0, "factorise": 0.0}
    originals = {key: getattr(static.StaticRun, key) for key in spent}

    def timed(key):
        def wrapper(self, *args, **kwargs):
            started = time.process_time()
            try:
                return originals[key](self, *args, **kwargs)
            finally:
                spent[key] += time.process_time() - started

        return wrapper

    default = spec.cells["default"]
    sequence = [(k, default) for k in KINEMATICS] + [
        (k, c) for c in spec.order_cells["default"] if c != default for k in ORDER_KINEMATICS
    ]
    for key in spent:
        setattr(static.StaticRun, key, timed(key))
    total = 0.0
    try:
        for kinematics, cells in sequence:
            model = build(spec, kinematics, cells)
            spent.update(tangent=0.0, factorise=0.0)
            started = time.process_time()
            result, _, _ = solve(model, spec.increments)
            cpu = time.process_time() - started
            total += cpu
            info = result.info
            print(
                f"{name} {kinematics:16s} {cells:3d} cells: {cpu:6.2f} s, tangents "
                f"{spent['tangent']:5.2f}, factorisations {spent['factorise']:5.2f}; "
                f"{len(result.frames) - 1} increments, "
                f"{sum(info['iterations_per_increment'])} iterations, {info['cuts']} cuts, "
                f"{info['evaluations']['tangent']} tangents",
                flush=True,
            )
    finally:
        for key, original in originals.items():
            setattr(static.StaticRun, key, original)
    print(f"{name}: {total:.2f} s of solves")


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--solve", default=None, choices=list(MODULES))
    parser.add_argument("--assembly", action="store_true")
    args = parser.parse_args()
    print(f"load before: {os.getloadavg()}")
    if args.assembly:
        for kinematics in ("fibrous", "mindlin"):
            print(assembly_line(kinematics, args.rounds), flush=True)
    elif args.solve is None:
        tangents(args.rounds)
    else:
        runs(args.solve)
    print(f"load after: {os.getloadavg()}")


if __name__ == "__main__":
    main()
