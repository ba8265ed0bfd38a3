"""Case files and the ``fibreshell`` command (fibreshell/): a case file builds the model its
Python twin builds, ``compare`` runs both kinematics with each Mindlin calibration (checked
against the Euler-Bernoulli cantilever; tests/test_compare.py has the rest), every mistake in
a file is a ValueError naming the file, the table and the key, and the JSON outputs are strict.
"""

import csv
import json
import re
import warnings
from pathlib import Path

import numpy as np
import pytest

from elements import FibrousShell
from femcore import Mesh, Model
from fibreshell import CaseError, compare_case, load_case, run_case, strict_json
from fibreshell.case import case_from_data
from fibreshell.cli import main
from materials import BendingLaw, ElasticShell, ShearLaw, TensionLaw, presets
from solvers import Static

ROOT = Path(__file__).resolve().parents[1]
STRIP = ROOT / "cases" / "g1151_strip.toml"

# Euler-Bernoulli cantilever of length L = 100 mm under its weight q = rho_A g per unit area,
# bending stiffness B = 10 N mm/mm: tip deflection q L^4 / (8 B) = 0.1 mm (0.1 % of L: linear).
MATERIAL = """[part.material]
thickness = 0.2
areal_density = 8.154943934760449e-12
tension = 1000.0
shear = 1.0
bending = 10.0
"""
CANTILEVER = f"""
title = "cantilever under uniform load"
[mesh]
rectangle = {{ lx = 100.0, ly = 10.0, nx = 20, ny = 2 }}
[sets]
tip = {{ x_min = 100.0 }}
[[part]]
element = "fibrous"
options = {{ clamped = "left" }}
{MATERIAL}
[[fix]]
nodes = "left"
[gravity]
acceleration = [0.0, 0.0, -9810.0]
[solver]
kind = "static"
increments = 1
[output]
history = {{ reactions = ["left"], displacements = ["tip"] }}
paths = {{ edge = {{ y_max = 0.0 }} }}
"""


def write(tmp_path: Path, text: str, name: str = "case.toml") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def strict_load(text: str):
    """json.loads that refuses NaN and Infinity, as strict parsers and JavaScript do."""

    def refuse(constant):
        raise AssertionError(f"non-standard JSON constant {constant}")

    return json.loads(text, parse_constant=refuse)


# ---------------------------------------------------------------------- what a case does
@pytest.mark.slow
def test_the_shipped_strip_case_builds_the_model_of_its_python_twin(tmp_path):
    """cases/g1151_strip.toml is the README's Python example: the same mesh, element, clamp,
    gravity and solver give the same tip deflection (the same arithmetic: 1e-12)."""
    run = run_case(load_case(STRIP), tmp_path, progress=False)
    mesh = Mesh.rectangle(200.0, 60.0, nx=8, ny=2)
    model = Model(mesh)
    model.add(FibrousShell(presets.g1151_laminate(), clamped="left"))
    model.fix("left")
    model.gravity((0.0, 0.0, -9810.0))
    twin = Static(increments=3, progress=False).solve(model)
    tip = mesh.nodes("right")
    expected = twin.displacements[tip].mean(axis=0)
    assert np.allclose(run.summary["mean_displacements"]["tip"], expected, rtol=0, atol=1e-12)
    # the clamp carries the weight: rho_A g times the area (Bai Table 2 laminate, 6.93 kg/m^2)
    weight = presets.g1151_laminate().areal_density * 9810.0 * 200.0 * 60.0
    assert run.summary["reactions"]["left"][2] == pytest.approx(weight, rel=1e-9)
    with open(tmp_path / "history.csv") as handle:
        rows = list(csv.DictReader(handle))
    assert len(rows) == len(run.result.frames) == 4
    assert float(rows[-1]["displacement_tip_z"]) == pytest.approx(expected[2], abs=1e-12)
    assert (tmp_path / "result.pvd").is_file()
    strict_load((tmp_path / "summary.json").read_text())


@pytest.mark.parametrize("calibration", ["laws", "initial-slope"])
def test_compare_runs_both_kinematics_against_the_beam_closed_form(tmp_path, calibration):
    """A cantilever strip under its weight, small deflection: q L^4 / (8 B) = 0.1 mm. The
    fibrous shell (rotation-free bending, 20 cells along: +0.25 % measured) and the Mindlin
    shell of either calibration (the fabric's laws, or ElasticShell.equivalent's E h^3 / 12 =
    B with nu = 0; transverse shear adds q L^2 / (2 S), 3e-6 of it here) both within 1 %: a
    linear law has one slope, so the calibrations agree; the reactions are the weight."""
    case = load_case(write(tmp_path, CANTILEVER))
    runs = compare_case(case, tmp_path / "out", progress=False, calibration=calibration)
    q = 8.154943934760449e-12 * 9810.0
    exact = q * 100.0**4 / (8 * 10.0)
    for kinematics in ("fibrous", "mindlin"):
        summary = runs[kinematics].summary
        assert summary["converged"]
        assert -summary["mean_displacements"]["tip"][2] == pytest.approx(exact, rel=0.01)
        assert summary["reactions"]["left"][2] == pytest.approx(q * 1000.0, rel=1e-9)
    comparison = strict_load((tmp_path / "out" / "comparison.json").read_text())
    assert comparison["figures"] == ["view-3d.png", "path-edge.png"]
    for figure in comparison["figures"]:
        assert (tmp_path / "out" / figure).stat().st_size > 10_000
    assert set(comparison["kinematics"]) == {"fibrous", "mindlin"}
    assert comparison["calibration"]["name"] == calibration


def test_both_shells_write_the_common_fields_and_the_beam_moment(tmp_path):
    """The fields of README "Output fields" under the same names and shapes for both shells;
    the warp bending moment per unit width against the cantilever's q (L - x)^2 / 2 on the
    half by the clamp (measured: 3.5 % of the root moment for the fibrous shell, whose
    curvature is constant per cell from the folds of its sides, 1.7 % for the Mindlin shell;
    tolerance 5 %)."""
    case = load_case(write(tmp_path, CANTILEVER))
    runs = compare_case(case, tmp_path / "out", progress=False)
    q = 8.154943934760449e-12 * 9810.0
    centre = case.mesh.points[case.mesh.triangles].mean(axis=1)[:, 0]
    exact = q * (100.0 - centre) ** 2 / 2
    near = centre < 50.0
    for kinematics, run in runs.items():
        result = run.result
        assert result.field("thickness").shape == (case.mesh.n_nodes,)
        assert result.field("director_tilt_deg").shape == (case.mesh.n_nodes,)
        assert result.field("membrane_force").shape == (len(case.mesh.triangles), 3)
        moment = np.abs(result.field("bending_moment")[:, 0])
        error = np.abs(moment - exact)[near].max() / exact.max()
        assert error < 0.05, (kinematics, error)
        # history.csv carries the strain energy of each frame: U = b q^2 L^5 / (40 B) for the
        # beam (b = 10 mm wide), 1.6e-6 N mm; measured +0.4 % (fibrous), +0.003 % (Mindlin)
        with open(tmp_path / "out" / kinematics / "history.csv") as handle:
            last = list(csv.DictReader(handle))[-1]
        energy = 10.0 * q**2 * 100.0**5 / (40 * 10.0)
        assert float(last["energy_internal"]) == pytest.approx(energy, rel=0.02)
    # the thickness along the director: h for the Mindlin section, h_m >= h for the fabric
    assert np.allclose(runs["mindlin"].result.field("thickness"), 0.2)
    assert (runs["fibrous"].result.field("thickness") >= 0.2 - 1e-12).all()


def test_the_mindlin_calibration_bends_like_the_fabric():
    """ElasticShell.equivalent: plate bending stiffness E h^3 / 12 (nu = 0) = B per direction,
    G12 h = K, mass per area = rho_A (the rule stated in its docstring, Bai §6)."""
    fabric = presets.g1151_laminate()
    section = ElasticShell.equivalent(fabric, shear_ratio=0.5)
    h = fabric.thickness
    q = section.plane_stress
    assert q[0, 0] * h**3 / 12 == pytest.approx(float(fabric.bending.slope(np.array(0.0))))
    assert q[1, 1] * h**3 / 12 == pytest.approx(float(fabric.bending_weft.slope(np.array(0.0))))
    assert q[0, 1] == 0.0
    assert q[2, 2] * h == pytest.approx(float(fabric.shear.slope(np.array(0.0))))
    assert section.areal_density == pytest.approx(fabric.areal_density)
    with pytest.raises(ValueError, match="Fabric"):
        ElasticShell.equivalent("g1151", 0.5)
    with pytest.raises(ValueError, match="shear_ratio"):
        ElasticShell.equivalent(fabric, -1.0)


# ---------------------------------------------------------------------- mistakes
@pytest.mark.parametrize(
    "old, new, where",
    [
        ("increments = 1", "incremnts = 1", r"\[solver.incremnts\]: unknown option"),
        ('kind = "static"', 'kind = "statics"', r"\[solver.kind\]: expected one of"),
        ("[gravity]", "[gravty]", r"\[gravty\]: unknown key"),
        ('nodes = "left"', 'nodes = "lefft"', r"\[fix\[0\].nodes\]: unknown node set 'lefft'"),
        ('element = "fibrous"', 'element = "fibrus"', r"\[part\[0\].element\]: unknown element"),
        ("bending = 10.0\n", "bending = 10.0\nbendng = 1.0\n", r"\[part\[0\].material.bendng\]"),
        ('clamped = "left"', 'clampd = "left"', r"\[part\[0\].options.clampd\]: unknown option"),
        ("tip = { x_min = 100.0 }", "tip = { x_min = 1000.0 }", r"\[sets.tip\]: no node"),
        ("tip = { x_min = 100.0 }", "tip = { x_mn = 100.0 }", r"\[sets.tip.x_mn\]: unknown key"),
        ("nx = 20", "nx = 2.5", r"\[mesh.rectangle.nx\]: expected a whole number"),
        ('displacements = ["tip"]', 'displacements = ["tp"]', r"\[output.history.displacements\]"),
        (
            "acceleration = [0.0, 0.0, -9810.0]",
            'acceleration = "down"',
            r"\[gravity.acceleration\]",
        ),
        ("increments = 1", "increments = -1", r"\[solver.increments\]: increments must be"),
        ("tension = 1000.0", 'tension = "x"', r"\[part\[0\].material.tension\]: expected"),
        ("bending = 10.0", "bending = { cubic = 1.0 }", r"\[part\[0\].material.bending\]"),
    ],
)
def test_a_mistake_in_a_case_file_names_the_file_the_table_and_the_key(tmp_path, old, new, where):
    assert old in CANTILEVER
    path = write(tmp_path, CANTILEVER.replace(old, new, 1))
    with pytest.raises(CaseError, match=where) as error:
        load_case(path)
    assert str(path) in str(error.value)
    assert isinstance(error.value, ValueError)


MINDLIN_PART = (
    '[[part]]\nelement = "mindlin"\n'
    "material = { E = 1e3, nu = 0.3, thickness = 0.2, density = 1e-9 }"
)


@pytest.mark.parametrize(
    "old, new, where",
    [
        ('clamped = "left"', 'clamped = "lefft"', r"\[part\[0\]\]: unknown node set 'lefft'"),
        ('clamped = "left"', "clamped = [0.5, 21.5, 42.5]",
         r"\[part\[0\].options.clamped\]: clamped: node ids must be integers"),
        ("tip = {", 'left = { x_min = 50.0 }\ntip = {', r"\[sets.left\]: node set 'left' already"),
        ('clamped = "left" }', 'clamped = "left" }\ncells = "blank"',
         r"\[part\[0\].cells\]: no triangle set named 'blank'"),
        ("", "[[grip]]\nnodes = { x_min = 100.0, y_min = 10.0 }\nstiffness = 1.0",
         r"\[grip\[0\]\]: Grip needs two or more distinct nodes"),
        ("", MINDLIN_PART, r"\[part\[1\]\]: MindlinShell on triangle cells .* already covers"),
        ("", MINDLIN_PART.replace('"mindlin"', '"cable"').replace(
            "E = 1e3, nu = 0.3, thickness = 0.2, density = 1e-9",
            "axial_stiffness = 1e3, mass_per_length = 1e-9"),
         r"\[part\[1\]\]: Cable block covers no cell"),
        ("", '[[displace]]\nnodes = "left"\nuz = 1.0',
         r"\[displace\[0\]\]: DOF uz of node \d+ is both fixed and prescribed"),
        ("", '[[moment]]\nnodes = "tip"\nvector = [0.0, 1.0, 0.0]',
         r"\[moment\[0\]\]: a moment on 3 node\(s\) .* FibrousShell cells use.* force couple"),
        ("nx = 20, ny = 2", "nx = 20, ny = 2, origin = [0.0, 0.0]",
         r"\[mesh.rectangle.origin\]: expected a list of 3 numbers"),
    ],
)  # fmt: skip
def test_a_mistake_found_as_the_model_is_built_names_the_file_the_table_and_the_key(
    tmp_path, old, new, where
):
    """What the model finds when it is built and compiled (a node set an element option
    names, a part on cells another covers, a fixed DOF displaced, a moment on the fibrous
    shell...) is named as a mistake in reading the file is: file, table, key, once."""
    assert old in CANTILEVER
    text = CANTILEVER.replace(old, new, 1) if old else f"{CANTILEVER}\n{new}\n"
    path = write(tmp_path, text)
    with pytest.raises(CaseError, match=where) as error:
        load_case(path).model()
    assert str(error.value).count(str(path)) == 1


@pytest.mark.parametrize(
    "solver, extra, where",
    [
        # the constructor's TypeError "CentralDifference.__init__() missing 1 required
        # positional argument: 'duration'", without the file or the table
        ('kind = "explicit"', "", r"\[solver.duration\]: missing: kind = 'explicit' needs"),
        # the solver's refusal named neither the file nor the [[displace]] table
        ('kind = "explicit"\nduration = 0.01', '[[displace]]\nnodes = "tip"\nuz = 1.0\n'
         'amplitude = "step"', r"\[displace\[0\].amplitude\]: .* \"step\" is prescribed "
         "already at t = 0"),
    ],
    ids=["explicit-without-duration", "explicit-step-displacement"],
)  # fmt: skip
def test_an_explicit_solver_s_missing_duration_and_a_jump_at_t0_name_the_file_and_table(
    tmp_path, solver, extra, where
):
    text = CANTILEVER.replace('kind = "static"\nincrements = 1', solver) + f"\n{extra}\n"
    path = write(tmp_path, text)
    with pytest.raises(CaseError, match=where) as error:
        load_case(path)
    assert str(error.value).startswith(str(path))


@pytest.mark.parametrize(
    "gravity, density, message",
    [
        (-9.81, 3e-10, r"gravity 9.81 fits m/s\^2, but .* in mm, N, t, s, where it is 9.81 mm/s"),
        (-9810.0, 0.3, r"gravity 9810 fits mm/s\^2, but .* in m, N, kg, s, where it is 9810 m/s"),
        (-9810.0, 3e-10, None),  # mm, N, t, s throughout: quiet
        (-9.81, 0.3, None),  # m, N, kg, s throughout: quiet
    ],
    ids=["m-per-s2-with-tonnes", "mm-per-s2-with-kg", "mm-throughout", "si-throughout"],
)
def test_a_gravity_in_the_other_system_of_units_than_the_materials_is_warned(
    tmp_path, gravity, density, message
):
    # 9.81 beside densities in t/mm^2 was taken as 9.81 mm/s^2, a thousandth of the Earth's
    # gravity, without a word (the materials' own unit checks are quiet: they fit mm, N, t, s).
    tables = {
        "mesh": {"rectangle": {"lx": 60.0, "ly": 10.0, "nx": 2, "ny": 1}},
        "part": [{"element": "fibrous", "material": {"thickness": 0.5 if density < 1 else 5e-4,
                  "areal_density": density, "tension": 1000.0, "shear": 0.5, "bending": 0.1}}],
        "fix": [{"nodes": "left"}],
        "gravity": {"acceleration": [0.0, 0.0, gravity]},
        "solver": {"kind": "static", "increments": 1},
    }  # fmt: skip
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        case_from_data(tables, tmp_path / "case.toml")
    said = [str(w.message) for w in caught if "[gravity]" in str(w.message)]
    if message is None:
        assert said == []
    else:
        assert len(said) == 1 and re.search(message, said[0]), said


@pytest.mark.parametrize(
    "option, where",
    [
        ("max_steps = 10", r"\[solver.max_steps\]: duration / dt = .* more than max_steps = 10"),
        ("mass_scaling_dt = 1.0", r"\[solver.mass_scaling_dt\]: mass_scaling_dt = 1 s would add"),
    ],
)
def test_a_solver_setting_the_model_cannot_run_with_names_its_key(tmp_path, option, where):
    text = CANTILEVER.replace(
        'kind = "static"\nincrements = 1', f'kind = "explicit"\nduration = 0.01\n{option}'
    )
    path = write(tmp_path, text)
    with pytest.raises(CaseError, match=where):
        run_case(load_case(path), tmp_path / "out", progress=False)


def test_unreadable_case_files_are_refused_clearly(tmp_path):
    with pytest.raises(CaseError, match="no such case file"):
        load_case(tmp_path / "missing.toml")
    with pytest.raises(CaseError, match="not valid TOML"):
        load_case(write(tmp_path, "[mesh\nrectangle = 1"))
    binary = tmp_path / "random.toml"
    binary.write_bytes(bytes(range(256)))
    with pytest.raises(CaseError, match="not"):
        load_case(binary)
    preset = CANTILEVER.replace(MATERIAL, "").replace('element = "fibrous"', 'element = "fibrous"'
                                                      '\nmaterial = "g11515"')  # fmt: skip
    with pytest.raises(CaseError, match=r"\[part\[0\].material\]: unknown preset 'g11515'"):
        load_case(write(tmp_path, preset))


def test_inline_laws_are_the_laws_of_materials(tmp_path):
    """A bilinear bending law, a tension-only table and a polynomial shear written inline are
    the laws the Python constructors build (same values along their range)."""
    text = CANTILEVER.replace(
        "tension = 1000.0\nshear = 1.0\nbending = 10.0",
        "tension = { table = { x = [0.0, 0.01, 0.05], y = [0.0, 20.0, 400.0] }, tension_only = "
        "true }\nshear = { polynomial = { k1 = 1.0, k3 = 5.0 } }\nbending = { bilinear = { "
        "initial = 10.0, final = 1.0, knee = 0.01 } }",
    )
    fabric = load_case(write(tmp_path, text)).parts[0]["element"].fabric
    x = np.linspace(-0.1, 0.1, 41)
    assert np.array_equal(fabric.tension.value(x), TensionLaw.table(
        [0.0, 0.01, 0.05], [0.0, 20.0, 400.0], tension_only=True).value(x))  # fmt: skip
    assert np.array_equal(fabric.shear.value(x), ShearLaw.polynomial(1.0, 5.0).value(x))
    assert np.array_equal(fabric.bending.value(x), BendingLaw.bilinear(10.0, 1.0, 0.01).value(x))


def test_compare_needs_a_fibrous_part(tmp_path):
    section = "[part.material]\nE = 15000.0\nnu = 0.0\nthickness = 0.2\ndensity = 4e-11\n"
    text = (
        CANTILEVER.replace(MATERIAL, section)
        .replace('element = "fibrous"', 'element = "mindlin"')
        .replace('options = { clamped = "left" }', "")
    )
    case = load_case(write(tmp_path, text))
    with pytest.raises(ValueError, match="compare needs a fibrous part"):
        compare_case(case, tmp_path / "out", progress=False)


@pytest.mark.parametrize(
    ("clamped", "fixed", "advised"),
    [
        # node ids of the left edge (21 nodes a row): the mesh's set of exactly those nodes
        ("[0, 21, 42]", "", ['"left"']),
        # node ids of half that edge: no set holds just them, a bounds table selects them
        ("[0, 21]", "", ["{ x_max = 0.0, y_max = 5.0 }"]),
        # two sets, the left one held already: only the loose set is named
        ('["left", "right"]', '[[fix]]\nnodes = "left"\n', ['"right"']),
    ],
    ids=["ids-of-a-named-set", "ids-of-a-bounds-table", "two-sets-one-held"],
)
def test_a_loose_clamp_is_refused_with_fix_tables_the_reader_takes(
    tmp_path, clamped, fixed, advised
):
    # The refusal of a clamp no support holds says what to add; followed, that advice must
    # build the model. It gave `[[fix]] nodes = [0, 21, 42]`, which the reader refuses
    # ("expected a node-set name or a bounds table"), and named a set held already.
    base = CANTILEVER.replace(
        'options = { clamped = "left" }', f"options = {{ clamped = {clamped} }}"
    )
    base = base.replace('[[fix]]\nnodes = "left"\n', fixed)
    with pytest.raises(CaseError, match=r"\[part\[0\]\.options\.clamped\]") as caught:
        load_case(write(tmp_path, base)).model()
    advice = re.search(r"are not held: add (.*) \(no dofs key", str(caught.value)).group(1)
    tables = re.findall(r"a \[\[fix\]\] nodes = (\"[^\"]*\"|\{[^}]*\})", advice)
    assert tables == advised and advice == " and ".join(f"a [[fix]] nodes = {t}" for t in tables)
    followed = base + "".join(f"[[fix]]\nnodes = {table}\n" for table in tables)
    assert load_case(write(tmp_path, followed, "followed.toml")).model() is not None


# ---------------------------------------------------------------------- the command
def test_the_command_runs_a_case_and_reports_bad_input_with_status_2(tmp_path, capsys):
    path = write(tmp_path, CANTILEVER)
    assert main(["run", str(path), "--out", str(tmp_path / "run"), "--quiet"]) == 0
    assert (tmp_path / "run" / "summary.json").is_file()
    assert "done in" in capsys.readouterr().out
    a_file = write(tmp_path, "x", "not-a-folder")
    assert main(["run", str(path), "--out", str(a_file), "--quiet"]) == 2
    assert "is a file" in capsys.readouterr().err
    broken = write(tmp_path, CANTILEVER.replace("increments", "incremnts"), "broken.toml")
    assert main(["run", str(broken), "--quiet"]) == 2
    assert "broken.toml: [solver.incremnts]" in capsys.readouterr().err


def test_json_outputs_are_strict():
    """Non-finite numbers become null and are listed, so strict parsers read the file."""
    text = strict_json({"a": float("inf"), "b": np.array([1.0, np.nan]), "c": np.float64(2.0)})
    data = strict_load(text)
    assert data["a"] is None and data["b"] == [1.0, None] and data["c"] == 2.0
    assert len(data["notes"]) == 2 and "a: inf" in data["notes"][0]


@pytest.mark.parametrize("kinematics", [pytest.param("fibrous", marks=pytest.mark.slow), "mindlin"])
@pytest.mark.parametrize("name", ["bai-6.1.1", "bai-6.2.1"])
def test_a_paper_case_file_runs_the_report_s_paper_case(tmp_path, kinematics, name):
    """cases/bai-6.1.1.toml and cases/bai-6.2.1.toml (coarse: n = 10) build the model the
    validation report builds for their case (validation.specimens.build: corner specimen,
    clamp, the gripped patch lifted as one with its directors held, gravity, and for "mindlin"
    the Mindlin shell of the calibration both default to, "laws": MindlinShell(fabric)) and run
    its solver: the same final state (same arithmetic: 1e-12 mm)."""
    from validation import paper, specimens
    from validation.cases import bai_6_1_1, bai_6_2_1

    spec = {"bai-6.1.1": bai_6_1_1, "bai-6.2.1": bai_6_2_1}[name].SPEC
    text = (ROOT / "cases" / f"{name}.toml").read_text().replace("n = 20", "n = 10")
    run = run_case(load_case(write(tmp_path, text)), tmp_path / "out", kinematics, False)
    specimen = spec.make_specimen(10)
    assert specimen.gripped
    stiffness = specimens.grip_stiffness(spec.fabric)
    assert f"stiffness = {stiffness}" in text and stiffness == 23000.0
    model = specimens.build(specimen, kinematics, spec.fabric, spec.displacement)
    expected, _, _ = paper.solve(model, spec.increments)
    assert run.result.converged and expected.converged
    np.testing.assert_allclose(run.result.positions, expected.positions, rtol=0, atol=1e-12)


@pytest.mark.parametrize(
    "old, new, where",
    [
        (
            "stiffness = 23000.0",
            "stiffness = -1.0",
            r"\[grip\[0\].stiffness\]: expected a positive",
        ),
        ("stiffness = 23000.0", "stifness = 23000.0", r"\[grip\[0\].stifness\]: unknown key"),
        ("grip = [20.0, 15.0]", "grip = [150.0, 150.0]", r"\[mesh.corner\]: grip must be"),
        ("grip = [20.0, 15.0]", 'grip = "jaws"', r"\[mesh.corner.grip\]: expected a finite"),
    ],
)
def test_a_mistake_in_a_grip_names_the_table_and_the_key(tmp_path, old, new, where):
    """The gripped patch of cases/bai-6.2.1.toml: [mesh] corner's grip and the [[grip]] table."""
    text = (ROOT / "cases" / "bai-6.2.1.toml").read_text()
    assert old in text
    with pytest.raises(CaseError, match=where):
        load_case(write(tmp_path, text.replace(old, new, 1)))


def test_an_explicit_case_streams_its_frames_and_energies(tmp_path):
    """kind = "explicit": the frames go to result.pvd as the run goes (one per output
    interval), the energy records to energies.csv, and the summary is that of the last frame;
    a 4 ms drop of the cantilever under gravity keeps its energy balance (the solver's check
    would stop it otherwise)."""
    text = CANTILEVER.replace(
        'kind = "static"\nincrements = 1',
        'kind = "explicit"\nduration = 0.004\noutput_interval = 0.001\ndamping = 100.0',
    ).replace("areal_density = 8.154943934760449e-12", "areal_density = 8e-9")  # a larger step
    run = run_case(load_case(write(tmp_path, text)), tmp_path / "out", progress=False)
    assert run.result.converged and not run.error
    pvd = (tmp_path / "out" / "result.pvd").read_text()
    assert pvd.count("<DataSet") == 5  # t = 0, 1, 2, 3, 4 ms
    with open(tmp_path / "out" / "energies.csv") as handle:
        records = list(csv.DictReader(handle))
    assert len(records) > 10 and float(records[-1]["time"]) == pytest.approx(0.004, rel=1e-3)
    summary = strict_load((tmp_path / "out" / "summary.json").read_text())
    assert summary["final_time"] == pytest.approx(0.004)
    assert summary["mean_displacements"]["tip"][2] < 0.0  # it falls


def test_an_explicit_case_has_a_history_row_per_frame_named_as_its_energies(tmp_path):
    """An explicit run streams its 11 frames and keeps two in memory: history.csv still has
    a row per frame of the series (at its times), summary.json counts its 11 frames, and the
    quantities history.csv and energies.csv share (time, energies, the force on a tool) have
    the same column names."""
    text = CANTILEVER.replace(
        'kind = "static"\nincrements = 1',
        'kind = "explicit"\nduration = 0.004\noutput_interval = 0.0004\ndamping = 100.0',
    ).replace("areal_density = 8.154943934760449e-12", "areal_density = 8e-9")
    text += '[[contact]]\ntool = "plane"\npoint = [0.0, 0.0, -50.0]\nnormal = [0.0, 0.0, 1.0]\n'
    run = run_case(load_case(write(tmp_path, text)), tmp_path / "out", progress=False)
    assert run.result.converged and len(run.result.frames) == 2
    pvd = (tmp_path / "out" / "result.pvd").read_text()
    with open(tmp_path / "out" / "history.csv") as handle:
        rows = list(csv.DictReader(handle))
    assert len(rows) == pvd.count("<DataSet") == 11
    summary = strict_load((tmp_path / "out" / "summary.json").read_text())
    assert summary["frames"] == run.summary["frames"] == 11  # the series', not the memory's 2
    times = [float(t) for t in re.findall(r'timestep="([^"]+)"', pvd)]
    assert [float(row["time"]) for row in rows] == times
    assert [int(row["frame"]) for row in rows] == list(range(11))
    tips = [float(row["displacement_tip_z"]) for row in rows]
    assert tips[0] == 0.0 and tips[-1] < tips[5] < 0.0  # it falls, frame by frame
    assert tips[-1] == pytest.approx(run.summary["mean_displacements"]["tip"][2], rel=1e-12)
    with open(tmp_path / "out" / "energies.csv") as handle:
        energy_columns = next(csv.reader(handle))
    shared = {"time", "tool1_force_x", "tool1_force_y", "tool1_force_z"}
    shared |= {f"energy_{key}" for key in ("kinetic", "internal", "external_work", "damping")}
    assert shared <= set(energy_columns) and shared <= set(rows[0])


@pytest.mark.slow
def test_the_shipped_strip_over_a_cylinder_drapes_as_the_heavy_elastica(tmp_path):
    """cases/strip_over_cylinder.toml run by ``fibreshell run``: the strip's free end where
    the boundary-value reference puts it (0.3 mm, as tests/test_contact.py: 50 cells), and
    the force on the cylinder in the summary and the history, the strip's weight less what
    the held top carries (the vertical reactions and the tool force balance the weight,
    1e-6)."""
    from validation.references.elastica import heavy_strip_over_cylinder

    case = load_case(ROOT / "cases" / "strip_over_cylinder.toml")
    run = run_case(case, tmp_path, progress=False)
    assert run.result.converged
    reference = heavy_strip_over_cylinder(100.0, 1.66e-9 * 9810.0, 0.833, 20.5)
    tip = run.result.positions[case.mesh.nodes("tip")]
    np.testing.assert_allclose(tip[:, 0], reference["tip_x"], atol=0.3)
    np.testing.assert_allclose(tip[:, 2], reference["tip_z"], atol=0.3)
    summary = json.loads((tmp_path / "summary.json").read_text())
    weight = 1.66e-9 * 9810.0 * 100.0 * 10.0
    on_tool = summary["tool_forces"]["tool1"][2]
    held = summary["reactions"]["left"][2]
    assert -on_tool + held == pytest.approx(weight, rel=1e-6)
    assert -on_tool > 0.0
    with open(tmp_path / "history.csv") as handle:
        rows = list(csv.DictReader(handle))
    assert float(rows[-1]["tool1_force_z"]) == pytest.approx(on_tool, rel=1e-12)


# a sphere whose top touches the strip's underside (h / 2 = 0.1 mm below its mid-surface)
CONTACT = """
[[contact]]
tool = "sphere"
centre = [50.0, 5.0, -30.1]
radius = 30.0
friction = 0.2
"""


def test_a_body_that_starts_overlapping_a_contact_s_tool_is_warned_at_its_table(tmp_path):
    """The sphere 0.1 mm higher: the strip's mid-surface on it, its underside h / 2 = 0.1 mm
    into it at the node above the top (elements/contact_start.py)."""
    higher = CONTACT.replace("centre = [50.0, 5.0, -30.1]", "centre = [50.0, 5.0, -30.0]")
    case = load_case(write(tmp_path, CANTILEVER + higher))
    said = r"case\.toml: \[contact\[0\]\]: the body starts overlapping the RigidSphere: "
    with pytest.warns(UserWarning, match=said + r"1 of 63 contact nodes lie up to 0\.1 mm"):
        case.model()


@pytest.mark.parametrize(
    "old, new, where",
    [
        ('tool = "sphere"', 'tool = "ball"', r"\[contact\[0\].tool\]: expected one of"),
        ("radius = 30.0", "radius = -30.0", r"\[contact\[0\].tool\]: .*radius"),
        ("radius = 30.0", "radius = 30.0\nnormal = [0.0, 0.0, 1.0]", r"unknown key 'normal'"),
        ("friction = 0.2", "friction = -0.2", r"\[contact\[0\].friction\]"),
        ("friction = 0.2", 'friction = 0.2\nnodes = "nowhere"', r"\[contact\[0\].nodes\]"),
        ("centre = [50.0, 5.0, -30.1]", "centre = [50.0, 5.0]", r"\[contact\[0\].centre\]"),
        ("friction = 0.2", "friction = 0.2\nstick_stiffness = 0.0", r"\[contact\[0\].stick_"),
        ("friction = 0.2", "friction = 0.2\nstick_stiffness = 2.0", r"in \(0, 1\], got 2.0"),
        ("friction = 0.2", "friction = 0.2\ndamping = 1.5", r"\[contact\[0\].damping\]"),
        ("radius = 30.0\n", "", r'\[contact\[0\].radius\]: tool = "sphere" needs radius'),
        (
            "friction = 0.2",
            "friction = 0.2\naugmented = true\ndamping = 0.2",
            r"\[contact\[0\].damping\]: .*augmented",
        ),
    ],
)
def test_a_mistake_in_a_contact_table_names_the_file_the_table_and_the_key(
    tmp_path, old, new, where
):
    text = (CANTILEVER + CONTACT).replace(old, new, 1)
    with pytest.raises(CaseError, match=where):
        load_case(write(tmp_path, text))


def test_a_contact_table_builds_the_tool_of_its_python_twin(tmp_path):
    case = load_case(write(tmp_path, CANTILEVER + CONTACT))
    (contact,) = case.contacts
    assert contact["friction"] == 0.2 and contact["nodes"] is None
    tool = contact["tool"]
    assert tool.radius == 30.0 and np.allclose(tool.centre, [50.0, 5.0, -30.1])
    model = case.model()
    assert model.interactions[-1].friction == 0.2


def test_a_contact_table_sets_the_stick_spring_of_its_friction(tmp_path):
    """``stick_stiffness`` = 0.01: the contact's stick spring is 1e-2 of its penalty; without
    the key, the penalty itself (elements/contact.py, "Stick spring")."""
    soft = CONTACT.replace("friction = 0.2", "friction = 0.2\nstick_stiffness = 0.01")
    assert (
        load_case(write(tmp_path, CANTILEVER + soft)).model().interactions[-1].stick_ratio == 0.01
    )
    plain = load_case(write(tmp_path, CANTILEVER + CONTACT, "plain.toml")).model()
    assert plain.interactions[-1].stick_ratio == 1.0


def test_a_contact_table_sets_its_normal_damping(tmp_path):
    """``damping`` = 0.2: the contact damps its normal approach at 0.2 of critical
    (elements/contact_damping.py); without the key, none."""
    damped = CONTACT.replace("friction = 0.2", "friction = 0.2\ndamping = 0.2")
    assert load_case(write(tmp_path, CANTILEVER + damped)).model().interactions[-1].damping == 0.2
    plain = load_case(write(tmp_path, CANTILEVER + CONTACT, "plain.toml")).model()
    assert plain.interactions[-1].damping == 0.0


@pytest.mark.parametrize(
    "calibration, section",
    [(None, "fabric"), ("laws", "fabric"), ("initial-slope", "elastic")],
)
def test_the_report_s_mindlin_shell_is_made_of_the_fabric_by_default(calibration, section):
    """validation.specimens.build gives the Mindlin shell the calibration it is told,
    "laws" by default: MindlinShell(fabric), the same Fabric as the fibrous shell's, so that a
    paper case compares kinematics, not materials; "initial-slope" is still there to show
    what the old comparison did."""
    from elements import MindlinShell
    from validation import specimens

    fabric = presets.g1151_laminate()
    specimen = specimens.corner(200.0, 150.0, 4)
    options = {} if calibration is None else {"calibration": calibration}
    model = specimens.build(specimen, "mindlin", fabric, (None, None, 40.0), **options)
    (entry,) = model.blocks
    assert isinstance(entry.element, MindlinShell)
    if section == "fabric":
        assert entry.element.material is fabric
    else:
        assert isinstance(entry.element.material, ElasticShell)
