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
from femcore import Mesh, Model
from solvers import ConvergenceError, Static
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
    (ConvergenceError, the line search finding no decrease). Smoothed, it converges (measured
    8-20 Newton iterations per increment: the tangent leaves out the surface's curvature), and
    the node lies where it lies on the analytic cylinder (solved the same way) within the
    facets' chordal sag R (1 - cos 5 deg) = 0.076 mm (measured 3.0e-3 mm apart)."""
    exact = Static(increments=4, progress=False).solve(
        trough(RigidCylinder((0.0, 0.0, 0.0), (0.0, 1.0, 0.0), RADIUS, side="inside"))
    )
    assert exact.converged
    with pytest.raises(ConvergenceError):
        Static(increments=4, max_cuts=3, progress=False).solve(trough(faceted_trough(False)))
    smoothed = Static(increments=4, progress=False).solve(trough(faceted_trough(True)))
    assert smoothed.converged
    sag = RADIUS * (1.0 - np.cos(np.radians(FACET_DEG / 2)))
    assert np.linalg.norm(smoothed.positions[1] - exact.positions[1]) < sag
