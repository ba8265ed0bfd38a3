"""The ply contact's smoothed penalty law compiled (elements/ply_penalty.py) gives numpy's
``penalty_law`` (elements/ply_projection.py, ``COMPILED = False``) to the last bit: the
energy, its slope and its curvature, on the ramp, deeper, at its ends, off contact, at
signed zeros and NaN."""

import numpy as np
import pytest

from elements import ply_penalty, ply_projection
from elements.ply_projection import penalty_law


@pytest.fixture
def numpy_law():
    def law(gap, stiffness, smoothing):
        ply_projection.COMPILED = False
        try:
            return penalty_law(gap, stiffness, smoothing)
        finally:
            ply_projection.COMPILED = True

    return law


def gaps(delta: float, count: int = 20000) -> np.ndarray:
    """Gaps over the ramp, deeper and off contact, with its ends, signed zeros and NaN."""
    rng = np.random.default_rng(7)
    special = [0.0, -0.0, -delta, np.nextafter(-delta, 0.0), np.nextafter(-delta, -1.0),
               -0.5 * delta, 1e-300, -1e-300, np.nan, -np.inf, np.inf]  # fmt: skip
    spread = rng.normal(-delta, 3.0 * delta, count)
    return np.concatenate([special, spread, spread * 1e-6])


@pytest.mark.parametrize("delta", [0.015, 1.0 / 3.0, 2.5e-4])
def test_the_compiled_law_gives_numpys_bits(numpy_law, delta):
    gap = gaps(delta)
    rng = np.random.default_rng(11)
    stiffness = rng.uniform(0.1, 500.0, len(gap))
    compiled = penalty_law(gap, stiffness, delta)
    reference = numpy_law(gap, stiffness, delta)
    for got, expected in zip(compiled, reference):
        assert got.dtype == expected.dtype and got.shape == expected.shape
        # bitwise: signed zeros and NaN included
        np.testing.assert_array_equal(got.view(np.int64), expected.view(np.int64))


def test_the_compiled_path_is_the_one_taken(monkeypatch):
    """penalty_law with ``COMPILED`` and a smoothing takes elements/ply_penalty.py's pass."""
    calls = []
    original = ply_penalty.smoothed_law

    def counted(*args):
        calls.append(args)
        return original(*args)

    monkeypatch.setattr(ply_penalty, "smoothed_law", counted)
    gap, stiffness = np.array([-0.1, -0.001, 0.2]), np.array([10.0, 20.0, 30.0])
    energy, force, curvature = penalty_law(gap, stiffness, 0.015)
    assert len(calls) == 1
    # deeper than the ramp: W' = k (g + delta/2), W'' = k; off contact: 0
    assert force[0] == 10.0 * (-0.1 + 0.0075) and curvature[0] == 10.0
    assert energy[2] == force[2] == curvature[2] == 0.0


def test_without_smoothing_or_of_other_shapes_numpy_answers(numpy_law):
    gap = np.array([-0.1, 0.0, 0.3])
    for smoothing, stiffness in ((0.0, np.array([1.0, 2.0, 3.0])), (0.015, 5.0)):
        for got, expected in zip(
            penalty_law(gap, stiffness, smoothing), numpy_law(gap, stiffness, smoothing)
        ):
            np.testing.assert_array_equal(got, expected)


@pytest.mark.parametrize("delta", [0.015, 2.5e-4])
def test_the_ramp_cubes_are_numpys_cubes_of_the_whole_array_where_the_ramp_reads_them(delta):
    """``ramp_cubes`` takes numpy's power on the points of the ramp alone (g > -delta, NaN
    included): there each cube has the bits numpy gives it within the whole array, whatever
    the other points; past the ramp 0 (unread)."""
    g = np.minimum(gaps(delta), 0.0)
    whole = g**3
    cube = ply_penalty.ramp_cubes(g, delta)
    ramp = ~(g <= -delta)
    assert ramp.sum() > 1000 and (~ramp).sum() > 1000
    np.testing.assert_array_equal(cube[ramp].view(np.int64), whole[ramp].view(np.int64))
    assert np.all(cube[~ramp] == 0.0)
    # without smoothing the law reads no cube
    assert np.all(ply_penalty.ramp_cubes(g, 0.0) == 0.0)
