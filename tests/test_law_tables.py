"""Law tables as the module docstring of materials/laws.py states them: the shear and bending
laws are odd in their strain (whose sign is a convention: the cells' winding, the fibres'
orientation), so a table given over both signs must be odd; a tension law's strain has one
meaning (stretch or shortening), so its table may differ between the two signs."""

from __future__ import annotations

import numpy as np
import pytest

from materials import BendingLaw, ShearLaw, TensionLaw

FAMILIES = {"shear": ShearLaw.table, "bending": BendingLaw.table}


@pytest.mark.parametrize("family", sorted(FAMILIES))
def test_a_table_over_both_signs_that_is_not_odd_is_refused(family):
    """y(-0.5) = -0.05 where y(0.5) = 1: the answer would depend on the sign convention."""
    with pytest.raises(ValueError, match=r"not odd.*x >= 0 only"):
        FAMILIES[family]([-0.5, 0.0, 0.5], [-0.05, 0.0, 1.0])


@pytest.mark.parametrize("family", sorted(FAMILIES))
def test_a_table_over_a_range_that_is_not_symmetric_is_refused(family):
    """Odd at every knot over [-0.3, 0.3] but extrapolated from (0.5, 1.0) on one side only."""
    with pytest.raises(ValueError, match="not odd"):
        FAMILIES[family]([-0.3, 0.0, 0.3, 0.5], [-0.6, 0.0, 0.6, 1.0])


@pytest.mark.parametrize("family", sorted(FAMILIES))
def test_an_odd_table_over_both_signs_is_the_mirrored_half(family):
    """The same law as its x >= 0 half, which the constructor mirrors; values typed to 1e-12
    of -y(x) (round-off of a computed table) are within ODD_TOLERANCE = 1e-6."""
    both = FAMILIES[family]([-1.0, -0.5, 0.0, 0.5, 1.0], [-3.0, -1.0 + 1e-12, 0.0, 1.0, 3.0])
    half = FAMILIES[family]([0.0, 0.5, 1.0], [0.0, 1.0, 3.0])
    x = np.linspace(-1.5, 1.5, 31)
    assert np.allclose(both.value(x), half.value(x), rtol=0.0, atol=1e-11)


@pytest.mark.parametrize("family", sorted(FAMILIES))
def test_a_table_computed_in_single_precision_is_odd_enough(family):
    """y = 0.1 g + 0.5 g^3 over g = -1.2..1.2 computed in float32: odd only to its round-off
    (6e-8 of the largest |y| at the knots, float32's unit round-off being 2**-24 = 6e-8), so
    accepted, and the law is the float64 one to float32's precision (1e-6 of max |y| = 1.03,
    a few ulps of float32 in y and in the knots)."""
    g32 = np.linspace(-1.2, 1.2, 13).astype(np.float32)
    law = FAMILIES[family](g32, 0.1 * g32 + 0.5 * g32**3)
    g = np.linspace(-1.2, 1.2, 13)
    exact = FAMILIES[family](g[6:], 0.1 * g[6:] + 0.5 * g[6:] ** 3)
    x = np.linspace(-1.5, 1.5, 31)
    assert np.allclose(law.value(x), exact.value(x), rtol=0.0, atol=1e-6)


@pytest.mark.parametrize("family", sorted(FAMILIES))
def test_a_table_a_thousandth_from_odd_is_refused(family):
    """An asymmetry of 1e-3 of the largest |y|, far from any round-off, is still refused."""
    with pytest.raises(ValueError, match="not odd"):
        FAMILIES[family]([-0.5, 0.0, 0.5], [-1.0 + 1e-3, 0.0, 1.0])


def test_a_tension_table_may_differ_in_compression():
    """A fibre softer in compression than in tension (the strain's sign is physical): kept
    as given, T(-0.01) = -5 N/mm and T(0.01) = 20 N/mm."""
    law = TensionLaw.table([-0.01, 0.0, 0.01], [-5.0, 0.0, 20.0])
    assert law.value(np.array([-0.01, 0.01])) == pytest.approx([-5.0, 20.0], rel=1e-15)


def test_a_shear_table_in_degrees_is_refused():
    """A picture-frame curve typed in degrees, [0, 20, 40, 60]: an angle past pi/2 rad cannot
    be (the fibres would lie flat on each other), and read as radians it is 86 x too soft at
    40 deg (0.00175 N/mm where 0.15 was meant)."""
    with pytest.raises(ValueError, match=r"radians.*degrees\?"):
        ShearLaw.table([0.0, 20.0, 40.0, 60.0], [0.0, 0.05, 0.15, 0.6])
    law = ShearLaw.table(np.radians([0.0, 20.0, 40.0, 60.0]), [0.0, 0.05, 0.15, 0.6])
    assert float(law.value(np.radians(40.0))) == pytest.approx(0.15, rel=1e-12)


@pytest.mark.parametrize("family", ["tension", "shear", "bending"])
def test_a_nested_table_is_refused_not_flattened(family):
    make = {"tension": TensionLaw.table, **FAMILIES}[family]
    with pytest.raises(ValueError, match="flat sequences"):
        make([[0.0, 1e-3]], [[0.0, 0.0075]])
