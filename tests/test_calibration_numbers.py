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
