"""The kinematic drape reference (validation/references/drape.py): Mack and Taylor's
pin-jointed net on a sphere keeps its segments and its crossings on the sphere, and converges
to the continuum Chebyshev net of the sphere, d^2 gamma / du dv = cos(gamma) / R^2, a
different equation integrated by a different scheme."""

import numpy as np
import pytest

from validation.references.drape import chebyshev_shear, fishnet_on_sphere

RADIUS = 50.0


def test_the_net_keeps_its_segments_on_the_sphere():
    """Every warp and weft segment is one cell long and every crossing on the sphere, to
    rounding (1e-9 mm); the generators are great circles with no shear; the net is symmetric
    under x -> -x (shear changes sign) and under swapping warp and weft."""
    net = fishnet_on_sphere(RADIUS, 2.5, 30)
    p = net["points"]
    for axis in (0, 1):
        lengths = np.linalg.norm(np.diff(p, axis=axis), axis=2)
        assert np.nanmax(np.abs(lengths - 2.5)) < 1e-9
    assert np.nanmax(np.abs(np.linalg.norm(p, axis=2) - RADIUS)) < 1e-9
    assert np.isfinite(p).sum() > 0.5 * p.size  # most of the net lies on the hemisphere
    n = 30
    np.testing.assert_allclose(net["shear"][n, :][np.isfinite(net["shear"][n, :])], 0, atol=1e-12)
    np.testing.assert_allclose(p[::-1, :, 0], -p[:, :, 0], atol=1e-9, equal_nan=True)
    np.testing.assert_allclose(p.transpose(1, 0, 2)[..., [1, 0, 2]], p, atol=1e-9, equal_nan=True)


def test_the_net_converges_to_the_chebyshev_net_of_the_sphere():
    """Shear at fibre arc lengths (30, 30) mm from the pole, nets of 5, 2.5 and 1.25 mm
    cells against the Chebyshev equation marched on a 0.1 mm grid (0.357431 rad; the
    small-angle value uv / R^2 is 0.36): the error falls four times per halving (second
    order; measured 7.1e-4, 1.8e-4, 4.4e-5 rad) and is below 1e-4 rad at 1.25 mm."""
    continuum = chebyshev_shear(RADIUS, 30.0, 300)["shear"][-1, -1]
    errors = []
    for cell in (5.0, 2.5, 1.25):
        steps = round(30.0 / cell)
        shear = fishnet_on_sphere(RADIUS, cell, steps + 1)["shear"]  # centre at steps + 1
        errors.append(shear[2 * steps + 1, 2 * steps + 1] - continuum)
    assert abs(errors[-1]) < 1e-4
    assert 3.0 < errors[0] / errors[1] < 5.0 and 3.0 < errors[1] / errors[2] < 5.0
    assert continuum == pytest.approx(30.0 * 30.0 / RADIUS**2, rel=0.02)  # small angles


def test_the_net_refuses_a_cell_as_large_as_the_sphere():
    with pytest.raises(ValueError, match="cell"):
        fishnet_on_sphere(RADIUS, 60.0, 3)
