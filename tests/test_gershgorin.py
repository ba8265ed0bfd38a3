"""femcore.gershgorin: the explicit solver's Gershgorin bound summed per node pair without a
sparse assembly equals the row sums of the assembled |K| (femcore.assembly.tangent_matrix)."""

import dataclasses

import numpy as np
import pytest

from elements import Cable, MindlinShell
from femcore import Mesh, Model
from femcore.assembly import tangent_matrix
from femcore.gershgorin import gershgorin_largest
from femcore.rotation import rotate_about
from materials import ElasticShell


def bent_plate():
    mesh = Mesh.rectangle(40.0, 30.0, nx=5, ny=4)
    model = Model(mesh)
    model.add(MindlinShell(ElasticShell(70e3, 0.3, 1.0, 2.7e-9)))
    model.fix("left")
    model.fix("bottom", ["uz", "alpha"])
    compiled = model.compile()
    state = compiled.initial_state()
    rng = np.random.default_rng(4)
    positions = state.positions + rng.normal(scale=0.3, size=state.positions.shape)
    turn = np.cross(state.directors, rng.normal(scale=0.2, size=state.positions.shape))
    directors = rotate_about(state.directors, turn)
    return compiled, dataclasses.replace(state, positions=positions, directors=directors)


def hanging_cable():
    mesh = Mesh.line((0.0, 0.0, 0.0), (100.0, 0.0, 0.0), 12)
    model = Model(mesh)
    model.add(Cable(axial_stiffness=5e3, mass_per_length=1e-6))
    model.fix("start")
    compiled = model.compile()
    state = compiled.initial_state()
    stretched = state.positions * np.array([1.01, 1.0, 1.0]) + np.array([0.0, 0.0, 0.5])
    return compiled, dataclasses.replace(state, positions=stretched)


def assembled(compiled, state, parts, scale):
    """The same bound from the assembled sparse tangent."""
    stiffness = tangent_matrix(compiled.dofs, parts, compiled.dofs.frames(state.directors))
    free = compiled.dofs.free_slots
    rows = np.asarray(abs(stiffness) @ scale).ravel()[free] * scale[free]
    return float(rows.max())


@pytest.mark.parametrize("example", [bent_plate, hanging_cable], ids=["mindlin", "cable"])
def test_the_bound_summed_per_node_pair_is_the_assembled_one(example):
    """Rotations with fixed alpha / beta and turned directors (the plate), translations only
    (the cable): the same bound to 1e-12."""
    compiled, state = example()
    parts = compiled.tangent_parts(state, list(range(len(compiled.parts))))
    assert parts is not None
    rng = np.random.default_rng(1)
    scale = np.zeros(compiled.dofs.n_slots)
    free = compiled.dofs.free_slots
    scale[free] = rng.uniform(0.5, 2.0, size=free.size)
    maps = compiled.dofs.node_maps(compiled.dofs.frames(state.directors))
    largest = gershgorin_largest(parts, maps, scale, compiled.n_nodes)
    reference = assembled(compiled, state, parts, scale)
    assert largest == pytest.approx(reference, rel=1e-12)
    assert largest > 0.0
