"""validation.specimens.hemisphere_die makes a die's arrays once a process: each call gives a
Mesh equal to the first, with arrays of its own, and another rim another die."""

import numpy as np

from validation.specimens import hemisphere_die


def test_a_die_made_again_is_the_same_mesh_with_its_own_arrays():
    first = hemisphere_die(10.0, 17.0, rings=8, rim=2.0)
    again = hemisphere_die(10.0, 17.0, rings=8, rim=2.0)
    np.testing.assert_array_equal(again.points, first.points)
    np.testing.assert_array_equal(again.triangles, first.triangles)
    assert not np.shares_memory(again.points, first.points)
    assert not np.shares_memory(again.triangles, first.triangles)
    other = hemisphere_die(10.0, 17.0, rings=8, rim=1.0)  # another rim, another die
    assert other.points.shape != first.points.shape or not np.array_equal(
        other.points, first.points
    )
