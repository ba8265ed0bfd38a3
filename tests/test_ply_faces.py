"""Where the ply contact puts a ply's faces (elements/ply_contact.py, "Faces along the
normal"): a fibrous ply's director is free to tilt, so its faces lie h/2 along the nodal
normal, and a pressed ply cannot pass through its neighbour by tilting its directors."""

from __future__ import annotations

import numpy as np
import pytest

from elements.layup import Layup
from elements.ply_contact import PlyContact
from femcore.state import State
from materials import Fabric

PLY = Fabric(thickness=0.3, areal_density=2.85e-10, tension=60.0, shear=0.2, bending=0.375)


def _pressed(layup: Layup, sink: float, tilt_deg: float) -> tuple[object, State]:
    """The layup's ply contact and a state with the top ply ``sink`` mm into the bottom one
    and every director tilted by ``tilt_deg`` about y."""
    compiled = layup.model().compile()
    contact = compiled.interactions[0]
    x = layup.mesh.points.copy()
    x[layup.ply_nodes[1], 2] -= sink
    tilt = np.radians(tilt_deg)
    directors = np.tile([np.sin(tilt), 0.0, np.cos(tilt)], (len(x), 1))
    zero = np.zeros_like(x)
    return contact, State(x, directors, zero, zero)


@pytest.mark.parametrize("angles", [(0.0, 90.0), (0.0, 45.0)])
@pytest.mark.parametrize("tilt_deg", [0.0, 30.0, 75.0])
def test_a_fibrous_layups_gap_is_its_plies_distance_less_their_thickness_whatever_the_tilt(
    angles, tilt_deg
):
    """Mid-surfaces 0.2 mm apart, plies 0.3 mm thick: every contact point penetrates by
    0.1 mm, with upright directors as with directors tilted 75 deg (faces along the
    director put them 0.3 cos 75 = 0.08 mm apart and the contact let go)."""
    layup = Layup(PLY, angles, 40.0, cells=4)
    contact, state = _pressed(layup, 0.1, tilt_deg)
    facing = contact.facing(state)
    assert facing.touching.all()
    np.testing.assert_allclose(facing.gap, -0.1, atol=1e-12)


def test_faces_along_the_normal_exert_no_moment_on_the_directors():
    """The gap does not depend on the directors, so neither does the energy: the contact
    pushes the positions apart and leaves the directors' moments zero."""
    layup = Layup(PLY, (0.0, 90.0), 40.0, cells=4, friction=0.2)
    contact, state = _pressed(layup, 0.1, 40.0)
    force, moment = contact.internal_force(state, contact.initial_history())
    assert np.abs(force[:, 2]).max() > 0.0
    np.testing.assert_array_equal(moment, 0.0)
    top, bottom = layup.ply_nodes
    assert force[top, 2].sum() == pytest.approx(-force[bottom, 2].sum(), rel=1e-12)


def test_faces_along_the_director_follow_a_tilted_director():
    """The option kept for Mindlin plies, whose directors stay near the normal: the faces
    lie h/2 along the directors (0.15 cos 75 from the mid-surface), so the same plies no
    longer touch."""
    layup = Layup(PLY, (0.0, 90.0), 40.0, cells=4, faces="director")
    contact, state = _pressed(layup, 0.1, 75.0)
    facing = contact.facing(state)
    np.testing.assert_allclose(facing.gap, 0.2 - 0.3 * np.cos(np.radians(75.0)), atol=1e-12)
    assert not facing.touching.any()


def test_a_layup_puts_fibrous_faces_along_the_normal_and_mindlin_faces_along_the_director():
    assert Layup(PLY, (0.0, 90.0), 40.0, cells=2).faces == "normal"
    assert Layup(PLY, (0.0, 90.0), 40.0, cells=2, kinematics="mindlin").faces == "director"


def test_unknown_faces_are_refused_with_the_choices():
    with pytest.raises(ValueError, match="faces must be one of .*'director', 'normal'.*'middle'"):
        PlyContact("ply_2", "ply_1", faces="middle")
