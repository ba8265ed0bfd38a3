"""solvers.newton_curvature: the curved step takes the share of its second-order correction at
which the residual is least along it (``Static(correction="fitted")``, the default), so that
the first update of an increment no longer overshoots into a compressed, indefinite iterate."""

from types import SimpleNamespace

import numpy as np
import pytest

from solvers import Static
from solvers.newton_curvature import LEAST_SCALE, correction_scale
from validation.references.elastica import tip_loaded_cantilever
from validation.specimens import mindlin_strip


def _linear_residual(target: np.ndarray):
    """A stand-in for solvers.newton.Residual whose residual at the step d is d - target:
    ||r(delta + a w)||^2 is then exactly a parabola in a, with its least at
    a* = -(delta - target) . w / (w . w)."""
    dofs = SimpleNamespace(advance=lambda state, step, frames: step)
    return SimpleNamespace(
        model=SimpleNamespace(dofs=dofs),
        residual=lambda step, frames: (step - target, 0.0, None),
    )


@pytest.mark.parametrize(("least", "expected"), [(0.6, 0.6), (0.1, 0.25), (1.7, 1.0)])
def test_the_share_is_the_least_of_the_residual_within_its_bounds(least, expected):
    # delta = 0, w = 1 in one unknown, the target at a*: the fit through a = 0, 1/2, 1 is the
    # parabola itself, its vertex a* clipped to [LEAST_SCALE, 1].
    assert LEAST_SCALE == 0.25
    delta, correction = np.zeros((1, 5)), np.zeros((1, 5))
    correction[0, 0] = 1.0
    target = least * correction
    share = correction_scale(_linear_residual(target), None, None, delta, correction)
    assert share == pytest.approx(expected, abs=1e-12)


def test_a_residual_that_is_not_finite_keeps_the_whole_correction():
    delta, correction = np.zeros((1, 5)), np.ones((1, 5))
    target = np.full((1, 5), np.nan)
    assert correction_scale(_linear_residual(target), None, None, delta, correction) == 1.0


def _elastica():
    """The mindlin-elastica case: a 100 x 5 x 1 mm strip of 20 cells, P L^2 / EI = 3."""
    length, bending = 100.0, 1e5 * 5.0 / 12.0
    mesh, model = mindlin_strip(length, 5.0, 1.0, 1e5, cells=20)
    tip = mesh.nodes("right")
    model.force(tip, (0.0, 0.0, -3.0 * bending / length**2 / len(tip)))
    drop = tip_loaded_cantilever(length, 3.0 * bending / length**2, bending)["tip_deflection"]
    return model, tip, drop


def test_the_elastica_takes_four_iterations_an_increment_and_meets_no_indefinite_iterate():
    # With the whole correction the first update of every increment compressed the strip
    # (1-14 negative pivots on the cantilevers: a mode search each) and the increments took
    # 4-6-5-4-4 Newton iterations; with the share the residual asks for, 4-4-4-4-4 and no
    # negative pivot on the way. The tip within the case's 1 % of the elastica (Bisshopp &
    # Drucker 1945) and within 1e-6 of the drop of the whole corrections (both converge to the
    # residual ratio 1e-8).
    model, tip, drop = _elastica()
    compiled = model.compile()
    result = Static(increments=5, progress=False).solve(compiled)
    assert max(result.info["iterations_per_increment"]) <= 4
    assert result.info["mode_searches"] == 0
    assert -result.displacements[tip, 2].mean() == pytest.approx(drop, rel=1e-2)
    whole = Static(increments=5, correction="whole", progress=False).solve(compiled)
    assert max(whole.info["iterations_per_increment"]) > 4
    assert whole.info["mode_searches"] > 0
    assert result.positions == pytest.approx(whole.positions, abs=1e-6 * drop)


@pytest.mark.parametrize("bad", ["half", "Fitted", None, 0.5])
def test_a_correction_that_is_not_fitted_or_whole_is_refused(bad):
    with pytest.raises(ValueError, match=r"correction must be one of \('fitted', 'whole'\)"):
        Static(correction=bad)
