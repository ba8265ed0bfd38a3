"""An Abaqus/CAE deck's part and assembly scopes kept apart, not merged into one numbering.

Reference: the Abaqus Analysis User's Guide, "Defining an assembly" and "Defining a
reference point": a part's nodes, elements and sets are its own (the assembly names them
through an instance, ``*NSET, INSTANCE=Plate-1``, or as ``Plate-1.Set-1``); the assembly's
own nodes (a reference point) and sets are numbered and named apart, from 1 again. The decks
are as Abaqus/CAE 2021 writes them (a plate of two S4R, one unmoved instance); the sets and
coordinates expected are read off their text.
"""

import warnings
from pathlib import Path

import numpy as np
import pytest

from femcore.mesh import Mesh

PART = """*Heading
*Part, name=Plate
*Node
      1,           0.,           0.,           0.
      2,           1.,           0.,           0.
      3,           1.,           1.,           0.
      4,           0.,           1.,           0.
      5,           2.,           0.,           0.
      6,           2.,           1.,           0.
*Element, type=S4R
1, 1, 2, 3, 4
2, 2, 5, 6, 3
*Nset, nset=Set-1, generate
 1,  6,  1
*Elset, elset=Set-1, generate
 1,  2,  1
*End Part
*Assembly, name=Assembly
*Instance, name=Plate-1, part=Plate
*End Instance
"""
REFERENCE_POINT = """*Node
      1,          0.5,          0.5,          5.
*Nset, nset=RP-1
 1,
"""
INSTANCE_SETS = """*Nset, nset={name}, instance=Plate-1
 1, 4
*Elset, elset=Skin, instance=Plate-1
 1,
*Nset, nset=_PickedSet4, internal, instance=Plate-1
 5, 6
*End Assembly
"""


def read(tmp_path: Path, text: str) -> Mesh:
    path = tmp_path / "cae.inp"
    path.write_text(text)
    return Mesh.read(path)


def test_a_reference_point_is_left_out_with_a_warning_not_read_as_the_part_s_node_1(tmp_path):
    """The assembly's node 1 at (0.5, 0.5, 5) replaced the part's node 1 before, silently."""
    text = PART + REFERENCE_POINT + INSTANCE_SETS.format(name="Clamp")
    with pytest.warns(
        UserWarning,
        match=r"cae.inp: line 21: \*NODE \(a reference point's node\); .*"
        r"line 23: \*NSET RP-1 \(the assembly's own set\)",
    ):
        mesh = read(tmp_path, text)
    assert mesh.points.tolist() == [
        [0, 0, 0],
        [1, 0, 0],
        [1, 1, 0],
        [0, 1, 0],
        [2, 0, 0],
        [2, 1, 0],
    ]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        flat = read(tmp_path, PART.split("*End Part")[0])  # the part alone, as a flat deck
    np.testing.assert_array_equal(mesh.triangles, flat.triangles)
    assert "RP-1" not in mesh.node_sets


def test_assembly_sets_given_with_instance_name_the_part_s_labels(tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        mesh = read(tmp_path, PART + INSTANCE_SETS.format(name="Clamp"))
    assert mesh.node_sets["Clamp"].tolist() == [0, 3]
    assert mesh.node_sets["_PickedSet4"].tolist() == [4, 5]
    assert mesh.node_sets["Set-1"].tolist() == [0, 1, 2, 3, 4, 5]


def test_a_set_name_of_the_part_and_of_the_assembly_is_refused_naming_both_lines(tmp_path):
    """Set-1 of the part (6 nodes) and of the assembly (2 nodes) merged into one set of 6
    before: a clamp of the whole plate where Abaqus clamps an edge."""
    with pytest.raises(
        ValueError,
        match=r"line 21: \*NSET 'Set-1' is defined in the part \(.*line 13\) and in the "
        r"assembly \(.*line 21\)",
    ):
        read(tmp_path, PART + INSTANCE_SETS.format(name="Set-1"))


def test_elements_of_the_assembly_itself_are_refused_naming_the_line(tmp_path):
    """Their labels name the assembly's nodes, which are not the part's."""
    text = PART + REFERENCE_POINT + "*Element, type=S3\n9, 1, 2, 3\n*End Assembly\n"
    with pytest.raises(ValueError, match=r"line 25: \*ELEMENT in the assembly, outside its"):
        read(tmp_path, text)
