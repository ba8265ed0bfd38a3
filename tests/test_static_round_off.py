"""Static converges where the answer carries almost no force: its force reference never falls
below the rounding of the internal forces (solvers.force_floor, docs/theory.md §6.4).

Before the floor, a rigid rotation prescribed on every node of a Mindlin plate stopped at load
factor 0.999 ("8 cuts"), and a cantilever under a tip force of 1e-10 N did not converge
(residual ratio 0.345 after 50 iterations): both judged round-off against round-off.
"""

import numpy as np
import pytest

from elements import MindlinShell
from femcore import Mesh, Model
from materials import ElasticShell
from solvers import Static

EPS = float(np.finfo(float).eps)


def rotation(angle: float, axis) -> np.ndarray:
    """Rodrigues' rotation matrix (3, 3) about the unit ``axis`` by ``angle`` rad."""
    a = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    k = np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])
    return np.eye(3) + np.sin(angle) * k + (1.0 - np.cos(angle)) * (k @ k)


def test_a_prescribed_rigid_rotation_leaves_no_force_and_turns_the_directors_with_it():
    modulus, thickness = 1e3, 1.0  # MPa, mm
    mesh = Mesh.rectangle(40.0, 20.0, nx=4, ny=2)
    turn = rotation(np.radians(60.0), (1.0, 2.0, 3.0))
    moved = mesh.points @ turn.T - mesh.points
    model = Model(mesh)
    model.add(MindlinShell(ElasticShell(E=modulus, nu=0.3, thickness=thickness, density=1e-9)))
    every = np.arange(len(mesh.points))
    model.displace(every, ux=moved[:, 0], uy=moved[:, 1], uz=moved[:, 2])
    result = Static(increments=4).solve(model)
    # Closed form: the rotated plate, its normals R e_z, no stress, so no reaction.
    extent = float(np.abs(mesh.points).max())
    np.testing.assert_allclose(result.positions, mesh.points @ turn.T, rtol=0, atol=1e-12 * extent)
    np.testing.assert_allclose(result.directors, np.tile(turn[:, 2], (len(every), 1)), atol=1e-12)
    # Round-off: coordinates of 45 mm round to eps 45 mm, forces to E t eps 45 mm = 1e-11 N;
    # 1e3 times that allowed (3e-12 N measured).
    allowed = 1e3 * EPS * modulus * thickness * extent
    assert np.abs(result.reactions).max() <= allowed
    assert np.abs(result.reaction_moments).max() <= allowed * extent


def cantilever_tip(force: float, tangent: str = "element") -> float:
    """Mean tip deflection (mm) of a 100 x 10 x 1 mm Mindlin strip, E = 1e4 MPa, clamped at
    x = 0, under a tip ``force`` (N) along -z; Static's ``tangent``."""
    mesh = Mesh.rectangle(100.0, 10.0, nx=20, ny=2)
    model = Model(mesh)
    model.add(MindlinShell(ElasticShell(E=1e4, nu=0.0, thickness=1.0, density=1e-9)))
    model.fix("left")
    tip = mesh.nodes("right")
    model.force(tip, (0.0, 0.0, -force / len(tip)))
    result = Static(increments=1, tangent=tangent).solve(model)
    return float(result.displacements[tip, 2].mean())


def test_a_cantilever_under_a_tip_force_of_1e_10_newton_follows_beam_theory():
    # P L^3 / (3 E I), I = b t^3 / 12: 40 mm per N; the shear flexibility adds (t/L)^2 of it.
    compliance = 100.0**3 / (3.0 * 1e4 * 10.0 / 12.0)
    # Forces whose deflection stays within 1e-4 of the length (linear): the tiny one and two
    # ordinary ones, each within 0.5 % of the closed form (the 20 x 2 MITC3 strip: 0.05 %).
    per_newton = {force: cantilever_tip(force) / force for force in (1e-10, 1e-8, 1e-3)}
    for force, tip in per_newton.items():
        assert tip == pytest.approx(-compliance, rel=5e-3), force
    # Linearity: the tiny load's compliance is the ordinary one's to its round-off (the
    # residual left is about 1e-3 of the floor, F_round = 7e-7 N).
    assert per_newton[1e-10] == pytest.approx(per_newton[1e-3], rel=1e-3)
    assert per_newton[1e-8] == pytest.approx(per_newton[1e-3], rel=1e-6)


def test_the_floor_holds_with_a_finite_difference_tangent_too():
    # The rounding of the forces comes from the element tangents at the start whatever tangent
    # the solve takes (before, with finite differences it was 0 and the 1e-10 N load failed
    # after 8 cuts).
    compliance = 100.0**3 / (3.0 * 1e4 * 10.0 / 12.0)
    tip = cantilever_tip(1e-10, tangent="finite_difference") / 1e-10
    assert tip == pytest.approx(-compliance, rel=5e-3)


def test_a_stop_at_the_rounding_of_the_internal_forces_says_so_and_not_limit_point():
    # MacNeal and Harder's thin twisted beam (Finite Elem. Anal. Des. 1 (1985) 3: L = 12,
    # width 1.1, t = 0.0032, E = 29e6, nu = 0.22, a quarter turn, clamped root), its tip load
    # scaled to 1e-9 (1.1e-10 a tip node): linear, yet a rigid translation changes the internal
    # forces by a quarter of the load at a node (a residual ratio ~1.5e-4 from rounding alone,
    # where the solver takes 1e-7), and Newton stays near 1.7e-3. The stop used to blame a
    # limit point; it must name the rounding, its figures and the remedy. One cut and ten
    # iterations stop it as the default eight cuts and fifty do (the ratio stays near 1.7e-3).
    from solvers import ConvergenceError

    length, width, load = 12.0, 1.1, 1e-9
    flat = Mesh.rectangle(length, width, nx=48, ny=8, origin=(0.0, -width / 2, 0.0))
    x, s = flat.points[:, 0], flat.points[:, 1]
    turn = np.pi / 2 * x / length
    model = Model(flat.with_points(np.column_stack([x, s * np.cos(turn), s * np.sin(turn)])))
    model.add(MindlinShell(ElasticShell(E=29e6, nu=0.22, thickness=0.0032, density=1e-9)))
    model.fix("left")
    tip = flat.nodes("right")
    model.force(tip, (0.0, 0.0, load / len(tip)))
    with pytest.raises(ConvergenceError) as caught:
        Static(increments=1, max_cuts=1, max_iterations=10).solve(model)
    message = str(caught.value)
    assert "the load is at the rounding of the internal forces" in message
    # the largest nodal load the user applied, not the cut increment's (load factor 1/2)
    assert f"the largest nodal load is {load / len(tip):.2g} N" in message
    assert "apply a larger load" in message and "units" in message
    assert "limit point" not in message


@pytest.mark.parametrize("ny", [2, 1], ids=["4x2-cells", "4x1-cells"])
def test_a_stop_on_an_unloaded_mechanism_names_it_not_the_cut_load(ny):
    # A clamped fibrous strip with shear K = 0 (materials.ShearLaw: "K = 0 leaves shear
    # free") under a tip force of 1e-4 N a node: its flat state has no in-plane shear or
    # director tilt stiffness, modes the load does not drive, and Newton's steps along them
    # are round-off over round-off. The stop blamed the rounding of the load after 8 cuts
    # ("the largest nodal load is 3.9e-07 N ... apply a larger load"); it must name the
    # mechanism, and never quote a cut increment's load as the user's. On 4 x 1 cells the
    # free tangent's smallest eigenvalues are 0, 0 and 1e-15 against a diagonal of 100 (by
    # numpy.linalg.eigvalsh), their rounding fell positive, and the stop sent the user to
    # path='arc_length' (which stops on the singular tangent at its start): zero modes of
    # either sign are the same mechanism.
    from elements import FibrousShell
    from materials import Fabric
    from solvers import ConvergenceError

    fabric = Fabric(thickness=0.3, areal_density=2.85e-10, tension=100.0, shear=0.0, bending=0.01)
    mesh = Mesh.rectangle(40.0, 10.0, nx=4, ny=ny)
    model = Model(mesh)
    model.add(FibrousShell(fabric, clamped="left"))
    model.fix("left")
    model.force("right", (0.0, 0.0, -1e-4))
    with pytest.raises(ConvergenceError) as caught:
        Static(increments=1).solve(model)
    message = str(caught.value)
    assert "zero-stiffness modes" in message and "shear K = 0" in message
    assert "apply a larger load" not in message and "limit point" not in message
