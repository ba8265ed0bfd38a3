"""Abaqus decks (.inp) read as Abaqus reads them, or refused naming the file, the line and the
set: assemblies the reader cannot place, sets generated or listed as Abaqus's keyword rules
allow, nodes and elements a set names that the deck does not define."""

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
