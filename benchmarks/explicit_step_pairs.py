"""The steady explicit step of a shell with another revision's force kernels beside this tree's,
in one process, taken in turns.

The revision's kernels module (``git show``: elements/kernels.py for the Mindlin shell,
elements/fibrous/kernels.py for the fibrous one) is written into a package of its own in a
temporary folder (benchmarks/revision_modules.py) and imported beside this tree's; a side's
turn puts its force functions (``SHELLS``) in this tree's module (what the block calls) and
runs ``CentralDifference`` on the pinned sheet of benchmarks/explicit_step.py (the Mindlin
shell aluminium, h = 1 mm; the fibrous shell the G986 stack; gravity from rest, 0.9 x the
stable step, one thread) over N and 2N steps: the steady step is the difference of the two
CPU times per added element-step (the run's start and its frames left out). Everything else
in the step is this tree's on both sides.

Printed, a line a size: each side's best steady step over ``--rounds`` rounds (the order of
the sides flipped every round), the median of new / old over the rounds with its quartiles,
whether the two runs of 2N steps end with the same positions, directors and velocities to the
last bit, the numpy reference pass of benchmarks/shell_sheet.py (CPU, best of 20) and the
machine's load before and after.

Measured on the 2-core Intel Xeon shared with other jobs (load 12-18), one numba thread,
``--ref 432e668 --sizes 100000 --rounds 5`` (432e668: the cells' pass into its (m, 3, 6)
buffer, the nodes' pass into the halves of one (n, 6) array, which the velocity and rotation
passes copied), µs of CPU an element-step, best of the rounds:

    this tree                                   old     new     new / old median (quartiles)
    one pass adding the loads to the nodes      0.1712  0.1445  0.854 (0.850-0.878)
    ... and its energy sums left out            0.1626  0.1420  0.875 (0.833-0.879)
      when the step does not check the balance

the same positions, directors and velocities to the last bit after 200 steps; the reference
pass 0.138 and 0.130 in those runs (the new step 1.05 and 1.09 times it). The second line's
change is within the first's spread at that load; alone, the force without its energy took
0.964 of the force with it (median of 15 rounds, load 14.7).

``--element fibrous`` measured a one-thread pulls pass tried on the fibrous shell (each
cell's corner forces and moments added to its nodes as it went; not kept): old 0.3412, new
0.3679, new / old 1.131 (1.096-1.166) over 3 rounds, the same bits, reference pass 0.126,
load 17-18.

Run from the project root (the other revision must be a git ref of this repository):

    python benchmarks/explicit_step_pairs.py --ref main --sizes 100000 --rounds 5
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

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install

from explicit_step import cpu_reference, run, sheet  # noqa: E402
from revision_modules import revision_modules  # noqa: E402

#: Each shell's kernels module (its path, its name) and the functions of it its block calls
#: (elements/mindlin.py, elements/fibrous/block.py).
SHELLS = {
    "mindlin": (
        ("elements/kernels.py", "elements.kernels"),
        ("mindlin_loads", "mindlin_loads_and_energy", "mindlin_energy"),
    ),
    "fibrous": (
        ("elements/fibrous/kernels.py", "elements.fibrous.kernels"),
        ("internal_force", "internal_force_and_energy", "strain_energy_parts"),
    ),
}


def other_kernels(ref: str, folder: Path, element: str):
    """The kernels module of ``element`` of revision ``ref``, imported from a package
    ``other_<hash>`` written into ``folder``, and the revision's short hash."""
    (path, name), _ = SHELLS[element]
    package, commit = revision_modules(ref, folder, {path: name})
    return importlib.import_module(f"{package}.{name.rsplit('.', 1)[1]}"), commit


def steady(compiled, steps: int) -> tuple[float, object]:
    """The steady step's CPU seconds per added step (runs of ``steps`` and twice as many) and
    the longer run's last frame."""
    (_, short), _ = run(compiled, steps)
    (_, long), result = run(compiled, 2 * steps)
    return (long - short) / steps, result.frames[-1]


def pair(old, compiled, element: str, steps: int, rounds: int) -> str:
    """The line of figures of the sheet ``compiled``: old and new sides in turns."""
    (_, module), called = SHELLS[element]
    kernels = importlib.import_module(module)
    own = {name: getattr(kernels, name) for name in called}
    theirs = {name: getattr(old, name) for name in called}
    m = sum(len(block.connectivity) for block in compiled.blocks)
    times: dict[str, list[float]] = {"old": [], "new": []}
    ends = {}
    load = os.getloadavg()[0]
    try:
        for functions in (theirs, own):  # untimed: the first calls
            for name, function in functions.items():
                setattr(kernels, name, function)
            run(compiled, 3)
        for r in range(rounds):
            order = (("old", theirs), ("new", own))
            for side, functions in order if r % 2 == 0 else order[::-1]:
                for name, function in functions.items():
                    setattr(kernels, name, function)
                seconds, frame = steady(compiled, steps)
                times[side].append(seconds / m * 1e6)
                ends[side] = frame
    finally:
        for name, function in own.items():
            setattr(kernels, name, function)
    same = all(
        np.array_equal(getattr(ends["old"], field), getattr(ends["new"], field))
        for field in ("positions", "directors", "velocities")
    )
    ratios = np.array(times["new"]) / np.array(times["old"])
    q1, median, q3 = np.percentile(ratios, [25, 50, 75])
    reference = cpu_reference(m)
    return (
        f"{m} triangles, {steps} / {2 * steps} steps: steady step old best "
        f"{min(times['old']):.4f}, new best {min(times['new']):.4f} us of CPU an "
        f"element-step; new / old median {median:.3f} (quartiles {q1:.3f}-{q3:.3f}) over "
        f"{rounds} rounds; {'the same' if same else 'NOT the same'} bits after "
        f"{2 * steps} steps; reference pass {reference:.4f} (new best "
        f"{min(times['new']) / reference:.2f} x); load {load:.2f} -> {os.getloadavg()[0]:.2f}"
    )


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ref", default="main", help="the other revision (a git ref)")
    parser.add_argument("--element", choices=tuple(SHELLS), default="mindlin")
    parser.add_argument("--sizes", default="100000")
    parser.add_argument("--steps", type=int, default=100)
    parser.add_argument("--rounds", type=int, default=5)
    args = parser.parse_args(argv)
    import numba

    numba.set_num_threads(1)
    with tempfile.TemporaryDirectory() as folder:
        old, commit = other_kernels(args.ref, Path(folder), args.element)
        print(
            f"{args.ref} ({commit}) beside this tree, {args.element} shell, one process, one "
            f"thread, "
            f"CPU time ({time.strftime('%Y-%m-%d %H:%M')})",
            flush=True,
        )
        compiled, _, _ = sheet(args.element, "compiled", 200)
        run(compiled, 3)  # this tree's loops compiled first
        for size in [int(s) for s in args.sizes.split(",")]:
            compiled, _, _ = sheet(args.element, "compiled", size)
            print(pair(old, compiled, args.element, args.steps, args.rounds), flush=True)


if __name__ == "__main__":
    main()
