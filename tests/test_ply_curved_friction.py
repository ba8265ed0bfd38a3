"""Coulomb friction on the curved faces (elements/ply_curved_friction.py, docs/theory.md §9.3a
"Curved faces"): a stuck point's loads are the gradient of the energy the block reports for
it, k_t |s|^2 / 2 with s measured across the curved face's turning normal (the force, the
couple and the lift), and the tangent is the derivative of the loads, stuck and sliding.

The model: the [0/45] pair of tests/test_ply_surface.py on the 50-mm sphere, 10-mm cells,
faces 0.1 mm into each other, jittered by 0.02 mm, mu = 0.3, every touching point anchored
on its facing patch at its projection's coordinates moved by 5e-4 (even points, ~5e-3 mm:
they stick) or 5e-2 (odd, ~0.5 mm: they slide). The reference: central differences of
``strain_energy`` and of the loads at every node, translations and director turns
(femcore.interaction_checks), held to 1e-6 of the largest entry. The steps are 1e-6 mm (the
energy) and 1e-7 mm (the loads), not the kit's default 4e-5 mm (1e-6 of the plies' size): a
stuck point lies 0.33 % of its friction limit from sliding, 1.6e-5 mm of slip, which the
default step carries past it (the loads are E's gradient on either side, not across).
"""

import numpy as np
import pytest

from elements.layup import Layup
from elements.ply_friction import PlyFrictionHistory
from femcore.interaction_checks import check_force_is_energy_gradient, check_tangent
from tests.test_ply_surface import PLY, _on_sphere

MU = 0.3


def _anchored(faces: str, smoothing=None, stuck_only: bool = True, mirrored: bool = False):
    """(block, state, history) of the pair with friction (module docstring); with
    ``stuck_only`` the sliding points' anchors dropped; with ``mirrored`` the mirrored pass
    (the bottom ply's nodes against the top ply's curved face)."""
    layup = Layup(
        PLY, (0.0, 45.0), 40.0, cells=4, rule="gauss", faces=faces, surface="curved",
        penalty=100.0, friction=MU, smoothing=smoothing,
        lower_rule="vertices" if mirrored else None,
    )  # fmt: skip
    block = layup.model().compile().interactions[1 if mirrored else 0]
    state = _on_sphere(layup, 0.1, jitter=0.02)
    facing = block.facing(state)
    count = len(facing.gap)
    shift = np.random.default_rng(7).normal(size=(count, 3))
    shift -= shift.mean(axis=1)[:, None]  # the coordinates still sum to 1
    size = np.where(np.arange(count) % 2, 0.05, 0.0005) / np.abs(shift).max(axis=1)
    on = facing.touching
    history = PlyFrictionHistory(
        np.where(on, facing.triangle, -1),
        np.where(on[:, None], facing.weights + size[:, None] * shift, np.nan),
        np.zeros(count),
        np.full(count, 0.5),
        1.0,
    )
    if stuck_only:
        kept = block.friction_state(state, history).stuck
        history = PlyFrictionHistory(
            np.where(kept, history.triangle, -1),
            np.where(kept[:, None], history.anchor, np.nan),
            history.slip,
            history.pressing,
            history.dissipated,
        )
    return block, state, history


@pytest.mark.parametrize("faces", ["normal", "director"])
@pytest.mark.parametrize("smoothing", [None, 0.05], ids=["deeper", "on the ramp"])
def test_a_stuck_points_loads_on_the_curved_face_are_the_gradient_of_its_energy(faces, smoothing):
    """Measured within 1e-8 of the largest force or moment (faces along the normals,
    deeper than the ramp: 1e-10). The loads before (k_t s alone, spread by the flat shape
    functions on the upper ply, without the couple, the lift or the normals' part) were off
    by 1.5e-4 to 1.6e-3 of it."""
    block, state, history = _anchored(faces, smoothing)
    sliding = block.friction_state(state, history)
    facing = block.facing(state)
    assert sliding.stuck.sum() >= 30 and not sliding.sliding.any()
    on_ramp = sliding.stuck & (facing.gap > -block.smoothing)
    assert on_ramp.sum() >= (4 if smoothing else 0)
    check_force_is_energy_gradient(block, state, history, step=1e-6)


@pytest.mark.parametrize("faces", ["normal", "director"])
@pytest.mark.parametrize("stuck_only", [True, False], ids=["stuck", "stuck and sliding"])
def test_the_curved_frictions_tangent_is_the_derivative_of_its_loads(faces, stuck_only):
    """Measured within 1e-10 (stuck) and 1e-8 (stuck and sliding) of the largest entry,
    faces along the normals."""
    block, state, history = _anchored(faces, stuck_only=stuck_only)
    sliding = block.friction_state(state, history)
    assert sliding.stuck.sum() >= 40 and (stuck_only or sliding.sliding.sum() >= 40)
    assert check_tangent(block, state, history, step=1e-7)


def test_the_mirrored_passs_curved_friction_loads_and_tangent():
    """The mirrored pass (``points="lower"``), faces along the normals: 48 stuck and 48
    sliding points; the stuck points' loads the energy's gradient, the tangent the loads'
    derivative, as above."""
    block, state, history = _anchored("normal", stuck_only=False, mirrored=True)
    sliding = block.friction_state(state, history)
    assert block.mirrored and sliding.stuck.sum() >= 40 and sliding.sliding.sum() >= 40
    assert check_tangent(block, state, history, step=1e-7)
    block, state, history = _anchored("normal", mirrored=True)
    check_force_is_energy_gradient(block, state, history, step=1e-6)
