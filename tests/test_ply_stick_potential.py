"""The ply contact's stick spring of the normal law as a potential (``PlyContact(stick="normal
law")``, elements/ply_friction.py "The stick potential", docs/theory.md "Friction between
plies"): a stuck point's loads are the gradient of the energy the block reports for it,
E = w W''(g) |s|^2 / 2, at fixed history: the tangential k_t s on the point and -Lambda_k k_t s
on its anchor's corners, the normal w W''' |s|^2 / 2 along dg/dz, W'' |s|^2 / 2 dw/dz past the
outline, and the couple k_t (n . r)(s . grad phi_m) n on the facing triangle's corners (F and
-F act a distance n . r ~ g apart across the facing normal n, which turns with the corners).

The model: tests/test_interaction_conformance.py's two jittered plies with friction, only the
chosen stuck points anchored (the others' anchors dropped, so every frictional point is stuck
and its energy a potential), each facing a triangle's plane: on the 0.05-mm ramp
(W''' = -k_p / delta), pressed deeper than the ramp (W''' = 0), the mirrored pass's points past
the upper ply's outline inside the fade (0 < w < 1, dw != 0; no smoothing, so W''' = 0), and
the mirrored pass's points on a 0.2-mm ramp inside the fade at once (W''' |s|^2 / 2 dw and its
dg). The reference is central differences of ``strain_energy`` (the normal law's w W plus the
stick potential) at every node of the block, translations and director turns
(femcore/interaction_checks.py ``check_force_is_energy_gradient``: step 1e-6 of the plies'
4-mm size or 1e-6 rad, truncation O(h^2) ~ 1e-11 relative, rounding 8 eps |W| / h, held to
1e-6 of the largest force or moment component). Measured: the loads agree to 2e-9 of the
largest; without the couple they were off by 4.7e-4 (ramp), 1.2e-3 (deeper), 8.1e-4 (fade) and
1.6e-3 (ramp and fade) of the largest force, 1.9e-4 to 2.4e-3 of the largest moment. Both the
compiled loads and the numpy reference.
"""

import numpy as np
import pytest
from friction_histories import kept_anchors

from elements import ply_projection
from elements.ply_friction import stick_couple
from femcore.interaction_checks import check_force_is_energy_gradient, check_tangent
from tests.test_interaction_conformance import plies_with_friction

CASES = {
    # name: (plies_with_friction's settings, which stuck points keep their anchors)
    "on the ramp": (
        {"rule": "gauss", "smoothing": 0.05, "points": "upper"},
        lambda facing, block: facing.gap > -block.smoothing,
    ),
    "deeper": (
        {"rule": "gauss", "smoothing": 0.05, "points": "upper"},
        lambda facing, block: facing.gap <= -block.smoothing,
    ),
    "in the fade": (
        {"rule": "vertices", "smoothing": None, "points": "lower"},
        lambda facing, block: (
            (facing.fade > 0.0)
            & (facing.fade < 1.0)
            & np.any(facing.fade_gradient != 0.0, axis=(1, 2))
        ),
    ),
    "on the ramp and in the fade": (
        {"rule": "vertices", "smoothing": 0.2, "points": "lower"},
        lambda facing, block: (
            (facing.gap > -block.smoothing)
            & (facing.fade > 0.0)
            & (facing.fade < 1.0)
            & np.any(facing.fade_gradient != 0.0, axis=(1, 2))
        ),
    ),
}


def _stuck_only(case: str, stick: str = "normal law"):
    """(block, state, history, kept (P,) bool) with only the case's stuck points anchored."""
    settings, chosen = CASES[case]
    block, state, history = plies_with_friction(stick=stick, **settings)
    facing = block.facing(state)
    kept = block.friction_state(state, history).stuck & chosen(facing, block)
    history = kept_anchors(history, kept)
    return block, state, history, kept


@pytest.mark.parametrize("compiled", [True, False], ids=["compiled", "numpy"])
@pytest.mark.parametrize("case", list(CASES))
def test_a_stuck_points_loads_are_the_gradient_of_its_reported_energy(monkeypatch, case, compiled):
    monkeypatch.setattr(ply_projection, "COMPILED", compiled)
    block, state, history, kept = _stuck_only(case)
    sliding = block.friction_state(state, history)
    facing = block.facing(state)
    # the premises: the chosen points stuck, none sliding, each facing a plane
    assert kept.sum() >= 4 and np.array_equal(sliding.stuck, kept) and not sliding.sliding.any()
    assert facing.on_edge is not None and not facing.on_edge[kept].any()
    check_force_is_energy_gradient(block, state, history)  # every node, u and psi
    # what the potential adds where the old force was k_t s alone
    if case == "on the ramp":
        assert np.all(sliding.lift[kept] < 0.0)  # W''' = -k_p / delta: -dE/dg pushes apart
    elif case == "deeper":
        assert np.all(sliding.lift[kept] == 0.0)
    elif case == "in the fade":
        assert np.all(sliding.stored[kept] > 0.0)
    else:  # W''' |s|^2 / 2 dw and its dg: lift and stored both
        assert np.any(sliding.lift[kept] < 0.0) and np.all(sliding.stored[kept] > 0.0)
    assert np.any(stick_couple(block, sliding, facing, np.flatnonzero(kept)) != 0.0)


@pytest.mark.parametrize("case", ["deeper", "in the fade"])
def test_with_the_penalty_as_stick_spring_the_loads_are_the_gradient_too(case):
    """``stick="penalty"``: E = k_p |s|^2 / 2 holds no g nor w, and its gradient is F and the
    couple (no lift, nothing stored), against the same central differences at every node
    (without the couple off by 1.2e-3 of the largest force deeper, measured); and the tangent
    their derivative (``check_tangent``)."""
    block, state, history, kept = _stuck_only(case, stick="penalty")
    sliding = block.friction_state(state, history)
    assert kept.sum() >= 4 and np.array_equal(sliding.stuck, kept)
    assert not sliding.lift.any() and not sliding.stored.any()
    check_force_is_energy_gradient(block, state, history)
    assert check_tangent(block, state, history)


@pytest.mark.parametrize("case", list(CASES))
def test_a_stuck_points_tangent_is_the_derivative_of_its_force(case):
    """The block's tangent with only the case's stuck points anchored, against central
    differences of its forces and moments at every node (femcore.interaction_checks
    ``check_tangent``: 1e-6 of the largest entry): the stick potential's terms (the gap's and
    the fade's Hessians times lift and stored, and their own derivatives) and the couple's
    derivative (``ply_friction_tangent._couple_tangent``) included. With the couple in the loads but
    not its derivative, the first entry out is off by 6.6e-5 (ramp), 3.6e-5 (deeper), 1.1e-3
    (fade) and 1.7e-3 (ramp and fade) of the largest entry; without the potential's terms by
    9e-5 on the ramp and 5e-4 in the fade (measured). The old code, whose loads lacked the
    terms its tangent lacked, passes it too (the loads' test above is the one it fails)."""
    block, state, history, _ = _stuck_only(case)
    assert check_tangent(block, state, history)
