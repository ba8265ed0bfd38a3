"""A meshed rigid tool whose neighbouring facets face opposite ways is refused, naming them:
the side a point is on would change from facet to facet (a point 5 mm above a flat table of
two facets, one flipped, was 5 mm inside it: signed distances +5 and -5). The rule is the one
the shell mesh follows (femcore.topology.check_orientation): neighbours run their shared edge
in opposite directions. Separate pieces may each face their own way."""

import numpy as np
import pytest

from elements import RigidSurface
from femcore import Mesh

TABLE = np.array(
    [[-50.0, -50.0, 0.0], [250.0, -50.0, 0.0], [250.0, 150.0, 0.0], [-50.0, 150.0, 0.0]]
)


def test_a_table_with_one_facet_flipped_is_refused_naming_both_facets():
    flipped = Mesh(TABLE, triangles=[[0, 1, 2], [0, 3, 2]])
    with pytest.raises(ValueError, match=r"facets 0 and 1 both run their shared edge 2 -> 0 the "
                                         r"same way: .* reorient the facets"):  # fmt: skip
        RigidSurface(flipped)


def test_a_consistent_table_puts_points_above_it_on_its_side():
    """The same table with both facets counter-clockwise seen from +z: both points +5 mm."""
    tool = RigidSurface(Mesh(TABLE, triangles=[[0, 1, 2], [0, 2, 3]]))
    distance = tool.distance(np.array([[200.0, 0.0, 5.0], [0.0, 100.0, 5.0]]))[0]
    np.testing.assert_allclose(distance, [5.0, 5.0], rtol=0.0, atol=1e-12)


def test_separate_pieces_may_face_their_own_ways():
    """A table facing +z and, apart from it, a plate facing -z (a holder above): no shared
    edge, nothing to disagree about."""
    holder = TABLE + [0.0, 0.0, 10.0]
    points = np.vstack([TABLE, holder])
    tool = RigidSurface(Mesh(points, triangles=[[0, 1, 2], [0, 2, 3], [4, 6, 5], [4, 7, 6]]))
    distance = tool.distance(np.array([[200.0, 0.0, 5.0], [0.0, 100.0, 5.0]]))[0]
    np.testing.assert_allclose(distance, [5.0, 5.0], rtol=0.0, atol=1e-12)
