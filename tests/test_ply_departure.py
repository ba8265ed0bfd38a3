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

from elements import MindlinShell, ply_projection
from elements.ply_block import PlyContactBlock
from elements.ply_contact import PlyContact
from elements.ply_friction import PlyFrictionHistory
from femcore import Mesh, Model
from materials import ElasticShell
from solvers import Static
from solvers.step import LumpedMasses, explicit_step

MU = 0.3
HALF = 0.1  # mm, each ply's half thickness: the faces lie HALF from the mid-surfaces
T_STICK, T_LIFT = 0.2, 0.713  # the shares of the run where the points start sliding and lift
VZ = 0.1  # mm up over the run
PEN0 = VZ * T_LIFT  # mm, the faces' overlap at the start
VX = MU * VZ * (T_LIFT / T_STICK - 1.0)  # mm along x over the run: t_s = T_STICK
PENALTY = 50.0  # N/mm per point
STEPS = 40
DURATION = 1.0e-4  # s


def lifted_plies(surface: str = "flat") -> Model:
    """The two plies (module docstring): the lower one held (but a far corner free along z,
    which no contact reaches, so that Static has an unknown), the upper one carried; the
    contact's faces ``surface`` ("flat" or "curved": the Phong patches of a flat ply are its
    facets)."""
    lower = Mesh.rectangle(6.0, 6.0, nx=3, ny=3)
    upper = Mesh.rectangle(2.0, 2.0, nx=2, ny=2, origin=(0.7, 0.9, 2 * HALF - PEN0))
    count, cells = len(lower.points), len(lower.triangles)
    nodes = count + len(upper.points)
    mesh = Mesh(
        np.vstack([lower.points, upper.points]),
        triangles=np.vstack([lower.triangles, upper.triangles + count]),
        node_sets={"lower": np.arange(count), "upper": np.arange(count, nodes)},
        element_sets={
            "lower": np.arange(cells),
            "upper": np.arange(cells, cells + len(upper.triangles)),
        },
    )
    model = Model(mesh)
    shell = ElasticShell(E=70e3, nu=0.3, thickness=2 * HALF, density=2.7e-9)
    for name in ("lower", "upper"):
        model.add(MindlinShell(shell), cells=name)
    contact = PlyContact(
        "upper",
        "lower",
        HALF,
        HALF,
        penalty=PENALTY,
        rule="gauss",
        smoothing=0.0,
        friction=MU,
        surface=surface,
    )
    model.interact(contact)
    model.fix(np.arange(count - 1))
    model.fix([count - 1], ("ux", "uy", "alpha", "beta"))
    model.fix(np.arange(count, nodes), ("alpha", "beta"))
    model.displace(np.arange(count, nodes), ux=VX, uy=0.0, uz=VZ, amplitude="linear")
    return model


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
    model = lifted_plies()
    compiled = model.compile()
    state = compiled.initial_state()
    masses = LumpedMasses.of(compiled, state)
    previous, dt = 0.0, DURATION / STEPS
    for _ in range(STEPS):
        outcome = explicit_step(compiled, state, dt, masses, dt_prev=previous, duration=DURATION)
        state, previous = compiled.commit(outcome.state), dt
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
    committed: list[PlyFrictionHistory] = []
    accept = PlyContactBlock.update_history

    def watched(block, state, history):
        committed.append(accept(block, state, history))
        return committed[-1]

    monkeypatch.setattr(PlyContactBlock, "update_history", watched)
    model = lifted_plies()
    result = Static(increments=increments, progress=False).solve(model)
    assert result.converged and len(committed) == increments
    last = committed[-1]
    dissipation, slip = coulomb(model.compile().interactions[0])
    assert np.all(last.triangle < 0)  # every point off the face at the end
    np.testing.assert_allclose(last.slip, slip, rtol=1e-12)
    assert last.dissipated == pytest.approx(dissipation, rel=1e-12)


def stepped(compiled: bool, steps: int, surface: str = "flat") -> PlyFrictionHistory:
    """The block's history stepped over the carried states by the compiled passes or the
    numpy reference (the explicit solver's and Static's acceptance alike), on ``surface``
    faces."""
    ply_projection.COMPILED = compiled
    compiled_model = lifted_plies(surface).compile()
    block = compiled_model.interactions[0]
    state = compiled_model.initial_state()
    upper = np.unique(block.above)
    history = block.initial_history()
    for step in range(1, steps + 1):
        positions = state.positions.copy()
        positions[upper] += np.array([VX, 0.0, VZ]) * step / steps
        history = block.update_history(dataclasses.replace(state, positions=positions), history)
    return history


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
