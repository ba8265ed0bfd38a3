"""A fibrous clamp carries the moment of the load: the wall its bending term bends against
(docs/theory.md §4.5, "The wall's moment") exerts a moment on the clamped nodes, reported in
``reaction_moments`` beside the DOFs' support moments.

Statics is the reference: at equilibrium the supports' forces and moments balance the load's
moment about any point. Before the wall's moment was gathered, a clamped fibrous cantilever
under a tip load P reported a clamp moment of 0 where the load's is P L, and the G1151 strip
under its weight -1.9e-6 N mm where its weight's is about -66 N mm.
"""

import numpy as np
import pytest

from elements import FibrousShell, MindlinShell
from femcore import Mesh, Model
from materials import Fabric, presets
from solvers import DynamicRelaxation, Static

LENGTH, WIDTH, BENDING = 100.0, 10.0, 10.0  # mm, mm, N mm
# A tip force that sags the strip by about 1 mm (P L^3 / (3 B b) = 1): small deflection.
TIP_FORCE = 3.0 * BENDING * WIDTH / LENGTH**3  # N


def tip_loaded_cantilever(kind: str = "fibrous") -> tuple[Model, np.ndarray]:
    """The 100 x 10 mm strip clamped along x = 0 with P spread over its tip nodes."""
    mesh = Mesh.rectangle(LENGTH, WIDTH, nx=10, ny=1)
    fabric = Fabric(thickness=1.0, areal_density=3e-10, tension=1e5, shear=1.0, bending=BENDING)
    model = Model(mesh)
    shell = FibrousShell(fabric, clamped="left") if kind == "fibrous" else MindlinShell(fabric)
    model.add(shell)
    model.fix("left")
    tip = mesh.nodes("right")
    model.force(tip, (0.0, 0.0, -TIP_FORCE / len(tip)))
    return model, tip


def support_moment(result) -> np.ndarray:
    """The supports' moment about the origin (3,), N mm: their forces' and their moments."""
    return np.cross(result.positions, result.reactions).sum(0) + result.reaction_moments.sum(0)


def load_moment(model: Model, result) -> np.ndarray:
    """The moment of the model's nodal loads at the final positions about the origin (3,)."""
    force, moment = model.compile().external_load(1.0)
    return np.cross(result.positions, force).sum(0) + moment.sum(0)


@pytest.mark.parametrize("solver", ["static", "relaxation"])
def test_the_clamp_of_a_fibrous_cantilever_carries_the_tip_load_moment(solver):
    model, _ = tip_loaded_cantilever()
    if solver == "static":
        result = Static(increments=1).solve(model)
    else:
        result = DynamicRelaxation(increments=1, tol=1e-4).solve(model)
    moment = support_moment(result)
    # Statics: the supports' moment about y is minus the load's, -P L on the reference arm;
    # the sag of about 1 mm shortens the arm by about int w'^2 / 2 = 6e-3 mm, 6e-5 of L.
    assert moment[1] == pytest.approx(-TIP_FORCE * LENGTH, rel=2e-4)
    # And exactly (to the solver's tolerance) minus the load's moment at the sagged arm.
    tol = 1e-7 if solver == "static" else 1e-3
    np.testing.assert_allclose(moment, -load_moment(model, result), atol=tol * TIP_FORCE * LENGTH)


def test_the_wall_moment_sits_on_the_clamped_nodes_about_the_clamped_edge():
    model, _ = tip_loaded_cantilever()
    result = Static(increments=1).solve(model)
    left = model.mesh.nodes("left")
    elsewhere = np.setdiff1d(np.arange(model.mesh.n_nodes), left)
    assert np.all(result.reaction_moments[elsewhere] == 0.0)
    # About the edge (y): each of its two nodes carries half of the edge's -P L (one cell
    # side between them), the directors' support moments about x and z naught here.
    np.testing.assert_allclose(
        result.reaction_moments[left, 1].sum(), -TIP_FORCE * LENGTH, rtol=2e-4
    )


def test_the_fibrous_and_mindlin_clamps_of_the_g1151_strip_balance_its_weight():
    moments = {}
    for kind in ("fibrous", "mindlin"):
        mesh = Mesh.rectangle(200.0, 60.0, nx=8, ny=2)
        model = Model(mesh)
        fabric = presets.g1151_laminate()
        model.add(
            FibrousShell(fabric, clamped="left") if kind == "fibrous" else MindlinShell(fabric)
        )
        model.fix("left")
        model.gravity((0.0, 0.0, -9810.0))
        result = Static(increments=3).solve(model)
        moments[kind] = support_moment(result)
        weight = load_moment(model, result)
        # Statics at the sagged shape: the supports' moment is minus the weight's.
        np.testing.assert_allclose(moments[kind], -weight, atol=1e-7 * abs(weight[1]))
    # The two kinematics sag alike (their tips 0.3 % apart), so their clamp moments agree:
    # measured -65.97 and -66.04 N mm (the weight's 0.816 N at half of 200 mm: 81.6 flat).
    assert moments["fibrous"][1] == pytest.approx(moments["mindlin"][1], rel=5e-3)
