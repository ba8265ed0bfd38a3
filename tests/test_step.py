"""solvers.explicit_step: a solver loop of one's own (the README example) agrees with
CentralDifference on the same model and the same fixed step."""

import numpy as np
import pytest

from elements import Cable, MindlinShell
from femcore import Mesh, Model
from femcore.rotation import rotate_about
from materials import ElasticShell
from solvers import CentralDifference, LumpedMasses, Step, explicit_step
from solvers.dynamics import EnergyAccount, damped_velocity
from solvers.step import advance, angular_rates, rotational_update


def hanging_cable():
    """A 100 mm cable held at one end, released horizontal under gravity."""
    mesh = Mesh.line((0.0, 0.0, 0.0), (100.0, 0.0, 0.0), 20)
    model = Model(mesh)
    model.add(Cable(axial_stiffness=5e3, mass_per_length=1e-6))
    model.fix("start")
    model.gravity((0.0, 0.0, -9810.0))
    return mesh, model, mesh.nodes("end")


def cantilever():
    """A Mindlin strip clamped on the left, a tip load on the right (rotations)."""
    mesh = Mesh.rectangle(100.0, 10.0, nx=5, ny=1)
    model = Model(mesh)
    model.add(MindlinShell(ElasticShell(E=70e3, nu=0.3, thickness=1.0, density=2.7e-9)))
    model.fix("left")
    tip = mesh.nodes("right")
    model.force(tip, (0.0, 0.0, -0.2 / len(tip)))
    return mesh, model, tip


def own_loop(mesh, model, tip, steps, damping, print_every):
    """The README example: a fixed-step explicit loop with damping that prints the tip
    displacement. Returns (the compiled model, the last state, dt)."""
    compiled = model.compile()
    state = compiled.initial_state()
    masses = LumpedMasses.of(compiled, state)
    dt = 0.9 * compiled.stable_dt(state)
    previous = 0.0  # from rest: the first step is a half step in velocity
    for i in range(steps):
        step = explicit_step(compiled, state, dt, masses, dt_prev=previous, damping=damping,
                             duration=steps * dt)  # fmt: skip
        state, previous = compiled.commit(step.state), dt
        if (i + 1) % print_every == 0:
            moved = state.positions[tip] - compiled.reference_positions[tip]
            print(f"t = {state.time:.4f} s: tip displacement {moved.mean(axis=0)} mm")
    return compiled, state, dt


@pytest.mark.parametrize(
    "example, steps, damping",
    [(hanging_cable, 1000, 5.0), (cantilever, 150, 200.0)],
    ids=["cable", "mindlin"],
)
def test_the_own_loop_agrees_with_central_difference(example, steps, damping, capsys):
    mesh, model, tip = example()
    compiled, state, dt = own_loop(mesh, model, tip, steps, damping, print_every=steps // 5)
    assert capsys.readouterr().out.count("tip displacement") == 5
    solver = CentralDifference(duration=steps * dt, dt=dt, damping=damping, progress=False)
    result = solver.solve(example()[1])
    assert result.steps == steps
    moved = np.abs(state.positions - compiled.reference_positions).max()
    assert moved > 1e-3  # it moved: the comparison means something
    # The same operations in the same order, but for CentralDifference's last step, which
    # ends on the duration exactly (duration - t instead of dt: round-off).
    assert state.positions == pytest.approx(result.positions, rel=0.0, abs=1e-9 * moved)
    turning = compiled.has_rotation  # (the frames hold no directors elsewhere)
    assert state.directors[turning] == pytest.approx(result.directors[turning], abs=1e-9)


def test_a_step_reports_its_state_reactions_and_energy():
    _, model, _ = cantilever()
    compiled = model.compile()
    state = compiled.initial_state()
    masses = LumpedMasses.of(compiled, state)
    dt = 0.5 * compiled.stable_dt(state)
    first = explicit_step(compiled, state, dt, masses, dt_prev=0.0, checking=True)
    assert isinstance(first, Step)
    assert first.state.time == dt and state.time == 0.0  # the given state is left unchanged
    assert first.reactions.shape == first.reaction_moments.shape == (compiled.n_nodes, 3)
    assert len(first.energy) == 8 and first.kinetic_energy > 0.0
    # The tip load pulls down, the clamp holds: its first reactions do not push down.
    assert first.reactions[:, 2].sum() >= 0.0
    second = explicit_step(compiled, compiled.commit(first.state), dt, masses)  # dt_prev = dt
    assert second.state.time == pytest.approx(2 * dt)
    assert masses.inverse_mass.shape == (compiled.n_nodes, 1)


def turned_plate(fix_rotations: bool, cells: tuple[int, int] = (6, 4)):
    """A Mindlin plate of ``cells`` squares along x and y, pinned on its left edge (alpha and
    beta held there too with ``fix_rotations``), in a tilted, moving state with a directed
    moment at every node."""
    mesh = Mesh.rectangle(60.0, 40.0, nx=cells[0], ny=cells[1])
    model = Model(mesh)
    model.add(MindlinShell(ElasticShell(E=70e3, nu=0.3, thickness=1.0, density=2.7e-9)))
    model.fix("left", ["ux", "uy", "uz", "alpha", "beta"] if fix_rotations else ["ux", "uz"])
    model.moment(mesh.nodes("right"), (0.0, 5.0, 1.0))
    compiled = model.compile()
    state = compiled.initial_state()
    rng = np.random.default_rng(11)
    state.positions = state.positions + rng.normal(scale=0.2, size=state.positions.shape)
    tilt = np.cross(state.directors, rng.normal(scale=0.3, size=state.positions.shape))
    state.directors = rotate_about(state.directors, tilt)
    state.velocities = rng.normal(scale=10.0, size=state.positions.shape)
    spin = rng.normal(scale=5.0, size=state.positions.shape)
    state.angular_velocities = np.cross(state.directors, spin)
    return compiled, state


@pytest.mark.parametrize("fix_rotations", [False, True])
@pytest.mark.parametrize("checking", [False, True])
@pytest.mark.parametrize("cells", [(6, 4), (60, 40)])
def test_the_fused_rotational_update_is_the_numpy_one(fix_rotations, checking, cells):
    """explicit_step's one compiled pass over the nodes (solvers/turning.py) gives the
    directors, positions, angular velocities, support moments and energy terms of
    ``rotational_update``, the public pieces in numpy, to 1e-12, with damping and a
    variable step; on 35 nodes (one chunk of the energy sums) and 2501 (three chunks of
    femcore.jit.CHUNK)."""
    compiled, state = turned_plate(fix_rotations, cells)
    masses = LumpedMasses.of(compiled, state)
    dt = 0.5 * compiled.stable_dt(state)
    step = explicit_step(
        compiled, state, dt, masses, dt_prev=0.8 * dt, damping=300.0, checking=checking
    )
    f_ext, m_ext = compiled.external_load(0.0)
    moved, reaction_moments, turning = rotational_update(
        compiled,
        state,
        dt,
        masses,
        (m_ext, compiled.internal_force(state)[1]),
        step.state.velocities,
        0.8 * dt,
        300.0,
        checking,
    )
    assert np.abs(step.state.angular_velocities).max() > 1.0  # it turns
    for name in ("positions", "directors", "angular_velocities"):
        mine, reference = getattr(step.state, name), getattr(moved, name)
        assert np.abs(mine - reference).max() <= 1e-12 * np.abs(reference).max(), name
    scale = np.abs(step.state.angular_velocities).max() * masses.inertia.max() / dt
    if fix_rotations:  # the held alpha and beta push back
        assert np.abs(reaction_moments).max() > 1e-3 * scale
    assert np.abs(step.reaction_moments - reaction_moments).max() <= 1e-12 * scale
    without = explicit_step(compiled, state, dt, masses, dt_prev=0.8 * dt, damping=300.0,
                            checking=checking)  # fmt: skip
    assert without.energy == step.energy  # the same numbers on every call
    translation = EnergyAccount.increments(
        (f_ext + step.reactions, compiled.internal_force(state)[0]),
        (state.velocities, step.state.velocities),
        masses.mass,
        300.0,
        0.8 * dt,
        dt,
        checking,
    )
    expected = [a + b for a, b in zip(translation, turning)]
    assert step.energy == pytest.approx(expected, rel=1e-12, abs=1e-12 * max(map(abs, expected)))


@pytest.mark.parallel
def test_a_step_is_the_same_to_the_last_bit_on_one_thread_and_on_all():
    """The velocity and rotation updates run over the nodes on the threads (solvers/
    dynamics.py, turning.py) and sum their energy terms by chunks of nodes in one order: a
    checked step of a 2501-node plate (three chunks) gives the same state, reactions and
    energy terms on one thread as on all of numba's threads."""
    import numba

    compiled, state = turned_plate(True, (60, 40))
    masses = LumpedMasses.of(compiled, state)
    dt = 0.5 * compiled.stable_dt(state)
    steps = []
    for threads in (1, numba.config.NUMBA_NUM_THREADS):
        numba.set_num_threads(threads)
        steps.append(explicit_step(compiled, state, dt, masses, dt_prev=0.8 * dt, damping=300.0,
                                   checking=True))  # fmt: skip
    one, every = steps
    assert every.energy == one.energy
    for name in ("positions", "directors", "velocities", "angular_velocities"):
        np.testing.assert_array_equal(getattr(every.state, name), getattr(one.state, name))
    np.testing.assert_array_equal(every.reactions, one.reactions)
    np.testing.assert_array_equal(every.reaction_moments, one.reaction_moments)


def test_a_checked_step_carries_the_strain_energy_of_its_state():
    """The strain energy the checks need comes with the force pass, on checked steps only."""
    compiled, state = turned_plate(False)
    masses = LumpedMasses.of(compiled, state)
    dt = 0.5 * compiled.stable_dt(state)
    checked = explicit_step(compiled, state, dt, masses, checking=True)
    assert checked.strain_energy == compiled.strain_energy(state) > 0.0
    assert explicit_step(compiled, state, dt, masses).strain_energy is None


@pytest.mark.parametrize("fix_rotations", [False, True])
def test_angular_rates_and_advance_are_the_numpy_passes(fix_rotations):
    """The one-loop angular_rates and advance dynamic relaxation moves with give the numpy
    passes' values (damped_velocity, constrain_angular, DofManager.move) to 1e-12."""
    compiled, state = turned_plate(fix_rotations)
    masses = LumpedMasses.of(compiled, state)
    rng = np.random.default_rng(8)
    moment = rng.normal(scale=50.0, size=state.positions.shape)
    free, held = angular_rates(
        compiled, state.angular_velocities, moment, masses.inverse_inertia, 1e-6, 40.0,
        state.directors,
    )  # fmt: skip
    expected = damped_velocity(state.angular_velocities, moment, masses.inverse_inertia, 1e-6, 40.0)
    assert np.abs(free - expected).max() <= 1e-12 * np.abs(expected).max()
    constrained = compiled.constrain_angular(expected, state.directors)
    assert np.abs(held - constrained).max() <= 1e-12 * np.abs(constrained).max()
    moved = advance(compiled, state, 1e-3, state.velocities, held)
    reference = compiled.dofs.move(state, 1e-3 * state.velocities, 1e-3 * held)
    for name in ("positions", "directors"):
        mine, theirs = getattr(moved, name), getattr(reference, name)
        assert np.abs(mine - theirs).max() <= 1e-12 * np.abs(theirs).max(), name
    assert np.abs(moved.directors - state.directors).max() > 1e-6  # it turned
