"""What the data of a fit determine (fibreshell/identifiability.py, docs/theory.md §10.2),
on residuals in closed form whose Jacobian's null space and standard errors are known: the
central-difference Jacobians at h and 2 h are taken of the closed forms as identify takes
them of the model's runs (h = 1e-3, identify's step)."""

import numpy as np
import pytest

from fibreshell.identifiability import combination_text, determinacy, reduced_combinations
from fibreshell.identify import Identification, format_result

STEP = 1e-3
X = np.linspace(0.0, 1.0, 12)


def _central(model, p, width):
    return np.column_stack(
        [(model(p + width * e) - model(p - width * e)) / (2.0 * width) for e in np.eye(len(p))]
    )


def _analysed(model, data, n):
    p = np.zeros(n)
    values = model(p)
    # identify's round-off of a difference of model values: eps |y| / h
    rounding = np.finfo(float).eps * float(np.linalg.norm(values)) / STEP
    return determinacy(
        _central(model, p, STEP), _central(model, p, 2 * STEP), values - data, n, rounding
    )


def _along_a_null_direction(p):
    # depends on p only through p2 - p3 and p1 - 0.04 (p2 + p3): (0.08, 1, 1) changes nothing
    u1, u2 = p[1] - p[2], p[0] - 0.04 * (p[1] + p[2])
    return (1.0 + X) * np.exp(0.8 * u1) + (0.5 + X**2) * np.exp(-0.6 * u2)


def _tied(p):
    # depends on p1 - p2 and on p3: the null direction (1, 1, 0)
    return (1.0 + X) * np.exp(0.8 * (p[0] - p[1])) + (0.5 + X**2) * np.exp(-0.6 * p[2])


def test_a_parameter_with_any_component_along_a_null_direction_is_not_determined():
    # Along (0.08, 1, 1) the residuals do not change at all, so theta1 can be multiplied by
    # exp(0.08 t) for any t with the same data: its interval is unbounded (Seber and Wild,
    # Nonlinear Regression, 1989, §3.4), though its share of that direction is only 0.0565
    # (the old test let a share up to 0.1 pass, and gave theta1 +-5 %).
    null = np.array([0.08, 1.0, 1.0])
    assert _along_a_null_direction(10.0 * null) == pytest.approx(
        _along_a_null_direction(np.zeros(3)), abs=1e-12
    )
    data = _along_a_null_direction(np.zeros(3)) + 0.01 * np.random.default_rng(0).normal(size=12)
    found = _analysed(_along_a_null_direction, data, 3)
    assert list(found.resolved) == [True, True, False]
    share = np.linalg.norm(found.vectors[0, ~found.resolved])
    assert share == pytest.approx(0.08 / np.linalg.norm(null), rel=1e-6)
    # the bound is the null space's error (Wedin), far below that share
    assert found.share_bound < 1e-4 < share
    assert not found.determined.any()
    assert np.isnan(found.correlation).all()
    (undetermined,) = reduced_combinations(found.vectors[:, ~found.resolved], found.share_bound)
    text, exponents = combination_text(["t1", "t2", "t3"], undetermined, found.share_bound)
    assert text == "t1^0.08 * t2^1 * t3^1" and exponents == pytest.approx(null, rel=1e-6)


def test_a_well_determined_parameter_of_small_effect_is_determined_with_its_textbook_error():
    # Two linear parameters, each with its own data, the second's responses 1e4 times
    # smaller, scatter 1e-10: J = diag-blocks x and y exactly at p = 0 (d exp(p) x / dp), so
    # ordinary least squares' standard errors are s / |x| and s / |y| (Seber and Wild, 1989,
    # §2.1). The old threshold, the forward difference's error (h / 2) sigma_1 = 1.88e-3 over
    # every direction, called the second (sigma 3.77e-4) undetermined.
    x = np.linspace(1.0, 2.0, 6)
    y = 1e-4 * x

    def model(p):
        return np.concatenate([np.exp(p[0]) * x, np.exp(p[1]) * y])

    data = model(np.zeros(2)) + 1e-10 * np.random.default_rng(2).normal(size=12)
    found = _analysed(model, data, 2)
    assert found.singular_values == pytest.approx([np.linalg.norm(x), np.linalg.norm(y)], rel=1e-6)
    assert found.resolved.all() and found.determined.all()
    residual = model(np.zeros(2)) - data
    s = np.sqrt(residual @ residual / (12 - 2))
    # to the central difference's truncation, h^2 / 6 = 1.7e-7 of the slope
    assert np.sqrt(np.diag(found.covariance_p)) == pytest.approx(
        [s / np.linalg.norm(x), s / np.linalg.norm(y)], rel=1e-6
    )


def test_a_direction_the_data_s_scatter_leaves_wider_than_a_factor_10_is_not_determined():
    # r depends on p1 and, with a weight 1e-4, on p2: the Jacobian resolves both directions
    # (singular values 5.3 and 5.5e-5, each far above its error), but under a scatter of 0.01
    # the second combination's 95 % half-width t s / sigma_2 is about 2 x 0.01 / 5.5e-5 = 360
    # in ln theta: not determined, by the statistics (WIDEST).
    # Under a scatter of 1e-8 it is +-1.5e-4: determined. A stated scatter (sigma given,
    # residuals in its units: 1) bounds s from below.
    def model(p):
        return (1.0 + X) * np.exp(p[0]) + 1e-4 * (0.5 + X**2) * np.exp(p[1])

    for noise, resolved in ((1e-2, [True, False]), (1e-8, [True, True])):
        data = model(np.zeros(2)) + noise * np.random.default_rng(3).normal(size=12)
        found = _analysed(model, data, 2)
        assert found.singular_values[1] > 10.0 * found.direction_errors[1]
        assert list(found.resolved) == resolved
        assert found.determined.all() == all(resolved)
    p = np.zeros(2)
    stated = determinacy(_central(model, p, STEP), _central(model, p, 2 * STEP),
                         model(p) - data, 2, scatter=1.0)  # fmt: skip
    assert list(stated.resolved) == [True, False]


def test_tied_parameters_get_no_correlation_and_the_clean_ratio_is_named():
    # The pseudo-inverse gave t1 and t3 a correlation 0.985 where t1's variance is infinite,
    # and named the determined directions by the singular vectors' mixes
    # (t1^1 * t2^-1 * t3^-0.439); the determined span is t1 / t2 and t3.
    data = _tied(np.zeros(3)) + 0.01 * np.random.default_rng(1).normal(size=12)
    found = _analysed(_tied, data, 3)
    assert list(found.determined) == [False, False, True]
    assert np.isnan(found.correlation[:2]).all() and np.isnan(found.correlation[:, :2]).all()
    keys = ["t1", "t2", "t3"]
    tolerance = found.share_bound
    determined = reduced_combinations(found.vectors[:, found.resolved], tolerance)
    texts = [combination_text(keys, v, tolerance)[0] for v in determined]
    assert texts == ["t1^1 * t2^-1", "t3^1"]
    (null,) = reduced_combinations(found.vectors[:, ~found.resolved], tolerance)
    assert combination_text(keys, null, tolerance) == ("t1^1 * t2^1", pytest.approx([1, 1, 0]))
    # printed: no correlation row for t1 or t2 (one determined value: no matrix at all)
    result = Identification(
        keys=keys, start=np.ones(3), values=np.ones(3), standard_errors=np.full(3, np.nan),
        intervals=np.full((3, 2), np.nan), residual_rms=0.01, success=True, message="done",
        evaluations=20, runs=20, wall_time_s=1.0, responses=["z"],
        correlation=found.correlation, determined=found.determined,
        undetermined=["t1^1 * t2^1"], singular_values=found.singular_values,
        direction_errors=found.direction_errors,
    )  # fmt: skip
    printed = format_result(result)
    assert "correlation" not in printed
    assert "t1^1 * t2^1 is not determined" in printed


def test_correlations_are_printed_among_the_determined_values_alone():
    correlation = np.array([[np.nan, np.nan, np.nan], [np.nan, 1.0, 0.5], [np.nan, 0.5, 1.0]])
    result = Identification(
        keys=["a", "b", "c"], start=np.ones(3), values=np.ones(3), standard_errors=np.ones(3),
        intervals=np.ones((3, 2)), residual_rms=0.01, success=True, message="done",
        evaluations=20, runs=20, wall_time_s=1.0, responses=["z"], correlation=correlation,
        determined=np.array([False, True, True]),
    )  # fmt: skip
    printed = format_result(result).splitlines()
    at = printed.index("correlation of the values b, c (rows and columns in that order):")
    assert printed[at + 1 : at + 3] == ["  +1.0000 +0.5000", "  +0.5000 +1.0000"]


def test_a_combination_within_its_error_of_whole_exponents_is_written_so():
    assert combination_text(["B", "w"], np.array([0.7071, -0.70712]), 1e-3)[0] == "B^1 * w^-1"
    text, exponents = combination_text(["B", "w"], np.array([0.3162, -0.9487]), 1e-3)
    assert text == "B^1 * w^-3" and list(exponents) == [1.0, -3.0]
    assert combination_text(["B", "w"], np.array([0.5, -0.7]), 1e-3)[0] == "B^0.714 * w^-1"


def test_bad_jacobians_are_a_value_error():
    with pytest.raises(ValueError, match=r"expected Jacobians of shape \(m, 2\)"):
        determinacy(np.ones((3, 2)), np.ones((3, 3)), np.ones(3), 2)
    with pytest.raises(ValueError, match="rounding must be a number >= 0"):
        determinacy(np.ones((3, 2)), np.ones((3, 2)), np.ones(3), 2, -1.0)
    with pytest.raises(ValueError, match="scatter must be a number > 0 or None"):
        determinacy(np.ones((3, 2)), np.ones((3, 2)), np.ones(3), 2, scatter=0.0)
