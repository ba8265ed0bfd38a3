"""A ply contact point that leaves the lower face within a step slid, in that step, up to where
its way left the face (elements/ply_departure.py, docs/theory.md §9.2 and §9.3a "Friction
between plies"): its slip and dissipation are counted to the lift-off.

The model: an upper ply (2 x 2 mm, 2 x 2 cells, Gauss points) pressed PEN0 into a lower ply
(6 x 6 mm, 3 x 3 cells) held fixed, mu = 0.3, the plain penalty (smoothing 0: N = k_p pen, the
stick spring k_t = W'' = k_p), and carried at a steady pace along x by VX and up by VZ over the
run (prescribed translations, directors held). Each point, anchored where it starts, sticks
until its offset VX t reaches the spring's hold mu pen(t), pen = PEN0 - VZ t, at t_s = mu PEN0
/ (VX + mu VZ) (0.2 of the run: a step's and an increment's end), then slides, its offset mu
pen, its anchor moving at VX + mu VZ, until it leaves the face at t_l = PEN0 / VZ (0.713 of
the run: within a step and an increment). Coulomb's dissipation of a point is

    D_p = integral of mu k_p pen(t) d(slip) = mu k_p VZ (VX + mu VZ) (t_l - t_s)^2 / 2,

its slip (VX + mu VZ)(t_l - t_s) = VX t_l (its way while touching, the spring holding nothing
at the lift-off). The normal force is linear over each step, so the record (the limit force at
the mean of a step's start and end) is that integral to round-off (asserted 1e-12 relative).
The lower face is flat and fixed and the way straight: the rule is exact.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from elements import ply_projection
from elements.ply_friction import PlyFrictionHistory
from femcore import Model
from tests.explicit_runs import run_explicitly
from tests.ply_pair import MU, moved_plies, static_histories, stepped_history

# the upper ply starts PEN0 into the lower one on purpose (the points lift off): the start
# check's overlap warning (elements/ply_start.py) is expected
pytestmark = pytest.mark.filterwarnings("ignore:.*the plies start overlapping")

T_STICK, T_LIFT = 0.2, 0.713  # the shares of the run where the points start sliding and lift
VZ = 0.1  # mm up over the run
PEN0 = VZ * T_LIFT  # mm, the faces' overlap at the start
VX = MU * VZ * (T_LIFT / T_STICK - 1.0)  # mm along x over the run: t_s = T_STICK
STEPS = 40
DURATION = 1.0e-4  # s


def lifted_plies(surface: str = "flat") -> Model:
    """The two plies (module docstring; tests/ply_pair.py), the upper one PEN0 into the lower
    one's face, carried VX along x and VZ up, on faces ``surface``."""
    return moved_plies(-PEN0, VX, VZ, surface)


def coulomb(block) -> tuple[float, float]:
    """(D, slip): the module docstring's dissipation summed over the points of the contact
    ``block``, with their penalties k_p (PENALTY shared among them), N mm, and each point's
    slip, mm."""
    stiffness = float(np.sum(block.stiffness))
    sliding = T_LIFT - T_STICK
    return MU * stiffness * VZ * (VX + MU * VZ) * sliding**2 / 2, VX * T_LIFT


def test_an_explicit_run_dissipates_coulombs_work_up_to_the_lift_off():
    """40 explicit steps: the lift-off falls 0.52 of the way through step 29. Before, the
    departure step counted no slip: 0.1898630 against 0.1899850 N mm (6.4e-4 short), each
    point's slip 0.053475 against 0.054865 mm (fails)."""
    compiled, state = run_explicitly(lifted_plies(), STEPS, DURATION)
    assert state.load_factor == pytest.approx(1.0, rel=1e-12)
    dissipation = coulomb(compiled.interactions[0])[0]
    assert compiled.dissipated_energy(state) == pytest.approx(dissipation, rel=1e-12)


@pytest.mark.parametrize("increments", [5, 10])
def test_static_counts_the_slip_of_a_departure_increment_up_to_the_lift_off(
    monkeypatch, increments
):
    """Static in 5 and 10 increments (the committed histories watched): each point slid VX
    t_l = 0.054865 mm and the dissipation is Coulomb's, 0.1899850 N mm. Before, the departure
    increment counted no slip: 0.042780 / 0.053475 mm, 0.1807669 / 0.1898630 N mm (fails)."""
    model = lifted_plies()
    last = static_histories(monkeypatch, model, increments)[-1]
    dissipation, slip = coulomb(model.compile().interactions[0])
    assert np.all(last.triangle < 0)  # every point off the face at the end
    np.testing.assert_allclose(last.slip, slip, rtol=1e-12)
    assert last.dissipated == pytest.approx(dissipation, rel=1e-12)


def stepped(compiled: bool, steps: int, surface: str = "flat") -> PlyFrictionHistory:
    """The block's history stepped over the carried states by the compiled passes or the
    numpy reference (the explicit solver's and Static's acceptance alike), on ``surface``
    faces."""
    ply_projection.COMPILED = compiled
    return stepped_history(lifted_plies(surface), np.array([VX, 0.0, VZ]), steps)[1]


@pytest.mark.parametrize("steps", [40, 5])
def test_the_compiled_and_numpy_histories_count_the_slip_to_the_lift_off(monkeypatch, steps):
    """The compiled passes and the numpy reference: Coulomb's records, the same bits."""
    monkeypatch.setattr(ply_projection, "COMPILED", ply_projection.COMPILED)
    fast, reference = stepped(True, steps), stepped(False, steps)
    dissipation, slip = coulomb(lifted_plies().compile().interactions[0])
    np.testing.assert_allclose(fast.slip, slip, rtol=1e-12)
    assert fast.dissipated == pytest.approx(dissipation, rel=1e-12)
    np.testing.assert_array_equal(fast.slip, reference.slip)
    assert fast.dissipated == reference.dissipated


def test_the_curved_faces_count_the_slip_to_the_lift_off(monkeypatch):
    """The curved faces' history (the numpy reference): a flat ply's patches are its facets,
    where the rule is exact too."""
    monkeypatch.setattr(ply_projection, "COMPILED", ply_projection.COMPILED)
    history = stepped(True, 40, "curved")
    dissipation, slip = coulomb(lifted_plies("curved").compile().interactions[0])
    np.testing.assert_allclose(history.slip, slip, rtol=1e-12)
    assert history.dissipated == pytest.approx(dissipation, rel=1e-12)


def test_a_point_pushed_along_the_face_off_its_outline_is_not_counted_a_departure():
    """A point that leaves past the lower ply's outline has no gap to its triangle's plane
    (g <= 0): no departure slip is given it (elements/ply_departure.py)."""
    compiled_model = lifted_plies().compile()
    block = compiled_model.interactions[0]
    state = compiled_model.initial_state()
    upper = np.unique(block.above)
    history = block.initial_history()
    positions = state.positions.copy()
    positions[upper] += np.array([6.0, 0.0, 0.0])  # beyond the lower ply, still below its plane
    moved = block.update_history(dataclasses.replace(state, positions=positions), history)
    assert np.all(moved.triangle < 0)
    np.testing.assert_array_equal(moved.slip, 0.0)
