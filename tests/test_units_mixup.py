"""Units: any consistent system is a valid model, a mix of two is caught. A material whose
values all fit mm, N, t, s or all fit m, N, kg, s is quiet; one that mixes them (a density in
kg/m^3 beside lengths in mm) warns; a shell thicker than its mesh's span (a mesh in m with a
material in mm) is refused, and one thicker than twenty times its cells' median edge draws a
warning."""

import re
import warnings
from pathlib import Path

import pytest

from elements import MindlinShell
from femcore import Model
from femcore.mesh import Mesh
from fibreshell.case import CaseError, case_from_data, read_case_data
from materials import ElasticShell, Fabric

STRIP = Path(__file__).parents[1] / "cases" / "strip.toml"


def test_materials_wholly_in_si_are_quiet():
    """A fabric of 300 micrometres and 1.66 kg/m^2, aluminium at 70 GPa and 2700 kg/m^3 in a
    1 mm sheet: every value plausible in m, N, kg, s."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        Fabric(thickness=3e-4, areal_density=1.66, tension=1.2e6, shear=0.2, bending=1e-4)
        ElasticShell(E=70e9, nu=0.3, thickness=1e-3, density=2700.0)
        ElasticShell(E=70e3, nu=0.3, thickness=1.0, density=2.7e-9)  # and in mm, N, t, s


@pytest.mark.parametrize(
    "make, named",
    [
        # a density in kg/m^3 beside a modulus in MPa and a thickness in mm
        (lambda: ElasticShell(E=70e3, nu=0.3, thickness=1.0, density=2700.0),
         "ElasticShell density = 2700 t/mm^3"),
        # a mass per area in kg/m^2 beside a thickness in mm
        (lambda: Fabric(thickness=0.3, areal_density=1.66, tension=1e3, shear=0.2, bending=0.1),
         "Fabric areal_density = 1.66 t/mm^2"),
    ],
)  # fmt: skip
def test_a_material_that_mixes_two_systems_warns_naming_the_value(make, named):
    with pytest.warns(
        UserWarning, match=rf"{re.escape(named)} .*nor do they fit m, N, kg, s together"
    ):
        make()


def test_a_mesh_in_metres_with_a_material_in_millimetres_is_refused():
    """cases/strip.toml with its 60 x 10 mm strip written in m: the 0.5 mm fabric is 8 x
    longer than the strip, and ran silently."""
    data = read_case_data(STRIP)
    data["mesh"]["rectangle"].update(lx=0.06, ly=0.01)
    case = case_from_data(data, STRIP)
    refused = r"\[part\[0\]\]: .*thickness 0.5 is 8.33 x the largest extent of its cells \(0.06\)"
    with pytest.raises(CaseError, match=refused + ": is the mesh in m"):
        case.model()


def test_a_shell_thicker_than_twenty_times_its_cells_warns_and_a_thinner_one_is_quiet():
    """A 20 m roof in m, 0.25 m cells (each triangle's sides 0.25, its diagonal 0.354),
    a 7 mm sheet written in mm: within the span (20), 28 x the median edge; 4.9 mm is 19.6 x,
    as a fine mesh of a thick stack may be (the G1151 laminate, 15 mm, on 1.4 mm cells: 10.5)."""
    mesh = Mesh.rectangle(20.0, 20.0, 80, 80)
    sheet = MindlinShell(ElasticShell(E=70e3, nu=0.3, thickness=7.0, density=2.7e-9))
    with pytest.warns(UserWarning, match=r"thickness 7 is 28 x the median edge of its cells "
                                         r"\(0.25; .*is the mesh in m"):  # fmt: skip
        Model(mesh).add(sheet)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        Model(mesh).add(MindlinShell(ElasticShell(E=70e3, nu=0.3, thickness=4.9, density=2.7e-9)))
        fine = Mesh.rectangle(200.0, 150.0, 140, 100)  # the G1151 laminate's fine mesh, mm
        Model(fine).add(MindlinShell(ElasticShell(E=70e3, nu=0.3, thickness=15.0, density=2.7e-9)))
