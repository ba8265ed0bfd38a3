"""validation/studies/grid_convergence.py on manufactured sequences f(h) = f0 + C h^p, whose
order, limit and error band are known in closed form (Roache 1998, ch. 5: through three meshes
of an exact power law GCI = Fs |f3 - f0|)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from validation.studies.grid_convergence import (
    SAFETY_FACTOR,
    change_orders,
    consecutive_orders,
    grid_convergence_index,
    power_fit,
)

# the two-ply hemisphere's resolutions (cells across the blank): unequal ratios
CELLS = np.array([8, 10, 12, 14, 16, 20])
SIZES = 200.0 / CELLS


def _law(p, f0=3.0, c=0.02):
    return f0 + c * SIZES**p


@pytest.mark.parametrize("p", [0.7, 1.0, 1.5, 2.0])
def test_every_triplet_of_a_power_law_has_its_order(p):
    # the orders solve (f1 - f2) / (f2 - f3) = (h1^p - h2^p) / (h2^p - h3^p) by
    # observed_order's root finding: 1e-8 is far above its tolerance, far below any use
    assert np.allclose(consecutive_orders(SIZES, _law(p)), p, rtol=0.0, atol=1e-8)


@pytest.mark.parametrize("p", [1.0, 2.0])
def test_the_index_of_a_power_law_is_the_safety_factor_times_the_finest_error(p):
    values = _law(p)
    index = grid_convergence_index(SIZES[-3:], values[-3:])
    assert index["order"] == pytest.approx(p, abs=1e-8)
    assert index["extrapolated"] == pytest.approx(3.0, abs=1e-10)
    error = abs(values[-1] - 3.0)
    assert index["gci"] == pytest.approx(SAFETY_FACTOR * error, rel=1e-7)
    assert index["relative"] == pytest.approx(SAFETY_FACTOR * error / values[-1], rel=1e-7)
    assert index["ratio"] == pytest.approx(20.0 / 16.0)


@pytest.mark.parametrize("p", [1.0, 2.0, 2.5])
def test_a_fields_order_from_its_changes(p):
    # a manufactured field f_h(X) = g(X) + C(X) h^p at fixed points: the rms of its change
    # from each mesh to the next is rms(C) |h_i^p - h_(i+1)^p|, whatever g
    points = np.linspace(0.0, 1.0, 50)
    g, c = np.sin(3.0 * points), 0.01 * (1.0 + points**2)
    fields = [g + c * h**p for h in SIZES]
    changes = [np.sqrt(np.mean((a - b) ** 2)) for a, b in zip(fields[:-1], fields[1:])]
    assert np.allclose(change_orders(SIZES, changes), p, rtol=0.0, atol=1e-8)
    with pytest.raises(ValueError, match="m - 1 changes"):
        change_orders(SIZES, changes[:-1])


@pytest.mark.parametrize("p", [1.3, 2.0])
def test_a_fields_order_from_its_distances_to_the_finest(p):
    # the same field: its rms distance from each mesh's to the finest's is rms(C) (h^p -
    # h_m^p), a power law whose limit -rms(C) h_m^p is the finest field's distance to g
    points = np.linspace(0.0, 1.0, 50)
    g, c = np.sin(3.0 * points), 0.01 * (1.0 + points**2)
    fields = [g + c * h**p for h in SIZES]
    distances = [np.sqrt(np.mean((f - fields[-1]) ** 2)) for f in fields]
    fit = power_fit(SIZES, distances)
    assert fit["order"] == pytest.approx(p, abs=1e-5)
    finest = np.sqrt(np.mean((fields[-1] - g) ** 2))
    assert -fit["extrapolated"] == pytest.approx(finest, rel=1e-4)


def test_an_oscillating_sequence_has_no_order_nor_index():
    index = grid_convergence_index([25.0, 20.0, 16.0], [24.9, 29.7, 23.3])
    assert math.isnan(index["order"]) and math.isnan(index["gci"])
    orders = consecutive_orders([25.0, 20.0, 16.0, 12.5], [24.9, 29.7, 23.3, 25.0])
    assert np.isnan(orders).all()


def test_a_sequence_whose_differences_grow_has_no_index_nor_limit():
    # f = 4, 2, 1 on meshes 0, 1, 3: the differences 1, 2 grow (order -1 with the ratio 2);
    # Roache's band Fs |f2 - f3| / (r^p - 1) would come out negative
    index = grid_convergence_index([4.0, 2.0, 1.0], [0.0, 1.0, 3.0])
    assert index["order"] == pytest.approx(-1.0)
    assert math.isnan(index["gci"]) and math.isnan(index["relative"])
    assert math.isnan(index["extrapolated"])


@pytest.mark.parametrize("p", [0.8, 1.0, 2.0, 3.0])
def test_the_fit_recovers_a_power_law(p):
    fit = power_fit(SIZES, _law(p))
    assert fit["order"] == pytest.approx(p, abs=1e-5)
    assert fit["extrapolated"] == pytest.approx(3.0, abs=1e-6)
    assert fit["coefficient"] == pytest.approx(0.02, rel=1e-4)
    assert fit["residual"] < 1e-8
    assert fit["change"] == pytest.approx(0.02 * (SIZES[0] ** p - SIZES[-1] ** p), rel=1e-4)
    assert not fit["bound"]


def test_a_sequence_whose_steps_grow_has_its_fit_at_the_bound():
    # steps 1, 2, 4 on shrinking h: no f0 + C h^p with p > 0 passes near them
    assert power_fit([4.0, 3.0, 2.0, 1.0], [0.0, 1.0, 3.0, 7.0])["bound"]


def test_a_fixed_order_fit_on_scatter_reports_the_scatter():
    # f = 1 + h alternately +-e: at p = 1 the fit is the least-squares line, numpy's
    # polynomial fit of degree 1 the reference; its residuals' deviation over m - 2 = 4
    e = 0.05
    signs = np.array([1.0, -1.0, 1.0, -1.0, 1.0, -1.0])
    values = 1.0 + SIZES + e * signs
    fit = power_fit(SIZES, values, order=1.0)
    slope, intercept = np.polyfit(SIZES, values, 1)
    residual = values - (intercept + slope * SIZES)
    assert fit["extrapolated"] == pytest.approx(intercept, abs=1e-12)
    assert fit["coefficient"] == pytest.approx(slope, rel=1e-12)
    assert fit["residual"] == pytest.approx(math.sqrt(residual @ residual / 4), rel=1e-10)
    assert fit["residual"] > 0.5 * e


@pytest.mark.parametrize(
    "sizes, values, message",
    [
        ([1.0, 2.0, 3.0], [1.0, 2.0, 3.0], "decreasing"),
        ([3.0, 2.0], [1.0, 2.0], "at least 3"),
        ([3.0, 2.0, 1.0], [1.0, np.nan, 3.0], "finite"),
        ([3.0, 2.0, 1.0], [1.0, 2.0], "at least 3"),
    ],
)
def test_bad_sequences_are_refused(sizes, values, message):
    for function in (consecutive_orders, power_fit):
        with pytest.raises(ValueError, match=message):
            function(sizes, values)


def test_bad_settings_are_refused():
    with pytest.raises(ValueError, match="factor of safety"):
        grid_convergence_index([3.0, 2.0, 1.0], [1.0, 2.0, 2.5], safety=0.0)
    with pytest.raises(ValueError, match="three sizes"):
        grid_convergence_index([4.0, 3.0, 2.0, 1.0], [1.0, 2.0, 2.5, 2.6])
    with pytest.raises(ValueError, match="fixed order"):
        power_fit([3.0, 2.0, 1.0], [1.0, 2.0, 2.5], order=-1.0)
