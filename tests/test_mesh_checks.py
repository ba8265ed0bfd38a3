"""A mesh refuses at construction what would make every answer wrong or end in a raw error:
the same cell twice, coordinates beyond what products of lengths keep in double precision,
an extent too small for the tolerances of the checks, and a size that cannot fit in memory
(refused before anything is allocated, with the numbers)."""

import time

import numpy as np
import pytest

from elements import FibrousShell
from femcore import Mesh, Model, memory
from femcore.mesh_checks import COORDINATE_LIMIT, MIN_EXTENT
from femcore.topology import check_duplicate_nodes
from fibreshell.case import CaseError, case_from_data
from materials import presets
from solvers import Static

TRIANGLE = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]]


@pytest.mark.parametrize("copy", [(0, 1, 2), (1, 2, 0), (0, 2, 1), (2, 1, 0)])
def test_the_same_triangle_twice_in_any_node_order_is_refused_naming_both(copy):
    named = rf"triangles 0 \(0, 1, 2\) and 2 \({', '.join(map(str, copy))}\)"
    with pytest.raises(ValueError, match=named):
        Mesh(TRIANGLE, [[0, 1, 2], [1, 3, 2], copy])


def test_the_same_line_twice_is_refused_and_many_copies_are_counted():
    with pytest.raises(ValueError, match=r"the same line is given twice: lines 0 \(0, 1\) and 1"):
        Mesh(TRIANGLE, lines=[[0, 1], [1, 0]])
    plate = Mesh.rectangle(1.0, 1.0, 4, 4)
    doubled = np.concatenate([plate.triangles, plate.triangles[:, ::-1]])
    with pytest.raises(ValueError, match=r"\(and 27 more pairs\)"):
        Mesh(plate.points, doubled)


def test_triangles_sharing_nodes_but_not_all_three_are_accepted():
    mesh = Mesh(TRIANGLE, [[0, 1, 2], [1, 3, 2]], lines=[[0, 1], [1, 3]])
    assert mesh.n_triangles == 2 and mesh.n_lines == 2


@pytest.mark.parametrize("scale", [1e200, -1e61, 1e100])
def test_coordinates_beyond_the_range_are_refused_naming_the_node_and_the_range(scale):
    plate = Mesh.rectangle(1.0, 1.0, 2, 2)
    named = r"node 1 has coordinates .* outside the range \[-1e\+60, 1e\+60\]"
    with pytest.raises(ValueError, match=named):
        plate.with_points(plate.points * scale)
    with pytest.raises(ValueError, match=r"outside the range"):
        Mesh.rectangle(1.0, 1.0, 2, 2, origin=(abs(scale), 0.0, 0.0))


def test_a_mesh_too_small_for_the_tolerances_is_degenerate_and_says_its_extent():
    plate = Mesh.rectangle(1.0, 1.0, 2, 2)
    with pytest.raises(ValueError, match=r"degenerate or too small: its extent is 1.41e-200"):
        plate.with_points(plate.points * 1e-200)
    with pytest.raises(ValueError, match=r"degenerate or too small: all its nodes coincide"):
        Mesh(np.zeros((3, 3)), [[0, 1, 2]])
    # The triangles' own nodes coincide while other nodes are elsewhere: check() says so.
    with pytest.raises(ValueError, match=r"degenerate or too small: its 3 nodes span 0"):
        check_duplicate_nodes([[0, 0, 0], [0, 0, 0], [0, 0, 0], [1, 0, 0]], [[0, 1, 2]])


@pytest.mark.parametrize("scale", [1e-40, 1e40])
def test_meshes_far_from_unit_size_inside_the_range_are_accepted_and_check(scale):
    plate = Mesh.rectangle(1.0, 1.0, 2, 2)
    moved = plate.with_points(plate.points * scale)
    moved.check()
    assert MIN_EXTENT < scale < COORDINATE_LIMIT
    assert len(Mesh([[5.0, 5.0, 5.0]]).points) == 1  # one node has no extent to speak of


def test_a_rectangle_too_large_for_memory_is_refused_at_once_with_the_numbers(monkeypatch):
    monkeypatch.setattr(memory, "available_memory", lambda: 16 * 1024**3)
    start = time.perf_counter()
    with pytest.raises(
        ValueError,
        match=r"Mesh.rectangle\(nx=30000, ny=30000\) with 1800000000 triangles would need "
        r"about 2\d\d GB; this machine has 16 GB available",
    ):
        Mesh.rectangle(1.0, 1.0, 30000, 30000)
    assert time.perf_counter() - start < 1.0


@pytest.mark.parametrize(
    "build, message",
    [
        (lambda: Mesh.rectangle(1.0, 1.0, 20, 20), r"Mesh.rectangle\(nx=20, ny=20\) with 800"),
        (lambda: Mesh.corner(1.0, 1.0, 20), r"Mesh.corner\(n=20\) with 800 triangles"),
        (
            lambda: Mesh.quadrilateral([[0, 0], [1, 0], [1, 1], [0, 1]], 20, 20),
            r"Mesh.quadrilateral\(nx=20, ny=20\)",
        ),
        (lambda: Mesh.line((0, 0), (1, 0), 1000), r"Mesh.line\(n=1000\) with 1000 lines"),
        (
            lambda: Mesh.from_quads(np.zeros((1000, 3)), np.zeros((500, 4), dtype=int)),
            r"Mesh.from_quads with 1000 triangles",
        ),
    ],
)
def test_every_generator_checks_the_memory_before_building(monkeypatch, build, message):
    monkeypatch.setattr(memory, "available_memory", lambda: 50_000)
    with pytest.raises(ValueError, match=message + r".* would need about .* GB"):
        build()


def test_a_case_file_rectangle_of_1e8_cells_is_refused_naming_the_table(tmp_path, monkeypatch):
    monkeypatch.setattr(memory, "available_memory", lambda: 16 * 1024**3)
    data = {
        "mesh": {"rectangle": {"lx": 1.0, "ly": 1.0, "nx": 10000, "ny": 10000}},
        "part": [{"element": "fibrous", "material": "g986_ply"}],
        "solver": {"kind": "static"},
    }
    with pytest.raises(CaseError, match=r"\[mesh.rectangle\]: .* 200000000 triangles would need"):
        case_from_data(data, tmp_path / "huge.toml")


def test_reading_a_file_too_large_for_memory_is_refused_before_building(tmp_path, monkeypatch):
    path = tmp_path / "plate.vtu"
    Mesh.rectangle(1.0, 1.0, 4, 4).write(path)
    monkeypatch.setattr(memory, "available_memory", lambda: 1000)
    with pytest.raises(ValueError, match=r"the mesh of .*plate.vtu with 32 cells would need"):
        Mesh.read(path)


def test_a_model_too_large_for_memory_is_refused_at_compile(monkeypatch):
    model = Model(Mesh.rectangle(10.0, 10.0, 2, 2))
    model.add(FibrousShell(presets.g986_ply()))
    monkeypatch.setattr(memory, "available_memory", lambda: 5_000)
    with pytest.raises(ValueError, match=r"a model of 8 element cells .* would need about"):
        model.compile()


def test_a_static_solve_too_large_for_memory_is_refused_before_its_first_tangent(monkeypatch):
    model = Model(Mesh.rectangle(10.0, 10.0, 2, 2))
    model.add(FibrousShell(presets.g986_ply()))
    model.fix("left")
    model.gravity((0.0, 0.0, -9810.0))
    monkeypatch.setattr(memory, "available_memory", lambda: 100_000)  # the model fits
    compiled = model.compile()
    with pytest.raises(ValueError, match=r"a static solve of 8 element cells .* would need"):
        Static(increments=1, progress=False).solve(compiled)


def test_the_available_memory_is_read_from_the_system():
    assert memory.available_memory() > 0


def test_a_control_group_limit_caps_the_available_memory(tmp_path, monkeypatch):
    meminfo = tmp_path / "meminfo"
    meminfo.write_text("MemTotal:       4000000 kB\nMemAvailable:   2000000 kB\n")
    limit, usage = tmp_path / "memory.max", tmp_path / "memory.current"
    limit.write_text("1000000000\n")
    usage.write_text("300000000\n")
    monkeypatch.setattr(memory, "MEMINFO", meminfo)
    monkeypatch.setattr(memory, "CGROUP_FILES", ((limit, usage),))
    assert memory.available_memory() == 700_000_000
    limit.write_text("max\n")  # no limit: the machine's MemAvailable
    assert memory.available_memory() == 2_048_000_000
