"""validation.specimens.hemisphere_die makes a die's arrays once a process: a second call
takes them from the cache and gives a Mesh equal to the first, with arrays of its own (the
Mesh's copies: a caller that could write one die's points cannot move another's), and
another rim another die."""

import numpy as np
import pytest

from validation import specimens
from validation.specimens import hemisphere_die


def test_a_die_made_again_is_the_cached_mesh_with_its_own_arrays():
    first = hemisphere_die(10.0, 17.0, rings=8, rim=2.0)
    hits = specimens._die_arrays.cache_info().hits
    again = hemisphere_die(10.0, 17.0, rings=8, rim=2.0)
    assert specimens._die_arrays.cache_info().hits == hits + 1
    np.testing.assert_array_equal(again.points, first.points)
    np.testing.assert_array_equal(again.triangles, first.triangles)
    assert not np.shares_memory(again.points, first.points)
    assert not again.points.flags.writeable
    other = hemisphere_die(10.0, 17.0, rings=8, rim=1.0)  # another rim, another die
    assert other.points.shape != first.points.shape or not np.array_equal(
        other.points, first.points
    )


@pytest.mark.parametrize("rings", [8.5, "8", 0, True])
def test_a_ring_count_that_is_not_a_whole_number_is_refused(rings):
    with pytest.raises(ValueError, match="rings must be a whole number >= 1"):
        hemisphere_die(10.0, 17.0, rings=rings)
