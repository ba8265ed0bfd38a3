"""What the fibres' in-plane bending (elements/fibre_bending.py) adds to an explicit step: its
compiled force pass against the fibrous shell's own force pass (the reference) on the same
blank and state, in one process, one numba thread, best of ``--repeat`` after a warm-up.

The blank is the one-ply hemisphere's (``Mesh.rectangle``, 200 mm, ``--cells`` a side, the
case's ply), at a state off the flat blank by 0.3 mm at random (out of its plane too). Printed:
the load, the patches, each pass's best time (ms) and their ratio, and the numpy reference's
time for the term.

    python benchmarks/fibre_bending_force.py --cells 48

Measured (one thread), 48 cells, 9024 patches, at load 1.9, back to back: the fibrous force
pass 1.266 / 1.274 ms; the term's compiled pass with the angle in each cell's plane 1.250 ms
(0.99 x), with the unfolded angle (docs/theory.md §4.7, its numpy functions compiled) 0.740 ms
(0.58 x); the numpy pass 9.9 / 10.7 ms; the compiled and numpy forces 1.1e-16 N apart
(largest 0.26 N). The springs bounding the whole stiffness (a Hessian per patch,
docs/theory.md §4.7), taken every 10 steps: with the Hessian by the complex step 25.4 ms
compiled (1.96 x the fibrous pass a step), 92 ms numpy, at load 4.7; by a forward
difference (kept) 10.2 ms (0.79 x), 60 ms numpy, at load 5.6, 1.1e-16 N/mm apart (largest
0.50).
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from elements import FibrousShell  # noqa: E402
from elements.fibre_bending import FibreBending  # noqa: E402
from femcore import Mesh, Model  # noqa: E402
from femcore.interaction import SPRINGS_HELD_STEPS  # noqa: E402
from validation.cases import hemisphere_forming as case  # noqa: E402


def best(call, repeat: int) -> float:
    call()
    times = []
    for _ in range(repeat):
        start = time.process_time()
        call()
        times.append(time.process_time() - start)
    return min(times)


def main(argv: list[str]) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cells", type=int, default=48)
    parser.add_argument("--repeat", type=int, default=20)
    parser.add_argument("--stiffness", type=float, default=0.5, help="B_in, N mm")
    arguments = parser.parse_args(argv)
    cells = arguments.cells
    mesh = Mesh.rectangle(200.0, 200.0, nx=cells, ny=cells, origin=(-100.0, -100.0, 0.0))
    built = Model(mesh)
    built.add(FibrousShell(case.fabric()))
    built.interact(FibreBending(arguments.stiffness))
    built.interact(FibreBending(arguments.stiffness, kernel="numpy"))
    compiled = built.compile()
    state = compiled.initial_state()
    rng = np.random.default_rng(0)
    state.positions = state.positions + rng.normal(scale=0.3, size=state.positions.shape)
    shell = compiled.blocks[0]
    term, reference = compiled.interactions
    history = state.history[0]
    f_term, _ = term.internal_force(state)
    f_reference, _ = reference.internal_force(state)
    shell_ms = 1e3 * best(lambda: shell.internal_force(state, history), arguments.repeat)
    term_ms = 1e3 * best(lambda: term.internal_force(state), arguments.repeat)
    numpy_ms = 1e3 * best(lambda: reference.internal_force(state), max(3, arguments.repeat // 5))
    springs_ms = 1e3 * best(lambda: term.springs_at(state), max(3, arguments.repeat // 5))
    springs_numpy_ms = 1e3 * best(lambda: reference.springs_at(state), 3)
    s_term, s_reference = term.springs_at(state)[1], reference.springs_at(state)[1]
    print(f"load {os.getloadavg()[0]:.1f}; {cells} cells, {len(term.connectivity)} patches")
    print(f"  fibrous shell force pass (reference): {shell_ms:.3f} ms")
    print(f"  in-plane bending, compiled:           {term_ms:.3f} ms ({term_ms / shell_ms:.2f} x)")
    print(f"  in-plane bending, numpy:              {numpy_ms:.3f} ms")
    print(
        f"  springs (every {SPRINGS_HELD_STEPS} steps), compiled: {springs_ms:.3f} ms "
        f"({springs_ms / shell_ms / SPRINGS_HELD_STEPS:.2f} x the shell's pass a step), "
        f"numpy {springs_numpy_ms:.3f} ms, apart by {np.abs(s_term - s_reference).max():.3g} "
        f"N/mm (largest {np.abs(s_reference).max():.3g})"
    )
    print(f"  compiled - numpy force: {np.abs(f_term - f_reference).max():.3g} N (largest "
          f"{np.abs(f_reference).max():.3g})")  # fmt: skip


if __name__ == "__main__":
    main(sys.argv[1:])
