"""A user's element type and material, named in a case file (fibreshell.registry), and the
conformance kit (femcore.testing) run on that element.

The element is written outside the project: ``PLUGIN`` below is the source of a module written
to a temporary folder and imported from there, as a user's package would be. It is the
constant-strain triangle (CST) membrane of a St Venant-Kirchhoff film, against the protocol of
elements.base only: W = A t 1/2 E : D : E per cell, E = (F^T F - I) / 2 the Green strain of the
in-plane deformation gradient F, f_a = A t F S grad N_a. It is registered by a call
(``register_element``) and, as an installed distribution would be, through an entry point
(a dist-info folder on sys.path: importlib.metadata finds it as it finds any distribution).

Reference (closed form): a strip L x W of thickness t, held along x = 0 and pulled to a stretch
lambda = 1 + dL / L, free to contract sideways, deforms homogeneously (the CST reproduces it
exactly); S22 = 0 gives S11 = E' E11 with E11 = (lambda^2 - 1) / 2 and E' = E (plane stress)
or E / (1 - nu^2) (plane strain), and the pulling force is the first Piola stress times the
reference section: F = lambda S11 t W. For dL / L -> 0 it is the bar's E t W / L dL.
"""

from __future__ import annotations

import importlib
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from femcore import Mesh
from femcore.testing import check_element
from fibreshell import CaseError, load_case, registry
from fibreshell.cli import main
from materials import Fabric, presets

ROOT = Path(__file__).resolve().parents[1]

PLUGIN = '''
"""CST membrane of a St Venant-Kirchhoff film (a user's element type)."""
from dataclasses import dataclass

import numpy as np

from elements.base import ElementBlock, ElementType, Scatter, check_positive, local_tangent


@dataclass(frozen=True)
class Film:
    E: float  # N/mm^2
    nu: float
    thickness: float  # mm
    density: float  # t/mm^3


def film(E=3000.0, nu=0.3, thickness=0.1, density=1.4e-9):
    """The material factory: a registered preset."""
    return Film(check_positive(E, "E", "N/mm^2"), float(nu),
                check_positive(thickness, "thickness", "mm"),
                check_positive(density, "density", "t/mm^3"))


class Membrane(ElementType):
    """material : Film or the inline table of a case file (film's keywords)."""

    dofs = ("ux", "uy", "uz")
    cell_type = "triangle"

    def __init__(self, material, plane_strain=False):
        self.material = material if isinstance(material, Film) else film(**material)
        self.plane_strain = bool(plane_strain)

    def bind(self, mesh, cell_ids, directors):
        return MembraneBlock(self, mesh, cell_ids)


class MembraneBlock(ElementBlock):
    dofs = Membrane.dofs
    cell_type = "triangle"
    reach = 1

    def __init__(self, membrane, mesh, cell_ids):
        e, nu = membrane.material.E, membrane.material.nu
        if membrane.plane_strain:
            c = e / ((1 + nu) * (1 - 2 * nu))
            self.d = c * np.array([[1 - nu, nu, 0], [nu, 1 - nu, 0], [0, 0, (1 - 2 * nu) / 2]])
        else:
            self.d = e / (1 - nu**2) * np.array([[1, nu, 0], [nu, 1, 0], [0, 0, (1 - nu) / 2]])
        self.cell_ids = np.asarray(cell_ids, dtype=np.int64)
        self.connectivity = mesh.triangles[self.cell_ids]
        self.scatter = Scatter(self.connectivity, mesh.n_nodes)
        x = mesh.points[self.connectivity]
        normal = np.cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0])
        self.area = 0.5 * np.linalg.norm(normal, axis=1)
        e1 = (x[:, 1] - x[:, 0]) / np.linalg.norm(x[:, 1] - x[:, 0], axis=1)[:, None]
        e2 = np.cross(normal / (2 * self.area[:, None]), e1)
        edges = np.stack([x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]], axis=2)  # (m, 3, 2)
        jacobian = np.stack([e1, e2], axis=1) @ edges  # local coordinates of the two edges
        # Gradients of the three shape functions in the cell's own plane (m, 3, 2).
        self.grad = np.array([[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]]) @ np.linalg.inv(jacobian)
        self.thickness = membrane.material.thickness
        self.cell_mass = membrane.material.density * self.thickness * self.area

    def strain_stress(self, x):
        f = np.einsum("mai,maj->mij", x, self.grad)  # (m, 3, 2)
        green = 0.5 * (np.einsum("mki,mkj->mij", f, f) - np.eye(2))
        strain = np.stack([green[:, 0, 0], green[:, 1, 1], 2 * green[:, 0, 1]], axis=1)
        return f, strain, strain @ self.d

    def cell_forces(self, x, v=None):
        f, _, s = self.strain_stress(x)
        stress = np.stack([s[:, [0, 2]], s[:, [2, 1]]], axis=1)  # (m, 2, 2)
        scale = (self.area * self.thickness)[:, None, None]
        return scale * np.einsum("miI,mIJ,maJ->mai", f, stress, self.grad), None

    def internal_force(self, state, history=None):
        return self.scatter.vectors(self.cell_forces(self.scatter.gather(state.positions))[0]), None

    def strain_energy(self, state, history=None):
        _, strain, stress = self.strain_stress(self.scatter.gather(state.positions))
        return float(0.5 * np.sum(self.area * self.thickness * np.sum(strain * stress, axis=1)))

    def lumped_mass(self, state, density_scale=None):
        third = self.cell_mass / 3 if density_scale is None else self.cell_mass * density_scale / 3
        return self.scatter.scalars(np.repeat(third[:, None], 3, axis=1)), None

    def cell_stable_dt(self, state):
        # The largest eigenvalue of each cell's own stiffness over its nodal mass bounds the
        # assembly's (the element eigenvalue inequality), here at the current state.
        x = self.scatter.gather(state.positions)
        blocks = local_tangent(self.cell_forces, x, None, 1e-7 * np.sqrt(self.area.max()))
        k = blocks.reshape(len(x), 9, 9)
        omega2 = np.linalg.eigvalsh(0.5 * (k + k.transpose(0, 2, 1)))[:, -1] / (self.cell_mass / 3)
        return 2.0 / np.sqrt(omega2)

    def cell_fields(self, state, history=None):
        _, strain, stress = self.strain_stress(self.scatter.gather(state.positions))
        return {"green_strain": strain, "stress": stress}
'''

METADATA = "Metadata-Version: 2.1\nName: fibreshell-membrane\nVersion: 0.1\n"
ENTRY_POINTS = """[fibreshell.elements]
cst_plugin = fibreshell_membrane:Membrane
broken = fibreshell_membrane_missing:Membrane
[fibreshell.materials]
film_plugin = fibreshell_membrane:film
"""

LENGTH, WIDTH, PULL = 100.0, 20.0, 2.0  # mm


def strip_case(element: str, material: str, options: str = "") -> str:
    return f"""
title = "film strip pulled"
[mesh]
rectangle = {{ lx = {LENGTH}, ly = {WIDTH}, nx = 10, ny = 2 }}
[sets]
corner = {{ x_max = 0.0, y_max = 0.0 }}
[[part]]
element = "{element}"
material = {material}
{options}
[[fix]]
nodes = "left"
dofs = ["ux"]
[[fix]]
nodes = "corner"
dofs = ["uy"]
[[fix]]
nodes = {{ z_min = -1.0 }}
dofs = ["uz"]
[[displace]]
nodes = "right"
ux = {PULL}
[solver]
kind = "static"
increments = 2
[output]
history = {{ reactions = ["right"] }}
"""


def pulling_force(e: float, nu: float, thickness: float, plane_strain: bool = False) -> float:
    stretch = 1.0 + PULL / LENGTH
    modulus = e / (1 - nu**2) if plane_strain else e
    return stretch * modulus * 0.5 * (stretch**2 - 1) * thickness * WIDTH


@pytest.fixture(scope="module")
def plugin(tmp_path_factory):
    """The user's module, written to a folder of its own and imported from there."""
    folder = tmp_path_factory.mktemp("user_package")
    (folder / "fibreshell_membrane.py").write_text(PLUGIN)
    sys.path.insert(0, str(folder))
    try:
        yield importlib.import_module("fibreshell_membrane"), folder
    finally:
        sys.path.remove(str(folder))
        sys.modules.pop("fibreshell_membrane", None)


@pytest.fixture
def installed(tmp_path, monkeypatch, plugin):
    """The plugin as an installed distribution: its dist-info folder (entry points) on
    sys.path."""
    info = tmp_path / "site" / "fibreshell_membrane-0.1.dist-info"
    info.mkdir(parents=True)
    (info / "METADATA").write_text(METADATA)
    (info / "entry_points.txt").write_text(ENTRY_POINTS)
    monkeypatch.syspath_prepend(str(info.parent))
    return info.parent


@pytest.fixture(autouse=True)
def clean_registry():
    """Each test sees the project's registries only, and leaves them so."""
    saved = dict(registry.ELEMENTS.entries), dict(registry.MATERIALS.entries)
    yield
    registry.ELEMENTS.entries.clear()
    registry.ELEMENTS.entries.update(saved[0])
    registry.MATERIALS.entries.clear()
    registry.MATERIALS.entries.update(saved[1])


def summary_reaction(out: Path) -> float:
    return json.loads((out / "summary.json").read_text())["reactions"]["right"][0]


# ---------------------------------------------------------------------- register calls
@pytest.mark.parametrize("plane_strain", [False, True])
def test_a_registered_element_runs_its_case_through_the_command(plugin, tmp_path, plane_strain):
    module, _ = plugin
    registry.register_element("cst", module.Membrane)
    case = tmp_path / "strip.toml"
    material = "{ E = 3000.0, nu = 0.3, thickness = 0.1, density = 1.4e-9 }"
    options = f"options = {{ plane_strain = {str(plane_strain).lower()} }}"
    case.write_text(strip_case("cst", material, options))
    assert main(["run", str(case), "--out", str(tmp_path / "out"), "--quiet"]) == 0
    expected = pulling_force(3000.0, 0.3, 0.1, plane_strain)
    assert summary_reaction(tmp_path / "out") == pytest.approx(expected, rel=1e-8)
    # The options and the inline material reached the type as written.
    element = load_case(case).parts[0]["element"]
    assert element.plane_strain is plane_strain and element.material == module.film()


def test_a_registered_material_preset_is_named_in_a_case_file(plugin, tmp_path):
    module, _ = plugin
    registry.register_element("cst", module.Membrane)
    registry.register_material("test_film", module.film)
    case = tmp_path / "strip.toml"
    case.write_text(strip_case("cst", '{ preset = "test_film", E = 2000.0 }'))
    assert main(["run", str(case), "--out", str(tmp_path / "out"), "--quiet"]) == 0
    expected = pulling_force(2000.0, 0.3, 0.1)
    assert summary_reaction(tmp_path / "out") == pytest.approx(expected, rel=1e-8)
    assert load_case(case).parts[0]["element"].material == module.film(E=2000.0)


def test_a_registered_fabric_preset_serves_the_built_in_shells_with_changed_fields(tmp_path):
    registry.register_material("stiff_ply", lambda plies=1: presets.g986_stack(plies))
    case = tmp_path / "strip.toml"
    text = strip_case("fibrous", '{ preset = "stiff_ply", plies = 2, thickness = 0.7 }')
    case.write_text(text)
    fabric = load_case(case).parts[0]["element"].fabric
    assert isinstance(fabric, Fabric)
    assert fabric.thickness == 0.7  # changed; the preset's own argument used:
    assert fabric.areal_density == presets.g986_stack(2).areal_density
    case.write_text(text.replace('element = "fibrous"', 'element = "mindlin"'))
    assert load_case(case).parts[0]["element"].material.thickness == 0.7  # its calibration


def test_a_type_with_from_case_takes_the_part_its_own_way(plugin, tmp_path):
    module, _ = plugin

    class StiffMembrane(module.Membrane):
        @classmethod
        def from_case(cls, material, stiffening=1.0):
            """material: the inline table; the option scales its modulus."""
            return cls(module.film(**{**material, "E": stiffening * material["E"]}))

    registry.register_element("stiff_cst", StiffMembrane)
    case = tmp_path / "strip.toml"
    case.write_text(strip_case("stiff_cst", "{ E = 1000.0 }", "options = { stiffening = 3.0 }"))
    assert load_case(case).parts[0]["element"].material == module.film(E=3000.0)
    case.write_text(strip_case("stiff_cst", "{ E = 1000.0 }", "options = { plane_strain = 1 }"))
    with pytest.raises(CaseError, match=r"unknown option 'plane_strain'; expected one of stiff"):
        load_case(case)


def test_a_name_is_registered_once_unless_replaced(plugin):
    module, _ = plugin
    registry.register_element("cst", module.Membrane)
    registry.register_element("cst", module.Membrane)  # the same type again: no conflict
    with pytest.raises(ValueError, match=r"element 'cst' is already registered .*replace=True"):
        registry.register_element("cst", type("Other", (module.Membrane,), {}))
    registry.register_element("cst", type("Other", (module.Membrane,), {}), replace=True)
    assert registry.element_type("cst").__name__ == "Other"
    with pytest.raises(ValueError, match="preset 'paper_stack' is already registered"):
        registry.register_material("paper_stack", module.film)
    with pytest.raises(TypeError, match="subclass of elements.base.ElementType"):
        registry.register_element("film", module.film)
    with pytest.raises(TypeError, match="callable"):
        registry.register_material("film", 3.0)


def test_unknown_names_and_options_are_case_errors_naming_the_known_ones(plugin, tmp_path):
    module, _ = plugin
    registry.register_element("cst", module.Membrane)
    case = tmp_path / "strip.toml"
    case.write_text(strip_case("cts", '"paper_stack"'))
    known = r"expected one of fibrous, mindlin, cable, cst"
    with pytest.raises(CaseError, match=rf"\[part\[0\].element\]: unknown element 'cts'; {known}"):
        load_case(case)
    case.write_text(strip_case("cst", '"film"'))
    with pytest.raises(CaseError, match=r"\[part\[0\].material\]: unknown preset 'film'; expec"):
        load_case(case)
    case.write_text(strip_case("cst", "{ E = 1.0 }", "options = { colour = 1 }"))
    with pytest.raises(
        CaseError, match=r"\[part\[0\].options.colour\]: unknown option 'colour'; .* plane_strain"
    ):
        load_case(case)
    case.write_text(strip_case("cst", "{ E = -1.0 }"))
    with pytest.raises(CaseError, match=r"\[part\[0\]\]: E must be a positive"):
        load_case(case)


# ---------------------------------------------------------------------- entry points
def test_entry_points_are_found_when_a_case_names_them(installed, tmp_path):
    assert "cst_plugin" in registry.element_names()
    assert "cst_plugin" not in registry.ELEMENTS.entries  # listed, not loaded
    case = tmp_path / "strip.toml"
    case.write_text(strip_case("cst_plugin", '"film_plugin"'))
    assert main(["run", str(case), "--out", str(tmp_path / "out"), "--quiet"]) == 0
    expected = pulling_force(3000.0, 0.3, 0.1)
    assert summary_reaction(tmp_path / "out") == pytest.approx(expected, rel=1e-8)
    assert registry.ELEMENTS.entries["cst_plugin"].__name__ == "Membrane"
    assert "broken" not in registry.ELEMENTS.entries  # never named: never imported
    case.write_text(strip_case("broken", '"film_plugin"'))
    with pytest.raises(CaseError, match=r"element 'broken': the entry point .*missing"):
        load_case(case)


def test_an_installed_plugin_serves_the_fibreshell_command(installed, plugin, tmp_path):
    """The command in a process of its own: only the entry points tell it of the plugin."""
    _, module_folder = plugin
    case = tmp_path / "strip.toml"
    case.write_text(strip_case("cst_plugin", '{ preset = "film_plugin", thickness = 0.2 }'))
    path = os.pathsep.join([str(module_folder), str(installed), str(ROOT)])
    done = subprocess.run(
        [sys.executable, "-m", "fibreshell", "run", str(case), "--out", str(tmp_path / "out"),
         "--quiet"],
        env={**os.environ, "PYTHONPATH": path}, capture_output=True, text=True, timeout=600,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    expected = pulling_force(3000.0, 0.3, 0.2)
    assert summary_reaction(tmp_path / "out") == pytest.approx(expected, rel=1e-8)


# ---------------------------------------------------------------------- conformance kit
def patch(refine: int) -> Mesh:
    return Mesh.rectangle(40.0, 30.0, nx=4 * refine, ny=3 * refine)


def test_the_user_element_passes_the_conformance_kit(plugin):
    module, _ = plugin
    material = module.film()
    for plane_strain in (False, True):
        report = check_element(
            module.Membrane(material, plane_strain=plane_strain),
            patch,
            total_mass=material.density * material.thickness * 40.0 * 30.0,
            rigid_fields=("green_strain", "stress"),
        )
        assert report.passed, report
        outcome = {result.name: result.status for result in report.results}
        assert outcome["tangent is the force derivative"] == "not applicable"  # none of its own
        assert outcome["stable step at deformed"] == "passed"


def test_the_kit_names_what_a_faulty_element_gets_wrong(plugin):
    module, _ = plugin

    class HeavyBlock(module.MembraneBlock):
        def lumped_mass(self, state, density_scale=None):
            mass, inertia = super().lumped_mass(state, density_scale)
            return 2.0 * mass, inertia

    class Heavy(module.Membrane):
        def bind(self, mesh, cell_ids, directors):
            return HeavyBlock(self, mesh, cell_ids)

    material = module.film()
    report = check_element(
        Heavy(material), Mesh.rectangle(40.0, 30.0, nx=4, ny=3),
        total_mass=material.density * material.thickness * 40.0 * 30.0,
    )  # fmt: skip
    assert [result.name for result in report.failures] == ["lumped mass"]
    assert "not to the total mass" in str(report)
    outcome = {result.name: result.status for result in report.results}
    # One mesh, not refine -> Mesh: the mesh-size check cannot run.
    assert outcome["stable step shrinks with the mesh"] == "not applicable"
    # The stable step of the heavy element is still safe, against the heavy mass it reports.
    assert outcome["stable step at reference"] == "passed"
