"""Central difference on a bar: wave arrival, reflection, energy balance, divergence."""

import numpy as np
import pytest

from elements import Cable
from femcore import Body, Interaction, InteractionBlock, Mesh, Model
from solvers import CentralDifference, DivergenceError

LENGTH, N = 1000.0, 100  # mm, elements
EA, MU = 1.0e6, 1.0e-8  # N, t/mm  -> wave speed c = 1e7 mm/s
C = np.sqrt(EA / MU)
TRANSIT = LENGTH / C  # s
LOAD = 100.0  # N


def bar_model(amplitude="step"):
    points = np.column_stack([np.linspace(0, LENGTH, N + 1), np.zeros(N + 1), np.zeros(N + 1)])
    mesh = Mesh(points, lines=np.column_stack([np.arange(N), np.arange(1, N + 1)]))
    model = Model(mesh)
    model.add(Cable(EA, MU))
    model.fix([0])
    model.fix(np.arange(1, N + 1), ("uy", "uz"))
    model.force([N], (LOAD, 0.0, 0.0), amplitude=amplitude)
    return model


@pytest.fixture(scope="module")
def wave():
    solver = CentralDifference(duration=2.8 * TRANSIT, output_interval=TRANSIT / 200)
    return solver.solve(bar_model())


def test_the_wave_reaches_the_fixed_end_after_L_over_c(wave):
    # Reference: 1-D wave equation, a step load travels at c = sqrt(EA/mu). The lumped-mass
    # central difference smears the front over a few elements: allow 3 element transits.
    times = wave.times
    support = -np.array([f.reactions[0, 0] for f in wave.frames])
    arrival = times[np.argmax(support > LOAD)]
    assert arrival == pytest.approx(TRANSIT, abs=3 * TRANSIT / N)
    assert np.abs(support[times < 0.9 * TRANSIT]).max() < 0.01 * LOAD


def test_the_reflection_doubles_the_load_at_the_fixed_end(wave):
    # Reference: reflection at a fixed end doubles the stress: the support force is 2F between
    # L/c and 3L/c. The discrete front rings (Gibbs), so compare the mean over the plateau (2 %).
    times = wave.times
    support = -np.array([f.reactions[0, 0] for f in wave.frames])
    plateau = (times > 1.2 * TRANSIT) & (times < 2.8 * TRANSIT)
    assert support[plateau].mean() == pytest.approx(2 * LOAD, rel=0.02)


def test_undamped_energy_balance_holds(wave):
    # Kinetic + internal - external work = 0 for an undamped elastic system (0.5 % of the work).
    e = wave.energies
    balance = e["kinetic"] + e["internal"] - e["external_work"]
    assert e["external_work"][-1] > 0
    assert np.abs(balance).max() < 5e-3 * e["external_work"][-1]


def test_accumulated_internal_work_is_the_strain_energy(wave):
    # The internal work is integrated step by step; for an elastic bar it must equal the strain
    # energy evaluated directly from the final configuration (1 %).
    from femcore.state import State

    model = bar_model().compile()
    last = wave.frames[-1]
    state = State(last.positions, last.directors, last.velocities, np.zeros_like(last.velocities))
    assert wave.energies["internal"][-1] == pytest.approx(model.strain_energy(state), rel=1e-2)


def test_damping_removes_the_motion():
    # Mass-proportional damping well above the fundamental frequency: the bar creeps to its
    # static elongation F L / EA (exact for a uniform bar).
    omega_1 = np.pi / 2 * C / LENGTH
    solver = CentralDifference(duration=30 * TRANSIT, damping=4 * omega_1)
    result = solver.solve(bar_model())
    assert result.displacements[N, 0] == pytest.approx(LOAD * LENGTH / EA, rel=1e-3)
    assert result.energies["damping"][-1] > 0


def test_a_too_large_step_diverges_with_a_clear_error_and_keeps_the_last_good_frame():
    solver = CentralDifference(duration=5 * TRANSIT, dt=3 * TRANSIT / N)
    with pytest.raises(DivergenceError, match="diverged") as error:
        solver.solve(bar_model())
    result = error.value.result
    assert not result.converged
    assert np.all(np.isfinite(result.frames[-1].positions))


def test_mass_scaling_reaches_the_target_step_and_reports_the_added_mass():
    target = 2.0 * TRANSIT / N
    solver = CentralDifference(duration=TRANSIT, mass_scaling_dt=target)
    result = solver.solve(bar_model())
    # The cells reach the target; the assembly's Gershgorin bound, the smaller of the two on
    # the scaled bar, takes 5 % off it (and the tension a little geometric stiffness).
    assert 0.9 * target < result.info["dt"] <= target * (1.0 + 1e-3)
    # dt ~ sqrt(m). The step taken is safety x the cells' stable step, so every cell must reach
    # target / safety = (2 / 0.9) L/c: its mass grows by (2 / 0.9)^2.
    assert result.info["added_mass_ratio"] == pytest.approx((2.0 / 0.9) ** 2 - 1.0, rel=1e-9)


def test_stable_step_follows_the_element_size():
    # Lumped two-node bar: dt_crit = L_e / c exactly; halving the element halves the step.
    model = bar_model().compile()
    dt = model.stable_dt(model.initial_state())
    assert dt == pytest.approx(LENGTH / N / C, rel=1e-6)


def test_frames_follow_the_output_interval():
    result = CentralDifference(duration=TRANSIT, output_interval=TRANSIT / 4).solve(bar_model())
    assert result.times / TRANSIT == pytest.approx([0, 0.25, 0.5, 0.75, 1.0], abs=0.02)
    assert result.steps > N


# ---------------------------------------------------------------------- blow-ups of any speed
SPAN, LINKS_ACROSS = 100.0, 20  # mm, elements: a slack cable between two fixed ends


def hanging_cable() -> Model:
    points = np.column_stack(
        [
            np.linspace(0, SPAN, LINKS_ACROSS + 1),
            np.zeros(LINKS_ACROSS + 1),
            np.zeros(LINKS_ACROSS + 1),
        ]
    )
    lines = np.column_stack([np.arange(LINKS_ACROSS), np.arange(1, LINKS_ACROSS + 1)])
    model = Model(Mesh(points, lines=lines))
    model.add(Cable(axial_stiffness=1e3, mass_per_length=1e-9))
    model.fix([0, LINKS_ACROSS])
    model.gravity((0.0, 0.0, -9810.0))
    return model


def critical_step() -> float:
    compiled = hanging_cable().compile()
    return compiled.stable_dt(compiled.initial_state())


@pytest.fixture(scope="module")
def stable_swing():
    """The reference: the same cable at 0.9 of its critical step for 0.02 s."""
    return CentralDifference(duration=0.02, dt=0.9 * critical_step(), progress=False).solve(
        hanging_cable()
    )


def test_below_the_critical_step_the_energy_balance_holds(stable_swing):
    assert stable_swing.converged
    # The scheme conserves KE* + U exactly on a linear model; the cable's geometric
    # nonlinearity leaves 6e-5 of the largest energy.
    assert stable_swing.info["energy_balance_error"] < 1e-3
    # From rest under a step load, kinetic plus strain energy is the work done (1) up to the
    # time discretisation.
    assert stable_swing.info["energy_growth"] < 1.01


@pytest.mark.parametrize("duration", [0.02, 0.1])
@pytest.mark.parametrize("factor", [1.02, 1.05, 1.10])
def test_a_step_just_beyond_the_critical_one_is_caught(factor, duration, stable_swing):
    """Above the critical step the highest mode grows by a little each step: the strain
    energy grows with the kinetic, which a check of the kinetic energy against the work and
    the internal work did not see (it returned 6e80 mm as converged). The run stops with the
    frames that passed the checks: they stay within the envelope of the stable motion."""
    solver = CentralDifference(duration=duration, dt=factor * critical_step(), progress=False)
    with pytest.raises(DivergenceError, match="grown to") as error:
        solver.solve(hanging_cable())
    result = error.value.result
    assert not result.converged
    envelope = max(
        np.abs(f.positions - stable_swing.frames[0].positions).max() for f in stable_swing.frames
    )
    for frame in result.frames:
        assert np.abs(frame.positions - result.frames[0].positions).max() <= envelope


def test_a_refreshed_rotary_inertia_keeps_each_nodes_rotational_kinetic_energy():
    """The explicit solver refreshes the rotary inertia as the directors tilt (their lever
    grows up to 25-fold at the guard); the angular velocities are scaled so that 1/2 I w^2 is
    kept at each node, which the energy balance would otherwise see made without work."""
    from femcore.state import State
    from solvers.explicit import _keep_rotary_energy

    rng = np.random.default_rng(0)
    before, after = np.array([1.0, 2.0, 0.0]), np.array([60.0, 2.0, 0.0])
    omega = rng.normal(size=(3, 3))
    state = State(np.zeros((3, 3)), np.tile([0.0, 0.0, 1.0], (3, 1)), np.zeros((3, 3)), omega)
    kept = _keep_rotary_energy(state, before, after)
    energy = 0.5 * np.sum(omega**2, axis=1)
    assert np.allclose(after[:2] * 0.5 * np.sum(kept.angular_velocities[:2] ** 2, axis=1),
                       before[:2] * energy[:2], rtol=1e-12)  # fmt: skip
    assert np.array_equal(kept.angular_velocities[2], omega[2])  # no inertia: left alone
    assert np.array_equal(state.angular_velocities, omega)  # the state given is unchanged


class _EnergyStep(Interaction):
    """A stored energy ``jump`` (N mm) that appears, with no force, once ``node`` passes x =
    ``at`` (mm): what a contact point does when it changes its facing facet under a deep
    penetration (the energy of the new facet's plane is not the old one's)."""

    dofs = ("ux", "uy", "uz")

    def __init__(self, node: int, at: float, jump: float):
        self.node, self.at, self.jump = node, at, jump

    def bind(self, body: Body) -> "_EnergyStepBlock":
        return _EnergyStepBlock(self.node, self.at, self.jump, body.n_nodes)


class _EnergyStepBlock(InteractionBlock):
    dofs = _EnergyStep.dofs
    reach = 1
    n_tools = 0

    def __init__(self, node: int, at: float, jump: float, n_nodes: int):
        self.connectivity = np.array([[node]])
        self.node, self.at, self.jump, self.n_nodes = node, at, jump, n_nodes

    def internal_force(self, state, history=None):
        return np.zeros((self.n_nodes, 3)), None

    def strain_energy(self, state, history=None):
        return self.jump if state.positions[self.node, 0] > self.at else 0.0

    def tangent(self, state, history=None):
        return []


def test_a_failed_energy_balance_names_the_part_whose_energy_jumped():
    # The loaded end moves at F / sqrt(EA mu) = 1000 mm/s until the wave comes back; an
    # energy of 1 N mm appears without work when it passes 0.05 mm, against F x 0.05 mm =
    # 5 N mm of work by then: the balance is off by 0.2, four times its tolerance, at any
    # step size. The message names the part and the jump, so that the cause is not sought in
    # the step (the old message said only "Reduce dt or safety").
    model = bar_model()
    model.interact(_EnergyStep(N, LENGTH + 0.05, 1.0))
    solver = CentralDifference(duration=3 * TRANSIT, safety=0.5)
    with pytest.raises(DivergenceError, match="energy balance") as error:
        solver.solve(model)
    assert "part 1 of 2 (_EnergyStepBlock): +1 N mm" in str(error.value)
