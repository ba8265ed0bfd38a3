"""Normal contact damping (elements/contact_damping.py): a plate hit by a rigid plane moving
at a constant speed leaves it with the closed-form restitution of a mass on a damped spring,
exp(-zeta pi / sqrt(1 - zeta^2)); critically damped it does not leave; the energy the damping
takes out is reported and closes the energy balance; the quasi-static solvers see no force."""

from __future__ import annotations

import math

import numpy as np
import pytest

from elements import MindlinShell, RigidPlane
from elements.contact import Contact
from elements.contact_damping import DampedContactBlock, damped_spring
from femcore import Mesh, Model
from materials import ElasticShell
from solvers import CentralDifference

SPEED, GAP, DURATION = 100.0, 0.05, 0.002  # mm/s, mm, s: the plane meets the plate at 0.5 ms
DT = 5e-7  # s: the contact spring's omega dt = 0.2, its period 30 steps


def _plate_hit_by_a_plane(zeta: float) -> Model:
    """A free 2 x 2-cell plate 0.05 mm above the reach of a plane below it that moves up at
    SPEED: each node meets the plane at once on its own spring (the automatic penalty is
    proportional to the node's mass, and so is the damping), so the plate moves as a rigid
    body, a mass on a damped spring in the plane's frame."""
    flat = Mesh.rectangle(20.0, 20.0, nx=2, ny=2)
    model = Model(flat.with_points(flat.points + [0.0, 0.0, 0.5 + GAP]))
    model.add(MindlinShell(ElasticShell(E=1000.0, nu=0.3, thickness=1.0, density=1e-9)))
    model.contact(RigidPlane((0, 0, 0), (0, 0, 1), motion=(0, 0, SPEED * DURATION)), damping=zeta)
    return model


def _bounce(zeta: float, dt: float | None = DT):
    run = CentralDifference(duration=DURATION, dt=dt, kinetic_bound=None, progress=False).solve(
        _plate_hit_by_a_plane(zeta)
    )
    velocity = run.frames[-1].velocities[:9, 2]
    assert np.ptp(velocity) < 1e-9 * SPEED  # a rigid motion
    return run, (float(velocity.mean()) - SPEED) / SPEED  # the speed it leaves with / SPEED


@pytest.mark.parametrize("zeta", [0.2, 0.5])
def test_a_damped_contact_returns_the_closed_form_share_of_the_energy(zeta):
    """Restitution of a Kelvin-Voigt contact, e = exp(-zeta pi / sqrt(1 - zeta^2)) (the mass
    leaves the spring after half a damped period): 0.527 and 0.163 of the approach speed,
    e^2 of its energy in the plane's frame. Central difference at omega dt = 0.2 (a contact
    period of 30 steps) has measured 0.532 and 0.164; within 2 % (its error is O(omega dt),
    the force lagging the velocity by half a step). The energy the damping took, reported
    with the friction's, is 1/2 M V^2 (1 - e^2) and closes the balance (1e-3 of the work)."""
    run, restitution = _bounce(zeta)
    closed = math.exp(-zeta * math.pi / math.sqrt(1.0 - zeta**2))
    assert restitution == pytest.approx(closed, rel=0.02)
    e = run.energies
    mass = 1e-9 * 1.0 * 20.0 * 20.0  # t
    taken = 0.5 * mass * SPEED**2 * (1.0 - restitution**2)
    assert e["friction"][-1] == pytest.approx(taken, rel=1e-3)
    assert e["external_work"][-1] == pytest.approx(e["kinetic"][-1] + e["friction"][-1], rel=1e-3)
    assert run.info["energy_balance_error"] < 1e-2


def test_an_undamped_contact_returns_all_of_it_and_a_critical_one_none():
    """zeta = 0: the plate leaves at the approach speed (elastic, 1e-2); zeta = 1: it stays on
    the plane (no rebound: its speed relative to the plane below 1e-6 of the approach speed
    2.5 contact periods on), and the damping took half the plane's work, all of the plate's
    energy in the plane's frame."""
    _, elastic = _bounce(0.0)
    assert elastic == pytest.approx(1.0, rel=1e-2)
    run, critical = _bounce(1.0)
    assert abs(critical) < 1e-6
    e = run.energies
    assert e["friction"][-1] == pytest.approx(0.5 * e["external_work"][-1], rel=1e-3)


def test_the_automatic_step_takes_the_damping_in_and_stays_stable():
    """At the automatic step, critically damped: the run passes its energy checks (the lag of
    the damping force shortens the stable step; ``springs`` reports it) with a step shorter
    than the undamped contact's, and the plate does not rebound (1e-6)."""
    undamped = CentralDifference(duration=DURATION, kinetic_bound=None)._start(
        _plate_hit_by_a_plane(0.0).compile()
    )
    run, critical = _bounce(1.0, dt=None)
    assert run.converged
    assert run.info["dt"] < 0.9 * undamped.dt_nominal
    assert abs(critical) < 1e-6


def test_the_damped_spring_gives_the_stable_step_of_a_lagged_dashpot():
    """A mass alone on a spring with a dashpot acting on the velocity half a step behind:
    x(i+1) = (2 - a - b) x(i) - (1 - b) x(i-1), a = (w dt)^2, b = c dt / m, is stable while
    a + 2 b < 4 (its roots z^2 - (2 - a - b) z + (1 - b) within the unit circle). At the
    step 2 / sqrt(k' / m) of ``damped_spring``'s k', a + 2 b = 4 (the bound): 0.99 of that
    step is stable, 1.01 of it is not."""
    mass, stiffness = 2.0, 50.0
    for zeta in (0.0, 0.3, 1.0):
        c = 2.0 * zeta * math.sqrt(stiffness * mass)
        k = float(damped_spring(np.array([stiffness]), np.array([mass]), np.array([c]), 0.0)[0])
        dt = 2.0 / math.sqrt(k / mass)
        a, b = stiffness / mass * dt**2, c * dt / mass
        assert a + 2.0 * b == pytest.approx(4.0, rel=1e-12)
        for factor, stable in ((0.99, True), (1.01, False)):
            a_, b_ = a * factor**2, b * factor
            roots = np.roots([1.0, -(2.0 - a_ - b_), 1.0 - b_])
            assert bool(np.abs(roots).max() <= 1.0 + 1e-12) is stable, (zeta, factor)


def test_at_rest_the_damping_pushes_nothing():
    """The quasi-static solvers' states are at rest: with the plane moved since the last
    accepted state and the nodes in it, the damped contact's forces are the undamped one's."""
    forces = []
    for zeta in (0.0, 0.5):
        compiled = _plate_hit_by_a_plane(zeta).compile()
        state = compiled.initial_state()
        state.load_factor = state.time = 0.5  # the plane 0.05 mm into the plate's reach
        block = compiled.interactions[0]
        history = compiled.commit(state).history[-1]
        assert isinstance(block, DampedContactBlock) is (zeta > 0.0)
        forces.append(block.contact_forces(state, history))
    assert np.abs(forces[0]).max() > 0.0
    assert np.array_equal(forces[0], forces[1])


@pytest.mark.parametrize("damping", [-0.1, 1.5, float("nan"), "a lot"])
def test_contact_damping_refuses_what_is_not_a_fraction_of_critical(damping):
    with pytest.raises(ValueError, match="damping"):
        Contact(RigidPlane((0, 0, 0), (0, 0, 1)), [0], damping=damping)
