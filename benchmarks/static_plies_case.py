"""The Static ply cases of the report, set up one way for the benchmarks of their Newton
iterations (benchmarks/static_plies_newton.py and its siblings static_plies_iterates.py,
static_plies_tangent_check.py, static_plies_deck_start.py, static_plies_active_set.py, and
the scripts that solve the same plies: measured_shrink.py, band_columns.py, ply_*.py):
``solve_case`` solves a case's plies with its own solver or with one of its rules changed;
``command`` reads the options the scripts share and prints the machine's load.

bai: plies-bai-5.1's stack (validation/cases/plies_bai_5_1.py); heavy: plies-heavy-cantilever's;
deck and sag: plies-deck-of-cards' deck at its largest N on 20 cells and its heavy stack of the
fewest plies.
"""

from __future__ import annotations

import argparse
import functools
import os
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

from solvers import Static  # noqa: E402

#: What the scripts record of a solve: ``solve_case`` the last stack and case (the material
#: lines of ``--active-set``), static_plies_iterates.py's ``instrument`` the attempts.
RECORD: dict = {}


def machine_load() -> list[float]:
    """The machine's load averages over 1, 5 and 15 minutes, to 0.01."""
    return np.round(os.getloadavg(), 2).tolist()


def command(
    description: str | None,
    *options: Callable[[argparse.ArgumentParser], None],
    case: bool = True,
    rounds: bool = False,
) -> argparse.Namespace:
    """The command line of a script on the ply cases: ``--case`` and ``--resolution`` (with
    ``case``), ``--rounds`` (with ``rounds``), then the options each of ``options`` adds to
    the parser; the machine's load printed before the script's work."""
    parser = argparse.ArgumentParser(description=(description or "").split("\n\n")[0])
    if case:
        parser.add_argument("--case", default="bai", help="bai, heavy, deck or sag")
        parser.add_argument("--resolution", default="coarse")
    if rounds:
        parser.add_argument(
            "--rounds", type=int, default=1, help="solve both sides this many times, alternately"
        )
    for add in options:
        add(parser)
    args = parser.parse_args()
    print(f"load before (1, 5, 15 min): {machine_load()}")
    return args


def solve_case(
    name: str,
    resolution: str,
    stall: int | None | str = "case",
    first_turn: float | None | str = "case",
    update_turn: float | None | str = "case",
    curved: bool | None = None,
    increments: int | None = None,
    static_law: str = "ramp",
    plies: int | None = None,
):
    """Solve the Static plies of case ``name`` at ``resolution`` with
    ``Static(stall_iterations=stall, first_turn=first_turn, update_turn=update_turn,
    curved_with_contact=curved)`` (each ``"case"`` by default, and ``curved`` None: the
    case's own, the run the report makes; None for stall, first_turn or update_turn: the rule
    off; bai sets stall 25 and first_turn 0.1, heavy neither, neither sets update_turn, the
    deck curves its steps) and, for the deck, ``increments`` (None: the case's); the
    result."""
    if name in ("bai", "heavy"):
        from fibreshell.plies import plies_solver, ply_stack, stack_model
        from validation.cases import plies_bai_5_1, plies_heavy_cantilever
        from validation.ground_truth import _case

        case_module: Any = plies_bai_5_1 if name == "bai" else plies_heavy_cantilever
        solver = dict(case_module.PLIES_SOLVER)
        if name == "bai":
            solver["increments"] = case_module.PLIES_INCREMENTS[resolution]
        for key, value in (
            ("stall_iterations", stall),
            ("first_turn", first_turn),
            ("update_turn", update_turn),
        ):
            if value != "case":
                solver[key] = value
        if curved is not None:
            solver["curved_with_contact"] = curved
        for key in ("stall_iterations", "first_turn", "update_turn"):
            if solver.get(key, 0) is None:
                del solver[key]
        case = _case(case_module.FILE, case_module.CELLS[resolution], {"solver": solver})
        count = case_module.PLIES[resolution] if plies is None else plies
        stack = ply_stack(case, count, static_law=static_law)
        RECORD["stack"], RECORD["case"] = stack, case  # the material lines of ``--active-set``
        model = stack_model(case, stack).compile()
        return plies_solver(case, progress=False).solve(model)
    from validation.cases import plies_deck_of_cards as deck

    options = {
        key: value
        for key, value in (
            ("stall_iterations", stall),
            ("first_turn", first_turn),
            ("update_turn", update_turn),
        )
        if value != "case"
    }
    deck.Static = functools.partial(Static, **options)  # type: ignore[attr-defined]
    if update_turn != "case":
        deck.SAG_UPDATE_TURN = update_turn  # type: ignore[assignment]
    if curved is not None:
        deck.DECK_CURVED = curved
    if increments is not None:
        deck.DECK_INCREMENTS = increments
    if name == "deck":
        return deck.bend(deck.COUNTS[resolution][-1], deck.MIDDLE).result
    if name == "sag":
        return deck.sag(deck.SAG_COUNTS[resolution][0]).result
    raise ValueError(f"case {name!r}: expected bai, heavy, deck or sag")
