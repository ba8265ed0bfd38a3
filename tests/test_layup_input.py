"""A Layup's angles and contact options at its boundary (elements/layup.py): angles as any
1-D sequence of numbers, angles that look like radians warned, a bad ``lower_rule`` named."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from elements.layup import Layup
from materials import Fabric

PLY = Fabric(thickness=0.3, areal_density=2.85e-10, tension=60.0, shear=0.2, bending=0.375)


def test_angles_may_be_a_numpy_array():
    layup = Layup(PLY, np.array([0.0, 90.0]), 40.0, cells=2)
    assert layup.angles.tolist() == [0.0, 90.0]


@pytest.mark.parametrize(
    "angles", [(0.0, np.pi / 2), (0.0, -np.pi / 4, np.pi / 4), (np.pi / 2,)],
    ids=["0-pi/2", "0-pi/4", "pi/2"],
)  # fmt: skip
def test_angles_that_look_like_radians_are_warned(angles):
    with pytest.warns(UserWarning, match=r"radians\? angles are in degrees"):
        Layup(PLY, angles, 40.0, cells=2)


@pytest.mark.parametrize(
    "angles", [(0.0, 0.0), (0.0, 1.0), (0.0, 90.0), (0.0, 45.0, -45.0)],
    ids=["zeros", "one-degree", "0-90", "0-45--45"],
)  # fmt: skip
def test_angles_in_degrees_are_not_taken_for_radians(angles):
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        Layup(PLY, angles, 40.0, cells=2)
    # (1 deg warns of its staircase outline, not of radians)
    assert not [w for w in said if "radians" in str(w.message)]


def test_a_bad_lower_rule_is_named():
    with pytest.raises(ValueError, match=r"lower_rule must be None or one of .*'corners'"):
        Layup(PLY, (0.0, 90.0), 40.0, cells=2, lower_rule="corners")
