"""Bad input across the public surface: every numeric parameter of the materials, elements,
tools and solvers refuses strings, booleans, None and NaN with the parameter's name; node
predicates, node ids, DOF names and paths of the wrong kind are ValueErrors saying what was
expected. Each case is a call and the message it must raise: never a raw TypeError from numpy,
never a value silently converted ("1" read as 1, True as 1, "no" as True)."""

import numpy as np
import pytest

from elements import (
    Cable,
    Contact,
    FibrousShell,
    Grip,
    MindlinShell,
    RigidCylinder,
    RigidPlane,
    RigidSphere,
    RigidSurface,
)
from elements.plies import PlyStack
from femcore import Mesh, Model
from materials import BendingLaw, ElasticShell, Fabric, ShearLaw, TensionLaw
from solvers import CentralDifference, DynamicRelaxation, Static

NAN = float("nan")


def steel(**changes) -> ElasticShell:
    arguments = {"E": 70e3, "nu": 0.3, "thickness": 1.0, "density": 2.7e-9} | changes
    return ElasticShell(**arguments)


def fabric(**changes) -> Fabric:
    arguments = {
        "thickness": 1.0,
        "areal_density": 1.66e-9,
        "tension": 1000.0,
        "shear": 1.0,
        "bending": 0.833,
    } | changes
    return Fabric(**arguments)


def orthotropic(**changes) -> ElasticShell:
    arguments = {
        "E1": 1.0,
        "E2": 1.0,
        "nu12": 0.3,
        "G12": 1.0,
        "G13": 1.0,
        "G23": 1.0,
        "thickness": 1.0,
        "density": 1e-9,
    } | changes
    return ElasticShell.orthotropic(**arguments)


def strip() -> Model:
    model = Model(Mesh.rectangle(20.0, 5.0, nx=4, ny=1))
    model.add(MindlinShell(steel()))
    return model


PLANE = ((0.0, 0.0, -1.0), (0.0, 0.0, 1.0))

# ------------------------------------------------------------------ numbers
NUMBERS = {
    "ElasticShell thickness '1'": (lambda: steel(thickness="1"), r"thickness .*got '1'"),
    "ElasticShell E True": (lambda: steel(E=True), r"ElasticShell E .*got True"),
    "ElasticShell nu '0.3'": (lambda: steel(nu="0.3"), r"nu must be .*got '0.3'"),
    "ElasticShell density None": (lambda: steel(density=None), r"density .*got None"),
    "ElasticShell thickness NaN": (lambda: steel(thickness=NAN), r"thickness .*got nan"),
    "orthotropic E1 '1'": (lambda: orthotropic(E1="1"), r"E1 .*got '1'"),
    "orthotropic nu12 True": (lambda: orthotropic(nu12=True), r"nu12 .*got True"),
    "orthotropic warp strings": (
        lambda: orthotropic(warp=["1", "0", "0"]),
        r"ElasticShell warp must be a non-zero 3-vector",
    ),
    "equivalent shear_ratio '0.5'": (
        lambda: ElasticShell.equivalent(fabric(), shear_ratio="0.5"),
        r"shear_ratio .*got '0.5'",
    ),
    "Fabric thickness '1'": (lambda: fabric(thickness="1"), r"Fabric thickness .*got '1'"),
    "Fabric tension 'stiff'": (lambda: fabric(tension="stiff"), r"Fabric tension .*'stiff'"),
    "Fabric bending True": (lambda: fabric(bending=True), r"Fabric bending .*got True"),
    "TensionLaw.linear '1'": (lambda: TensionLaw.linear("1"), r"stiffness C .*got '1'"),
    "TensionLaw tension_only 'no'": (
        lambda: TensionLaw.linear(1.0, tension_only="no"),
        r"tension_only must be True or False, got 'no'",
    ),
    "BendingLaw.bilinear 'x'": (lambda: BendingLaw.bilinear(1.0, "x", 0.1), r"B2 .*got 'x'"),
    "ShearLaw.table strings": (
        lambda: ShearLaw.table(["0", "1"], ["0", "1"]),
        r"table abscissae must be a sequence of numbers",
    ),
    "Law.scaled '2'": (lambda: TensionLaw.linear(1.0).scaled("2"), r"factor .*got '2'"),
    "Cable EA '1e3'": (lambda: Cable("1e3", 1e-9), r"axial_stiffness EA .*got '1e3'"),
    "Cable EA True": (lambda: Cable(True, 1e-9), r"axial_stiffness EA .*got True"),
    "Cable tension_only 'yes'": (
        lambda: Cable(1e3, 1e-9, tension_only="yes"),
        r"tension_only must be True or False, got 'yes'",
    ),
    "MindlinShell twisting '1'": (
        lambda: MindlinShell(fabric(), twisting="1"),
        r"MindlinShell twisting .*got '1'",
    ),
    "FibrousShell fibre_angle_tolerance '1'": (
        lambda: FibrousShell(fabric(), fibre_angle_tolerance="1"),
        r"fibre_angle_tolerance .*got '1'",
    ),
    "FibrousShell warp strings": (
        lambda: FibrousShell(fabric(), warp=["1", "0", "0"]),
        r"FibrousShell warp must be a non-zero 3-vector",
    ),
    "FibrousShell thickness_variation 'no'": (
        lambda: FibrousShell(fabric(), thickness_variation="no"),
        r"thickness_variation must be True or False, got 'no'",
    ),
    "RigidSphere radius '5'": (lambda: RigidSphere((0, 0, 0), "5"), r"radius .*got '5'"),
    "RigidSphere radius True": (lambda: RigidSphere((0, 0, 0), True), r"radius .*got True"),
    "RigidPlane point strings": (
        lambda: RigidPlane(["0", "0", "0"], (0, 0, 1)),
        r"RigidPlane point must be 3 finite numbers",
    ),
    "RigidCylinder axis bools": (
        lambda: RigidCylinder((0, 0, 0), (True, False, False), 5.0),
        r"RigidCylinder axis must be 3 finite numbers",
    ),
    "RigidSurface flip 'yes'": (
        lambda: RigidSurface(Mesh.rectangle(1.0, 1.0, 2, 2), flip="yes"),
        r"flip must be True or False, got 'yes'",
    ),
    "Contact offset strings": (
        lambda: Contact(RigidPlane(*PLANE), offset=["1"]),
        r"offset must be finite numbers >= 0",
    ),
    "Grip stiffness True": (lambda: Grip("left", True), r"Grip stiffness .*got True"),
    "PlyStack penalty True": (
        lambda: PlyStack(Mesh.rectangle(1.0, 1.0, 2, 2), fabric(), 2, penalty=True),
        r"penalty must be a positive number \(N/mm\) or None, got True",
    ),
    "CentralDifference history 5": (
        lambda: CentralDifference(duration=1e-4, history=5),
        r"history must be a file name .*got 5",
    ),
    "Grip stiffness 'stiff'": (lambda: Grip("left", "stiff"), r"Grip stiffness .*'stiff'"),
    "CentralDifference duration '1e-3'": (
        lambda: CentralDifference(duration="1e-3"),
        r"duration .*got '1e-3'",
    ),
    "CentralDifference duration True": (
        lambda: CentralDifference(duration=True),
        r"duration .*got True",
    ),
    "CentralDifference dt '1e-6'": (
        lambda: CentralDifference(duration=1e-3, dt="1e-6"),
        r"dt .*got '1e-6'",
    ),
    "CentralDifference progress 'yes'": (
        lambda: CentralDifference(duration=1e-3, progress="yes"),
        r"progress must be true or false, got 'yes'",
    ),
    "DynamicRelaxation tol '1e-3'": (lambda: DynamicRelaxation(tol="1e-3"), r"tol .*'1e-3'"),
    "DynamicRelaxation tol True": (lambda: DynamicRelaxation(tol=True), r"tol .*got True"),
    "Mesh.rectangle lx '1'": (lambda: Mesh.rectangle("1", 1.0, 2, 2), r"lx .*got '1'"),
    "Mesh.rectangle lx True": (lambda: Mesh.rectangle(True, 1.0, 2, 2), r"lx .*got True"),
    "Mesh.line p0 strings": (
        lambda: Mesh.line(["0", "0", "0"], (1.0, 0.0, 0.0), 3),
        r"p0 must be a point",
    ),
    "Mesh.corner grip strings": (
        lambda: Mesh.corner(200.0, 150.0, 4, grip=["20", "15"]),
        r"grip must be a size or a pair of sizes",
    ),
    "Static progress 'no'": (
        lambda: Static(progress="no"),
        r"progress must be true or false, got 'no'",
    ),
}


@pytest.mark.parametrize("call, message", NUMBERS.values(), ids=NUMBERS.keys())
def test_a_string_boolean_none_or_nan_where_a_number_is_meant_is_refused_by_name(call, message):
    with pytest.raises(ValueError, match=message):
        call()


def test_numbers_of_numpy_types_are_still_accepted():
    shell = steel(E=np.float64(70e3), thickness=np.float32(1.0))
    assert shell.thickness == 1.0
    assert Cable(np.int64(1000), 1e-9).axial_stiffness == 1000.0
    assert fabric(tension=np.float64(10.0)).tension.slope(0.0) == pytest.approx(10.0)


# ------------------------------------------------------------------ node predicates
PREDICATES = {
    "one argument": (lambda x: x > 0, r"cannot be called as predicate\(x, y, z\)"),
    "two arguments": (lambda x, y: x > 0, r"cannot be called as predicate\(x, y, z\)"),
    "a scalar": (lambda x, y, z: True, r"shape \(\), expected \(9,\)"),
    "floats": (lambda x, y, z: x, r"dtype float64, expected bool"),
}


@pytest.mark.parametrize("predicate, message", PREDICATES.values(), ids=PREDICATES.keys())
def test_a_node_predicate_of_the_wrong_form_says_what_a_predicate_is(predicate, message):
    mesh = Mesh.rectangle(1.0, 1.0, 2, 2)
    with pytest.raises(ValueError, match=message) as raised:
        mesh.nodes(predicate)
    assert "takes the (x, y, z) coordinate arrays and returns a bool array" in str(raised.value)


def test_a_type_error_inside_a_predicate_of_the_right_form_is_the_predicates_own():
    mesh = Mesh.rectangle(1.0, 1.0, 2, 2)
    with pytest.raises(TypeError, match="has no len"):
        mesh.nodes(lambda x, y, z: len(5))


def test_a_predicate_with_defaults_or_varargs_is_accepted():
    mesh = Mesh.rectangle(1.0, 1.0, 2, 2)
    assert mesh.nodes(lambda *xyz: xyz[0] == 0.0).tolist() == [0, 3, 6]
    assert mesh.nodes(lambda x, y, z, tol=1e-9: x < tol).tolist() == [0, 3, 6]


# ------------------------------------------------------------------ the model
MODEL_CALLS = {
    "fix with id strings": (
        lambda m: m.fix(["0", "1"]),
        r"node selection must be node ids \(integers\), a set name or a predicate",
    ),
    "fix None": (lambda m: m.fix(None), r"node selection must be node ids"),
    "fix a 2-D id array": (
        lambda m: m.fix(np.array([[0, 1]])),
        r"node ids must be a flat sequence of integers, got an array of shape \(1, 2\)",
    ),
    "fix dofs 5": (lambda m: m.fix("left", 5), r"DOFs must be a name or a sequence of names"),
    "displace uz True": (lambda m: m.displace("right", uz=True), r"uz must be .*got True"),
    "displace uz 'down'": (lambda m: m.displace("right", uz="down"), r"uz must be .*'down'"),
    "force of strings": (
        lambda m: m.force("right", ["0", "0", "1"]),
        r"force must be 3 finite numbers",
    ),
    "force of bools": (
        lambda m: m.force("right", (True, False, False)),
        r"force must be 3 finite numbers",
    ),
    "contact friction True": (
        lambda m: m.contact(RigidPlane(*PLANE), friction=True),
        r"friction must be a Coulomb coefficient >= 0, got True",
    ),
    "contact penalty '1e3'": (
        lambda m: m.contact(RigidPlane(*PLANE), penalty="1e3"),
        r"penalty must be a positive number \(N/mm\) or None, got '1e3'",
    ),
    "contact penalty True": (
        lambda m: m.contact(RigidPlane(*PLANE), penalty=True),
        r"penalty must be a positive number \(N/mm\) or None, got True",
    ),
    "add on a 2-D cell array": (
        lambda m: m.add(Cable(1e3, 1e-9), cells=np.array([[0, 1]])),
        r"line cell ids must be a flat sequence",
    ),
}


@pytest.mark.parametrize("call, message", MODEL_CALLS.values(), ids=MODEL_CALLS.keys())
def test_model_methods_refuse_values_of_the_wrong_kind(call, message):
    model = strip()
    with pytest.raises(ValueError, match=message):
        call(model)


# ------------------------------------------------------------------ paths
def held_cable() -> Model:
    """A cable held at both ends: a model whose result has no directors."""
    model = Model(Mesh.line((0.0, 0.0, 0.0), (10.0, 0.0, 0.0), 4))
    model.add(Cable(1e3, 1e-9))
    model.fix("start")
    model.fix("end")
    return model


def test_a_path_that_is_not_a_file_name_is_a_value_error(tmp_path):
    # Refused before any computation: a result of one frame at rest, built by hand.
    from femcore import Frame, Result

    mesh = Mesh.line((0.0, 0.0, 0.0), (10.0, 0.0, 0.0), 4)
    zero = np.zeros_like(mesh.points)
    result = Result(mesh, [Frame(0.0, 0.0, mesh.points, zero, zero, zero, zero)])
    with pytest.raises(ValueError, match=r"Result.write path must be a file name .*got 5"):
        result.write(5)
    with pytest.raises(ValueError, match=r"Mesh.read path must be a file name .*got 5"):
        Mesh.read(5)
    with pytest.raises(ValueError, match=r"output must be a file name .*got 5"):
        CentralDifference(duration=1e-4, output=5)
    afile = tmp_path / "afile"
    afile.write_text("x")
    with pytest.raises(ValueError, match=r"Mesh.write .*afile.* is a file, not a folder|afile"):
        Mesh.rectangle(1.0, 1.0, 2, 2).write(afile / "m.vtu")


# ------------------------------------------------------------------ results
def test_the_director_angle_of_a_result_without_directors_is_refused_not_zero():
    # A cable's result (its nodes carry no director), one frame at rest built by hand: the
    # refusal needs no solve, whose cost here was only the compiling of the cable's kernels.
    from femcore import Frame, Result

    mesh = held_cable().mesh
    zero = np.zeros_like(mesh.points)
    result = Result(mesh, [Frame(0.0, 0.0, mesh.points, zero, zero, zero, zero)])
    with pytest.raises(ValueError, match=r"no node of this result has a director"):
        result.director_angle()


def test_the_director_angle_is_nan_at_the_nodes_of_a_cable_beside_a_shell():
    mesh = Mesh.rectangle(20.0, 5.0, nx=2, ny=1)
    model = Model(mesh)
    model.add(MindlinShell(steel()))
    state = model.compile().initial_state()
    from femcore import Frame, Result

    directors = state.directors.copy()
    directors[0] = 0.0  # a node without a director, as a cable's
    zero = np.zeros_like(state.positions)
    result = Result(mesh, [Frame(0.0, 0.0, state.positions, zero, directors, zero, zero)])
    angle = result.director_angle()
    assert np.isnan(angle[0])
    assert np.allclose(angle[1:], 90.0)


def test_a_meshed_tool_answers_no_points_with_no_distances_and_refuses_a_wrong_shape():
    """An empty set of points (a block with no node near the tool) gets empty answers, not
    numpy's reshape error; points not of shape (k, 3) are a ValueError naming the shape."""
    floor = RigidSurface(Mesh.rectangle(2.0, 2.0, nx=2, ny=2))
    d, n = floor.distance(np.zeros((0, 3)))
    assert d.shape == (0,) and n.shape == (0, 3)
    with pytest.raises(ValueError, match=r"expected \(k, 3\)"):
        floor.distance(np.zeros((4, 2)))
    d, n = floor.distance(np.array([[0.5, 0.5, 0.25]]))
    assert d[0] == pytest.approx(0.25) and n[0] == pytest.approx([0.0, 0.0, 1.0])
