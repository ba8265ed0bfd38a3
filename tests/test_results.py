"""Results: frames, shortcuts to the final state, and files ParaView reads (through meshio)."""

import meshio
import numpy as np
import pytest

from elements import Cable
from femcore import Frame, Mesh, Model, Result
from solvers import DynamicRelaxation


@pytest.fixture(scope="module")
def sagging():
    mesh = Mesh.line((0.0, 0.0, 0.0), (100.0, 0.0, 0.0), 20)
    model = Model(mesh)
    model.add(Cable(5.0e3, 1.0e-6))
    model.fix("start")
    model.displace("end", ux=-20.0, uy=0.0, uz=0.0)
    model.gravity((0.0, 0.0, -9810.0))
    return DynamicRelaxation(increments=3, tol=1e-6).solve(model)


def test_the_result_exposes_the_final_frame(sagging):
    assert sagging.converged and len(sagging.frames) == 4
    assert sagging.positions is sagging.frames[-1].positions
    assert sagging.displacements[-1] == pytest.approx([-20.0, 0.0, 0.0])
    assert np.isnan(sagging.directors).all()  # cable nodes have no director
    assert sagging.wall_time > 0 and sagging.steps == sum(sagging.info["iterations_per_increment"])


def test_vtu_holds_the_reference_mesh_the_displacement_and_the_fields(sagging, tmp_path):
    """As the XDMF series does: reference points + displacement (Warp By Vector deforms it
    once, whichever format is open)."""
    path = sagging.write(tmp_path / "cable.vtu")
    back = meshio.read(path)
    assert np.allclose(back.points, sagging.mesh.points)
    assert np.allclose(back.points + back.point_data["displacement"], sagging.positions)
    assert np.allclose(back.point_data["displacement"], sagging.displacements)
    assert np.allclose(back.point_data["reaction"], sagging.reactions)
    force = back.cell_data["axial_force"][0]
    assert force.shape == (20,) and (force > 0).all()


def test_pvd_series_has_one_vtu_per_frame(sagging, tmp_path):
    sagging.write(tmp_path / "cable.pvd")
    parts = sorted(tmp_path.glob("cable_*.vtu"))
    assert len(parts) == len(sagging.frames)
    last = meshio.read(parts[-1])
    assert np.allclose(last.points + last.point_data["displacement"], sagging.positions)
    assert (tmp_path / "cable.pvd").read_text().count("<DataSet") == len(sagging.frames)


def test_xdmf_time_series_reads_back(sagging, tmp_path):
    path = sagging.write(tmp_path / "cable.xdmf")
    with meshio.xdmf.TimeSeriesReader(path) as reader:
        points, _ = reader.read_points_cells()
        assert reader.num_steps == len(sagging.frames)
        t, point_data, _ = reader.read_data(reader.num_steps - 1)
    assert np.allclose(points + point_data["displacement"], sagging.positions)


def test_an_unknown_format_is_refused(sagging, tmp_path):
    with pytest.raises(ValueError, match="expected a .vtu, .pvd or .xdmf"):
        sagging.write(tmp_path / "cable.obj")


def test_progress_lines_appear_only_when_asked(capsys):
    mesh = Mesh.line((0.0, 0.0, 0.0), (10.0, 0.0, 0.0), 4)
    model = Model(mesh)
    model.add(Cable(5.0e3, 1.0e-6))
    model.fix("start")
    model.force("end", (1.0, 0.0, 0.0))
    DynamicRelaxation().solve(model)
    assert capsys.readouterr().err == ""
    DynamicRelaxation(progress=True).solve(model)
    assert "increment 1/1 converged" in capsys.readouterr().err


def test_field_returns_point_and_cell_fields_by_name(sagging):
    force = sagging.field("axial_force")
    assert force.shape == (20,) and force is sagging.frames[-1].fields["line"]["axial_force"]
    first = sagging.field("axial_force", frame=0)
    assert first.shape == (20,)
    with pytest.raises(ValueError, match=r"no field 'stress'.*available fields: \[.*axial_force"):
        sagging.field("stress")
    assert sagging.thickness is None  # cables provide no nodal thickness


def test_export_loops_over_the_cell_kinds_of_the_mesh():
    plate = Mesh.rectangle(1.0, 1.0, 1, 1)
    mesh = Mesh(plate.points, plate.triangles, lines=[[0, 1]])
    zeros = np.zeros((mesh.n_nodes, 3))
    frame = Frame(
        time=0.0,
        load_factor=1.0,
        positions=mesh.points.copy(),
        velocities=zeros,
        directors=zeros,
        reactions=zeros,
        reaction_moments=zeros,
        fields={
            "point": {"thickness": np.ones(mesh.n_nodes)},
            "triangle": {"strain": np.array([0.1, 0.2])},
            "line": {"axial_force": np.array([3.0])},
        },
    )
    result = Result(mesh=mesh, frames=[frame])
    out = result.to_meshio()
    assert [block.type for block in out.cells] == ["triangle", "line"]
    strain, force = out.cell_data["strain"], out.cell_data["axial_force"]
    assert strain[0].tolist() == [0.1, 0.2] and np.isnan(strain[1]).all()
    assert np.isnan(force[0]).all() and force[1].tolist() == [3.0]
    assert result.thickness is result.field("thickness")
    assert result.field("strain").tolist() == [0.1, 0.2]


def test_the_director_angle_to_a_plane_of_an_inclined_sheet():
    """A sheet inclined by 30 deg about x: its directors (the normals of the compiled model)
    make 60 deg with the horizontal plane and lie in the plane whose normal is x (0 deg)."""
    from elements import FibrousShell
    from femcore import Frame, Mesh, Model, Result
    from materials import presets

    flat = Mesh.rectangle(20.0, 10.0, nx=2, ny=1)
    turn = np.radians(30.0)
    y, z = flat.points[:, 1], flat.points[:, 2]
    mesh = flat.with_points(
        np.column_stack([flat.points[:, 0], y * np.cos(turn) - z * np.sin(turn),
                         y * np.sin(turn) + z * np.cos(turn)])
    )  # fmt: skip
    model = Model(mesh)
    model.add(FibrousShell(presets.g986_ply()))
    state = model.compile().initial_state()
    zero = np.zeros_like(state.positions)
    result = Result(mesh, [Frame(0.0, 0.0, state.positions, zero, state.directors, zero, zero)])
    assert np.allclose(result.director_angle(), 60.0)
    assert np.allclose(result.director_angle((1.0, 0.0, 0.0)), 0.0, atol=1e-9)
    with pytest.raises(ValueError, match="non-zero 3-vector"):
        result.director_angle((0.0, 0.0, 0.0))
