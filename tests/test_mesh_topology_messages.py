"""A mesh file that no shell can use is refused naming the case file, its [mesh] table and the
mesh file, how many triangles or nodes are at fault, and the remedy (femcore.topology,
femcore.orientation, fibreshell/case_model.py).

Reference: the counts are those the meshes are built with: a rectangle of 2 x 2 x 2 triangles
with one or two of them reversed, the same rectangle with a node split along a line, and a
Moebius band (one-sided: no choice of orientation makes it consistent)."""

import meshio
import numpy as np
import pytest

from femcore import Mesh
from femcore.topology import check_orientation
from fibreshell.case import load_case

CASE = """
[mesh]
file = "{mesh}"
[[part]]
element = "mindlin"
material = {{ E = 1000.0, nu = 0.3, thickness = 1.0, density = 1e-9 }}
[[fix]]
nodes = {{ x_max = "0%" }}
[solver]
kind = "static"
"""


def written(tmp_path, points, triangles, name="plate.vtu"):
    """A case file reading a VTU of ``triangles`` on ``points``: its path."""
    meshio.write(tmp_path / name, meshio.Mesh(points, [("triangle", np.asarray(triangles))]))
    case = tmp_path / "case.toml"
    case.write_text(CASE.format(mesh=name))
    return case


def plate():
    return Mesh.rectangle(20.0, 10.0, nx=2, ny=2)


def test_reversed_triangles_are_counted_named_and_their_remedy_given(tmp_path):
    mesh = plate()
    triangles = mesh.triangles.copy()
    triangles[[2, 5]] = triangles[[2, 5]][:, ::-1]  # two of the 8 triangles face down
    case = written(tmp_path, mesh.points, triangles)
    with pytest.raises(ValueError) as raised:
        load_case(case).model()
    message = str(raised.value)
    assert f"{case}: [mesh.file]: plate.vtu: " in message
    assert "2 of the 8 triangles of their connected surface face the other way" in message
    assert "(triangles 2, 5)" in message
    assert "gmsh.model.mesh.reverse" in message


def test_one_reversed_triangle_is_the_one_named():
    mesh = plate()
    triangles = mesh.triangles.copy()
    triangles[6] = triangles[6][::-1]
    with pytest.raises(ValueError, match=r"1 of the 8 triangles .* faces .*\(triangle 6\)"):
        check_orientation(triangles)


def moebius_band(n: int = 8) -> np.ndarray:
    """The triangles of a band of n segments closed with a half twist: bottom node i, top node
    n + i; the last segment joins bottom to top."""
    triangles = []
    for i in range(n):
        a, b = i, n + i
        c, d = (i + 1, n + i + 1) if i < n - 1 else (n, 0)  # the twist swaps the sides
        triangles += [(a, c, d), (a, d, b)]
    return np.array(triangles)


def test_a_one_sided_surface_is_said_to_be_not_orientable():
    with pytest.raises(ValueError, match="not orientable"):
        check_orientation(moebius_band())


def test_duplicate_nodes_name_the_mesh_file_and_the_remedy(tmp_path):
    mesh = plate()
    points = np.vstack([mesh.points, mesh.points[4]])  # the centre node, twice
    triangles = mesh.triangles.copy()
    triangles[triangles[:, 0] == 4, 0] = len(mesh.points)  # some triangles on the copy
    case = written(tmp_path, points, triangles)
    with pytest.raises(ValueError) as raised:
        load_case(case).model()
    message = str(raised.value)
    assert f"{case}: [mesh.file]: plate.vtu: duplicate nodes 4 and 9" in message
    assert "1 such pair in all" in message and "removeDuplicateNodes" in message
