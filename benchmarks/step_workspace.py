"""The explicit step with the shells' cell-pass arrays kept between calls (femcore/workspace.py)
against the same step with them made afresh at every call (the reference pass, as before).

One process, one numba thread, the pinned square sheet of ``model_memory.py`` (5 mm cells,
under gravity) of the Mindlin or the fibrous shell: the model is built once and run by
``CentralDifference`` (its own loop: the energy check every tenth step, the frames, the
bookkeeping) for ``--steps`` steps at 0.9 x the cells' stable step, its block's workspace a
kept one and a ``Fresh`` one in turns (the order swapped each round). Each step of the run
(``solvers.step.explicit_step``) is timed apart, its user and system CPU time and its minor
page faults (``getrusage``); the first five steps of a run are left out (its arrays' first
touch). Printed: the median over the rounds of each run's mean, µs per element-step (user,
system) and faults a step, with their ratio, and whether the positions at the end are the
same to the bit.

Measured on the 2-core Intel Xeon shared with other runs (load 4.8-5.1), ``--rounds 3
--steps 30``, one thread, µs of CPU an element-step, user + system, fresh -> kept (faults a
step), the positions after 30 steps the same to the bit in every case:

    fibrous 100k    0.413 + 0.072 -> 0.410 + 0.000   (3580 -> 59)    CPU 0.845 of before
    fibrous 400k    0.414 + 0.077 -> 0.416 + 0.012   (3409 -> 464)   0.870
    Mindlin 100k    0.177 + 0.000 -> 0.174 + 0.000   (36 -> 47)      0.982
    Mindlin 400k    0.175 + 0.026 -> 0.173 + 0.001   (828 -> 86)     0.866

With every per-step array of the fibrous force passes kept as well (the normals, areas,
angles, side folds, nodal normal sums and frames, side moments and pulls; the forces
returned and the checking step's energies still made afresh), load 6.5: fibrous 400k 0.401 +
0.066 -> 0.403 + 0.000 (3265 -> 54 faults a step), CPU 0.862 of before; 100k 0.425 + 0.000
-> 0.423 + 0.000 (no fault either way in that run), 0.995.

What the kept arrays cost in memory: about 163 MB at 400k fibrous triangles (0.41 kB a
triangle: the (m, 3, 3) arrays 86 MB, the rest 77), held from the first force pass on, where
the step's own arrays used to take the freed ones' place. model_memory.py, fibrous 400k, warm
cache, one thread (load 3.2-5.5): the steps' peak above the baseline 560 MB (1.434 kB a
triangle) -> 704-715 (1.80-1.83), the whole run's 585 (1.500; 899 MB with the interpreter's)
-> 751-760 (1.93-1.95; 947-956), under issue 30's 2 kB a triangle; an energy-only pass that
kept nothing changed it by nothing measurable (743 MB, tried, not kept). Mindlin 400k, the
same way, the kernels before the workspace and these in turns (load 1.6-2.3): the run's peak
534 MB (1.368 kB a triangle) -> 575 (1.474), its corner loads and energies 61 MB kept; the
ten steps' faults 18267 -> 10753-11265, their system time 0.66-0.80 -> 0.39-1.17 s (noisy).

Whether a freed array goes back to the system depends on the heap's layout (glibc's
thresholds move with the sizes freed before): a bare loop of ``explicit_step`` on a freshly
built 400k fibrous sheet paid no fault a step with fresh arrays, ``CentralDifference`` on the
same sheet 2200-3700 (model_memory.py: 0.239 µs of system an element-step beside 0.404 of
user). The faults left come from the solver's state and the forces returned, mostly on
the steps that check the energy balance.

Run from the project root (one 400k case at a time; about 1 GB at 400k triangles):

    python benchmarks/step_workspace.py --elements fibrous --sizes 100000,400000
"""

from __future__ import annotations

import argparse
import os
import resource
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install

import numba  # noqa: E402
import numpy as np  # noqa: E402
from model_memory import pinned_sheet, sheet_mesh  # noqa: E402

SKIPPED = 5  # the first steps of a run: its arrays' first touch


def _usage() -> tuple[float, float, float]:
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime, usage.ru_stime, float(usage.ru_minflt)


def run(compiled, steps: int, record: list) -> np.ndarray:
    """``steps`` steps of ``CentralDifference`` from rest; the positions at the end."""
    from solvers import CentralDifference

    dt = 0.9 * compiled.stable_dt(compiled.initial_state())
    record.clear()
    result = CentralDifference(
        duration=steps * dt, dt=dt, output_interval=steps * dt, progress=False
    ).solve(compiled)
    return result.frames[-1].positions


def case(name: str, triangles: int, rounds: int, steps: int) -> None:
    import solvers.explicit as explicit
    from femcore.workspace import Fresh, Workspace

    record: list[tuple[float, float, float]] = []
    step = explicit.explicit_step

    def timed(*args, **kwargs):
        before = _usage()
        outcome = step(*args, **kwargs)
        after = _usage()
        record.append(tuple(b - a for a, b in zip(before, after)))
        return outcome

    explicit.explicit_step = timed
    try:
        pinned_sheet(name, sheet_mesh(200)).compile()  # the loops loaded or compiled
        compiled = pinned_sheet(name, sheet_mesh(triangles)).compile()
        cells = len(compiled.mesh.triangles)
        block = compiled.blocks[0]
        figures: dict[str, list[np.ndarray]] = {"kept": [], "fresh": []}
        ends = {}
        for index in range(rounds):
            for label in ("kept", "fresh") if index % 2 == 0 else ("fresh", "kept"):
                block._workspace = Workspace() if label == "kept" else Fresh()
                ends[label] = run(compiled, steps, record)
                figures[label].append(np.mean(np.array(record[SKIPPED:]), axis=0))
    finally:
        explicit.explicit_step = step
    kept, fresh = (np.median(np.array(figures[k]), axis=0) for k in ("kept", "fresh"))
    per = 1e6 / cells
    print(
        f"{name}, {cells} triangles, {rounds} rounds of {steps} steps, one thread: "
        f"kept user {kept[0] * per:.3f} + system {kept[1] * per:.3f} us/element-step, "
        f"{kept[2]:.0f} faults a step; fresh {fresh[0] * per:.3f} + {fresh[1] * per:.3f}, "
        f"{fresh[2]:.0f}; kept / fresh CPU {(kept[0] + kept[1]) / (fresh[0] + fresh[1]):.3f}; "
        f"positions the same to the bit: {np.array_equal(ends['kept'], ends['fresh'])}; "
        f"load {os.getloadavg()[0]:.2f}",
        flush=True,
    )


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--elements", default="mindlin,fibrous")
    parser.add_argument("--sizes", default="100000,400000")
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--steps", type=int, default=40)
    args = parser.parse_args(argv)
    numba.set_num_threads(1)
    for name in args.elements.split(","):
        if name not in ("mindlin", "fibrous"):
            raise ValueError(f"--elements takes mindlin and fibrous, got {name!r}")
        for size in [int(s) for s in args.sizes.split(",")]:
            case(name, size, args.rounds, args.steps)


if __name__ == "__main__":
    main()
