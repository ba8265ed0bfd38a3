"""The stack as N sliding plies (elements/plies.py, elements/ply_contact.py, docs/theory.md
"The stack as plies"): the ply's fabric, the stack builder and its node maps, the material
lines, and the closed forms the plies must meet."""

import numpy as np
import pytest

from materials import BendingLaw, Fabric, ShearLaw, TensionLaw


# ---------------------------------------------------------------------- Law.scaled, plies
@pytest.mark.parametrize(
    "law",
    [
        TensionLaw.linear(1200.0),
        TensionLaw.linear(1200.0, tension_only=True),
        TensionLaw.table([0.0, 0.01, 0.02], [0.0, 5.0, 30.0]),
        ShearLaw.polynomial(0.1, 0.5, 2.0),
        BendingLaw.bilinear(7.5, 0.5, knee=1e-3),
    ],
    ids=repr,
)
def test_a_scaled_law_is_factor_times_the_law(law):
    x = np.linspace(-0.05, 0.05, 41)
    scaled = law.scaled(0.25)
    assert scaled.family == law.family and scaled.compression == law.compression
    for what in ("value", "slope", "energy"):
        assert np.allclose(getattr(scaled, what)(x), 0.25 * getattr(law, what)(x), rtol=1e-14)
    assert scaled.max_slope() == pytest.approx(0.25 * law.max_slope())


@pytest.mark.parametrize("factor", [0.0, -1.0, np.inf, "2", True, None])
def test_a_law_refuses_a_bad_scale(factor):
    with pytest.raises(ValueError, match="factor"):
        TensionLaw.linear(10.0).scaled(factor)


def test_the_ply_fabric_is_the_stack_shared_equally():
    stack = Fabric(
        thickness=6.0,
        areal_density=5.7e-9,
        tension=1200.0,
        shear=ShearLaw.linear(4.0),
        bending=BendingLaw.bilinear(7.5, 0.5, knee=1e-3),
        bending_weft=6.0,
    )
    ply = stack.plies(4)
    assert ply.thickness == 1.5 and ply.areal_density == pytest.approx(5.7e-9 / 4)
    chi = np.linspace(-0.01, 0.01, 21)
    for name in ("tension", "tension_weft", "shear", "bending", "bending_weft"):
        assert np.allclose(getattr(ply, name).value(chi), getattr(stack, name).value(chi) / 4)
    assert ply.tension_weft is ply.tension  # the weft followed the warp: it still does
    assert stack.plies(1) == stack


@pytest.mark.parametrize("count", [0, -2, 2.0, 2.5, "4", True, None])
def test_plies_refuses_a_count_that_is_not_a_positive_integer(count):
    stack = Fabric(thickness=1.0, areal_density=1e-9, tension=10.0, shear=1.0, bending=1.0)
    with pytest.raises(ValueError, match="count must be an integer >= 1"):
        stack.plies(count)
