"""Mesh files read right: every block of every kind, in any order, gives meshio's own cells in
meshio's node ids (quads split in two triangles), and every named group or set comes back as
a node set and as a set of the cells of its dimension."""

import warnings

import gmsh
import meshio
import numpy as np
import pytest

from femcore import Mesh
from femcore.mesh_generators import split_quads
from fibreshell.case import load_case


def _meshio_cells(path, meshio_type):
    """meshio's cells of one type over all blocks, in file order (quads split)."""
    raw = meshio.read(path, file_format="gmsh" if str(path).endswith(".msh") else None)
    blocks = [np.asarray(b.data) for b in raw.cells if b.type == meshio_type]
    if meshio_type == "quad":
        blocks = [split_quads(b) for b in blocks]
    return raw, np.concatenate(blocks)


def _first_copies(rows):
    """rows without repeats, each kept where it first appears (gmsh's MSH 2.2 writes an
    element once per physical group of its entity)."""
    _, first = np.unique(rows, axis=0, return_index=True)
    return rows[np.sort(first)]


def _ids_of(rows, among):
    """Sorted indices in ``among`` of each row of ``rows``."""
    index = {tuple(r): i for i, r in enumerate(among.tolist())}
    return np.sort([index[tuple(r)] for r in rows.tolist()])


def _gmsh_strip(path, surfaces, version, **options):
    """``surfaces`` unit squares side by side along x, conforming, with physical surfaces
    "first" (the first square), "rest" (the others), "all" (every square: each triangle is
    in two groups), the physical curve "clamp" (the edge x = 0, tag 1 like "first") and the
    physical point "corner" (3, 0, 0) written as MSH ``version``; ``options`` are gmsh Mesh
    options (e.g. Binary=1, RecombineAll=1 for quads, SaveAll=1)."""
    gmsh.initialize(readConfigFiles=False, interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        occ = gmsh.model.occ
        squares = [occ.addRectangle(float(i), 0.0, 0.0, 1.0, 1.0) for i in range(surfaces)]
        occ.fragment([(2, s) for s in squares], [])
        occ.synchronize()
        tags = sorted(t for _, t in gmsh.model.getEntities(2))
        gmsh.model.addPhysicalGroup(2, tags[:1], tag=1, name="first")
        gmsh.model.addPhysicalGroup(2, tags[1:], tag=2, name="rest")
        gmsh.model.addPhysicalGroup(2, tags, tag=3, name="all")
        edge = gmsh.model.getEntitiesInBoundingBox(-0.1, -0.1, -0.1, 0.1, 1.1, 0.1, 1)
        gmsh.model.addPhysicalGroup(1, [t for _, t in edge], tag=1, name="clamp")
        far = float(surfaces)
        point = gmsh.model.getEntitiesInBoundingBox(far - 0.1, -0.1, -0.1, far + 0.1, 0.1, 0.1, 0)
        gmsh.model.addPhysicalGroup(0, [t for _, t in point], tag=1, name="corner")
        gmsh.option.setNumber("Mesh.MeshSizeMax", 0.35)
        for name, value in options.items():
            gmsh.option.setNumber(f"Mesh.{name}", value)
        gmsh.model.mesh.generate(2)
        gmsh.option.setNumber("Mesh.MshFileVersion", version)
        gmsh.write(str(path))
    finally:
        gmsh.finalize()


def test_an_empty_abaqus_elset_reads_and_is_refused_only_where_a_part_uses_it(tmp_path):
    """meshio reads "*ELSET, ELSET=EMPTY" with no line after it as a set of no block; the
    deck read as without it, the set empty, and a part on it refused as empty."""
    quads = np.concatenate([LEFT_QUADS, RIGHT_QUADS])
    deck = (
        f"*NODE\n{_nodes_text(STRIP_POINTS)}\n"
        f"*ELEMENT, TYPE=S4R, ELSET=BLANK\n{_elements_text(quads, 1)}\n"
        "*NSET, NSET=CLAMP\n1, 6\n"
    )
    (tmp_path / "plain.inp").write_text(deck)
    (tmp_path / "strip.inp").write_text(deck + "*ELSET, ELSET=EMPTY\n")
    plain, mesh = Mesh.read(tmp_path / "plain.inp"), Mesh.read(tmp_path / "strip.inp")
    np.testing.assert_array_equal(mesh.triangles, plain.triangles)
    np.testing.assert_array_equal(mesh.element_sets["BLANK"], plain.element_sets["BLANK"])
    assert mesh.element_sets["EMPTY"].size == 0
    (tmp_path / "case.toml").write_text(
        '[mesh]\nfile = "strip.inp"\n[[part]]\nelement = "mindlin"\ncells = "EMPTY"\n'
        "material = { E = 1e3, nu = 0.3, thickness = 0.1, density = 1e-9 }\n"
        '[[fix]]\nnodes = "CLAMP"\n[solver]\nkind = "static"\n'
    )
    with pytest.raises(ValueError, match=r"\[part\[0\].cells\]: .* set 'EMPTY' is empty"):
        load_case(tmp_path / "case.toml").model()


@pytest.mark.parametrize("version", [2.2, 4.1])
@pytest.mark.parametrize("surfaces", [2, 3])
def test_a_gmsh_file_of_several_surfaces_gives_meshios_triangles_and_its_groups(
    tmp_path, surfaces, version
):
    path = tmp_path / f"strip{surfaces}.msh"
    _gmsh_strip(path, surfaces, version)
    raw, triangles = _meshio_cells(path, "triangle")
    mesh = Mesh.read(path)
    mesh.check()  # a conforming, consistently oriented surface
    np.testing.assert_array_equal(mesh.points, raw.points)
    expected = _first_copies(triangles)
    np.testing.assert_array_equal(mesh.triangles, expected)
    assert mesh.n_triangles == len(triangles) // (2 if version == 2.2 else 1)
    # The surface groups are the triangles of their squares, by their centroids.
    centroid_x = mesh.points[mesh.triangles].mean(axis=1)[:, 0]
    np.testing.assert_array_equal(mesh.element_sets["first"], np.flatnonzero(centroid_x < 1.0))
    np.testing.assert_array_equal(mesh.element_sets["rest"], np.flatnonzero(centroid_x > 1.0))
    np.testing.assert_array_equal(mesh.element_sets["all"], np.arange(mesh.n_triangles))
    # The physical curve: its lines as a line set, its nodes as a node set (the edge x = 0).
    _, lines = _meshio_cells(path, "line")
    np.testing.assert_array_equal(mesh.lines, _first_copies(lines))
    np.testing.assert_array_equal(mesh.line_sets["clamp"], np.arange(mesh.n_lines))
    on_edge = np.flatnonzero(np.isclose(mesh.points[:, 0], 0.0))
    on_edge = np.intersect1d(on_edge, mesh.triangles)
    np.testing.assert_array_equal(mesh.nodes("clamp"), on_edge)
    np.testing.assert_array_equal(mesh.nodes("first"), np.unique(mesh.triangles[centroid_x < 1]))
    np.testing.assert_allclose(mesh.points[mesh.nodes("corner")], [[surfaces, 0.0, 0.0]])


def test_a_case_file_fixes_the_nodes_of_a_gmsh_physical_curve(tmp_path):
    _gmsh_strip(tmp_path / "strip.msh", 3, 4.1)
    (tmp_path / "case.toml").write_text(
        '[mesh]\nfile = "strip.msh"\n'
        '[[part]]\nelement = "mindlin"\nmaterial = "g986_ply"\ncells = "all"\n'
        '[[fix]]\nnodes = "clamp"\n'
        "[gravity]\nacceleration = [0.0, 0.0, -9810.0]\n"
        '[solver]\nkind = "static"\nincrements = 1\n'
    )
    case = load_case(tmp_path / "case.toml")
    model = case.model()
    assert np.array_equal(model.fixes[0].nodes, case.mesh.nodes("clamp"))
    model.compile()


def _nodes_text(points):
    return "\n".join(f"{i + 1}, {x:.6f}, {y:.6f}, {z:.6f}" for i, (x, y, z) in enumerate(points))


def _elements_text(cells, first_id):
    return "\n".join(
        f"{first_id + k}, " + ", ".join(str(n + 1) for n in cell) for k, cell in enumerate(cells)
    )


# A 4 x 1 strip of unit squares: nodes 0-4 along y = 0, 5-9 along y = 1.
STRIP_POINTS = np.array([[x, y, 0.0] for y in (0.0, 1.0) for x in range(5)], dtype=float)
LEFT_QUADS = np.array([[0, 1, 6, 5], [1, 2, 7, 6]])
RIGHT_QUADS = np.array([[2, 3, 8, 7], [3, 4, 9, 8]])


def test_an_abaqus_deck_with_the_right_block_first_gives_meshios_triangles(tmp_path):
    path = tmp_path / "two_blocks.inp"
    path.write_text(
        f"*NODE\n{_nodes_text(STRIP_POINTS)}\n"
        f"*ELEMENT, TYPE=S4R\n{_elements_text(RIGHT_QUADS, 11)}\n"
        f"*ELEMENT, TYPE=S4R, ELSET=LEFT\n{_elements_text(LEFT_QUADS, 1)}\n"
        "*NSET, NSET=CLAMP\n1, 6\n*ELSET, ELSET=TIP\n12\n"
    )
    _, expected = _meshio_cells(path, "quad")
    mesh = Mesh.read(path)
    mesh.check()
    np.testing.assert_array_equal(mesh.triangles, expected)
    np.testing.assert_array_equal(
        mesh.triangles, split_quads(np.concatenate([RIGHT_QUADS, LEFT_QUADS]))
    )
    # ELSET= of the second *ELEMENT line names the second block (meshio gives it the first).
    np.testing.assert_array_equal(mesh.element_sets["LEFT"], [4, 5, 6, 7])
    np.testing.assert_array_equal(mesh.element_sets["TIP"], [2, 3])  # element 12: quad 1
    np.testing.assert_array_equal(mesh.nodes("CLAMP"), [0, 5])


def test_a_mixed_triangle_and_quad_deck_gives_meshios_cells_in_file_order(tmp_path):
    path = tmp_path / "mixed.inp"
    left_triangles = split_quads(LEFT_QUADS)[:, ::-1][:, [2, 0, 1]]  # any node order
    path.write_text(
        f"*NODE\n{_nodes_text(STRIP_POINTS)}\n"
        f"*ELEMENT, TYPE=S4R, ELSET=QUADS\n{_elements_text(RIGHT_QUADS, 1)}\n"
        f"*ELEMENT, TYPE=S3, ELSET=TRIS\n{_elements_text(left_triangles, 101)}\n"
        f"*ELEMENT, TYPE=T3D2, ELSET=CABLE\n{_elements_text([[0, 5]], 201)}\n"
    )
    raw = meshio.read(path)
    assert [b.type for b in raw.cells] == ["quad", "triangle", "line"]
    mesh = Mesh.read(path)
    np.testing.assert_array_equal(
        mesh.triangles, np.concatenate([split_quads(raw.cells[0].data), raw.cells[1].data])
    )
    np.testing.assert_array_equal(mesh.lines, raw.cells[2].data)
    np.testing.assert_array_equal(mesh.element_sets["QUADS"], [0, 1, 2, 3])
    np.testing.assert_array_equal(mesh.element_sets["TRIS"], [4, 5, 6, 7])
    np.testing.assert_array_equal(mesh.line_sets["CABLE"], [0])


def test_a_vtu_with_two_cell_blocks_gives_meshios_cells(tmp_path):
    path = tmp_path / "two_blocks.vtu"
    cells = [("quad", RIGHT_QUADS), ("triangle", split_quads(LEFT_QUADS)), ("line", [[0, 5]])]
    meshio.write(path, meshio.Mesh(STRIP_POINTS, cells))
    raw = meshio.read(path)
    mesh = Mesh.read(path)
    np.testing.assert_array_equal(
        mesh.triangles, np.concatenate([split_quads(raw.cells[0].data), raw.cells[1].data])
    )
    np.testing.assert_array_equal(mesh.lines, raw.cells[2].data)
    mesh.check()


def test_deck_keywords_the_reader_does_not_use_are_listed_in_one_warning(tmp_path):
    path = tmp_path / "deck.inp"
    text = (
        "*HEADING\nstrip\n"
        f"*NODE\n{_nodes_text(STRIP_POINTS)}\n"
        f"*ELEMENT, TYPE=S4R, ELSET=BLANK\n{_elements_text(RIGHT_QUADS, 1)}\n"
        "** a comment: *BOUNDARY here is not a keyword\n"
        "*MATERIAL, NAME=FABRIC\n*ELASTIC\n1000., 0.3\n"
        "*SHELL SECTION, ELSET=BLANK, MATERIAL=FABRIC\n1.0\n"
        "*BOUNDARY\n3, ENCASTRE\n*STEP\n*STATIC\n*CLOAD\n5, 3, -1.\n*END STEP\n"
    )
    path.write_text(text)
    boundary_line = text.split("\n").index("*BOUNDARY") + 1
    with pytest.warns(UserWarning) as caught:
        mesh = Mesh.read(path)
    assert len(caught) == 1
    message = str(caught[0].message)
    for keyword in ("*MATERIAL", "*ELASTIC", "*SHELL SECTION", "*BOUNDARY", "*STEP", "*CLOAD"):
        assert keyword in message
    assert f"*BOUNDARY (line {boundary_line})" in message  # not the comment's line
    assert "*HEADING" not in message and "*NODE" not in message and "END STEP" not in message
    assert mesh.n_triangles == 4


def test_a_deck_of_mesh_keywords_only_reads_without_a_warning(tmp_path):
    path = tmp_path / "mesh_only.inp"
    path.write_text(
        f"*Node\n{_nodes_text(STRIP_POINTS)}\n"
        f"*Element, type=S4R\n{_elements_text(RIGHT_QUADS, 1)}\n*Nset, nset=A\n1\n"
    )
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert Mesh.read(path).n_triangles == 4


def test_a_deck_with_two_node_blocks_keeps_the_nodes_of_both(tmp_path):
    """Abaqus reads every *NODE block; meshio 5.3 keeps the last alone (the deck was refused,
    and with its nodes in an *INCLUDE file of their own it could not be written otherwise)."""
    path = tmp_path / "two_node_blocks.inp"
    path.write_text(
        f"*NODE, NSET=LOW\n{_nodes_text(STRIP_POINTS[:5])}\n"
        f"*ELEMENT, TYPE=S4R\n{_elements_text(RIGHT_QUADS, 1)}\n"
        "*NODE, NSET=HIGH\n" + _nodes_text(STRIP_POINTS).split("\n", 5)[5] + "\n"
    )
    mesh = Mesh.read(path)
    np.testing.assert_array_equal(mesh.points, STRIP_POINTS)
    np.testing.assert_array_equal(mesh.nodes("LOW"), [0, 1, 2, 3, 4])
    np.testing.assert_array_equal(mesh.nodes("HIGH"), [5, 6, 7, 8, 9])
    assert mesh.n_triangles == 2 * len(RIGHT_QUADS)


def test_abaqus_sets_made_of_other_sets_join_their_members(tmp_path):
    path = tmp_path / "set_of_sets.inp"
    path.write_text(
        f"*NODE\n{_nodes_text(STRIP_POINTS)}\n"
        f"*ELEMENT, TYPE=S4R, ELSET=RIGHT\n{_elements_text(RIGHT_QUADS, 11)}\n"
        f"*ELEMENT, TYPE=S4R\n{_elements_text(LEFT_QUADS, 1)}\n"
        "*ELSET, ELSET=FIRST\n1\n*ELSET, ELSET=BOTH\nRIGHT, FIRST\n"
        "*NSET, NSET=LOW\n1, 2\n*NSET, NSET=HIGH, GENERATE\n6, 10, 2\n"
        "*NSET, NSET=CORNERS\nLOW\nHIGH\n"
    )
    mesh = Mesh.read(path)
    np.testing.assert_array_equal(mesh.element_sets["RIGHT"], [0, 1, 2, 3])
    np.testing.assert_array_equal(mesh.element_sets["FIRST"], [4, 5])
    np.testing.assert_array_equal(mesh.element_sets["BOTH"], [0, 1, 2, 3, 4, 5])
    np.testing.assert_array_equal(mesh.nodes("HIGH"), [5, 7, 9])
    np.testing.assert_array_equal(mesh.nodes("CORNERS"), [0, 1, 5, 7, 9])
    path.write_text(path.read_text() + "*NSET, NSET=BAD\nLOW, NOWHERE\n")
    with pytest.raises(ValueError, match=r"NSET 'BAD' joins the sets \['NOWHERE'\]"):
        Mesh.read(path)


@pytest.mark.parametrize("version", [2.2, 4.1])
def test_binary_and_quad_gmsh_files_give_meshios_cells_split(tmp_path, version):
    path = tmp_path / "quads.msh"
    _gmsh_strip(path, 2, version, Binary=1, RecombineAll=1)
    _, triangles = _meshio_cells(path, "quad")
    mesh = Mesh.read(path)
    mesh.check()
    np.testing.assert_array_equal(mesh.triangles, _first_copies(triangles))
    np.testing.assert_array_equal(mesh.element_sets["all"], np.arange(mesh.n_triangles))
    np.testing.assert_array_equal(mesh.nodes("clamp"), np.flatnonzero(mesh.points[:, 0] == 0.0))


def test_physical_groups_gmsh_wrote_without_elements_are_named_in_a_warning(tmp_path):
    path = tmp_path / "save_all.msh"
    _gmsh_strip(path, 2, 2.2, SaveAll=1)  # MSH 2.2 elements then carry physical tag 0
    every = r"\['corner', 'clamp', 'first', 'rest', 'all'\]"
    with pytest.warns(UserWarning, match=rf"physical groups {every} hold no element"):
        mesh = Mesh.read(path)
    assert mesh.node_sets["clamp"].size == 0
    path = tmp_path / "save_all_41.msh"
    _gmsh_strip(path, 2, 4.1, SaveAll=1)
    with pytest.raises(ValueError, match=r"cannot read .* without SaveAll, or as MSH 2.2"):
        Mesh.read(path)


def test_a_format_whose_meshio_reader_needs_a_missing_package_says_which(tmp_path):
    try:
        import h5py  # noqa: F401
    except ModuleNotFoundError:
        path = tmp_path / "plate.med"
        path.write_bytes(b"")
        with pytest.raises(ValueError, match=r"needs the package 'h5py'"):
            Mesh.read(path)
    else:  # .med readable: its blocks read as the other formats'
        path = tmp_path / "plate.med"
        cells = [("quad", RIGHT_QUADS), ("triangle", split_quads(LEFT_QUADS))]
        meshio.write(path, meshio.Mesh(STRIP_POINTS, cells))
        raw = meshio.read(path)
        expected = [split_quads(b.data) if b.type == "quad" else b.data for b in raw.cells]
        np.testing.assert_array_equal(Mesh.read(path).triangles, np.concatenate(expected))
