"""The angles of the fibrous shell's compiled loops (elements/fibrous/angles.py) against the
C library's arctan2 and arcsin through numpy: the same angles to a few units in the last
place (the quotient's rounding and the arctan's), on every octant, the axes and the ends."""

from __future__ import annotations

import numpy as np
import pytest

from elements.fibrous.angles import arc_sine, polar_angle

# Both sides are correctly rounded to within about one unit in the last place of pi (4.4e-16);
# the reduction adds the quotient's rounding and, past |y| > |x|, one addition: 4 units.
TOLERANCE = 4 * np.finfo(float).eps * np.pi


def test_polar_angle_is_atan2_everywhere():
    rng = np.random.default_rng(7)
    angle = rng.uniform(-np.pi, np.pi, 4000)
    radius = 10.0 ** rng.uniform(-8, 8, 4000)
    points = [(r * np.sin(a), r * np.cos(a)) for r, a in zip(radius, angle)]
    # the axes, the diagonals (the branch between the two quotients), signed zeros
    points += [(0.0, 1.0), (0.0, -1.0), (1.0, 0.0), (-1.0, 0.0), (0.0, 0.0), (-0.0, 0.0)]
    points += [(1.0, 1.0), (-1.0, 1.0), (1.0, -1.0), (-1.0, -1.0), (3.0, -2.0), (-2.0, 3.0)]
    points += [(1e-300, 1.0), (1.0, 1e-300), (-1e-17, -1.0)]
    for y, x in points:
        assert abs(polar_angle(y, x) - np.arctan2(y, x)) <= TOLERANCE, (y, x)
    assert polar_angle(0.0, 0.0) == 0.0
    assert polar_angle(0.0, 2.0) == 0.0  # a flat fold is exactly flat


def test_arc_sine_is_asin_on_its_domain():
    values = np.concatenate(
        [np.linspace(-1.0, 1.0, 2001), [1e-300, -1e-20, 0.5, -0.5, 1 - 1e-16, -1 + 1e-16]]
    )
    for s in values:
        expected = np.arcsin(s)
        # relative near 0, where both are s to the last place
        assert abs(arc_sine(s) - expected) <= max(TOLERANCE * abs(expected) / np.pi, 1e-300), s
        assert abs(arc_sine(s) - expected) <= TOLERANCE, s
    assert arc_sine(1.0) == pytest.approx(np.pi / 2, abs=0.0)
    assert arc_sine(-1.0) == pytest.approx(-np.pi / 2, abs=0.0)
    assert arc_sine(1.5) == pytest.approx(np.pi / 2, abs=0.0)  # clipped, as the loops clip
    assert arc_sine(0.0) == 0.0
