"""What sets the two-ply hemisphere's explicit step (validation/studies/hemisphere_plies_run.py,
8 cells, holder 20 N, the [0/90] layup): at states of the case's run, the bound the solver
steps by (solvers/explicit_step_size.py ``_step_size``: the cells' estimate (2 / dt_cells)^2 plus
the largest sum over a node of the penalty springs' k / m, femcore/compiled.py
``penalty_frequency_squared``) beside the largest eigenvalue of M^-1 K at that state (K the
parts' own tangent over the free slots, M the lumped masses and rotary inertias; scipy's
eigsh), of the elements alone and of every part (the contacts' tangents with them).

The eigenvalue is not a bound the solver could step by as it is: it holds at the state alone
(the springs are held for SPRINGS_HELD_STEPS steps, for points that may touch by then,
elements/ply_springs.py), and a power iteration gives it from below. It measures the bound's
margin: how many more steps the case pays than an exact critical step at each state would
ask for.

Measured (this script, one thread, load 8-10 on 2 cores; omega^2 in 1/s^2), with the fade's
SIDEWAYS = 0.5 (its factor 12 beside an outline vertex) up to "A wider wedge" below:

* fibrous, steps 1000 / 3000 / 5000 of 5612: the bound 9.71e9 / 9.96e9 / 1.08e10 (cells
  2.24e9 / 2.46e9 / 2.81e9, springs 7.47e9 / 7.49e9 / 7.99e9), lambda_max of every part
  2.12e9 / 2.12e9 / 2.23e9 (the elements alone 1.52e9 / 1.52e9 / 1.65e9): the bound 4.6-4.9
  times the state's omega^2, the step taken 0.41-0.42 of the state's critical one (the
  safety 0.9 included);
* Mindlin, steps 1000 / 5000 / 9000 of 11195: the bound 3.40e10 / 3.42e10 / 4.86e10 (cells
  7.96e9 / 8.48e9 / 1.21e10, springs 2.60e10 / 2.57e10 / 3.65e10), lambda_max 6.19e9 /
  5.13e9 / 1.36e10 (the elements 5.51e9 / 5.13e9 / 5.13e9): 3.6-6.7 times, the step
  0.35-0.48 of the state's critical one.

The springs are 3.3-3.6 times the cells' omega^2 and come from the mirrored pass (the bottom
ply's nodes against the top ply's faces) at the top ply's outline nodes: at the start its
corner node (lumped mass 2.97e-8 t, a third of an edge node's) takes 190.6 N/mm, the corner
point's penalty 6.64 N/mm times the fade's factor 12 beside an outline vertex times s_p = 2
(elements/ply_springs.py), 6.42e9 of the 7.83e9 there; the other pass's largest 5.09e8. The
cells' estimate is itself 1.45-1.47 times the elements' lambda_max (both kinematics).

What the margin costs, tried and not kept (no bound of the reachable states backs it): the
springs' omega^2 quartered in ``penalty_frequency_squared`` (the bound then still 1.6-2.3
times each sampled state's lambda_max), the whole case (``python -m validation --cases
hemisphere-plies``, load 6-14): 35357 -> 23608 steps (5612 / 11195 / 6636 / 11914 -> 3698 /
7492 / 4546 / 7872), 24 of 24 checks; the fibrous rms of shear - net moved <= 0.022 deg, the
draw-in <= 0.29 mm; the Mindlin rms <= 0.45 deg, the corners' draw-in <= 2.4 mm (the spread
a changed step gives them).

With the springs' nodes weighed by their masses (elements/ply_springs.py, "Weights"; load
12-14): fibrous, steps 1000 / 3000 / 5000 of 5530, the bound 9.56e9 / 9.94e9 / 1.02e10
(springs 7.32e9 / 7.47e9 / 7.43e9), 4.5-4.7 times lambda_max 2.12e9 / 2.12e9 / 2.24e9; the
springs asked for the step taken 0.984 / 0.983 / 0.931 of the equal weights' at the same
state; Mindlin, steps 1000 / 5000 / 9000 of 11032, the bound 3.35e10 / 3.48e10 / 4.80e10,
5.4 / 6.9 / 2.8 times lambda_max 6.19e9 / 5.03e9 / 1.71e10, the springs 0.984 / 0.988 / 0.961
of the equal weights'. Small gains: the largest springs join a bottom ply's outline node to
the top ply's node it lies on, two nodes of equal mass, where Cauchy-Schwarz is exact.

Why a quarter of the springs was not safe at SIDEWAYS 0.5 (tests/test_ply_springs_case.py
then): each of those top nodes is an outline vertex of three triangles (one at a corner) with a
wedge beside it; a bottom node moved 0.15 mm into it (under the slide at rest) and lifted 1e-4
mm meets the fade's 12 k along the normal (10.4 k there). With every bottom outline node so
moved, lambda_max of every part is 4.88e9 (Mindlin 1.75e10): 1.16 (1.20) times the cells plus a
quarter of the springs, 0.50 (0.52) of the bound; the mirrored pass alone 0.78 of its own
springs. The margin is in the cells' bound and in the sum of the two parts, not in the springs.

A wider wedge, tried and then adopted (elements/ply_fade.py ``SIDEWAYS``, the fade's factor
beside an outline vertex 3 / SIDEWAYS^2): the whole case (``python -m validation --cases
hemisphere-plies --jobs 1``, one thread, the three run side by side from cold numba caches,
load 6-12), SIDEWAYS 0.5 / 1 / 0.75 (factor 12 / 3 / 5.3): 33325 / 26376 / 28582 steps (5530 /
4131 / 4538, 11032 / 8429 / 9123, 5949 / 4825 / 5318, 10814 / 8991 / 9603 per run: 1.26 and
1.17 times fewer, not the 1.4 the springs' share estimated), case_cpu_s 151.8 / 131.1 / 144.1
s; 24 of 24 checks each. The plies' order in the die -0.133 / -0.132 / -0.134 mm (fibrous
[0/90]), -0.123 / -0.129 / -0.155 (Mindlin [0/90]), +0.006 / +0.007 / +0.013 and +0.26 / +0.33
/ +0.29 ([0/45]); through the holder at most 0.025 mm deeper (Mindlin [0/90] ply 1, 0.068 ->
0.093 mm at SIDEWAYS 1), the least gap over the run nowhere deeper (Mindlin [0/90] -3.36 /
-0.76 / -0.72 mm): nothing sinks a tenth of a ply (0.03 mm) further. The fibrous rms of shear -
net moved <= 0.018 / 0.019 deg, the draw-in <= 0.37 / 1.78 mm (the [0/45] bottom ply's corner
at 0.75). The Mindlin runs moved past the spread a changed step gives them (0.45-0.74 deg,
corners 1.4-2.4 mm): at SIDEWAYS 1 the [0/45] top ply's rms 5.67 -> 4.77 deg and the [0/90] top
ply's corner draw-in 14.9 -> 21.5 mm; at 0.75 the [0/45] bottom ply's edge middle 29.2 -> 24.7
mm. That move is the step's: SIDEWAYS 0.5 with the springs' factor 3 (the step of SIDEWAYS 1,
the contact of 0.5; warm caches, load 1.4-4.7, 60.1 s CPU, 26515 steps, 24 of 24 checks) moved
them alike (5.67 -> 4.94 deg, 14.9 -> 19.8 mm), and the wedge alone (that run beside SIDEWAYS
1, nearly the same step) moved the fibrous rms <= 0.007 deg and draw-in <= 0.09 mm, the Mindlin
rms <= 0.38 deg and corners <= 2.7 mm (the [0/45] top ply's; its edge middle 4.3 mm, where the
two steps at 0.5 differed by 0.3 and 2.4 mm). So SIDEWAYS 1 passes the case's tests of the
contact; adopted after this study (elements/ply_fade.py; docs/theory.md §9.3a). The wedge state
of tests/test_ply_springs_case.py at SIDEWAYS 1: lambda_max of every part 1.54e9 (Mindlin
6.14e9), within the bound (its cells alone 2.24e9 and 7.79e9): the springs' check holds, the
claim that a quarter of them would not hold is the factor 12's.

Run: NUMBA_NUM_THREADS=1 python benchmarks/ply_step_bound.py --kinematics fibrous \
--steps 1000 3000 5000
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import eigsh

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install

import solvers.explicit as explicit  # noqa: E402
from femcore.compiled import _springs_at  # noqa: E402
from solvers.interrupts import STOP, Interrupted, interruptible  # noqa: E402
from validation.studies import hemisphere_plies_setup as setup  # noqa: E402
from validation.studies.hemisphere_plies_run import case_solver  # noqa: E402


def largest_eigenvalue(compiled, state, parts) -> float:
    """lambda_max of M^-1 K (1/s^2) over the free slots with a positive mass or inertia, K
    the tangent of ``parts`` (indices into ``compiled.parts``; None: all) at ``state``."""
    mass, inertia = compiled.lumped_mass(state)
    masses = np.zeros((compiled.n_nodes, 5))
    masses[:, :3] = mass[:, None]
    masses[:, 3:] = inertia[:, None]
    free = compiled.dofs.free_slots
    stiffness = compiled.stiffness(state, parts=parts)[free][:, free]
    diagonal = masses.ravel()[free]
    kept = diagonal > 0.0
    scale = sp.diags(1.0 / np.sqrt(diagonal[kept]))
    scaled = scale @ stiffness[kept][:, kept] @ scale
    return float(eigsh(0.5 * (scaled + scaled.T), k=1, which="LA", return_eigenvectors=False)[0])


def springs_by_part(compiled, state, step: float) -> list[tuple[str, float]]:
    """Each interaction's largest k / m over the nodes (1/s^2) at ``state``, its springs
    asked for ``step`` s, the nodes weighed by the lumped masses (as the solver's step
    weighs them, femcore/compiled.py ``penalty_frequency_squared``)."""
    mass = compiled.lumped_mass(state)[0]
    found = []
    for interaction in compiled.interactions:
        springs = _springs_at(interaction, state, step, mass)
        largest = 0.0
        if springs is not None and len(springs[0]):
            nodes = np.asarray(springs[0])
            largest = float(np.max(np.asarray(springs[1]) / mass[nodes]))
        found.append((type(interaction).__name__, largest))
    return found


def equal_weights(compiled, mass, state, step: float) -> float:
    """``penalty_frequency_squared`` with the ply springs' nodes weighed equally (their
    bound before the masses weighed them, elements/ply_springs.py "Weights"), 1/s^2."""
    plies = [b for b in compiled.interactions if getattr(b, "calibrated_mass", None) is not None]
    held = [b.calibrated_mass for b in plies]
    for block in plies:
        block.calibrated_mass = None
    try:
        return compiled.penalty_frequency_squared(mass, state, step)
    finally:
        for block, mass_held in zip(plies, held):
            block.calibrated_mass = mass_held


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--kinematics", default="fibrous", help="fibrous or mindlin plies")
    parser.add_argument("--steps", type=int, nargs="+", default=[1000, 3000, 5000])
    args = parser.parse_args()
    _, model = setup.model(8, setup.LAYUPS["0/90"], args.kinematics, 20.0)
    compiled = model.compile()
    asked: list[tuple[float, float, float]] = []  # (critical, springs, step) per evaluation
    lowered = explicit.CentralDifference._lowered

    def logged(solver, critical: float, springs: float) -> float:
        step = lowered(solver, critical, springs)
        asked.append((critical, springs, step))
        return step

    explicit.CentralDifference._lowered = logged  # type: ignore[method-assign]
    commit = type(compiled).commit
    states = {}
    count = [0]

    def counted(state):
        count[0] += 1
        accepted = commit(compiled, state)
        if count[0] in args.steps:
            states[count[0]] = (accepted, asked[-1])
        if count[0] == max(args.steps):
            STOP.signal = "SIGINT"  # stops the run at this step's end
        return accepted

    compiled.commit = counted  # type: ignore[method-assign]
    print(f"load {os.getloadavg()}")
    with interruptible():
        try:
            case_solver("0/90", args.kinematics, output_interval=None).solve(compiled)
        except Interrupted:
            pass
    compiled.commit = commit.__get__(compiled)  # type: ignore[method-assign]
    for step, (state, (critical, springs, dt)) in sorted(states.items()):
        cells = (2.0 / critical) ** 2
        elements = largest_eigenvalue(compiled, state, list(range(len(compiled.blocks))))
        every = largest_eigenvalue(compiled, state, None)
        exact = 2.0 / np.sqrt(every)
        print(f"step {step}: bound {cells + springs:.3e} (cells {cells:.3e}, springs "
              f"{springs:.3e}); lambda_max {every:.3e} (elements {elements:.3e}); "
              f"bound / lambda_max {(cells + springs) / every:.2f}; the step {dt:.3e} s, "
              f"{dt / exact:.2f} of the state's critical one {exact:.3e} s")  # fmt: skip
        parts = ", ".join(f"{n} {w:.2e}" for n, w in springs_by_part(compiled, state, dt))
        print(f"    each interaction's largest k / m: {parts}")
        mass = compiled.lumped_mass(state)[0]
        weighted = compiled.penalty_frequency_squared(mass, state, dt)
        equal = equal_weights(compiled, mass, state, dt)
        print(f"    the springs asked for the step taken: {weighted:.3e}, with equal weights "
              f"{equal:.3e} ({weighted / equal:.3f})")  # fmt: skip
    print(f"load {os.getloadavg()}")


if __name__ == "__main__":
    main()
