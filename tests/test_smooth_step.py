"""femcore.loads.smooth_step: the closed form, and a scalar tau (an explicit run's, a few a
step) answered to the bit as np.clip and the formula on that scalar answer it."""

import numpy as np
import pytest

from femcore.loads import smooth_step


@pytest.mark.parametrize(
    ("tau", "exact"),
    [
        (0.5, 0.5),  # symmetric about the middle
        (0.25, 106.0 / 1024.0),  # 10/64 - 15/256 + 6/1024, exact in binary
        (0.75, 918.0 / 1024.0),  # 1 - a(0.25)
        (0.0, 0.0),
        (1.0, 1.0),
        (-0.3, 0.0),  # clipped
        (1.7, 1.0),
    ],
)
def test_closed_form(tau, exact):
    """10 tau^3 - 15 tau^4 + 6 tau^5 clipped to [0, 1] (Abaqus's SMOOTH STEP): these values
    are exact in binary, so equal to the last bit."""
    assert smooth_step(tau) == exact
    assert smooth_step(np.float64(tau)) == exact


def _clipped_formula(tau):
    """The reference: np.clip, then the formula in numpy's scalar arithmetic (an array's
    powers may differ in the last bit: numpy's vector power)."""
    tau = np.clip(tau, 0.0, 1.0)
    return tau**3 * (10.0 - 15.0 * tau + 6.0 * tau**2)


def test_scalar_same_bits_as_clipped_formula():
    """A Python float or numpy float64 tau gives a numpy float64 with the bits of the
    reference (the scalar path skips np.clip where it would return tau), at random taus,
    tiny and subnormal ones, the ends and past them, NaN."""
    rng = np.random.default_rng(7)
    taus = np.concatenate(
        [
            rng.uniform(-0.5, 1.5, 20000),
            rng.uniform(0.0, 1e-100, 200),
            [0.0, -0.0, 1.0, 5e-324, 1.0 - 2.0**-53, np.nan, np.inf, -np.inf],
        ]
    )
    for tau in taus:
        for scalar in (float(tau), np.float64(tau)):
            got, expected = smooth_step(scalar), _clipped_formula(scalar)
            assert type(got) is np.float64
            assert np.asarray(got).tobytes() == np.asarray(expected).tobytes(), scalar


def test_shapes_kept():
    """An array tau gives an array of its shape; a 0-d array a 0-d result."""
    assert smooth_step(np.zeros((2, 3))).shape == (2, 3)
    assert np.ndim(smooth_step(np.array(0.4))) == 0
