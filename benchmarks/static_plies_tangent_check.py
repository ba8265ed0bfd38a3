"""The tangent of a Static ply solve against central differences, with no timing
(benchmarks/static_plies_newton.py ``--tangent-check``, or this script alone): the case
solved once with its own solver; on the last increment's iterates (with ``--check-load L
--every k`` on every k-th iterate of the attempt that converged at load factor L) each
part's tangent against central differences of its forces, and the whole residual's
directional derivative against -K v.

    python benchmarks/static_plies_tangent_check.py [--case bai|heavy|deck|sag]
        [--resolution coarse|default] [--check-load 1.8] [--every 15]

The options below are benchmarks/static_plies_newton.py's (``--tangent-check``); this script
takes the same without it.

The deck's linear tail (``--case deck --tangent-check``; 4 plies, 20 cells, its last
increment, 92 tangents; one thread):

* The tangent is the derivative of the forces there. Each part's own tangent against central
  differences of its forces at the iterates 0, 15, ..., 90: the four Mindlin plies within
  3.5e-10 of the largest entry (step 1e-6 of the median edge, the solver's) and 6.5e-7 (step
  1e-9, round-off); the three ply contacts within 1.7e-6 at the step 1e-9 (5e-9 mm), but
  0.4-0.65 at the step 1e-6 (5e-6 mm): their points sit within a few 1e-7 mm of g = 0, where
  W'' = -k g / delta changes by k / delta = 3e6 N/mm^2 per mm (k = 750 N/mm, delta = 2.5e-4
  mm), so a 5e-6 mm step is not small there. The whole residual (the frames re-evaluated at
  each side, as the iteration does) along a random free direction against -K v: within 3.3e-7
  (step 1e-7; 1.2e-5 at 1e-5) at the same iterates; the moments' components along the directors
  (left out of the 5-DOF equations) at most 2.4e-8 N mm. The deck is frictionless, clamped
  (no support, no tool): nothing else enters its tangent.
* The cause is the root: the exact deck needs no contact force, so its equilibrium puts
  contact points at g = 0, where the ramp's force k g^2 / (2 delta) and stiffness -k g / delta
  both vanish (a double root). There Newton halves g each iteration and quarters the
  residual: runs of ratios 1.7e-2, 4.2e-3, 1.0e-3, 2.6e-4 and 8.2e-3, 2.1e-3, 5.1e-4, 1.3e-4
  (a factor 3.9-4.1 an iteration). Each run is broken when 3-5 points off contact (g > 0, no
  stiffness, so the linear step does not see them) are carried to g = -5e-6 to -1e-5 mm in
  one step: the ratio jumps back to 1e-2 (iterations 29, 34, 36, 38, 40, 45, 50, 56, 61, 67,
  72, 77 of the increment's 92; its first 21 iterates at ratio 0.34-1.0, the 12th with
  points 0.18 mm deep); 19 of each interface's 40 points have |g| < delta, 55 of 120
  touch at the 4th iterate and 9 at the last, each carrying at most 1e-6 N. Not a tangent that
  differs from the derivative, so nothing local mends it: the law's degenerate root at
  zero-force contact (the smoothed penalty, docs/theory.md §9.3a) sets the rate.


The second phase's increments (plies-bai-5.1, the case's solver: ``--first-turn 0.1
--tangent-check --check-load 1.8``; ``--resolution default`` for the default stack; one thread;
the counts and the iterates: benchmarks/static_plies_iterates.py, "The second phase's
increments"):

* The tangent is the forces' derivative at every iterate. Coarse, load 1.8, all 10 iterates: the
  Mindlin plies within 3.6e-10 of the largest entry (central differences, 1e-6 of the median
  edge), the three ply contacts within 2.0e-8, the whole residual along a random free direction
  within 5.9e-9 (step 1e-5); default, load 1.8, iterates 0, 3, ..., 18: the plies 3.5e-10, the
  contacts 4.2e-8 but one at the 6th iterate 4.3e-4 (7.9e-7 at the step 1e-9: a point within the
  step of an end of the ramp, where the law's third derivative jumps by k / delta), the whole
  residual 1.3e-8. No term is missing where points step on or off (none changes its facing
  triangle).
"""

from __future__ import annotations

import argparse
import functools
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install

import solvers.static as static_module  # noqa: E402
from benchmarks.static_plies_case import command, solve_case  # noqa: E402
from elements.ply_block import PlyContactBlock  # noqa: E402


def tangent_check(name: str, resolution: str, every: int = 15, load: float | None = None) -> None:
    """The tangent against central differences on the last increment's iterates of case
    ``name`` (or, with ``load``, those of the converged attempt at that load factor; module
    docstring): per part, the
    largest difference between its own tangent and central differences of its forces (the
    solver's step, 1e-6 of the median element edge, and 1e-9), over the largest entry; per
    ply contact, its points with |g| < delta, those touching, its force; and the whole
    residual's directional derivative (the frames re-evaluated at each side, as the Newton
    iteration does) along a random unit direction against -K v."""
    from femcore.assembly import finite_difference_tangent
    from solvers.newton import Residual

    captured: list = []
    plain = static_module.StaticRun.tangent

    def keep(self, state, frames, compression_free=False, real=None):
        captured.append((self, state, frames))
        return plain(self, state, frames, compression_free, real)

    static_module.StaticRun.tangent = keep  # type: ignore[method-assign]
    try:
        solve_case(name, resolution)  # the case's own solver
    finally:
        static_module.StaticRun.tangent = plain  # type: ignore[method-assign]
    if load is None:
        load = captured[-1][1].load_factor
    at = [abs(entry[1].load_factor - load) < 1e-9 for entry in captured]
    if not any(at):
        raise ValueError(f"no increment at load factor {load}: expected one the solve reached")
    end = len(at) - at[::-1].index(True)  # the last attempt at that load: the converged one
    start = end
    while start > 0 and at[start - 1]:  # the trailing run of tangents at that load
        start -= 1
    last = captured[start:end]
    run = last[0][0]
    model, dofs = run.model, run.model.dofs
    free = dofs.free_slots
    equilibrium = Residual(model, *run.solver.loads(model, last[0][1].load_factor))
    direction = np.zeros(dofs.n_slots)  # free slots alone: the fixed ones stay where they are
    direction[free] = np.random.default_rng(0).standard_normal(free.size)
    direction /= np.linalg.norm(direction)
    print(f"last increment: {len(last)} tangents")
    for n in range(0, len(last), every):
        _, state, frames = last[n]
        print(f"iterate {n}")
        for index, part in enumerate(model.parts):
            own = model.stiffness(state, "element", frames, [index])[free][:, free].toarray()
            graph = model.node_graph([index])
            line = f"  {index} {type(part).__name__}:"
            for relative in (1e-6, 1e-9):
                central = finite_difference_tangent(
                    dofs,
                    functools.partial(model.internal_force, parts=[index]),
                    state,
                    graph,
                    step=relative * model.element_size,
                    frames=frames,
                )[free][:, free].toarray()
                scale = max(np.abs(central).max(), 1e-300)
                line += (
                    f" |K - K_cd({relative:g})| / max|K| {np.abs(own - central).max() / scale:.1e}"
                )
            if isinstance(part, PlyContactBlock):
                gap = np.asarray(part.facing(state).gap)
                force = np.linalg.norm(model.internal_force(state, [index])[0])
                line += (
                    f"; |g| < delta {int(np.sum(np.abs(gap) < part.smoothing))}, touching "
                    f"{int(np.sum(gap < 0.0))} of {gap.size}, |F| {force:.1e} N"
                )
            print(line)
        stiffness = model.stiffness(state, "element", frames)[free][:, free]
        step = np.zeros((model.n_nodes, 5))
        for h in (1e-5, 1e-7):
            sides = []
            for sign in (1.0, -1.0):
                step.ravel()[:] = sign * h * direction
                moved = dofs.advance(state, step, frames)
                r = equilibrium.residual(moved, dofs.frames(moved.directors))[0]
                sides.append(r.ravel()[free])
            derivative = (sides[0] - sides[1]) / (2.0 * h)
            predicted = -(stiffness @ direction[free])
            error = np.linalg.norm(derivative - predicted) / np.linalg.norm(predicted)
            print(
                f"  residual along a random direction, step {h:g}: |dR + K v| / |K v| {error:.1e}"
            )


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The check's options: the converged increment and the iterates' spacing."""
    parser.add_argument(
        "--check-load",
        type=float,
        default=None,
        help="the increment converged at this load factor (default the last)",
    )
    parser.add_argument("--every", type=int, default=15, help="every this many iterates")


def run(args: argparse.Namespace) -> None:
    """The check on the case and the iterates ``args`` name."""
    tangent_check(args.case, args.resolution, args.every, args.check_load)


if __name__ == "__main__":
    run(command(__doc__, add_arguments))
