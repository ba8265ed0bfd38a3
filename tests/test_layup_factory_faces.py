"""A Layup's fibrous plies take their contact faces along the normal whatever names their
shell: "fibrous" or a factory building a FibrousShell (how a case gives element options such
as a clamp, fibreshell.case_layup.PlyShell). Faces along a fibrous director are a zero-energy
path (docs/theory.md §9.3b, "Faces of fibrous plies"), on which two plies in bending do not
slip over each other."""

from __future__ import annotations

import numpy as np
import pytest

from elements.layup import Layup
from fibreshell.case_layup import PlyShell
from materials import Fabric
from solvers import Static

BENDING = 0.375  # N mm, B per unit width
PLY = Fabric(thickness=0.3, areal_density=2.85e-10, tension=60.0, shear=0.2, bending=BENDING)
LENGTH, WIDTH = 100.0, 20.0  # mm


@pytest.mark.parametrize(
    "kinematics, faces",
    [("fibrous", "normal"), (PlyShell("fibrous", {"clamped": "left"}), "normal"),
     ("mindlin", "director"), (PlyShell("mindlin", {}), "director")],
    ids=["fibrous", "fibrous-factory", "mindlin", "mindlin-factory"],
)  # fmt: skip
def test_the_default_faces_follow_the_shell_the_plies_are(kinematics, faces):
    assert Layup(PLY, (0.0, 90.0), 20.0, cells=2, kinematics=kinematics).faces == faces


def test_two_frictionless_fibrous_plies_of_a_factory_slip_as_euler_bernoulli_plies():
    """Two [0/0] fibrous plies (a factory's, clamped at x = 0), frictionless, a tip force F on
    the top ply's free end: each ply bends alone under F / 2, its section turned by theta(x)
    = (F / 2) (L x - x^2 / 2) / (B w), and the faces h apart slip by h theta(x) (Euler-
    Bernoulli). Measured at 10 cells: 0.00455 mm at the tip against 0.00450, 0.00340 at
    mid-span against 0.00338 (1.1 and 0.6 %; the rotation-free bending's discretisation at 10
    cells); within 3 %. Faces along the directors gave 0.00005 mm at the tip."""
    layup = Layup(
        PLY,
        (0.0, 0.0),
        LENGTH,
        WIDTH,
        cells=10,
        kinematics=PlyShell("fibrous", {"clamped": "left"}),
        centre=(LENGTH / 2, WIDTH / 2),
    )
    model = layup.model()
    model.fix("left")
    force = 3.0 * BENDING * WIDTH / LENGTH**3 * 2  # N: a tip deflection of 1 mm
    tip = layup.mesh.node_sets["ply_2_right"]
    model.force(tip, (0.0, 0.0, -force / len(tip)), amplitude="linear")
    result = Static(increments=4, progress=False, seek_stable=False).solve(model)
    slip = result.field("ply_slip")
    x = layup.mesh.points[:, 0]
    top = layup.ply_nodes[1]
    for at in (LENGTH, LENGTH / 2):
        theta = (force / 2) * (LENGTH * at - at**2 / 2) / (BENDING * WIDTH)
        nodes = top[np.isclose(x[top], at)]
        assert np.mean(slip[nodes]) == pytest.approx(PLY.thickness * theta, rel=0.03)
