"""Speed of an explicit forming run: the hemisphere forming case of the validation report
(validation/cases/hemisphere_forming.py) with a blank of about 20k triangles.

The blank (200 x 200 mm, fibrous shell, ``--cells`` squares along a side, two triangles each)
is pressed by the rigid spherical punch into the meshed die (elements.RigidSurface) over
``--duration`` s of simulated time. Printed: the pieces of one step on the starting state (the
element's force, the contact blocks' forces, a reference pass over the same nodes: one norm
per node), then per run (``--mass-scaling-dt``, a list: "none" for the model's own masses) the
wall and CPU time, the machine's load before and after (/proc/loadavg: the machine may be
shared), the threads (elements/jit.py), the steps, ms per step and its ratio to the
reference pass, the step size, the mass scaling asked and the mass it added, and the kinetic
energy at the end over the work done (a quasi-static run keeps it small). ``--fraction`` stops
each run at that fraction of the stroke's time (its figures: those of the steps done).

Measured on 2 cores shared with other work (load 5-15, so CPU time; the default threads chose
one), the first fifth of the stroke at 20k triangles, 7230 steps: 52.8 ms CPU per step before
the meshed tool searched again only the nodes that moved, the assembled stable step built its
tangent once and waited for the cells' bound to move, and the threads stopped spinning; 34.5
ms after (977 x the reference pass). With ``--mass-scaling-dt 5e-6`` (1.72 times the model's
mass added, the starting step 4.56e-6 s instead of 2.77e-6 s): 4384 steps, 35.0 ms each.

``--phases`` times the pieces of the steps (CPU and wall per step): the element force
passes, the contacts (the meshed die's closest-facet search inside), the cells' and the
assembled stable step, the lumped masses (the rotary inertia refresh every 10 steps), the rest
(the update, the output, the bookkeeping); and each run prints its mean step and the whole
stroke projected at that pace. Measured at 20k triangles on the first 1 % of the stroke (1281
steps of 2.34e-6 s; one thread, the default at a load of 1.7-5 on the 2 cores; two threads
forced, elements.jit.FOLLOW_LOAD = False, gave the same wall time at a load of 4.5): 17-22 ms
CPU per step, of which the element force 6.8-9.9 ms (42 %), the contacts 5.7-7.5 (33 %), the
assembled stable step 2.6-3.7 (one evaluation of 3.5-4 s at the start over these steps; it comes
again every 4000 steps or when the cells' bound moves by 1 %), the cells' bound 0.2, the rotary
inertia refresh 0.15-0.2 (0.9 %), the rest 0.9-1.1 (the same code measured 10-20 % apart from
one run to the next: other work shared the cores). The stroke, 128k steps at that pace: 37-48
min CPU on one thread. With ``--mass-scaling-dt 5e-6`` (1.72 x the mass added, mean step 4.56e-6
s): 65.7k steps, 17 min CPU projected.

The closest-facet search of the die, timed apart on the nodes it was asked about every 200
steps of the first 2 % of the stroke (10201 nodes, 82.6k candidate facets, best of 40, the
three interleaved): 3.54 ms CPU a pass before, 2.30 with the corners read as scalars, 1.55 with
the candidates further than the node's facet of the last step skipped (elements/facet_search.py;
the same points, facets and distances to the last bit). The punch's contact forces asked again
for its work in the same step: 0.43 ms computed, 0.085 from the contact's memory. Together
about 2.4 ms CPU per step of the 17-22 (the whole-run figures above do not resolve it).

Run from the project root:

    python benchmarks/hemisphere_forming.py                       # 100 x 100 x 2 = 20k
    python benchmarks/hemisphere_forming.py --mass-scaling-dt none,3.5e-6
    python benchmarks/hemisphere_forming.py --cells 40 --duration 0.05
    python benchmarks/hemisphere_forming.py --fraction 0.2        # the first fifth of it
    python benchmarks/hemisphere_forming.py --fraction 0.01 --phases  # where a step goes
"""

from __future__ import annotations

import argparse
import itertools
import os
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install
os.environ.setdefault("FIBRESHELL_PROGRESS", "0")

from contact_search import best  # noqa: E402

from elements import jit  # noqa: E402
from solvers import CentralDifference  # noqa: E402
from validation.cases import hemisphere_forming as case  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cells", type=int, default=100)
    parser.add_argument("--duration", type=float, default=case.DURATION)
    parser.add_argument(
        "--mass-scaling-dt", default="none", help='target steps, s, a list ("none": no scaling)'
    )
    parser.add_argument("--safety", type=float, default=0.9, help="the solver's default 0.9")
    parser.add_argument(
        "--fraction", type=float, default=1.0, help="stop at this fraction of the stroke's time"
    )
    parser.add_argument(
        "--phases", action="store_true", help="time the pieces of each step (CPU and wall)"
    )
    args = parser.parse_args()
    mesh, model = case.model(args.cells, "fibrous")
    compiled = model.compile()
    print(f"blank: {mesh.n_triangles} triangles, {mesh.n_nodes} nodes; punch travel "
          f"{case.PUNCH + case.THICKNESS} mm in {args.duration} s")  # fmt: skip

    # The pieces of one step, timed on the reference state: the element, the contacts, a
    # reference pass.
    state = compiled.initial_state()
    shell = list(range(len(compiled.blocks)))  # compiled.parts: the blocks, then the contacts
    contact_blocks = list(range(len(compiled.blocks), len(compiled.parts)))

    compiled.internal_force(state)  # compiles the kernels and fills the tools' caches
    element = best(lambda: compiled.internal_force(state, shell), 20)
    # Two states in turn: the meshed tool answers the same points asked again from memory.
    nudged = replace(state, positions=state.positions + 1e-6)
    turns = itertools.cycle([state, nudged])
    contact = best(lambda: compiled.internal_force(next(turns), contact_blocks), 20)
    reference = best(lambda: np.linalg.norm(state.positions, axis=1), 20)
    n = mesh.n_nodes
    print(f"per step: element force {element * 1e3:.2f} ms ({element / mesh.n_triangles * 1e6:.3f} "
          f"us/triangle), contact forces of {len(contact_blocks)} tools {contact * 1e3:.2f} ms "
          f"({contact / n / len(contact_blocks) * 1e6:.3f} us per node and tool), reference pass "
          f"{reference * 1e3:.3f} ms")  # fmt: skip

    threads = jit.threads_for(mesh.n_triangles)
    # The steps, counted where the solver accepts each (a run stopped early has no result).
    steps = [0]
    reached = [0.0]  # the time of the last step accepted, s
    commit = compiled.commit

    def counted(new_state):
        steps[0] += 1
        reached[0] = new_state.time
        return commit(new_state)

    compiled.commit = counted  # type: ignore[method-assign]

    def stop_early(frame) -> dict:
        if frame.time >= args.fraction * args.duration * (1.0 - 1e-9):
            raise _Enough
        return {}

    for target in args.mass_scaling_dt.split(","):
        scaling = None if target.strip().lower() == "none" else float(target)
        solver = CentralDifference(
            duration=args.duration,
            safety=args.safety,
            damping=case.DAMPING,
            mass_scaling_dt=scaling,
            progress=False,
            # --fraction is looked at on each frame: a frame at least every 1 % and at it.
            output_interval=args.duration * min(0.01, args.fraction)
            if args.fraction < 1.0
            else None,
            frame_summary=stop_early if args.fraction < 1.0 else None,
        )
        load_before = load()
        steps[0] = 0
        phases = Phases(compiled) if args.phases else None
        start, cpu = time.perf_counter(), time.process_time()
        try:
            result = solver.solve(compiled)
        except _Enough:
            result = None
        wall, cpu = time.perf_counter() - start, time.process_time() - cpu
        per_step = wall / steps[0]
        print(f"run, mass scaling {scaling}, {args.fraction:g} of the stroke: {wall:.1f} s wall, "
              f"{cpu:.1f} s CPU on {threads} threads (load {load_before} -> {load()}), "
              f"{steps[0]} steps, {per_step * 1e3:.2f} ms per step ({cpu / steps[0] * 1e3:.2f} "
              f"ms CPU; {per_step / reference:.0f} x the reference pass)", flush=True)  # fmt: skip
        stroke = args.duration / (reached[0] / steps[0])  # steps at the mean step so far
        print(f"  mean step {reached[0] / steps[0]:.3g} s: the stroke at this pace {stroke:.0f} "
              f"steps, {stroke * cpu / steps[0] / 60:.1f} min CPU, {stroke * per_step / 60:.1f} "
              "min wall", flush=True)  # fmt: skip
        if phases is not None:
            print(phases.report(wall, cpu, steps[0]), flush=True)
            phases.undo()
        if result is not None:
            energies = {key: values[-1] for key, values in result.energies.items()}
            ratio = energies["kinetic"] / max(abs(energies["external_work"]), 1e-300)
            print(f"  dt {result.info['dt']:.3g} s at the end, added mass "
                  f"{result.info['added_mass_ratio']:.3g} x the model's, kinetic / work at the "
                  f"end {ratio:.3f}, punch force {result.tool_forces[-1, 1, 2]:.3g} N, "
                  f"converged {result.converged}", flush=True)  # fmt: skip


class _Enough(Exception):
    """Raised to stop a run at ``--fraction`` of its stroke."""


class Phases:
    """CPU and wall time spent in the pieces of the steps, by wrapping (on the instances)
    the element blocks' force passes, the contact blocks' (the closest-facet search inside),
    the cells' and the assembled stable step and the lumped masses (the rotary inertia
    refresh); the rest of a step is the solver's own update and bookkeeping."""

    def __init__(self, compiled) -> None:
        self.spent: dict[str, list[float]] = {}
        self.wrapped: list[tuple[object, str]] = []
        # Each evaluation of the assembled bound: (time, the bound, the cells' bound), s.
        self.assembled: list[tuple[float, float, float]] = []
        evaluate, cells = compiled.assembled_stable_dt, compiled.cell_stable_dt

        def logged(state, mass, inertia):
            value = evaluate(state, mass, inertia)
            cell = min(float(dt.min()) for dt in cells(state))
            self.assembled.append((state.time, value, cell))
            return value

        object.__setattr__(compiled, "assembled_stable_dt", logged)  # timed below, undone once
        for block in compiled.blocks:
            for name in ("internal_force", "internal_force_and_energy"):
                self._wrap(block, name, "element force")
        for interaction in compiled.interactions:
            for name in ("internal_force", "strain_energy", "tool_work"):
                self._wrap(interaction, name, "contact")
        self._wrap(compiled, "cell_stable_dt", "stable step (cells)")
        self._wrap(compiled, "assembled_stable_dt", "stable step (assembled)")
        self._wrap(compiled, "lumped_mass", "rotary inertia refresh")

    def _wrap(self, owner, name: str, phase: str) -> None:
        method = getattr(owner, name, None)
        if method is None:
            return
        totals = self.spent.setdefault(phase, [0.0, 0.0])

        def timed(*args, **kwargs):
            wall, cpu = time.perf_counter(), time.process_time()
            try:
                return method(*args, **kwargs)
            finally:
                totals[0] += time.perf_counter() - wall
                totals[1] += time.process_time() - cpu

        object.__setattr__(owner, name, timed)
        self.wrapped.append((owner, name))

    def undo(self) -> None:
        for owner, name in self.wrapped:
            object.__delattr__(owner, name)

    def report(self, wall: float, cpu: float, steps: int) -> str:
        rest = [wall - sum(w for w, _ in self.spent.values()),
                cpu - sum(c for _, c in self.spent.values())]  # fmt: skip
        rows = [*self.spent.items(), ("update, output, bookkeeping", rest)]
        lines = [
            f"  {phase:28s} {w / steps * 1e3:7.3f} ms wall {c / steps * 1e3:7.3f} ms CPU per step "
            f"({c / max(cpu, 1e-300):5.1%} of the CPU)"
            for phase, (w, c) in rows
        ]
        ratios = ", ".join(f"{t:.3g} s: {a / c:.3f}" for t, a, c in self.assembled)
        lines.append(
            f"  the assembled bound evaluated {len(self.assembled)} times; its ratio to the "
            f"cells' bound then: {ratios}"
        )
        return "\n".join(lines)


def load() -> str:
    """The 1-minute load average (/proc/loadavg), '?' where there is none."""
    try:
        return Path("/proc/loadavg").read_text().split(" ")[0]
    except OSError:
        return "?"


if __name__ == "__main__":
    main()
