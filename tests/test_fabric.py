"""Fabric laws (docs/theory.md §2-4.6) and the paper's presets (Bai Tables 1-2)."""

import numpy as np
import pytest
from scipy.integrate import quad

from materials import BendingLaw, Fabric, ShearLaw, TensionLaw, presets

LAWS = [
    TensionLaw.linear(1200.0),
    TensionLaw.table([-0.01, 0.0, 0.002, 0.01], [-5.0, 0.0, 1.0, 20.0]),
    ShearLaw.linear(0.3),
    ShearLaw.polynomial(0.2, -0.1, 2.0),
    ShearLaw.table([0.0, 0.3, 0.7], [0.0, 0.05, 0.6]),
    BendingLaw.linear(72.0),
    BendingLaw.bilinear(7.5, 0.5, knee=1e-3),
    BendingLaw.table([0.0, 1e-3, 5e-3], [0.0, 0.01, 0.012]),
]


@pytest.mark.parametrize("law", LAWS, ids=repr)
def test_energy_is_the_integral_of_the_law_and_slope_its_derivative(law):
    span = {"TensionLaw": 0.02, "ShearLaw": 0.9, "BendingLaw": 8e-3}[law.family]
    knots = [] if law.knots is None else list(law.knots[0])
    for x in 0.97 * np.linspace(-span, span, 13):  # off the knots, where the slope jumps
        breaks = [k for k in knots if min(0.0, x) < k < max(0.0, x)] or None
        integral, _ = quad(lambda t: float(law.value(t)), 0.0, x, limit=200, points=breaks)
        assert law.energy(x) == pytest.approx(integral, rel=1e-9, abs=1e-15)
        h = 1e-7 * span
        numeric = (law.value(x + h) - law.value(x - h)) / (2 * h)
        assert law.slope(x) == pytest.approx(numeric, rel=1e-6, abs=1e-12)


def test_table_1_bilinear_law_is_continuous_at_the_knee():
    # Bai Table 1 read as in docs/theory.md §4.6: M = 7.5 chi up to 1e-3, then 0.0075 + 0.5 (chi -
    # 1e-3).
    law = BendingLaw.bilinear(7.5, 0.5, knee=1e-3)
    assert law.value(1e-3) == pytest.approx(0.0075)
    assert law.value(1e-3 * (1 + 1e-9)) == pytest.approx(0.0075, rel=1e-8)
    assert law.value(3e-3) == pytest.approx(0.0075 + 0.5 * 2e-3)
    assert law.value(-3e-3) == pytest.approx(-(0.0075 + 0.5 * 2e-3))
    assert law.slope(5e-4) == pytest.approx(7.5) and law.slope(2e-3) == pytest.approx(0.5)


def test_tension_only_fibres_carry_nothing_in_compression():
    law = TensionLaw.linear(100.0, tension_only=True)
    assert law.value(-0.01) == 0.0 and law.energy(-0.01) == 0.0
    assert law.value(0.01) == pytest.approx(1.0)


def test_tables_given_for_positive_arguments_are_mirrored():
    law = ShearLaw.table([0.0, 0.5], [0.0, 1.0])
    assert law.value(-0.25) == pytest.approx(-0.5)


@pytest.mark.parametrize(
    "build, message",
    [
        (lambda: TensionLaw.linear(-1.0), "stiffness C must be > 0"),
        (lambda: BendingLaw.linear(0.0), "B must be > 0"),
        (lambda: BendingLaw.bilinear(7.5, -0.5, 1e-3), "B2 > 0"),
        (lambda: ShearLaw.polynomial(1.0, -10.0), "slope"),
        (lambda: BendingLaw.table([0.0, 2e-3, 1e-3], [0, 1, 2]), "strictly increasing"),
        (lambda: BendingLaw.table([0.0, 1e-3, 2e-3], [0, 2, 1]), "non-decreasing"),
        (lambda: TensionLaw.table([0.01, 0.02], [1.0, 2.0]), "span 0"),
        (lambda: TensionLaw.table([-0.01, 0.02], [1.0, 2.0]), "give 0 at 0"),
        (lambda: ShearLaw.table([0.0], [0.0]), "length >= 2"),
    ],
)
def test_bad_laws_are_refused_with_a_clear_message(build, message):
    with pytest.raises(ValueError, match=message):
        build()


def test_fabric_accepts_numbers_as_linear_laws_and_defaults_weft_to_warp():
    fabric = Fabric(thickness=2.0, areal_density=1e-9, tension=100.0, shear=0.1, bending=5.0)
    assert fabric.tension.value(0.01) == pytest.approx(1.0)
    assert fabric.bending_weft is fabric.bending and fabric.tension_weft is fabric.tension
    assert fabric.density == pytest.approx(5e-10)


def test_replace_keeps_weft_laws_that_followed_the_warp_following_it():
    """fabric.replace(tension=...) changes both directions of a fabric whose weft law was the
    warp law; an explicit weft law stays (dataclasses.replace would keep the old weft)."""
    balanced = Fabric(thickness=2.0, areal_density=1e-9, tension=100.0, shear=0.1, bending=5.0)
    stiffer = balanced.replace(tension=1000.0)
    assert stiffer.tension_weft is stiffer.tension
    assert stiffer.tension_weft.value(0.01) == pytest.approx(10.0)
    assert stiffer.bending_weft is stiffer.bending is balanced.bending
    unbalanced = balanced.replace(tension_weft=50.0).replace(tension=1000.0)
    assert unbalanced.tension_weft.value(0.01) == pytest.approx(0.5)
    with pytest.raises(ValueError, match="unknown field"):
        balanced.replace(stiffness=1.0)


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"thickness": 0.0}, "thickness"),
        ({"areal_density": -1.0}, "areal_density"),
        ({"tension": ShearLaw.linear(1.0)}, "tension must be a TensionLaw"),
        ({"bending": "stiff"}, "bending must be a BendingLaw"),
        ({"shear": BendingLaw.linear(1.0)}, "shear must be a ShearLaw"),
        ({"bending_weft": TensionLaw.linear(1.0)}, "bending_weft"),
    ],
)
def test_fabric_refuses_bad_input(kwargs, message):
    args = dict(thickness=2.0, areal_density=1e-9, tension=100.0, shear=0.1, bending=5.0)
    args.update(kwargs)
    with pytest.raises(ValueError, match=message):
        Fabric(**args)


def test_presets_carry_the_paper_tables():
    stack = presets.g986_stack()  # Bai Table 1
    assert stack.tension.value(1e-3) == pytest.approx(1.2)
    assert stack.bending.value(1e-3) == pytest.approx(0.0075)
    assert stack.thickness == pytest.approx(6.0)
    laminate = presets.g1151_laminate()  # Bai Table 2 and §6.2
    assert laminate.tension.value(1e-3) == pytest.approx(2.3)
    assert laminate.bending.value(1.0) == pytest.approx(72.0)
    assert laminate.bending_weft.value(1.0) == pytest.approx(68.0)
    assert laminate.thickness == presets.G1151_SPECIMEN["thickness"] == 15.0
    paper = presets.paper_stack()
    assert paper.shear.slope(0.0) > 100 * laminate.shear.slope(0.0)  # "large" (Bai §6.1)
    assert presets.g986_ply().thickness == pytest.approx(0.3)
    with pytest.raises(ValueError, match="positive integer"):
        presets.g986_stack(0)
