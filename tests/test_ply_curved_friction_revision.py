"""elements/ply_curved_friction_kernels.py: the pass's flat point and offsets, written once
(``_flat_point``) and spliced into its projections and its Jacobian maps, leave the local
loads the bits of the pass of revision BEFORE, which spelled them out twice (its file taken
from git and imported beside this tree's, tests/revision_modules.py), real and at every
complex step. Marked slow: numba builds the pass of BEFORE too (about 10 s of CPU, real and
complex, on an empty cache; kept from run to run in pytest's cache folder)."""

from __future__ import annotations

import numpy as np
import pytest

from elements import ply_curved_friction, ply_curved_friction_kernels
from elements.jit import AVAILABLE
from tests.revision_modules import revision_for_tests
from tests.test_ply_curved_friction import _local

pytestmark = [pytest.mark.skipif(not AVAILABLE, reason="numba missing"), pytest.mark.slow]

BEFORE = "14e312d"
FILE = {"elements/ply_curved_friction_kernels.py": "elements.ply_curved_friction_kernels"}


@pytest.fixture(scope="module")
def before(request):
    """The pass's module of BEFORE."""
    return revision_for_tests(request, BEFORE, FILE)["ply_curved_friction_kernels"]


def test_the_local_loads_are_the_bits_of_the_pass_before(before):
    block, data, arguments, stepped, repeated = _local()
    settings = (block.smoothing, block.friction, block.stick == "penalty")
    for points, per_point in ((data, arguments), (stepped, repeated)):
        now = ply_curved_friction_kernels.local_loads(
            points, *per_point, *settings, ply_curved_friction.STEPS
        )
        assert np.abs(now).max() > 0.0
        then = before.local_loads(points, *per_point, *settings, ply_curved_friction.STEPS)
        np.testing.assert_array_equal(now, then)
