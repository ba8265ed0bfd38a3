"""How deep a body ends inside its rigid tools (solvers/tool_penetration.py, through
``InteractionBlock.tool_penetrations``): ``result.info["tool_penetration"]``, summary.json's
``tool_penetration``, and a warning past a quarter of the thickness with the remedies.

Reference, a closed form: a plate (2 x 2 cells, 9 nodes) between a fixed die plane and a
holder plane free along z pushed by F, in statics, its in-plane motion held, every contact
node a penalty spring of k N/mm: the plate translates as one, every node of each contact
presses alike, and each tool's depth into the plate's contact surface is F / (9 k) (Newton's
residual tolerance, 1e-8, leaves far less than the 1e-6 asked).
"""

import json
import warnings

import numpy as np
import pytest

from elements import MindlinShell, RigidPlane
from femcore import Mesh, Model
from fibreshell.case import load_case
from fibreshell.run import run_case
from materials import ElasticShell
from solvers import Static
from solvers.tool_penetration import PENETRATION_SHARE

PENALTY = 1000.0  # N/mm per node
NODES = 9  # of the 2 x 2 plate
THICKNESS = 1.0  # mm


def plate_between_tools(force: float, augmented: bool = False) -> Model:
    """The plate on the die z = 0 (mid-surface h / 2 above), the holder on its top face."""
    flat = Mesh.rectangle(20.0, 20.0, nx=2, ny=2)
    model = Model(flat.with_points(flat.points + [0.0, 0.0, 0.5 * THICKNESS]))
    model.add(MindlinShell(ElasticShell(E=1000.0, nu=0.3, thickness=THICKNESS, density=1e-9)))
    model.fix(lambda x, y, z: np.ones_like(x, dtype=bool), ["ux", "uy"])
    model.contact(RigidPlane((0.0, 0.0, 0.0), (0.0, 0.0, 1.0)), penalty=PENALTY)
    holder = RigidPlane((0.0, 0.0, THICKNESS), (0.0, 0.0, -1.0), free="z", force=(0, 0, -force))
    model.contact(holder, penalty=PENALTY, augmented=augmented)
    return model


def solved(model: Model):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = Static(increments=2).solve(model)
    assert result.converged
    return result, [str(w.message) for w in caught if "into its rigid tools" in str(w.message)]


@pytest.mark.parametrize("force", [400.0, 4000.0], ids=["within", "past"])
def test_each_tool_reports_the_closed_form_depth_and_where(force):
    """Both tools F / (9 k) deep (1e-6 relative), on 9 pressed nodes, at a node of the plate
    whose position is given; a quarter of h past the share counts every node."""
    result, _ = solved(plate_between_tools(force))
    report = result.info["tool_penetration"]
    assert set(report) == {"tool1", "tool2"}
    depth = force / (NODES * PENALTY)
    for entry in report.values():
        assert entry["deepest_mm"] == pytest.approx(depth, rel=1e-6)
        assert entry["share_of_thickness"] == pytest.approx(depth / THICKNESS, rel=1e-6)
        assert entry["thickness_mm"] == THICKNESS
        assert entry["pressed"] == NODES
        assert entry["past_share"] == (NODES if depth > PENETRATION_SHARE * THICKNESS else 0)
        assert entry["force_N"] == pytest.approx(force, rel=1e-6)
        np.testing.assert_allclose(entry["at"], result.positions[entry["node"]], atol=1e-12)


def test_a_tool_past_a_quarter_of_the_thickness_warns_with_the_penalty_that_holds_it():
    """4000 N: 0.444 h into each tool, one warning naming both, a penalty that keeps them
    within the quarter (under it, F / (9 k) is at most 0.25 h: checked by its closed form),
    and the remedies Static supports (augmented); 400 N (0.044 h) says nothing."""
    _, quiet = solved(plate_between_tools(400.0))
    assert quiet == []
    result, said = solved(plate_between_tools(4000.0))
    assert len(said) == 1
    assert "tool1 by 0.444 mm" in said[0] and "tool2 by 0.444 mm" in said[0]
    assert "augmented" in said[0] and "finer mesh" in said[0]
    penalty = result.info["tool_penetration"]["tool1"]["penalty"]
    assert f"penalty = {penalty:.3g} N/mm" in said[0]
    assert 4000.0 / (NODES * penalty) <= PENETRATION_SHARE * THICKNESS


def test_the_augmented_holder_stays_within_its_tolerance_and_does_not_warn_of_itself():
    """The remedy said: the augmented holder's depth is within its tolerance (1e-3 h by
    default), where the plain die beside it is still F / (9 k) deep and warns alone."""
    result, said = solved(plate_between_tools(4000.0, augmented=True))
    report = result.info["tool_penetration"]
    assert report["tool2"]["deepest_mm"] <= 1e-3 * THICKNESS * (1.0 + 1e-9)
    assert report["tool1"]["deepest_mm"] == pytest.approx(4000.0 / (NODES * PENALTY), rel=1e-6)
    assert len(said) == 1 and "tool1 by" in said[0] and "tool2" not in said[0]


CASE = """
title = "plate between tools"
[mesh]
rectangle = { lx = 20.0, ly = 20.0, nx = 2, ny = 2, origin = [0.0, 0.0, 0.5] }
[[part]]
element = "mindlin"
material = { E = 1000.0, nu = 0.3, thickness = 1.0, density = 1e-9 }
[[fix]]
nodes = { x_min = 0.0 }
dofs = ["ux", "uy"]
[[contact]]
tool = "plane"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
penalty = 1000.0
[[contact]]
tool = "plane"
point = [0.0, 0.0, 1.0]
normal = [0.0, 0.0, -1.0]
penalty = 1000.0
free = ["z"]
force = [0.0, 0.0, -4000.0]
[solver]
kind = "static"
increments = 2
"""


def test_a_case_run_writes_each_tools_depth_into_summary_json_and_warns(tmp_path):
    """The same plate from a case file: summary.json's tool_penetration holds each tool's
    closed-form depth and where, and the run warns."""
    path = tmp_path / "plate.toml"
    path.write_text(CASE)
    with pytest.warns(UserWarning, match="into its rigid tools: tool1 by 0.444 mm"):
        run_case(load_case(path), tmp_path / "out", progress=False)
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    for tool in ("tool1", "tool2"):
        entry = summary["tool_penetration"][tool]
        assert entry["deepest_mm"] == pytest.approx(4000.0 / (NODES * PENALTY), rel=1e-6)
        assert len(entry["at"]) == 3 and isinstance(entry["node"], int)
