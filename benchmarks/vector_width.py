"""How wide LLVM runs the fibrous force's loops across cells here, and whether a wider vector
pays: the question of what the cells' lanes (elements/fibrous/level_lanes.py) get from the
processor.

numba builds for the host processor as LLVM names it, and LLVM's tuning of that name decides
the vector width of a loop it vectorises: on the Intel Xeon of this machine LLVM says
"rocketlake", whose tuning has ``prefer-256-bit``, so a loop across cells runs 4 doubles at a
time in ymm registers although the processor has AVX-512 (on the AMD EPYC, znver4, the same
loops ran 8 wide in zmm). ``NUMBA_CPU_FEATURES`` with ``-prefer-256-bit`` added to the host's
features, set before numba loads, lifts the preference for the whole process.

Each round runs two fresh processes, one thread each, the host's features and the 512-bit
ones in turns (the order flipped every round), each with a numba cache of its own: the
compiled force (``internal_force``) and the cells' pass alone on the sheet of
benchmarks/fibrous_shell.py sagged into a bowl, CPU µs a cell, best of ``--calls``.
``--registers`` (a fresh, empty cache per process: numba inspects only what it compiles)
prints, per compiled loop of the force, how many instructions name zmm, ymm and xmm
registers. ``--perf-map`` (one process, the host's features, 40 calls of the force) writes,
while the process runs, a perf map of the compiled loops (``/tmp/perf-<pid>.map``, the form
``perf report`` reads for code made at run time), so that ``perf record`` of it attributes
the samples to the kernels (the helpers LLVM inlined count in their caller).

Measured on the 2-core Intel Xeon (AVX-512, LLVM 22, numba 0.68.1), 100k triangles, one
thread, load 2.9-3.1 (other jobs on the machine), four rounds, µs of CPU a cell, host and
512-bit: force 0.331 / 0.326 / 0.335 / 0.338 and 0.341 / 0.339 / 0.352 / 0.342, the cells'
pass 0.153 / 0.151 / 0.157 / 0.158 and 0.161 / 0.155 / 0.161 / 0.164: the wider vectors are
1-5 % slower (an earlier set of rounds at a load of 4: 3-12 %). The lanes' chunk of 32 cells
is four 8-wide iterations, and the rest of the pass is scalar; the host's tuning stays.
``--registers`` (instructions naming zmm / ymm / xmm), host: level_lanes 0 / 869 / 742,
load_lanes 0 / 266 / 272, moment_lanes 0 / 637 / 696, linear_lanes 0 / 316 / 422, the cells'
pass 0 / 2487 / 4819; 512-bit: level_lanes 864 / 4 / 745, the cells' pass 2381 / 51 / 4822.
The pulls' pass (0 / 44 / 936) and the sides' folds (0 / 195 / 427) are scalar code.

Run from the project root:

    python benchmarks/vector_width.py --rounds 3
    python benchmarks/vector_width.py --registers
    perf record -o /tmp/force.data python benchmarks/vector_width.py --perf-map
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))  # run from anywhere: this tree's packages first


def _features(wide: bool) -> dict:
    """The environment of a child: the host's features, or those without prefer-256-bit."""
    if not wide:
        return {}
    import llvmlite.binding as ll

    return {"NUMBA_CPU_FEATURES": ll.get_host_cpu_features().flatten() + ",-prefer-256-bit"}


def _compiled_loops() -> dict:
    """{name: numba build} of the fibrous force's compiled loops and lanes in this process."""
    from elements.fibrous import geometry_kernels, kernels
    from elements.fibrous import level_lanes as lane

    loops = {name: getattr(lane, name) for name in lane.__all__ if name not in ("CHUNK", "ROWS")}
    for module, names in (
        (kernels, ("_cells_pass", "_pulls_pass", "_node_loads")),
        (geometry_kernels, ("_normals_pass", "_side_folds", "_normal_sums", "_node_frames")),
    ):
        for name in names:
            kernel = getattr(module, name)
            loops[name] = getattr(kernel, "serial", kernel)
    return loops


def _child(registers: bool, perf_map: bool, calls: int) -> None:
    sys.path.insert(0, str(ROOT / "benchmarks"))
    import numba
    import numpy as np
    from fibrous_shell import _sheet

    from elements.fibrous import kernels

    numba.set_num_threads(1)
    compiled = _sheet(100000)
    block, state = compiled.blocks[0], compiled.initial_state()
    x = state.positions
    centre = x[:, :2].mean(axis=0)
    sag = 1e-3 * np.sum((x[:, :2] - centre) ** 2, axis=1)
    state.positions = x + np.column_stack([0 * sag, 0 * sag, sag])
    block.internal_force(state)
    if perf_map:
        _write_perf_map()
    if registers:
        for name, loop in _compiled_loops().items():
            for assembly in loop.inspect_asm().values():
                counts = {r: len(re.findall(r, assembly)) for r in ("zmm", "ymm", "xmm")}
                print(f"{name:16s} " + " ".join(f"{r} {n:5d}" for r, n in counts.items()))
        return
    m, best = len(block.connectivity), {"force": 1e9, "cells": 1e9}
    original = kernels._cells_pass

    def cells(*args):  # the cells' pass timed inside the force
        started = time.process_time()
        original(*args)
        timed["cells"] += time.process_time() - started

    kernels._cells_pass = cells
    for _ in range(calls):
        timed = {"cells": 0.0}
        started = time.process_time()
        block.internal_force(state)
        best["force"] = min(best["force"], time.process_time() - started)
        best["cells"] = min(best["cells"], timed["cells"])
    print(f"{1e6 * best['force'] / m:.4f} {1e6 * best['cells'] / m:.4f}")


def _write_perf_map() -> None:
    """/tmp/perf-<pid>.map: each compiled build's entry and the distance to the next entry."""
    from numba.core.registry import CPUDispatcher

    entries = []
    for name, loop in _compiled_loops().items():
        if isinstance(loop, CPUDispatcher):
            for result in loop.overloads.values():
                address = result.library.get_pointer_to_function(result.fndesc.llvm_func_name)
                entries.append((address, name))
    entries.sort()
    with open(f"/tmp/perf-{os.getpid()}.map", "w") as out:
        for (address, name), (after, _) in zip(
            entries, entries[1:] + [(entries[-1][0] + (1 << 16), "")]
        ):
            out.write(f"{address:x} {min(after - address, 1 << 20):x} {name}\n")


def _run(wide: bool, registers: bool, calls: int, cache: str) -> str:
    env = {
        **os.environ, **_features(wide), "PYTHONPATH": str(ROOT), "NUMBA_NUM_THREADS": "1",
        "NUMBA_CACHE_DIR": cache,
    }  # fmt: skip
    script = (
        f"import sys; sys.path.insert(0, 'benchmarks'); import vector_width as b; "
        f"b._child({registers}, False, {calls})"
    )
    out = subprocess.run(
        [sys.executable, "-c", script], cwd=ROOT, env=env, capture_output=True, text=True
    )
    if out.returncode:
        raise RuntimeError(out.stderr[-2000:])
    return out.stdout


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--calls", type=int, default=10)
    parser.add_argument("--registers", action="store_true")
    parser.add_argument("--perf-map", action="store_true", help="one run here, a perf map")
    args = parser.parse_args(argv)
    if args.perf_map:
        sys.path.insert(0, str(ROOT))
        _child(False, True, 40)
        return
    with tempfile.TemporaryDirectory() as narrow, tempfile.TemporaryDirectory() as wide:
        if args.registers:
            for name, features in (("host", False), ("512-bit", True)):
                with tempfile.TemporaryDirectory() as empty:
                    print(f"{name}:\n" + _run(features, True, 0, empty))
            return
        print("µs of CPU a cell, force / cells' pass, 100k triangles, one thread")
        for round_ in range(args.rounds):
            order = (False, True) if round_ % 2 == 0 else (True, False)
            for features in order:
                figures = _run(features, False, args.calls, wide if features else narrow)
                label = "512-bit" if features else "host   "
                print(f"round {round_}: {label} {figures.strip()}  load {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
