"""Specification of femcore.mesh.Mesh: construction, generators, selections and file I/O."""

import gmsh
import meshio
import numpy as np
import pytest

from femcore.mesh import Mesh

# ---------------------------------------------------------------------------------------------
# helpers
# ---------------------------------------------------------------------------------------------


def local_edges(mesh: Mesh) -> tuple[np.ndarray, np.ndarray]:
    """Edge vectors (m, 3) from local node 1 to 2 and from local node 1 to 3 (1-based)."""
    x = mesh.points[mesh.triangles]
    return x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]


def total_area(mesh: Mesh) -> float:
    e12, e13 = local_edges(mesh)
    return 0.5 * np.linalg.norm(np.cross(e12, e13), axis=1).sum()


def triangle_geometry(mesh: Mesh) -> list[tuple]:
    """Sorted list of triangles, each the sorted tuple of its rounded vertex coordinates."""
    x = np.round(mesh.points[mesh.triangles], 9)
    return sorted(tuple(sorted(map(tuple, tri.tolist()))) for tri in x)


def parallel(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise: is a parallel (or antiparallel) to the single vector b?"""
    return np.linalg.norm(np.cross(a, b), axis=1) <= 1e-9 * np.linalg.norm(a, axis=1) * (
        np.linalg.norm(b)
    )


# ---------------------------------------------------------------------------------------------
# construction and validation
# ---------------------------------------------------------------------------------------------


def test_points_are_stored_as_read_only_3d_float_and_2d_points_get_z_zero():
    mesh = Mesh([[0, 0], [1, 0], [0, 1]], [[0, 1, 2]])
    assert mesh.points.shape == (3, 3) and mesh.points.dtype == np.float64
    assert np.all(mesh.points[:, 2] == 0.0)
    assert mesh.triangles.dtype == np.int64 and mesh.lines.shape == (0, 2)
    with pytest.raises(ValueError):
        mesh.points[0, 0] = 5.0  # read-only: a checked mesh cannot be changed behind its back


def test_non_finite_coordinate_names_the_node():
    with pytest.raises(ValueError, match=r"node 2 has a non-finite coordinate"):
        Mesh([[0, 0, 0], [1, 0, 0], [0, np.nan, 0]], [[0, 1, 2]])


def test_node_id_out_of_range_names_the_cell_and_the_id():
    with pytest.raises(ValueError, match=r"triangle 1 refers to node 7"):
        Mesh([[0, 0], [1, 0], [0, 1], [1, 1]], [[0, 1, 2], [1, 3, 7]])
    with pytest.raises(ValueError, match=r"line 0 refers to node -1"):
        Mesh([[0, 0], [1, 0]], lines=[[-1, 1]])


def test_cell_repeating_a_node_is_degenerate():
    with pytest.raises(ValueError, match=r"triangle 0 is degenerate"):
        Mesh([[0, 0], [1, 0], [0, 1]], [[0, 1, 1]])


@pytest.mark.parametrize(
    ("points", "cells", "message"),
    [
        ([[0, 0, 0, 0]], None, r"points must have shape \(n, 3\) or \(n, 2\)"),
        (np.zeros((0, 3)), None, r"n >= 1"),
        ([[0, 0], [1, 0], [0, 1]], [[0, 1]], r"triangle cells must have shape \(k, 3\)"),
        ([[0, 0], [1, 0], [0, 1]], [[0.0, 1.0, 2.0]], r"integer node ids"),
    ],
)
def test_wrong_shapes_and_dtypes_are_rejected(points, cells, message):
    with pytest.raises(ValueError, match=message):
        Mesh(points, cells)


def test_sets_are_validated_and_never_overwritten():
    mesh = Mesh.rectangle(1.0, 1.0, 1, 1)
    mesh.add_node_set("corner", [3, 0, 0])
    np.testing.assert_array_equal(mesh.node_sets["corner"], [0, 3])  # sorted, unique
    mesh.add_element_set("lower", np.array([True, False]))  # a bool mask works too
    np.testing.assert_array_equal(mesh.element_sets["lower"], [0])
    with pytest.raises(ValueError, match=r"node set 'far' refers to node 4"):
        mesh.add_node_set("far", [4])
    with pytest.raises(ValueError, match=r"element set 'corner' refers to triangle 2"):
        mesh.add_element_set("corner", [2])
    with pytest.raises(ValueError, match=r"node set 'corner' already exists"):
        mesh.add_node_set("corner", [1])
    with pytest.raises(ValueError, match=r"must not contain"):
        mesh.add_node_set("a,b", [1])


def test_set_views_cannot_be_modified():
    mesh = Mesh.rectangle(1.0, 1.0, 1, 1)
    with pytest.raises(TypeError):
        mesh.node_sets["x"] = np.array([0])  # type: ignore[index]


def test_check_runs_the_topology_checks():
    mesh = Mesh([[0, 0], [1, 0], [0, 1], [0, 1]], [[0, 1, 2], [0, 1, 3]])
    with pytest.raises(ValueError, match=r"inconsistent orientation"):
        mesh.check()
    Mesh.rectangle(2.0, 1.0, 4, 2).check()  # a generated mesh passes


# ---------------------------------------------------------------------------------------------
# Mesh.rectangle
# ---------------------------------------------------------------------------------------------


def test_rectangle_counts_and_node_numbering():
    mesh = Mesh.rectangle(3.0, 2.0, 3, 2, origin=(1.0, -1.0, 0.5))
    assert mesh.n_nodes == 4 * 3 and mesh.n_triangles == 2 * 3 * 2 and mesh.n_lines == 0
    i, j = 2, 1
    np.testing.assert_allclose(mesh.points[j * 4 + i], [1.0 + 2.0, -1.0 + 1.0, 0.5])
    lo, hi = mesh.bounding_box()
    np.testing.assert_allclose(lo, [1.0, -1.0, 0.5])
    np.testing.assert_allclose(hi, [4.0, 1.0, 0.5])


def test_rectangle_cell_order_and_split_follow_the_spec():
    mesh = Mesh.rectangle(3.0, 2.0, 3, 2)
    # cell (i=0, j=0): T_A = (P00, P10, P01), T_B = (P11, P01, P10); then cell (1, 0).
    np.testing.assert_array_equal(mesh.triangles[:4], [[0, 1, 4], [5, 4, 1], [1, 2, 5], [6, 5, 2]])
    # last cell (i=2, j=1)
    np.testing.assert_array_equal(mesh.triangles[-2:], [[6, 7, 10], [11, 10, 7]])


def test_rectangle_triangles_are_right_angled_fibre_aligned_and_face_plus_z():
    mesh = Mesh.rectangle(3.0, 2.0, 6, 5)
    e12, e13 = local_edges(mesh)
    normal = np.cross(e12, e13)
    assert np.all(normal[:, 2] > 0.0) and np.allclose(normal[:, :2], 0.0)
    np.testing.assert_allclose(np.einsum("ij,ij->i", e12, e13), 0.0, atol=1e-14)
    # edge 1 -> 2 along +x or -x (warp), edge 1 -> 3 along +y or -y (weft)
    np.testing.assert_allclose(np.abs(e12), np.tile([0.5, 0.0, 0.0], (mesh.n_triangles, 1)))
    np.testing.assert_allclose(np.abs(e13), np.tile([0.0, 0.4, 0.0], (mesh.n_triangles, 1)))
    assert total_area(mesh) == pytest.approx(3.0 * 2.0)


def test_rectangle_side_sets_and_element_set():
    mesh = Mesh.rectangle(3.0, 2.0, 3, 2)
    x, y = mesh.points[:, 0], mesh.points[:, 1]
    np.testing.assert_array_equal(mesh.nodes("left"), np.flatnonzero(x == 0.0))
    np.testing.assert_array_equal(mesh.nodes("right"), np.flatnonzero(x == 3.0))
    np.testing.assert_array_equal(mesh.nodes("bottom"), np.flatnonzero(y == 0.0))
    np.testing.assert_array_equal(mesh.nodes("top"), np.flatnonzero(y == 2.0))
    np.testing.assert_array_equal(mesh.element_sets["all"], np.arange(12))


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ((0.0, 1.0, 2, 2), r"lx must be a positive"),
        ((1.0, np.inf, 2, 2), r"ly must be a positive"),
        ((1.0, 1.0, 0, 2), r"nx must be a positive integer"),
        ((1.0, 1.0, 2, 2.0), r"ny must be a positive integer"),
    ],
)
def test_rectangle_rejects_bad_dimensions(args, message):
    with pytest.raises(ValueError, match=message):
        Mesh.rectangle(*args)


# ---------------------------------------------------------------------------------------------
# Mesh.line
# ---------------------------------------------------------------------------------------------


def test_line_mesh():
    mesh = Mesh.line([0.0, 0.0], [2.0, 0.0, 2.0], 4)
    assert mesh.n_nodes == 5 and mesh.n_lines == 4 and mesh.n_triangles == 0
    np.testing.assert_allclose(mesh.points[2], [1.0, 0.0, 1.0])
    np.testing.assert_array_equal(mesh.lines[1], [1, 2])
    np.testing.assert_array_equal(mesh.nodes("start"), [0])
    np.testing.assert_array_equal(mesh.nodes("end"), [4])
    np.testing.assert_array_equal(mesh.line_sets["all"], np.arange(4))
    with pytest.raises(ValueError, match=r"p0 and p1 must differ"):
        Mesh.line([1, 1], [1, 1], 2)


# ---------------------------------------------------------------------------------------------
# node selection
# ---------------------------------------------------------------------------------------------


def test_corner_is_the_free_triangle_beyond_the_diagonal():
    """Mesh.corner (Bai §6): the triangles of Mesh.rectangle(n x n) before the diagonal from
    (lx, 0) to (0, ly), renumbered in order; for n = 2 the numbers the corner specimen of
    the validation report was built from."""
    mesh = Mesh.corner(2.0, 1.0, 2)
    np.testing.assert_array_equal(
        mesh.points, [[0, 0, 0], [1, 0, 0], [2, 0, 0], [0, 0.5, 0], [1, 0.5, 0], [0, 1, 0]]
    )
    np.testing.assert_array_equal(mesh.triangles, [[0, 1, 3], [4, 3, 1], [1, 2, 4], [3, 4, 5]])
    assert {name: ids.tolist() for name, ids in mesh.node_sets.items()} == {
        "clamp": [2, 4, 5],
        "corner": [0],
    }
    assert not mesh.element_sets and mesh.n_lines == 0


def test_corner_of_the_paper_size_clamps_the_diagonal_and_covers_half_the_rectangle():
    lx, ly, n = 210.0, 148.0, 20
    mesh = Mesh.corner(lx, ly, n)
    mesh.check()
    assert (mesh.n_nodes, mesh.n_triangles) == ((n + 1) * (n + 2) // 2, n * n)
    x = mesh.points[mesh.triangles]
    area = 0.5 * np.cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0])[:, 2]
    assert area.min() > 0.0
    np.testing.assert_allclose(area.sum(), 0.5 * lx * ly, rtol=1e-12)
    clamp = mesh.points[mesh.nodes("clamp")]
    assert len(clamp) == n + 1
    np.testing.assert_allclose(clamp[:, 0] / lx + clamp[:, 1] / ly, 1.0, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(mesh.points[mesh.nodes("corner")], [[0.0, 0.0, 0.0]])
    # The validation report's specimen is this mesh, its clamp and its loaded corner.
    from validation import specimens

    specimen = specimens.corner(lx, ly, n)
    np.testing.assert_array_equal(specimen.mesh.points, mesh.points)
    np.testing.assert_array_equal(specimen.mesh.triangles, mesh.triangles)
    np.testing.assert_array_equal(specimen.clamp, mesh.nodes("clamp"))
    np.testing.assert_array_equal(specimen.loaded, mesh.nodes("corner"))


@pytest.mark.parametrize("n", [4, 8, 20, 33])
def test_a_gripped_corner_has_the_same_patch_at_every_resolution(n):
    """Mesh.corner(grip=a): the a x b patch at the corner is bounded by grid lines whatever n
    (node set "grip": the nodes with x <= a and y <= b, the lines x = a and y = b among
    them), the clamp is still the diagonal, a line of cell diagonals, the triangles cover the
    free triangle, and the grid is nearly uniform: the patch's cells no longer than lx / n,
    ly / n, the others no longer than the uniform grid's of two cells fewer."""
    lx, ly, a, b = 200.0, 150.0, 10.0, 12.0
    mesh = Mesh.corner(lx, ly, n, grip=(a, b))
    mesh.check()
    assert (mesh.n_nodes, mesh.n_triangles) == ((n + 1) * (n + 2) // 2, n * n)
    p = mesh.points
    grip = p[mesh.nodes("grip")]
    assert grip[:, 0].max() == pytest.approx(a, abs=1e-12)
    assert grip[:, 1].max() == pytest.approx(b, abs=1e-12)
    inside = (p[:, 0] <= a + 1e-9) & (p[:, 1] <= b + 1e-9)
    np.testing.assert_array_equal(mesh.nodes("grip"), np.flatnonzero(inside))
    clamp = p[mesh.nodes("clamp")]
    assert len(clamp) == n + 1
    np.testing.assert_allclose(clamp[:, 0] / lx + clamp[:, 1] / ly, 1.0, rtol=0, atol=1e-12)
    x = p[mesh.triangles]
    area = 0.5 * np.cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0])[:, 2]
    assert area.min() > 0.0
    np.testing.assert_allclose(area.sum(), 0.5 * lx * ly, rtol=1e-12)
    for axis, length, size in ((0, lx, a), (1, ly, b)):
        spacing = np.diff(np.unique(np.round(p[:, axis], 9)))
        lines = np.unique(np.round(p[:, axis], 9))
        assert spacing[lines[1:] <= size + 1e-9].max() <= length / n * (1 + 1e-9)
        assert spacing.max() <= length / (n - 2) * (1 + 1e-9)


def test_a_grip_that_does_not_fit_is_refused():
    with pytest.raises(ValueError, match="a / lx [+] b / ly < 1"):
        Mesh.corner(200.0, 150.0, 8, grip=120.0)
    with pytest.raises(ValueError, match="positive"):
        Mesh.corner(200.0, 150.0, 8, grip=(10.0, -1.0))
    with pytest.raises(ValueError, match="give n >= 3"):
        Mesh.corner(200.0, 150.0, 2, grip=10.0)


def test_nodes_calls_the_predicate_once_with_coordinate_arrays():
    mesh = Mesh.rectangle(3.0, 2.0, 3, 2)
    calls = []

    def on_left_or_top(x, y, z):
        calls.append((x.shape, y.shape, z.shape))
        return np.isclose(x, 0.0) | np.isclose(y, 2.0)

    ids = mesh.nodes(on_left_or_top)
    assert calls == [((12,), (12,), (12,))]
    np.testing.assert_array_equal(ids, [0, 4, 8, 9, 10, 11])
    assert ids.dtype == np.int64


def test_empty_selection_is_an_error():
    mesh = Mesh.rectangle(3.0, 2.0, 3, 2)
    with pytest.raises(ValueError, match=r"selected no node"):
        mesh.nodes(lambda x, y, z: x > 10.0)
    mesh.add_node_set("nothing", [])
    with pytest.raises(ValueError, match=r"node set 'nothing' selected no node"):
        mesh.nodes("nothing")


def test_bad_selections_are_errors():
    mesh = Mesh.rectangle(3.0, 2.0, 3, 2)
    with pytest.raises(ValueError, match=r"shape \(\), expected \(12,\)"):
        mesh.nodes(lambda x, y, z: True)
    with pytest.raises(ValueError, match=r"dtype float64, expected bool"):
        mesh.nodes(lambda x, y, z: x)
    with pytest.raises(ValueError, match=r"unknown node set 'middle'"):
        mesh.nodes("middle")


# ---------------------------------------------------------------------------------------------
# Mesh.with_points
# ---------------------------------------------------------------------------------------------


def test_with_points_moves_nodes_and_keeps_cells_and_sets():
    mesh = Mesh.rectangle(3.0, 2.0, 3, 2)
    rotation = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    moved = mesh.with_points(mesh.points @ rotation.T + [0.0, 0.0, 1.0])
    np.testing.assert_array_equal(moved.triangles, mesh.triangles)
    np.testing.assert_array_equal(moved.nodes("left"), mesh.nodes("left"))
    np.testing.assert_allclose(moved.points[mesh.nodes("right")][:, 1], 3.0)
    with pytest.raises(ValueError, match=r"points must have 12 rows"):
        mesh.with_points(mesh.points[:5])


# ---------------------------------------------------------------------------------------------
# Mesh.quadrilateral (gmsh)
# ---------------------------------------------------------------------------------------------


def test_quadrilateral_of_a_rectangle_matches_rectangle():
    reference = Mesh.rectangle(3.0, 2.0, 3, 2)
    mesh = Mesh.quadrilateral([[0, 0], [3, 0], [3, 2], [0, 2]], 3, 2)
    assert triangle_geometry(mesh) == triangle_geometry(reference)
    e12, e13 = local_edges(mesh)
    # gmsh's transfinite interpolation places nodes to ~1e-12, hence the tolerances.
    np.testing.assert_allclose(np.einsum("ij,ij->i", e12, e13), 0.0, atol=1e-9)
    assert parallel(e12, np.array([1.0, 0.0, 0.0])).all()
    assert parallel(e13, np.array([0.0, 1.0, 0.0])).all()
    # The documented numbering coincides with rectangle() as well.
    np.testing.assert_allclose(mesh.points, reference.points, atol=1e-9)
    np.testing.assert_array_equal(mesh.triangles, reference.triangles)
    np.testing.assert_array_equal(mesh.nodes("left"), reference.nodes("left"))


def test_quadrilateral_of_a_skewed_parallelogram_in_3d():
    c0 = np.array([1.0, 0.0, 2.0])
    warp, weft = np.array([4.0, 0.0, 1.0]), np.array([1.0, 2.0, 0.0])
    corners = [c0, c0 + warp, c0 + warp + weft, c0 + weft]
    mesh = Mesh.quadrilateral(corners, 4, 3)
    assert mesh.n_nodes == 5 * 4 and mesh.n_triangles == 2 * 4 * 3
    e12, e13 = local_edges(mesh)
    assert parallel(e12, warp).all() and parallel(e13, weft).all()
    normal = np.cross(warp, weft)
    assert np.all(np.cross(e12, e13) @ normal > 0.0)
    assert total_area(mesh) == pytest.approx(np.linalg.norm(normal))
    mesh.check()
    np.testing.assert_allclose(mesh.points[mesh.nodes("top")][-1], c0 + warp + weft)


def test_quadrilateral_leaves_no_gmsh_session_behind():
    assert not gmsh.isInitialized()
    Mesh.quadrilateral([[0, 0], [1, 0], [1, 1], [0, 1]], 1, 1)
    assert not gmsh.isInitialized()


def test_quadrilateral_inside_a_running_gmsh_session_restores_it():
    gmsh.initialize(readConfigFiles=False, interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("user-model")
        Mesh.quadrilateral([[0, 0], [1, 0], [1, 1], [0, 1]], 2, 2)
        assert gmsh.isInitialized()
        assert gmsh.model.getCurrent() == "user-model"
        assert "femcore-quadrilateral" not in gmsh.model.list()
    finally:
        gmsh.finalize()


@pytest.mark.parametrize(
    ("corners", "message"),
    [
        ([[0, 0, 0], [1, 0, 0], [1, 1, 0.1], [0, 1, 0]], r"coplanar"),
        ([[0, 0], [2, 0], [0.5, 0.5], [0, 2]], r"convex"),  # dart: reflex corner 2
        ([[0, 0], [1, 0], [0, 1], [1, 1]], r"convex|self-intersecting"),  # bow tie
        ([[0, 0], [1, 0], [2, 0], [3, 0]], r"no area"),
        ([[0, 0], [1, 0], [1, 1]], r"shape \(4, 3\) or \(4, 2\)"),
    ],
)
def test_quadrilateral_rejects_bad_corners(corners, message):
    with pytest.raises(ValueError, match=message):
        Mesh.quadrilateral(corners, 2, 2)


# ---------------------------------------------------------------------------------------------
# file I/O
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("suffix", [".vtu", ".msh", ".inp"])
def test_triangle_mesh_round_trip_keeps_cells_and_sets(tmp_path, suffix):
    mesh = Mesh.rectangle(3.0, 2.0, 3, 2, origin=(0.0, 0.0, 1.5))
    mesh.add_element_set("first_cell", [0, 1])
    path = tmp_path / f"plate{suffix}"
    mesh.write(path)
    back = Mesh.read(path)
    np.testing.assert_allclose(back.points, mesh.points)
    np.testing.assert_array_equal(back.triangles, mesh.triangles)
    assert set(back.node_sets) == set(mesh.node_sets)
    for name, ids in mesh.node_sets.items():
        np.testing.assert_array_equal(back.node_sets[name], ids)
    for name, ids in mesh.element_sets.items():
        np.testing.assert_array_equal(back.element_sets[name], ids)


@pytest.mark.parametrize("suffix", [".vtu", ".msh", ".inp"])
def test_line_mesh_round_trip(tmp_path, suffix):
    mesh = Mesh.line([0.0, 0.0, 0.0], [1.0, 2.0, 3.0], 3)
    path = tmp_path / f"cable{suffix}"
    mesh.write(path)
    back = Mesh.read(path)
    np.testing.assert_allclose(back.points, mesh.points)
    np.testing.assert_array_equal(back.lines, mesh.lines)
    np.testing.assert_array_equal(back.nodes("end"), [3])
    np.testing.assert_array_equal(back.line_sets["all"], np.arange(3))


@pytest.mark.parametrize("suffix", [".vtu", ".inp"])
def test_mixed_mesh_round_trip_keeps_element_and_line_sets(tmp_path, suffix):
    plate = Mesh.rectangle(1.0, 1.0, 2, 2)
    mesh = Mesh(
        plate.points,
        plate.triangles,
        lines=[[0, 1], [1, 2]],
        element_sets={"a": [3]},
        line_sets={"cable": [1]},
    )
    mesh.write(tmp_path / f"mixed{suffix}")
    back = Mesh.read(tmp_path / f"mixed{suffix}")
    np.testing.assert_array_equal(back.lines, mesh.lines)
    np.testing.assert_array_equal(back.element_sets["a"], [3])
    np.testing.assert_array_equal(back.line_sets["cable"], [1])


def test_read_pads_2d_points_and_ignores_vertex_cells(tmp_path):
    path = tmp_path / "flat.inp"  # node lines without z: z = 0, as Abaqus reads them
    points_2d = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    path.write_text("*NODE\n1, 0., 0.\n2, 1., 0.\n3, 0., 1.\n*ELEMENT, TYPE=S3\n1, 1, 2, 3\n")
    back = Mesh.read(path)
    np.testing.assert_allclose(back.points, [[0, 0, 0], [1, 0, 0], [0, 1, 0]])
    path = tmp_path / "with_vertex.vtu"
    cells = [("vertex", np.array([[0]])), ("triangle", np.array([[0, 1, 2]]))]
    meshio.write(path, meshio.Mesh(np.column_stack((points_2d, np.zeros(3))), cells))
    assert Mesh.read(path).n_triangles == 1


def test_read_rejects_files_without_triangles_or_lines(tmp_path):
    path = tmp_path / "points.vtu"
    meshio.write(path, meshio.Mesh(np.zeros((1, 3)), [("vertex", np.array([[0]]))]))
    with pytest.raises(ValueError, match=r"neither triangle nor line cells"):
        Mesh.read(path)


def test_read_rejects_unsupported_cell_types(tmp_path):
    path = tmp_path / "tetra.vtu"
    points = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    meshio.write(path, meshio.Mesh(points, [("tetra", np.array([[0, 1, 2, 3]]))]))
    with pytest.raises(ValueError, match=r"\['tetra'\] cells"):
        Mesh.read(path)
    quad = tmp_path / "quad.vtu"  # quads are read as two triangles each (from_quads)
    square = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]])
    meshio.write(quad, meshio.Mesh(square, [("quad", np.array([[0, 1, 2, 3]]))]))
    assert Mesh.read(quad).triangles.tolist() == [[0, 1, 3], [2, 3, 1]]


def test_unknown_suffix_missing_file_and_empty_mesh_are_errors(tmp_path):
    with pytest.raises(ValueError, match=r"cannot tell the mesh format"):
        Mesh.rectangle(1.0, 1.0, 1, 1).write(tmp_path / "mesh.unknown")
    with pytest.raises(ValueError, match=r"does not exist"):
        Mesh.read(tmp_path / "missing.vtu")
    with pytest.raises(ValueError, match=r"is a directory"):
        Mesh.read(tmp_path)
    with pytest.raises(ValueError, match=r"neither triangles nor lines"):
        Mesh([[0.0, 0.0]]).write(tmp_path / "empty.vtu")


def test_gmsh_physical_groups_become_sets(tmp_path):
    path = tmp_path / "gmsh.msh"
    gmsh.initialize(readConfigFiles=False, interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        surface = gmsh.model.occ.addRectangle(0.0, 0.0, 0.0, 2.0, 1.0)
        gmsh.model.occ.synchronize()
        gmsh.model.addPhysicalGroup(2, [surface], name="plate")
        gmsh.model.addPhysicalGroup(1, [1], name="edge")
        gmsh.model.addPhysicalGroup(0, [1], name="corner")
        gmsh.option.setNumber("Mesh.MeshSizeMax", 0.5)
        gmsh.model.mesh.generate(2)
        gmsh.write(str(path))
    finally:
        gmsh.finalize()
    mesh = Mesh.read(path)
    mesh.check()
    np.testing.assert_array_equal(mesh.element_sets["plate"], np.arange(mesh.n_triangles))
    np.testing.assert_array_equal(mesh.line_sets["edge"], np.arange(mesh.n_lines))
    assert len(mesh.nodes("corner")) == 1


# ---------------------------------------------------------------------------------------------
# the open vocabulary of cell kinds
# ---------------------------------------------------------------------------------------------


def test_generic_cell_accessors_agree_with_the_named_views():
    plate = Mesh.rectangle(1.0, 1.0, 2, 1)
    mesh = Mesh(
        plate.points,
        plate.triangles,
        lines=[[0, 1], [1, 2]],
        element_sets={"a": [3]},
        line_sets={"cable": [1]},
    )
    assert mesh.cell_kinds == ("triangle", "line")
    assert mesh.cells("triangle") is mesh.triangles and mesh.cells("line") is mesh.lines
    assert dict(mesh.cell_sets("triangle")) == dict(mesh.element_sets)
    np.testing.assert_array_equal(mesh.cell_sets("line")["cable"], [1])
    assert plate.cell_kinds == ("triangle",) and plate.cells("line").shape == (0, 2)
    assert Mesh.line((0, 0), (1, 0), 2).cell_kinds == ("line",)
    with pytest.raises(ValueError, match=r"unknown cell kind 'quad'"):
        mesh.cells("quad")
    with pytest.raises(ValueError, match=r"unknown cell kind"):
        mesh.cell_sets("tetra")


def test_add_cell_set_is_the_generic_form_of_add_element_and_line_set():
    mesh = Mesh.line((0, 0), (3, 0), 3)
    mesh.add_cell_set("line", "middle", [1])
    np.testing.assert_array_equal(mesh.line_sets["middle"], [1])
    with pytest.raises(ValueError, match=r"line set 'middle' already exists"):
        mesh.add_line_set("middle", [0])
    with pytest.raises(ValueError, match=r"element set 'x' refers to triangle 0"):
        mesh.add_cell_set("triangle", "x", [0])


def test_cells_and_cell_sets_keywords_build_the_same_mesh():
    plate = Mesh.rectangle(1.0, 1.0, 1, 1)
    mesh = Mesh(
        plate.points,
        cells={"triangle": plate.triangles, "line": [[0, 1]]},
        cell_sets={"triangle": {"all": [0, 1]}, "line": {"edge": [0]}},
    )
    np.testing.assert_array_equal(mesh.triangles, plate.triangles)
    np.testing.assert_array_equal(mesh.element_sets["all"], [0, 1])
    np.testing.assert_array_equal(mesh.line_sets["edge"], [0])
    with pytest.raises(ValueError, match=r"given twice"):
        Mesh(plate.points, plate.triangles, cells={"triangle": plate.triangles})
    with pytest.raises(ValueError, match=r"given twice"):
        Mesh(plate.points, lines=[[0, 1]], line_sets={}, cell_sets={"line": {}})
    with pytest.raises(ValueError, match=r"unknown cell kind 'quad'"):
        Mesh(plate.points, cells={"quad": [[0, 1, 2, 3]]})


def test_with_points_keeps_every_kind_of_cell_and_set():
    plate = Mesh.rectangle(1.0, 1.0, 1, 1)
    mesh = Mesh(plate.points, plate.triangles, lines=[[0, 3]], line_sets={"diagonal": [0]})
    moved = mesh.with_points(mesh.points + 1.0)
    for kind in ("triangle", "line"):
        np.testing.assert_array_equal(moved.cells(kind), mesh.cells(kind))
        assert dict(moved.cell_sets(kind)).keys() == dict(mesh.cell_sets(kind)).keys()


@pytest.fixture
def with_quads(monkeypatch):
    """CELL_KINDS extended by one entry: a 4-node "quad" kind."""
    from femcore import mesh as mesh_module

    quad = mesh_module.CellKind(4, "quad", 2, "quad set", "qset:")
    monkeypatch.setitem(mesh_module._CELL_KIND_TABLE, "quad", quad)
    return quad


def test_a_new_cell_kind_is_one_table_entry(with_quads, tmp_path):
    points = [[0, 0], [1, 0], [2, 0], [0, 1], [1, 1], [2, 1]]
    mesh = Mesh(
        points,
        triangles=[[1, 2, 4], [2, 5, 4]],
        cells={"quad": [[0, 1, 4, 3]]},
        cell_sets={"quad": {"left": [0]}},
    )
    assert mesh.cell_kinds == ("triangle", "quad")
    assert mesh.cells("quad").shape == (1, 4) and mesh.cells("line").shape == (0, 2)
    with pytest.raises(ValueError, match=r"quad set 'far' refers to quad 1"):
        mesh.add_cell_set("quad", "far", [1])
    for suffix in (".vtu", ".inp"):
        mesh.write(tmp_path / f"mixed{suffix}")
        back = Mesh.read(tmp_path / f"mixed{suffix}")
        np.testing.assert_array_equal(back.cells("quad"), mesh.cells("quad"))
        np.testing.assert_array_equal(back.triangles, mesh.triangles)
        np.testing.assert_array_equal(back.cell_sets("quad")["left"], [0])


def test_a_quad_mesh_is_split_into_fibre_aligned_triangles_on_read(tmp_path):
    """An Abaqus S4R mesh (what a forming engineer's blank often is) is read as triangles: each
    quad (a, b, c, d) gives (a, b, d) and (c, d, b), the split Mesh.rectangle makes, so a grid
    along the fibres gives the same triangles, element sets and a model the fibrous shell
    accepts (one side of each triangle along the warp, one along the weft)."""
    from elements import FibrousShell
    from femcore import Model
    from femcore.mesh_generators import grid_quads
    from materials import presets

    grid = Mesh.rectangle(40.0, 20.0, nx=4, ny=2)
    quads = grid_quads(4, 2)
    path = tmp_path / "blank.inp"  # as Abaqus/CAE writes it: 1-based ids, S4R shells
    nodes = "\n".join(
        f"{i + 1}, {x:.6f}, {y:.6f}, {z:.6f}" for i, (x, y, z) in enumerate(grid.points)
    )
    elements = "\n".join(
        f"{q + 1}, " + ", ".join(str(n + 1) for n in quad) for q, quad in enumerate(quads)
    )
    path.write_text(
        f"*NODE\n{nodes}\n*ELEMENT, TYPE=S4R, ELSET=BLANK\n{elements}\n"
        "*ELSET, ELSET=half\n1, 2, 5, 6\n"
    )
    mesh = Mesh.read(path)
    assert np.array_equal(mesh.triangles, grid.triangles)
    assert np.array_equal(np.sort(mesh.element_sets["half"]), [0, 1, 2, 3, 8, 9, 10, 11])
    model = Model(mesh)
    model.add(FibrousShell(presets.g986_ply()))
    model.compile()
    same = Mesh.from_quads(grid.points, quads, quad_sets={"half": [0, 1, 4, 5]})
    assert np.array_equal(same.triangles, grid.triangles)
    assert np.array_equal(same.element_sets["half"], mesh.element_sets["half"])
    with pytest.raises(ValueError, match=r"shape \(q, 4\)"):
        Mesh.from_quads(grid.points, quads[:, :3])
