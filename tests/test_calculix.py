"""Peer comparison with CalculiX (validation/calculix.py): the deck, the .dat parser, and - when
ccx is installed - MindlinShell against CalculiX S4 on the same cantilever strip."""

import shutil

import numpy as np
import pytest

from validation.calculix import (
    Strip,
    calculix_deck,
    mindlin_tip,
    parse_tip_displacement,
    run_calculix,
)


def test_deck_describes_the_strip():
    strip = Strip(nx=4, ny=1)
    deck = calculix_deck(strip, load=2.0, nonlinear=True)
    assert deck.count("\n") > 10
    assert "*ELEMENT, TYPE=S4" in deck and "*STEP, NLGEOM" in deck
    assert "CLAMP, 1, 6" in deck
    loads = [float(line.split(",")[2]) for line in deck.split("*CLOAD\n")[1].splitlines()[:2]]
    assert sum(loads) == pytest.approx(-2.0)
    assert "NLGEOM" not in calculix_deck(strip, 2.0, nonlinear=False)


def test_dat_parser_takes_the_last_block():
    text = """
 displacements (vx,vy,vz) for set TIP and time  0.5000000E+00

         3  1.0E+00  0.0E+00 -2.0E+00
         6  1.0E+00  0.0E+00 -4.0E+00

 displacements (vx,vy,vz) for set TIP and time  0.1000000E+01

         3  2.0E+00  0.0E+00 -6.0E+00
         6  4.0E+00  0.0E+00 -8.0E+00
"""
    assert parse_tip_displacement(text) == pytest.approx([3.0, 0.0, -7.0])
    with pytest.raises(ValueError, match="no displacement"):
        parse_tip_displacement("nothing here")


@pytest.mark.skipif(shutil.which("ccx") is None, reason="CalculiX (calculix-ccx) not installed")
@pytest.mark.parametrize("nonlinear", [False, True])
def test_mindlin_matches_calculix_s4(nonlinear):
    # Measured: 0.00% (linear) and 0.10% (P L^2 / EI = 3, NLGEOM) on 20 x 2 cells.
    strip = Strip()
    load = 3.0 * strip.bending_stiffness / strip.length**2
    ours = mindlin_tip(strip, load, nonlinear)
    theirs = run_calculix(strip, load, nonlinear)
    assert ours[2] == pytest.approx(theirs[2], rel=0.01)
    assert np.isfinite(ours).all()
