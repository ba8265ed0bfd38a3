"""Static's stalled attempts (``Static(stall_iterations=N)``, solvers.newton.stalled): an
attempt whose residual ratio stayed above 0.1 over its last N iterations is cut at once
(docs/theory.md §6.5, "Stalled attempts")."""

import coarse_plies_bai
import numpy as np
import pytest

from solvers import ConvergenceError, Static
from solvers.newton import STALLED_RATIO, stalled
from validation.specimens import mindlin_strip


def test_an_attempt_is_stalled_only_when_its_whole_window_stayed_above_the_ratio():
    # history[0] is the ratio before the first update; the window holds the last N ratios
    high = 2.0 * STALLED_RATIO
    assert stalled([1e-9, high, high, high], 3)
    assert not stalled([1e-9, high, high, high], 4)  # the window is not full yet
    assert not stalled([1e-9, high, 0.5 * STALLED_RATIO, high], 3)
    assert not stalled([1e-9, high, high, high], None)


def _rollup():
    """The strip rolled up by an end moment to an eighth of a turn: in one increment the
    residual ratio stays near 1 for 10 iterations and falls in 3 more (14 and 4 with
    correction="whole"); in two halves, 8 iterations in all (measured)."""
    length, width, thickness, young = 100.0, 10.0, 1.0, 1e5
    mesh, model = mindlin_strip(length, width, thickness, young, cells=10)
    bending = young * width * thickness**3 / 12
    tip = mesh.nodes("right")
    model.moment(tip, (0.0, -0.25 * np.pi * bending / length / len(tip), 0.0), amplitude="linear")
    return model


def test_a_stalled_attempt_is_cut_and_says_why():
    # The rule is worth its cut where the plateau is longer than the window plus the halves'
    # iterations: a window of 3 on the plateau of 10 (3 + 8 against 13, measured; 5 + 10
    # against 18 with correction="whole").
    plain = Static(increments=1, max_cuts=0, progress=False).solve(_rollup())
    history = plain.info["residual_history"][0]
    assert min(history[1:4]) > STALLED_RATIO  # the plateau the rule is for
    with pytest.raises(ConvergenceError, match=r"stayed above 0\.1 for 3 iterations"):
        Static(increments=1, max_cuts=0, stall_iterations=3, progress=False).solve(_rollup())
    # cut in half instead: fewer iterations in all, the same equilibrium within Static's
    # tolerance
    halved = Static(increments=1, stall_iterations=3, progress=False).solve(_rollup())
    assert halved.info["cuts"] == 1
    assert halved.info["iterations_cut"] == 3  # the stalled attempt's window, no more
    assert halved.steps + halved.info["iterations_cut"] < plain.steps
    scale = np.abs(plain.positions).max()
    assert np.abs(halved.positions - plain.positions).max() <= 1e-6 * scale


@pytest.mark.slow
def test_the_coarse_bai_plies_take_fewer_iterations_for_the_same_equilibrium(once_per_run):
    # The coarse plies-bai-5.1 stack (12 cells, 4 Mindlin plies, 10 increments per phase).
    # Measured (benchmarks/static_plies_newton.py): without the rule 358 Newton iterations
    # converged and 470 in cut attempts (828), the first displacement increment's attempts
    # at ratio ~1 for up to 150 iterations; with stall_iterations=25 261 and 140 (401).
    # Bound: 500, a quarter of margin on 401 and well below the 828 of before.
    # (without the case's first_turn, which takes the first displacement increment's cut
    # attempts away: tests/test_static_first_turn.py, which reads the run with the rule)
    plain = coarse_plies_bai.solve(once_per_run, stall_iterations=False, first_turn=False)
    ruled = coarse_plies_bai.solve(once_per_run, stall_iterations=True, first_turn=False)
    spent = {None: plain["spent"], 25: ruled["spent"]}
    assert spent[25] <= 500 < spent[None], spent
    # the same equilibrium: the plies' positions to 1e-6 of the strip's 150 mm
    difference = np.abs(ruled["positions"] - plain["positions"]).max()
    assert difference <= 1.5e-4, difference
