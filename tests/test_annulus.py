"""elements.annulus.RigidAnnulus, a flat ring (a blank holder's face with a bore): over its
face the plane's signed distance, over the bore the distance to the inner edge's circle (closed
forms), continuous across the edge, and bad input refused."""

import math

import numpy as np
import pytest

from elements.annulus import RigidAnnulus


def test_over_the_face_the_distance_is_the_planes_and_over_the_bore_the_edges():
    """A ring at z = 0.3 facing down (-z), bore 60 mm. At radius 70 (face): d = 0.3 - z, n = -z.
    At radius 57, z = -3.7 (bore): the edge circle's nearest point is (60, 0, 0.3), d =
    hypot(3, 4) = 5, n = (-3, 0, -4) / 5 (closed form, to round-off)."""
    ring = RigidAnnulus((0.0, 0.0, 0.3), (0.0, 0.0, -1.0), 60.0)
    x = np.array([[70.0, 0.0, 0.1], [0.0, -70.0, 0.5], [57.0, 0.0, -3.7], [0.0, 57.0, -3.7]])
    d, n = ring.distance(x)
    assert d == pytest.approx([0.2, -0.2, 5.0, 5.0], abs=1e-12)
    assert np.allclose(n[:2], [0.0, 0.0, -1.0], atol=1e-15)
    assert np.allclose(n[2], [-0.6, 0.0, -0.8], atol=1e-15)
    assert np.allclose(n[3], [0.0, -0.6, -0.8], atol=1e-15)


def test_the_distance_is_continuous_across_the_inner_edge_on_the_bodys_side():
    """A point under the face (z below the ring) crossing the edge radius: d changes by less
    than the radial step (the edge's distance is hypot(step, height) there)."""
    ring = RigidAnnulus((0.0, 0.0, 0.3), (0.0, 0.0, -1.0), 60.0)
    step = 1e-6
    x = np.array([[60.0 + step, 0.0, 0.15], [60.0 - step, 0.0, 0.15]])
    d, _ = ring.distance(x)
    assert abs(d[0] - d[1]) < 2.0 * step
    assert d[0] == pytest.approx(0.15, abs=1e-12)


def test_a_moved_ring_measures_from_where_it_is():
    """Translated by (0, 0, 2) at the end of a linear motion: the face 2 mm higher at tau 1."""
    ring = RigidAnnulus((0.0, 0.0, 0.0), (0.0, 0.0, -1.0), 10.0, motion=(0.0, 0.0, 2.0))
    d, _ = ring.distance(np.array([[20.0, 0.0, 0.0]]), 1.0)
    assert d[0] == pytest.approx(2.0, abs=1e-12)


def test_the_projector_scale_is_zero_on_the_face_and_one_over_the_edge_distance_in_the_bore():
    ring = RigidAnnulus((0.0, 0.0, 0.0), (0.0, 0.0, -1.0), 60.0)
    scale = ring.projector_scale(np.array([[65.0, 0.0, -1.0], [57.0, 0.0, -4.0]]))
    assert scale == pytest.approx([0.0, 0.2], abs=1e-15)


@pytest.mark.parametrize("inner", [0.0, -1.0, math.inf, math.nan])
def test_a_ring_without_a_positive_finite_bore_is_refused(inner):
    with pytest.raises(ValueError, match="inner"):
        RigidAnnulus((0.0, 0.0, 0.0), (0.0, 0.0, -1.0), inner)
