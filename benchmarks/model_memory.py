"""What a large shell model costs to build and hold: peak memory and seconds, stage by stage.

For each shell (the Mindlin shell, aluminium h = 1 mm; the fibrous shell, G986 stack) and each
size, in a fresh process of its own (one numba thread), on the pinned square sheet of
``shell_sheet.py`` (5 mm cells, under gravity):

* the baseline: the process's resident memory and peak (``resource.getrusage``'s
  ``ru_maxrss``) after the imports and a 200-triangle sheet built and stepped (the compiled
  loops loaded from numba's cache, so that neither the loading nor the compiling is counted
  as the model's);
* the mesh's generation, apart (wall and CPU seconds, resident memory it added);
* ``Model.compile`` split by stage (wall and CPU seconds; the process's peak above the
  baseline at the end of each stage, kB per triangle): the triangle checks, the DOF numbering
  (``DofManager``), the reference directors (nodal normals), the median edge, the element
  block's set-up (``bind``), its checks, its supports, the lumped mass, the rest;
* the solver's state and a few explicit steps, twice: ``CentralDifference`` with a given step
  (0.9 x the cells' stable step), then with the solver's own (the cells' bound and the
  assembled Gershgorin bound, femcore/gershgorin.py), each split into its start (initial
  state, lumped mass, the stable step, the first frame) and its steps;
* the peak of the whole process above the baseline, kB per triangle (what issue 30 bounds by
  2 kB a triangle), and the whole peak with the interpreter's.

The stages are timed by wrapping the functions ``CompiledModel`` and ``CentralDifference``
call (in the child process only); "rest" is what the wrapped calls leave of the whole. Each
row's peak and resident memory are those when its stage last returned; the CPU time includes
the system's share ("of it sys"), most of it the first touch of fresh memory ("faults": minor
page faults). ``--reference`` runs each case first as before ``femcore.memory.small_pages``
(numpy's advice of huge pages kept in the build, the Mindlin calibration and the assembled
bound), then as now.

Measured on main 8a6e6f5 and after, the 2-core AMD EPYC machine shared with other runs (load
7.8-10.8), ``--reference``, 10 steps a run; the build's CPU seconds (of it system), the peak
above the baseline (kB a triangle; with the interpreter's in brackets):

    case            build before        build after         peak before      peak after
    Mindlin 100k    0.278 (0.044)       0.291 (0.066)       1.496 (3.38)     1.496 (3.39)
    Mindlin 400k    2.845 (1.939)       1.223 (0.301)       1.368 (1.84)     1.368 (1.84)
    fibrous 100k    0.371 (0.066)       0.407 (0.099)       2.615 (4.61)     2.622 (4.62)
    fibrous 400k    5.236 (3.964)       1.822 (0.404)       1.501 (2.00)     1.510 (2.01)

With every change of this series (the fibrous bind in slices too), ``--reference`` once more,
load 4.7-9.4, build CPU s with numpy's advice kept -> held back (peak above the baseline, kB a
triangle, held back):
Mindlin 100k 0.796 -> 0.297 (1.496), 400k 2.379 -> 1.245 (1.368); fibrous 100k 0.357 ->
0.360 (2.585 with the solver's own step, its assembled bound), 400k 2.953 -> 1.631 (1.518).
Two earlier pairs at 400k (load 8-12): Mindlin 3.42 / 2.34 -> 1.26 / 1.22 s CPU (system 2.43 /
1.38 -> 0.29 / 0.27, ``Model.compile`` alone after the loops), fibrous 5.97 -> 1.74 (4.62 ->
0.45). At 100k huge pages cost nothing much (the same within this machine's noise); at 400k
the build's arrays pass glibc's largest mmap threshold (32 MB), each is mapped afresh, and
the kernel zeroes, and compacts memory for, every huge page it gives them. The first call of
the Mindlin cells' stable step (its calibration) 1.49-1.68 s CPU (1.24-1.41 system) -> 0.37
(0.09-0.13). The values are the same to the bit (pages change where memory lies, not what is
computed): ``--step-pair`` steps a model built each way in turns in one process and compares
the positions after ten steps; the step on the small-page model is no slower, within 1 %
(100k, load 7.7-8.7, two runs each: Mindlin 0.990 and 0.985 of the other, quartiles
0.980-0.998 and 0.971-0.999; fibrous 0.995 and 1.007, 0.991-0.999 and 1.001-1.011; the same
bits each time).

Where the peaks are: the run itself (the model's 0.86-0.91 kB a triangle resident and the
steps' states and temporaries, 1.27-1.41 kB resident during the steps at 400k), the Mindlin
calibration's temporaries (0.41 kB a triangle above the built model at 400k, reached once)
and, before it was formed in slices of 8192 cells (elements/fibrous/block.py
``_reference_geometry``), the fibrous block's bind. That slicing, 400k, load 9.0-9.4: the bind
0.980 -> 0.663 s CPU (157 -> 57 thousand page faults), the build 1.822 -> 1.429 s, the
build's peak 1.447 -> 0.814 kB a triangle above the baseline (100k: 1.432 -> 0.797, the bind
0.220 -> 0.168 s); the whole run's peak is now the steps' (1.43 with a given step).
The fibrous sheet with the solver's own step at 100k peaked at 2.6-2.95 kB a triangle,
above issue 30's 2: the assembled bound's pieces of 4096 cells took 70-84 MB each whatever
the sheet's size (12.7 kB a triangle at 10k), and smaller ones would have changed the bound's
round-off. The pieces are now the whole tangent's complete rows a run of nodes at a time
(elements/fibrous/tangent_pieces.py, docs/theory.md §2.6), the same bits whatever their
length, and a 96th of the nodes (32-1024); the Mindlin pieces a 24th of the cells
(256-4096), the same bits whatever their size too (femcore/gershgorin.py). Main cfaff59
(a ``git archive`` in /tmp) and this, each case in its fresh process, 10 steps, one thread,
load 4.4-9.3, the whole run's peak above the baseline, kB a triangle, own step (the bound's
CPU s):

    case            main                 now
    fibrous 10k     12.715 (0.356)       1.835 (0.692)
    fibrous 100k     2.952 (3.451)       1.877 (4.316)
    fibrous 400k     1.971 (15.2)        1.840 (17.7)
    Mindlin 10k      3.992 (0.094)       1.714 (0.091)
    Mindlin 100k     1.641 (0.715)       1.523 (0.720)
    Mindlin 400k     1.521 (2.909)       1.521 (2.861)

The step and the positions after 30 steps of the 10k and 100k sheets of both shells the same
bits as main's. The fibrous bound costs more CPU (1.9, 1.25 and 1.16 x at 10k, 100k and 400k;
the bound alone at 100k in turns, best of 3, load 8.3-8.8: 3.39-3.43 -> 4.32-4.39 s, its peak
above the built model 223-226 -> 100-102 MB): each run forms the
Hessians, Jacobians and bending patches of its halo too (H's rows shared with the next run
are kept, not formed again); the model build is unchanged (400k: 1.34 and 1.18 s CPU, both
well under 3). The build at 400k now: the fibrous bind 0.66 s of 1.43, the triangle checks 0.34;
the Mindlin bind 0.57 of 1.22 (its compiled tables, 1.4 µs a cell).

The explicit step at 400k pays the system much: the fibrous steps 4.1-4.4 s CPU for ten, 1.9-2.1
of it system (35-39 thousand page faults); ``solvers.step.explicit_step`` alone, 30 steps,
load 7.4-7.8: 0.403 user + 0.231 system µs an element-step (2243 faults a step, on huge
pages), 0.405 + 0.126 with numpy's advice off (25596 faults a step) and 0.406 + 0.000 with
glibc told to keep its memory (``MALLOC_MMAP_THRESHOLD_=1000000000
MALLOC_TRIM_THRESHOLD_=2000000000`` in the environment, no fault); Mindlin 0.171 + 0.023. The
step's (m, 3, 3) arrays are allocated and freed at every step and glibc hands them back to the
kernel; at 100k none is (no fault a step). Tried outside the tree and not made (the force
path of elements/fibrous/kernels.py is not this script's to change, and a block's scratch
needs care with threads and pickling): the cell pass's three (m, 3, 3) arrays (force,
moment, dW/dS) kept on the block between calls, 400k, 30 steps, load 8.6-9.1: 0.419 user +
0.127 system -> 0.399 + 0.000 µs an element-step, no fault, the same positions. Since made
(femcore/workspace.py, every per-step array of the fibrous passes and the Mindlin corner
loads), measured beside arrays made afresh by benchmarks/step_workspace.py.

Run from the project root (one 400k case at a time; about 1 GB at 400k triangles):

    python benchmarks/model_memory.py
    python benchmarks/model_memory.py --reference --elements mindlin --sizes 400000
    python benchmarks/model_memory.py --step-pair 12 --sizes 100000
"""

from __future__ import annotations

import argparse
import contextlib
import functools
import gc
import math
import os
import resource
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install

from fresh_process import fresh_output  # noqa: E402
from shell_sheet import GRAVITY  # noqa: E402

ALUMINIUM = dict(E=70e3, nu=0.3, thickness=1.0, density=2.7e-9)  # MPa, mm, t/mm^3


def element(name: str):
    """A fresh element of the benchmark's kind (compiled kernels)."""
    if name == "mindlin":
        from elements import MindlinShell
        from materials import ElasticShell

        return MindlinShell(ElasticShell(**ALUMINIUM))
    from elements import FibrousShell
    from materials import presets

    return FibrousShell(presets.g986_stack())


def resident_mb() -> float:
    """The process's resident memory now, MB (Linux /proc)."""
    with open("/proc/self/statm") as statm:
        pages = int(statm.read().split()[1])
    return pages * os.sysconf("SC_PAGE_SIZE") / 2**20


def kernel_side() -> tuple[float, float]:
    """(system CPU seconds, minor page faults) of this process so far: the kernel's share of
    the CPU time, most of it the first touch of newly allocated memory."""
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_stime, float(usage.ru_minflt)


def peak_mb() -> float:
    """The process's peak resident memory so far, MB (Linux reports kB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


class Stages:
    """Seconds and memory of named stages, in the order they ended: each wrapped call adds its
    wall and CPU seconds to its stage (``prefix`` + name) and records the process's peak and
    resident memory when it returns."""

    def __init__(self):
        self.rows: dict[str, list[float]] = {}
        self.prefix = ""
        self._depth = 0

    def wrap(self, name: str, function):
        """``function`` timed as the stage ``name`` (an inner wrapped call inside another is
        counted in the outer one only)."""

        @functools.wraps(function)
        def timed(*args, **kwargs):
            if self._depth:
                return function(*args, **kwargs)
            self._depth += 1
            wall, cpu, system = time.perf_counter(), time.process_time(), kernel_side()
            try:
                return function(*args, **kwargs)
            finally:
                self._depth -= 1
                self.add(
                    name,
                    time.perf_counter() - wall,
                    time.process_time() - cpu,
                    *(b - a for a, b in zip(system, kernel_side())),
                )

        return timed

    def add(
        self, name: str, wall: float, cpu: float, system: float = 0.0, faults: float = 0.0
    ) -> None:
        row = self.rows.setdefault(self.prefix + name, [0.0] * 6)
        row[0] += wall
        row[1] += cpu
        row[2], row[3] = peak_mb(), resident_mb()
        row[4] += system
        row[5] += faults

    def whole(self, call):
        """``call()`` timed as the stage "whole" and what its wrapped stages leave of it as
        "rest"; returns what it returns."""
        before = {key: list(row) for key, row in self.rows.items()}
        wall, cpu, system = time.perf_counter(), time.process_time(), kernel_side()
        result = call()
        spent = [
            time.perf_counter() - wall,
            time.process_time() - cpu,
            *(b - a for a, b in zip(system, kernel_side())),
        ]
        inner = [0.0] * 4
        for key, row in self.rows.items():
            if key.startswith(self.prefix):
                old = before.get(key, [0.0] * 6)
                for i, column in enumerate((0, 1, 4, 5)):
                    inner[i] += row[column] - old[column]
        self.add("rest", *(a - b for a, b in zip(spent, inner)))
        self.add("whole", *spent)
        return result

    def patch(self, owner, attribute: str, name: str) -> None:
        setattr(owner, attribute, self.wrap(name, getattr(owner, attribute)))


def pinned_sheet(name: str, mesh):
    from femcore import Model

    model = Model(mesh)
    model.add(element(name))
    for edge in ("left", "right", "bottom", "top"):
        model.fix(edge, ["ux", "uy", "uz"])
    model.gravity(GRAVITY)
    return model


def sheet_mesh(triangles: int):
    from femcore import Mesh

    n = max(2, round(math.sqrt(triangles / 2)))
    return Mesh.rectangle(5.0 * n, 5.0 * n, nx=n, ny=n)


def _case_child(name: str, triangles: int, steps: int, huge_pages: bool = False) -> None:
    """One case in its fresh process: prints a line ``stage|wall|cpu|peak|resident|system|
    faults`` per stage (seconds, MB, faults), then ``baseline|...`` and ``cells|...``.
    ``huge_pages``: the build and the assembled bound with numpy's own advice of huge pages
    (the reference pass: as before femcore.memory.small_pages)."""
    import femcore.compiled as compiled_module
    from femcore.compiled import CompiledModel
    from solvers import CentralDifference

    def explicit(compiled, given: bool):
        """``steps`` steps of 0.9 x the cells' stable step, given (or the solver's own)."""
        cells = 0.9 * compiled.stable_dt(compiled.initial_state())
        duration = steps * cells
        solver = CentralDifference(
            duration=duration, dt=cells if given else None, output_interval=duration,
            progress=False,
        )  # fmt: skip
        return solver.solve(compiled)

    if huge_pages:  # every femcore.memory.small_pages leaves numpy's advice as it is
        import numpy._core.multiarray as numpy_arrays

        numpy_arrays._set_madvise_hugepage = lambda enabled: numpy_arrays._get_madvise_hugepage()
    small = pinned_sheet(name, sheet_mesh(200)).compile()  # the loops loaded or compiled
    explicit(small, True)
    explicit(small, False)
    del small
    gc.collect()
    baseline = (peak_mb(), resident_mb())

    stages = Stages()
    for function, label in (
        ("check_triangles", "triangle checks"),
        ("DofManager", "DOF numbering"),
        ("nodal_normals", "directors"),
        ("median_edge", "median edge"),
        ("check_block", "block checks"),
    ):
        stages.patch(compiled_module, function, label)
    stages.patch(CompiledModel, "_element_lumped_mass", "lumped mass")
    stages.patch(CompiledModel, "initial_state", "initial state")
    stages.patch(CompiledModel, "strain_energy", "strain energy")
    stages.patch(CompiledModel, "cell_stable_dt", "cells' stable step")
    stages.patch(CompiledModel, "assembled_stable_dt", "assembled stable step")
    stages.patch(CentralDifference, "_march", "steps")

    stages.prefix = "mesh: "
    mesh = stages.wrap("generation", sheet_mesh)(triangles)
    model = pinned_sheet(name, mesh)
    shell = model.blocks[0].element
    bind = shell.bind

    def bound(*args):
        block = bind(*args)
        stages.patch(block, "apply_supports", "block supports")
        return block

    object.__setattr__(shell, "bind", stages.wrap("block set-up (bind)", bound))
    stages.prefix = "compile: "
    compiled = stages.whole(model.compile)

    for label, given in (("run, given dt: ", True), ("run, own dt: ", False)):
        stages.prefix = label
        stages.whole(lambda given=given: explicit(compiled, given))
    for key, row in stages.rows.items():
        print("|".join([key, *map(str, row)]))
    print(f"baseline|0|0|{baseline[0]}|{baseline[1]}|0|0")
    print(f"cells|{len(mesh.triangles)}|{mesh.n_nodes}|0|0|0|0")


def case(name: str, triangles: int, steps: int, huge_pages: bool = False) -> None:
    """Run one case in a fresh process and print its table."""
    out = fresh_output("model_memory", f"_case_child({name!r}, {triangles}, {steps}, {huge_pages})")
    rows = {}
    for line in out.strip().splitlines():
        key, *values = line.split("|")
        rows[key] = [float(v) for v in values]
    cells, nodes = int(rows["cells"][0]), int(rows["cells"][1])
    base_peak, base_resident = rows.pop("baseline")[2:4]
    del rows["cells"]
    per = 1024.0 / cells  # MB -> kB per triangle
    print(
        f"\n{name}{' (huge pages: the reference pass)' if huge_pages else ''}, {cells} "
        f"triangles, {nodes} nodes, {steps} steps a run; baseline after "
        f"the imports and the loops: peak {base_peak:.0f} MB, resident {base_resident:.0f} MB; "
        f"load {os.getloadavg()[0]:.2f}"
    )
    print(
        f"  {'stage':<34} {'wall s':>7} {'CPU s':>7} {'of it sys':>9} {'faults':>8} "
        f"{'peak-base MB':>12} {'kB/tri':>7} {'resident-base MB':>16} {'kB/tri':>7}"
    )
    for key, (wall, cpu, peak, resident, system, faults) in rows.items():
        print(
            f"  {key:<34} {wall:7.3f} {cpu:7.3f} {system:9.3f} {faults:8.0f} "
            f"{peak - base_peak:12.0f} {(peak - base_peak) * per:7.3f} "
            f"{resident - base_resident:16.0f} {(resident - base_resident) * per:7.3f}"
        )
    final = max(row[2] for row in rows.values())
    print(
        f"  whole process: peak {final - base_peak:.0f} MB above the baseline "
        f"({(final - base_peak) * per:.3f} kB per triangle), {final:.0f} MB with the "
        f"interpreter's ({final * per:.3f} kB per triangle)",
        flush=True,
    )


def step_pair(name: str, triangles: int, rounds: int) -> None:
    """Does a model built on small pages step slower? Two models of the same sheet in this
    process, one built with numpy's advice of huge pages (the reference) and one without
    (as ``Model.compile`` builds), ten explicit steps of each in turns (the order swapped
    each round), CPU time: best of each, the median of the per-round ratios and the
    positions after ten steps compared bit for bit."""
    import numba
    import numpy as np

    import femcore.model
    from solvers.step import LumpedMasses, explicit_step

    numba.set_num_threads(1)
    pinned_sheet(name, sheet_mesh(200)).compile()  # the loops loaded or compiled
    small = pinned_sheet(name, sheet_mesh(triangles)).compile()
    kept = femcore.model.small_pages
    femcore.model.small_pages = contextlib.nullcontext  # the advice as numpy gives it
    try:
        huge = pinned_sheet(name, sheet_mesh(triangles)).compile()
    finally:
        femcore.model.small_pages = kept
    runs = {}
    for label, compiled in (("small", small), ("huge", huge)):
        state = compiled.initial_state()
        runs[label] = (
            compiled,
            state,
            0.9 * compiled.stable_dt(state),
            LumpedMasses.of(compiled, state),
        )
    times: dict[str, list[float]] = {"small": [], "huge": []}
    ends = {}
    for index in range(rounds):
        for label in ("small", "huge") if index % 2 == 0 else ("huge", "small"):
            compiled, state, dt, masses = runs[label]
            started = time.process_time()
            for _ in range(10):
                state = explicit_step(compiled, state, dt, masses, duration=1.0).state
            times[label].append(time.process_time() - started)
            ends[label] = state.positions
    cells = len(small.mesh.triangles)
    ratio = np.array(times["small"]) / np.array(times["huge"])
    print(
        f"{name}, {cells} triangles, {rounds} rounds of 10 steps: best "
        f"{1e6 * min(times['small']) / (10 * cells):.4f} us/element-step built on small pages, "
        f"{1e6 * min(times['huge']) / (10 * cells):.4f} on huge; median ratio "
        f"{np.median(ratio):.3f} (quartiles {np.quantile(ratio, 0.25):.3f}-"
        f"{np.quantile(ratio, 0.75):.3f}); positions the same to the bit: "
        f"{np.array_equal(ends['small'], ends['huge'])}; load {os.getloadavg()[0]:.2f}",
        flush=True,
    )


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--elements", default="mindlin,fibrous")
    parser.add_argument("--sizes", default="100000,400000")
    parser.add_argument("--steps", type=int, default=10)
    parser.add_argument(
        "--reference",
        action="store_true",
        help="each case also with numpy's advice of huge pages kept in the build and the "
        "assembled bound (as before femcore.memory.small_pages), in turns",
    )
    parser.add_argument(
        "--step-pair",
        type=int,
        default=0,
        metavar="ROUNDS",
        help="instead: the explicit step of a model built on small pages against one built "
        "on huge pages, in one process, ROUNDS rounds",
    )
    args = parser.parse_args(argv)
    for name in args.elements.split(","):
        if name not in ("mindlin", "fibrous"):
            raise ValueError(f"--elements takes mindlin and fibrous, got {name!r}")
        if args.step_pair:
            for size in [int(s) for s in args.sizes.split(",")]:
                step_pair(name, size, args.step_pair)
            continue
        for size in [int(s) for s in args.sizes.split(",")]:
            if args.reference:
                case(name, size, args.steps, huge_pages=True)
            case(name, size, args.steps)


if __name__ == "__main__":
    main()
