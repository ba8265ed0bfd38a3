"""The order of Static's Newton iterations near equilibrium (docs/theory.md §6.5): with a
consistent tangent the residual ratio r of the last iterations falls as r_k+1 ~ r_k^2, i.e.
log(r_k+1) / log(r_k) near 2; a tangent that is off by a fraction (a missing geometric term, a
spin term left out) converges linearly, r_k+1 ~ c r_k, whose order from r_k = 1e-2 with
c = 0.1 is 1.5 and tends to 1 as r_k falls.

The order is read from the last step of each increment (``closing_order``), where Newton's
quadratic region is: the first updates of an increment carry the load step's remainder (the
ratio near 1), and on the Mindlin strips the curved step's fitted correction
(solvers.newton_curvature) leaves the second iterate at a ratio of 3e-4 to 3e-3, from which the
next step still meets the third-order remainder of the path (orders 1.04-1.6 measured on the
elastica) before the last one falls quadratically (1.67-3.67). A linearly converging
iteration cannot pass this measure: its last step starts at r_k <= tol / c (1e-7 with the
tolerance 1e-8 and c = 0.1), and of the steps from r_k >= START (1e-6) none shows an order
above 1 + log(c) / log(r_k) <= 1.17. The last step's end, r_k+1, may lie on the round-off floor
of the internal forces, which only raises it: such a step's order understates Newton's, never
fakes it; from r_k >= START a quadratic step landing on a floor of 1e-9 to 1e-8 still shows
1.33-1.5 at the least (1.68-1.79 measured), and steps from below START are passed over for the
one before.
"""

import dataclasses
import math

import numpy as np
import pytest

from materials import BendingLaw
from materials.presets import g986_stack
from solvers import Static
from validation import specimens
from validation.references.elastica import peirce_overhang

# The order the last step of each increment must reach: above a linear iteration's (c = 0.1:
# 1.5 from 1e-2, lower below), below the 1.67-3.67 measured on these strips.
LEAST_ORDER = 1.55
# The round-off floor of the strips' internal forces lies at ratios of 3e-9 to 9e-9
# (benchmarks/newton_iterations.py): a step from below START ends there before its order can
# show; one from START or above may end there (module docstring).
START = 1e-6


def closing_order(history: list[float]) -> float | None:
    """log(r_k+1) / log(r_k) of the last decreasing step of a residual-ratio history that
    starts at START <= r_k <= 0.1 (module docstring); None where there is none."""
    orders = [
        math.log(after) / math.log(before)
        for before, after in zip(history[:-1], history[1:])
        if START <= before <= 0.1 and after < before
    ]
    return orders[-1] if orders else None


def _elastica():
    """The mindlin-elastica case: 100 x 5 x 1 mm, 20 cells, P L^2 / EI = 3."""
    length, width, young = 100.0, 5.0, 1e5
    mesh, model = specimens.mindlin_strip(length, width, 1.0, young, cells=20)
    tip = mesh.nodes("right")
    model.force(tip, (0.0, 0.0, -3.0 * young * width / 12 / length**2 / len(tip)))
    return model


def _rollup():
    """The mindlin-rollup case: 100 x 10 x 1 mm, 20 cells, a quarter circle."""
    length, width, young = 100.0, 10.0, 1e5
    mesh, model = specimens.mindlin_strip(length, width, 1.0, young, cells=20)
    tip = mesh.nodes("right")
    moment = 0.5 * math.pi * young * width / 12 / length
    model.moment(tip, (0.0, -moment / len(tip), 0.0), amplitude="linear")
    return model


@pytest.mark.parametrize(
    ("build", "increments"), [(_elastica, 5), (_rollup, 4)], ids=["elastica", "rollup"]
)
def test_the_mindlin_strips_converge_quadratically(build, increments):
    # Measured: elastica 1.73-3.67, roll-up 1.68-1.76 (the last steps end on the round-off
    # floor: module docstring); with correction="whole" 1.83-5.04 and 1.72-2.65.
    result = Static(increments=increments, progress=False).solve(build())
    orders = [closing_order(h) for h in result.info["residual_history"]]
    assert None not in orders, result.info["residual_history"]
    assert min(orders) >= LEAST_ORDER, (orders, result.info["residual_history"])


def test_the_fibrous_strip_converges_quadratically_with_a_linear_bending_law():
    # Peirce's G986 strip (20 x 1 cells, 3 increments) with its bilinear bending law replaced
    # by the initial slope, 7.5 N mm: the fibrous tangent (tension, shear, rotation-free
    # bending, the clamped edge) is exact, the last steps quadratic (1.96, 2.33, 2.55 measured)
    # and 3-4-4 iterations. With the bilinear law the soft branch's deflection per increment
    # takes 9-9-10 (benchmarks/newton_iterations.py).
    fabric = g986_stack()
    overhang = peirce_overhang(fabric.areal_density * specimens.GRAVITY, fabric.bending)
    stiff = dataclasses.replace(fabric, bending=BendingLaw.linear(7.5))
    mesh, model = specimens.fibrous_strip(overhang["overhang"], 10.0, stiff, 20)
    # The plain Newton steps (no level-strain projection, solvers.newton_levels): with it
    # the strip takes 3-3-3 iterations, and its last increment reaches 3.3e-3 from 0.11,
    # outside the small region where Newton is quadratic on this strip (docs/theory.md §6.5;
    # the next step rises to 7.6e-3, the one after takes it to 1.4e-8).
    result = Static(increments=3, progress=False, level_projection=False).solve(model)
    orders = [closing_order(h) for h in result.info["residual_history"]]
    assert None not in orders, result.info["residual_history"]
    assert min(orders) >= LEAST_ORDER, (orders, result.info["residual_history"])
    assert max(result.info["iterations_per_increment"]) <= 4
    # The strip bends as the small-deflection cantilever under its own weight to a tenth:
    # q L^4 / (8 B) per unit width (B = 7.5 N mm per mm of width).
    load = fabric.areal_density * specimens.GRAVITY  # N/mm^2
    length = overhang["overhang"]
    drop = -result.displacements[mesh.nodes("right"), 2].mean()
    assert drop == pytest.approx(load * length**4 / (8.0 * 7.5), rel=0.1)


def test_a_linearly_converging_history_fails_the_order():
    # The measure itself: a quadratic history passes, a linear one (c = 0.1, converged to the
    # tolerance 1e-8 from 1e-2) does not, and neither does one whose ratio stopped falling.
    quadratic = [1.0, 1e-2, 1e-4, 1e-8]
    linear = list(1e-2 * 0.1 ** np.arange(7))
    assert closing_order(quadratic) >= LEAST_ORDER
    assert closing_order(linear) < LEAST_ORDER
    assert closing_order([1.0, 0.9, 0.95]) is None


def test_the_closing_order_reads_the_last_step_clear_of_the_floor():
    # A slow step before the last does not count (the elastica's first increment with the
    # fitted correction: 2.7e-3 -> 5.1e-3 -> 3.8e-9); a last step that starts below START
    # is passed over for the one before it (the roll-up's 1.1e-8 -> 1.6e-10).
    assert closing_order([1.0, 1.0, 2.7e-3, 5.1e-3, 3.8e-9]) == pytest.approx(
        math.log(3.8e-9) / math.log(5.1e-3)
    )
    assert closing_order([1.0, 2.7e-2, 3.0e-5, 1.1e-8, 1.6e-10]) == pytest.approx(
        math.log(1.1e-8) / math.log(3.0e-5)
    )
