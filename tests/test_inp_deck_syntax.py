"""Abaqus decks read by Abaqus's input syntax, or refused naming the keyword and the line.

References: the Abaqus Analysis User's Guide, "Input syntax rules" (labels are read in any
case and without blanks unless quoted; an empty or left-out numeric field is 0), and the
Abaqus Keywords Reference for *NODE (SYSTEM=C: r, theta in degrees, z; data lines from
INPUT=), *NSET (ELSET: the nodes of the listed element sets), *ELEMENT (its TYPE) and the
keywords that make or move nodes and elements (*NGEN, *NFILL, *NCOPY, *NMAP, *ELGEN, *ELCOPY,
*SYSTEM). Each deck is a few nodes: the expected sets and coordinates are counted by hand from
the deck's text, coordinates compared to 1e-12 mm (double rounding of cos 30 deg and of the
text's decimals only).
"""

from pathlib import Path

import numpy as np
import pytest

from femcore.mesh import Mesh
from fibreshell.case import case_from_data
from fibreshell.cli import main

NODES = """*NODE, NSET=AllNodes
1, 0., 0., 0.
2, 50., 0., 0.
3, 0., 40., 0.
4, 50., 40., 0.
"""
SKIN = "*ELEMENT, TYPE=S3, ELSET=Skin\n1, 1, 2, 4\n2, 1, 4, 3\n"


def deck(tmp_path: Path, text: str, name: str = "deck.inp") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


# ---------------------------------------------------------------------- set names
def test_set_names_differing_in_case_or_blanks_are_one_set_named_as_first_written(tmp_path):
    """Tip (node 2) and TIP (node 4) were two sets: a load on 'TIP' took node 4 alone."""
    text = NODES + SKIN + "*NSET, NSET=Tip\n2\n*NSET, NSET=TIP\n4\n*NSET, NSET=t ip\n1\n"
    mesh = Mesh.read(deck(tmp_path, text + "*ELSET, ELSET=Both\nSKIN\n*NSET, NSET=Edge\ntip\n"))
    assert sorted(mesh.node_sets) == ["AllNodes", "Edge", "Tip"]
    assert mesh.node_sets["Tip"].tolist() == [0, 1, 3] == mesh.node_sets["Edge"].tolist()
    assert mesh.element_sets["Both"].tolist() == [0, 1]
    assert mesh.nodes("TIP").tolist() == [0, 1, 3] == mesh.nodes("t i p").tolist()


def test_a_case_names_a_deck_set_in_any_case(tmp_path):
    deck(tmp_path, NODES + SKIN + "*NSET, NSET=Tip\n2\n*NSET, NSET=TIP\n4\n", "plate.inp")
    data = {
        "mesh": {"file": "plate.inp"},
        "part": [{"element": "mindlin", "cells": "SKIN",
                  "material": {"E": 1e3, "nu": 0.3, "thickness": 1.0, "density": 1e-9}}],
        "fix": [{"nodes": "allnodes"}],
        "force": [{"nodes": "TIP", "vector": [0.0, 0.0, -1.0]}],
        "solver": {"kind": "static"},
    }  # fmt: skip
    model = case_from_data(data, tmp_path / "case.toml").model()
    assert model.loads[0].nodes.tolist() == [1, 3]


def test_names_of_a_mesh_not_read_from_a_deck_stay_exact(tmp_path):
    """gmsh and Python keep 'Tip' and 'TIP' apart; an .inp file could not: refused."""
    mesh = Mesh(np.eye(3), triangles=[[0, 1, 2]], node_sets={"Tip": [1], "TIP": [2]})
    assert mesh.nodes("TIP").tolist() == [2]
    with pytest.raises(ValueError, match=r"unknown node set 'tip'"):
        mesh.nodes("tip")
    with pytest.raises(ValueError, match=r"\['TIP', 'Tip'\] differ in case or blanks only"):
        mesh.write(tmp_path / "out.inp")


# ---------------------------------------------------------------------- element types
@pytest.mark.parametrize(
    "element, said",
    [
        (
            "R3D3, ELSET=DIE\n101, 1, 2, 4",
            r"TYPE=R3D3 is a rigid element: .* a file of its own, read as a rigid tool .*"
            r"shell's own triangles .* write TYPE=S3",
        ),
        ("R3D4\n101, 1, 2, 4, 3", r"TYPE=R3D4 is a rigid element"),
        ("M3D3\n101, 1, 2, 4", r"TYPE=M3D3 is a membrane element"),
        ("SFM3D3\n101, 1, 2, 4", r"TYPE=SFM3D3 is a surface element"),
        ("CPE3\n101, 1, 2, 4", r"TYPE=CPE3 is a plane or axisymmetric continuum element"),
        ("CAX3\n101, 1, 2, 4", r"TYPE=CAX3 is a plane or axisymmetric continuum element"),
        ("C3D4\n101, 1, 2, 4, 3", r"TYPE=C3D4 is a continuum or continuum shell element"),
        ("XYZ3\n101, 1, 2, 4", r"TYPE=XYZ3 is not a type the reader takes \(S3, "),
    ],
    ids=["R3D3", "R3D4", "M3D3", "SFM3D3", "CPE3", "CAX3", "C3D4", "unknown"],
)
def test_an_element_type_that_is_not_a_shell_or_a_truss_is_refused_naming_it(
    tmp_path, element, said
):
    """R3D3 was read as shell triangles (a rigid die run as fabric); the rest as 'not a
    valid abaqus file'."""
    path = deck(tmp_path, NODES + SKIN + f"*ELEMENT, TYPE={element}\n")
    with pytest.raises(ValueError, match=r"deck.inp: line 9: \*ELEMENT: " + said):
        Mesh.read(path)


def test_a_written_deck_holds_shell_triangles_and_trusses_and_reads_back(tmp_path):
    """meshio wrote triangles as R3D3 (rigid) and lines as B31H (beams)."""
    mesh = Mesh(np.eye(3), triangles=[[0, 1, 2]], lines=[[0, 1]])
    mesh.write(tmp_path / "out.inp")
    keywords = [line for line in (tmp_path / "out.inp").read_text().splitlines() if "TYPE" in line]
    assert keywords == ["*ELEMENT, TYPE=S3", "*ELEMENT, TYPE=T3D2"]
    back = Mesh.read(tmp_path / "out.inp")
    assert back.triangles.tolist() == [[0, 1, 2]] and back.lines.tolist() == [[0, 1]]


# ---------------------------------------------------------------------- node coordinates
def test_cylindrical_nodes_are_read_in_cartesian_coordinates(tmp_path):
    """SYSTEM=C was read as x, y, z: (100, 30, 0) for x = 100 cos 30 deg, y = 100 sin 30."""
    text = "*NODE, SYSTEM=C\n1, 100., 0., 0.\n2, 100., 30., 0.\n3, 100., 30., 50.\n"
    mesh = Mesh.read(deck(tmp_path, text + "*ELEMENT, TYPE=S3\n1, 1, 2, 3\n"))
    half_root3 = 0.5 * np.sqrt(3.0)
    expected = [[100.0, 0.0, 0.0], [100.0 * half_root3, 50.0, 0.0], [100 * half_root3, 50, 50]]
    np.testing.assert_allclose(mesh.points, expected, rtol=0.0, atol=1e-12)


def test_spherical_nodes_are_refused_naming_the_line(tmp_path):
    text = "*NODE\n1, 0., 0., 0.\n*NODE, SYSTEM=S\n2, 100., 0., 0.\n3, 100., 30., 0.\n"
    with pytest.raises(ValueError, match=r"deck.inp: line 3: \*NODE, SYSTEM=S: the reader takes"):
        Mesh.read(deck(tmp_path, text + "*ELEMENT, TYPE=S3\n1, 1, 2, 3\n"))


def test_coordinates_left_out_or_blank_are_zero(tmp_path):
    """A line without z beside lines with it was 'inhomogeneous shape'; a blank field
    'could not convert string to float'."""
    text = "*NODE\n1, 0., 0.\n2, 50., , \n3, , 40.,\n4, 50., 40., 5.\n"
    mesh = Mesh.read(deck(tmp_path, text + "*ELEMENT, TYPE=S3\n1, 1, 2, 4\n2, 1, 4, 3\n"))
    assert mesh.points.tolist() == [[0, 0, 0], [50, 0, 0], [0, 40, 0], [50, 40, 5]]


@pytest.mark.parametrize(
    "line, said",
    [("2, 50., x, 0.", r"'x' is not a number"), ("two, 50., 0., 0.", r"label 'two' is not an")],
    ids=["field", "label"],
)
def test_a_node_line_that_is_not_numbers_is_refused_naming_the_line(tmp_path, line, said):
    text = f"*NODE\n1, 0., 0., 0.\n{line}\n3, 0., 40., 0.\n*ELEMENT, TYPE=S3\n1, 1, 2, 3\n"
    with pytest.raises(ValueError, match=r"deck.inp: line 3: \*NODE line .*" + said):
        Mesh.read(deck(tmp_path, text))


def test_node_and_element_lines_in_files_named_by_input_are_read(tmp_path):
    """*NODE, INPUT= was a KeyError; *ELEMENT, INPUT= an IndexError."""
    (tmp_path / "nodes.txt").write_text(NODES.split("\n", 1)[1])
    (tmp_path / "elements.txt").write_text("1, 1, 2, 4\n2, 1, 4, 3\n")
    text = "*NODE, NSET=N, INPUT=nodes.txt\n*ELEMENT, TYPE=S3, INPUT=elements.txt, ELSET=E\n"
    mesh = Mesh.read(deck(tmp_path, text))
    assert mesh.points.tolist() == [[0, 0, 0], [50, 0, 0], [0, 40, 0], [50, 40, 0]]
    assert mesh.triangles.tolist() == [[0, 1, 3], [0, 3, 2]]
    assert mesh.node_sets["N"].tolist() == [0, 1, 2, 3] and mesh.element_sets["E"].size == 2


# ---------------------------------------------------------------------- sets and blocks
def test_a_node_set_of_element_sets_holds_their_elements_nodes(tmp_path):
    """*NSET, ELSET was refused as joining unknown node sets."""
    text = NODES + "5, 100., 0., 0.\n6, 100., 40., 0.\n" + SKIN
    text += "*ELEMENT, TYPE=S3, ELSET=Right\n3, 2, 5, 6\n4, 2, 6, 4\n"
    mesh = Mesh.read(deck(tmp_path, text + "*NSET, NSET=RightNodes, ELSET\nRIGHT\n"))
    assert mesh.node_sets["RightNodes"].tolist() == [1, 3, 4, 5]


def test_an_empty_element_block_is_refused_naming_it_and_the_command_exits_2(tmp_path, capsys):
    """It was an IndexError from the reader, exit 1 with a traceback."""
    path = deck(
        tmp_path, NODES + SKIN + "*ELEMENT, TYPE=T3D2, ELSET=STIFFENERS\n*NSET, NSET=L\n1\n"
    )
    said = r"deck.inp: line 9: \*ELEMENT, TYPE=T3D2: the block has no element line"
    with pytest.raises(ValueError, match=said):
        Mesh.read(path)
    case = tmp_path / "case.toml"
    case.write_text(
        '[mesh]\nfile = "deck.inp"\n[[part]]\nelement = "mindlin"\nmaterial = { E = 1000.0, '
        'nu = 0.3, thickness = 1.0, density = 1e-9 }\n[solver]\nkind = "static"\n'
    )
    assert main(["run", str(case), "--out", str(tmp_path / "out")]) == 2
    assert "the block has no element line" in capsys.readouterr().err


@pytest.mark.parametrize(
    "text, said",
    [
        ("1, 1, 2\n", r"line 6: \*ELEMENT, TYPE=S3: its lines hold 3 integers, not a whole"),
        ("1, 1, 2, 9\n", r"line 7: element 1 names node 9, which the deck does not define"),
        ("1, 1, 2, x\n", r"line 7: \*ELEMENT line '1, 1, 2, x': expected integers"),
    ],
    ids=["count", "node", "integers"],
)
def test_element_lines_abaqus_would_refuse_are_refused_naming_the_line(tmp_path, text, said):
    path = deck(tmp_path, NODES + "*ELEMENT, TYPE=S3\n" + text)
    with pytest.raises(ValueError, match=r"deck.inp: " + said):
        Mesh.read(path)


# ---------------------------------------------------------------------- generation
@pytest.mark.parametrize("keyword", ["NGEN", "NFILL", "NCOPY", "NMAP", "ELGEN", "ELCOPY"])
def test_a_keyword_that_makes_nodes_or_elements_is_refused_naming_it(tmp_path, keyword):
    """*ELGEN gave 2 triangles where Abaqus builds 4; *NGEN a KeyError."""
    path = deck(tmp_path, NODES + SKIN + f"*{keyword}\n1, 2, 1, 2\n")
    with pytest.raises(ValueError, match=rf"deck.inp: line 9: \*{keyword} makes or moves nodes"):
        Mesh.read(path)


def test_a_system_moving_the_nodes_that_follow_is_refused_naming_it(tmp_path):
    """*SYSTEM shifting by (10, 0, 0) was ignored: x read 0, 50, 0 where Abaqus has 10, 60, 10."""
    path = deck(tmp_path, "*SYSTEM\n10., 0., 0.\n" + NODES + SKIN)
    with pytest.raises(ValueError, match=r"deck.inp: line 1: \*SYSTEM makes or moves nodes"):
        Mesh.read(path)


def test_the_direction_cosines_of_a_normal_after_the_coordinates_are_left_with_a_warning(
    tmp_path,
):
    text = "*NODE\n1, 0., 0., 0., 0., 0., 1.\n2, 50., 0., 0.\n3, 0., 40., 0.\n"
    with pytest.warns(UserWarning, match=r"deck.inp: line 2 gives the direction cosines") as seen:
        mesh = Mesh.read(deck(tmp_path, text + "*ELEMENT, TYPE=S3\n1, 1, 2, 3\n"))
    assert mesh.points.tolist() == [[0, 0, 0], [50, 0, 0], [0, 40, 0]]
    said = str(seen[0].message)
    assert said.count("deck.inp") == 1 and "more" not in said  # the path once, no "0 more"


def test_a_keyword_line_in_a_file_of_data_lines_is_refused_naming_both(tmp_path):
    (tmp_path / "nodes.txt").write_text("1, 0., 0., 0.\n*ELEMENT, TYPE=S3\n")
    with pytest.raises(ValueError, match=r"line 1: \*NODE, INPUT=nodes.txt: .*nodes.txt line 2 "
                                         r"is a keyword line"):  # fmt: skip
        Mesh.read(deck(tmp_path, "*NODE, INPUT=nodes.txt\n"))


def test_a_quoted_name_is_read_as_written_and_one_clashing_with_another_set_refused(tmp_path):
    text = NODES + SKIN + '*NSET, NSET="My Tip"\n2\n*NSET, NSET="My TIP"\n4\n'
    mesh = Mesh.read(deck(tmp_path, text))
    assert mesh.node_sets["My Tip"].tolist() == [1] and mesh.node_sets["My TIP"].tolist() == [3]
    with pytest.raises(ValueError, match=r"'my tip' is ambiguous: the sets \['My Tip', 'My TIP'\]"):
        mesh.nodes("my tip")  # an unquoted name: either set, as Abaqus reads it
    with pytest.raises(
        ValueError,
        match=r"deck.inp: line 11: the deck names two sets 'Tip', one quoted \(read as written\)",
    ):
        Mesh.read(deck(tmp_path, NODES + SKIN + '*NSET, NSET=Tip\n2\n*NSET, NSET="Tip"\n4\n'))


def test_a_node_set_with_a_valued_elset_parameter_is_refused_naming_the_line(tmp_path):
    """*NSET, NSET=NB, ELSET=Skin gave an empty set silently: Abaqus's ELSET of *NSET takes no
    value, the element sets stand on the data lines."""
    text = NODES + SKIN + "*NSET, NSET=NB, ELSET=Skin\n"
    with pytest.raises(ValueError, match=r"deck.inp: line 9: \*NSET, ELSET=Skin: .* no value"):
        Mesh.read(deck(tmp_path, text))
    mesh = Mesh.read(deck(tmp_path, NODES + SKIN + "*NSET, NSET=NB, ELSET\nSkin\n"))
    assert mesh.node_sets["NB"].tolist() == [0, 1, 2, 3]


@pytest.mark.parametrize(
    "keyword, continued",
    [("*ELEMENT, TYPE=S3,", "ELSET=Plate"), ("*ELEMENT,", " type=S3, elset=Plate")],
    ids=["element", "type"],
)
def test_a_keyword_line_ending_with_a_comma_continues_on_the_next(tmp_path, keyword, continued):
    """Abaqus "Input syntax rules": refused before as 'expected integers' at the second line."""
    text = NODES + f"{keyword}\n{continued}\n1, 1, 2, 4\n2, 1, 4, 3\n*NSET,\n NSET=Tip\n2, 4\n"
    mesh = Mesh.read(deck(tmp_path, text))
    assert mesh.triangles.tolist() == [[0, 1, 3], [0, 3, 2]]
    assert mesh.element_sets["Plate"].tolist() == [0, 1]
    assert mesh.node_sets["Tip"].tolist() == [1, 3]
    with pytest.raises(ValueError, match=r"deck.inp: line 10: element 3 names node 9"):
        Mesh.read(deck(tmp_path, text.replace("*NSET,", "3, 1, 2, 9\n*NSET,")))


def test_an_unknown_label_in_a_data_file_is_refused_naming_its_line(tmp_path):
    """Was reported at the keyword line of the main deck only."""
    (tmp_path / "tip.txt").write_text("1, 2\n3, 99\n")
    text = NODES + SKIN + "*NSET, NSET=Tip, INPUT=tip.txt\n"
    with pytest.raises(ValueError, match=r"names node 99, .* \(its data line: .*tip.txt: line 2\)"):
        Mesh.read(deck(tmp_path, text))
