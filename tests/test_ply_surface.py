"""The lower ply's face as a curved surface over its nodal normals (elements/ply_surface.py,
``PlyContact(surface="curved")``): plies at different angles on a sphere see their true gap,
and the contact force is the exact gradient of the contact energy."""

from __future__ import annotations

import numpy as np
import pytest

from elements.layup import Layup
from elements.ply_contact import PlyContact
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
