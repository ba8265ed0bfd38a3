"""An increment started with soft ply contacts (``Static(ply_penalty_start=share)``;
docs/theory.md §6.5, "The deck's last increment").

Newton first converges the increment with the penalties of the interactions that take a soft
start (``InteractionBlock.softened_penalty``: the frictionless ply contacts,
elements/ply_block.py) times ``share``, then goes on from that equilibrium with the full
penalties, to the equilibrium of the full law: the result is that of the plain increment
within Newton's tolerance, and only the path to it changes. Where the plies need almost no
contact force (plies-deck-of-cards' decks), the full penalty makes the plies' gap mode, their
bending alone, some 1e7 times softer than the contact, and Newton halves the gaps towards
the smoothed ramp's double root for tens of iterations; with a soft penalty the equilibrium
gap lies further from that root, and the full penalty's equilibrium is then a few
iterations away. Frictional ply contacts keep their penalty (their stick anchors and return
mapping hold the penalty's history), and so does every other interaction.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import ExitStack, contextmanager
from typing import TYPE_CHECKING

from solvers.newton import IncrementFailed, newton

if TYPE_CHECKING:
    from femcore.compiled import CompiledModel
    from femcore.state import State
    from solvers.static import StaticRun

__all__ = ["newton_with_soft_start", "softened", "stability_unsought", "then_whole"]


@contextmanager
def softened(model: CompiledModel, share: float) -> Iterator[bool]:
    """The interactions of ``model`` that take a soft start (the frictionless ply contacts)
    with their penalties times ``share`` inside the block, restored after it, even on an
    error (each block's ``softened_penalty``); yields whether there is one."""
    with ExitStack() as stack:
        soft = [stack.enter_context(part.softened_penalty(share)) for part in model.interactions]
        yield any(soft)


@contextmanager
def stability_unsought(run: StaticRun) -> Iterator[None]:
    """The solver's ``seek_stable`` off inside the block: the soft law's equilibrium is a
    way-point whose stability says nothing of the full law's (its tangent may be indefinite
    where the full one is not); mode searches, pushes and kept saddles there would cost
    solves and mark the run for the full phase."""
    solver = run.solver
    kept = solver.seek_stable
    solver.seek_stable = False
    try:
        yield
    finally:
        solver.seek_stable = kept


def newton_with_soft_start(
    run: StaticRun,
    state: State,
    load_factor: float,
    share: float | None,
    turn_limit: float | None = None,
):
    """solvers.newton.newton at ``load_factor`` from ``state``, first with the frictionless
    ply contacts' penalties times ``share`` (None: not), then with the full ones from the
    state it converged to (module docstring): (converged state, the iterations of both,
    final ratio, the ratios of both). IncrementFailed counts both attempts' iterations."""
    if share is None:
        return newton(run, state, load_factor, turn_limit=turn_limit)
    with softened(run.model, share) as soft:
        if not soft:
            return newton(run, state, load_factor, turn_limit=turn_limit)
        with stability_unsought(run):
            start, count, _, history = newton(run, state, load_factor, turn_limit=turn_limit)
    run.info["soft_start_iterations"] += count
    return then_whole(run, start, load_factor, count, history)


def then_whole(run: StaticRun, start: State, load_factor: float, count: int, history: list):
    """Newton's second phase from ``start``, the first phase's converged state under a
    changed law (the soft penalty here, stiff stick springs in solvers/stick_start.py), with
    the model's own laws: the increment's (state, iterations, ratio, ratios), the first
    phase's ``count`` iterations and ratios ``history`` counted in, also in a failure's."""
    try:
        converged, more, ratio, rest = newton(run, start, load_factor)
    except IncrementFailed as failure:
        failure.iterations += count
        raise
    return converged, count + more, ratio, history + rest
