"""solvers.Static: Newton-Raphson with the coloured finite-difference tangent."""

import numpy as np
import pytest

from elements import Cable, FibrousShell, MindlinShell
from femcore import Mesh, Model
from materials import BendingLaw, ElasticShell, Fabric, ShearLaw
from solvers import ConvergenceError, DynamicRelaxation, Static
from solvers.static import _unknowns, finite_difference_tangent
from tests.shell_helpers import stiffness_and_mass


def fibrous_strip(tension=1200.0, cells=10):
    mesh = Mesh.rectangle(100.0, 10.0, nx=cells, ny=1)
    fabric = Fabric(
        thickness=6.0,
        areal_density=5.7e-9,
        tension=tension,
        shear=ShearLaw.linear(4.0),
        bending=BendingLaw.linear(7.5),
    )
    model = Model(mesh)
    model.add(FibrousShell(fabric, clamped="left"))
    model.fix("left")
    model.gravity((0.0, 0.0, -9810.0))
    return mesh, model


def test_coloured_tangent_equals_the_dense_jacobian():
    mesh, model = fibrous_strip(cells=6)
    compiled = model.compile()
    state = compiled.initial_state()
    rng = np.random.default_rng(3)
    state.positions = state.positions + rng.normal(scale=0.3, size=state.positions.shape)
    sparse = finite_difference_tangent(compiled, state).toarray()
    free = _unknowns(compiled).ravel()
    dense, _ = stiffness_and_mass(compiled, state, step=1e-6 * compiled.element_size)
    assert np.abs(sparse[np.ix_(free, free)] - dense).max() <= 1e-6 * np.abs(dense).max()


def test_static_and_dynamic_relaxation_agree_on_the_fibrous_cantilever():
    mesh, model = fibrous_strip(tension=120.0)
    static = Static(increments=2).solve(model)
    relaxed = DynamicRelaxation(tol=1e-6, max_iterations=100_000).solve(model)
    tip = mesh.nodes("right")
    assert static.positions[tip] == pytest.approx(relaxed.positions[tip], rel=1e-3, abs=1e-2)
    assert static.info["iterations_per_increment"][-1] < 30


def test_static_and_dynamic_relaxation_agree_on_a_sagging_cable():
    mesh = Mesh.line((0.0, 0.0, 0.0), (100.0, 0.0, 0.0), 30)
    model = Model(mesh)
    model.add(Cable(axial_stiffness=5.0e3, mass_per_length=1.0e-6))
    model.fix("start")
    model.displace("end", ux=-20.0, uy=0.0, uz=0.0)
    model.gravity((0.0, 0.0, -9810.0))
    static = Static(increments=8).solve(model)
    relaxed = DynamicRelaxation(increments=8, tol=1e-7).solve(model)
    assert static.positions == pytest.approx(relaxed.positions, rel=1e-3, abs=1e-3)


def test_cantilever_rolls_up_into_a_circle_under_an_end_moment():
    # Closed form: an end moment M bends an inextensible strip into an arc of radius EI / M.
    length, width, thickness, young = 100.0, 10.0, 1.0, 1e5
    mesh = Mesh.rectangle(length, width, nx=20, ny=1)
    model = Model(mesh)
    model.add(MindlinShell(ElasticShell(young, 0.0, thickness, 1e-9)))
    model.fix("left")
    bending = young * width * thickness**3 / 12
    moment = 0.25 * 2 * np.pi * bending / length  # a quarter circle
    tip = mesh.nodes("right")
    model.moment(tip, (0.0, -moment / len(tip), 0.0), amplitude="linear")
    result = Static(increments=4).solve(model)
    radius = bending / moment
    x, _, z = result.positions[tip].mean(axis=0)
    assert x == pytest.approx(radius, rel=0.01)
    assert z == pytest.approx(radius, rel=0.01)


def test_an_unsupported_structure_reports_a_singular_tangent():
    mesh = Mesh.line((0.0, 0.0, 0.0), (10.0, 0.0, 0.0), 2)
    model = Model(mesh)
    model.add(Cable(axial_stiffness=1.0, mass_per_length=1e-6))
    model.force("end", (1.0, 0.0, 0.0))
    with pytest.raises(ConvergenceError, match="singular|load factor"):
        Static(increments=1, max_cuts=1).solve(model)


def test_bad_options_are_refused():
    with pytest.raises(ValueError, match="tol"):
        Static(tol=2.0)
    with pytest.raises(ValueError, match="increments"):
        Static(increments=0)
