"""Whether a load step of Static's load path jumped across a limit point (docs/theory.md §6.5,
"Load control past a limit point"): a snap-through that equal load steps pass over, landing
on a far stable branch, that no converged state reports (both ends are stable).

A step is examined only where its Newton iterates met an exact tangent with a negative pivot
between a stable start and a stable end (``StaticRun.met_indefinite``); that alone is no
jump: the iterates of a cantilever bent by a large load step pass through compressed,
indefinite states on the way to a neighbouring equilibrium of the same branch (the elastica,
Peirce's cantilever, the heavy fibrous cantilever were flagged so). The step is then solved
back: chord iterations on the end state's own tangent (factorised for its stability count)
from the end state at the start's load factor. Where they converge to a state other than the
start, the start's load factor has two equilibria, the start and one the end state leads
back to: the step left the start's branch. Where they converge to the start, or do not
converge (a chord of a strongly nonlinear step, a prescribed motion placed back at once),
nothing is reported: a report is a proof, a missed jump is possible. Measured on the cheap
tests of the 78 test files that run Static: 51 steps examined, the chords of 49 did not
converge (none of them a jump), those of the von Mises truss's snap converged on its far
branch, 0.989 of the step away from the start.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from femcore.dofs import N_COLUMNS
from femcore.state import State
from solvers.common import IncrementFailed
from solvers.newton import Residual

if TYPE_CHECKING:
    from solvers.static_run import StaticRun

__all__ = ["BACK_ITERATIONS", "BACK_RATIO", "BACK_STEP_SHARE", "jumped"]

#: Chord iterations allowed to solve a step back, and the residual ratio they must reach.
BACK_ITERATIONS = 30
BACK_RATIO = 1e-6
#: An equilibrium at the start's load factor farther from the start than this share of the
#: step's own largest nodal motion is another one.
BACK_STEP_SHARE = 0.5


def jumped(run: StaticRun, start: State, start_load: float, end: State, end_load: float) -> bool:
    """Whether the converged step from ``start`` (at ``start_load``) to ``end`` (at
    ``end_load``) left the start's branch: chord iterations back from ``end`` at
    ``start_load`` converge to an equilibrium farther from ``start`` than ``BACK_STEP_SHARE``
    of the step's largest nodal motion (positions, mm). Evaluations are not counted in the
    run's ``info["evaluations"]``."""
    model, dofs = run.model, run.model.dofs
    moved = float(np.abs(end.positions - start.positions).max(initial=0.0))
    if moved == 0.0:
        return False
    factor = run.factor_at(end, run.last_factorisation)
    force, moment, imposed = run.solver.loads(model, start_load)
    back = Residual(model, force, moment, imposed)  # its own counts, not the run's
    state = run.place(end, start_load)
    tolerance = max(run.solver.tol, BACK_RATIO)
    step = np.zeros(model.n_nodes * N_COLUMNS)
    for _ in range(BACK_ITERATIONS):
        if not (np.isfinite(state.positions).all() and np.isfinite(state.directors).all()):
            return False  # the chords diverged: no proof either way
        frames = dofs.frames(state.directors)
        try:
            r, ratio, _ = back.residual(state, frames)
        except (IncrementFailed, ValueError, FloatingPointError, ZeroDivisionError):
            # No forces at that state (a part refuses it: the ply contact a non-finite one,
            # a cell turned inside out): nothing to judge by. The run itself is unharmed.
            return False
        if not np.isfinite(ratio):
            return False
        if ratio <= tolerance:
            away = float(np.abs(state.positions - start.positions).max(initial=0.0))
            return away > BACK_STEP_SHARE * moved
        delta = factor.solve(r.ravel()[dofs.free_slots])
        if delta is None:
            return False
        step[dofs.free_slots] = delta
        state = dofs.advance(state, step.reshape(-1, N_COLUMNS), frames)
    return False
