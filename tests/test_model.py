"""Model building: DOFs, constraints and loads, and the errors a user gets for bad input."""

import numpy as np
import pytest

from elements import Cable
from femcore import Mesh, Model
from femcore.dofs import DOF_NAMES
from solvers import CentralDifference, DynamicRelaxation


def bar(n=4):
    points = np.column_stack([np.linspace(0, 10.0, n + 1), np.zeros(n + 1), np.zeros(n + 1)])
    return Mesh(points, lines=np.column_stack([np.arange(n), np.arange(1, n + 1)]))


def cable_model(mesh=None):
    model = Model(mesh or bar())
    model.add(Cable(100.0, 1e-9))
    return model


def test_cable_nodes_carry_three_translations():
    model = cable_model()
    model.fix([0])
    model.fix([4], "uz")
    dofs = model.compile().dofs
    assert dofs.names_at(2) == ("ux", "uy", "uz")
    assert dofs.n_dofs == 15
    assert dofs.fixed[0, :3].all() and dofs.fixed[4].tolist() == [False, False, True, False, False]
    assert dofs.n_free == 15 - 3 - 1
    # global numbering is contiguous per node
    assert dofs.number[1, :3].tolist() == [3, 4, 5]
    assert (dofs.number[:, 3:] == -1).all()


def test_loads_are_dead_and_follow_their_amplitude():
    model = cable_model()
    model.force([4], (1.0, 2.0, 3.0), amplitude="linear")
    model.gravity((0.0, 0.0, -10.0))
    compiled = model.compile()
    force, moment = compiled.external_load(0.5)
    assert force[4] == pytest.approx(
        np.array([0.5, 1.0, 1.5]) + compiled.mass0[4] * np.array([0, 0, -10.0])
    )
    assert not moment.any()
    assert compiled.mass0.sum() == pytest.approx(1e-9 * 10.0)


def test_smooth_amplitude_reaches_the_prescribed_value_at_the_end():
    model = cable_model()
    model.fix([0])
    model.displace([4], ux=1.0)
    compiled = model.compile()
    assert compiled.prescribed_displacement(1.0)[4, 0] == pytest.approx(1.0)
    assert compiled.prescribed_displacement(0.5)[4, 0] == pytest.approx(0.5)
    assert compiled.prescribed_displacement(0.1)[4, 0] == pytest.approx(0.00856)
    # quasi-static solvers ramp in equal increments
    assert compiled.prescribed_displacement(0.1, quasi_static=True)[4, 0] == pytest.approx(0.1)


@pytest.mark.parametrize(
    "build, message",
    [
        (lambda m: m.fix([0], "uw"), "unknown DOF name 'uw'"),
        (lambda m: m.fix([0], ("ux", "spin")), "unknown DOF name 'spin'"),
        (lambda m: m.fix([7]), "node id 7 out of range"),
        (lambda m: m.fix([-1]), "node id -1 out of range"),
        (lambda m: m.fix([]), "empty node selection"),
        (lambda m: m.force([1], (1.0, 2.0)), "force must be 3 finite numbers"),
        (lambda m: m.gravity((0, 0, np.inf)), "gravity must be 3 finite numbers"),
        (lambda m: m.displace([1]), "at least one of ux, uy, uz"),
        (lambda m: m.displace([1], ux=np.nan), "ux must be a finite number"),
        (lambda m: m.displace([1], ux=1.0, amplitude="wobbly"), "unknown amplitude 'wobbly'"),
        (lambda m: m.add(Cable(1.0, 1.0), cells=[9]), "line cell id 9 out of range"),
        (lambda m: m.add("cable"), "not an element type"),
        (lambda m: m.fix("clamp"), "no node set named 'clamp'"),
    ],
)
def test_bad_model_input_is_named_where_it_is_written(build, message):
    model = cable_model(bar())
    with pytest.raises(ValueError, match=message):
        build(model)


def test_empty_predicate_selection_is_an_error():
    with pytest.raises(ValueError, match="no node"):
        bar().nodes(lambda x, y, z: x > 100.0)


def test_a_dof_fixed_and_prescribed_at_once_is_refused():
    model = cable_model()
    model.fix([4])
    model.displace([4], ux=1.0)
    with pytest.raises(ValueError, match="ux of node 4 is both fixed and prescribed"):
        model.compile()


def test_fixing_a_rotation_on_a_cable_node_is_refused():
    model = cable_model()
    model.fix([1], "alpha")
    with pytest.raises(ValueError, match="cannot fix alpha at node 1"):
        model.compile()


def test_a_moment_on_a_node_without_rotations_is_refused():
    model = cable_model()
    model.moment([1], (0.0, 1.0, 0.0))
    with pytest.raises(ValueError, match="moment on node 1, which has no rotational DOFs"):
        model.compile()


def test_a_force_on_a_node_no_element_uses_is_refused_in_plain_words():
    # The cable spans segments 0-2 of the bar: node 4 belongs to no cell of a block (as a
    # mesh's cells restricted to one part leave the others' nodes).
    model = Model(bar())
    model.add(Cable(100.0, 1e-9), cells=[0, 1, 2])
    model.fix([0])
    model.force([4], (0.0, 0.0, -1.0))
    with pytest.raises(
        ValueError, match="force on node 4, which no element uses: it carries no DOF"
    ) as refused:
        model.compile()
    assert "no any" not in str(refused.value)


def strip_of(left: str, right: str) -> tuple[Model, np.ndarray]:
    """A 100 x 20 mm strip, 4 x 1 cells, its left half of ``left`` cells and its right half of
    ``right`` ("fibrous" or "mindlin"), clamped at x = 0; and the ids of its tip nodes."""
    from elements import FibrousShell, MindlinShell
    from materials import presets

    mesh = Mesh.rectangle(100.0, 20.0, nx=4, ny=1)
    fabric = presets.g1151_laminate()
    make = {"fibrous": lambda: FibrousShell(fabric), "mindlin": lambda: MindlinShell(fabric)}
    centres = mesh.points[mesh.triangles].mean(axis=1)[:, 0]
    model = Model(mesh)
    model.add(make[left](), np.flatnonzero(centres < 50.0))
    model.add(make[right](), np.flatnonzero(centres >= 50.0))
    model.fix("left")
    return model, mesh.nodes("right")


def test_a_moment_on_nodes_only_fibrous_cells_use_is_refused_naming_them_and_the_way_out():
    """The fibrous shell's rotational DOFs turn its directors (material normals), its bending
    is rotation-free (docs/theory.md §4.5): a tip moment moved the strip 4.7e-5 mm where the
    bending closed form wants 0.45 mm, silently."""
    model, tip = strip_of("fibrous", "fibrous")
    model.moment(tip, (0.0, -0.05, 0.0))
    with pytest.raises(
        ValueError, match=r"moment on 2 node\(s\) \(4, 9\) that only FibrousShell"
    ) as e:
        model.compile()
    assert "force couple" in str(e.value) and "Mindlin part" in str(e.value)


def test_a_moment_on_nodes_a_mindlin_block_uses_is_kept_even_where_fibrous_cells_meet_them():
    model, tip = strip_of("fibrous", "mindlin")
    middle = model.mesh.nodes(lambda x, y, z: np.isclose(x, 50.0))  # both blocks use them
    model.moment(tip, (0.0, -0.05, 0.0))
    model.moment(middle, (0.0, -0.05, 0.0))
    model.compile()
    model, _ = strip_of("mindlin", "fibrous")
    model.moment(middle, (0.0, -0.05, 0.0))
    model.compile()


@pytest.mark.parametrize("solver", [DynamicRelaxation(), CentralDifference(duration=1.0)])
def test_a_model_without_elements_is_refused(solver):
    with pytest.raises(ValueError, match="no elements"):
        solver.solve(Model(bar()))


def test_non_finite_coordinates_are_refused():
    points = bar().points.copy()
    points[2, 1] = np.nan
    with pytest.raises(ValueError, match="non-finite"):
        Mesh(points, lines=bar().lines)


def test_solver_parameters_are_checked():
    with pytest.raises(ValueError, match="duration"):
        CentralDifference(duration=0.0)
    with pytest.raises(ValueError, match="safety"):
        CentralDifference(duration=1.0, safety=1.5)
    with pytest.raises(ValueError, match="increments"):
        DynamicRelaxation(increments=0)
    with pytest.raises(ValueError, match="damping"):
        DynamicRelaxation(damping="magic")


def test_dof_names_are_the_documented_five():
    assert DOF_NAMES == ("ux", "uy", "uz", "alpha", "beta")


def triangle_model(points, triangles):
    from elements.base import ElementBlock, ElementType

    class Membrane(ElementType):  # the smallest triangle element: enough to reach the checks
        dofs = ("ux", "uy", "uz")
        cell_type = "triangle"

        def bind(self, mesh, cell_ids, directors) -> ElementBlock:
            raise AssertionError("a bad mesh must be refused before binding")

    model = Model(Mesh(points, triangles=triangles))
    model.add(Membrane())
    return model


def test_duplicate_nodes_are_refused_when_the_model_is_compiled():
    points = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 0, 0], [1, 1, 0]])
    with pytest.raises(ValueError, match="duplicate"):
        triangle_model(points, [[0, 1, 2], [3, 4, 2]]).compile()


def test_zero_area_triangles_are_refused_when_the_model_is_compiled():
    points = np.array([[0.0, 0, 0], [1, 0, 0], [2, 0, 0], [0, 1, 0]])
    with pytest.raises(ValueError, match="zero area|zero-area"):
        triangle_model(points, [[0, 1, 2], [0, 3, 1]]).compile()
