"""A tool contact's stored energy (elements/contact.py ``ContactBlock.strain_energy``): 1/2 k p^2
plus the tangential springs' 1/2 |f_t|^2 / k_t (docs/theory.md §9). Without friction the
springs' term is 0 / k_t, +0 wherever k_t > 0, and the energy is 1/2 sum k p^2 to the bit:
the explicit energy check asks it every tenth step without making the zero arrays. The
reference is the whole formula, written out here."""

import numpy as np
import pytest

from elements import MindlinShell, RigidPlane, RigidSphere
from femcore import Mesh, Model
from materials import ElasticShell


def _pressed(tool, friction=0.0, penalty=None):
    """A 40 x 40 mm Mindlin plate on z = 0, its nodes pushed down by up to 0.3 mm (random,
    some off the tool), against ``tool``; (compiled model, state)."""
    mesh = Mesh.rectangle(40.0, 40.0, nx=5, ny=5)
    mesh = mesh.with_points(mesh.points + [-20.0, -20.0, 0.5])
    model = Model(mesh)
    model.add(MindlinShell(ElasticShell(E=70e3, nu=0.3, thickness=1.0, density=2.7e-9)))
    model.contact(tool, friction=friction, penalty=penalty)
    compiled = model.compile()
    state = compiled.initial_state()
    state.positions[:, 2] -= np.random.default_rng(4).uniform(-0.2, 0.3, len(mesh.points))
    return compiled, state


def _whole_formula(block, state, history):
    p, n, touching = block.touch(state, history)
    friction, *_ = block.tangential(state, history, p, n, touching)
    stick = block.stiffness * block.stick_ratio
    return float(0.5 * np.sum(block.stiffness * p**2 + np.sum(friction**2, axis=1) / stick))


@pytest.mark.parametrize(
    "tool",
    [RigidPlane((0.0, 0.0, 0.0), (0.0, 0.0, 1.0)), RigidSphere((0.0, 0.0, -500.0), 500.0)],
    ids=["plane", "sphere"],
)
def test_a_frictionless_contact_s_energy_is_the_whole_formula_s_to_the_bit(tool):
    compiled, state = _pressed(tool)
    block = compiled.interactions[0]
    history = compiled._histories(state)[len(compiled.blocks)]
    energy = block.strain_energy(state, history)
    assert energy > 0.0
    assert (
        np.float64(energy).tobytes() == np.float64(_whole_formula(block, state, history)).tobytes()
    )


@pytest.mark.filterwarnings("ignore:invalid value encountered")
@pytest.mark.parametrize("stiffness", [0.0, np.nan], ids=["zero", "unset"])
def test_a_node_without_penalty_keeps_the_whole_formula_s_nan(stiffness):
    """k = 0 at a node (0 / 0 in the springs' term) or no penalty set (NaN, a contact
    without ``penalty`` before the solver calibrates it): NaN, as before (not hidden)."""
    compiled, state = _pressed(RigidPlane((0.0, 0.0, 0.0), (0.0, 0.0, 1.0)))
    block = compiled.interactions[0]
    block.stiffness = block.stiffness.copy()
    block.stiffness[3] = stiffness
    history = compiled._histories(state)[len(compiled.blocks)]
    assert np.isnan(block.strain_energy(state, history))
    assert np.isnan(_whole_formula(block, state, history))


def test_a_frictional_contact_s_energy_holds_its_stick_springs():
    """With friction and anchors the springs' term counts: the energy exceeds 1/2 sum k p^2
    and is the whole formula's."""
    compiled, state = _pressed(RigidPlane((0.0, 0.0, 0.0), (0.0, 0.0, 1.0)), friction=0.3)
    block = compiled.interactions[0]
    history = compiled._histories(state)[len(compiled.blocks)]
    state.positions[:, 0] += 1e-4  # the anchored nodes slid a little: stick springs loaded
    energy = block.strain_energy(state, history)
    p, _, _ = block.touch(state, history)
    assert energy == _whole_formula(block, state, history)
    assert energy > 0.5 * np.sum(block.stiffness * p**2)
