"""A symmetry plane held with ``tilt`` holds the director's turn out of the plane at every node,
whatever way the model faces (femcore/frame_branches.py onto_symmetry_planes, docs/theory.md
§1.2).

The pinched hemisphere of MacNeal and Harder (Finite Elem. Anal. Des. 1 (1985) 3: R = 10,
h = 0.04, E = 6.825e7, nu = 0.3, an 18 deg hole at the pole, unit loads in and out at the
equator 90 deg apart), one quadrant with the planes
x = 0 and y = 0 held by tilt. Its two loaded points are equivalent by symmetry, and the same
quadrant turned 90 deg about z is the same model. The nodes of a plane average only their own
side's facet normals, so their directors sat half a facet angle off the plane (2.8 deg at 16
cells); on x = 0 near the equator, close to e2, Eq. 7's V1 = e2 x V / |e2 x V| swung with that
small x-part, and the DOF tilt held there mixed the meridional turn into the out-of-plane one:
the 16-cell point on x = 0 deflected 0.04553 per newton where the one on y = 0 gave 0.05575,
turned or not, and the 8-cell quadrant was refused outright.
"""

import warnings

import numpy as np
import pytest

from elements import MindlinShell
from femcore import Mesh, Model
from femcore.entry_error import EntryError
from femcore.frame_branches import tilt_columns
from femcore.loads import Fix
from materials import ElasticShell
from solvers import Static

RADIUS, LOAD = 10.0, 0.01  # a hundredth of the unit load: the linear range the reference reads
# The radial displacement under each load of the hemisphere with the 18 deg hole, the geometry
# run here (latitudes 0 to 72 deg). MacNeal and Harder (1985, Finite Elements in Analysis and
# Design 1, 3-20) tabulate 0.094; later converged solutions of this open hemisphere are taken
# as 0.093 (FinEtoolsFlexStructures' open hemisphere example, where the Abaqus eight-node
# curved shell it quotes extrapolates to 0.0936); 0.0924 is quoted for the closed one. The
# tolerances below hold against 0.093; 0.094 is within the 8-cell bound as well.
REFERENCE = 0.093


def quadrant(
    cells: int, turned: bool, named: bool = False
) -> tuple[Model, int, int, np.ndarray, np.ndarray]:
    """The quadrant (alternating diagonals), turned 90 deg about z or not, with the load out
    at A and in at B: the equator's points on the planes y = 0 and x = 0 unturned, on x = 0
    and y = 0 turned; ``named``: the planes held by naming the DOFs (uy and beta on y = 0, ux
    and alpha on x = 0) instead of by tilt. Returns the model, A, B and the two loads' unit
    directions."""
    flat = Mesh.rectangle(np.pi / 2, np.radians(72.0), nx=cells, ny=cells, diagonals="alternating")
    theta = flat.points[:, 0] + (np.pi / 2 if turned else 0.0)
    latitude = flat.points[:, 1]
    points = RADIUS * np.column_stack(
        [np.cos(latitude) * np.cos(theta), np.cos(latitude) * np.sin(theta), np.sin(latitude)]
    )
    model = Model(flat.with_points(points))
    model.add(MindlinShell(ElasticShell(E=6.825e7, nu=0.3, thickness=0.04, density=1e-9)))
    if named:
        model.fix(lambda x, y, z: np.abs(y) < 1e-9, ["uy", "beta"])
        model.fix(lambda x, y, z: np.abs(x) < 1e-9, ["ux", "alpha"])
    else:
        model.fix(lambda x, y, z: np.abs(y) < 1e-9, ["uy"], tilt="y")
        model.fix(lambda x, y, z: np.abs(x) < 1e-9, ["ux"], tilt="x")
    out = np.array([0.0, 1.0, 0.0]) if turned else np.array([1.0, 0.0, 0.0])
    inward = np.array([-1.0, 0.0, 0.0]) if turned else np.array([0.0, 1.0, 0.0])
    a = int(np.argmin(np.linalg.norm(points - RADIUS * out, axis=1)))
    b = int(np.argmin(np.linalg.norm(points - RADIUS * inward, axis=1)))
    model.fix([a], ["uz"])  # the rigid drift along z
    model.force([a], LOAD * out)
    model.force([b], -LOAD * inward)
    return model, a, b, out, inward


def displacements(cells: int, turned: bool) -> tuple[float, float]:
    """The radial displacements per newton under the two loads: out at A, in at B."""
    model, a, b, out, inward = quadrant(cells, turned)
    result = Static(increments=1).solve(model)
    assert result.converged
    moved = result.positions - model.mesh.points
    return float(moved[a] @ out) / LOAD, -float(moved[b] @ inward) / LOAD


def test_a_tilt_plane_s_reference_directors_lie_in_it():
    model, *_ = quadrant(8, turned=False)
    compiled = model.compile()
    directors = compiled.reference_directors
    on_x, on_y = (
        model.mesh.nodes(lambda x, y, z: np.abs(x) < 1e-9),
        model.mesh.nodes(lambda x, y, z: np.abs(y) < 1e-9),
    )
    assert np.all(directors[on_x, 0] == 0.0) and np.all(directors[on_y, 1] == 0.0)
    assert np.allclose(np.linalg.norm(directors, axis=1), 1.0, atol=1e-12)
    # the held DOF turns the director straight out of the plane: alpha towards V1 = +-e1 on
    # x = 0, beta towards -V2 = -+e2 on y = 0 (docs/theory.md §1.2)
    held = compiled.dofs.fixed
    assert held[on_x, 3].all() and not held[on_x, 4].any()
    assert held[on_y, 4].all() and not held[on_y, 3].any()


def test_the_quadrant_turned_about_z_deflects_as_the_quadrant_unturned():
    # The same triangles turned: equal to the Newton solves' tolerance (1e-6 relative; the
    # off-plane directors gave 18 % between the two points at 16 cells)
    a, b = displacements(8, turned=False)
    a_turned, b_turned = displacements(8, turned=True)
    assert a_turned == pytest.approx(a, rel=1e-6) and b_turned == pytest.approx(b, rel=1e-6)
    # the two points are equivalent by symmetry but for the alternating diagonals, which
    # lie the other way under the one load than under the other: measured 1.4e-4 apart
    assert b == pytest.approx(a, rel=1e-3)
    # 8 cells over 90 deg, each 11 deg: 8 % under the open hemisphere's 0.093
    assert a == pytest.approx(REFERENCE, rel=0.10)


def test_the_quadrant_converges_on_the_reference_as_the_mesh_is_refined():
    # the 3-node shell converges in h^2 here: the error to 0.093 falls about fourfold per
    # halving (measured 8.1 % and 2.3 %); it must fall by at least 3 and end within 3 %
    coarse = displacements(8, turned=False)
    fine = displacements(16, turned=False)
    for c, f in zip(coarse, fine):
        assert abs(f - REFERENCE) < abs(c - REFERENCE) / 3.0
        assert f == pytest.approx(REFERENCE, rel=0.03)


def test_the_tilt_refusal_names_the_frame_not_a_director_far_from_the_plane():
    # the review's director on x = 0 half a facet off the plane (5.6 deg) near e2, given to
    # the pick directly (Model.compile lays it into the plane first)
    director = np.array([[0.0977, 0.9921, 0.0781]])
    director /= np.linalg.norm(director)
    active = np.ones((1, 5), dtype=bool)
    with pytest.raises(EntryError) as refused:
        tilt_columns(Fix(np.array([0]), None, 0), 0, active, director)
    message = str(refused.value)
    assert "5.6 deg off the plane" in message and "V1 = e2 x V" in message
    assert "more than 30 deg from the plane" not in message


def test_a_symmetry_plane_named_by_dofs_where_alpha_holds_another_turn_warns_towards_tilt():
    # ux and alpha on x = 0 without tilt: the directors stay one-sided, and at the nodes near
    # e2 alpha turns the director 51 deg (8 cells) from the turn out of the plane; the two
    # loaded points read 0.0263 and 0.0135 per newton there (reported, not asserted: the
    # warning is the specification)
    model, *_ = quadrant(8, turned=False, named=True)
    with pytest.warns(UserWarning, match=r"at nodes \[8, 17, 26, 35\] alpha turns") as said:
        model.compile()
    assert any("tilt='x'" in str(w.message) for w in said)


def test_a_named_plane_whose_held_dof_is_the_turn_out_of_it_does_not_warn():
    # the plane y = 0 of the same quadrant: beta turns towards -V2 = -+e2 whatever the
    # director's small y-part
    model, *_ = quadrant(8, turned=False, named=True)
    del model.fixes[1]  # the plane x = 0 (the fixes: y = 0, x = 0, uz at A)
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        model.compile()
    assert not [w for w in said if "as a symmetry plane" in str(w.message)]


def cylindrical_panel(edge_deg: float = 20.0) -> tuple[Model, float]:
    """A cylindrical panel (axis y, R = 100 mm, from the crown x = 0 to ``edge_deg``), 8 x 4
    cells alternating: its crown x = 0 is a symmetry plane of the whole cylinder, its straight
    edge at ``edge_deg`` is not (the surface crosses the plane x = R sin(edge) at that angle)."""
    radius = 100.0
    flat = Mesh.rectangle(np.radians(edge_deg), 50.0, nx=8, ny=4, diagonals="alternating")
    theta, y = flat.points[:, 0], flat.points[:, 1]
    points = np.column_stack([radius * np.sin(theta), y, radius * np.cos(theta)])
    model = Model(flat.with_points(points))
    model.add(MindlinShell(ElasticShell(E=70000.0, nu=0.3, thickness=1.0, density=1e-9)))
    return model, radius * np.sin(np.radians(edge_deg))


def test_a_tilt_on_an_edge_that_crosses_its_plane_at_an_angle_is_refused():
    # The edge's directors lie 18.75 deg from the plane x = const (the surface crosses it at
    # 20 deg; the nodal normals average the edge cells) where the surface folds by 1.25 deg
    # from one facet to the next: not a symmetry plane. Laying its directors into the plane
    # turned them 18.75 deg, silently (a review).
    model, edge = cylindrical_panel()
    model.fix(lambda x, y, z: np.abs(x - edge) < 1e-7, ["ux"], tilt="x")
    with pytest.raises(EntryError, match="not one of its symmetry planes"):
        model.compile()


def test_an_edge_support_named_by_its_dofs_is_not_taken_for_a_symmetry_plane():
    # The same edge held by ux, uz and alpha (an ordinary support) and the crown by ux and
    # alpha (a symmetry plane whose alpha is the turn out of it): no advice to declare the
    # edge with tilt=, which would turn its directors (a review).
    model, edge = cylindrical_panel()
    model.fix(lambda x, y, z: np.abs(x - edge) < 1e-7, ["ux", "alpha"])
    model.fix(lambda x, y, z: np.abs(x - edge) < 1e-7, ["uz"])
    model.fix(lambda x, y, z: np.abs(x) < 1e-9, ["ux", "alpha"])
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        model.compile()
    assert not [w for w in said if "tilt=" in str(w.message)]


def test_a_flat_plane_held_by_the_wrong_rotation_is_named_so_not_blamed_on_the_directors():
    # A flat strip's directors are e3 exactly on the plane x = 50: beta turns them about x,
    # within the plane, and leaves the turn out of it (alpha) free: the half sags twice the
    # whole's. Before, the warning said the directors "lie a little off the plane".
    mesh = Mesh.rectangle(50.0, 10.0, nx=4, ny=1)
    model = Model(mesh)
    model.add(MindlinShell(ElasticShell(E=70000.0, nu=0.3, thickness=1.0, density=1e-9)))
    model.fix("left")
    model.fix("right", ["ux", "beta"])
    with pytest.warns(UserWarning, match="as a symmetry plane") as said:
        model.compile()
    message = next(str(w.message) for w in said if "as a symmetry plane" in str(w.message))
    assert "beta turns their directors within the plane" in message
    assert "the wrong rotation is held (alpha turns them out of it)" in message
    assert "a little off" not in message and "tilt='x'" in message
