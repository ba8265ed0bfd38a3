"""A dashpot on a force-driven holder (elements/dashpot.py): at the critical damping of its
mass on its contact springs the holder's force settles on its target, and the energy the
dashpot takes out keeps the explicit energy balance."""

from __future__ import annotations

import numpy as np
import pytest

from elements import MindlinShell, RigidPlane
from elements.dashpot import Dashpot, critical_damping
from femcore import Mesh, Model
from femcore.state import State
from materials import ElasticShell
from solvers import CentralDifference

SIDE, FORCE, MASS, PENALTY = 20.0, 1.0, 1e-3, 100.0  # mm, N, t, N/mm per node
DURATION = 0.05  # s: about 7 periods of the holder on its 9 springs (6.6 ms)


def holder_on_a_held_plate(
    damping: float | None, follow: float | None = None, gap: float = 0.01
) -> Model:
    """A 2 x 2-cell plate held still, a 1-kg holder ``gap`` mm above it pushed down by 1 N at
    once, its 9 contact springs of 100 N/mm; a dashpot of ``damping`` on the holder's node
    (tests/test_tool_force_watch.py lands it: gap 0)."""
    flat = Mesh.rectangle(SIDE, SIDE, nx=2, ny=2)
    model = Model(flat.with_points(flat.points + [0.0, 0.0, 0.5]))
    model.add(MindlinShell(ElasticShell(E=1000.0, nu=0.3, thickness=1.0, density=1e-9)))
    model.fix(lambda x, y, z: np.ones_like(x, dtype=bool))
    holder = RigidPlane(
        (0.0, 0.0, 1.0 + gap), (0.0, 0.0, -1.0), free="z", force=(0, 0, -FORCE), mass=MASS,
        amplitude="step",
    )  # fmt: skip
    model.contact(holder, penalty=PENALTY)
    if damping is not None:
        model.interact(Dashpot(model.rigid_nodes[0].node, damping, follow))
    return model


def _last_tenth_mean_force(run) -> float:
    times = np.array([frame.time for frame in run.frames])
    return float(np.mean(run.tool_forces[times >= 0.9 * DURATION, 0, 2]))


@pytest.mark.parametrize("follow", [None, 0.005], ids=["still", "following"])
def test_a_critically_damped_holder_carries_its_force_over_the_last_tenth(follow):
    """Undamped, the holder rings on its springs and its force over the last tenth of the
    run (shorter than a period) averages away from 1 N; with the dashpot c = 2 sqrt(k m) of
    its 900 N/mm it settles within 5 % (measured 1e-6), and when the dashpot follows the
    holder's mean velocity over 5 ms, about the period (measured 1e-3; over 10 and 20 ms
    the mean velocity of the fall lingers after the landing: 2.5 % and 17 % off)."""
    c = critical_damping(MASS, 9 * PENALTY)
    damped = CentralDifference(duration=DURATION, dt=1e-4, kinetic_bound=None).solve(
        holder_on_a_held_plate(c, follow)
    )
    assert _last_tenth_mean_force(damped) == pytest.approx(FORCE, rel=0.05)
    ringing = CentralDifference(duration=DURATION, dt=1e-4, kinetic_bound=None).solve(
        holder_on_a_held_plate(None)
    )
    assert abs(_last_tenth_mean_force(ringing) - FORCE) > 0.05 * FORCE


def test_the_dashpot_reports_the_energy_it_takes_out():
    """The holder at rest on its springs after 0.05 s: of the work F (gap + F / k) the
    springs hold F^2 / (2 k), and the dashpot reports the rest as dissipated (the friction
    column of the energy records; the internal column is what the springs hold, the work of
    every internal force less that dissipation), to 1e-3 of the work."""
    c = critical_damping(MASS, 9 * PENALTY)
    run = CentralDifference(duration=DURATION, dt=1e-4).solve(holder_on_a_held_plate(c))
    e = run.energies
    work = FORCE * (0.01 + FORCE / (9 * PENALTY))
    assert e["external_work"][-1] == pytest.approx(work, rel=1e-6)
    springs = FORCE**2 / (2 * 9 * PENALTY)
    assert e["friction"][-1] == pytest.approx(work - springs, abs=1e-3 * work)
    assert e["internal"][-1] == pytest.approx(springs, abs=1e-3 * work)


def test_a_following_dashpot_lets_a_steady_drift_through():
    """The holder's node moving up at 10 mm/s for 5 tau: a still dashpot pushes back by
    c v, one that follows its mean over tau by c v exp(-5) (the flange lifting a holder is
    no ringing to damp)."""
    c, tau, v = 2.0, 0.01, 10.0
    forces = []
    for follow in (None, tau):
        compiled = holder_on_a_held_plate(c, follow).compile()
        block = compiled.interactions[-1]
        node = int(block.nodes[0])
        history = block.initial_history()
        x = compiled.reference_positions.copy()
        velocities = np.zeros_like(x)
        velocities[node, 2] = v
        for time in np.arange(1, 51) * 1e-3:
            x[node, 2] += v * 1e-3
            state = State(x.copy(), np.zeros_like(x), velocities, np.zeros_like(x), time=time)
            history = block.update_history(state, history)
        forces.append(block.internal_force(state, history)[0][node, 2])
    assert forces[0] == pytest.approx(c * v, rel=1e-12)
    assert forces[1] == pytest.approx(c * v * np.exp(-5.0), rel=1e-9)


@pytest.mark.parametrize(
    "nodes, damping, words",
    [
        ([], 1.0, "node ids"),
        ([-1], 1.0, "negative"),
        ([0], 0.0, "positive"),
        ([0], "1", "positive"),
    ],
)
def test_a_dashpot_refuses_bad_nodes_or_damping(nodes, damping, words):
    with pytest.raises(ValueError, match=words):
        Dashpot(nodes, damping)
    with pytest.raises(ValueError, match="follow must be a positive time"):
        Dashpot([0], 1.0, follow=0.0)


def test_critical_damping_refuses_a_mass_or_stiffness_that_is_not_positive():
    assert critical_damping(1e-3, 900.0) == pytest.approx(2.0 * np.sqrt(0.9))
    with pytest.raises(ValueError, match="stiffness must be a positive number"):
        critical_damping(1e-3, 0.0)
