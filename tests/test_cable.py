"""The cable element: what is particular to it (the tension-only option, the closed-form
stable step, bad parameters). Its conformance to the element protocol (rigid motions,
objectivity, energy gradient, tangent, mass, stable step) is checked by
tests/test_conformance.py, cases "cable" and "cable-tension-only"."""

import numpy as np
import pytest

from elements import Cable
from femcore import Mesh, Model
from femcore.state import State
from tests.conformance_cases import net_mesh


def compiled(mesh, **options):
    model = Model(mesh)
    model.add(Cable(axial_stiffness=2.0e4, mass_per_length=3.0e-9, **options))
    return model.compile()


def state_at(model, positions):
    n = model.n_nodes
    return State(positions, np.zeros((n, 3)), np.zeros((n, 3)), np.zeros((n, 3)))


def test_tension_only_cable_goes_slack_in_compression():
    mesh = Mesh(np.array([[0.0, 0, 0], [10, 0, 0]]), lines=np.array([[0, 1]]))
    model = compiled(mesh, tension_only=True)
    squeezed = state_at(model, np.array([[0.0, 0, 0], [9.0, 0, 0]]))
    assert not model.internal_force(squeezed)[0].any()
    assert model.strain_energy(squeezed) == 0.0


def test_stable_step_is_the_two_mass_bar_value_on_the_shortest_cable():
    # L / c, c = sqrt(EA / mu): two lumped masses mu L / 2 on a spring EA / L. (That it halves
    # with the cable length is checked by the conformance suite.)
    fine = compiled(net_mesh(8, 6, size=5.0))
    assert fine.stable_dt(fine.initial_state()) == pytest.approx(
        5.0 / np.sqrt(2.0e4 / 3.0e-9), rel=1e-12, abs=0.0
    )


@pytest.mark.parametrize(
    "arguments, message",
    [
        ((0.0, 1e-9), "axial_stiffness"),
        ((-5.0, 1e-9), "axial_stiffness"),
        ((1.0, 0.0), "mass_per_length"),
        ((1.0, -1e-9), "mass_per_length"),
        ((np.nan, 1e-9), "axial_stiffness"),
        (("stiff", 1e-9), "axial_stiffness"),
    ],
)
def test_bad_cable_parameters_are_named(arguments, message):
    with pytest.raises(ValueError, match=message):
        Cable(*arguments)


@pytest.mark.parallel
def test_the_compiled_kernel_gives_the_numpy_forces():
    """elements/kernels.py against the vectorised reference on a jittered chain with stretched
    and slack links (tension only): 1e-12 of the largest force."""
    points = np.column_stack([np.linspace(0.0, 100.0, 21), np.zeros(21), np.zeros(21)])
    lines = np.column_stack([np.arange(20), np.arange(1, 21)])
    jitter = np.random.default_rng(5).normal(scale=1.0, size=points.shape)
    forces = {}
    for kernel in ("numpy", "compiled"):
        model = Model(Mesh(points, lines=lines))
        model.add(Cable(1e3, 1e-9, tension_only=True, kernel=kernel))
        compiled = model.compile()
        state = compiled.initial_state()
        state.positions = state.positions + jitter
        forces[kernel] = compiled.internal_force(state)[0]
    scale = np.abs(forces["numpy"]).max()
    assert np.abs(forces["compiled"] - forces["numpy"]).max() <= 1e-12 * scale
