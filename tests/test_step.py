"""solvers.explicit_step: a solver loop of one's own (the README example) agrees with
CentralDifference on the same model and the same fixed step."""

import numpy as np
import pytest

from elements import Cable, MindlinShell
from femcore import Mesh, Model
from materials import ElasticShell
from solvers import CentralDifference, LumpedMasses, Step, explicit_step


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
