"""A ``[[contact]]`` table's tool read from a case file (fibreshell/case_tools.py): a meshed
tool's ``smooth`` (the remedy a Static stop in a concave crease gives, solvers/
stop_diagnosis.py) reaches ``RigidSurface(smooth=True)``, checked as every key is."""

import pytest

from elements import RigidSurface
from femcore import Mesh
from fibreshell.case import CaseError, load_case
from fibreshell.run import run_case

CASE = """
title = "plate under a meshed holder"
[mesh]
rectangle = {{ lx = 20.0, ly = 20.0, nx = 2, ny = 2 }}
[[part]]
element = "mindlin"
material = {{ E = 1000.0, nu = 0.3, thickness = 1.0, density = 1e-9 }}
[[fix]]
nodes = {{ x_min = 0.0 }}
dofs = ["ux", "uy"]
[[contact]]
tool = "plane"
point = [0.0, 0.0, -0.5]
normal = [0.0, 0.0, 1.0]
[[contact]]
tool = "surface"
file = "face.vtu"
flip = true
{smooth}
free = ["z"]
pressure = 0.125
[solver]
kind = "static"
increments = 2
"""


def write_case(tmp_path, smooth: str):
    face = Mesh.rectangle(20.0, 20.0, nx=4, ny=4)
    face.with_points(face.points + [0.0, 0.0, 0.5]).write(tmp_path / "face.vtu")
    path = tmp_path / "holder.toml"
    path.write_text(CASE.format(smooth=smooth))
    return path


def test_a_meshed_holder_takes_smooth_and_presses_its_pressure_through_the_plate(tmp_path):
    """smooth = true builds the smoothed surface; on the flat face its normal is the facets',
    so the die carries the holder's pressure times its 20 x 20 mm area, 50 N (statics, 1e-6:
    Newton's tolerance is far below)."""
    case = load_case(write_case(tmp_path, "smooth = true"))
    tool = case.contacts[1]["tool"]
    assert isinstance(tool, RigidSurface) and tool.smooth
    run = run_case(case, tmp_path / "out", progress=False)
    assert run.result.converged
    assert run.result.tool_forces[-1, 0, 2] == pytest.approx(-50.0, rel=1e-6)


def test_without_smooth_the_meshed_tool_keeps_its_closest_facet_normal(tmp_path):
    assert not load_case(write_case(tmp_path, "")).contacts[1]["tool"].smooth


@pytest.mark.parametrize("smooth", ['smooth = "yes"', "smooth = 1"], ids=["string", "number"])
def test_smooth_that_is_not_a_boolean_is_refused_naming_the_key(tmp_path, smooth):
    with pytest.raises(CaseError, match=r"contact\[1\]\.smooth\]: expected true or false"):
        load_case(write_case(tmp_path, smooth))


def test_smooth_on_an_analytic_tool_is_an_unknown_key(tmp_path):
    path = write_case(tmp_path, "")
    text = path.read_text().replace('tool = "plane"\npoint', 'tool = "plane"\nsmooth = true\npoint')
    path.write_text(text)
    with pytest.raises(CaseError, match=r"contact\[0\]\.smooth\]: unknown key"):
        load_case(path)


HOLDER = """
title = "plate between a die and a holder"
[mesh]
rectangle = {{ lx = 20.0, ly = 20.0, nx = 2, ny = 2, origin = [0.0, 0.0, 0.5] }}
[[part]]
element = "mindlin"
material = {{ E = 1000.0, nu = 0.3, thickness = 1.0, density = 1e-9 }}
[[fix]]
nodes = {{ x_min = 0.0 }}
dofs = ["ux", "uy"]
[[contact]]
tool = "plane"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
[[contact]]
tool = "plane"
point = [0.0, 0.0, 1.0]
normal = [0.0, 0.0, -1.0]
free = ["z"]
force = [0.0, 0.0, {force}]
[solver]
kind = "{kind}"
increments = 2
"""


@pytest.mark.parametrize("kind", ["static", "relaxation"])
def test_a_holder_force_away_from_the_body_is_refused_at_its_file_table_and_key(
    tmp_path, capsys, kind
):
    """The holder (the second [[contact]], its face looking down at the plate) pushed up by
    10 N, away from the plate: no quasi-static position balances it. Refused before anything
    runs, as every case-file error, naming the file, [contact[1].force] and the sign to give
    (before: the solver's text alone, without the file and the key)."""
    from fibreshell.cli import main

    path = tmp_path / "holder.toml"
    path.write_text(HOLDER.format(force=10.0, kind=kind))
    assert main(["run", str(path), "--out", str(tmp_path / "out"), "--quiet"]) == 2
    said = capsys.readouterr().err
    assert f"{path}: [contact[1].force]: tool2's force (0, 0, 10) N points away from" in said
    assert "(0, 0, -10) N" in said
    with pytest.raises(CaseError, match=r"\[contact\[1\]\.force\]"):
        load_case(path).model()
    path.write_text(HOLDER.format(force=-10.0, kind=kind))
    load_case(path).model()  # towards the plate: taken


LAYUP_HOLDER = """
title = "two plies between a die and a holder"
[mesh]
rectangle = { lx = 40.0, ly = 20.0, nx = 4, ny = 2, origin = [0.0, 0.0, 0.15] }
[[part]]
element = "fibrous"
[part.material]
thickness = 0.3
areal_density = 2.85e-10
tension = 60.0
shear = 0.2
bending = 0.375
[layup]
angles = [0.0, 90.0]
friction = 0.2
[[fix]]
nodes = { y_max = "0%" }
dofs = ["uy"]
[[contact]]
tool = "plane"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
[[contact]]
tool = "plane"
point = [0.0, 0.0, 0.6]
normal = [0.0, 0.0, -1.0]
free = ["z"]
force = [0.0, 0.0, 10.0]
[solver]
kind = "static"
"""


def test_a_ply_stack_s_holder_force_away_is_named_at_its_own_contact_table(tmp_path):
    """The stack's ply-on-ply contact comes first among the model's interactions and drives
    no tool: the holder, the second [[contact]], is still the one named."""
    path = tmp_path / "plies.toml"
    path.write_text(LAYUP_HOLDER)
    with pytest.raises(CaseError, match=r"plies.toml: \[contact\[1\]\.force\]: tool2's force"):
        load_case(path).model()
