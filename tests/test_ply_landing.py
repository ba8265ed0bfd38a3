"""A ply contact point landing in a step is anchored, for that step, where its way crossed the
lower face (elements/ply_landing.py, docs/theory.md §9.2 and §9.3a "Friction between plies"):
only its slip after the touch dissipates, and the tangent carries the anchor's motion.

The model: an upper ply (2 x 2 mm, 2 x 2 cells, Gauss points) carried at a steady pace, along
x by VX and down by VZ over the run (prescribed translations, directors held), onto a lower
ply (6 x 6 mm, 3 x 3 cells) held fixed, mu = 0.3, the plain penalty (smoothing 0: N = k_p pen,
and the normal law's stick spring k_t = W'' = k_p). Every point lies G0 above the lower face at
the start and touches at t_c = G0 / VZ (0.213 of the run, within a step and an increment);
from there it slides (VX > mu VZ), its penetration pen = VZ (t - t_c), the stick spring holding
mu pen of its offset. Coulomb's dissipation of a point is then

    D_p = integral of mu k_p pen(t) d(slip) = mu k_p VZ (VX - mu VZ) (1 - t_c)^2 / 2,

its slip (VX - mu VZ)(1 - t_c): the gap is linear in time and the normal force linear over
each step, so the record (the limit force at the mean of a step's start and end) is that
integral to round-off (asserted 1e-12 relative). The lower face is flat and fixed and the way
straight: the rule is exact there, also where a point's way crosses triangles within a step
(0.83 mm of 2-mm cells an increment in 3 increments).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from elements import ply_landing, ply_projection
from elements.ply_friction import PlyFrictionHistory
from elements.ply_sides import CLEAR, PlySides
from femcore import Model
from femcore.interaction_checks import check_tangent
from tests.explicit_runs import run_explicitly
from tests.ply_pair import MU, moved_plies, static_histories
from tests.test_interaction_conformance import plies
from tests.test_ply_curved_friction import _anchored

G0 = 0.0213  # mm between the faces at the start
VX, VZ = 2.5, 0.1  # mm over the run, along x and down
STEPS = 40
DURATION = 1.0e-4  # s


def carried_plies(surface: str = "flat") -> Model:
    """The two plies (module docstring; tests/ply_pair.py), the upper one carried VX along x
    and VZ down from G0 over the lower one's face, on faces ``surface``."""
    return moved_plies(G0, VX, -VZ, surface)


def coulomb(block) -> tuple[float, float]:
    """(D, slip): the module docstring's dissipation summed over the points of the contact
    ``block``, with their penalties k_p (PENALTY shared among them), N mm, and each point's
    slip, mm."""
    after = 1.0 - G0 / VZ  # the share of the run after the touch
    stiffness = float(np.sum(block.stiffness))
    return MU * stiffness * VZ * (VX - MU * VZ) * after**2 / 2, (VX - MU * VZ) * after


def test_an_explicit_run_dissipates_coulombs_work_after_the_touch():
    """40 explicit steps: the touch falls 0.52 of the way through step 9. Before, the landing
    step took no friction and its points were anchored at their projections once it was
    accepted: 10.323910 against 10.326430 N mm (2.4e-4 short: fails)."""
    compiled, state = run_explicitly(carried_plies(), STEPS, DURATION)
    assert state.load_factor == pytest.approx(1.0, rel=1e-12)
    dissipation = coulomb(compiled.interactions[0])[0]
    assert compiled.dissipated_energy(state) == pytest.approx(dissipation, rel=1e-12)


@pytest.mark.parametrize("increments", [3, 7])
def test_static_counts_the_slip_of_a_landing_increment_from_the_touch(monkeypatch, increments):
    """Static in 3 and 7 increments (the committed histories watched): each point slid
    (VX - mu VZ)(1 - t_c) = 1.94389 mm and the dissipation is Coulomb's. Before, the landing
    increment was frictionless: 1.64306 / 1.76210 mm and 10.0710 / 10.2340 N mm (fails)."""
    model = carried_plies()
    last = static_histories(monkeypatch, model, increments)[-1]
    dissipation, slip = coulomb(model.compile().interactions[0])
    np.testing.assert_allclose(last.slip, slip, rtol=1e-12)
    assert last.dissipated == pytest.approx(dissipation, rel=1e-12)


@pytest.mark.parametrize(
    "surface, compiled",
    [("flat", True), ("flat", False), ("curved", True)],
    ids=["compiled", "numpy", "curved"],
)
@pytest.mark.parametrize("steps", [40, 3])
def test_the_accepted_histories_count_the_slip_after_the_touch(
    monkeypatch, surface, compiled, steps
):
    """The block's history stepped over the carried states (the explicit solver's and
    Static's acceptance alike), by the compiled passes and the numpy reference, and on the
    curved faces (a flat ply's patches are its facets: the rule is exact there too)."""
    monkeypatch.setattr(ply_projection, "COMPILED", compiled)
    compiled_model = carried_plies(surface).compile()
    block = compiled_model.interactions[0]
    state = compiled_model.initial_state()
    upper = np.unique(block.above)
    history = block.initial_history()
    for step in range(1, steps + 1):
        positions = state.positions.copy()
        positions[upper] += np.array([VX, 0.0, -VZ]) * step / steps
        history = block.update_history(dataclasses.replace(state, positions=positions), history)
    dissipation, slip = coulomb(block)
    np.testing.assert_allclose(history.slip, slip, rtol=1e-12)
    assert history.dissipated == pytest.approx(dissipation, rel=1e-12)


def landing_plies(smoothing, stick, aside=1.0):
    """(block, state, history): tests/test_interaction_conformance.py's jittered plies with
    friction 0.3, and a history where no point touched, each face point then 0.3 mm off
    along its facing normal now and ``aside`` x 0.058 mm aside, the lower faces where they
    are now."""
    block, state, _ = plies(rule="gauss", smoothing=smoothing, friction=MU, stick=stick)
    facing = block.facing(state)
    count = len(facing.gap)
    faces, corners = block._faces(state)
    then = faces + aside * np.array([0.05, -0.03, 0.0]) + 0.3 * facing.normal
    sides = PlySides(np.full(count, CLEAR, dtype=np.int8), then, corners)
    nowhere = np.full((count, 3), np.nan)
    history = PlyFrictionHistory(
        np.full(count, -1), nowhere, np.zeros(count), np.zeros(count), 0.0, sides
    )
    return block, state, history


@pytest.mark.parametrize(
    "smoothing, stick, aside",
    [(0.05, "normal law", 1.0), (None, "penalty", 1.5)],
    ids=["ramp", "penalty"],
)
def test_the_tangent_at_a_landing_state_carries_the_anchors_motion(smoothing, stick, aside):
    """Every touching point lands (29 of them, theta 0.48-1.0), some stuck and some sliding:
    the tangent against central differences of the loads at every node (the conformance
    kit's ``check_tangent``, 1e-6 of the largest entry). Without the anchor's motion
    (dLambda_a/dz) it was off by 2.2 and 9.9 of the largest 76 and 81 (measured); before, the
    landing points had no friction (the premise fails)."""
    block, state, history = landing_plies(smoothing, stick, aside)
    facing = block.facing(state)
    found = ply_landing.landing(block, state, history, facing)
    assert found is not None and np.array_equal(found.rows, np.flatnonzero(facing.touching))
    sliding = block.friction_state(state, ply_landing.landed(block, state, history, facing))
    assert sliding.stuck.sum() >= 2 and sliding.sliding.sum() >= 2
    # the block's own energy holds the landing points' stick springs (not the rule before)
    unsided = dataclasses.replace(history, sides=None)
    assert block.strain_energy(state, history) > block.strain_energy(state, unsided)
    assert check_tangent(block, state, history)


def test_a_point_touching_at_the_last_state_without_an_anchor_does_not_land():
    """Only points clear at the accepted state land (their side); a history whose anchors a
    caller dropped keeps those points frictionless for the step, as before."""
    block, state, history = landing_plies(0.05, "normal law")
    assert history.sides is not None
    touching = np.full(len(history.triangle), 1, dtype=np.int8)
    kept = dataclasses.replace(history, sides=dataclasses.replace(history.sides, sides=touching))
    facing = block.facing(state)
    assert ply_landing.landing(block, state, kept, facing) is None
    assert ply_landing.landed(block, state, kept, facing) is kept


def test_a_frictionless_contact_never_asks_for_a_landing(monkeypatch):
    """Frictionless plies (the report's plies-bai-5.1, deck and heavy-stack cases) take the
    code path they took before: no landing is asked for by their loads, energy, tangent or
    accepted history."""

    def refused(*args, **kwargs):
        raise AssertionError("a frictionless contact asked for a landing")

    monkeypatch.setattr(ply_landing, "landing", refused)
    monkeypatch.setattr(ply_landing, "landed", refused)
    block, state, _ = plies(rule="gauss", smoothing=0.05)
    history = block.initial_history()
    assert block.facing(state).touching.any()
    block.internal_force(state, history)
    block.strain_energy(state, history)
    block.tangent(state, history)
    block.update_history(state, history)


@pytest.mark.parametrize("surface", ["flat", "curved"])
def test_a_point_landing_along_the_facing_normal_does_not_slip(surface):
    """Each point of a ply pair coming straight down along its facing normal (its face point
    at the last accepted state 0.3 mm out along it, clear) lands with no tangential way, so
    its landing anchor is its projection and its slip vanishes (1e-9 mm, round-off): on the
    flat faces, and on the curved ones (the [0/45] pair on a 50-mm sphere), where the anchor
    was once taken from the point's place on T's plane, not from its projection on T's Phong
    patch (slips up to 0.032 mm, 16 of 41 points sliding at mu N)."""
    if surface == "flat":
        block, state, _ = plies(rule="gauss", friction=0.3)
    else:
        block, state, _ = _anchored("normal", stuck_only=False)
    facing = block.facing(state)
    faces, corners = block._faces(state)
    count = len(facing.gap)
    sides = PlySides(np.full(count, CLEAR, dtype=np.int8), faces + 0.3 * facing.normal, corners)
    history = PlyFrictionHistory(
        np.full(count, -1), np.full((count, 3), np.nan), np.zeros(count), np.zeros(count), 0.0,
        sides,
    )  # fmt: skip
    found = ply_landing.landing(block, state, history, facing)
    assert found is not None and len(found.rows) > 0
    sliding = block.friction_state(state, ply_landing.landed(block, state, history, facing), facing)
    assert np.abs(sliding.slip[found.rows]).max() < 1e-9
