"""What sets the explicit step of the hemisphere forming case (validation/cases/
hemisphere_forming.py): the bounds the solver (solvers/explicit_step_size.py ``_step_size``)
combines, beside the exact 2 / omega_max of the blank, at the start and at states of the stroke.

At each state, printed (s): the cells' own bound (``cell_stable_dt``, min over the cells),
the assembled Gershgorin bound of the elements (``assembled_stable_dt``), the exact 2 /
omega_max of the elements (scipy ``eigsh`` on M^-1/2 K M^-1/2 over the free DOFs, K the
elements' own tangent at the state, its symmetric part, M the lumped masses and rotary
inertias the solver uses there), the same with the contacts' tangents of the nodes touching
then (the springs as they are), and with every blank node pressed along z by all the tools
at once (the worst case the solver's spring bound covers: k_i of each tool on each node's
z); the tools' springs as the solver bounds them (k / m of each tool,
``penalty_frequency_squared``) and the step the solver takes there (safety 0.9, the
damping), and each as a ratio to the exact one.

The states of the stroke are those of an unscaled run of the case (``--at``: fractions of the
stroke; the run's state, masses and inertias kept at the first step past each), saved in
``--states`` and read again from there.

    python benchmarks/hemisphere_step_bounds.py --cells 100 --at 0.01,0.25,0.5
    python benchmarks/hemisphere_step_bounds.py --cells 20 --at 0.01,0.5,0.9

Measured (main d004b4e; one thread; the ratios are to the exact 2 / omega_max of the
elements at that state):

* 20k triangles (100 cells), 0.01 of the stroke (t = 0.003 s): exact 4.103e-6 s; the cells'
  bound 2.853e-6 (0.695), the assembled Gershgorin bound 3.994e-6 (0.974); the exact with the
  contacts touching then 1.000, with every node pressed along z by all three tools 1.000 (the
  highest mode is the fibres' in-plane one: springs along the normal do not reach it); the
  springs' bound the solver adds, sum over the tools of max k / m, 0.644 of the elements'
  exact omega^2 (0.207 a tool: the penalty is PENALTY_SHARE of the cells' omega^2, and the
  cells' bound is 0.695 of the exact); the solver's step 2.242e-6 (0.546); the same rule on
  the assembled bound alone 2.833e-6 (0.690). 10 s of CPU for the bounds. At 0.25 of the
  stroke (t = 0.075 s, the punch 5.2 mm down) the same to three digits: exact 4.103e-6 s, the
  cells' 0.694, Gershgorin 0.974, the contacts 1.000 and 1.000, the springs 0.644, the step
  2.239e-6 (0.546), on the assembled bound alone 0.690. At mid-stroke (t = 0.15 s, the punch
  25 mm down; the run there took 781 s of CPU on two threads, load 5-13): exact 3.979e-6 s;
  the cells' bound 2.748e-6 (0.691), Gershgorin 3.738e-6 (0.939); the contacts touching then
  1.000, every node pressed by every tool 3.558e-6 (0.894); the springs 0.606; the solver's
  step 2.178e-6 (0.547), on the assembled bound alone 2.716e-6 (0.682). 19 s of CPU.
* 20 cells, 0.01 / 0.5 / 0.9 of the stroke: exact 2.051e-5 / 2.047e-5 / 1.818e-5 s; the
  cells' bound 0.697 / 0.675 / 0.708; Gershgorin 0.974 / 0.940 / 0.807; with the contacts
  touching then 1.000 / 1.000 / 0.998; every node pressed by every tool 1.000 / 0.916 /
  0.862; the springs' bound 0.641 / 0.638 / 0.503 of the elements' omega^2; the solver's step
  0.548 / 0.535 / 0.569; on the assembled bound alone 0.691 / 0.677 / 0.631.

So the step is about 0.55 of the exact one, from three factors: the safety 0.9; the cells'
bound, 0.68-0.71 of the exact along the stroke (the element-by-element estimate, §6.2 of
docs/theory.md: L / c on the assembled sheet's fibres against 0.82 L / c on one cell, with
the shear and bending added in); the springs, which lower the cells' own critical step to
0.873 of it (2 / sqrt(omega_cells^2 (1 + 0.1 + 0.1 + 0.1 (1 + r))), r = 0.117 the holder's
share of its tool node, elements/contact.py ``springs``). The springs do not cut the step
well below the cells' own (12.7 %), and the penetration they allow is not small already
(benchmarks/hemisphere_scaling.py: 0.11-0.12 mm at most on the 0.3-mm ply at 20 cells; a
softer penalty saved 9 % of the steps at a quarter of it and let the ply 0.41 mm into the
die). The assembled bound alone (not the library's rule, which takes the smaller of the two)
gave 0.834 / 0.839 / 0.841 of the steps at 20 / 32 / 40 cells with the compared results within
2 % (benchmarks/hemisphere_scaling.py ``--bound``).
"""

from __future__ import annotations

import argparse
import math
import os
import pickle
import sys
import time
from pathlib import Path

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import eigsh

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install
os.environ.setdefault("FIBRESHELL_PROGRESS", "0")

import solvers.explicit as explicit  # noqa: E402
from solvers import CentralDifference  # noqa: E402
from validation.cases import hemisphere_forming as case  # noqa: E402

SAFETY = 0.9  # the solver's default


class _Enough(Exception):
    """Raised once the run has passed the last state asked for."""


def states(cells: int, fractions: list[float], folder: Path) -> dict[float, dict]:
    """{fraction: {"state", "mass", "inertia", "dt"}}: the unscaled run's state, masses and
    inertias at the first step past each fraction of the stroke, read from ``folder`` where
    saved there, else run and saved."""
    saved = {f: folder / f"hemisphere_{cells}_{f:g}.pkl" for f in fractions}
    todo = [f for f in fractions if not saved[f].exists()]
    if todo:
        compiled = case.model(cells, "fibrous", rim=case.DIE_RIM)[1].compile()
        last: dict = {}
        step = explicit.explicit_step

        def kept(model, state, dt, masses, **options):
            last.update(state=state, mass=masses.mass, inertia=masses.inertia, dt=dt)
            return step(model, state, dt, masses, **options)

        def summary(frame) -> dict:
            while todo and frame.time >= todo[0] * case.DURATION * (1 - 1e-9) and last:
                with open(saved[todo.pop(0)], "wb") as file:
                    pickle.dump(dict(last), file)
            if not todo:
                raise _Enough
            return {}

        explicit.explicit_step = kept
        solver = CentralDifference(
            duration=case.DURATION,
            damping=case.DAMPING,
            progress=False,
            output_interval=0.005 * case.DURATION,
            frame_summary=summary,
        )
        try:
            solver.solve(compiled)
        except _Enough:
            pass
        finally:
            explicit.explicit_step = step
    return {f: pickle.loads(saved[f].read_bytes()) for f in fractions}


def largest(k: sp.spmatrix, diagonal: np.ndarray) -> float:
    """The largest eigenvalue of D^-1/2 sym(K) D^-1/2 (1/s^2), D = diag(``diagonal``)."""
    scale = sp.diags(1.0 / np.sqrt(diagonal))
    a = scale @ (0.5 * (k + k.T)) @ scale
    return float(eigsh(a.tocsc(), k=1, which="LA", tol=1e-6, return_eigenvectors=False)[0])


def bounds(compiled, saved: dict, damping: float) -> dict[str, float]:
    """The bounds at one saved state (module docstring), s."""
    state, mass, inertia = saved["state"], saved["mass"], saved["inertia"]
    dofs = compiled.dofs
    free = dofs.free_slots
    diagonal = np.column_stack([mass, mass, mass, inertia, inertia]).ravel()[free]
    cells = min(float(dt.min()) for dt in compiled.cell_stable_dt(state))
    assembled = compiled.assembled_stable_dt(state, mass, inertia)
    blocks = list(range(len(compiled.blocks)))
    k_elements = compiled.stiffness(state, parts=blocks)[free][:, free]
    exact = 2.0 / math.sqrt(largest(k_elements, diagonal))
    k_all = compiled.stiffness(state)[free][:, free]
    touching = 2.0 / math.sqrt(largest(k_all, diagonal))
    # Every blank node pressed along z by every tool: the sum of their k_i on its uz slot.
    pressed = np.zeros(dofs.n_slots)
    per_tool = []
    for interaction in compiled.interactions:
        nodes, k = interaction.connectivity[:, 0], interaction.stiffness
        np.add.at(pressed, 5 * nodes + 2, k)
        per_tool.append(float(np.max(k / mass[nodes])))
    worst = 2.0 / math.sqrt(largest(k_elements + sp.diags(pressed[free]), diagonal))
    springs = compiled.penalty_frequency_squared(mass, state)
    solver = CentralDifference(duration=case.DURATION, damping=damping, progress=False)
    solver._assembled = None
    taken = solver._step_size(compiled, state, None, mass, inertia, 0)
    # The same rule on the assembled bound alone (benchmarks/hemisphere_scaling.py --bound).
    alone = 2.0 / math.sqrt((2.0 / assembled) ** 2 + springs)
    xi = damping * alone / 4.0
    alone = SAFETY * alone * (math.sqrt(1.0 + xi * xi) - xi)
    return {
        "cells": cells,
        "assembled": assembled,
        "exact": exact,
        "exact_touching": touching,
        "exact_all_pressed": worst,
        "springs_omega2": springs,
        "per_tool_omega2": per_tool,
        "taken": taken,
        "dt_run": saved["dt"],
        "assembled_alone": alone,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cells", type=int, default=100)
    parser.add_argument("--at", default="0.01,0.5", help="fractions of the stroke")
    parser.add_argument("--states", default="/tmp", help="where the run's states are kept")
    args = parser.parse_args()
    fractions = [float(f) for f in args.at.split(",")]
    folder = Path(args.states)
    folder.mkdir(parents=True, exist_ok=True)
    saved = states(args.cells, fractions, folder)
    compiled = case.model(args.cells, "fibrous", rim=case.DIE_RIM)[1].compile()
    for fraction, at in saved.items():
        cpu = time.process_time()
        b = bounds(compiled, at, case.DAMPING)
        exact = b["exact"]
        omega_e = (2.0 / exact) ** 2
        print(f"{args.cells} cells, {fraction:g} of the stroke (t = {at['state'].time:.4g} s): "
              f"exact 2/omega_max of the elements {exact:.4g} s; the cells' bound "
              f"{b['cells']:.4g} ({b['cells'] / exact:.3f} of it), assembled Gershgorin "
              f"{b['assembled']:.4g} ({b['assembled'] / exact:.3f}); with the contacts touching "
              f"now {b['exact_touching']:.4g} ({b['exact_touching'] / exact:.3f}), every node "
              f"pressed by every tool {b['exact_all_pressed']:.4g} "
              f"({b['exact_all_pressed'] / exact:.3f}); the springs' bound k/m "
              f"{b['springs_omega2']:.3g} 1/s^2 ({b['springs_omega2'] / omega_e:.3f} of the "
              f"elements' exact omega^2; per tool "
              f"{', '.join(f'{w / omega_e:.3f}' for w in b['per_tool_omega2'])}); the solver's "
              f"step {b['taken']:.4g} ({b['taken'] / exact:.3f}; the run's {b['dt_run']:.4g}), "
              f"on the assembled bound alone {b['assembled_alone']:.4g} "
              f"({b['assembled_alone'] / exact:.3f}); "
              f"{time.process_time() - cpu:.0f} s CPU", flush=True)  # fmt: skip


if __name__ == "__main__":
    main()
