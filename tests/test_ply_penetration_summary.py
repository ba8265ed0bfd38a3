"""A run's ply contacts that gave way under their pressure (fibreshell/layup_summary.py
``ply_penetrations``, fibreshell/run.py ``_say_penetrations``): past a quarter of the ply
thickness the summary holds the penetration and the penalty that would keep it within that
share, and the run warns naming it (a crossing's advice is then the penalty, not the
mirrored pass that does not help a contact that gives way)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from elements import RigidPlane
from elements.layup import Layup
from fibreshell.layup_summary import PENETRATION_SHARE, ply_penetrations
from fibreshell.run import _say_crossings, _say_penetrations
from materials import Fabric
from solvers import Static

PLY = Fabric(thickness=0.3, areal_density=2.85e-10, tension=60.0, shear=0.2, bending=0.375)
SIDE = 40.0  # mm


def _pressed(pressure, penalty=None):
    """A [0/90] pair on a table, held in plane, the top ply pressed by ``pressure`` (MPa)."""
    layup = Layup(PLY, (0.0, 90.0), SIDE, cells=2, penalty=penalty)
    model = layup.model()
    model.fix(np.arange(layup.mesh.n_nodes), ["ux", "uy"])
    model.contact(RigidPlane((0.0, 0.0, 0.0), (0.0, 0.0, 1.0)), nodes="ply_1")
    top = layup.ply_nodes[1]
    x = layup.mesh.points
    tri = layup.mesh.triangles[layup.ply_cells[1]]
    area = 0.5 * np.abs(np.cross(x[tri[:, 1]] - x[tri[:, 0]], x[tri[:, 2]] - x[tri[:, 0]])[:, 2])
    lumped = np.bincount(tri.ravel(), np.repeat(area / 3.0, 3), layup.mesh.n_nodes)
    for node in top:
        model.force([int(node)], (0.0, 0.0, -pressure * lumped[node]), amplitude="linear")
    result = Static(increments=2, progress=False, seek_stable=False).solve(model)
    return layup, result.frames[-1].fields["point"]


def test_a_pair_pressed_at_a_consolidation_pressure_gets_the_penalty_that_holds_it():
    layup, fields = _pressed(0.1)  # 160 N on 40 x 40 mm
    said = ply_penetrations(layup, fields)
    assert list(said) == ["ply_2"]
    assert said["ply_2"]["share_of_thickness"] > PENETRATION_SHARE
    # the penalty said, given: the deepest node within the share, and not by much more than
    # the margin's 1.5 (the load the same, statics; the give is the load over the springs)
    again, fields = _pressed(0.1, penalty=said["ply_2"]["penalty"])
    depth = -np.nanmin(fields["ply_gap"])
    limit = PENETRATION_SHARE * PLY.thickness
    assert limit / 2.0 < depth <= limit
    assert ply_penetrations(again, fields) == {}


def test_a_light_press_is_not_said():
    layup, fields = _pressed(1e-4)
    assert ply_penetrations(layup, fields) == {}


def test_the_warning_names_the_penalty_and_the_crossing_advice_follows_it():
    penetrations = {
        "ply_2": {"upper": "ply_2", "lower": "ply_1", "deepest_mm": 0.251,
                  "share_of_thickness": 0.837, "nodes": 9, "penalty": 5331.0}
    }  # fmt: skip
    with pytest.warns(
        UserWarning, match=r"ply_2 into ply_1 by up to 0\.251 mm.*penalty = 5.33e\+03"
    ):
        _say_penetrations(penetrations)
    crossed = {"ply_2": {"lower": "ply_1", "nodes": 2, "deepest_mm": 0.1, "first": [3, 4]}}
    with pytest.warns(UserWarning, match=r"a larger \[layup\] penalty") as said:
        _say_crossings(crossed, None, penetrated=True)
    assert "lower_rule" not in str(said[0].message)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        _say_penetrations({})


def test_a_ply_beside_the_other_is_not_taken_for_a_penetration():
    """Beside the lower ply's outline the gap field is the distance to its edge (negative
    below its plane), with no contact force: not a penetration."""
    layup = Layup(PLY, (0.0, 90.0), SIDE, cells=2)
    n = layup.mesh.n_nodes
    gap = np.full(n, np.nan)
    gap[layup.ply_nodes[1]] = -25.0
    fields = {"ply_gap": gap, "ply_contact_force": np.zeros(n)}
    assert ply_penetrations(layup, fields) == {}
