"""The lower ply's face as a curved surface over its nodal normals (elements/ply_surface.py,
``PlyContact(surface="curved")``): plies at different angles on a sphere see their true gap,
and the contact force is the exact gradient of the contact energy."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from elements.layup import Layup
from elements.ply_contact import PlyContact
from femcore.interaction import Body
from femcore.state import State
from materials import Fabric

PLY = Fabric(thickness=0.3, areal_density=2.85e-10, tension=60.0, shear=0.2, bending=0.375)
RADIUS = 50.0  # mm, the hemisphere's punch


def _on_sphere(layup: Layup, overlap: float, jitter: float = 0.0) -> State:
    """The layup's plies laid on spheres about the origin: the bottom mid-surface of radius
    ``RADIUS``, the top one h - ``overlap`` above it (the plies' faces ``overlap`` mm into
    each other); directors radial; nodes moved by ``jitter`` mm at random."""
    x = layup.mesh.points.copy()
    for k, nodes in enumerate(layup.ply_nodes):
        radius = RADIUS + k * (PLY.thickness - overlap)
        x[nodes, 2] = np.sqrt(radius**2 - np.sum(x[nodes, :2] ** 2, axis=1))
    x += jitter * np.random.default_rng(1).standard_normal(x.shape)
    zero = np.zeros_like(x)
    return State(x, x / np.linalg.norm(x, axis=1)[:, None], zero, zero)


def _contact(cells: int, size: float, surface: str, faces: str = "normal"):
    layup = Layup(
        PLY,
        (0.0, 45.0),
        size,
        cells=cells,
        rule="gauss",
        faces=faces,
        surface=surface,
        penalty=100.0,
    )
    return layup, layup.model().compile().interactions[0]


@pytest.mark.parametrize("cells, size", [(4, 40.0), (6, 60.0)])
def test_a_0_45_pair_on_the_punchs_sphere_has_its_true_gap_on_the_curved_face(cells, size):
    """10-mm cells, [0/45] (the meshes do not match), faces 0.1 mm into each other: away from
    the blank's edge (whose one-sided nodal normals tilt) every contact point's gap is -0.1
    within 0.01 mm on the curved surface. The flat facets are chords of the sphere: measured
    there -0.17 to +0.06 mm (4 cells) and -0.24 to 0.00 (6 cells)."""
    gaps = {}
    for surface in ("flat", "curved"):
        layup, contact = _contact(cells, size, surface)
        facing = contact.facing(_on_sphere(layup, 0.1))
        inner = np.linalg.norm(facing.face[:, :2], axis=1) < 0.5 * size - size / cells
        assert inner.sum() >= 20
        gaps[surface] = facing.gap[inner]
    np.testing.assert_allclose(gaps["curved"], -0.1, atol=0.01)
    assert np.abs(gaps["flat"] + 0.1).max() > 0.06


@pytest.mark.parametrize("faces", ["normal", "director"])
def test_the_curved_contact_force_is_the_gradient_of_its_energy(faces):
    """Plies 0.1 mm into each other on the sphere, jittered by 0.02 mm: the contact's force
    along six random directions of the positions is the central difference of its energy to
    1e-6, the nodal normals' own dependence on the neighbours' positions included (the
    flat facets with faces along the normal hold the normals fixed: off by 1e-3 there)."""
    layup, contact = _contact(4, 40.0, "curved", faces)
    state = _on_sphere(layup, 0.1, jitter=0.02)
    force, _ = contact.internal_force(state, None)
    rng = np.random.default_rng(3)
    step = 1e-6
    zero = np.zeros_like(state.positions)
    for _ in range(6):
        v = rng.standard_normal(state.positions.shape)
        energies = [
            contact.strain_energy(State(state.positions + s * v, state.directors, zero, zero))
            for s in (step, -step)
        ]
        difference = (energies[0] - energies[1]) / (2.0 * step)
        assert float(np.sum(force * v)) == pytest.approx(difference, rel=1e-6, abs=1e-6)


def test_the_curved_surface_is_flat_on_a_plane():
    """Plies laid flat: the curved surface is the facet, the same gaps as the flat one."""
    gaps = []
    for surface in ("flat", "curved"):
        layup, contact = _contact(4, 40.0, surface)
        x = layup.mesh.points.copy()
        x[layup.ply_nodes[1], 2] -= 0.1
        zero = np.zeros_like(x)
        gaps.append(contact.facing(State(x, np.tile([0.0, 0.0, 1.0], (len(x), 1)), zero, zero)).gap)
    np.testing.assert_allclose(gaps[1], gaps[0], atol=1e-12)
    np.testing.assert_allclose(gaps[1], -0.1, atol=1e-12)


def test_an_unknown_surface_is_refused_with_the_choices():
    with pytest.raises(ValueError, match="surface must be one of .*'flat', 'curved'.*'bumpy'"):
        PlyContact("ply_2", "ply_1", surface="bumpy")


def _turned_pair(cells: int = 4, size: float = 40.0):
    """A [0/45] pair on the sphere, 0.1 mm into each other, and a ply contact of the top
    ply's inner triangles alone (off the blank's edge) on the bottom ply's curved face
    (penalty 100 N/mm); ``turned(a)`` the state with the top ply turned by a rad about x,
    its points sliding over the bottom ply's patches."""
    layup = Layup(PLY, (0.0, 45.0), size, cells=cells, rule="gauss", surface="curved")
    mesh = layup.mesh
    upper = np.asarray(mesh.cell_sets("triangle")["ply_2"])
    centres = mesh.points[mesh.triangles[upper]].mean(axis=1)
    inner = upper[np.abs(centres[:, :2]).max(axis=1) < 0.5 * size - 1.2 * size / cells]
    active = np.zeros((mesh.n_nodes, 6), dtype=bool)
    active[:, :5] = True
    body = Body(mesh, (), np.tile([0.0, 0.0, 1.0], (mesh.n_nodes, 1)), active)
    half = 0.5 * PLY.thickness
    contact = PlyContact(
        inner, "ply_1", half, half, penalty=100.0, rule="gauss", faces="normal", surface="curved"
    ).bind(body)
    laid = _on_sphere(layup, 0.1).positions
    top = layup.ply_nodes[1]

    def turned(a: float) -> State:
        c, s = np.cos(a), np.sin(a)
        x = laid.copy()
        x[top] = laid[top] @ np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]]).T
        zero = np.zeros_like(x)
        return State(x, x / np.linalg.norm(x, axis=1)[:, None], zero, zero)

    return contact, turned


def test_a_point_passing_from_one_curved_patch_to_the_next_keeps_its_energy():
    """The top ply turned over the bottom one by a cell: wherever a point's facing patch
    changes, bisected to 1e-10 rad, the contact energy is continuous to 1e-6 N mm (its slope
    is ~3 N mm/rad). With the patch chosen by the flat facets' projections it jumped there
    by up to 0.007 N mm (the point changed patch where its flat projection crossed the
    facets' edge, off the patches' edge by the chord's sag times the facet's tilt), and an
    explicit run's energy balance took the jumps as work from nowhere."""
    contact, turned = _turned_pair()
    span = 10.0 / 50.0
    angles = np.linspace(-0.5 * span, 0.5 * span, 101)
    triangles = [contact.facing(turned(a)).triangle for a in angles]
    switches = [i for i in range(100) if np.any(triangles[i] != triangles[i + 1])]
    assert len(switches) >= 8
    jumps = []
    for i in switches[:8]:
        lo, hi = angles[i], angles[i + 1]
        start = triangles[i]
        while hi - lo > 1e-10:
            mid = 0.5 * (lo + hi)
            if np.array_equal(contact.facing(turned(mid)).triangle, start):
                lo = mid
            else:
                hi = mid
        jumps.append(abs(contact.strain_energy(turned(hi)) - contact.strain_energy(turned(lo))))
    assert max(jumps) < 1e-6, jumps


def test_the_curved_face_does_not_reach_far_past_a_plys_edge():
    """A point half a cell past the bottom ply's edge, penetrating the patch extrapolated
    there, does not touch the curved face (it did up to half a cell, ``MARGIN``, where the
    quadratic patch over the edge's one-sided normals is no surface: on the coarse [0/45]
    hemisphere, gaps jumping from +0.06 to -0.66 mm in a step); nor the flat facet's plane,
    whose contact fades out over ``FADE`` (0.15) past the outline (elements/ply_fade.py), and
    carries a point 0.07 past it at a part of its stiffness."""
    from elements.ply_fade import FADE

    for surface, slid, touching in (
        ("flat", 6.0, False),
        ("curved", 6.0, False),
        ("flat", 4.0, True),
    ):
        layup = Layup(PLY, (0.0, 0.0), 40.0, cells=4, rule="centroid", surface=surface)
        contact = layup.model().compile().interactions[0]
        x = layup.mesh.points.copy()
        top = layup.ply_nodes[1]
        # the top ply slid 0.6 (0.4) of a cell: its outer centroids 0.27 (0.07) past the edge
        x[top, 0] += slid
        x[top, 2] -= 0.05
        zero = np.zeros_like(x)
        facing = contact.facing(State(x, np.tile([0.0, 0.0, 1.0], (len(x), 1)), zero, zero))
        overshoot = np.maximum(0.0, -facing.weights.min(axis=1))
        past = overshoot > 0.05
        assert past.any() and np.all(overshoot[past] < 0.5)  # within MARGIN, the old reach
        assert np.all(facing.touching[past] == touching), surface
        if touching:
            assert facing.fade is not None and np.all(overshoot[past] < FADE)
            assert np.all((facing.fade[past] > 0.0) & (facing.fade[past] < 1.0))


@pytest.mark.parametrize("cells", [3, 6])
def test_projecting_only_the_near_patches_chooses_as_projecting_every_candidate(cells):
    """The curved facing projects only the candidates whose flat projection lies within
    ``NEAR`` of their facet (elements/ply_curved.py): on the [0/45] pair on the punch's
    sphere at 23- and 12-mm cells (the coarse hemisphere's are 25 mm), jittered by 0.05 mm,
    it picks the same patch with the same gap (to 1e-12 mm) as projecting every candidate,
    the reference."""
    from elements import ply_curved

    layup, contact = _contact(cells, 70.0, "curved")
    state = _on_sphere(layup, 0.1, jitter=0.05)
    p, near, y = contact._candidates(state)
    every = ply_curved.curved_facing(contact, state, p, y, near, every=True)
    facing = contact.facing(state)
    assert facing.touching.sum() >= 5 * cells
    np.testing.assert_array_equal(facing.triangle, every.triangle)
    np.testing.assert_allclose(facing.gap, every.gap, atol=1e-12)


@pytest.mark.parametrize("lift", [7.0, 12.0])
def test_a_ply_far_off_the_curved_face_touches_nothing_and_keeps_its_energy_finite(lift):
    """The frictional [0/45] pair on the punch's sphere (17.5-mm cells, both passes), the top
    ply lifted ``lift`` mm off the bottom one: some points' curved projections do not settle
    in ``ITERATIONS`` Gauss-Newton steps on any candidate (a point mm off a patch tilted by
    its cell's angle), so those points face no patch. Nothing touches: the contact's energy
    (its stick springs' too) is 0, its forces and moments are 0, and every facing normal is
    finite, to the bit; the accepted friction history anchors none (and meets no inf x 0).
    Before, such a point kept its failed projection's NaN normal and the
    friction's slip made the energy NaN (Mindlin [0/45] on the curved faces stopped so at 61 %
    of the hemisphere's stroke)."""
    layup = Layup(
        PLY,
        (0.0, 45.0),
        70.0,
        cells=4,
        rule="gauss",
        faces="normal",
        surface="curved",
        friction=0.2,
        penalty=100.0,
        lower_rule="nodes",
    )
    x = layup.mesh.points.copy()
    for k, nodes in enumerate(layup.ply_nodes):
        radius = RADIUS + k * (PLY.thickness + lift)
        x[nodes, 2] = np.sqrt(radius**2 - np.sum(x[nodes, :2] ** 2, axis=1))
    zero = np.zeros_like(x)
    state = State(x, x / np.linalg.norm(x, axis=1)[:, None], zero, zero)
    unsettled = 0
    for contact in layup.model().compile().interactions:
        history = contact.initial_history()
        facing = contact.facing(state)
        unsettled += int(np.isinf(facing.gap).sum())
        assert not facing.touching.any()
        assert np.isfinite(facing.normal).all()
        assert contact.strain_energy(state, history) == 0.0
        force, moment = contact.internal_force(state, history)
        assert np.abs(force).max() == 0.0 and np.abs(moment).max() == 0.0
        with warnings.catch_warnings():
            warnings.simplefilter("error")  # no inf x 0 on the way
            accepted = contact.update_history(state, history)
        assert (accepted.triangle == -1).all()
        # The points the stacked reference anchored leave in this one step: their departure
        # dissipates mu N_0 / 2 times their slip (docs/theory.md §9.3a), N_0 their normal
        # force at rest, the plies laid at a zero gap (round-off on the law's ramp): finite
        # and at most mu N_0 / 2 times the farthest any point went.
        went = np.linalg.norm(x - layup.mesh.points, axis=1).max() + 2 * PLY.thickness
        bound = 0.2 * 0.5 * float(np.sum(history.pressing)) * went
        assert np.isfinite(accepted.dissipated) and 0.0 <= accepted.dissipated <= bound
    assert unsettled > 0  # the case the test is for: points with no converged patch
