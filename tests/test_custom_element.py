"""An element type written outside the project, in this file, plugs into every solver.

``PlaneContact`` is what a user would write for a rigid floor: a one-sided penalty on the nodes
of a node set against the plane z = 0. It has no mesh cells (``cell_type = None``), its own
exact tangent, and a history variable (the deepest penetration each node has seen), and it
imports only the protocol (elements.base). The model is a cable laid on the floor under
gravity, its horizontal motion held; each node then sinks until the floor carries its weight.

Reference (closed form, Hooke's law of the penalty spring): penetration of node i = m_i g / k,
m_i its lumped mass (half a link at the ends). The end nodes sink half as deep as the others;
the stretch of the end links then pulls them down by EA/2 (dz/L)^3 = 6e-8 N (dz = 4.9e-3 mm,
L = 10 mm), 1.2e-6 of their weight: the reference holds to 1e-5 whatever the solver.
"""

import numpy as np
import pytest

from elements import Cable
from elements.base import CellTangent, ElementBlock, ElementType, Scatter
from femcore import Mesh, Model
from solvers import CentralDifference, DynamicRelaxation, Static

K = 10.0  # N/mm, penalty stiffness per node
EA = 1.0e3  # N
G = 9810.0  # mm/s^2
MU = 1.0e-6  # t/mm
LINKS = 10
LENGTH = 100.0  # mm


class PlaneContact(ElementType):
    """Frictionless one-sided penalty of the nodes of ``node_set`` against z = 0.

    stiffness : k, N/mm per node; energy W = 1/2 k min(z, 0)^2 per node.
    """

    dofs = ("ux", "uy", "uz")
    cell_type = None

    def __init__(self, node_set: str, stiffness: float):
        self.node_set = node_set
        self.stiffness = stiffness

    def bind(self, mesh, cell_ids, directors):
        return PlaneContactBlock(mesh.nodes(self.node_set), self.stiffness, mesh.n_nodes)


class PlaneContactBlock(ElementBlock):
    dofs = PlaneContact.dofs
    cell_type = None
    reach = 1

    def __init__(self, nodes, stiffness, n_nodes):
        self.cell_ids = np.zeros(0, dtype=np.int64)
        self.connectivity = np.asarray(nodes, dtype=np.int64)[:, None]  # one "cell" per node
        self.scatter = Scatter(self.connectivity, n_nodes)
        self.stiffness = stiffness
        self.n_nodes = n_nodes

    def _gap(self, state):
        """Signed distance of each node to the floor where it penetrates, else 0 (m,)."""
        return np.minimum(state.positions[self.connectivity[:, 0], 2], 0.0)

    def lumped_mass(self, state, density_scale=None):
        return np.zeros(self.n_nodes), None  # a rigid floor adds no mass

    def internal_force(self, state, history=None):
        per_node = np.zeros((len(self.connectivity), 1, 3))
        per_node[:, 0, 2] = self.stiffness * self._gap(state)  # dW/dz: down when inside
        return self.scatter.vectors(per_node), None

    def strain_energy(self, state, history=None):
        return float(0.5 * self.stiffness * np.sum(self._gap(state) ** 2))

    def tangent(self, state, history=None):
        blocks = np.zeros((len(self.connectivity), 1, 3, 1, 3))
        touching = state.positions[self.connectivity[:, 0], 2] <= 0.0
        blocks[:, 0, 2, 0, 2] = np.where(touching, self.stiffness, 0.0)
        return [CellTangent(self.connectivity, blocks)]

    def cell_stable_dt(self, state):
        # The floor's frequency needs the nodes' masses, which other blocks hold; the test
        # keeps sqrt(k / m) = 1000 rad/s below the cable's 6300 rad/s, so that the cable's
        # step at safety 0.9 stays stable with the floor (omega dt = 1.82 < 2).
        return np.full(len(self.connectivity), np.inf)

    def initial_history(self):
        return np.zeros(len(self.connectivity))

    def update_history(self, state, history):
        return np.maximum(history, -self._gap(state))  # a new array: history is never mutated

    def node_fields(self, state, history=None):
        deepest = np.zeros(self.n_nodes)
        if history is not None:
            deepest[self.connectivity[:, 0]] = history
        return {"deepest_penetration": deepest}


def cable_on_the_floor() -> Model:
    mesh = Mesh.line((0.0, 0.0, 0.0), (LENGTH, 0.0, 0.0), LINKS)
    mesh.add_node_set("all", np.arange(mesh.n_nodes))
    model = Model(mesh)
    model.add(Cable(axial_stiffness=EA, mass_per_length=MU))
    model.add(PlaneContact("all", K))
    model.fix("all", ("ux", "uy"))
    model.gravity((0.0, 0.0, -G))
    return model


def expected_penetration() -> np.ndarray:
    link = LENGTH / LINKS
    mass = np.full(LINKS + 1, MU * link)
    mass[[0, -1]] *= 0.5
    return mass * G / K


SOLVERS = {
    # Newton with the exact tangents of both blocks, to a residual of 1e-10: the reference's
    # own 1.2e-6 governs.
    "static": (Static(increments=2, tol=1e-10), 1e-5),
    # Kinetic damping to a residual of 1e-9 of the forces: again the reference governs.
    "relaxation": (DynamicRelaxation(tol=1e-9), 1e-5),
    # Damped dynamics, c = 500 1/s over 0.05 s: the step load's oscillation (omega = 1000
    # rad/s) decays as exp(-c t / 2) = 4e-6.
    "explicit": (CentralDifference(0.05, damping=500.0), 1e-4),
}


@pytest.mark.parametrize("name", SOLVERS)
def test_a_user_element_rests_the_cable_on_the_floor_with_every_solver(name):
    solver, tolerance = SOLVERS[name]
    result = solver.solve(cable_on_the_floor())
    penetration = -result.positions[:, 2]
    expected = expected_penetration()
    assert result.converged
    assert np.abs(penetration - expected).max() <= tolerance * expected.max()


@pytest.mark.parametrize("name", SOLVERS)
def test_the_history_of_a_user_element_is_kept_by_every_solver(name):
    solver, _ = SOLVERS[name]
    result = solver.solve(cable_on_the_floor())
    deepest = result.frames[-1].fields["point"]["deepest_penetration"]
    over_frames = np.max([-frame.positions[:, 2] for frame in result.frames], axis=0)
    # The history sees every accepted step, the frames only some of them.
    assert np.all(deepest >= over_frames - 1e-15)
    if name == "explicit":
        # Gravity is a step load: each interior node is a damped oscillator (omega = sqrt(k/m)
        # = 1000 rad/s, damping ratio c / (2 omega) = 0.25) whose first peak is
        # 1 + exp(-pi xi / sqrt(1 - xi^2)) times the static penetration. The steps sample the
        # peak within omega dt / 2 = 0.14 rad: 1% of the static value covers it.
        xi = 500.0 / (2.0 * np.sqrt(K / (MU * LENGTH / LINKS)))
        peak = 1.0 + np.exp(-np.pi * xi / np.sqrt(1.0 - xi**2))
        interior = expected_penetration()[1:-1]
        assert np.abs(deepest[1:-1] - peak * interior).max() <= 0.01 * interior.max()
    else:
        assert np.allclose(deepest, over_frames, rtol=0.0, atol=1e-15)


def test_the_user_element_tangent_is_the_derivative_of_its_force():
    compiled = cable_on_the_floor().compile()
    state = compiled.initial_state()
    state.positions = state.positions + np.column_stack(
        [np.zeros(LINKS + 1), np.zeros(LINKS + 1), -np.linspace(0.01, 0.02, LINKS + 1)]
    )
    own = compiled.stiffness(state, "element").toarray()
    numerical = compiled.stiffness(state, "finite_difference").toarray()
    assert np.abs(own - numerical).max() <= 1e-6 * np.abs(numerical).max()


def test_a_node_block_takes_no_cells_and_needs_nodes_of_a_cell_element():
    mesh = Mesh.line((0.0, 0.0, 0.0), (LENGTH, 0.0, 0.0), LINKS)
    mesh.add_node_set("all", np.arange(mesh.n_nodes))
    model = Model(mesh)
    with pytest.raises(ValueError, match="acts on nodes"):
        model.add(PlaneContact("all", K), cells=[0])
    model.add(PlaneContact("all", K))
    with pytest.raises(ValueError, match="only node blocks"):
        model.compile()


def test_an_object_that_is_not_an_element_type_is_refused():
    model = Model(Mesh.line((0.0, 0.0, 0.0), (1.0, 0.0, 0.0), 2))
    with pytest.raises(ValueError, match="not an element type"):
        model.add(object())


def test_a_block_whose_methods_do_not_take_the_history_is_named():
    class OldBlock(PlaneContactBlock):
        def internal_force(self, state):  # the protocol passes (state, history)
            return super().internal_force(state)

    class OldContact(PlaneContact):
        def bind(self, mesh, cell_ids, directors):
            return OldBlock(mesh.nodes(self.node_set), self.stiffness, mesh.n_nodes)

    model = cable_on_the_floor()
    model.add(OldContact("all", K))
    with pytest.raises(ValueError, match=r"OldBlock.internal_force must take \(state, history"):
        model.compile()
