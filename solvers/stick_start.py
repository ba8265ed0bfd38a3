"""An increment that failed, tried again with stiff stick springs first (docs/theory.md §9.3a,
"Friction from plies laid on each other").

A frictional ply contact's stick spring is the normal law's W''(g) (elements/ply_friction.py),
0 at zero penetration: plies laid on each other and not yet pressed hold nothing tangentially
at Newton's first iterate, so a ply held by friction alone and pressed and pulled in one
increment is free in its plane there and runs off. Before the increment is cut, Newton
converges it once more with every interaction's stick spring that vanishes with the normal
force held at the penalty (``InteractionBlock.stiff_stick``), then goes on from that
equilibrium with the interactions' own laws, to their equilibrium: the result is the plain
increment's within Newton's tolerance (the anchors of the increment's start are the same in
both), only the path to it changes. An increment that converges at the first try is not
touched (the same bits).
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import ExitStack, contextmanager
from typing import TYPE_CHECKING

from solvers.common import IncrementFailed
from solvers.newton import newton
from solvers.penalty_start import stability_unsought, then_whole

if TYPE_CHECKING:
    from femcore.compiled import CompiledModel
    from femcore.state import State
    from solvers.static import StaticRun

__all__ = ["newton_with_stick_start", "stiffened"]


@contextmanager
def stiffened(model: CompiledModel) -> Iterator[bool]:
    """The interactions of ``model`` with a stick spring that vanishes with the normal force,
    held at the penalty inside the block and restored after it, even on an error (each
    block's ``stiff_stick``); yields whether there is one."""
    with ExitStack() as stack:
        stiff = [stack.enter_context(part.stiff_stick()) for part in model.interactions]
        yield any(stiff)


def newton_with_stick_start(run: StaticRun, state: State, load_factor: float):
    """solvers.newton.newton at ``load_factor`` from ``state``, first with the stiff stick
    springs, then with the interactions' own laws from the state it converged to (module
    docstring): (converged state, the iterations of both, final ratio, the ratios of both).
    IncrementFailed where there is no stick spring to stiffen (0 iterations) or either
    attempt fails (their iterations)."""
    with stiffened(run.model) as stiff:
        if not stiff:
            raise IncrementFailed("no stick spring to stiffen")
        with stability_unsought(run):
            start, count, _, history = newton(run, state, load_factor)
    run.info["stick_start_iterations"] = run.info.get("stick_start_iterations", 0) + count
    return then_whole(run, start, load_factor, count, history)
