"""numba's compilations of a fresh checkout, kernel by kernel: which kernels compile, the CPU
each compilation takes (its own, its callees' compilations taken out), the signatures each
kernel is compiled for (a kernel compiled twice for a read-only and a writable array, for
int32 and int64 indices or for C and A layouts shows two), and what a serial build of each
parallel kernel (femcore/jit.py ``jit``) would cost against its parallel build.

One pass: a fresh process on a fresh empty numba cache (NUMBA_CACHE_DIR), one numba and BLAS
thread, runs the given pytest modules (default: the compile-heavy modules of the suite,
``-m "not slow"``) with numba's ``Dispatcher.compile`` timed. ``--serial`` then compiles the
Python function of every parallel kernel met, for each signature it was compiled for, once
with ``parallel=False`` and once with ``parallel=True`` (no cache, its callees already
compiled), and prints both. CPU is ``time.process_time``; the machine's load is printed.

Measured on the 2-core machine shared with other jobs (load 5.5-7), the three default
modules, fresh cache, one process:

* before (every ``jit`` kernel compiled as numba's parallel build, run on one thread): CPU
  of the process 436.9 s (load 1.8-7). ``--serial`` then compiled each parallel kernel's
  function both ways in that process (its callees compiled, no cache): plain 98.9 s, parallel
  294.7 s in all (load 5.0); fibrous ``_cells_pass`` 33.8 s against 133.8 s,
  ``_hessian_cells`` 29.7 against 83.4, Mindlin ``_tangent_cells`` 6.9 against 14.9,
  ``_normal_pull_cells`` 5.0 against 10.2, ``_mindlin_tables`` 4.1 against 7.7, every other
  one 1.4-3.5 times as long parallel as plain;
* after (a loop on one thread runs the plain build: every loop of these tests):
  CPU of the process 192.6 s, of the compilations 179.2 s (load 5.6-6.2); again with the
  fibrous bind's writable reference points, 159.2 s and 144.9 s (load 5.5). The largest:
  fibrous ``_cells_pass`` 36-47 s, ``_hessian_cells`` 30-37 s, fabric_section_kernels
  ``_response_cells`` 28-33 s (a plain build already), Mindlin ``_tangent_cells`` 5.6-5.8 s,
  ``_normal_pull_cells`` 4.9-5.8 s; every other kernel under 5 s. Signatures: before the
  writable reference points ``_normals_pass`` and ``_bending_sides`` were compiled twice (a
  read-only and a writable ``positions``: 1.7 and 3.2 s for the two), after once (0.4 and
  1.0 s); ``_base_vectors`` (a helper of the Mindlin tables and fields) still twice, 1.2 s
  for both (the Mindlin block's reference positions are read-only). No int32/int64 or C/A
  layout duplicates.

numba's ``inline="always"`` (femcore/jit.py ``inline``) against helpers compiled on their own
(``serial``), modules tests/test_fibrous.py, test_bias_extension.py and
test_fabric_section_kernels.py, fresh cache, one process (CPU of the process / of the
compilations): main 7e3a340, every fibrous helper spliced, 141.0 / 136.6 s (load 6.4-9.1):
``_cells_pass`` 39.6 s, ``_hessian_cells`` 35.8, ``_response_cells`` 25.5, every other kernel
under 6 s; every helper on its own 74.7 / 70.3 s (load 1.9-6.4): 3.8, 5.8 and 4.3 s, but LLVM
left the laws and ``level_strains`` as calls in ``_cells_pass`` (their array arguments'
reference counting kept, numba's IR of the kernel) and the explicit step of
benchmarks/explicit_step.py (fibrous, 10082 cells, one thread) took 1.71 µs of CPU per
element-step, the force 1.61, against 0.45-0.82 and 0.49-0.88 on main (load 4.6-8); the laws' value,
slope and energy and ``level_strains`` spliced, the rest on its own: 69.5 / 66.2 s (load
4.8-6.1): 8.1, 11.1 and 9.8 s; the step, in turns with main's (µs of CPU per element-step:
steady step, force, force with energy): 1.045, 0.970, 1.828 against main's 1.061, 0.831, 1.524
(load 4.6-6.1); 1.109, 0.641, 1.230 against 1.097, 0.817, 1.529 (load 5.2-5.8); 0.982, 0.731,
1.231 against 0.809, 1.010, 1.577 (load 5.2-5.5): the same within the machine's noise. The same
numbers either way (the kernel-vs-numpy tests of these modules pass). The law calls with a
literal index (the shear law, 2) still compile ``_table_integral`` and ``_table_energy`` once
more per literal (4 signatures, 2.3 s).

The suite's compile-heavy modules as CI runs them (a fresh clone, a fresh NUMBA_CACHE_DIR,
``python -m pytest -q -p no:cacheprovider tests/test_fibrous.py tests/test_bias_extension.py
tests/test_conformance.py``: two xdist workers, the slow tests included; CPU the user + system
time of pytest and its workers), this branch then main 7e3a340, one after the other: 168.6 s of
CPU, 323 s wall (load 4.8-5.7 before, 4.3 after) against 290.9 s of CPU, 410 s wall (load
4.3-5.7 before, 2.0 after). The slowest item, the first compiled fibrous test of a worker
(test_the_compiled_pieces_give_the_numpy_forces), 194 s wall against 282 s: it still waits on
the other worker's compilations (femcore/compile_lock.py) at that load.

The tests marked ``parallel`` run the parallel builds when numba has more than one thread,
as in a CI run on 2 cores (``--threads=2``: numba's setting in the probed process; the other
tests still run on one, tests/conftest.py). tests/test_fibrous.py, fresh cache, one process,
``--threads=2``, main c108a2a and the parallel build as a loop over parts of the plain build
(femcore/jit.py ``_Parallel``), in turns: CPU of the process / of the compilations 52.7 /
50.9 s (load 3.4-5.1), then 28.9 / 27.0 (5.1-5.2), 48.2 / 46.6 (5.2-5.0), 27.6 / 25.8
(5.0-5.3). On main the fibrous ``_cells_pass_parallel`` took 23.1 and 22.1 s beside the plain
``_cells_pass``'s 7.0; as a loop over parts 3.6 and 3.3 s beside the parted plain build's 6.4
and 6.0 (the one plain build serves both); the helpers ``corner_thickness`` and ``wall_fold``
were built again for the parallel loop's unsigned index (uint64), no longer.
``--threads=2`` on the first compiled fibrous test alone
(test_the_compiled_pieces_give_the_numpy_forces, load 1.2-2.9): 38.1 s of CPU, 36.6 of it
compiling (the parallel builds 31.2 of it, ``_cells_pass_parallel`` 23.9), against 24.9 and
23.5 s (``_cells_pass_parallel`` 3.6, the parted plain ``_cells_pass`` 7.8).

The ply contact's fused passes (elements/ply_facing_pass.py, ply_facing_whole.py,
ply_friction_pass.py) compiled each stage as a helper of its own (``lanes(function)``) beside
the kernel's plain build of the same loop: eight loops built twice from an empty cache
(``_choose`` 3.14 s, ``_facets_at`` 1.16, ``_moved`` 0.93, ``_sides`` 0.92, ``_outline`` 0.79,
``_return_mapping`` 0.72, ``_chosen`` 0.53, ``_parts`` 0.33 s beside their part builds; load
5.5), and a literal True there built ``signing_at`` again. They call the kernels' own part
builds now (femcore/jit.py ``plain_part``). tests/test_ply_facing_pass.py,
test_ply_facing_whole.py, test_ply_friction_pass.py and test_ply_search.py, fresh cache, one
process, a base export (9e8d4d5) and the change alternating (load 3.1-4.2): CPU of the process
/ of the compilations 43.2 / 35.2, then 31.8 / 24.4, 40.8 / 32.7, 34.0 / 25.8 s.

Run: python benchmarks/suite_kernels.py [--serial] [--threads=2] [tests/test_x.py ...]
"""

import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
MODULES = [
    "tests/test_bias_extension.py",
    "tests/test_conformance.py",
    "tests/test_augmented_contact.py",
]

PROBE = r"""
import json, sys, time
from collections import defaultdict
from numba.core import dispatcher

records = []          # (kernel, signature, own CPU s, loaded from the cache)
stack = [0.0]         # CPU of the callees' compilations inside the current one
original = dispatcher.Dispatcher.compile
kernels = {}


def compile(self, sig):
    name = f"{self.py_func.__module__}.{self.py_func.__qualname__}"
    hits = sum(self._cache_hits.values())
    stack.append(0.0)
    started = time.process_time()
    try:
        return original(self, sig)
    finally:
        spent = time.process_time() - started
        inner = stack.pop()
        stack[-1] += spent
        loaded = sum(self._cache_hits.values()) > hits
        kernels[name] = self
        records.append((name, str(sig), spent - inner, loaded,
                        bool(self.targetoptions.get("parallel"))))


dispatcher.Dispatcher.compile = compile
import pytest
started = time.process_time()
code = pytest.main(sys.argv[2:])
total = time.process_time() - started
out = {"records": list(records), "total": total, "code": int(code), "serial": []}
if sys.argv[1] == "serial":
    import numba
    done = set()
    for name, sig, _, _, parallel in records:
        if not parallel or (name, sig) in done:
            continue
        done.add((name, sig))
        function = kernels[name].py_func
        signature = [s for s in kernels[name].overloads if str(s) == sig]
        if not signature:
            continue
        times = []
        for flag in (False, True):
            build = numba.njit(parallel=flag, fastmath=False)(function)
            t = time.process_time()
            build.compile(signature[0])
            times.append(time.process_time() - t)
        out["serial"].append((name, sig, times[0], times[1]))
print("PROBE" + json.dumps(out))
"""


def run(modules: list[str], serial: bool, threads: int = 1) -> dict:
    """One fresh process on a fresh cache, numba's thread setting ``threads`` (the tests
    marked ``parallel`` run the parallel builds only above 1): the records of the probe
    above."""
    import json

    with tempfile.TemporaryDirectory() as cache:
        env = {**os.environ, "NUMBA_CACHE_DIR": cache, "PYTHONPATH": str(ROOT),
               "NUMBA_NUM_THREADS": str(threads), "OPENBLAS_NUM_THREADS": "1",
               "OMP_NUM_THREADS": "1"}  # fmt: skip
        args = ["serial" if serial else "-", "-q", "-n", "0", "-p", "no:randomly",
                "-p", "no:cacheprovider", "-m", "not slow", *modules]  # fmt: skip
        done = subprocess.run(
            [sys.executable, "-c", PROBE, *args], cwd=ROOT, env=env, capture_output=True,
            text=True,
        )  # fmt: skip
        line = [x for x in done.stdout.splitlines() if x.startswith("PROBE")]
        if not line:
            raise RuntimeError(done.stdout[-3000:] + done.stderr[-3000:])
        return json.loads(line[0][5:])


def main() -> None:
    serial = "--serial" in sys.argv
    threads = int(next((a.split("=")[1] for a in sys.argv if a.startswith("--threads=")), 1))
    modules = [a for a in sys.argv[1:] if not a.startswith("--")] or MODULES
    print(f"load before: {os.getloadavg()[0]:.1f}; threads {threads}; modules: {' '.join(modules)}")
    out = run(modules, serial, threads)
    per: dict[str, list] = {}
    for name, sig, own, loaded, parallel in out["records"]:
        entry = per.setdefault(name, [0.0, [], parallel, 0])
        entry[0] += own
        if sig not in entry[1]:  # (a callee is asked again for each caller typed)
            entry[1].append(sig)
        entry[3] += loaded
    compiled = sum(v[0] for v in per.values())
    print(f"pytest exit {out['code']}; CPU of the process {out['total']:.1f} s, "
          f"of numba's compilations {compiled:.1f} s; load {os.getloadavg()[0]:.1f}")  # fmt: skip
    print(f"{'kernel (numba internals left out)':60s} {'par':>3s} {'sigs':>4s} {'CPU s':>7s}")
    for name, (own, sigs, parallel, _) in sorted(per.items(), key=lambda kv: -kv[1][0]):
        if name.startswith("numba."):
            continue
        print(f"{name[-60:]:60s} {'P' if parallel else '':>3s} {len(sigs):4d} {own:7.2f}")
        if len(sigs) > 1:
            for s in sigs:
                print(f"{'':8s}{s[:300]}")
    if serial:
        print(f"\n{'parallel kernel':60s} {'serial s':>9s} {'parallel s':>10s}")
        for name, _, t_serial, t_parallel in out["serial"]:
            print(f"{name[-60:]:60s} {t_serial:9.2f} {t_parallel:10.2f}")
        plain, parallel = (sum(r[i] for r in out["serial"]) for i in (2, 3))
        print(f"total: serial {plain:.1f} s, parallel {parallel:.1f} s; "
              f"load {os.getloadavg()[0]:.1f}")  # fmt: skip


if __name__ == "__main__":
    main()
