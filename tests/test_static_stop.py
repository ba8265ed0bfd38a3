"""What a Static run that stops keeps: the last good state, with the support reactions that
hold it, and the Newton iterations spent reaching it."""

import pytest

from solvers import ConvergenceError, Static
from validation.specimens import mindlin_strip

LENGTH, WIDTH, THICKNESS, DENSITY = 100.0, 10.0, 1.0, 1e-9  # mm, mm, mm, t/mm^3


def _stopped_half_way():
    """A Mindlin strip clamped at x = 0 under gravity 1e5 mm/s^2, in one increment of at
    most 3 Newton iterations and one cut: the whole increment fails, its first half
    converges, the second half fails, and the run stops at load factor 0.5 (measured) with
    no frame of the increment written yet. Returns (the error, the strip's weight, N).
    Each curved step takes its whole second-order correction (correction="whole"): with
    the share fitted (the default) both halves converge within the 3 iterations and the
    run does not stop; at 1.2e5 mm/s^2 and above the first half fails as well (measured)."""
    gravity = 1e5
    mesh, model = mindlin_strip(LENGTH, WIDTH, THICKNESS, 1e4, cells=8)
    model.gravity((0.0, 0.0, -gravity))
    weight = DENSITY * LENGTH * WIDTH * THICKNESS * gravity
    with pytest.raises(ConvergenceError, match="stopped at load factor 0.5") as stop:
        Static(
            increments=1, max_iterations=3, max_cuts=1, correction="whole", progress=False
        ).solve(model)
    return stop.value, weight


def test_a_stop_part_way_through_an_increment_keeps_the_reactions_of_the_last_good_state():
    # Statics: the clamp holds lambda x the weight. The kept state is a converged one, so its
    # reactions balance the load to Static's residual tolerance (1e-8 of the force scale);
    # 1e-6 relative leaves room for the rounding of the sum over the clamped nodes.
    error, weight = _stopped_half_way()
    last = error.result.frames[-1]
    assert error.result.info["load_factors"] == []  # the increment had no frame of its own
    assert last.load_factor == error.load_factor == 0.5
    assert last.positions[:, 2].min() < 0.0  # it sags
    assert last.reactions[:, 2].sum() == pytest.approx(0.5 * weight, rel=1e-6)
    assert last.reactions[:, :2].sum(axis=0) == pytest.approx([0.0, 0.0], abs=1e-9 * weight)


def test_a_stop_part_way_through_an_increment_counts_the_iterations_that_reached_it():
    # The converged first half took between 1 and max_iterations = 3 Newton iterations; the
    # failed attempts are counted apart, in info["iterations_cut"].
    error, _ = _stopped_half_way()
    assert 1 <= error.result.steps <= 3
    assert (
        error.result.info["iterations_cut"] >= 2
    )  # two failed attempts, one iteration or more each
