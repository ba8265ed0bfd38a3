"""Speed of the fibrous shell: explicit steps per element, and a dynamic-relaxation solve.

1. ``CentralDifference`` on a square sheet of ``FibrousShell`` (G986 stack of Bai Table 1)
   with about 1k, 10k and 100k triangles, pinned on its boundary and loaded by gravity from
   rest, over a fixed number of steps at 0.9 x the stable step: microseconds per
   element-step (compilation excluded; frames only at the start and the end).
2. The two thickness options side by side on the same sheet, interleaved: the internal force
   and the element tangent with nodal normals (the default) and with Bai's Eq. 15 element
   normals, microseconds per element and their ratio.
3. ``DynamicRelaxation`` of a 40 x 10-cell cantilever strip (200 x 50 mm, G1151 laminate of
   Bai Table 2, clamped-edge option) under its own weight: wall time and iterations (the
   strip builder of the validation case fibrous-heavy-cantilever, validation.specimens).
4. ``--phases``: the explicit step on one thread in CPU time (honest on a shared machine,
   where wall time counts the other processes' turns): a whole run of ``--steps`` steps (its
   start and its two frames included) and the steady step (the difference of runs of N and
   2N steps per added element-step, as benchmarks/explicit_step.py measures it); the compiled
   force split into its passes (elements/fibrous/kernels.py), the energy check as a separate
   strain-energy pass and as the increment of the fused force-and-energy pass, beside the
   reference pass; and the peak memory per triangle of a run in a fresh process (its
   resident peak over the process's baseline after compilation).
5. ``--scaling``: the share of a step's CPU time on one thread spent outside the parallel
   loops (Python, numpy, serial compiled loops: what a second thread cannot shorten) with
   Amdahl's bound on 2 threads, then the step and each pass of the force on 1 and on 2
   threads (every loop on them, whatever the load), in turns, wall time, best of
   ``--repeats``.

Run from the project root:

    python benchmarks/fibrous_shell.py
    python benchmarks/fibrous_shell.py --sizes 1000,10000 --steps 50
    python benchmarks/fibrous_shell.py --phases --sizes 10000,100000 --skip-relaxation
    python benchmarks/fibrous_shell.py --scaling --sizes 100000 --steps 20

Measured on this 2-core machine (AMD EPYC, 2.6 GHz) shared with other processes (1-minute load
2.5-4 on 2 cores), CPU microseconds per element(-step) on one thread at 10k / 100k triangles
(CentralDifference 50 steps, frames at the start and the end; force and energy on the sheet
sagged into a bowl; memory: the peak of a fresh process's 20-step run over its baseline):

    before (main 3698780: four passes over copies of the corners, per-cell scratch arrays,
    the laws called with their tables, a full strain-energy pass):
        step 1.17 / 0.90, force 0.64 / 0.68, strain energy 0.63 / 0.67, 2059 / 2181 B/triangle
    after (three passes reading the nodes, scalars only, the laws inlined):
        step 0.40 / 0.39, force 0.30 / 0.33, strain energy 0.25 / 0.26, the energy with the
        force 0.08 more than the force alone, 1489 / 1493 B/triangle
    reference pass (wall) 0.07 / 0.08 in both runs; with the default 2 threads at a load of 4
    (free_cores leaves one): step wall 1.59 / 1.41 before, 0.53 / 0.73 after.

One reciprocal for the quotients that share a denominator (elements/fibrous/cell_terms.py:
35 fewer divisions and 2 fewer square roots per cell), measured against main ff266b3's
kernels in the same process, taken in turns, order flipped every pair, CPU time on one
thread, at a load of 6.7-8 on 2 cores (no quiet moment; absolute figures were 1.5-2.5 x
the quiet ones and varied by +-30 % between runs, so only the paired ratios are given),
median (quartiles) of new / old: force 20k 0.946 (0.89-1.03) over 150 pairs; force and
energy 100k 0.934 (best of 12); explicit step 20k 0.942 (0.88-1.01) over 150 pairs, 100k
0.965 (0.92-1.05) over 40. A 50-step run of ``step_cpu`` at 100k spends 7 % (median of 4,
load 8) outside its steps (its start, its two frames): the "CentralDifference step" row
carries it, the steady-step row does not. ``--scaling`` at 100k (20 steps, load 4.6): serial
share 0.072 of a step on one thread, so Amdahl's bound on 2 threads is 1.87 x (of it, by a
profile of 30 steps: the serial compiled update of the velocities, solvers/dynamics.py,
1.4 %; the external load 0.9 %; the Python around the loops); 2 threads 0.76 x one at that
load (no core was free: the 1.7 x of a quiet machine could not be measured).

The table law's energy inlined into the cell loops (elements/fibrous/packed_laws.py; the
bending laws of G986 are tables, met twice per cell by the energy check), on another 2-core
machine (Intel Xeon, AVX-512), one thread, CPU time, load 9-10 throughout. Paired in one
process against the previous kernels (a copy of main 7305bbb's kernels.py, cell_terms.py and
packed_laws.py imported beside the new ones, taken in turns, order flipped every round), 100k
triangles, 8 rounds: force 0.502 -> 0.492 us per element (best; median ratio 0.989, the same
numbers to the last bit), force and energy 0.631 -> 0.560 (median ratio 0.892); 5k, 40
rounds: force 0.99, force and energy 0.84. benchmarks/explicit_step.py --element fibrous
--sizes 100000 --repeats 3 on the previous tree (main 7305bbb exported) and on this one, one
after the other: whole run of 100 steps 0.546 -> 0.541 us per element-step, steady step
0.710 -> 0.532 (a difference of two runs: noisy at this load, the whole runs say the two
are equal within it), force 0.490 -> 0.462, force and energy 0.614 -> 0.530, reference pass
0.181 / 0.170 CPU: the whole run 3.0 / 3.2 x the reference pass. The Mindlin shell there
(same script, --element mindlin): steady step 0.185, whole run 0.222, reference 0.177.
Measured and left out, no gain: the corner, fold and shear angles by one arctan of a
quotient instead of arctan2 and arcsin (force 0.997 of the library's, paired, 5k, 60 rounds;
the library's arctan2 is as fast as its arctan inside the loops); numba's numpy error model
(no zero test per division), within the noise.

The level loop on scalars, measured and left out (no gain): the dot products of g_1, g_2
and n formed once per cell as polynomials in zeta of those of r_a, l_a and n, the levels'
loads kept as coefficients of g_1, g_2, n and turned into vectors once after the loop, and
one division per level for 1 / l_a^2, 1 / (|g1| |g2|) and 1 / |g1 x g2|: paired in one
process against the kernels of main 40ae4af, 100k triangles, one thread, CPU time, 30
rounds in turns at a load of 3-4, force 0.994 of the previous (median), force and energy
1.000, best 0.687 against 0.650 us per cell; the director moments moved by 4e-13 of the
largest. On the AMD machine at that load, with the level loop above (cProfile of 60 steps
at 100k, CPU time): the
cells' pass 67 % of a step, the pulls 9 %, the normals 7 %, the rotational update 4 %, the
nodal loads 3 %, the normal sums 3 %, the sums of dW/dS_k 2 %; a perf profile of the force:
libm about 30 % of it (atan2 15 %, log 7 %, asin 5 %). benchmarks/explicit_step.py
--element fibrous --sizes 100000 --repeats 3 on this tree and on main 40ae4af, one after
the other (the same step), load 3.5-5.8: steady step 1.16 and 0.99 us of CPU, 4.0 and 3.5 x
the reference pass (0.29 CPU; at a load of 6, earlier: 0.60, 3.4 x): the ratio is not met,
and at these loads a run's CPU figures vary by a factor of two.

Where a whole run's time goes, on the Intel machine at a load of 7-9, one thread, CPU time: a
cProfile of ``CentralDifference`` over 200 steps at 30k (1.09 us per element-step): the cells'
pass 63 %, the pulls' pass 9 %, the normals' pass 8 %, the rotational update and the motion
(solvers/turning.py) 3.7 %, the normal sums 2.6 %, the nodal loads 2.5 %, the sums of dW/dS_k
1.6 %, the velocities' update 1.3 %; the refresh every 10 steps of the rotary inertia 0.3 %
and of the cells' stable step below 0.2 %; the energy check (the fused force and energy every
10 steps) 0.014 us per element-step at 100k (force 0.817, force and energy 0.955 at that
load). A perf profile of the force at 20k: libm 23 % (atan2 of the corner and fold angles
14 %, log of the strains 8 %, asin of the shear 0.8 %), the compiled loops 57 %. Tried and
left out: LLVM's fused multiply-add (numba fastmath "contract") on the cells' pass, 0.963 of
the time (median of 30 paired rounds at 20k) but its moments and dW/dS_k 1.3e-11 (relative
to their largest) off the IEEE pass.

Work done twice no longer (elements/fibrous/kernels.py): each fold angle once per side shared
by two cells (a side pass after the normals writes the angle and the curvature scale for both
cells: 1.5 arctangents and roots per cell instead of 3), and a node's corner thickness, nodal
normal and director terms once per node (a node loop after the normal sums) instead of once
per corner (3 roots and 6 divisions per cell); the corner terms the same numbers to the last
bit, the folds within a rounding of the cell's own (forces 1.9e-16 of the largest apart on the
100k bowl, moments equal). Intel Xeon, one thread, CPU time, paired in one process against
the previous kernels (a copy of main 78b2577's kernels.py and cell_terms.py imported beside
the new ones, the block's kernels swapped, taken in turns, order flipped every round), 100k
triangles, the force on the bowl, the explicit step from rest (10 steps a turn, the energy
checked every 10th), new / old, median (quartiles): 20 rounds at a load of 5.5-5.8, force
0.958 (0.887-1.073), force and energy 0.974 (0.898-1.030), step 0.933 (0.890-0.963); best
force 0.526 -> 0.532 us per element, best step 0.479 -> 0.470 us per element-step, reference
pass 0.189 CPU (best; median 0.254): the step 2.53 -> 2.48 x the reference pass by the best
figures. 16 rounds at a load of 6.8 (a test run beside it): force 0.904 (0.811-1.061), step
0.928 (0.862-1.065); the side pass alone, 12 rounds at 6.7-7.5: force 0.931 (0.888-0.953),
force and energy 0.926, step 0.967 (0.906-1.030). benchmarks/explicit_step.py --element
fibrous --sizes 100000 --repeats 3 on the previous tree (a second checkout) and on this one,
one after the other, load 5.8-6.1: steady step 1.039 -> 0.743 us of CPU (4.8 -> 3.9 x the
reference pass, 0.217 / 0.192 CPU), but the whole runs of 100 steps 0.677 -> 0.704: the
steady step, a difference of two runs, moves by more than the change at these loads; force
0.589 -> 0.498, force and energy 0.752 -> 0.574, energy 0.440 -> 0.350. So about 5-7 % off a
step: 3 x the reference pass is met by the paired best figures and not by the steady-step
figure at this load, and 0.35 us per element-step is not met (best 0.47); the transcendental
functions left (12.5 a cell) and the cells' pass remain the bulk.
"""

from __future__ import annotations

import argparse
import math
import os
import platform
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install

import numpy as np  # noqa: E402
from fresh_process import fresh_output  # noqa: E402
from shell_sheet import GRAVITY, kernel_rows, print_explicit_table, reference_pass  # noqa: E402

from elements import FibrousShell  # noqa: E402
from elements.fibrous import geometry_kernels, kernels  # noqa: E402
from elements.shell_geometry import GUARD  # noqa: E402
from femcore import Mesh, Model  # noqa: E402
from materials import presets  # noqa: E402
from solvers import CentralDifference, DynamicRelaxation  # noqa: E402
from solvers.step import LumpedMasses, explicit_step  # noqa: E402
from validation.specimens import fibrous_strip  # noqa: E402

__all__ = [
    "force_phases",
    "main",
    "peak_memory",
    "relaxation",
    "serial_share",
    "steady_step",
    "step_cpu",
    "thickness_options",
    "thread_scaling",
]


def _sheet(triangles: int, kernel: str = "compiled"):
    """The benchmark sheet of shell_sheet.py (5 mm cells, pinned edges, gravity), compiled."""
    n = max(2, round(math.sqrt(triangles / 2)))
    mesh = Mesh.rectangle(5.0 * n, 5.0 * n, nx=n, ny=n)
    model = Model(mesh)
    model.add(FibrousShell(presets.g986_stack(), kernel=kernel))
    for edge in ("left", "right", "bottom", "top"):
        model.fix(edge, ["ux", "uy", "uz"])
    model.gravity(GRAVITY)
    return model.compile()


def step_cpu(triangles: int, steps: int) -> dict:
    """CentralDifference on the sheet for ``steps`` steps at 0.9 x the stable step (frames at
    the start and the end only): CPU and wall microseconds per element-step."""
    compiled = _sheet(triangles)
    dt = 0.9 * compiled.stable_dt(compiled.initial_state())
    solver = CentralDifference(
        duration=steps * dt, dt=dt, output_interval=steps * dt, progress=False
    )
    cpu, wall = time.process_time(), time.perf_counter()
    result = solver.solve(compiled)
    cpu, wall = time.process_time() - cpu, time.perf_counter() - wall
    per = 1e6 / (len(compiled.blocks[0].connectivity) * result.steps)
    return {"cpu": cpu * per, "wall": wall * per, "steps": result.steps}


def force_phases(triangles: int, repeats: int = 10, compiled=None, clock=time.process_time) -> dict:
    """CPU microseconds per element of each pass of the compiled force (best of
    ``repeats``; ``clock`` another clock) on the sheet sagged into a bowl (``compiled``: that
    sheet, already built), and of the energy: a separate strain-energy pass, and what the
    fused force-and-energy pass adds to the force."""
    compiled = _sheet(triangles) if compiled is None else compiled
    block = compiled.blocks[0]
    state = compiled.initial_state()
    x = state.positions
    centre = x[:, :2].mean(axis=0)
    state.positions = x + np.column_stack(
        [0 * x[:, 0], 0 * x[:, 0], 1e-3 * np.sum((x[:, :2] - centre) ** 2, axis=1)]
    )
    positions, directors = state.positions, state.directors
    m, corners = len(block.connectivity), block.node_corners
    best: dict[str, float] = {}

    def timed(name, function, *args):
        started = clock()
        out = function(*args)
        best[name] = min(best.get(name, math.inf), clock() - started)
        return out

    for _ in range(repeats + 1):  # the first round compiles or loads the loops
        normal, area, angles = timed(
            "1 cells: normals", geometry_kernels._cell_normals, block, positions, True
        )
        sums = np.empty((block.n_nodes, 3))
        timed("1 nodes: normal sums", geometry_kernels._normal_sums, corners.offsets,
              corners.corners, angles, normal, sums)  # fmt: skip
        frame = np.empty((block.n_nodes, 10))
        timed("1 nodes: frames", geometry_kernels._node_frames, sums, directors,
              block.node_in_block, float(block.fabric.thickness), GUARD, frame)  # fmt: skip
        side_fold, side_scale = timed(
            "1 sides: folds", geometry_kernels._shared_folds, block, positions, normal, area
        )
        force, moment, d_sums = (np.empty((m, 3, 3)) for _ in range(3))
        own, energy = np.empty((m, 3)), np.empty((0, 3))
        timed("2 cells: membrane, bending", kernels._cells_pass,
            block.connectivity, positions, directors, frame, normal, area, True,
            float(block.fabric.thickness), GUARD, block.zeta, block.weights,
            block.reference_area, block.reference_length1, block.reference_length2,
            block.shear_sign, block.reference_shear, block.xi_is_warp, *block.packed_laws,
            block.thickness_variation, side_fold, side_scale, block.interior_side,
            block.clamped_side, block.reference_normal, block.mirror_normal,
            block.reference_fold, block.reference_coefficients,
            block.reference_curvature_coefficients, True, False, force, moment, d_sums, own,
            energy)  # fmt: skip
        pull = timed("2 nodes: dW/dS sums", corners.sum, d_sums)
        timed("3 cells: pulls", kernels._pulls_pass,
            block.connectivity, positions, normal, area, angles, pull, True, own,
            block.across_cell, block.across_side, block.interior_side, force)  # fmt: skip
        out_force, out_moment = np.empty((block.n_nodes, 3)), np.empty((block.n_nodes, 3))
        timed("3 nodes: forces, moments", kernels._node_loads,
            corners.offsets, corners.corners, force.reshape(-1, 3), moment.reshape(-1, 3),
            out_force, out_moment)  # fmt: skip
        timed("internal_force", block.internal_force, state)
        timed("strain_energy", block.strain_energy, state)
        timed("internal_force_and_energy", block.internal_force_and_energy, state)
    return {name: 1e6 * value / m for name, value in best.items()}


def peak_memory(triangles: int, steps: int) -> float:
    """Bytes per triangle: the resident peak of a CentralDifference run of the sheet in a
    fresh process, over that process's baseline once the loops are compiled (Linux)."""
    return float(fresh_output("fibrous_shell", f"_memory_child({triangles}, {steps})").split()[-1])


def _memory_child(triangles: int, steps: int) -> None:
    """``peak_memory`` inside its fresh process: prints bytes per triangle."""

    def resident(key: str) -> int:
        with open("/proc/self/status") as status:
            return next(int(line.split()[1]) for line in status if line.startswith(key))

    step_cpu(200, 2)  # compile (or load) every loop first
    baseline = resident("VmRSS")
    with open("/proc/self/clear_refs", "w") as clear:
        clear.write("5")  # the peak starts from here
    step_cpu(triangles, steps)
    print(1024.0 * (resident("VmHWM") - baseline) / (2 * round(math.sqrt(triangles / 2)) ** 2))


def _start(compiled) -> tuple:
    """What ``_steps`` starts from: (the initial state, its lumped masses, 0.9 x its stable
    step)."""
    state = compiled.initial_state()
    return state, LumpedMasses.of(compiled, state), 0.9 * compiled.stable_dt(state)


def _steps(compiled, start: tuple, steps: int) -> None:
    """``steps`` explicit steps of the sheet from ``start`` (``_start``) as CentralDifference
    takes them (the energy checked every 10th), without its frames."""
    state, masses, dt = start
    previous = 0.0
    for step in range(steps):
        outcome = explicit_step(
            compiled, state, dt, masses, dt_prev=previous, duration=1.0, checking=step % 10 == 0
        )
        state, previous = compiled.commit(outcome.state), dt


def steady_step(triangles: int, steps: int) -> float:
    """CPU microseconds per element-step of a long run: CentralDifference over ``steps`` and
    over 2 ``steps`` steps, the difference of the two times per added element-step (the run's
    start and its two frames left out, as benchmarks/explicit_step.py measures it)."""
    short, long = step_cpu(triangles, steps), step_cpu(triangles, 2 * steps)
    return 2.0 * long["cpu"] - short["cpu"]


def serial_share(triangles: int, steps: int) -> float:
    """The share of a step's CPU time, on one thread, spent outside the parallel loops of
    femcore.jit (Python, numpy, the serial compiled loops): what a second thread cannot
    shorten (Amdahl)."""
    from femcore import jit

    compiled = _sheet(triangles)
    inside = [0.0]
    original = jit._Parallel.__call__

    def timed(self, *args):
        started = time.process_time()
        try:
            return original(self, *args)
        finally:
            inside[0] += time.process_time() - started

    start = _start(compiled)
    _steps(compiled, start, 2)  # warm
    jit._Parallel.__call__ = timed  # type: ignore[method-assign]
    try:
        started = time.process_time()
        _steps(compiled, start, steps)
        total = time.process_time() - started
    finally:
        jit._Parallel.__call__ = original  # type: ignore[method-assign]
    return 1.0 - inside[0] / total


def thread_scaling(triangles: int, steps: int, repeats: int) -> dict:
    """Wall seconds of ``steps`` explicit steps and of each pass of the force on 1 and on 2
    threads (every parallel loop on them: femcore.jit.FOLLOW_LOAD off), taken in turns,
    best of ``repeats``."""
    import numba

    from femcore import jit

    compiled = _sheet(triangles)
    start = _start(compiled)
    best: dict[tuple[str, int], float] = {}
    follow, before = jit.FOLLOW_LOAD, numba.get_num_threads()
    jit.FOLLOW_LOAD = False
    try:
        for _ in range(repeats):
            for threads in (1, 2):
                numba.set_num_threads(threads)
                started = time.perf_counter()
                _steps(compiled, start, steps)
                key = ("explicit step", threads)
                best[key] = min(best.get(key, math.inf), time.perf_counter() - started)
                for name, value in force_phases(
                    triangles, 1, compiled, clock=time.perf_counter
                ).items():
                    best[name, threads] = min(best.get((name, threads), math.inf), value)
    finally:
        jit.FOLLOW_LOAD = follow
        numba.set_num_threads(before)
    per = 1e6 / (len(compiled.blocks[0].connectivity) * steps)
    return {
        key: (value * per if key[0] == "explicit step" else value) for key, value in best.items()
    }


def print_scaling(sizes, steps: int, repeats: int) -> None:
    """The --scaling tables: the serial share of a step and 1 against 2 threads."""
    import numba

    numba.set_num_threads(1)
    step_cpu(200, 2)
    for size in sizes:
        share = serial_share(size, steps)
        print(
            f"{size} triangles: serial share of a step on one thread {share:.3f} (CPU), "
            f"Amdahl's bound on 2 threads {1.0 / (share + (1.0 - share) / 2.0):.2f} x; "
            f"1-minute load {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores"
        )
        rows = thread_scaling(size, steps, repeats)
        print(
            f"  {'wall us per element(-step)':37s} {'1 thread':>9s} {'2 threads':>9s} {'ratio':>6s}"
        )
        for name in dict.fromkeys(key[0] for key in rows):
            one, two = rows[name, 1], rows[name, 2]
            print(f"  {name:38s} {one:9.3f} {two:9.3f} {one / two:6.2f}")
        print(f"  1-minute load after: {os.getloadavg()[0]:.1f}", flush=True)


def print_phases(sizes, steps: int) -> None:
    """The --phases tables (see the module docstring, item 4)."""
    import numba

    numba.set_num_threads(1)
    step_cpu(200, 2)
    print(
        "FibrousShell on one thread, CPU microseconds per element (-step), "
        f"1-minute load {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores:"
    )
    rows = {}
    for size in sizes:
        rows[size] = force_phases(size) | {
            "CentralDifference step": step_cpu(size, steps)["cpu"],
            "steady step (runs of N and 2N steps)": steady_step(size, steps),
            "reference pass (wall)": reference_pass(size),
            "peak memory, bytes per triangle": peak_memory(size, 20),
        }
    print(f"{'':40s}" + "".join(f"{size:>12d}" for size in sizes))
    for name in rows[sizes[0]]:
        print(f"{name:40s}" + "".join(f"{rows[size][name]:12.3f}" for size in sizes))


def thickness_options(cells_per_side: int, repeats: int = 5) -> dict:
    """Internal force and tangent of one tilted, bent sheet with both thickness options,
    timed alternately (best of ``repeats``), microseconds per element."""
    mesh = Mesh.rectangle(100.0, 100.0, nx=cells_per_side, ny=cells_per_side)
    models = {}
    for option in ("nodal", "element"):
        model = Model(mesh)
        model.add(FibrousShell(presets.g986_stack(), thickness=option))
        models[option] = model.compile()
    state = models["nodal"].initial_state()
    x = mesh.points[:, 0]
    state.positions = state.positions + np.column_stack(
        [np.zeros_like(x), np.zeros_like(x), 0.002 * (x - 50.0) ** 2]
    )
    best = {(o, w): np.inf for o in models for w in ("force", "tangent")}
    for _ in range(repeats):
        for option, compiled in models.items():
            block = compiled.blocks[0]
            started = time.perf_counter()
            block.internal_force(state)
            best[option, "force"] = min(best[option, "force"], time.perf_counter() - started)
            started = time.perf_counter()
            block.tangent(state)
            best[option, "tangent"] = min(best[option, "tangent"], time.perf_counter() - started)
    elements = len(mesh.triangles)
    return {key: value / elements * 1e6 for key, value in best.items()} | {"elements": elements}


def relaxation() -> dict:
    """The G1151 strip of validation.specimens.fibrous_strip relaxed under its own weight."""
    mesh, model = fibrous_strip(200.0, 50.0, presets.g1151_laminate(), cells=40, across=10)
    compiled = model.compile()
    started = time.perf_counter()
    result = DynamicRelaxation(max_iterations=1_000_000).solve(compiled)
    wall = time.perf_counter() - started
    tip = mesh.nodes("right")
    return {
        "elements": len(mesh.triangles),
        "iterations": result.steps,
        "wall_s": wall,
        "tip_deflection_mm": float(-result.displacements[tip, 2].mean()),
    }


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="1000,10000,100000")
    parser.add_argument("--steps", type=int, default=100)
    parser.add_argument("--skip-relaxation", action="store_true")
    parser.add_argument("--thickness-cells", type=int, default=70)
    parser.add_argument("--phases", action="store_true", help="the one-thread CPU tables only")
    parser.add_argument(
        "--scaling", action="store_true", help="the serial share and 1 against 2 threads only"
    )
    parser.add_argument("--repeats", type=int, default=3, help="--scaling: best of")
    args = parser.parse_args(argv)
    print(f"python {platform.python_version()} on {platform.machine()} ({platform.system()})")
    sizes = [int(size) for size in args.sizes.split(",")]
    if args.phases:
        print_phases(sizes, args.steps)
        return
    if args.scaling:
        print_scaling(sizes, args.steps, args.repeats)
        return
    print_explicit_table(
        "FibrousShell, CentralDifference (the numpy path, and the compiled loops on 1 and on "
        "all threads):",
        kernel_rows(lambda kernel: FibrousShell(presets.g986_stack(), kernel=kernel)),
        sizes,
        args.steps,
    )
    row = thickness_options(args.thickness_cells)
    print(f"Thickness options on a {row['elements']}-triangle sheet (us per element, best of 5):")
    for what in ("force", "tangent"):
        nodal, element = row["nodal", what], row["element", what]
        print(
            f"  {what:8s} nodal normals {nodal:8.2f}   element normals (Bai Eq. 15) "
            f"{element:8.2f}   ratio {nodal / element:5.2f}"
        )
    if not args.skip_relaxation:
        row = relaxation()
        print(
            f"DynamicRelaxation, 40 x 10-cell strip ({row['elements']} triangles, G1151, "
            f"self-weight): {row['wall_s']:.1f} s, {row['iterations']} iterations, tip "
            f"deflection {row['tip_deflection_mm']:.2f} mm"
        )


if __name__ == "__main__":
    main()
