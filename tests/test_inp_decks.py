"""Abaqus decks (.inp) read as Abaqus reads them, or refused naming the file, the line and the
set: assemblies the reader cannot place, sets generated or listed as Abaqus's keyword rules
allow, nodes and elements a set names that the deck does not define."""

import os
import shutil
import subprocess
import warnings
from pathlib import Path

import numpy as np
import pytest

from femcore.mesh import Mesh

PART = """*Heading
*Part, name=plate
*Node
 1, 0., 0., 0.
 2, 10., 0., 0.
 3, 10., 10., 0.
 4, 0., 10., 0.
*Element, type=S4R, elset=all
 1, 1, 2, 3, 4
*Nset, nset=left
 1, 4
*End Part
*Assembly, name=Assembly
"""


def deck(tmp_path: Path, text: str, name: str = "deck.inp") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


# ---------------------------------------------------------------------- assemblies
def test_two_instances_of_a_part_are_refused_naming_both_and_their_lines(tmp_path):
    """The second copy, 5 mm above, was dropped and its set landed on the first's nodes."""
    path = deck(tmp_path, PART + """*Instance, name=plate-1, part=plate
*End Instance
*Instance, name=plate-2, part=plate
 0., 0., 5.
*End Instance
*Nset, nset=clamp, instance=plate-2
 1, 4
*End Assembly
""")  # fmt: skip
    with pytest.raises(ValueError, match=r"deck.inp has 2 \*INSTANCE entries, 'plate-1' \(line "
                                         r"14\), 'plate-2' \(line 16\)"):  # fmt: skip
        Mesh.read(path)


@pytest.mark.parametrize(
    "moves, said",
    [([" 0., 0., 5."], "0, 0, 5"), ([" 0., 0., 0.", " 0., 0., 0., 0., 0., 1., 90."], "90")],
)
def test_an_instance_moved_or_rotated_is_refused_naming_its_line(tmp_path, moves, said):
    text = PART + "*Instance, name=plate-1, part=plate\n" + "\n".join(moves)
    path = deck(tmp_path, text + "\n*End Instance\n*End Assembly\n")
    with pytest.raises(
        ValueError, match=rf"\*INSTANCE 'plate-1' \(line 14\) is moved or rotated, by .*{said}"
    ):
        Mesh.read(path)


def test_one_instance_where_its_part_stands_is_read_quietly(tmp_path):
    text = PART + "*Instance, name=plate-1, part=plate\n 0., 0., 0.\n*End Instance\n"
    path = deck(tmp_path, text + "*Nset, nset=clamp, instance=plate-1\n 1, 4\n*End Assembly\n")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        mesh = Mesh.read(path)
    assert np.allclose(mesh.points[mesh.nodes("clamp")], [[0, 0, 0], [0, 10, 0]])


# ---------------------------------------------------------------------- sets
NODES = """*Node
 1, 0., 0., 0.
 2, 10., 0., 0.
 3, 10., 10., 0.
 4, 0., 10., 0.
 5, 20., 0., 0.
 6, 20., 10., 0.
"""
QUAD = "*Element, type=S4R\n 1, 1, 2, 3, 4\n"
TRIANGLES = "*Element, type=S3\n 2, 2, 5, 6\n 3, 2, 6, 3\n"


@pytest.mark.parametrize(
    "sets, name, expected",
    [
        # an *ELSET between the two *ELEMENT blocks: refused ("a set of sets in an *INCLUDE
        # file"), though it lists its element; quad 1 is triangles 0 and 1
        (QUAD + "*Elset, elset=first\n 1\n" + TRIANGLES, "first", [0, 1]),
        # GENERATE over two data lines: "not a valid abaqus file"
        (QUAD + TRIANGLES + "*Elset, elset=two, generate\n 1, 1, 1\n 2, 3, 1\n", "two",
         [0, 1, 2, 3]),
        # and an element set by labels and set names on one line
        (QUAD + TRIANGLES + "*Elset, elset=tri\n 2, 3\n*Elset, elset=both\n 1, tri\n", "both",
         [0, 1, 2, 3]),
    ],
)  # fmt: skip
def test_element_sets_are_read_as_abaqus_reads_them(tmp_path, sets, name, expected):
    mesh = Mesh.read(deck(tmp_path, NODES + sets))
    assert mesh.element_sets[name].tolist() == expected


@pytest.mark.parametrize(
    "text, name, labels",
    [
        ("*Nset, nset=row, generate\n 1, 2\n", "row", [1, 2]),  # the increment omitted: 1
        ("*Nset, nset=row, generate\n 1, 5, 2\n 2, 2\n", "row", [1, 2, 3, 5]),  # two lines
        ("*Nset, nset=a\n 1\n*Nset, nset=b\n a, 6\n", "b", [1, 6]),  # a name and a label
    ],
)
def test_node_sets_are_read_as_abaqus_reads_them(tmp_path, text, name, labels):
    mesh = Mesh.read(deck(tmp_path, NODES + QUAD + TRIANGLES + text))
    assert (mesh.nodes(name) + 1).tolist() == labels  # labels 1..6 are nodes 0..5


def test_the_nset_of_a_node_block_holds_its_nodes(tmp_path):
    text = NODES.replace("*Node", "*Node, nset=allnodes") + QUAD + TRIANGLES
    assert Mesh.read(deck(tmp_path, text)).nodes("allnodes").tolist() == list(range(6))


@pytest.mark.parametrize(
    "text, message",
    [
        # was "KeyError: np.int32(77)"
        ("*Nset, nset=bad\n 1, 77\n", r"deck.inp: line 11: \*NSET 'bad' names node 77, which "),
        # was dropped silently
        ("*Elset, elset=second\n 2, 3, 99\n", r"line 11: \*ELSET 'second' names element 99, "),
        # was "not a valid abaqus file"
        ("*Nset, nset=row, generate\n 1, 2, 3, 4\n", r"line 12: \*NSET 'row', GENERATE: expected "
                                                     r"'first, last\[, increment\]'"),
        ("*Nset, nset=row, generate\n 4, 2\n", r"line 12: \*NSET 'row', GENERATE: .* got '4, 2'"),
        ("*Elset, elset=u\n unknown\n", r"line 11: \*ELSET 'u' joins the sets \['unknown'\]"),
    ],
)  # fmt: skip
def test_a_set_naming_what_the_deck_does_not_define_is_refused_naming_the_line(
    tmp_path, text, message
):
    with pytest.raises(ValueError, match=message):
        Mesh.read(deck(tmp_path, NODES + "*Element, type=S3\n 2, 2, 5, 6\n 3, 2, 6, 3\n" + text))


def test_a_collapsed_quadrilateral_is_refused_naming_the_file_the_line_and_the_element(tmp_path):
    """Was "triangle 3 is degenerate: it repeats a node in (2, 2, 4)", neither the file nor
    the element 12 named."""
    text = NODES + "*Element, type=S4R, elset=plate\n 11, 1, 2, 3, 4\n 12, 2, 5, 3, 3\n"
    with pytest.raises(ValueError, match=r"deck.inp: line 10: element 12 repeats a node in "
                                         r"\(2, 5, 3, 3\)"):  # fmt: skip
        Mesh.read(deck(tmp_path, text))


# ------------------------------------------------------------ one name, several definitions
MIXED = """*Heading
*Node
 1, 0., 0., 0.
 2, 10., 0., 0.
 3, 10., 10., 0.
 4, 0., 10., 0.
 5, 20., 0., 0.
 6, 20., 10., 0.
*Element, type=S3, elset=PLATE
 1, 1, 2, 3
 2, 1, 3, 4
*Element, type=S4R, elset=PLATE
 3, 2, 5, 6, 3
*Nset, nset=FIX
 1
*Nset, nset=FIX
 4
"""


def test_a_set_named_on_several_element_blocks_holds_every_blocks_elements(tmp_path):
    """Triangles and quadrilaterals in one ELSET, as hand-written decks give a plate: the set is
    every definition's elements (CalculiX's manual, "Sets": a name defined again adds to the
    set). It held the last block's alone (its two triangles of the quadrilateral), so a part
    on cells "PLATE" covered half the shell without a word."""
    mesh = Mesh.read(deck(tmp_path, MIXED))
    assert len(mesh.triangles) == 4  # the quadrilateral split in two
    assert sorted(mesh.element_sets["PLATE"].tolist()) == [0, 1, 2, 3]
    assert sorted(mesh.node_sets["FIX"].tolist()) == [0, 3]  # *NSET given twice: both nodes


def test_an_elset_keyword_adds_to_the_set_an_element_block_named(tmp_path):
    text = MIXED.replace("*Element, type=S4R, elset=PLATE", "*Element, type=S4R") + (
        "*Elset, elset=PLATE\n 3\n"
    )
    mesh = Mesh.read(deck(tmp_path, text))
    assert sorted(mesh.element_sets["PLATE"].tolist()) == [0, 1, 2, 3]


def test_a_set_names_the_node_its_label_defines_after_a_label_given_twice(tmp_path):
    """Node 2 given twice (the later line's coordinates are node 2's, as meshio reads them):
    the set of node 5 held the point of the line before it, the index of every node after the
    repeat one short."""
    text = NODES.replace(" 3, 10., 10., 0.\n", " 2, 10., 0., 0.\n 3, 10., 10., 0.\n")
    mesh = Mesh.read(deck(tmp_path, text + TRIANGLES + "*Nset, nset=five\n 5\n"))
    assert mesh.points[mesh.nodes("five")].tolist() == [[20.0, 0.0, 0.0]]


# ----------------------------------------------- NSET= of a *NODE block, a label given twice
TWICE = """*Heading
*Node, nset=A
 1, 0., 0., 0.
 2, 1., 0., 0.
 3, 1., 1., 0.
*Node, nset=B
 4, 0., 1., 0.
 2, 2., 0., 0.
*Element, type=S3, elset=E
 1, 1, 2, 3
 2, 1, 3, 4
"""
#: Each label's node as the deck defines it: node 2 is the later line's, at (2, 0, 0).
TWICE_POINTS = {1: [0.0, 0.0, 0.0], 2: [2.0, 0.0, 0.0], 3: [1.0, 1.0, 0.0], 4: [0.0, 1.0, 0.0]}


def test_the_nset_of_a_node_block_holds_the_node_its_labels_name_after_a_label_given_twice(
    tmp_path,
):
    """Node 2 given in block A, then again in block B: the elements use the later line's node,
    and A = {1, 2, 3} holds that node too, as Abaqus's keyword rules read it (the set of a
    *NODE block is its labels). A held the first line's point (1, 0, 0), which no element
    uses, so a support on A left the elements' node 2 free."""
    mesh = Mesh.read(deck(tmp_path, TWICE))
    held = mesh.nodes("A")
    assert np.isin(held, mesh.triangles).all()
    assert sorted(mesh.points[held].tolist()) == sorted(TWICE_POINTS[k] for k in (1, 2, 3))
    assert sorted(mesh.points[mesh.nodes("B")].tolist()) == sorted(TWICE_POINTS[k] for k in (2, 4))


TWICE_JOB = """*INCLUDE, INPUT=mesh.inp
*MATERIAL, NAME=M
*ELASTIC
1000., 0.3
*SHELL SECTION, ELSET=E, MATERIAL=M
0.1
*NSET, NSET=ALLN
1, 2, 3, 4
*BOUNDARY
A, 1, 6
*STEP
*STATIC
*CLOAD
4, 1, 1.
*NODE PRINT, NSET=ALLN
U
*END STEP
"""


@pytest.mark.skipif(shutil.which("ccx") is None, reason="CalculiX (calculix-ccx) not installed")
def test_the_nset_of_a_node_block_after_a_label_given_twice_is_the_set_calculix_holds(tmp_path):
    """CalculiX 2.20 on the same deck, A held in every DOF and node 4 pulled (0.03 s): the
    nodes it holds (displacement exactly 0) are those of labels 1, 2, 3, node 2 the one the
    elements use (else the shell would be free at its corner 2); Mesh.read's A is those
    nodes, at the points the deck gives their labels."""
    (tmp_path / "mesh.inp").write_text(TWICE)
    (tmp_path / "job.inp").write_text(TWICE_JOB)
    env = dict(os.environ, OMP_NUM_THREADS="1")
    subprocess.run(["ccx", "job"], cwd=tmp_path, env=env, capture_output=True, timeout=120)
    dat = (tmp_path / "job.dat").read_text()
    rows = dat.split("displacements", 1)[1].split("\n\n", 2)[1].splitlines()
    moved = {
        int(row.split()[0]): [float(v) for v in row.split()[1:]] for row in rows if row.strip()
    }
    held_by_ccx = sorted(label for label, u in moved.items() if not any(u))
    assert held_by_ccx == [1, 2, 3] and any(moved[4])  # the peer's reading, not ours
    mesh = Mesh.read(tmp_path / "mesh.inp")
    held = sorted(mesh.points[mesh.nodes("A")].tolist())
    assert held == sorted(TWICE_POINTS[k] for k in held_by_ccx)
