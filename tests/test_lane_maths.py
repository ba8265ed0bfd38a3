"""The branch-free log and arcsine of elements/lane_maths.py against numpy's (the C library's)
over their whole domain: random values across every binade, near 1 and near 0, and the edges
(0, -0, the smallest subnormal, the largest float, inf, nan, negative values); the bound in
units in the last place of numpy's value is the module's claim (1 for the log, 2 for the
arcsine: fdlibm's error below 1, the arcsine's simpler reduction above 0.5 one more; 2 for
the arctangent of two values: the rounding of |y| / |x| and fdlibm's atan's own)."""

from __future__ import annotations

import numpy as np
import pytest

numba = pytest.importorskip("numba")

from elements.lane_maths import lane_arcsin, lane_arctan2, lane_log  # noqa: E402


@numba.njit
def _logs(x, out):
    for i in range(x.shape[0]):
        out[i] = lane_log(x[i])


@numba.njit
def _arcsines(x, out):
    for i in range(x.shape[0]):
        out[i] = lane_arcsin(x[i])


@numba.njit(error_model="numpy")  # lane_arctan2 is spliced: its division unchecked here too
def _arctangents(y, x, out):
    for i in range(x.shape[0]):
        out[i] = lane_arctan2(y[i], x[i])


def _ulps(value: np.ndarray, reference: np.ndarray) -> np.ndarray:
    """|value - reference| in units in the last place of the reference; 0 where both are the
    same (infinities included) or both nan, inf where only one is nan."""
    same = (value == reference) | (np.isnan(value) & np.isnan(reference))
    with np.errstate(invalid="ignore"):
        ulps = np.abs(value - reference) / np.spacing(np.abs(reference))
    ulps = np.where(np.isnan(ulps), np.inf, ulps)
    return np.where(same, 0.0, ulps)


def _evaluated(loop, x: np.ndarray) -> np.ndarray:
    out = np.empty_like(x)
    loop(x, out)
    return out


def test_the_log_is_within_one_ulp_of_numpys_over_its_whole_domain():
    rng = np.random.default_rng(3)
    x = np.concatenate([
        10.0 ** rng.uniform(-323.0, 308.0, 400_000),  # every binade, subnormals included
        rng.uniform(0.3, 3.0, 400_000),  # stretches squared
        1.0 + rng.uniform(-1e-6, 1e-6, 100_000),  # near 1, where log x ~ x - 1
        [5e-324, 2.2250738585072014e-308, 2.225073858507201e-308, np.sqrt(2.0),
         np.nextafter(np.sqrt(2.0), 0.0), np.sqrt(0.5), 0.5, 1.0, 2.0, np.e,
         1.7976931348623157e308],
    ])  # fmt: skip
    value = _evaluated(_logs, x)
    assert np.max(_ulps(value, np.log(x))) <= 1.0
    assert value[x == 1.0].tolist() == [0.0]  # exactly


def test_the_log_of_zero_negatives_infinity_and_nan_is_numpys():
    x = np.array([0.0, -0.0, -1.0, -5e-324, -np.inf, np.inf, np.nan])
    with np.errstate(divide="ignore", invalid="ignore"):
        reference = np.log(x)
    value = _evaluated(_logs, x)
    assert np.array_equal(value, reference, equal_nan=True)


def test_the_arcsine_is_within_two_ulps_of_numpys_over_its_whole_domain():
    rng = np.random.default_rng(4)
    x = np.concatenate([
        rng.uniform(-1.0, 1.0, 400_000),
        rng.uniform(-0.6, 0.6, 400_000),  # shear angles' sines, and both sides of 0.5
        10.0 ** rng.uniform(-323.0, 0.0, 100_000) * rng.choice([-1.0, 1.0], 100_000),
        1.0 - 10.0 ** rng.uniform(-16.0, -1.0, 100_000),  # near 1, where asin x ~ pi/2
        [0.5, -0.5, np.nextafter(0.5, 0.0), 0.975, 1.0, -1.0, 5e-324, -5e-324],
    ])  # fmt: skip
    value = _evaluated(_arcsines, x)
    assert np.max(_ulps(value, np.arcsin(x))) <= 2.0
    assert value[np.abs(x) == 1.0].tolist() == np.arcsin(x[np.abs(x) == 1.0]).tolist()


def test_the_arcsine_keeps_the_sign_of_zero_and_is_nan_beyond_one():
    x = np.array([0.0, -0.0, 1.0000000000000002, -1.5, np.inf, -np.inf, np.nan])
    with np.errstate(invalid="ignore"):
        reference = np.arcsin(x)
    value = _evaluated(_arcsines, x)
    assert np.array_equal(value, reference, equal_nan=True)
    assert np.array_equal(np.signbit(value[:2]), [False, True])


def test_the_arctangent_of_two_is_within_two_ulps_of_numpys_over_its_whole_domain():
    rng = np.random.default_rng(5)
    n = 300_000
    signs = rng.choice([-1.0, 1.0], (2, n))
    y = np.concatenate([
        rng.normal(size=n),
        signs[0] * 10.0 ** rng.uniform(-320.0, 308.0, n),  # every binade of y / x
        rng.uniform(0.0, 1.0, n),  # a corner's |c| against its cosine times |c|
    ])  # fmt: skip
    x = np.concatenate([
        rng.normal(size=n),
        signs[1] * 10.0 ** rng.uniform(-320.0, 308.0, n),
        rng.uniform(-1.0, 1.0, n),
    ])  # fmt: skip
    value = np.empty_like(x)
    _arctangents(y, x, value)
    assert np.max(_ulps(value, np.arctan2(y, x))) <= 2.0


def test_the_arctangent_of_two_is_numpys_at_zeros_infinities_and_nan():
    edges = np.array([0.0, -0.0, np.inf, -np.inf, np.nan, 1.0, -1.0, 5e-324, -5e-324])
    y, x = (a.ravel() for a in np.meshgrid(edges, edges))
    value = np.empty_like(x)
    _arctangents(y, x, value)
    reference = np.arctan2(y, x)
    assert np.array_equal(value, reference, equal_nan=True)
    number = ~np.isnan(reference)  # the signed zeros and infinities' quadrants (a nan's sign
    # bit is no part of its value)
    assert np.array_equal(np.signbit(value[number]), np.signbit(reference[number]))


def test_the_functions_run_with_numbas_jit_switched_off():
    """NUMBA_DISABLE_JIT=1 (a kernel debugged in Python) must still give the log and the
    arcsine: the bit casts fall back to ``struct`` (an intrinsic cannot run in Python). Run in
    a fresh interpreter, since numba reads the switch once, at import; checked against numpy
    within the module's ulp bounds on a few values."""
    import os
    import subprocess
    import sys

    script = (
        "import numpy as np\n"
        "from elements.lane_maths import lane_arcsin, lane_log\n"
        "xs = [1e-300, 0.3, 1.0, 2.5, 1e300]\n"
        "ulp = lambda v, r: abs(v - r) / np.spacing(abs(r) or 1.0)\n"
        "print(max(ulp(lane_log(x), np.log(x)) for x in xs))\n"
        "ss = [-1.0, -0.6, 0.1, 0.49, 0.97]\n"
        "print(max(ulp(lane_arcsin(s), np.arcsin(s)) for s in ss))\n"
    )
    env = dict(os.environ, NUMBA_DISABLE_JIT="1")
    done = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, env=env, timeout=300
    )
    assert done.returncode == 0, done.stderr[-2000:]
    log_ulps, arcsin_ulps = (float(line) for line in done.stdout.split())
    assert log_ulps <= 1.0
    assert arcsin_ulps <= 2.0
