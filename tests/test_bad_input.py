"""Bad input at the API boundary is a ValueError that says what was wrong and what was
expected, never a raw traceback from deep inside numpy or meshio, a process that ends, or a
silent wrong answer."""

import warnings

import numpy as np
import pytest

from elements import Cable, FibrousShell
from femcore import Mesh, Model
from materials import ElasticShell, Fabric, presets
from solvers import DynamicRelaxation


@pytest.mark.parametrize(
    "name, content",
    [
        ("corrupt.msh", b"$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\ngarbage\n"),
        ("corrupt.vtu", b'<VTKFile type="UnstructuredGrid"><garbage'),
        ("random.inp", bytes(range(256)) * 4),
        ("empty.msh", b""),
    ],
)
def test_a_corrupt_mesh_file_is_a_value_error_naming_it(tmp_path, name, content):
    """meshio's VTU reader calls sys.exit on a corrupt file and its .inp reader raises
    UnicodeDecodeError on binary data: both become a ValueError naming the file."""
    path = tmp_path / name
    path.write_bytes(content)
    with pytest.raises(ValueError, match=f"cannot read .*{name}"):
        Mesh.read(path)


def test_supports_and_loads_take_a_predicate_as_the_mesh_does():
    mesh = Mesh.rectangle(10.0, 10.0, nx=2, ny=2)
    model = Model(mesh)
    model.fix(lambda x, y, z: x < 1.0, ["ux", "uy", "uz"])
    model.force(lambda x, y, z: np.isclose(x, 10.0), (0.0, 0.0, -1.0))
    assert np.array_equal(model.fixes[0].nodes, mesh.nodes("left"))
    with pytest.raises(ValueError, match="selected no node"):
        model.fix(lambda x, y, z: x > 100.0)


def test_two_blocks_on_the_same_cells_are_refused():
    """A repeated add, or a second element on cells already covered, would add their mass
    and stiffness twice."""
    mesh = Mesh.line((0.0, 0.0, 0.0), (10.0, 0.0, 0.0), 4)
    model = Model(mesh)
    cable = Cable(1.0e3, 1.0e-9)
    model.add(cable)
    with pytest.raises(ValueError, match="same element object added again"):
        model.add(cable)
    with pytest.raises(ValueError, match=r"line cells \[2, 3\] that block 0 \(Cable\)"):
        model.add(Cable(2.0e3, 1.0e-9), cells=[2, 3])
    shell_mesh = Mesh.rectangle(10.0, 10.0, nx=2, ny=1)
    shells = Model(shell_mesh)
    shells.add(FibrousShell(presets.g986_ply()), cells=[0, 1])
    shells.add(FibrousShell(presets.g986_ply()), cells=[2, 3])  # disjoint cells: fine
    assert len(shells.blocks) == 2


def test_a_frame_out_of_range_is_a_value_error():
    mesh = Mesh.line((0.0, 0.0, 0.0), (10.0, 0.0, 0.0), 4)
    model = Model(mesh)
    model.add(Cable(1.0e3, 1.0e-9))
    model.fix("start")
    model.fix("end")
    result = DynamicRelaxation(progress=False).solve(model)
    count = len(result.frames)
    with pytest.raises(ValueError, match=f"frame 99 out of range: the result has {count}"):
        result.field("axial_force", frame=99)
    with pytest.raises(ValueError, match="frame must be an integer"):
        result.to_meshio(frame="last")
    assert result.field("axial_force", frame=-count).shape == (4,)


def test_values_in_the_wrong_units_draw_a_warning():
    """The presets use mm, N, t, s: 285 g/m^2 is 2.85e-10 t/mm^2, 70 GPa is 7e4 MPa."""
    with pytest.warns(UserWarning, match=r"areal_density = 0.285 t/mm\^2 .* kg/m\^2"):
        Fabric(thickness=0.3, areal_density=0.285, tension=1200.0, shear=0.2, bending=0.1)
    with pytest.warns(UserWarning, match="modulus in Pa"):
        ElasticShell(E=70e9, nu=0.3, thickness=1.0, density=2.7e-9)
    # The modulus as the user gave it, not E / (1 - nu^2) = 7.69231e10 of the plane stress.
    with pytest.warns(UserWarning, match=r"ElasticShell modulus E = 7e\+10 MPa is outside"):
        ElasticShell(E=70e9, nu=0.3, thickness=1.0, density=2.7e-9)
    with pytest.warns(UserWarning, match=r"ElasticShell modulus E1 = 1\.4e\+11 MPa is outside"):
        ElasticShell.orthotropic(1.4e11, 1e10, 0.3, 5e9, 5e9, 5e9, thickness=1.0, density=1.5e-9)
    # G12 is written by the user as E is: 5 GPa in Pa among moduli in MPa (a carbon lamina,
    # E1 = 140 GPa, E2 = 10 GPa in MPa) was quiet.
    with pytest.warns(UserWarning, match=r"ElasticShell modulus G12 = 5e\+09 MPa is outside"):
        ElasticShell.orthotropic(1.4e5, 1e4, 0.3, 5e9, 5e3, 3e3, thickness=1.0, density=1.6e-9)
    with pytest.warns(UserWarning, match="density in kg/m"):
        ElasticShell(E=70e3, nu=0.3, thickness=1.0, density=2700.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the presets and their Mindlin calibration are quiet
        for make in (presets.g986_ply, presets.g986_stack, presets.g1151_laminate):
            ElasticShell.equivalent(make())
        ElasticShell(E=70e3, nu=0.3, thickness=1.0, density=2.7e-9)
