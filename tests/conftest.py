"""Shared fixtures: small cable models whose answers are known in closed form."""

import pytest

from femcore import Mesh
from validation import specimens


@pytest.fixture
def box_chain() -> Mesh:
    """40 segments of 3 mm hanging from (0,0,0) and (96,0,0): down 12, across 96, up 12
    (unstretched length 120 mm). Far from the catenary it relaxes to."""
    return specimens.box_chain(40)
