"""The compile of two groups of small compiled helpers and the speed of their callers, this
checkout beside another (``--against``, e.g. a worktree of the previous commit), each pass a
fresh process on a fresh empty numba cache (NUMBA_CACHE_DIR), one numba and BLAS thread:

* the packed laws' energy (elements/fibrous/packed_laws.py ``law_energy``) called with the
  constant indices 0, 1, 2 and with a variable one from two small compiled callers: the CPU
  of the first calls (compiling the callers and the table helpers) and the builds of
  ``_table_energy`` / ``_table_integral`` (one per Literal[int] index the callers give it, or
  one int64 build for all; "none" in a checkout where the table energy is spliced into its
  callers, as it is since the integrals at the knots are tabled by ``pack_laws``);
* femcore/gershgorin.py on a synthetic tangent of ``--cells`` triangles (random 18 x 18
  blocks on a strip of nodes, random node maps and scales: what the explicit solver's
  assembled stable step reads): the CPU of the first bound (compiling its kernels) and the
  best of ``--repeats`` bounds after it (the compiled loops alone), both pieces' ways (every
  pair held, and streamed piece by piece). The bounds must be the same number to the last
  bit in both checkouts.

CPU is ``time.process_time`` in the pass's process; the machine's 1-minute load is printed
beside each pass (2 cores shared with other jobs).

Measured (40k cells, 5 repeats, one round; 2 cores shared with other jobs, load 7.0-9.5):

* the laws: the constant indices' builds of the table helpers 4 and 4 before (each caller's
  literal 0, 1, 2 and the variable's int64), first calls 4.78 s of CPU; with the index given
  as int64 (``law_energy``) 1 and 1, 2.00 s; the same energy to the last bit.
* gershgorin, ``_add_transformed`` and ``_add_row`` spliced (numba's ``inline="always"``, as
  kept) against compiled on their own (a checkout with plain ``numba.njit(cache=True)`` on
  both): first bounds 10.42 against 10.82 s of CPU (splicing costs no compile here), then
  the bound with every pair held 78.6 against 108.5 ms, streamed 90.9 against 116.5 ms
  (called, the two helpers' array arguments are reference counted per node pair); the same
  bounds to the last bit. The splicing stays.

Run: python benchmarks/suite_helpers.py --against /tmp/old-checkout [--cells 40000]
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

WORKLOAD = r"""
import os, sys, time
import numpy as np
import numba
from elements.fibrous import packed_laws
from elements.fibrous.packed_laws import law_energy, pack_laws
from materials import BendingLaw, ShearLaw
from femcore.assembly import CellTangent
from femcore import gershgorin

numba.set_num_threads(1)
started = time.process_time()
@numba.njit
def constant(integers, reals, x):
    return (law_energy(integers, reals, 0, x) + law_energy(integers, reals, 1, x)
            + law_energy(integers, reals, 2, x))
@numba.njit
def variable(integers, reals, i, x):
    return law_energy(integers, reals, i, x)
laws = [BendingLaw.bilinear(7.5, 0.5, 1e-3), ShearLaw.table([0.0, 0.5, 1.0], [0.0, 1.0, 3.0]),
        BendingLaw.bilinear(2.0, 0.5, 2e-3)]
integers, reals = pack_laws(laws)
energy = constant(integers, reals, 7e-4) + variable(integers, reals, 1, 0.3)
laws_cpu = time.process_time() - started
def builds(name):  # a checkout whose table energy is spliced has no such helper
    helper = getattr(packed_laws, name, None)
    return "none" if helper is None else len(helper.signatures)
print(f"laws: first calls {laws_cpu:.2f} s CPU, _table_energy builds "
      f"{builds('_table_energy')}, _table_integral builds "
      f"{builds('_table_integral')}, energy {energy!r}")

cells = int(sys.argv[1]); repeats = int(sys.argv[2])
rng = np.random.default_rng(3)
n_nodes = cells // 2 + 2
first = np.arange(cells) // 2
nodes = np.stack([first, first + 1, first + 2], axis=1).astype(np.int64)
blocks = rng.normal(size=(cells, 3, 6, 3, 6))
maps = rng.normal(size=(n_nodes, 6, 5))
scale = rng.uniform(0.5, 1.5, size=5 * n_nodes)
pieces = [CellTangent(nodes[i : i + cells // 4], blocks[i : i + cells // 4])
          for i in range(0, cells, cells // 4)]
started = time.process_time()
held = gershgorin.gershgorin_largest(pieces, maps, scale, n_nodes)
streamed = gershgorin.gershgorin_largest(pieces, maps, scale, n_nodes, again=lambda: pieces)
compile_cpu = time.process_time() - started
best_held = best_streamed = float("inf")
for _ in range(repeats):
    started = time.process_time()
    gershgorin.gershgorin_largest(pieces, maps, scale, n_nodes)
    best_held = min(best_held, time.process_time() - started)
    started = time.process_time()
    gershgorin.gershgorin_largest(pieces, maps, scale, n_nodes, again=lambda: pieces)
    best_streamed = min(best_streamed, time.process_time() - started)
print(f"gershgorin: first bounds {compile_cpu:.2f} s CPU; then best of {repeats}: "
      f"held {best_held * 1e3:.1f} ms, streamed {best_streamed * 1e3:.1f} ms; "
      f"bounds {held!r} {streamed!r}")
"""


def one_pass(checkout: Path, cells: int, repeats: int) -> None:
    with tempfile.TemporaryDirectory() as cache:
        one = {"NUMBA_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1"}
        env = {**os.environ, **one, "NUMBA_CACHE_DIR": cache, "PYTHONPATH": str(checkout)}
        print(f"{checkout} (load {os.getloadavg()[0]:.1f})", flush=True)
        command = [sys.executable, "-c", WORKLOAD, str(cells), str(repeats)]
        subprocess.run(command, env=env, cwd=checkout, check=True)
        print(f"  (load after {os.getloadavg()[0]:.1f})", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--against", type=Path, required=True, help="the other checkout")
    parser.add_argument("--cells", type=int, default=40_000)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--rounds", type=int, default=2, help="passes of each, in turns")
    args = parser.parse_args()
    for _ in range(args.rounds):
        for checkout in (args.against.resolve(), ROOT):
            one_pass(checkout, args.cells, args.repeats)


if __name__ == "__main__":
    main()
