"""The Mindlin hemisphere's explicit step along the stroke (validation/cases/hemisphere_forming.py
``run``, unscaled, one ply): the step the solver takes, the cells' bound and the assembled
Gershgorin bound it combines (solvers/explicit_step_size.py ``_step_size``) at fractions of the
stroke, the steps of the whole stroke and the run's results, to be run on two versions of the code
side by side (each prints the load).

    python benchmarks/mindlin_hemisphere_step.py --cells 20,28

Why the 28-cell stroke took 222591 steps where 20 cells took 47270 (docs/theory.md §6.2 B5):
the cells' bound followed the current altitudes (B1 + B2 at the current positions), which fall
as the cells shear and vanish where one folds flat, while the element's Green-Lagrange
stiffness grows only as its squared stretch. Measured with that bound (main 5850b10, one
thread, nice 5, load 5-11), the solver's step / the cells' bound / the assembled bound, s:

* 20 cells: 7.06e-6 / 9.06e-6 / 8.97e-6 at the start; 6.79e-6 / 8.51e-6 / 8.95e-6 at half the
  stroke; 5.39e-6 / 6.44e-6 / 7.67e-6 at the end (the cells' bound down to 0.70 of its start);
  47270 steps.
* 28 cells: 5.05e-6 / 6.47e-6 / 6.40e-6 at the start; 4.83e-6 / 6.05e-6 / 6.39e-6 at half;
  3.00e-6 / 3.48e-6 / 5.53e-6 at 0.8; 7.6e-7 / 8.5e-7 / 5.28e-6 at 0.85; 4.5e-7 / 5.0e-7 /
  5.38e-6 at the end; the cells' bound as low as 0.0006 of its start (a folded cell); 222591
  steps, 169 s of CPU. At 0.85 of the stroke the cells with the lowest bound (8.4e-7 to 2.9e-6
  s) have element eigenvalue steps (the 18 x 18 problem at their current corners and
  directors) of 5.65-5.84e-6 s: the bound was 0.15 of their own step. With the bound of B5
  there: 4.70e-6 s (0.83 of the element's own), at 0.7 of the stroke 4.98e-6 against 6.06e-6.

The springs (``penalty_frequency_squared``) stay at their start on both meshes (0.31 of the
cells' omega^2): not the cause.

With the bound of B5 (the same machine, load 3-4, side by side with the code before in a copy
of main): 20 cells 46967 steps (47270 before), the step 7.06e-6 / 6.53e-6 / 5.68e-6 s at the
start / half / end, the cells' bound at its lowest 0.75 of its start (0.70 before); 28 cells
66484 steps (222591 before), 5.05e-6 / 4.65e-6 / 3.88e-6 s, its lowest 0.71 of its start, 47
s of CPU (143 before, load 2.3): 1.42 times the 20-cell steps (the cells' ratio 28 / 20 = 1.4). The
results the runs print moved by at most 0.3 mm of draw-in, 0.2 N of late force and 0.03 deg
of rms (docs/hemisphere_forming.md, "Observed orders on finer meshes").
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install
os.environ.setdefault("FIBRESHELL_PROGRESS", "0")

from solvers import CentralDifference  # noqa: E402
from validation.cases import hemisphere_forming as case  # noqa: E402

FRACTIONS = (0.0, 0.25, 0.5, 0.7, 0.8, 0.85, 0.9, 1.0)


def logged_run(cells: int) -> tuple[dict, np.ndarray]:
    """The case's Mindlin run on ``cells`` with the solver's step evaluations logged: (the
    run's record, (k, 4) rows of time s, step taken s, cells' bound s, assembled bound s)."""
    log: list[tuple[float, float, float, float]] = []
    original = CentralDifference._step_size

    def step_size(self, model, state, scale, mass, inertia=None, step=0, previous=None):
        dt = original(self, model, state, scale, mass, inertia, step, previous)
        cells_dt = min(float(d.min()) for d in model.cell_stable_dt(state))
        assembled = self._assembled[0] if self._assembled is not None else np.nan
        log.append((state.time, dt, cells_dt, assembled))
        return dt

    CentralDifference._step_size = step_size  # type: ignore[method-assign]
    try:
        record = case.run(cells, "mindlin")
    finally:
        CentralDifference._step_size = original  # type: ignore[method-assign]
    return record, np.array(log)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cells", default="20,28")
    args = parser.parse_args()
    for cells in (int(c) for c in args.cells.split(",")):
        cpu = time.process_time()
        record, log = logged_run(cells)
        print(f"{cells} cells (load {os.getloadavg()[0]:.1f}): {record['result'].steps} "
              f"steps (reached the end: {record['result'].converged}), "
              f"{time.process_time() - cpu:.0f} s CPU; draw-in of the edge middle "
              f"{record['draw_in_mm']:.2f} mm, edges' mean {record['edge_draw_in_mm']:.2f}, "
              f"corners' {record['corner_draw_in_mm']:.2f}; late punch force "
              f"{record['late_punch_force_N']:.2f} N; rms shear - net {record['rms_deg']:.3f} "
              f"deg; largest KE / W {record['largest_kinetic_over_work']:.3f}; holder lift "
              f"{record['holder_lift_mm']:.2f} mm", flush=True)  # fmt: skip
        for fraction in FRACTIONS:
            i = min(int(np.searchsorted(log[:, 0], fraction * case.DURATION)), len(log) - 1)
            t, dt, cells_dt, assembled = log[i]
            print(f"  {fraction:.2f} of the stroke: step {dt:.3e} s, cells' bound "
                  f"{cells_dt:.3e}, assembled {assembled:.3e}")  # fmt: skip
        print(f"  the cells' bound at its lowest {log[:, 2].min():.3e} s "
              f"({log[:, 2].min() / log[0, 2]:.4f} of its start)", flush=True)  # fmt: skip


if __name__ == "__main__":
    main()
