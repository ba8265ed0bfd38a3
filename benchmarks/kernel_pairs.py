"""The fibrous force's compiled loops of another revision beside this tree's, in one process,
taken in turns: the paired measure a change to elements/fibrous/kernels.py (or to the helpers
and the jit it compiles with) needs on a shared machine, where two runs minutes apart differ
by more than the change.

The revision's ``elements/fibrous/kernels.py``, ``cell_terms.py``, ``packed_laws.py``,
``level_lanes.py``, ``elements/lane_maths.py`` and the jit (``femcore/jit.py``, before in
``elements/``) (``git show``; those
it has) are written into a package of their own in a temporary folder, their
imports of one another pointed there, and imported beside this tree's; the block is built
once by this tree (the two must read the same block), the sheet of
benchmarks/fibrous_shell.py sagged into a bowl. Each round times ``--calls`` calls of each in
CPU time, the order flipped every round; printed: the best µs per cell of each, the median
and quartiles of new / old over the rounds, whether the two give the same numbers to the last
bit (else the largest difference over the largest value), the machine's load.

Measured by this pairing on the 2-core AMD EPYC (znver4, AVX-512), one thread, 100k triangles, the
tree's kernels changed for each line and main 544e521's beside them, 12-16 rounds, median
new / old of the force (quartiles), load 2.6-6.5 (what each change was:
benchmarks/explicit_step.py):

    numba's numpy error model on every compiled loop          1.025 (0.97-1.03), same bits
    fastmath {"contract"} on every compiled loop              0.984 (0.95-1.05)
    the corner and fold angles by Cephes' atan, branches      1.003 (0.95-1.04)
    the same with selects for the quadrants                   1.024 (0.90-1.05)
    the cells' index unsigned (no negative-index select)      1.021 (1.00-1.05), same bits
    bounds (wrong, timed only):
    the three arctan2 a cell replaced by arithmetic           0.880 (0.84-0.91)
    the membrane's laws replaced by c x (linear: same bits)   1.003 (0.93-1.06)
    the bending of the cells' pass skipped                    0.899 (0.90-0.91)
    the fibre levels skipped                                  0.585 (0.57-0.61)

Run from the project root (the other revision must be a git ref of this repository):

    python benchmarks/kernel_pairs.py --ref main --sizes 100000 --rounds 12
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

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))  # run from anywhere, no install
sys.path.insert(0, str(ROOT / "benchmarks"))

from fibrous_shell import _sheet  # noqa: E402
from revision_modules import revision_modules  # noqa: E402

# The modules copied from the other revision, and the name each is imported under there.
MODULES = {
    "elements/fibrous/kernels.py": "elements.fibrous.kernels",
    "elements/fibrous/geometry_kernels.py": "elements.fibrous.geometry_kernels",
    "elements/fibrous/cell_terms.py": "elements.fibrous.cell_terms",
    "elements/fibrous/packed_laws.py": "elements.fibrous.packed_laws",
    "elements/fibrous/level_lanes.py": "elements.fibrous.level_lanes",
    "elements/lane_maths.py": "elements.lane_maths",
    # where a revision has it: elements/jit.py before it moved to femcore (one module "jit")
    "elements/jit.py": "elements.jit",
    "femcore/jit.py": "femcore.jit",
}
CALLS = {
    "force": "internal_force",
    "force+energy": "internal_force_and_energy",
    "energy": "strain_energy_parts",
}


def other_kernels(ref: str, folder: Path):
    """The kernels module of revision ``ref``, imported from a package ``other_<hash>`` written
    into ``folder`` (benchmarks/revision_modules.py)."""
    package, commit = revision_modules(ref, folder, MODULES)
    return importlib.import_module(f"{package}.kernels"), commit


def sagged(triangles: int):
    """The fibrous sheet of benchmarks/fibrous_shell.py, its block, and positions and directors
    sagged into a bowl."""
    compiled = _sheet(triangles)
    state = compiled.initial_state()
    x = state.positions
    centre = x[:, :2].mean(axis=0)
    bowl = 1e-3 * np.sum((x[:, :2] - centre) ** 2, axis=1)
    return compiled.blocks[0], x + np.column_stack([0 * bowl, 0 * bowl, bowl]), state.directors


def flat(result) -> np.ndarray:
    """The numbers of a kernel's result (arrays, a dict of energies, or a tuple of them)."""
    parts = result if isinstance(result, tuple) else (result,)
    return np.concatenate(
        [np.asarray(list(p.values())) if isinstance(p, dict) else np.ravel(p) for p in parts]
    )


def pair(old, new, block, positions, directors, what: str, rounds: int, calls: int) -> str:
    """The line of figures of ``what`` by the two kernels modules, in turns."""
    name = CALLS[what]
    run_old, run_new = getattr(old, name), getattr(new, name)
    a = flat(run_old(block, positions, directors))
    b = flat(run_new(block, positions, directors))
    same = np.array_equal(a, b)
    difference = (
        "the same bits" if same else f"differ by {np.max(np.abs(a - b)) / np.max(np.abs(a)):.1e}"
    )
    m = len(block.connectivity)
    times: dict = {run_old: [], run_new: []}
    ratios = []
    for kernel in (run_old, run_new):  # a round untimed: the first calls run slower
        for _ in range(calls):
            kernel(block, positions, directors)
    for r in range(rounds):
        for kernel in (run_old, run_new) if r % 2 == 0 else (run_new, run_old):
            started = time.process_time()
            for _ in range(calls):
                kernel(block, positions, directors)
            times[kernel].append((time.process_time() - started) / calls / m * 1e6)
        ratios.append(times[run_new][-1] / times[run_old][-1])
    q1, median, q3 = np.percentile(ratios, [25, 50, 75])
    return (
        f"{what} {m} cells: old best {min(times[run_old]):.4f}, new best "
        f"{min(times[run_new]):.4f} us per cell; new / old median {median:.3f} "
        f"(quartiles {q1:.3f}-{q3:.3f}) over {rounds} rounds; {difference}; load "
        f"{os.getloadavg()[0]:.2f}"
    )


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ref", default="main", help="the other revision (a git ref)")
    parser.add_argument("--sizes", default="100000")
    parser.add_argument("--what", default="force", help="force, force+energy, energy (a list)")
    parser.add_argument("--rounds", type=int, default=12)
    parser.add_argument("--calls", type=int, default=0, help="calls a turn (0: 2M cells' worth)")
    args = parser.parse_args(argv)
    from elements.fibrous import kernels as new

    with tempfile.TemporaryDirectory() as folder:
        old, commit = other_kernels(args.ref, Path(folder))
        print(f"{args.ref} ({commit}) beside this tree, one process, CPU time", flush=True)
        for size in [int(s) for s in args.sizes.split(",")]:
            block, positions, directors = sagged(size)
            calls = args.calls or max(1, 2_000_000 // len(block.connectivity))
            for what in args.what.split(","):
                print(pair(old, new, block, positions, directors, what, args.rounds, calls),
                      flush=True)  # fmt: skip


if __name__ == "__main__":
    main()
