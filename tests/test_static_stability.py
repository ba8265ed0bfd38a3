"""Static's stability verdict (docs/theory.md §6.5, "The stability of a converged state"): the
negative-eigenvalue count of a converged state is its own tangent's, and ``seek_stable`` leaves a
saddle for the branch below it. The reference is Euler's column clamped at one end: the buckling
load P_cr = pi^2 EI / (4 L^2) and the post-buckled elastica (Timoshenko & Gere, Theory of
Elastic Stability, §2.7; validation.references.elastica.euler_cantilever).

The strip: MindlinShell 100 x 5 x 1 mm, E = 1e5 N/mm^2, nu = 0, 20 x 1 cells, clamped at
x = 0 (EI = 4.17e4 N mm^2, P_cr = 10.28 N). Its discrete buckling load lies within 0.2 % of
P_cr (the lowest eigenvalue of the straight strip's tangent is +1.3e-3 at 0.9 P_cr and -2.5e-3
at 1.2 P_cr, zero near 0.999 P_cr).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from elements import MindlinShell
from femcore import Mesh, Model
from materials import ElasticShell
from solvers import ConvergenceError, Static
from validation.references.elastica import euler_cantilever

LENGTH, WIDTH, E = 100.0, 5.0, 1.0e5
BENDING = E * WIDTH / 12.0  # EI, N mm^2 (h = 1 mm)
CRITICAL = np.pi**2 * BENDING / (4.0 * LENGTH**2)


def strip(nx: int = 20) -> tuple[Model, np.ndarray]:
    """(the clamped strip's model, its tip nodes)."""
    mesh = Mesh.rectangle(LENGTH, WIDTH, nx=nx, ny=1)
    model = Model(mesh)
    model.add(MindlinShell(ElasticShell(E=E, nu=0.0, thickness=1.0, density=1e-9)))
    model.fix("left")
    return model, mesh.nodes("right")


def pushed(ratio: float, side: float = 0.0) -> tuple[Model, np.ndarray]:
    """The strip under a dead end load ``ratio`` P_cr along -x, with ``side`` P_cr along z."""
    model, tip = strip()
    load = (-ratio * CRITICAL / len(tip), 0.0, side * CRITICAL / len(tip))
    model.force(tip, load, amplitude="linear")
    return model, tip


@pytest.mark.parametrize("increments", [1, 4])
def test_the_count_of_negative_eigenvalues_is_the_converged_states_own(increments):
    # 1.2 P_cr in 1 or 4 increments (0.3 .. 1.2 P_cr): the strip stays straight, and every
    # state past P_cr has one negative eigenvalue. Newton reaches each straight state in one
    # update from the increment's start, whose tangent (0.9 P_cr at most) has none: the count
    # of the tangent factorised on the way read 0 at every increment.
    model, _ = pushed(1.2)
    result = Static(increments=increments, seek_stable=False, progress=False).solve(model)
    levels = 1.2 * np.asarray(result.info["load_factors"][-increments:])
    assert result.info["negative_eigenvalues"] == [int(level > 1.0) for level in levels]
    assert result.info["evaluations"]["stability_tangents"] >= 1


@pytest.mark.parametrize("ratio", [1.5, 3.0])
def test_the_default_static_leaves_the_straight_saddle_for_the_elastica(ratio):
    # The perfect strip under 1.5 or 3 P_cr in 4 dead-load increments: the straight state
    # past P_cr is a saddle (lowest eigenvalue -0.0065 at 1.5 P_cr). A straight push along the
    # mode by half an element (2.5 mm) stretches the strip and gains 6.3 N mm; the energy falls
    # only within about 0.3 mm, so the push was no descent, the saddle was kept
    # (info["saddles_kept"]) and Static returned the straight strip as converged. The push
    # relaxed with the mode's amplitude held is a descent, and Newton from it finds the
    # post-buckled branch (either side). 20 cells: within 0.2 % of the elastica's lateral
    # tip (78.94 / 70.62 against 78.86 / 70.74 mm), the end within 0.5 mm along the load
    # (36.12 / -20.87 against 36.36 / -20.41 mm).
    model, tip = pushed(ratio)
    result = Static(increments=4, progress=False).solve(model)
    elastica = euler_cantilever(LENGTH, BENDING, load=ratio * CRITICAL)
    end = result.positions[tip].mean(axis=0)
    assert abs(end[2]) == pytest.approx(elastica["tip_lateral"], rel=2e-3)
    assert end[0] == pytest.approx(elastica["tip_axial"], abs=0.5)
    assert result.info["saddles_kept"] == []
    assert result.info["branch_switches"]
    assert result.info["negative_eigenvalues"][-1] == 0


def test_the_arc_length_leaves_the_straight_saddle_for_the_elastica_too():
    # The perfect strip under 1.5 P_cr along the arc length (5 increments): it switches to
    # the post-buckled branch at the saddle past P_cr and then follows that softer branch to
    # the end, its steps no longer held to the first, stiff step's length (solvers/
    # arc_step.py): the straight strip was returned as converged, then (the push finding the
    # descent, the steps still capped) the run crawled in steps of about 1e-3 mm and stopped.
    # The same bounds as the load path's (the discretisation at 20 cells).
    model, tip = pushed(1.5)
    result = Static(increments=5, path="arc_length", progress=False).solve(model)
    elastica = euler_cantilever(LENGTH, BENDING, load=1.5 * CRITICAL)
    end = result.positions[tip].mean(axis=0)
    assert abs(end[2]) == pytest.approx(elastica["tip_lateral"], rel=2e-3)
    assert end[0] == pytest.approx(elastica["tip_axial"], abs=0.5)
    assert result.info["branch_switches"]
    assert result.info["negative_eigenvalues"][-1] == 0


def test_a_side_imperfection_follows_the_same_elastica_without_a_push():
    # 1e-4 P_cr sideways: no saddle on the way, the same branch as the pushed perfect strip.
    model, tip = pushed(1.5, side=1e-4)
    result = Static(increments=4, progress=False).solve(model)
    elastica = euler_cantilever(LENGTH, BENDING, load=1.5 * CRITICAL)
    assert result.positions[tip, 2].mean() == pytest.approx(elastica["tip_lateral"], rel=2e-3)
    assert result.info["branch_switches"] == []


def test_a_cell_whose_directors_all_point_against_its_normal_is_inside_out():
    # The flat strip's directors are its normals (+z): a cell is inside out when every one of
    # its corners' directors is reversed; a cell with one or two reversed is a fold (a coarse
    # blank's flange folded over under Static), not refused.
    model, _ = strip()
    compiled = model.compile()
    state = compiled.initial_state()
    assert compiled.inverted_cells(state).size == 0
    triangles = compiled.mesh.triangles
    directors = state.directors.copy()
    directors[[5]] *= -1.0
    folded = compiled.inverted_cells(replace(state, directors=directors))
    assert folded.size == 0  # one corner reversed in each cell around node 5
    directors = -state.directors  # every director reversed: every cell mirrored
    flipped = compiled.inverted_cells(replace(state, directors=directors))
    np.testing.assert_array_equal(flipped, np.arange(len(triangles)))
    cell = 7
    directors = state.directors.copy()
    directors[triangles[cell]] *= -1.0  # one cell's three corners: that cell is mirrored,
    flipped = compiled.inverted_cells(replace(state, directors=directors))
    np.testing.assert_array_equal(flipped, [cell])  # its neighbours (one or two) are folds


def test_an_increment_that_converges_inside_out_is_refused_naming_the_cells():
    # The strip's end moved 20 mm towards the clamp (tip free sideways) in one increment:
    # Newton from the push off the straight saddle converges with 21 of the 40 cells turned
    # inside out (their directors 180 deg from their normals), a mirror image whose membrane
    # metric, and so its Saint Venant-Kirchhoff strain, is that of the unmirrored cell.
    model, tip = strip()
    model.displace(tip, ux=-20.0)
    with pytest.raises(ConvergenceError, match="turned inside out .*: cells [0-9]"):
        Static(increments=1, max_cuts=0, progress=False).solve(model)


@pytest.mark.parametrize("increments", [1, 10])
def test_the_shortened_strip_buckles_to_the_elastica_with_no_cell_inside_out(increments):
    # The same end shortening of 20 mm: the elastica's end lies 53.26 mm off the axis
    # (Timoshenko & Gere §2.7). In 10 increments Static returned a strip whose cells 10-13
    # ran backwards (tip 36.86 mm, strain energy 129 N mm); in 1 increment the straight strip
    # (40 negative eigenvalues, reported 0). Now the inside-out state is cut back and the
    # straight one left: 53.28 mm at 20 cells (0.03 %).
    model, tip = strip()
    model.displace(tip, ux=-20.0)
    result = Static(increments=increments, progress=False).solve(model)
    elastica = euler_cantilever(LENGTH, BENDING, shortening=20.0)
    assert abs(result.positions[tip, 2].mean()) == pytest.approx(elastica["tip_lateral"], rel=2e-3)
    compiled = model.compile()
    final = replace(
        compiled.initial_state(), positions=result.positions, directors=result.directors
    )
    assert compiled.inverted_cells(final).size == 0
    assert result.info["negative_eigenvalues"][-1] == 0
