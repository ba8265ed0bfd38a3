"""The numbers a calibration states (comparison.json's "calibration", the figures' titles)
are those of the Mindlin shell it builds (fibreshell/calibration.py)."""

from __future__ import annotations

import pytest

from elements import FibrousShell
from fibreshell.calibration import Calibration
from materials import presets


@pytest.mark.parametrize("scale", [1.0, 2.0])
def test_the_laws_calibration_states_the_scaled_sections_transverse_shear_and_twist(scale):
    """G1151 laminate (Bai Table 2: B = 72 N mm warp, h = 15 mm), bending scaled by ``scale``:
    the defaults of docs/theory.md §5.7 on the scaled slope, S = 5 B0 / h^2 (1.6 N/mm at
    scale 1, 3.2 at 2) and D_t = B0 / 2 (36, 72 N mm), stated as the built shell has them
    (closed forms of exact products: 1e-12 relative)."""
    fabric = presets.g1151_laminate()
    rule = Calibration.from_options("laws", bending_scale=scale)
    numbers = rule.numbers(fabric)
    shell = rule.mindlin(FibrousShell(fabric))
    b0, h = 72.0 * scale, 15.0
    assert numbers["transverse_shear_N_per_mm"] == pytest.approx(5.0 * b0 / h**2, rel=1e-12)
    assert shell.transverse_shear == pytest.approx(5.0 * b0 / h**2, rel=1e-12)
    assert numbers["twisting_N_mm"] == pytest.approx(0.5 * b0, rel=1e-12)
    assert shell.twisting == pytest.approx(0.5 * b0, rel=1e-12)
    assert f"S = {5.0 * b0 / h**2:.3g} N/mm" in rule.label(fabric)


# ------------------------------------------------- a fabric whose bending law has a toe
def _toe_fabric():
    """The shell's own example (tests/test_mindlin_fabric.py): a bending table flat up to
    1e-4 1/mm, B0 = 0, so that the defaults S = 5 B0 / h^2 and D_t = B0 / 2 would be 0."""
    from materials import BendingLaw, Fabric

    toe = BendingLaw.table([0.0, 1e-4, 1e-2], [0.0, 0.0, 0.0743])
    return Fabric(thickness=0.3, areal_density=2.85e-10, tension=1200.0, shear=0.2, bending=toe)


def test_the_laws_calibration_takes_a_toe_fabrics_transverse_shear_and_twisting():
    """Given S and D_t, the calibration builds, states and labels the section with them (it
    had no twisting: Calibration.numbers and .label raised for such a fabric)."""
    fabric = _toe_fabric()
    rule = Calibration.from_options("laws", transverse_shear=416.7, twisting=3.75)
    shell = rule.mindlin(FibrousShell(fabric))
    assert (shell.transverse_shear, shell.twisting) == (416.7, 3.75)
    numbers = rule.numbers(fabric)
    assert (numbers["transverse_shear_N_per_mm"], numbers["twisting_N_mm"]) == (416.7, 3.75)
    assert "S = 417 N/mm, D_t = 3.75 N mm" in rule.label(fabric)
    with pytest.raises(ValueError, match="twisting belongs to the laws and fit"):
        Calibration.from_options("initial-slope", twisting=3.75)
    with pytest.raises(ValueError, match="calibration twisting"):
        Calibration(twisting=-1.0)


def test_a_toe_fabric_without_both_numbers_is_refused_naming_the_route_from_where_one_is(
    tmp_path,
):
    """The message named 'transverse_shear and twisting' without saying how compare takes
    them (it could not); now compare's options, a run's options, a case file's part options,
    each where it is met."""
    from fibreshell.case import CaseError, load_case
    from fibreshell.compare import calibration_lines, compare_case

    case = tmp_path / "toe.toml"
    case.write_text(TOE_CASE)
    loaded = load_case(case)
    with pytest.raises(ValueError, match=r"compare --transverse-shear S --twisting D"):
        compare_case(loaded, tmp_path / "out", progress=False)
    assert not (tmp_path / "out").exists()  # refused before the fibrous run
    with pytest.raises(ValueError, match=r"compare --transverse-shear S --twisting D"):
        calibration_lines(loaded, "laws", transverse_shear=416.7)  # twisting missing
    lines = calibration_lines(loaded, "laws", transverse_shear=416.7, twisting=3.75)
    assert "  twisting_N_mm = 3.75" in lines and "  transverse_shear_N_per_mm = 416.7" in lines
    with pytest.raises(ValueError, match=r"run's options transverse_shear and twisting"):
        Calibration().mindlin(FibrousShell(_toe_fabric()))  # a sweep in the mindlin kinematics
    case.write_text(TOE_CASE.replace('"fibrous"', '"mindlin"'))
    with pytest.raises(CaseError, match=r"\[part\[0\]\.options\]: .*options = \{ transverse_shea"):
        load_case(case)


TOE_CASE = """
title = "toe strip"
[mesh]
rectangle = { lx = 100.0, ly = 10.0, nx = 4, ny = 1 }
[[part]]
element = "fibrous"
[part.material]
thickness = 0.3
areal_density = 2.85e-10
tension = 1200.0
shear = 0.2
bending = { table = { x = [0.0, 1e-4, 1e-2], y = [0.0, 0.0, 0.0743] } }
[[fix]]
nodes = "left"
[gravity]
acceleration = [0.0, 0.0, -9810.0]
[solver]
kind = "static"
increments = 1
"""
