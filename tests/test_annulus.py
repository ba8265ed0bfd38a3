"""elements.annulus.RigidAnnulus, a flat ring (a blank holder's face with a bore): over its
face the plane's signed distance, over the bore the distance to the inner edge's circle (closed
forms), continuous across the edge, and bad input refused."""

import math

import numpy as np
import pytest

from elements.annulus import RigidAnnulus


def test_over_the_face_the_distance_is_the_planes_and_over_the_bore_the_edges():
    """A ring at z = 0.3 facing down (-z), bore 60 mm. At radius 70 (face): d = 0.3 - z, n = -z.
    At radius 57, z = -3.7 (bore): the edge circle's nearest point is (60, 0, 0.3), d =
    hypot(3, 4) = 5, n = (-3, 0, -4) / 5 (closed form, to round-off)."""
    ring = RigidAnnulus((0.0, 0.0, 0.3), (0.0, 0.0, -1.0), 60.0)
    x = np.array([[70.0, 0.0, 0.1], [0.0, -70.0, 0.5], [57.0, 0.0, -3.7], [0.0, 57.0, -3.7]])
    d, n = ring.distance(x)
    assert d == pytest.approx([0.2, -0.2, 5.0, 5.0], abs=1e-12)
    assert np.allclose(n[:2], [0.0, 0.0, -1.0], atol=1e-15)
    assert np.allclose(n[2], [-0.6, 0.0, -0.8], atol=1e-15)
    assert np.allclose(n[3], [0.0, -0.6, -0.8], atol=1e-15)


def test_the_distance_is_continuous_across_the_inner_edge_on_the_bodys_side():
    """A point under the face (z below the ring) crossing the edge radius: d changes by less
    than the radial step (the edge's distance is hypot(step, height) there)."""
    ring = RigidAnnulus((0.0, 0.0, 0.3), (0.0, 0.0, -1.0), 60.0)
    step = 1e-6
    x = np.array([[60.0 + step, 0.0, 0.15], [60.0 - step, 0.0, 0.15]])
    d, _ = ring.distance(x)
    assert abs(d[0] - d[1]) < 2.0 * step
    assert d[0] == pytest.approx(0.15, abs=1e-12)


def test_a_moved_ring_measures_from_where_it_is():
    """Translated by (0, 0, 2) at the end of a linear motion: the face 2 mm higher at tau 1."""
    ring = RigidAnnulus((0.0, 0.0, 0.0), (0.0, 0.0, -1.0), 10.0, motion=(0.0, 0.0, 2.0))
    d, _ = ring.distance(np.array([[20.0, 0.0, 0.0]]), 1.0)
    assert d[0] == pytest.approx(2.0, abs=1e-12)


def test_the_projector_scale_is_zero_on_the_face_and_one_over_the_edge_distance_in_the_bore():
    ring = RigidAnnulus((0.0, 0.0, 0.0), (0.0, 0.0, -1.0), 60.0)
    scale = ring.projector_scale(np.array([[65.0, 0.0, -1.0], [57.0, 0.0, -4.0]]))
    assert scale == pytest.approx([0.0, 0.2], abs=1e-15)


@pytest.mark.parametrize("inner", [0.0, -1.0, math.inf, math.nan])
def test_a_ring_without_a_positive_finite_bore_is_refused(inner):
    with pytest.raises(ValueError, match="inner"):
        RigidAnnulus((0.0, 0.0, 0.0), (0.0, 0.0, -1.0), inner)


# The ring as the face of a solid: the half-space behind the face less the bore, a cylinder of
# radius ``inner`` about the axis (elements/annulus.py). A die's flange facing up (+z), bore 11.
DIE = RigidAnnulus((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), 11.0)


def test_behind_the_face_the_distance_is_continuous_across_the_bores_wall():
    """A blank drawn through a die's opening goes behind the flange's plane. A point 0.5 mm
    behind it crossing the bore's radius: d goes through zero (the wall) by the radial step,
    not from +0.5 to -0.5 (the far side of the flange, which threw a node |z| + h/2 deep)."""
    step = 1e-6
    d, n = DIE.distance(np.array([[11.0 - step, 0.0, -0.5], [11.0 + step, 0.0, -0.5]]))
    assert d == pytest.approx([step, -step], abs=1e-12)
    assert np.allclose(n, [-1.0, 0.0, 0.0], atol=1e-15)  # the wall's normal, towards the axis


def test_in_the_bore_behind_the_face_the_distance_is_to_the_wall():
    """At radius 7 in the (3, 4) direction, 2 mm behind the face: d = 11 - 7 = 4, n = -(0.6,
    0.8, 0) (the cylinder's inner normal, closed form)."""
    d, n = DIE.distance(np.array([[4.2, 5.6, -2.0]]))
    assert d[0] == pytest.approx(4.0, abs=1e-12)
    assert np.allclose(n[0], [-0.6, -0.8, 0.0], atol=1e-15)


def test_inside_the_solid_the_distance_is_to_the_nearer_of_face_and_wall():
    """At radius 11.3, 0.5 mm behind the face: the wall is 0.3 away, the face 0.5: d = -0.3
    along the wall's normal; at radius 12, 0.5 behind: the face, d = -0.5, n = +z."""
    d, n = DIE.distance(np.array([[11.3, 0.0, -0.5], [0.0, 12.0, -0.5]]))
    assert d == pytest.approx([-0.3, -0.5], abs=1e-12)
    assert np.allclose(n, [[-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]], atol=1e-15)


def test_a_point_on_the_axis_is_as_far_as_the_edge_circle():
    """On the axis 0.15 mm in front of the bore the nearest solid is the edge circle all round:
    d = hypot(11, 0.15), as 1e-9 mm off the axis (a quarter model's pole lies on it); the
    axis had a phantom floor, d = 0.15. Behind the face, d = 11, the wall's distance."""
    d, n = DIE.distance(np.array([[0.0, 0.0, 0.15], [1e-9, 0.0, 0.15], [0.0, 0.0, -3.0]]))
    assert d == pytest.approx([math.hypot(11.0, 0.15), math.hypot(11.0, 0.15), 11.0], abs=1e-9)
    assert np.linalg.norm(n, axis=1) == pytest.approx(1.0, abs=1e-15)
    assert n[0, 2] == pytest.approx(0.15 / math.hypot(11.0, 0.15), abs=1e-15)


@pytest.mark.parametrize(
    "point",
    [
        (15.0, 2.0, 0.7),
        (6.0, -3.0, -1.5),
        (8.0, 8.0, -0.2),
        (12.0, 0.5, -3.0),
        (10.8, 0.0, 0.2),
        (6.0, 7.0, 2.5),
    ],
    ids=["face", "wall", "inside-near-wall", "inside-near-face", "edge-near", "edge-far"],
)
def test_the_normals_gradient_is_its_derivative(point):
    """dn/dx (``normal_gradient``) against central differences of n (step 1e-6 mm, error
    about step^2 / radius^3, under 1e-8) where n is smooth: the face, the bore's wall (a
    concave cylinder: -(I - n n - a a) / radius), inside the solid by either part, and in
    front of the bore, where the edge circle's nearest point turns with the point (the edge
    taken as a point before, (I - n n) / d: off by 3.6 per mm at d = 0.28 mm)."""
    x = np.array([point])
    _, n = DIE.distance(x)
    gradient = DIE.normal_gradient(x, n)[0]
    step = 1e-6
    numeric = np.empty((3, 3))
    for j in range(3):
        dx = np.zeros((1, 3))
        dx[0, j] = step
        numeric[:, j] = (DIE.distance(x + dx)[1][0] - DIE.distance(x - dx)[1][0]) / (2 * step)
    assert np.allclose(gradient, numeric, atol=1e-8)


def test_the_compiled_pass_gives_the_rings_distance_in_every_region():
    """elements/tool_contact.py's ``annulus_forces`` (the frictionless contact's compiled pass)
    gives k max(offset - d, 0) n with RigidAnnulus.distance's d and n to round-off, at points
    in front of the face and the bore, on the axis, behind the face in the bore and inside
    the solid."""
    from elements.tool_contact import annulus_forces

    rng = np.random.default_rng(7)
    x = np.column_stack(
        [rng.uniform(-16.0, 16.0, 400), rng.uniform(-16.0, 16.0, 400), rng.uniform(-3, 1, 400)]
    )
    x[:2] = [[0.0, 0.0, 0.1], [0.0, 0.0, -1.0]]
    offset = np.full(len(x), 20.0)  # every point pressed: d < 20 everywhere here
    stiffness = np.full(len(x), 3.0)
    forces = np.empty((len(x), 3))
    annulus_forces(
        x, DIE.point, DIE.normal, DIE.radial_on_axis, DIE.inner, offset, stiffness, forces
    )
    d, n = DIE.distance(x)
    assert np.allclose(forces, (stiffness * (offset - d))[:, None] * n, rtol=1e-13, atol=1e-12)


QUARTER_DRAW = """
title = "a quarter of a ply drawn into a ring die"
[mesh]
rectangle = { lx = 30.0, ly = 30.0, nx = 4, ny = 4, origin = [0.0, 0.0, 0.15] }
[sets]
pole = { x_max = "0%", y_max = "0%" }
[[part]]
element = "fibrous"
options = { symmetric = ["left", "bottom"] }
[part.material]
thickness = 0.3
areal_density = 2.85e-10
tension = 60.0
shear = 0.2
bending = 0.375
[[fix]]
nodes = "left"
dofs = ["ux", "alpha"]
[[fix]]
nodes = "bottom"
dofs = ["uy", "beta"]
[[contact]]
tool = "annulus"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
inner = 11.0
[[contact]]
tool = "sphere"
centre = [0.0, 0.0, 10.3]
radius = 10.0
motion = [0.0, 0.0, -4.0]
amplitude = "smooth"
[solver]
kind = "explicit"
duration = 0.08
damping = 20.0
[output]
history = { displacements = ["pole"] }
"""


def test_a_quarter_models_pole_on_the_rings_axis_follows_the_punch(tmp_path):
    """A quarter of a ply (symmetry planes x = 0 and y = 0) drawn 4 mm by a sphere into a ring
    die: the pole, on the ring's axis, is carried down with the punch's travel (4 mm, less the
    contact springs' give, under 0.1 mm) to the end of the stroke. The axis's phantom floor
    held it on the flange's plane (0.98 N of die force), and the run stopped at a sixth of
    its stroke on the energy check."""
    import tomllib

    from fibreshell import run_case
    from fibreshell.case import case_from_data

    case = case_from_data(tomllib.loads(QUARTER_DRAW), tmp_path / "quarter.toml")
    run = run_case(case, tmp_path / "out", progress=False, write_frames=False)
    assert run.status == "done", run.error
    assert run.summary["mean_displacements"]["pole"][2] == pytest.approx(-4.0, abs=0.1)
