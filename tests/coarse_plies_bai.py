"""The coarse plies-bai-5.1 stack (12 cells, 4 Mindlin plies, 10 increments per phase) solved
with the case's solver less some of its rules, once per run of the suite: the run with the
stall rule and without the first-turn limit is the rule-on side of tests/test_static_stall.py
and the limit-off side of tests/test_static_first_turn.py, the same options to the last key,
so the first of the two tests to ask solves it and the other reads it back (tests/run_once.py;
the two may run in different pytest-xdist workers)."""

from fibreshell.plies import plies_solver, ply_stack, stack_model
from validation.cases import plies_bai_5_1
from validation.ground_truth import _case


def solve(once_per_run, stall_iterations: bool, first_turn: bool) -> dict:
    """The coarse stack solved with the case's ``stall_iterations`` (25) and ``first_turn``
    (0.1 rad) each kept (True) or taken out (False): the Newton iterations spent ``spent``
    (converged and cut), ``first_turn_cuts`` and the plies' final ``positions`` (n, 3) mm."""

    def compute(_out):
        solver = {
            **plies_bai_5_1.PLIES_SOLVER,
            "increments": plies_bai_5_1.PLIES_INCREMENTS["coarse"],
        }
        for key, kept in (("stall_iterations", stall_iterations), ("first_turn", first_turn)):
            if not kept:
                del solver[key]
        case = _case(plies_bai_5_1.FILE, plies_bai_5_1.CELLS["coarse"], {"solver": solver})
        stack = ply_stack(case, plies_bai_5_1.PLIES["coarse"])
        result = plies_solver(case, progress=False).solve(stack_model(case, stack))
        return {
            "spent": result.steps + result.info["iterations_cut"],
            "first_turn_cuts": result.info.get("first_turn_cuts"),
            "positions": result.positions,
        }

    name = f"coarse-plies-bai-stall-{stall_iterations}-first-turn-{first_turn}"
    return once_per_run(name, compute)[1]
