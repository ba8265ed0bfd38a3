"""The two-ply hemisphere study's measure of the plies' order in the die
(validation/studies/hemisphere_plies_gaps.py) on plies laid face to face on concentric
spheres: their true gap is zero wherever both lie on their spheres."""

from __future__ import annotations

import numpy as np

from elements.layup import Layup
from validation.studies import hemisphere_plies_setup as study
from validation.studies.hemisphere_plies_gaps import node_gaps, radial_gaps

RIM_ANGLE = 1.45  # rad, the polar angle past which a node lies on the flat flange


def _laid(layup: Layup) -> np.ndarray:
    """(n, 3) the plies laid on their spheres about the origin (ply k at the study's radius
    PUNCH + (PLIES - k - 1/2) h: the faces touch), each blank point at the polar angle of its
    distance from the blank's centre over 50.45 mm, in its own direction; past RIM_ANGLE on
    a flange at z = (k - 1) h, as a die's flange: the bottom ply's nodes next to it get nodal
    normals turned towards it."""
    points = layup.mesh.points
    x = np.zeros_like(points)
    for k, nodes in enumerate(layup.ply_nodes):
        radius = study.PUNCH + (study.PLIES - k - 0.5) * study.THICKNESS
        rho = np.linalg.norm(points[nodes, :2], axis=1)
        phi = np.arctan2(points[nodes, 1], points[nodes, 0])
        theta = rho / 50.45
        on = theta < RIM_ANGLE
        plan = np.where(
            on, radius * np.sin(theta), radius * np.sin(RIM_ANGLE) + rho - 50.45 * RIM_ANGLE
        )
        z = np.where(on, -radius * np.cos(theta), k * study.THICKNESS)
        x[nodes] = np.column_stack([plan * np.cos(phi), plan * np.sin(phi), z])
    return x


def test_plies_face_to_face_on_concentric_spheres_read_a_zero_gap_in_the_die():
    """Every top node in the die whose ray meets a bottom triangle with its corners on the
    bottom ply's sphere reads r_b - r - h = 0 exactly (to round-off, 1e-9 mm). The curved
    (Phong) face the study measured to before read -2.57 mm at the blank's (33.3, -33.3):
    the bottom corners next to the flange have their nodal normals turned towards it and the
    face bulges; the study's check of one ply thickness failed on plies in order."""
    layup = Layup(study.FABRIC, study.LAYUPS["0/45"], 2 * study.HALF, cells=8)
    x = _laid(layup)
    gaps = radial_gaps(layup, x, study.THICKNESS)
    top = layup.ply_nodes[-1]
    measured = np.isfinite(gaps) & (x[top, 2] < -5.0)
    assert measured.sum() >= 20  # the 45-deg ply's nodes over the bowl
    np.testing.assert_allclose(gaps[measured], 0.0, atol=1e-9)
    # what the study measured before, for the record: the curved face misreads it
    probe = (
        Layup(
            study.FABRIC,
            study.LAYUPS["0/45"],
            2 * study.HALF,
            cells=8,
            rule="vertices",
            surface="curved",
        )
        .model()
        .compile()
        .interactions[0]
    )
    curved = node_gaps(probe, layup, x, below=-5.0)
    assert np.nanmin(curved[x[top, 2] < -5.0]) < -study.THICKNESS


def test_a_top_node_pushed_through_the_bottom_ply_reads_its_depth():
    """A top node moved 0.8 mm out along its radius from touching (its face 0.8 mm past the
    bottom ply's) reads -0.8 mm, to round-off."""
    layup = Layup(study.FABRIC, study.LAYUPS["0/45"], 2 * study.HALF, cells=8)
    x = _laid(layup)
    top = layup.ply_nodes[-1]
    deep = np.flatnonzero(np.isfinite(radial_gaps(layup, x, study.THICKNESS)) & (x[top, 2] < -5.0))
    node = top[deep[0]]
    x[node] *= 1.0 + 0.8 / np.linalg.norm(x[node])
    gaps = radial_gaps(layup, x, study.THICKNESS)
    np.testing.assert_allclose(gaps[deep[0]], -0.8, atol=1e-9)


def _probe(layup: Layup, rule: str, surface: str):
    return (
        Layup(
            study.FABRIC, tuple(layup.angles), 2 * study.HALF, cells=8, rule=rule, surface=surface
        )
        .model()
        .compile()
        .interactions[0]
    )


def test_one_point_per_node_reads_the_gaps_of_a_point_in_each_triangle():
    """``least_gaps``' probe takes one point per node ("nodes"): on plies laid on their
    spheres, wrinkled by a random jitter of 0.4 mm (a sixth of the top nodes then lie past
    the bottom ply's face) and with one top node pushed 0.8 mm through, its node gaps are
    those of a point at the node in each of its triangles ("vertices", the least of them
    per node) to the bit, on the flat facets and the curved face, in the die and over the
    whole blank: the points at one node lie at one place and each point's facing is its
    place's alone."""
    for angles in ("0/90", "0/45"):
        layup = Layup(study.FABRIC, study.LAYUPS[angles], 2 * study.HALF, cells=8)
        x = _laid(layup)
        x += np.random.default_rng(7).normal(scale=0.4, size=x.shape)
        top = layup.ply_nodes[-1]
        x[top[len(top) // 2]] *= 1.0 + 0.8 / np.linalg.norm(x[top[len(top) // 2]])
        for surface in ("flat", "curved"):
            each = _probe(layup, "vertices", surface)
            once = _probe(layup, "nodes", surface)
            assert len(once.above) < len(each.above) / 4  # 81 points for 384
            for below in (None, -5.0):
                expected = node_gaps(each, layup, x, below)
                found = node_gaps(once, layup, x, below)
                assert np.isfinite(expected).sum() >= (10 if below else 40)
                assert np.nanmin(expected) < -0.1  # points past the face: not all zero
                np.testing.assert_array_equal(found, expected)
