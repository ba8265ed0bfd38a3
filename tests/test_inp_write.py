"""Mesh.write's .inp read back as written: by this reader bit for bit, by CalculiX at all.

References: CalculiX 2.20 reads at most 20 characters per number of a data line (an F20.0
field: its "*ERROR reading *NODE" on meshio's 23-character ``%.16e``); Python's repr is the
shortest decimal that reads back to the same double (at most 17 significant digits), so a
double of magnitude 0.01 to 1e17 fits 20 characters (sign, 17 digits, point, and ".0" below
0.1). The Abaqus Analysis User's Guide, "Input syntax rules": a label's blanks are read away
unless it is quoted.
"""

import re
import shutil
import subprocess

import numpy as np
import pytest

from femcore.inp_write import FIELD_WIDTH, node_number
from femcore.mesh import Mesh


def triangles_over(points: np.ndarray) -> np.ndarray:
    """Triangles (0, k, k + 1) over points that are not collinear."""
    k = np.arange(1, len(points) - 1)
    return np.column_stack([np.zeros_like(k), k, k + 1])


def node_fields(text: str) -> list[str]:
    block = text.split("*NODE\n")[1].split("*")[0]
    return [field.strip() for line in block.splitlines() for field in line.split(",")[1:]]


def test_written_coordinates_fit_20_characters_and_read_back_bit_for_bit(tmp_path):
    """meshio's %.16e (23 characters) before: CalculiX refused every node line."""
    rng = np.random.default_rng(7)
    magnitude = 10.0 ** rng.uniform(-2, 17, size=(300, 3))  # the range every double fits
    points = magnitude * rng.choice([-1.0, 1.0], size=(300, 3)) * rng.uniform(1, 9.99, (300, 3))
    points[:3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
    points[3] = [-0.0, -0.012345678901234567, 99999999999999984.0]
    mesh = Mesh(points, triangles=triangles_over(points[:4]))
    mesh.write(tmp_path / "m.inp")
    fields = node_fields((tmp_path / "m.inp").read_text())
    assert max(len(field) for field in fields) <= FIELD_WIDTH
    assert np.array_equal(Mesh.read(tmp_path / "m.inp").points, points)  # every bit


@pytest.mark.parametrize("value", [-1.2345678901234567e-5, 1.7976931348623157e308, -3.3e-300])
def test_a_coordinate_that_cannot_fit_is_the_closest_decimal_that_does(value):
    text, exact = node_number(value)
    assert len(text) <= FIELD_WIDTH
    assert float(text) == pytest.approx(value, rel=1e-13, abs=0.0)
    assert exact == (float(text) == value)


def test_set_names_with_blanks_are_quoted_and_read_back(tmp_path):
    """'left edge' was written unquoted and read back as 'leftedge'."""
    points = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]])
    mesh = Mesh(
        points,
        triangles=np.array([[0, 1, 2]]),
        node_sets={"left edge": [0, 2], "tip": [1]},
        element_sets={"My Plate": [0]},
    )
    mesh.write(tmp_path / "named.inp")
    text = (tmp_path / "named.inp").read_text()
    assert '*NSET, NSET="left edge"' in text and "*NSET, NSET=tip\n" in text
    back = Mesh.read(tmp_path / "named.inp")
    assert sorted(back.node_sets) == ["left edge", "tip"]
    assert list(back.element_sets) == ["My Plate"]
    assert back.nodes("left edge").tolist() == [0, 2]


CANTILEVER = """*MATERIAL, NAME=STEEL
*ELASTIC
210000., 0.3
*SHELL SECTION, ELSET=PLATE, MATERIAL=STEEL
0.1
*STEP
*STATIC
*BOUNDARY
LEFT, 1, 6
*CLOAD
RIGHT, 3, 1.
*NODE PRINT, NSET=RIGHT
U
*END STEP
"""


def calculix_tip(folder, name: str, deck: str) -> np.ndarray:
    (folder / f"{name}.inp").write_text(deck + CANTILEVER)
    run = subprocess.run(["ccx", "-i", name], cwd=folder, capture_output=True, text=True)
    assert "ERROR" not in run.stdout, run.stdout[-2000:]
    rows = re.findall(
        r"^\s*\d+\s+(\S+)\s+(\S+)\s+(\S+)\s*$", (folder / f"{name}.dat").read_text(), re.M
    )
    return np.array(rows, dtype=float)


@pytest.mark.skipif(shutil.which("ccx") is None, reason="CalculiX (calculix-ccx) not installed")
def test_calculix_reads_a_written_mesh_as_the_mesh(tmp_path):
    """A cantilever of S3 triangles whose coordinates need 16-17 digits (lengths of pi / 3):
    ccx refused Mesh.write's file before; its tip deflection equals that of the same mesh
    written by hand with 9 decimals (a change of 1e-9 mm: 1e-6 relative is plenty)."""
    mesh = Mesh.rectangle(2.0 * np.pi / 3, np.pi / 3, 2, 1)
    mesh.add_element_set("plate", range(mesh.n_triangles))
    assert mesh.nodes("left").tolist() == [0, 3] and mesh.nodes("right").tolist() == [2, 5]
    mesh.write(tmp_path / "written.inp")
    written = (tmp_path / "written.inp").read_text()
    by_hand = written.split("*NODE\n")[0] + "*NODE\n"
    by_hand += "".join(
        f"{i + 1}, {x:.9f}, {y:.9f}, {z:.9f}\n" for i, (x, y, z) in enumerate(mesh.points)
    )
    by_hand += written[written.index("*ELEMENT") :]
    ours = calculix_tip(tmp_path, "written", written)
    theirs = calculix_tip(tmp_path, "by_hand", by_hand)
    assert ours.shape == (2, 3) and abs(ours[0, 2]) > 0.0
    np.testing.assert_allclose(ours, theirs, rtol=1e-6, atol=1e-12)
