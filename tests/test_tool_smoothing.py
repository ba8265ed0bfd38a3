"""The smoothed gap of a meshed rigid tool (``RigidSurface(smooth=True)``,
elements/tool_smoothing.py): on the concave side of a faceted curved tool the closest-point
normal jumps by the dihedral angle where a node's closest facet changes, and a node pressed
there lies on a kink of the contact force that Static's Newton cannot converge on; the
normal of the Phong surface over the facets turns with the curved tool. References: the
analytic sphere and cylinder the facets approximate (their normals and, for a node pressed
into a trough, the equilibrium on the analytic RigidCylinder), within the facets' chordal
sag."""

import numpy as np
import pytest

from elements import Cable, RigidCylinder, RigidSurface
from elements.contact import Contact, FrictionHistory
from femcore import Body, Mesh, Model
from femcore.state import State
from solvers import ConvergenceError, Static
from tests.test_contact import assert_tangent_is_the_force_derivative
from validation.specimens import hemisphere_die, holder_ring

DIE = 50.6  # mm, the bowl of validation/cases/hemisphere_forming.py, 48 rings of facets


def test_smoothed_normal_turns_with_the_sphere_inside_a_faceted_bowl():
    """Along a path 0.15 mm inside the bowl at 60 deg from its pole, across about six facets:
    the closest-point normal jumps by up to the dihedral angle (measured 1.89 deg) and lies up
    to 1.25 deg off the sphere's; the smoothed one turns by less than 0.01 deg between samples
    1e-4 rad of azimuth apart (the sphere's own turn there: 0.005 deg; measured 0.0053) and
    lies within 0.01 deg of the sphere's radial normal (closed form; measured 7e-4 deg). Both
    gaps lie within the facets' chordal sag w^2 / 8R (w the facet width) of the sphere's
    (the smoothed one measured within 1e-6 mm)."""
    mesh = hemisphere_die(DIE, 170.0, rings=48)
    width = DIE * 0.5 * np.pi / 48
    azimuth = np.linspace(0.3, 0.5, 2001)
    polar, radius = np.radians(60.0), DIE - 0.15
    x = radius * np.column_stack(
        [
            np.sin(polar) * np.cos(azimuth),
            np.sin(polar) * np.sin(azimuth),
            -np.full_like(azimuth, np.cos(polar)),
        ]
    )
    radial = -x / np.linalg.norm(x, axis=1)[:, None]
    for smooth in (False, True):
        d, n = RigidSurface(mesh, smooth=smooth).distance(x)
        jump = np.degrees(np.arccos(np.clip(np.sum(n[1:] * n[:-1], axis=1), -1.0, 1.0))).max()
        off = np.degrees(np.arccos(np.clip(np.sum(n * radial, axis=1), -1.0, 1.0))).max()
        assert np.all(np.abs(d - 0.15) <= 1.5 * width**2 / (8.0 * DIE))
        if smooth:
            assert jump < 0.01 and off < 0.01
        else:
            assert jump > 1.0 and off > 0.5


def test_the_smoothed_normal_holds_a_millimetre_off_the_bowl():
    """Points 0.6 and 1.2 mm inside the bowl (a node the frozen contact set holds off the die
    while Newton iterates), at polar angles 20-80 deg: the projection on the Phong patches
    settles (eight Gauss-Newton steps) and the smoothed normal lies within 0.1 deg of the
    sphere's (closed form; measured median 1.8e-3 deg, at most 0.039 deg where the zipped
    rings make the facets uneven), where the closest-point normal is up to 1.3 deg off. With
    four steps 97 % of the points at 0.6 mm fell back to the closest-point normal."""
    tool = RigidSurface(hemisphere_die(DIE, 55.0, rings=48), smooth=True)
    rng = np.random.default_rng(3)
    polar, azimuth = np.radians(rng.uniform(20.0, 80.0, 300)), rng.uniform(0.0, 6.3, 300)
    for off in (0.6, 1.2):
        x = (DIE - off) * np.column_stack(
            [np.sin(polar) * np.cos(azimuth), np.sin(polar) * np.sin(azimuth), -np.cos(polar)]
        )
        _, n = tool.distance(x)
        radial = -x / np.linalg.norm(x, axis=1)[:, None]
        off_deg = np.degrees(np.arccos(np.clip(np.sum(n * radial, axis=1), -1.0, 1.0)))
        assert off_deg.max() < 0.1


def test_smoothing_leaves_a_flat_tool_as_it_is():
    """A flat holder ring: every vertex normal is the facets' normal, so the smoothed gap and
    normal are the closest-point ones (to round-off), beside the ring's open edges too."""
    ring = holder_ring(52.6, 170.0, 0.5 * np.pi * DIE / 12.0)
    rng = np.random.default_rng(0)
    x = np.column_stack([rng.uniform(-120, 120, (600, 2)), rng.uniform(-1.0, 0.5, 600)])
    d0, n0 = RigidSurface(ring).distance(x)
    d1, n1 = RigidSurface(ring, smooth=True).distance(x)
    assert np.abs(d1 - d0).max() < 1e-12 and np.abs(n1 - n0).max() < 1e-12


RADIUS, FACET_DEG, LOAD, PULL, EA, LENGTH = 20.0, 10.0, 1.0, 0.05, 2.0, 20.0


def trough(tool) -> Model:
    """A node pressed into the bottom of a cylinder (axis y, radius RADIUS, the body inside) by
    a dead load LOAD down and PULL along x, and held along x by a cable of EA from an anchor
    LENGTH away: a plane problem (uy fixed)."""
    points = np.array([[-LENGTH, 0.0, -RADIUS], [0.0, 0.0, -RADIUS]])
    model = Model(Mesh(points, lines=np.array([[0, 1]])))
    model.add(Cable(EA, 1e-9))
    model.fix([0])
    model.fix([1], "uy")
    model.force([1], (PULL, 0.0, -LOAD))
    model.contact(tool, nodes=[1], penalty=1e3)
    return model


def faceted_trough(smooth: bool) -> RigidSurface:
    """The cylinder's bottom from -60 to 60 deg in facets of FACET_DEG, y from -5 to 5 mm,
    the facets' normals towards the axis; a vertex at the bottom (an edge of two facets)."""
    angles = np.radians(np.arange(-60.0, 60.0 + FACET_DEG / 2, FACET_DEG))
    ring = np.column_stack([RADIUS * np.sin(angles), RADIUS * -np.cos(angles)])
    points = np.vstack([np.insert(ring, 1, y, axis=1) for y in (-5.0, 5.0)])
    m = len(angles)
    quads = [(i, i + 1, m + i + 1, m + i) for i in range(m - 1)]
    triangles = np.array([t for a, b, c, d in quads for t in ((a, b, d), (b, c, d))])
    return RigidSurface(Mesh(points, triangles=triangles), smooth=smooth)


def test_static_settles_a_node_in_a_faceted_trough_as_on_the_cylinder():
    """The cable's pull (EA / LENGTH = 0.1 N/mm) is soft beside the change of the contact's
    sideways force from facet to facet (LOAD sin 10 deg = 0.17 N), so on the closest-point
    facets the node's equilibrium is on an edge, where that force jumps: Static stops
    (ConvergenceError, the line search finding no decrease). Smoothed, it converges in at most
    6 Newton iterations per increment (measured 4, 4, 4, 4: the tangent turns the smoothed
    normal with the patch, elements/facet_normal.py; 8, 11, 15, 20 when it left that out), and
    the node lies where it lies on the analytic cylinder (solved the same way) within the
    facets' chordal sag R (1 - cos 5 deg) = 0.076 mm (measured 3.0e-3 mm apart). The stop on
    the closest-point facets names node 1, the two facets of the edge it was carried across
    and back (8 times in the tool's last 16 evaluations) and the smoothed tool, and no hint of a
    limit point."""
    exact = Static(increments=4, progress=False).solve(
        trough(RigidCylinder((0.0, 0.0, 0.0), (0.0, 1.0, 0.0), RADIUS, side="inside"))
    )
    assert exact.converged
    # The stop names the node and the crease it cycles across (solvers/stop_diagnosis.py).
    crease = "node 1 .* crossed the edge between facets 11 and 12 .* 10 deg apart"
    # the remedy worded for a case file's user too (fibreshell/case_tools.py reads it)
    remedy = r"smooth=True\) \(in a case file, smooth = true in the tool's \[\[contact\]\]"
    with pytest.raises(ConvergenceError, match=crease + ".*" + remedy) as stopped:
        Static(increments=4, max_cuts=3, progress=False).solve(trough(faceted_trough(False)))
    # The crease named, the generic hint of a limit point does not follow it (no path to
    # follow, no smaller increment removes a crease's cycle).
    assert "limit point" not in str(stopped.value)
    assert "arc_length" not in str(stopped.value)
    smoothed = Static(increments=4, progress=False).solve(trough(faceted_trough(True)))
    assert smoothed.converged
    assert max(smoothed.info["iterations_per_increment"]) <= 6
    sag = RADIUS * (1.0 - np.cos(np.radians(FACET_DEG / 2)))
    assert np.linalg.norm(smoothed.positions[1] - exact.positions[1]) < sag


def test_a_node_cycling_across_an_edge_of_a_smoothed_tool_names_no_crease():
    """The same record of a node's closest facet (facets 11 and 12 of the trough in turn, 16
    calls): on the closest-point facets a crease of 10 deg is named; on the smoothed tool,
    whose normal is continuous across that edge, nothing is (its remedy would be itself)."""
    from types import SimpleNamespace

    from solvers.stop_diagnosis import crossing_cycles

    angle = np.radians(np.array([-0.5, 0.5] * 8))  # either side of the bottom edge (0 deg)
    found = []
    for smooth in (False, True):
        tool = faceted_trough(smooth)
        # a contact of one node with the tool (its record's one row), bound before the calls
        part = Contact(tool, np.array([0]), 0.0, 1.0).bind(
            Body.bare(Mesh.line([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], 1))
        )
        tool.record_facets = True  # as a frozen contact (Static) keeps it
        for a in angle:
            tool.distance(
                np.array([[(RADIUS - 0.1) * np.sin(a), 0.0, -(RADIUS - 0.1) * np.cos(a)]])
            )
        found.append(crossing_cycles(SimpleNamespace(interactions=[part])))
    assert len(found[0]) == 1 and found[0][0]["switches"] == 15
    assert abs(found[0][0]["angle_deg"] - FACET_DEG) < 1e-9
    assert found[1] == []


@pytest.mark.parametrize("frozen", [False, True])
def test_the_contact_tangent_turns_the_smoothed_normal_with_the_bowl(frozen):
    """Nodes inside the smoothed bowl of the die, 0.05-0.3 mm from it (pressed at the contact
    offset 0.5 mm), and, frozen (the bilateral spring of Static's contact sets), also 0.6-1.2
    mm off it (p < 0), at polar angles 15-80 deg: the smoothed normal turns as the closest
    point slides over its Phong patch, and the tangent's k p dn/dx (elements/facet_normal.py
    ``turn_on_patches``) matches central differences of the contact force (step 1e-6 mm) to
    1e-6 of the penalty (the differences' round-off is about 1e-8 of it). The tangent that
    left the smoothed normal's turn out was off by k |p| / R, 0.1-1.4 N/mm here against a
    tolerance of 1e-4. Beside it, the closed form: on the sphere the normal turns by
    (I - n n^T) / (R - d) inward; the patches' turn lies within 3 % of it (measured 1.1 %: the
    Phong patch's curvature is the sphere's to first order in the facet's angle, 0.033 rad)."""
    tool = RigidSurface(hemisphere_die(DIE, 55.0, rings=48), smooth=True)  # the bowl, a rim
    polar = np.radians([15.0, 30.0, 44.0, 52.0, 61.0, 73.0, 80.0, 37.0, 66.0])
    azimuth = np.array([0.1, 0.7, 1.3, 2.2, 3.0, 3.9, 4.4, 5.2, 5.9])
    off = np.array([0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.6, 0.9, 1.2])
    if not frozen:
        off = off[:6]
        polar, azimuth = polar[:6], azimuth[:6]
    radius = DIE - off
    x = radius[:, None] * np.column_stack(
        [np.sin(polar) * np.cos(azimuth), np.sin(polar) * np.sin(azimuth), -np.cos(polar)]
    )
    mesh = Mesh.rectangle(4.0, 4.0, nx=2, ny=2)
    contact = Contact(tool, np.arange(len(x)), offset=0.5, penalty=100.0)
    block = contact.bind(Body.bare(mesh))
    zero = np.zeros_like(x)
    state = State(positions=x, directors=zero, velocities=zero, angular_velocities=zero)
    history = None
    if frozen:
        none, empty = np.full((len(x), 3), np.nan), np.zeros(len(x))
        history = FrictionHistory(none, empty, empty, 0.0, np.ones(len(x), dtype=bool))
    d, n = tool.distance(x)
    turn = tool.normal_gradient(x, n)
    sphere = -(np.eye(3) - n[:, :, None] * n[:, None, :]) / radius[:, None, None]
    assert np.abs(turn - sphere).max() < 0.03 / DIE
    assert_tangent_is_the_force_derivative(block, state, history, tolerance=1e-6 * 100.0)
