"""Specification of femcore.topology: edges, neighbours, apexes, checks and nodal normals."""

import numpy as np
import pytest

from femcore.mesh import Mesh
from femcore.topology import (
    build_topology,
    check_duplicate_nodes,
    check_orientation,
    check_triangles,
    check_zero_area,
    nodal_normals,
    validate_cells,
)

# Side s of a triangle is opposite local node s (0-based): it joins these local nodes.
SIDE_NODES = np.array([[1, 2], [2, 0], [0, 1]])


@pytest.fixture
def plate() -> Mesh:
    return Mesh.rectangle(3.0, 2.0, 3, 2)


# ---------------------------------------------------------------------------------------------
# edges, neighbours, apexes
# ---------------------------------------------------------------------------------------------


def test_edge_counts_of_a_rectangle(plate):
    topo = build_topology(plate.triangles)
    m, b = plate.n_triangles, len(topo.boundary_edges)
    assert b == 2 * (3 + 2)
    interior = topo.n_edges - b
    assert 3 * m == 2 * interior + b  # every interior edge has two sides, boundary ones one
    assert interior == (3 * m - b) // 2 == 13
    assert plate.n_nodes - topo.n_edges + m == 1  # Euler characteristic of a disc


def test_edges_are_unique_sorted_pairs_in_lexicographic_order(plate):
    edges = build_topology(plate.triangles).edges
    assert edges.dtype == np.int64
    assert np.all(edges[:, 0] < edges[:, 1])
    order = np.lexsort((edges[:, 1], edges[:, 0]))
    np.testing.assert_array_equal(order, np.arange(len(edges)))
    assert len(np.unique(edges, axis=0)) == len(edges)


def test_side_s_is_opposite_local_node_s(plate):
    topo = build_topology(plate.triangles)
    for s, (a, b) in enumerate(SIDE_NODES):
        side = np.sort(plate.triangles[:, [a, b]], axis=1)
        np.testing.assert_array_equal(topo.edges[topo.triangle_edges[:, s]], side)


def test_every_interior_neighbour_points_back_across_the_same_edge(plate):
    topo = build_topology(plate.triangles)
    t, s = np.nonzero(topo.neighbour >= 0)
    other = topo.neighbour[t, s]
    back = topo.neighbour[other] == t[:, None]  # (k, 3): which side of `other` faces t
    assert np.all(back.sum(axis=1) == 1)
    np.testing.assert_array_equal(topo.triangle_edges[other][back], topo.triangle_edges[t, s])


def test_apex_is_the_neighbour_node_off_the_shared_side(plate):
    topo = build_topology(plate.triangles)
    t, s = np.nonzero(topo.neighbour >= 0)
    apex = topo.apex[t, s]
    side = plate.triangles[t[:, None], SIDE_NODES[s]]
    assert not np.any(side == apex[:, None])
    assert np.all(np.any(plate.triangles[topo.neighbour[t, s]] == apex[:, None], axis=1))


def test_boundary_sides_have_no_neighbour_and_no_apex(plate):
    topo = build_topology(plate.triangles)
    on_boundary = topo.neighbour < 0
    np.testing.assert_array_equal(on_boundary, topo.apex < 0)
    boundary_ids = np.flatnonzero(topo.edge_triangles[:, 1] < 0)
    np.testing.assert_array_equal(topo.edges[boundary_ids], topo.boundary_edges)
    np.testing.assert_array_equal(np.sort(topo.triangle_edges[on_boundary]), boundary_ids)


def test_edge_triangles_agree_with_triangle_edges(plate):
    topo = build_topology(plate.triangles)
    for column in range(2):
        t = topo.edge_triangles[:, column]
        has = t >= 0
        owns = topo.triangle_edges[t[has]] == np.flatnonzero(has)[:, None]
        assert np.all(owns.any(axis=1))


def test_topology_arrays_are_read_only(plate):
    topo = plate.topology
    with pytest.raises(ValueError):
        topo.neighbour[0, 0] = 3


# ---------------------------------------------------------------------------------------------
# checks
# ---------------------------------------------------------------------------------------------


def test_a_generated_mesh_passes_all_checks(plate):
    check_triangles(plate.points, plate.triangles)


def test_non_manifold_edge_names_its_nodes_and_triangles():
    points = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1]]
    triangles = [[0, 1, 2], [1, 0, 3], [0, 1, 4]]
    with pytest.raises(ValueError, match=r"non-manifold edge \(0, 1\).*triangles \[0, 1, 2\]"):
        build_topology(triangles)
    with pytest.raises(ValueError, match=r"non-manifold"):
        check_triangles(points, triangles)


def test_inconsistent_orientation_names_both_triangles():
    points = [[0, 0], [1, 0], [0, 1], [0, -1]]
    triangles = [[0, 1, 2], [0, 1, 3]]  # both traverse 0 -> 1
    with pytest.raises(
        ValueError, match=r"triangles 0 and 1 have inconsistent orientation.*edge 0 -> 1"
    ):
        check_orientation(triangles)
    with pytest.raises(ValueError, match=r"inconsistent orientation"):
        check_triangles(points, triangles)


def test_duplicate_nodes_are_named():
    points = [[0, 0], [1, 0], [0, 1], [1, 1], [1.0 + 1e-12, 0]]
    triangles = [[0, 1, 2], [4, 3, 2]]  # node 4 should have been node 1
    with pytest.raises(ValueError, match=r"duplicate nodes 1 and 4"):
        check_duplicate_nodes(points, triangles)
    with pytest.raises(ValueError, match=r"duplicate nodes 1 and 4"):
        check_triangles(points, triangles)


def test_nodes_unused_by_triangles_are_not_compared():
    points = [[0, 0], [1, 0], [0, 1], [1, 0]]  # node 3: e.g. a cable node on top of node 1
    check_duplicate_nodes(points, [[0, 1, 2]])
    with pytest.raises(ValueError, match=r"duplicate nodes 1 and 3"):
        check_duplicate_nodes(points)


def test_zero_area_triangle_is_named():
    points = [[0, 0], [1, 0], [0, 1], [2, 0]]
    triangles = [[0, 1, 2], [0, 3, 1]]  # collinear
    with pytest.raises(ValueError, match=r"triangle 1 with nodes \(0, 3, 1\) has zero area"):
        check_zero_area(points, triangles)
    with pytest.raises(ValueError, match=r"zero area"):
        check_triangles(points, triangles)


def test_invalid_connectivity_is_rejected():
    with pytest.raises(ValueError, match=r"triangle 0 refers to node 5"):
        check_triangles([[0, 0], [1, 0], [0, 1]], [[0, 1, 5]])
    with pytest.raises(ValueError, match=r"triangle 0 is degenerate"):
        build_topology([[0, 1, 0]])


@pytest.mark.parametrize("pair", [(0, 1), (1, 2), (0, 2)])
def test_the_first_cell_that_repeats_a_node_is_named_whichever_corners_repeat(pair):
    cells = np.array([[0, 1, 2], [1, 3, 2], [3, 4, 2], [4, 5, 2], [5, 6, 2]])
    cells[4] = [7, 7, 7]
    cells[3, pair[1]] = cells[3, pair[0]]
    with pytest.raises(ValueError, match=r"triangle 3 is degenerate: it repeats a node"):
        validate_cells(cells, 3, "triangle")
    with pytest.raises(ValueError, match=r"line 1 is degenerate"):
        validate_cells([[0, 1], [2, 2], [3, 3]], 2, "line")
    validate_cells(cells[:3], 3, "triangle")  # no repeat: accepted


# ---------------------------------------------------------------------------------------------
# nodal normals
# ---------------------------------------------------------------------------------------------


def test_nodal_normals_of_a_flat_mesh_are_plus_z(plate):
    normals = nodal_normals(plate.points, plate.triangles)
    np.testing.assert_allclose(normals, np.tile([0.0, 0.0, 1.0], (plate.n_nodes, 1)))


def test_nodal_normals_follow_a_rotation(plate):
    angle = 0.3
    rotation = np.array(
        [[1.0, 0.0, 0.0], [0.0, np.cos(angle), -np.sin(angle)], [0.0, np.sin(angle), np.cos(angle)]]
    )
    tilted = plate.with_points(plate.points @ rotation.T)
    normals = nodal_normals(tilted.points, tilted.triangles)
    np.testing.assert_allclose(normals, np.tile(rotation[:, 2], (plate.n_nodes, 1)), atol=1e-14)


def test_nodal_normals_are_area_weighted_and_zero_on_unused_nodes():
    # Two consistently oriented triangles folded 90 degrees along the x axis: one of area 1
    # facing +z, one of area 0.5 hanging down and facing -y. Node 4 belongs to no triangle.
    points = [[0, 0, 0], [1, 0, 0], [0, 2, 0], [0, 0, -1], [5, 5, 5]]
    triangles = [[0, 1, 2], [0, 3, 1]]
    normals = nodal_normals(points, triangles)
    expected = np.array([0.0, -0.5, 1.0]) / np.linalg.norm([0.0, -0.5, 1.0])
    np.testing.assert_allclose(normals[[0, 1]], [expected, expected])
    np.testing.assert_allclose(normals[2], [0.0, 0.0, 1.0])
    np.testing.assert_allclose(normals[3], [0.0, -1.0, 0.0])
    np.testing.assert_array_equal(normals[4], [0.0, 0.0, 0.0])
