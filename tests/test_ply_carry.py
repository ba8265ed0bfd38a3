"""The ply contact's Hessian over its points' z carried to the nodes' (u, psi)
(elements/ply_block.py ``carried_to_nodes``) against the whole map's contraction M^T H M, the
tangent's former form, to round-off."""

import numpy as np
import pytest

from elements.ply_block import carried_to_nodes
from femcore.rotation import cross_matrix


def whole_map(points, shape, offset, d):
    """M^T H M with the map M (t, Z, 3, Z + 2, 6) written out, zeros and all."""
    t, z = points.shape[:2]
    nodes = z + 2
    own = np.zeros((t, nodes, 3, 6))
    own[:, :, :, :3] = np.eye(3)
    own[:, :, :, 3:] = -offset[:, :, None, None] * cross_matrix(d)
    maps = np.zeros((t, z, 3, nodes, 6))
    for j in range(3):
        maps[:, 0, :, j, :] = shape[:, j, None, None] * own[:, j]
    for k in range(1, z):
        maps[:, k, :, 2 + k, :] = own[:, 2 + k]
    carried = np.einsum("tzisj,tsjcb->tzicb", points, maps)
    return np.einsum("tzira,tzicb->tracb", maps, carried)


@pytest.mark.parametrize("z", [4, 6])  # the contact's (p, y_1..3), the fade's (.., a, b)
def test_carried_to_nodes_is_the_whole_maps_product(z):
    rng = np.random.default_rng(7)
    t = 40
    points = rng.normal(size=(t, z, 3, z, 3))
    points = points + points.transpose(0, 3, 4, 1, 2)  # a Hessian is symmetric
    shape = rng.dirichlet(np.ones(3), size=t)
    offset = rng.normal(scale=0.5, size=(t, z + 2))
    d = rng.normal(size=(t, z + 2, 3))
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    expected = whole_map(points, shape, offset, d)
    got = carried_to_nodes(points, shape, offset, d)
    assert got.shape == (t, z + 2, 6, z + 2, 6)
    # the same products summed in another order: round-off of the largest entry
    assert np.abs(got - expected).max() <= 1e-12 * np.abs(expected).max()
    # symmetric as the Hessian it carries
    assert np.abs(got - got.transpose(0, 3, 4, 1, 2)).max() <= 1e-12 * np.abs(got).max()
