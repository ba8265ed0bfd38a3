"""gmsh physical groups read as sets, or refused naming the file and the groups: two groups of
one name (a curve "plate" beside a surface "plate" lost the curve's line set), a name a set
cannot take ("x=0 edge" made the file unreadable, the message naming no file)."""

from pathlib import Path

import pytest

from femcore.mesh import Mesh


def msh(tmp_path: Path, curve: str, surface: str) -> Path:
    """A unit square of two triangles (physical surface ``surface``, tag 1) and its edge at
    x = 0 (physical curve ``curve``, tag 1), MSH 2.2."""
    path = tmp_path / "square.msh"
    path.write_text(f"""$MeshFormat
2.2 0 8
$EndMeshFormat
$PhysicalNames
2
1 1 "{curve}"
2 1 "{surface}"
$EndPhysicalNames
$Nodes
4
1 0 0 0
2 1 0 0
3 1 1 0
4 0 1 0
$EndNodes
$Elements
3
1 1 2 1 1 4 1
2 2 2 1 1 1 2 3
3 2 2 1 1 1 3 4
$EndElements
""")  # fmt: skip
    return path


def test_groups_of_distinct_names_are_read(tmp_path):
    mesh = Mesh.read(msh(tmp_path, "clamp", "plate"))
    assert mesh.line_sets["clamp"].tolist() == [0] and mesh.element_sets["plate"].size == 2


def test_a_curve_and_a_surface_of_one_name_are_refused_naming_both(tmp_path):
    both = r"'plate' of dimension 1 \(tag 1\) and of dimension 2 \(tag 1\) share a name"
    with pytest.raises(ValueError, match=r"square.msh: the physical groups " + both):
        Mesh.read(msh(tmp_path, "plate", "plate"))


def test_a_group_name_a_set_cannot_take_is_refused_naming_the_file_and_the_group(tmp_path):
    group = r"'x=0 edge' \(dimension 1, tag 1\) has a name a set cannot take"
    with pytest.raises(ValueError, match=r"square.msh: the physical group " + group):
        Mesh.read(msh(tmp_path, "x=0 edge", "plate"))
