"""Which *ELEMENT types a deck is read with: a body's, a rigid tool's, gmsh's .inp export.

References: the Abaqus Analysis User's Guide, element libraries (R3D3/R3D4 discrete rigid
facets and SFM3D3/SFM3D4(R) surface elements: what Abaqus meshes a rigid tool with; CPS3/CPS4
plane stress; S3T..S4RT coupled temperature-displacement shells, the nodes of S3/S4; STRI65,
S8R: second order), and gmsh's own .inp export (it writes every 2-D triangle as CPS3). The
decks are a few nodes; counts and distances are read from their text by hand: a flat die in
the plane z = 0 puts a point at height h at signed distance h (exact in binary for the
numbers used, compared to 1e-12 mm).
"""

from pathlib import Path

import numpy as np
import pytest

from elements.rigid_surface import RigidSurface
from femcore.mesh import Mesh
from fibreshell.case import load_case

NODES = "*NODE\n1, -10., -10., 0.\n2, 10., -10., 0.\n3, 10., 10., 0.\n4, -10., 10., 0.\n"
FACETS = {
    "R3D3": "1, 1, 2, 3\n2, 1, 3, 4\n",
    "SFM3D3": "1, 1, 2, 3\n2, 1, 3, 4\n",
    "R3D4": "1, 1, 2, 3, 4\n",
    "SFM3D4": "1, 1, 2, 3, 4\n",
    "SFM3D4R": "1, 1, 2, 3, 4\n",
}


def deck(tmp_path: Path, text: str, name: str = "deck.inp") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


@pytest.mark.parametrize("element", list(FACETS))
def test_a_rigid_tool_given_as_a_deck_of_rigid_or_surface_facets_is_read(tmp_path, element):
    """Refused as "a rigid element ... give the tool as a separate surface file" when the
    user had: the body's refusal applied to the tool's reader too."""
    path = deck(tmp_path, NODES + f"*ELEMENT, TYPE={element}, ELSET=Die\n" + FACETS[element])
    tool = RigidSurface(str(path))
    assert tool.n_facets == 2  # two triangles, or one quadrilateral split in two
    distance, normal = tool.distance(np.array([[1.0, 2.0, 3.0], [-4.0, 0.5, -2.0]]))
    np.testing.assert_allclose(distance, [3.0, -2.0], atol=1e-12)
    np.testing.assert_allclose(normal, [[0, 0, 1], [0, 0, 1]], atol=1e-12)


def test_a_case_contact_tool_given_as_a_deck_of_r3d3_facets_loads(tmp_path):
    deck(tmp_path, NODES + "*ELEMENT, TYPE=R3D3, ELSET=Die\n" + FACETS["R3D3"], "die.inp")
    case = tmp_path / "case.toml"
    case.write_text(
        "[mesh]\nrectangle = { lx = 10.0, ly = 5.0, nx = 2, ny = 1 }\n[[part]]\n"
        'element = "fibrous"\nmaterial = { thickness = 0.5, areal_density = 1e-10, '
        "tension = 1000.0, shear = 0.5, bending = 1.0 }\n"
        '[[contact]]\ntool = "surface"\nfile = "die.inp"\n'
        '[solver]\nkind = "explicit"\nduration = 1e-4\n'
    )
    load_case(case)  # refused before, naming a [[tool]] table case files do not have


@pytest.mark.parametrize("element", list(FACETS))
def test_a_body_deck_of_rigid_facets_is_refused_naming_the_case_tool_entry(tmp_path, element):
    path = deck(tmp_path, NODES + f"*ELEMENT, TYPE={element}\n" + FACETS[element])
    with pytest.raises(ValueError, match=rf"line 6: \*ELEMENT: TYPE={element} is a") as caught:
        Mesh.read(path)
    assert '[[contact]] tool = "surface", file =' in str(caught.value)
    assert "[[tool]]" not in str(caught.value)  # no such table in a case file


# gmsh 4's .inp export of a square in two triangles with a physical surface "Blank", as it
# writes it (header, element banner, CPS3, the physical group as an *ELSET)
GMSH_EXPORT = """*Heading
 blank.inp
*NODE
1, 0, 0, 0
2, 100, 0, 0
3, 100, 50, 0
4, 0, 50, 0
******* E L E M E N T S *************
*ELEMENT, type=CPS3, ELSET=Surface1
1, 1, 2, 3
2, 1, 3, 4
*ELSET,ELSET=Blank
1, 2
"""


def test_gmsh_plane_stress_triangles_are_read_as_shell_triangles_with_a_warning(tmp_path):
    """gmsh writes 2-D triangles as CPS3 with no option for another type: refused before."""
    with pytest.warns(UserWarning, match=r"deck.inp: line 9: TYPE=CPS3 \(a plane-stress"):
        mesh = Mesh.read(deck(tmp_path, GMSH_EXPORT))
    assert mesh.triangles.tolist() == [[0, 1, 2], [0, 2, 3]]
    assert mesh.element_sets["Blank"].tolist() == [0, 1]


def test_gmsh_inp_export_reads_as_its_msh_file(tmp_path):
    """The peer: gmsh's own .msh of the same mesh (its nodes, triangles and sets)."""
    gmsh = pytest.importorskip("gmsh")
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("blank")
        surface = gmsh.model.occ.addRectangle(0, 0, 0, 100, 50)
        gmsh.model.occ.synchronize()
        gmsh.model.addPhysicalGroup(2, [surface], name="Blank")
        gmsh.option.setNumber("Mesh.MeshSizeMax", 25)
        gmsh.model.mesh.generate(2)
        gmsh.write(str(tmp_path / "blank.inp"))
        gmsh.write(str(tmp_path / "blank.msh"))
    finally:
        gmsh.finalize()
    with pytest.warns(UserWarning, match=r"TYPE=CPS3 .* is read as S3"):
        from_inp = Mesh.read(tmp_path / "blank.inp")
    from_msh = Mesh.read(tmp_path / "blank.msh")
    # gmsh writes the .inp coordinates with 12 decimals, the .msh with 16 digits
    np.testing.assert_allclose(from_inp.points, from_msh.points, rtol=0, atol=1e-10)
    np.testing.assert_array_equal(from_inp.triangles, from_msh.triangles)
    np.testing.assert_array_equal(from_inp.element_sets["Blank"], from_msh.element_sets["Blank"])


@pytest.mark.parametrize("element, read_as", [("S3T", "S3"), ("S3RT", "S3R")])
def test_coupled_temperature_shells_are_read_by_their_nodes_with_a_warning(
    tmp_path, element, read_as
):
    text = NODES + f"*ELEMENT, TYPE={element}\n1, 1, 2, 3\n"
    with pytest.warns(UserWarning, match=rf"TYPE={element} \(a coupled .* is read as {read_as}"):
        mesh = Mesh.read(deck(tmp_path, text))
    assert mesh.triangles.tolist() == [[0, 1, 2]]


@pytest.mark.parametrize("element", ["STRI65", "S8R", "S8R5"])
def test_second_order_shells_are_refused_saying_write_first_order(tmp_path, element):
    text = NODES + f"*ELEMENT, TYPE={element}\n1, 1, 2, 3, 4, 1, 2\n"
    with pytest.raises(ValueError, match=rf"TYPE={element} is a second-order element .* first"):
        Mesh.read(deck(tmp_path, text))
