"""The ply contact's stick spring of the normal law as a potential (``PlyContact(stick="normal
law")``, elements/ply_friction.py "The stick potential", docs/theory.md "Friction between
plies"): a stuck point's force is the gradient of the energy the block reports for it,
E = w W''(g) |s|^2 / 2, at fixed history: the tangential k_t s and the normal w W''' |s|^2 / 2
along dg/dz and W'' |s|^2 / 2 dw/dz past the outline.

The model: tests/test_interaction_conformance.py's two jittered plies with friction, only the
chosen stuck points anchored (the others' anchors dropped, so every frictional point is stuck
and its energy a potential): on the 0.05-mm ramp (W''' = -k_p / delta), pressed deeper than the
ramp (W''' = 0: the old force was already the gradient there) and the mirrored pass's points
past the upper ply's outline inside the fade (0 < w < 1, dw != 0). The reference is central
differences of ``strain_energy`` (the normal law's w W plus the stick potential) over the
points' own nodes (their upper triangle's corners: the point moves with them, its facing
normal does not, so s = (I - n n^T)(p - a) moves by (I - n n^T) dp exactly); the facing
triangle's corners are left out: there the energy's gradient also holds the couple
k_t (n . r) s . dn/dy that the loads leave out (docs/theory.md, F and -F a distance ~ g
apart). Tolerance as the conformance kit's (femcore/interaction_checks.py): step 1e-6 of the
plies' 4-mm size, truncation O(h^2) ~ 1e-11 relative, rounding 8 eps |W| / h, held to 1e-6 of
the largest force component; the old force (k_t s alone) was off by 1.7e-5 of it on the
ramp and 1.6e-4 in the fade (measured). Both the compiled loads and the numpy reference.
"""

import dataclasses

import numpy as np
import pytest

from elements import ply_projection
from elements.ply_friction import PlyFrictionHistory
from femcore.interaction_checks import check_tangent
from femcore.state import State
from tests.test_interaction_conformance import plies_with_friction

EPS = np.finfo(float).eps
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
}


def _stuck_only(case: str):
    """(block, state, history, kept (P,) bool) with only the case's stuck points anchored."""
    settings, chosen = CASES[case]
    block, state, history = plies_with_friction(stick="normal law", **settings)
    facing = block.facing(state)
    kept = block.friction_state(state, history).stuck & chosen(facing, block)
    history = PlyFrictionHistory(
        np.where(kept, history.triangle, -1),
        np.where(kept[:, None], history.anchor, np.nan),
        history.slip,
        history.pressing,
        history.dissipated,
    )
    return block, state, history, kept


def _moved(state: State, node: int, axis: int, amount: float) -> State:
    positions = state.positions.copy()
    positions[node, axis] += amount
    return dataclasses.replace(state, positions=positions)


@pytest.mark.parametrize("compiled", [True, False], ids=["compiled", "numpy"])
@pytest.mark.parametrize("case", list(CASES))
def test_a_stuck_points_force_is_the_gradient_of_its_reported_energy(monkeypatch, case, compiled):
    monkeypatch.setattr(ply_projection, "COMPILED", compiled)
    block, state, history, kept = _stuck_only(case)
    sliding = block.friction_state(state, history)
    facing = block.facing(state)
    # the premises: the chosen points stuck, none sliding, each facing a plane (n held by p)
    assert kept.sum() >= 4 and np.array_equal(sliding.stuck, kept) and not sliding.sliding.any()
    assert facing.hessian is None or not np.any(facing.hessian[kept] != 0.0)
    force = block.internal_force(state, history)[0]
    h = 1e-6 * 4.0
    nodes = np.unique(block.above[kept])
    rows = []
    for node in nodes:
        for axis in range(3):
            plus = block.strain_energy(_moved(state, node, axis, h), history)
            minus = block.strain_energy(_moved(state, node, axis, -h), history)
            rounding = 8.0 * EPS * max(abs(plus), abs(minus)) / h
            rows.append((node, axis, force[node, axis], (plus - minus) / (2.0 * h), rounding))
    scale = max(max(abs(r[2]), abs(r[3])) for r in rows)
    for node, axis, own, numeric, rounding in rows:
        assert abs(own - numeric) <= 1e-6 * scale + rounding, (node, axis, own, numeric)
    # what the potential adds along the normal (and dw/dz) where the old force was k_t s alone
    if case == "on the ramp":
        assert np.all(sliding.lift[kept] < 0.0)  # W''' = -k_p / delta: -dE/dg pushes apart
    elif case == "deeper":
        assert np.all(sliding.lift[kept] == 0.0)
    else:
        assert np.all(sliding.stored[kept] > 0.0)


@pytest.mark.parametrize("case", list(CASES))
def test_a_stuck_points_tangent_is_the_derivative_of_its_force(case):
    """The block's tangent with only the case's stuck points anchored, against central
    differences of its forces and moments at every node (femcore.interaction_checks
    ``check_tangent``: 1e-6 of the largest entry): the stick potential's terms (the gap's and
    the fade's Hessians times lift and stored, and their own derivatives) included; without
    them it is off by 9e-5 of the largest entry on the ramp and 5e-4 in the fade (measured).
    It holds on the old code too, whose force lacked the terms its tangent lacked."""
    block, state, history, _ = _stuck_only(case)
    assert check_tangent(block, state, history)
