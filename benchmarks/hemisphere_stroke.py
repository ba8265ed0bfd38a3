"""The hemisphere forming case's whole stroke (validation/cases/hemisphere_forming.py ``run``)
at one resolution and scaling, watched as it runs: a line every ``--every`` steps (the step,
the fraction of the stroke, CPU and wall so far, the machine's load), the case's compared
figures at the end (benchmarks/hemisphere_scaling.py ``measure``: rms shear - net, draw-ins,
punch force, KE / W, penetrations), and the run's states at ``--at`` fractions of the stroke
saved for benchmarks/hemisphere_step_bounds.py and hemisphere_step_parts.py (their
``states`` reads them: hemisphere_<cells>_<fraction>.pkl in ``--states``).

    python benchmarks/hemisphere_stroke.py --cells 100 --time-scaling 1 --at 0.25,0.5,0.75
    python benchmarks/hemisphere_stroke.py --cells 100 --pace 0.25,0.5 --steps 300 --threads 1,2

``--compare``: a scaled run's saved states (its folder) against the unscaled run's (``--states``)
at the same punch travel (the same fractions of each stroke), each fraction saved by both:
the shear field's difference (rms and largest, deg, over the cells the case compares with the
net, validation/cases/hemisphere_forming.py ``compared_cells``), the draw-ins (edge middle,
edges' mean, corners, mm), the punch's force on the blank (N, its contact's forces summed at
that state) and the kinetic energy of the blank's translations (N mm) of each.

    python benchmarks/hemisphere_stroke.py --cells 100 --compare /tmp/x4 --states /tmp/x1

``--pace``: from each saved state, ``--steps`` steps as the solver takes them (explicit_step,
the commit, the stable step every STABLE_DT_EVERY steps with the rotary inertia's refresh,
the energy check every BALANCE_EVERY) on each of ``--threads``, timed phase by phase
(benchmarks/hemisphere_forming.py ``Phases``: CPU and the main thread's CPU a step, which
bounds a two-thread step's wall from below on a machine whose second core is free);
``--short-lists on,off``: with and without the die's short lists (SHORT_LISTS).

Measured (one thread, nice 5, CPU; the machine shared by five at a load of 7-15; the study and
its conclusion in docs/hemisphere_forming.md, "The 20k-triangle stroke"):

* ``--pace 0.1,0.25 --threads 1,2`` from the unscaled stroke's states: one thread 10.81 /
  11.20 ms CPU a step (the element force 6.85 / 6.99, the die 1.84 / 1.82, the punch and
  holder 0.68 / 0.74, the cells' stable step 0.033 / 0.037, the nodal update 0.55 / 0.65; the
  reference pass 0.13 ms); two threads 8.14 / 9.43 ms CPU, 5.01 / 5.90 on the main thread
  (load 11.8-14.5);
* ``--short-lists off,on,off,on --pace 0.1``: the die 1.93 / 1.85 -> 1.82 / 1.78 ms a step;
* whole strokes at 100 cells: x4 34923 steps, rms 4.948 deg, edge middle 29.52 mm (edges'
  mean 13.80, corners 8.54), late punch force 53.21 N, KE / W at most 0.087 (none of the
  stroke above 0.1), 479 s CPU; x6 23234 steps, rms 5.192 deg, edge middle 26.64 mm
  (edges' mean 13.74, corners 8.50), late punch force 52.50 N, KE / W at most 0.239 (0.145 of
  the judged stroke above 0.1: the case's rule broken), 302 s CPU; the unscaled stroke
  stopped at 0.25 (33.5k steps, 6.4 min of CPU, 35 min of wall at that load);
* ``--compare`` at 0.25 of the stroke against the unscaled: x4 0.145 deg rms of the shear
  field's difference (largest 0.31), x6 0.295 (0.69), the field's own rms 0.38 deg; the punch
  force 0.10 -> 0.20 / 0.38 N, the kinetic energy 0.0104 -> 0.213 / 0.384 N mm.
"""

from __future__ import annotations

import argparse
import os
import pickle
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install
sys.path.insert(0, str(Path(__file__).resolve().parent))
os.environ.setdefault("FIBRESHELL_PROGRESS", "0")

import hemisphere_scaling as scaling  # noqa: E402
import numba  # noqa: E402
import numpy as np  # noqa: E402
from contact_search import best  # noqa: E402
from hemisphere_forming import Phases, load  # noqa: E402

import solvers.explicit as explicit  # noqa: E402
from elements import rigid_surface as surfaces  # noqa: E402
from femcore import jit  # noqa: E402
from solvers import CentralDifference  # noqa: E402
from solvers.step import LumpedMasses  # noqa: E402
from validation.cases import hemisphere_forming as case  # noqa: E402


def watched(cells: int, speed: float, target: float | None, every: int, at: list[float],
            folder: Path) -> dict:  # fmt: skip
    """``scaling.measure`` of one run with its progress printed and its states saved."""
    step = explicit.explicit_step
    duration = case.DURATION / speed
    todo = sorted(at)
    count = [0]
    start = time.perf_counter(), time.process_time()

    def kept(model, state, dt, masses, **options):
        count[0] += 1
        while todo and state.time >= todo[0] * duration * (1.0 - 1e-9):
            name = folder / f"hemisphere_{cells}_{todo.pop(0):g}.pkl"
            with open(name, "wb") as file:
                pickle.dump(
                    {"state": state, "mass": masses.mass, "inertia": masses.inertia, "dt": dt},
                    file,
                )
        if count[0] % every == 0:
            print(f"  step {count[0]}: {state.time / duration:.4f} of the stroke, dt {dt:.4g} s, "
                  f"{time.process_time() - start[1]:.0f} s CPU, "
                  f"{time.perf_counter() - start[0]:.0f} s wall, load "
                  f"{os.getloadavg()[0]:.1f}", flush=True)  # fmt: skip
        return step(model, state, dt, masses, **options)

    explicit.explicit_step = kept
    try:
        return scaling.measure(cells, target, speed)
    finally:
        explicit.explicit_step = step


def pace(cells: int, fraction: float, steps: int, folder: Path) -> None:
    """``steps`` steps from the saved state at ``fraction`` of the unscaled stroke, as the
    solver takes them, timed by phase (module docstring); printed with the load."""
    saved = pickle.loads((folder / f"hemisphere_{cells}_{fraction:g}.pkl").read_bytes())
    compiled = case.model(cells, "fibrous", rim=case.DIE_RIM)[1].compile()
    solver = CentralDifference(duration=case.DURATION, damping=case.DAMPING, progress=False)
    state, mass, inertia = saved["state"], saved["mass"], saved["inertia"]
    dt = previous = saved["dt"]
    # A first pass unmeasured (the kernels' loading, the tools' lists), then the timed one.
    for timed in (False, True):
        phases = Phases(compiled) if timed else None
        before = load()
        wall, cpu, own = time.perf_counter(), time.process_time(), time.thread_time()
        now, masses = state, LumpedMasses(mass, inertia)
        for step in range(steps if timed else 20):
            if step % explicit.STABLE_DT_EVERY == 0:
                inertia_now = np.maximum(masses.inertia, compiled.lumped_mass(now)[1])
                masses = LumpedMasses(mass, inertia_now)
                fresh = step % explicit.ASSEMBLED_DT_EVERY == 0
                dt = solver._step_size(compiled, now, None, mass, inertia_now if fresh else None,
                                       step, previous)  # fmt: skip
            outcome = explicit.explicit_step(
                compiled, now, dt, masses, dt_prev=previous, damping=case.DAMPING,
                duration=case.DURATION, checking=step % explicit.BALANCE_EVERY == 0,
            )  # fmt: skip
            now, previous = compiled.commit(outcome.state), dt
        wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
        own = time.thread_time() - own
        if phases is None:
            continue
        reference = best(lambda: np.linalg.norm(state.positions, axis=1), 20)
        print(f"{cells} cells from {fraction:g} of the stroke, {steps} steps on "
              f"{numba.get_num_threads()} threads (load {before} -> {load()}): "
              f"{wall / steps * 1e3:.2f} ms wall, {cpu / steps * 1e3:.2f} ms CPU, "
              f"{own / steps * 1e3:.2f} ms on the main thread a step; dt {dt:.4g} s; reference "
              f"pass {reference * 1e3:.3f} ms",
              flush=True)  # fmt: skip
        print(phases.report(wall, cpu, own, steps), flush=True)
        phases.undo()


def compare(cells: int, unscaled: Path, scaled: Path, fractions: list[float]) -> None:
    """The scaled run's states against the unscaled run's at the same fractions of the stroke
    (module docstring), printed a line each."""
    from validation.forming_measures import corner_draw_in, edge_draw_in

    mesh, built = case.model(cells, "fibrous", rim=case.DIE_RIM)
    compiled = built.compile()
    punch = compiled.interactions[1]  # the die, the punch, the holder
    cells_compared = case.compared_cells(mesh)
    edge = np.flatnonzero(
        np.isclose(mesh.points[:, 0], case.HALF) & np.isclose(mesh.points[:, 1], 0.0)
    )
    n = mesh.n_nodes
    for fraction in fractions:
        name = f"hemisphere_{cells}_{fraction:g}.pkl"
        if not ((unscaled / name).exists() and (scaled / name).exists()):
            continue
        figures = []
        shears = []
        for folder in (unscaled, scaled):
            saved = pickle.loads((folder / name).read_bytes())
            state, mass = saved["state"], saved["mass"]
            x = state.positions[:n]
            shears.append(case.blank_shear(mesh, x))
            force = -float(punch.contact_forces(state).sum(axis=0)[2])  # on the punch, +z
            kinetic = 0.5 * float(np.sum(mass[:n, None] * state.velocities[:n] ** 2))
            figures.append(
                (
                    float(case.HALF - np.linalg.norm(x[edge, :2], axis=1).mean()),
                    edge_draw_in(mesh.points, x, case.HALF),
                    corner_draw_in(mesh.points, x, case.HALF),
                    force,
                    kinetic,
                    state.time,
                )
            )
        difference = np.degrees(shears[1] - shears[0])[cells_compared]
        (a, b) = figures
        print(f"{cells} cells at {fraction:g} of the stroke (t {a[5]:.4g} / {b[5]:.4g} s): shear "
              f"scaled - unscaled rms {np.sqrt(np.mean(difference**2)):.3f} deg, largest "
              f"{np.abs(difference).max():.2f} deg (rms shear unscaled "
              f"{np.degrees(np.sqrt(np.mean(shears[0][cells_compared] ** 2))):.2f} deg); "
              f"draw-in edge middle {a[0]:.2f} / {b[0]:.2f} mm, edges' mean {a[1]:.2f} / "
              f"{b[1]:.2f}, corners {a[2]:.2f} / {b[2]:.2f}; punch force {a[3]:.2f} / "
              f"{b[3]:.2f} N; kinetic energy {a[4]:.4g} / {b[4]:.4g} N mm (unscaled / scaled)",
              flush=True)  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cells", type=int, default=100)
    parser.add_argument("--time-scaling", type=float, default=1.0)
    parser.add_argument("--mass-scaling-dt", type=float, default=None)
    parser.add_argument("--every", type=int, default=2000, help="steps between progress lines")
    parser.add_argument("--at", default="", help="fractions of the stroke whose states are saved")
    parser.add_argument("--states", default="/tmp", help="where the states are saved")
    parser.add_argument("--pace", default="", help="saved fractions to time steps from")
    parser.add_argument("--steps", type=int, default=300, help="steps timed by --pace")
    parser.add_argument("--threads", default="1", help="thread counts for --pace, a list")
    parser.add_argument("--compare", default="", help="a scaled run's states folder")
    parser.add_argument(
        "--short-lists",
        default="on",
        help='the die\'s short lists for --pace, a list of "on" and "off" (SHORT_LISTS)',
    )
    args = parser.parse_args()
    folder = Path(args.states)
    if args.compare:
        fractions = [float(f) for f in (args.at or "0.1,0.25,0.5,0.75,0.9").split(",")]
        compare(args.cells, folder, Path(args.compare), fractions)
        return
    if args.pace:
        jit.FOLLOW_LOAD = False
        settings = [w.strip() == "on" for w in args.short_lists.split(",")]
        for threads in (int(t) for t in args.threads.split(",")):
            numba.set_num_threads(threads)
            for fraction in (float(f) for f in args.pace.split(",")):
                for short in settings:
                    surfaces.SHORT_LISTS = short
                    print(f"the die's short lists {'on' if short else 'off'}:", flush=True)
                    pace(args.cells, fraction, args.steps, folder)
        return
    folder.mkdir(parents=True, exist_ok=True)
    at = [float(f) for f in args.at.split(",") if f.strip()]
    start = time.process_time()
    out = watched(args.cells, args.time_scaling, args.mass_scaling_dt, args.every, at, folder)
    result, info = out["result"], out["result"].info
    print(f"{args.cells} cells, time x{args.time_scaling:g}, mass_scaling_dt "
          f"{args.mass_scaling_dt}: converged {result.converged}, {result.steps} steps, dt "
          f"{info['dt']:.4g} s at the end, added mass {info['added_mass_ratio']:.3g}; rms "
          f"{out['rms_deg']:.3f} deg, draw-in {out['draw_in_mm']:.2f} mm (edges' mean "
          f"{out['edge_draw_in_mm']:.2f}, corners {out['corner_draw_in_mm']:.2f}), punch "
          f"{out['punch_force_N']:.1f} N (last fifth {out['late_punch_force_N']:.2f}), KE/W "
          f"largest {out['largest_kinetic_over_work']:.4f} at end "
          f"{out['kinetic_over_work']:.4f}, share above the bound "
          f"{out['kinetic_exceeded_share']:.3f}, damping/W {out['damping_over_work']:.3f}, "
          f"holder lift {out['holder_lift_mm']:.3f} mm; penetration (die, punch, holder) "
          f"{', '.join(f'{p:.4f}' for p in out['penetration_mm'])} mm; the assembled bound "
          f"evaluated {out['assembled_evaluations']} times; CPU "
          f"{time.process_time() - start:.0f} s, wall {out['cost']['wall_s']:.0f} s, load "
          f"{out['cost']['load'][0]:.1f} -> {out['cost']['load'][1]:.1f}", flush=True)  # fmt: skip


if __name__ == "__main__":
    main()
