"""An increment of dynamic relaxation whose relaxed state is not valid, relaxed again in halves
(docs/theory.md §6.4d).

Why. Dynamic relaxation puts a prescribed displacement's whole increment on its nodes at once.
A jump far past the cells next to them stretches their fibres beyond the tension law's peak
(solvers.acceptance), and the motion can settle in a state with no force because nothing is
left in it: a bias extension pulled 30 mm in one increment flew to 1e16 mm and was reported
converged; in 10 increments it gives the net's 43.62 deg and 41.0 N. The codes that relax
form-finding and forming problems (Barnes 1999; the dynamic relaxation of explicit codes, which
ramps a prescribed motion) never take such a jump in one, and Static cuts an increment that
fails. So the increment is halved where its relaxed state is no state the model is valid in
(``solvers.acceptance.invalid_state``), or where a cell lost its area on the way (the fibrous
kernels raise ZeroDivisionError): relaxed again from the last state that passed, to the middle
load factor, then the rest, up to CUTS halvings; then a DivergenceError with the cause. A run
whose increments pass is the same as before to the last bit.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np

from femcore.model import CompiledModel
from femcore.state import State
from solvers.common import DivergenceError, SolverError

__all__ = ["CUTS", "InvalidState", "more_increments", "relax_in_halves"]

#: The most halvings of one increment (its smallest part 1/2^CUTS of it).
CUTS = 8


class InvalidState(Exception):
    """A relaxed state the model is not valid in; ``iterations`` it took."""

    def __init__(self, reason: str, iterations: int):
        super().__init__(reason)
        self.iterations = iterations


def relax_in_halves(
    relax: Callable[[State, float], tuple[State, int, float, Any, Any]],
    state: State,
    start: float,
    target: float,
    increment: int,
    ramps: bool = True,
) -> tuple[tuple[State, int, float, Any, Any], int]:
    """Relax from ``state`` (at load factor ``start``) to ``target``, halving what is left
    where a relaxation fails.

    Parameters
    ----------
    relax : callable (state, load factor) -> (state, iterations, ratio, reactions (n, 3),
        reaction moments (n, 3))
        One relaxation to equilibrium; raises InvalidState or ZeroDivisionError where it
        fails.
    state : State
        The last accepted state, at ``start``.
    start, target : float
        Load factors.
    increment : int
        The increment's number (for the message).
    ramps : bool
        Whether some load or prescribed displacement ramps with the load factor
        (``more_increments``); where none does, a part of the increment is the same problem
        as the whole, and the first failure is the DivergenceError.

    Returns
    -------
    (relax's tuple at ``target``, its iterations the sum over the parts), number of halvings
    (the parts left after a success are tried whole again, so a run of them may take more
    than CUTS halvings in all; no part is shorter than 1/2^CUTS of the increment)

    Raises
    ------
    DivergenceError
        After CUTS halvings of a part that still fails: the cause, the load factor reached;
        ``steps`` the iterations spent, ``cuts`` the halvings made.
    SolverError
        Any other stop of ``relax`` (ConvergenceError, Interrupted ...), its ``steps`` with
        the earlier parts' iterations added and ``cuts`` the halvings made.
    """
    spent = cuts = 0
    reached, aims = start, [target]
    while True:
        aim = aims[-1]
        try:
            out = relax(replace(state, load_factor=aim, time=aim), aim)
        except SolverError as error:
            # a later part that stops (max_iterations, a stall, an interrupt): the earlier
            # parts' iterations and the halvings count in the run's steps and cuts too
            error.steps += spent
            error.cuts = cuts
            raise
        except (InvalidState, ZeroDivisionError) as error:
            spent += getattr(error, "iterations", 0)
            cause = (
                "a cell lost its area in the motion" if isinstance(error, ZeroDivisionError)
                else f"the relaxed state is not valid: {error}"
            )  # fmt: skip
            if not ramps or (aim - reached) <= (target - start) / 2**CUTS:
                parts = (
                    f", even in parts of 1/{2**CUTS:d} of the increment from load factor "
                    f"{reached:.4g}" if ramps
                    else " (nothing in the model ramps with the load factor: its loads are "
                    "'step' loads, so halving the increment changes nothing)"
                )  # fmt: skip
                stop = DivergenceError(
                    f"dynamic relaxation failed in increment {increment} at load factor "
                    f"{aim:.4g} ({cause}){parts}: a load or motion the model cannot follow "
                    "(its equilibrium left the laws' range), or one that needs a path: try "
                    f"Static{', or more increments' if ramps else ''}",
                    None,
                    steps=spent,
                )
                stop.cuts = cuts
                raise stop from (error if isinstance(error, ZeroDivisionError) else None)
            cuts += 1
            aims.append(0.5 * (reached + aim))
            continue
        state, iterations = out[0], out[1]
        spent += iterations
        reached = aims.pop()
        if not aims:
            return (state, spent, *out[2:]), cuts


def more_increments(model: CompiledModel) -> str:
    """ "use more increments, " where more increments would make each one's change smaller:
    some load, prescribed displacement or tool motion of ``model`` ramps with the load factor
    (a driven tool's force is a load on its node); "" where none does (gravity and other
    "step" loads go in full from the first increment of a relaxation, docs/theory.md §6.4: a
    strip over a cylinder under its weight alone was told to use more increments, and
    increment 1 carried the whole weight at any count)."""
    full = _driven(model, 1.0)
    ramps = any(
        not all(np.array_equal(a, b) for a, b in zip(_driven(model, probe), full))
        for probe in _PROBES
    )
    return "use more increments, " if ramps else ""


#: The load factors compared with 1 (an amplitude may hold its value over part of the run:
#: a pull reached at 0.5 and held reads the same at 0.5 and 1).
_PROBES = (0.25, 0.5, 0.75)


def _driven(model: CompiledModel, load_factor: float) -> list[np.ndarray]:
    """What drives ``model`` at ``load_factor``: its loads (a driven tool's force among them,
    a load on its node), its prescribed displacements and its tools' motions
    (InteractionBlock.tool_displacements, the body where it starts)."""
    driven = list(model.external_load(load_factor, quasi_static=True))
    if model.has_prescribed:
        driven.append(model.prescribed_displacement(load_factor, quasi_static=True))
    if model.interactions:
        # a pressed strip's plane lifted 5 mm read "nothing in the model ramps"
        at = replace(model.initial_state(), load_factor=load_factor, time=load_factor)
        driven.append(model.tool_displacements(at))
    return driven
