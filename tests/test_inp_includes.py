"""An Abaqus deck whose mesh lives in *INCLUDE files (the mesh exported to mesh.inp, the model
deck including it) is read by the rules of a deck in one file (femcore/inp_include.py,
femcore/inp_sets.py): the included lines stand in place of the *INCLUDE line, a relative
INPUT= is found from the main deck's folder at every depth, and an error names the file and
the line where the text stands.

Before, such a deck went to meshio's own reading, which reads each included file as a mesh of
its own: an *ELSET in an included file was dropped (a part on cells "PLATE" found no set), a
set naming the other file's nodes was "TypeError: 'NoneType' object is not subscriptable", a
set defined in two files was that TypeError too or its last definition, a file of the
INPUT= name in the working folder was read instead of the one beside the deck, a missing file
or a cycle was a FileNotFoundError or a RecursionError naming no line."""

import os
import shutil
import subprocess
import warnings
from pathlib import Path

import pytest

from femcore.mesh import Mesh

NODES = """*Node, nset=NALL
 1, 0., 0., 0.
 2, 10., 0., 0.
 3, 10., 10., 0.
 4, 0., 10., 0.
 5, 20., 0., 0.
 6, 20., 10., 0.
"""
ELEMENTS = "*Element, type=S3, elset=PLATE\n 1, 1, 2, 3\n 2, 1, 3, 4\n 3, 2, 5, 6\n 4, 2, 6, 3\n"
MESH = NODES + ELEMENTS  # labels 1..6 are nodes 0..5, elements 1..4 triangles 0..3


def write(folder: Path, files: dict[str, str]) -> Path:
    """Write ``files`` (path in ``folder`` -> text); the main deck is ``main.inp``."""
    for name, text in files.items():
        (folder / name).parent.mkdir(parents=True, exist_ok=True)
        (folder / name).write_text(text)
    return folder / "main.inp"


# ------------------------------------------------------------------ sets across the files
def test_sets_across_the_main_deck_and_its_included_file_are_read_as_one_deck(tmp_path):
    main = write(tmp_path, {
        "mesh.inp": MESH + "*Nset, nset=FIX\n 1\n*Elset, elset=A\n 1, 2\n",
        # FIX defined again (adds to it), B of an included element, AB a set of sets
        "main.inp": "*Heading\n*Include, input=mesh.inp\n*Nset, nset=FIX\n 4\n"
                    "*Elset, elset=B\n 3\n*Elset, elset=AB\n A, B\n",
    })  # fmt: skip
    mesh = Mesh.read(main)
    assert mesh.element_sets["PLATE"].tolist() == [0, 1, 2, 3]  # ELSET= of the included block
    assert mesh.node_sets["FIX"].tolist() == [0, 3]  # both definitions' nodes
    assert mesh.element_sets["AB"].tolist() == [0, 1, 2]
    assert mesh.node_sets["NALL"].tolist() == list(range(6))


def test_a_set_in_an_included_file_names_the_nodes_of_the_main_deck(tmp_path):
    main = write(tmp_path, {"main.inp": MESH + "*INCLUDE, INPUT=sets.inp\n",
                            "sets.inp": "*NSET, NSET=CLAMP, GENERATE\n 1, 4, 3\n"})  # fmt: skip
    assert Mesh.read(main).node_sets["CLAMP"].tolist() == [0, 3]


def test_nodes_in_two_files_are_one_deck_s_nodes(tmp_path):
    """The main deck's nodes and the included file's, an element of the included file on
    both: meshio read each file's nodes apart ("KeyError: 1" for the element), and two *NODE
    blocks in one deck were refused (meshio keeps the last alone)."""
    main = write(tmp_path, {
        "main.inp": "*Node, nset=LOW\n 1, 0., 0., 0.\n 2, 10., 0., 0.\n 5, 20., 0., 0.\n"
                    "*INCLUDE, INPUT=upper.inp\n",
        "upper.inp": "*Node, nset=HIGH\n 3, 10., 10., 0.\n 4, 0., 10., 0.\n 6, 20., 10., 0.\n"
                     + ELEMENTS,
    })  # fmt: skip
    mesh = Mesh.read(main)
    assert mesh.n_triangles == 4 and mesh.node_sets["HIGH"].tolist() == [3, 4, 5]
    assert mesh.points[mesh.triangles[0]].tolist() == [[0, 0, 0], [10, 0, 0], [10, 10, 0]]


# ------------------------------------------------------------------ where INPUT= is found
def test_a_relative_input_is_the_file_beside_the_deck_whatever_the_working_folder(
    tmp_path, monkeypatch
):
    main = write(tmp_path / "job", {"main.inp": "*INCLUDE, INPUT=mesh.inp\n", "mesh.inp": MESH})
    elsewhere = tmp_path / "elsewhere"
    write(elsewhere, {"mesh.inp": MESH.replace("20.,", "99.,")})  # another mesh of that name
    monkeypatch.chdir(elsewhere)
    assert Mesh.read(main).points[:, 0].max() == 20.0


def test_a_nested_include_is_found_from_the_main_decks_folder_at_every_depth(tmp_path, monkeypatch):
    main = write(tmp_path / "job", {
        "main.inp": "*INCLUDE, INPUT=parts/mesh.inp\n",
        "parts/mesh.inp": "*INCLUDE, INPUT=parts/nodes.inp\n" + ELEMENTS,
        "parts/nodes.inp": NODES,
    })  # fmt: skip
    monkeypatch.chdir(tmp_path)
    mesh = Mesh.read(main)
    assert mesh.n_triangles == 4 and mesh.element_sets["PLATE"].tolist() == [0, 1, 2, 3]


def test_an_input_written_from_the_including_files_folder_is_refused_naming_the_one_to_write(
    tmp_path,
):
    """Abaqus and CalculiX read INPUT=nodes.inp in parts/mesh.inp as the nodes.inp beside the
    main deck (CalculiX 2.20: "cannot open file nodes.inp", see the peer test below)."""
    main = write(tmp_path, {
        "main.inp": "*INCLUDE, INPUT=parts/mesh.inp\n",
        "parts/mesh.inp": "** nodes\n*INCLUDE, INPUT=nodes.inp\n" + ELEMENTS,
        "parts/nodes.inp": NODES,
    })  # fmt: skip
    with pytest.raises(ValueError, match=r"parts/mesh.inp: line 2: \*INCLUDE, INPUT=nodes.inp: "
                                         r"no file .*write INPUT=parts/nodes.inp"):  # fmt: skip
        Mesh.read(main)


def test_a_missing_included_file_is_refused_naming_the_including_file_and_line(tmp_path):
    main = write(tmp_path, {"main.inp": MESH + "*INCLUDE, INPUT=sets.inp\n"})
    with pytest.raises(ValueError, match=r"main.inp: line 13: \*INCLUDE, INPUT=sets.inp: no file "
                                         r".*sets.inp"):  # fmt: skip
        Mesh.read(main)


def test_an_include_without_its_file_name_is_refused_naming_its_line(tmp_path):
    main = write(tmp_path, {"main.inp": MESH + "*Include\n"})  # was "No such file: '*Include'"
    with pytest.raises(ValueError, match=r"main.inp: line 13: \*INCLUDE: no INPUT= file name"):
        Mesh.read(main)


def test_an_include_cycle_is_refused_naming_the_chain(tmp_path):
    main = write(tmp_path, {"main.inp": "*INCLUDE, INPUT=mesh.inp\n",
                            "mesh.inp": MESH + "*INCLUDE, INPUT=main.inp\n"})  # fmt: skip
    with pytest.raises(ValueError, match=r"mesh.inp: line 13: \*INCLUDE, INPUT=main.inp: an "
                                         r"include cycle \(.*main.inp -> .*mesh.inp -> "
                                         r".*main.inp\)"):  # fmt: skip
        Mesh.read(main)


# ------------------------------------------------------------------ errors where they stand
@pytest.mark.parametrize(
    "included, message",
    [
        (MESH + "*Nset, nset=BAD\n 1, 77\n", r"mesh.inp: line 13: \*NSET 'BAD' names node 77"),
        (NODES + "*Element, type=S4R\n 1, 1, 2, 3, 4\n 2, 2, 5, 6, 6\n",
         r"mesh.inp: line 10: element 2 repeats a node in \(2, 5, 6, 6\)"),
        (MESH + "*Elset, elset=AB\n A, B\n", r"mesh.inp: line 13: \*ELSET 'AB' joins the sets "
                                             r"\['A', 'B'\]"),
        (MESH + "*Part, name=p\n*End Part\n*Assembly, name=a\n*Instance, name=p-1, part=p\n"
         "*End Instance\n*Instance, name=p-2, part=p\n 0., 0., 5.\n*End Instance\n",
         r"2 \*INSTANCE entries, 'p-1' \(mesh.inp line 16\), 'p-2' \(mesh.inp line 18\)"),
    ],
    ids=["undefined node", "collapsed quad", "undefined sets", "two instances"],
)  # fmt: skip
def test_a_fault_in_an_included_file_is_refused_naming_that_file_and_its_line(
    tmp_path, included, message
):
    main = write(tmp_path, {"main.inp": "*Heading\n*INCLUDE, INPUT=mesh.inp\n",
                            "mesh.inp": included})  # fmt: skip
    with pytest.raises(ValueError, match=message):
        Mesh.read(main)


def test_keywords_of_an_included_file_the_reader_ignores_are_named_with_their_file(tmp_path):
    main = write(tmp_path, {"main.inp": "*INCLUDE, INPUT=mesh.inp\n*Step\n*Static\n*End Step\n",
                            "mesh.inp": MESH + "*Boundary\n 1, 1, 6\n"})  # fmt: skip
    with pytest.warns(UserWarning, match=r"ignores \*BOUNDARY \(mesh.inp line 13\), \*STEP "
                                         r"\(line 2\), \*STATIC \(line 3\)"):  # fmt: skip
        Mesh.read(main)


def test_a_deck_of_mesh_keywords_and_includes_reads_without_a_warning(tmp_path):
    main = write(tmp_path, {"main.inp": "*INCLUDE, INPUT=mesh.inp\n", "mesh.inp": MESH})
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert Mesh.read(main).n_triangles == 4


# ------------------------------------------------------------------ the peer: CalculiX
PEER_MAIN = """*HEADING
sets across included files
*INCLUDE, INPUT=parts/mesh.inp
*NSET, NSET=FIX
 4
*ELSET, ELSET=B
 3
*ELSET, ELSET=AB
 A, B
*MATERIAL, NAME=M
*ELASTIC
1000., 0.3
*SHELL SECTION, ELSET=PLATE, MATERIAL=M
1.0
*BOUNDARY
NALL, 1, 6
*STEP
*STATIC
*NODE PRINT, NSET=FIX
U
*EL PRINT, ELSET=AB
S
*END STEP
"""


def _printed_labels(dat: str, quantity: str) -> list[int]:
    """The node or element labels CalculiX printed under the block of ``quantity``."""
    block = dat.split(quantity, 1)[1].split("\n\n", 2)[1]
    return sorted({int(row.split()[0]) for row in block.splitlines() if row.strip()})


@pytest.mark.skipif(shutil.which("ccx") is None, reason="CalculiX (calculix-ccx) not installed")
def test_the_sets_of_a_deck_with_nested_includes_are_those_calculix_reads(tmp_path, monkeypatch):
    """CalculiX 2.20 run on the deck in its folder prints the members of FIX and AB (every node
    held: a static step with no load, 0.03 s); Mesh.read from another working folder gives the
    same members (node label k is node k - 1, element label k triangle k - 1). The same deck
    with the nested INPUT= written from the including file's folder stops CalculiX."""
    job = tmp_path / "job"
    main = write(job, {
        "main.inp": PEER_MAIN,
        "parts/mesh.inp": MESH + "*INCLUDE, INPUT=parts/sets.inp\n",
        "parts/sets.inp": "*NSET, NSET=FIX\n 1\n*ELSET, ELSET=A\n 1, 2\n",
    })  # fmt: skip
    env = dict(os.environ, OMP_NUM_THREADS="1")
    subprocess.run(["ccx", "main"], cwd=job, env=env, capture_output=True, timeout=120)
    dat = (job / "main.dat").read_text()
    fix, ab = _printed_labels(dat, "displacements"), _printed_labels(dat, "stresses")
    assert (fix, ab) == ([1, 4], [1, 2, 3])  # the peer's reading, not ours
    monkeypatch.chdir(tmp_path)
    with pytest.warns(UserWarning, match=r"ignores \*MATERIAL"):  # the model's keywords
        mesh = Mesh.read(main)
    assert (mesh.node_sets["FIX"] + 1).tolist() == fix
    assert (mesh.element_sets["AB"] + 1).tolist() == ab

    (job / "parts/mesh.inp").write_text(MESH + "*INCLUDE, INPUT=sets.inp\n")
    stopped = subprocess.run(["ccx", "main"], cwd=job, env=env, capture_output=True, text=True,
                             timeout=120)  # fmt: skip
    assert "cannot open file sets.inp" in stopped.stdout + stopped.stderr
    with pytest.raises(ValueError, match="write INPUT=parts/sets.inp"):
        Mesh.read(main)
