"""Output files name each quantity once, in one unit, with named components: what ParaView
lists from the VTU series is what summary.json reports, and the XDMF series is one grid over
one mesh whose arrays are binary HDF5."""

import json
import re
from pathlib import Path

import h5py
import meshio
import numpy as np
import pytest

import elements.ply_contact  # noqa: F401  (declares the components of its fields)
from femcore.field_names import LEVELS, component_names, level_names, name_components
from femcore.xdmf import write_xdmf
from fibreshell import load_case, run_case
from fibreshell.run import held_directors

# The README's strip, coarser and in one increment: a fibrous run whose directors tilt.
STRIP = """
title = "strip"
[mesh]
rectangle = { lx = 200.0, ly = 60.0, nx = 4, ny = 1 }
[sets]
tip = { x_min = 200.0 }
[[part]]
element = "fibrous"
material = "g1151_laminate"
options = { clamped = "left" }
[[fix]]
nodes = "left"
[gravity]
acceleration = [0.0, 0.0, -9810.0]
[solver]
kind = "static"
increments = 1
[output]
history = { displacements = ["tip"] }
"""


@pytest.fixture(scope="module")
def strip_run(tmp_path_factory):
    folder = tmp_path_factory.mktemp("strip")
    (folder / "strip.toml").write_text(STRIP)
    run = run_case(load_case(folder / "strip.toml"), folder / "out", progress=False)
    assert run.status == "done"
    return run, folder / "out"


def data_arrays(path: Path) -> dict[str, dict[str, str]]:
    """The attributes of every DataArray of a VTU file, by the array's name."""
    tags = re.findall(r"<DataArray ([^>]*)>", path.read_text())
    arrays = [dict(re.findall(r'(\w+)="([^"]*)"', tag)) for tag in tags]
    return {a["Name"]: a for a in arrays}


def components(attributes: dict[str, str]) -> list[str]:
    count = int(attributes.get("NumberOfComponents", 1))
    return [attributes.get(f"ComponentName{i}") for i in range(count)]


def last_frame(out: Path) -> Path:
    return sorted(out.glob("result_*.vtu"))[-1]


def test_the_vtu_names_each_component_of_the_level_section_and_vector_fields(strip_run):
    _, out = strip_run
    arrays = data_arrays(last_frame(out))
    assert components(arrays["shear_angle_deg"]) == ["bottom", "middle", "top"]
    assert components(arrays["warp_strain"]) == ["bottom", "middle", "top"]
    assert components(arrays["membrane_force"]) == ["11", "22", "12"]
    assert components(arrays["bending_moment"]) == ["11", "22", "12"]
    assert components(arrays["displacement"]) == ["x", "y", "z"]
    assert components(arrays["director"]) == ["x", "y", "z"]
    # the unit is in the angle's name; no field keeps the old unitless name
    assert "director_tilt_deg" in arrays and "director_tilt" not in arrays
    assert "shear_angle" not in arrays


def test_a_field_named_with_its_unit_reads_back_with_its_values(strip_run):
    run, out = strip_run
    back = meshio.read(last_frame(out))
    shear = back.cell_data["shear_angle_deg"][0]
    assert shear.shape == (len(run.result.mesh.triangles), 3)
    assert shear == pytest.approx(run.result.field("shear_angle_deg"))
    assert back.point_data["director_tilt_deg"] == pytest.approx(
        run.result.field("director_tilt_deg")
    )


def test_the_director_tilt_is_in_degrees_alike_in_the_vtu_and_in_summary_json(strip_run):
    """summary.json's range is the field's over the nodes whose directors no support holds
    (a held director is imposed: fibreshell.run.held_directors)."""
    _, out = strip_run
    tilt = meshio.read(last_frame(out)).point_data["director_tilt_deg"]
    free = np.ones(len(tilt), dtype=bool)
    free[held_directors(load_case(out.parent / "strip.toml").model())] = False
    summary = json.loads((out / "summary.json").read_text())["director_tilt_deg"]
    assert summary["max"] == pytest.approx(tilt[free].max(), rel=1e-12)
    assert summary["min"] == pytest.approx(tilt[free].min(), abs=1e-12)
    assert 5.0 < summary["max"] < 90.0  # degrees: the sagging strip's directors lean


def test_the_vtu_component_names_are_what_vtk_reads(strip_run):
    vtk = pytest.importorskip("vtk")
    _, out = strip_run
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(last_frame(out)))
    reader.Update()
    shear = reader.GetOutput().GetCellData().GetArray("shear_angle_deg")
    assert [shear.GetComponentName(i) for i in range(3)] == ["bottom", "middle", "top"]


def test_the_xdmf_series_is_one_grid_over_one_mesh_in_binary_hdf5(strip_run, tmp_path):
    run, _ = strip_run
    result = run.result
    path = result.write(tmp_path / "strip.xdmf")
    text = path.read_text()
    # no array inline: every data item points into the HDF5 file
    assert text.count("<DataItem") == text.count('Format="HDF"') > 0
    assert "XML" not in re.sub(r"<\?xml[^>]*\?>", "", text)
    # one temporal collection at the top of the domain, no second (unwarped) mesh grid
    domain = re.search(r"<Domain>(.*)</Domain>", text, re.S)[1]
    top = re.findall(r"^  <Grid [^>]*>", domain, re.M)
    assert top == ['  <Grid Name="result" GridType="Collection" CollectionType="Temporal">']
    assert text.count('GridType="Uniform"') == len(result.frames)
    with h5py.File(tmp_path / "strip.h5") as h5:
        assert sorted(h5["mesh"]) == ["points", "topology"]  # the mesh once
        assert len(h5["frames"]) == len(result.frames)
    with meshio.xdmf.TimeSeriesReader(path) as reader:
        points, cells = reader.read_points_cells()
        assert reader.num_steps == len(result.frames)
        t, point_data, cell_data = reader.read_data(reader.num_steps - 1)
    assert np.allclose(points, result.mesh.points)
    assert np.array_equal(cells[0].data, result.mesh.triangles)
    assert t == result.frames[-1].time
    assert np.allclose(points + point_data["displacement"], result.positions)
    assert point_data["director_tilt_deg"] == pytest.approx(result.field("director_tilt_deg"))
    assert cell_data["shear_angle_deg"][0] == pytest.approx(result.field("shear_angle_deg"))


def test_vtk_s_xdmf_reader_sees_one_grid_with_a_time_step_per_frame(strip_run, tmp_path):
    vtk = pytest.importorskip("vtk")
    run, _ = strip_run
    path = run.result.write(tmp_path / "strip.xdmf")
    reader = vtk.vtkXdmfReader()
    reader.SetFileName(str(path))
    reader.UpdateInformation()
    steps = reader.GetOutputInformation(0).Get(vtk.vtkStreamingDemandDrivenPipeline.TIME_STEPS())
    reader.Update()
    grid = reader.GetOutputDataObject(0)
    assert grid.GetClassName() == "vtkUnstructuredGrid"  # one grid, not a block of two
    assert list(steps) == [f.time for f in run.result.frames]
    assert grid.GetNumberOfCells() == len(run.result.mesh.triangles)
    assert grid.GetCellData().GetArray("shear_angle_deg").GetNumberOfComponents() == 3


def test_an_xdmf_series_of_triangles_and_lines_reads_back_block_by_block(tmp_path):
    points = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [2, 0, 0]])
    cells = [("triangle", np.array([[0, 1, 2]])), ("line", np.array([[1, 3], [3, 2]]))]
    force = [np.array([7.0]), np.array([1.0, 2.0])]
    write_xdmf(tmp_path / "mixed.xdmf", points, cells, [(0.5, {"u": points}, {"f": force})])
    with meshio.xdmf.TimeSeriesReader(tmp_path / "mixed.xdmf") as reader:
        _, back = reader.read_points_cells()
        t, point_data, cell_data = reader.read_data(0)
    assert [(c.type, c.data.tolist()) for c in back] == [(k, c.tolist()) for k, c in cells]
    assert t == 0.5 and np.allclose(point_data["u"], points)
    assert [f.tolist() for f in cell_data["f"]] == [[7.0], [1.0, 2.0]]


def test_the_xdmf_arrays_are_the_bytes_h5py_s_create_dataset_writes(tmp_path, monkeypatch):
    # femcore.xdmf makes a shape's creation properties once and creates the others at the low
    # level; the reference: every dataset by h5py's create_dataset. Fields of two shapes and
    # types over three frames, cells of two kinds (a Mixed topology).
    import femcore.xdmf as xdmf

    rng = np.random.default_rng(5)
    points = rng.random((40, 3))
    triangles = np.c_[np.arange(30), np.arange(1, 31), np.arange(2, 32)]
    cells = [("triangle", triangles), ("line", np.c_[np.arange(5), np.arange(1, 6)])]
    frames = [
        (0.25 * k, {"u": rng.random((40, 3)), "t": rng.random(40)}, {"s": [rng.random((30, 3)),
         rng.random((5, 3))]})
        for k in range(3)
    ]  # fmt: skip
    xdmf.write_xdmf(tmp_path / "fast.xdmf", points, cells, frames)

    class EveryDataset:
        def __init__(self, h5):
            self.h5 = h5

        def __call__(self, key, values):
            self.h5.create_dataset(key, data=values, **xdmf._PACKED)

    monkeypatch.setattr(xdmf, "_Datasets", EveryDataset)
    xdmf.write_xdmf(tmp_path / "reference.xdmf", points, cells, frames)
    fast, reference = (tmp_path / "fast.h5").read_bytes(), (tmp_path / "reference.h5").read_bytes()
    assert fast == reference
    light = (tmp_path / "fast.xdmf").read_text().replace("fast.h5", "reference.h5")
    assert light == (tmp_path / "reference.xdmf").read_text()
    with h5py.File(tmp_path / "fast.h5") as h5:
        assert h5["frames/2/node/u"].compression == "gzip"


def test_xdmf_refuses_a_cell_type_it_cannot_write(tmp_path):
    with pytest.raises(ValueError, match=r"cell types \['quad'\].*expected"):
        write_xdmf(tmp_path / "q.xdmf", np.zeros((4, 3)), [("quad", np.arange(4)[None])], [])


def test_levels_are_named_from_the_bottom_to_the_top():
    assert level_names(1) == ("middle",)
    assert level_names(2) == ("bottom", "top")
    assert level_names(3) == ("bottom", "middle", "top")
    assert level_names(5) == ("bottom", "level_2", "level_3", "level_4", "top")


def test_a_second_field_of_a_name_has_the_components_of_the_first():
    assert component_names("membrane_force", 3) == ("11", "22", "12")
    assert component_names("ply_slip_vector_2", 3) == ("x", "y", "z")
    assert component_names("warp_strain", 4) == level_names(4)
    assert component_names("membrane_force", 2) is None  # another count: left unnamed
    assert component_names("no_such_field", 3) is None


def test_two_element_types_must_agree_on_a_field_s_components():
    name_components("membrane_force", ("11", "22", "12"))  # the same again: accepted
    with pytest.raises(ValueError, match="already declared.*same components"):
        name_components("membrane_force", ("N11", "N22", "N12"))
    with pytest.raises(ValueError, match="LEVELS"):
        name_components("some_field", "level")
    with pytest.raises(ValueError, match="non-empty strings"):
        name_components("some_field", ("a", ""))
    assert LEVELS == "levels"


def test_a_clamped_mindlin_nodes_tilt_is_left_out_of_the_summary(tmp_path):
    """The Mindlin strip's clamp: its director is held, and its tilt against the deformed
    one-sided facets (several degrees, where the next node out leans less) said the largest
    tilt of the run in summary.json and sweep.csv; held directors are left out."""
    case = tmp_path / "strip.toml"
    mindlin = STRIP.replace('element = "fibrous"', 'element = "mindlin"', 1)
    case.write_text(mindlin.replace('options = { clamped = "left" }\n', "", 1))
    run = run_case(load_case(case), tmp_path / "out", progress=False)
    tilt = np.asarray(run.result.field("director_tilt_deg"), dtype=float)
    held = held_directors(load_case(case).model())
    free = np.ones(len(tilt), dtype=bool)
    free[held] = False
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())["director_tilt_deg"]
    assert held.size and summary["max"] == pytest.approx(tilt[free].max(), rel=1e-12)
    assert tilt[held].max() > tilt[free].max()  # what the summary said before
