"""Interactions written outside the project, in this file, plug into every solver.

An interaction (femcore.interaction) acts on nodes that elements carry, with no cells or mass
of its own. Both below import only that protocol (and the ``CellTangent`` of its tangent):

``PlaneContact`` is what a user would write for a rigid floor: a one-sided penalty on the nodes
of a node set against the plane through the origin with unit normal n (z = 0 by default), its
own exact tangent, a history variable (the deepest penetration each node has seen) and a node
field. The model is a cable laid on the floor under gravity, its horizontal motion held; each
node then sinks until the floor carries its weight. Reference (closed form, Hooke's law of the
penalty spring): penetration of node i = m_i g / k, m_i its lumped mass (half a link at the
ends). The end nodes sink half as deep as the others; the stretch of the end links then pulls
them down by EA/2 (dz/L)^3 = 6e-8 N (dz = 4.9e-3 mm, L = 10 mm), 1.2e-6 of their weight: the
reference holds to 1e-5 whatever the solver.

``SpringTie`` joins node pairs (a, b) by springs of stiffness k, energy 1/2 k |x_a - x_b -
(X_a - X_b)|^2. The model is two cables end to end, the end of the first tied to the start of
the second (coincident nodes), one end fixed and the far end pulled by P: the cables and the
tie are linear in their stretch, so the far end moves P (L1 / EA + 1 / k + L2 / EA) and the
support carries -P, exactly.
"""

from typing import Any

import numpy as np
import pytest

from elements import Cable
from elements.base import CellTangent
from femcore import Body, Interaction, InteractionBlock, Mesh, Model
from solvers import CentralDifference, DynamicRelaxation, Static
from tests.test_custom_element import ramp_then_hold, settling_explicit

K = 10.0  # N/mm, penalty stiffness per node
EA = 1.0e3  # N
G = 9810.0  # mm/s^2
MU = 1.0e-6  # t/mm
LINKS = 10
LENGTH = 100.0  # mm


class PlaneContact(Interaction):
    """Frictionless one-sided penalty of the nodes of ``node_set`` against the plane through
    the origin with unit ``normal`` (the body on its side).

    stiffness : k, N/mm per node; energy W = 1/2 k min(x . n, 0)^2 per node.
    """

    dofs = ("ux", "uy", "uz")
    block_class: type["PlaneContactBlock"]  # (set below it; the floors below bind their own)

    def __init__(self, node_set, stiffness: float, normal=(0.0, 0.0, 1.0)):
        self.node_set, self.stiffness = node_set, stiffness
        self.normal = np.asarray(normal, dtype=float) / np.linalg.norm(normal)

    def bind(self, body: Body) -> "PlaneContactBlock":
        nodes = body.mesh.nodes(self.node_set) if isinstance(self.node_set, str) else self.node_set
        return self.block_class(np.asarray(nodes), self.stiffness, self.normal, body.n_nodes)


class PlaneContactBlock(InteractionBlock):
    dofs = PlaneContact.dofs
    reach = 1
    n_tools = 1  # the floor: tool_forces gives the force on it

    def __init__(self, nodes, stiffness, normal, n_nodes):
        self.connectivity = nodes.astype(np.int64)[:, None]  # one row per node
        self.stiffness, self.normal, self.n_nodes = stiffness, normal, n_nodes

    def _gap(self, state):
        """Signed distance (s,) of each node to the floor where it penetrates, else 0."""
        return np.minimum(state.positions[self.connectivity[:, 0]] @ self.normal, 0.0)

    def internal_force(self, state, history=None):
        force = np.zeros((self.n_nodes, 3))  # dW/dx: into the floor where a node is inside
        force[self.connectivity[:, 0]] = self.stiffness * self._gap(state)[:, None] * self.normal
        return force, None

    def strain_energy(self, state, history=None):
        return float(0.5 * self.stiffness * np.sum(self._gap(state) ** 2))

    def tangent(self, state, history=None):
        touching = state.positions[self.connectivity[:, 0]] @ self.normal <= 0.0
        k = np.where(touching, self.stiffness, 0.0)[:, None, None]
        blocks = k * np.outer(self.normal, self.normal)
        return [CellTangent(self.connectivity, blocks[:, None, :, None, :])]

    def springs(self):
        # The explicit step takes the floor's sqrt(k / m) in with the elements' masses.
        nodes = self.connectivity[:, 0]
        return nodes, np.full(len(nodes), float(self.stiffness))

    def tool_forces(self, state, history=None):
        return self.internal_force(state, history)[0].sum(axis=0)[None, :]

    def initial_history(self):
        return np.zeros(len(self.connectivity))

    def update_history(self, state, history):
        return np.maximum(history, -self._gap(state))  # a new array: history is never mutated

    def node_fields(self, state, history=None):
        deepest = np.zeros(self.n_nodes)
        if history is not None:
            deepest[self.connectivity[:, 0]] = history
        return {"deepest_penetration": deepest}


PlaneContact.block_class = PlaneContactBlock


class SpringTie(Interaction):
    """Springs of stiffness k (N/mm) between the nodes ``first[i]`` and ``second[i]`` (node
    ids or node-set names, paired in order), energy 1/2 k |x_a - x_b - (X_a - X_b)|^2."""

    dofs = ("ux", "uy", "uz")

    def __init__(self, first, second, stiffness: float):
        self.first, self.second, self.stiffness = first, second, stiffness

    def bind(self, body: Body) -> "SpringTieBlock":
        pairs = [body.mesh.nodes(s) if isinstance(s, str) else s for s in (self.first, self.second)]
        a, b = (np.asarray(p, dtype=np.int64).ravel() for p in pairs)
        if a.shape != b.shape:
            raise ValueError(f"SpringTie pairs {a.size} nodes with {b.size}: give as many of each")
        return SpringTieBlock(np.column_stack([a, b]), self.stiffness, body.mesh.points)


class SpringTieBlock(InteractionBlock):
    dofs = SpringTie.dofs
    reach = 1

    def __init__(self, pairs, stiffness, points):
        self.connectivity = pairs  # rows (a, b)
        self.stiffness, self.n_nodes = stiffness, len(points)
        self.rest = points[pairs[:, 0]] - points[pairs[:, 1]]  # X_a - X_b, (m, 3)

    def _stretch(self, state):
        x = state.positions
        return x[self.connectivity[:, 0]] - x[self.connectivity[:, 1]] - self.rest

    def internal_force(self, state, history=None):
        pull = self.stiffness * self._stretch(state)  # dW/dx_a; node b gets the opposite
        force = np.zeros((self.n_nodes, 3))
        np.add.at(force, self.connectivity[:, 0], pull)
        np.add.at(force, self.connectivity[:, 1], -pull)
        return force, None

    def strain_energy(self, state, history=None):
        return float(0.5 * self.stiffness * np.sum(self._stretch(state) ** 2))

    def tangent(self, state, history=None):
        k = self.stiffness * np.eye(3)
        blocks = np.empty((len(self.connectivity), 2, 3, 2, 3))
        blocks[:, 0, :, 0] = blocks[:, 1, :, 1] = k
        blocks[:, 0, :, 1] = blocks[:, 1, :, 0] = -k
        return [CellTangent(self.connectivity, blocks)]

    def springs(self):
        # A spring between two nodes raises omega^2 by at most k (1 / m_a + 1 / m_b), which a
        # spring of 2 k to the ground at each of them bounds.
        nodes = self.connectivity.ravel()
        return nodes, np.full(len(nodes), 2.0 * self.stiffness)


# ---------------------------------------------------------------------- the floor
def cable_on_the_floor(height: float = 0.0) -> Model:
    mesh = Mesh.line((0.0, 0.0, height), (LENGTH, 0.0, height), LINKS)
    mesh.add_node_set("all", np.arange(mesh.n_nodes))
    model = Model(mesh)
    model.add(Cable(axial_stiffness=EA, mass_per_length=MU))
    model.interact(PlaneContact("all", K))
    model.fix("all", ("ux", "uy"))
    model.gravity((0.0, 0.0, -G))
    return model


def expected_penetration() -> np.ndarray:
    link = LENGTH / LINKS
    mass = np.full(LINKS + 1, MU * link)
    mass[[0, -1]] *= 0.5
    return mass * G / K


SOLVERS = {
    # Newton with the exact tangents of the cable and the floor, to a residual of 1e-10: the
    # reference's own 1.2e-6 governs.
    "static": (Static(increments=2, tol=1e-10, progress=False), 1e-5),
    # Kinetic damping to a residual of 1e-9 of the forces: again the reference governs.
    "relaxation": (DynamicRelaxation(tol=1e-9, progress=False), 1e-5),
    # Damped dynamics, c = 500 1/s over 0.05 s: the step load's oscillation (omega = 1000
    # rad/s) decays as exp(-c t / 2) = 4e-6. The step is given, 2.5e-4 s, a third of the
    # automatic one (the floor's springs on the nodes' vertical motion alone), so that the
    # history test below samples the first peak finely.
    "explicit": (CentralDifference(0.05, dt=2.5e-4, damping=500.0, progress=False), 1e-4),
}


@pytest.mark.parametrize("name", SOLVERS)
def test_a_user_interaction_rests_the_cable_on_the_floor_with_every_solver(name):
    solver, tolerance = SOLVERS[name]
    compiled = cable_on_the_floor().compile()
    result = solver.solve(compiled)
    penetration = -result.positions[:, 2]
    expected = expected_penetration()
    assert result.converged
    assert np.abs(penetration - expected).max() <= tolerance * expected.max()
    # The floor carries the cable's weight (the tool force is what the cable exerts on it).
    weight = MU * LENGTH * G
    assert result.tool_forces[-1, 0, 2] == pytest.approx(-weight, rel=tolerance)


@pytest.mark.parametrize("name", SOLVERS)
def test_the_history_of_a_user_interaction_is_kept_by_every_solver(name):
    solver, _ = SOLVERS[name]
    result = solver.solve(cable_on_the_floor())
    deepest = result.frames[-1].fields["point"]["deepest_penetration"]
    over_frames = np.max([-frame.positions[:, 2] for frame in result.frames], axis=0)
    # The history sees every accepted step, the frames only some of them.
    assert np.all(deepest >= over_frames - 1e-15)
    if name == "explicit":
        # Gravity is a step load: each interior node is a damped oscillator (omega = sqrt(k/m)
        # = 1000 rad/s, damping ratio c / (2 omega) = 0.25) whose first peak is
        # 1 + exp(-pi xi / sqrt(1 - xi^2)) = 1.44 times the static penetration. The steps
        # sample the peak within omega dt / 2 = 0.125 rad of its phase, 0.44 (1 - cos 0.125)
        # = 0.35 % of the static value: 1 % covers it with the integrator's period error.
        xi = 500.0 / (2.0 * np.sqrt(K / (MU * LENGTH / LINKS)))
        peak = 1.0 + np.exp(-np.pi * xi / np.sqrt(1.0 - xi**2))
        interior = expected_penetration()[1:-1]
        assert np.abs(deepest[1:-1] - peak * interior).max() <= 0.01 * interior.max()
    else:
        assert np.allclose(deepest, over_frames, rtol=0.0, atol=1e-15)


def test_the_user_interaction_tangent_is_the_derivative_of_its_force():
    compiled = cable_on_the_floor().compile()
    state = compiled.initial_state()
    state.positions = state.positions + np.column_stack(
        [np.zeros(LINKS + 1), np.zeros(LINKS + 1), -np.linspace(0.01, 0.02, LINKS + 1)]
    )
    own = compiled.stiffness(state, "element").toarray()
    numerical = compiled.stiffness(state, "finite_difference").toarray()
    assert np.abs(own - numerical).max() <= 1e-6 * np.abs(numerical).max()


# ---------------------------------------------------------------------- the tie
L1, L2, TIE, P = 50.0, 70.0, 20.0, 10.0  # mm, mm, N/mm, N


def tied_cables(amplitude="linear") -> Model:
    """Cable 1 (nodes 0..5) from x = 0 to L1, cable 2 (nodes 6..12) from L1 to L1 + L2, the
    tie joining nodes 5 and 6 (coincident); node 0 fixed, the far end pulled by P along x,
    the transverse motion held."""
    x = np.concatenate([np.linspace(0.0, L1, 6), np.linspace(L1, L1 + L2, 7)])
    lines = [[i, i + 1] for i in range(5)] + [[i, i + 1] for i in range(6, 12)]
    mesh = Mesh(np.column_stack([x, np.zeros((13, 2))]), lines=lines)
    model = Model(mesh)
    model.add(Cable(axial_stiffness=EA, mass_per_length=MU))
    model.interact(SpringTie([5], [6], TIE))
    model.fix([0])
    model.fix(np.arange(13), ("uy", "uz"))
    model.force([12], (P, 0.0, 0.0), amplitude=amplitude)
    return model


def tie_explicit(compiled):
    """``settling_explicit`` on the pulled chain: 1e-5 of the elongation and of P."""
    return settling_explicit(compiled, increments=1), 1e-5


TIE_SOLVERS = {
    # Linear in the stretch: Newton to 1e-10 of the forces, the closed form within 1e-8.
    "static": lambda compiled: (Static(increments=1, tol=1e-10, progress=False), 1e-8),
    # Kinetic damping to 1e-9 of the forces: the elongation within 1e-7 (the support's
    # reaction is the residual's own balance).
    "relaxation": lambda compiled: (DynamicRelaxation(tol=1e-9, progress=False), 1e-7),
    "explicit": tie_explicit,
}


@pytest.mark.parametrize("name", TIE_SOLVERS)
def test_a_user_tie_carries_the_pull_through_two_cables_with_every_solver(name):
    compiled = tied_cables(ramp_then_hold if name == "explicit" else "linear").compile()
    solver, tolerance = TIE_SOLVERS[name](compiled)
    result = solver.solve(compiled)
    assert result.converged
    elongation = result.displacements[12, 0]
    assert elongation == pytest.approx(P * (L1 / EA + 1.0 / TIE + L2 / EA), rel=tolerance)
    tie_opening = result.displacements[6, 0] - result.displacements[5, 0]
    assert tie_opening == pytest.approx(P / TIE, rel=tolerance)
    assert result.reactions[0, 0] == pytest.approx(-P, rel=tolerance)


# ---------------------------------------------------------------------- refusals
def test_an_interaction_added_as_an_element_is_refused():
    model = Model(Mesh.line((0.0, 0.0, 0.0), (1.0, 0.0, 0.0), 2))
    with pytest.raises(ValueError, match=r"PlaneContact is an interaction.*model.interact"):
        model.add(PlaneContact([0], K))


def test_an_interaction_on_nodes_without_its_dofs_is_named():
    points = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]]
    model = Model(Mesh(np.array(points), lines=[[0, 1]]))  # node 2: no element
    model.add(Cable(axial_stiffness=EA, mass_per_length=MU))
    model.interact(SpringTie([1], [2], TIE))
    with pytest.raises(ValueError, match="SpringTie acts on node 2, which carries only no DOF"):
        model.compile()

    class TurningTie(SpringTie):
        dofs = ("ux", "uy", "uz", "alpha", "beta")

    model = Model(Mesh(np.array(points), lines=[[0, 1], [1, 2]]))
    model.add(Cable(axial_stiffness=EA, mass_per_length=MU))
    model.interact(TurningTie([0], [2], TIE))
    with pytest.raises(ValueError, match="TurningTie acts on node 0, which carries only ux, uy"):
        model.compile()


def test_a_bind_that_returns_no_interaction_block_is_named():
    class Loose(SpringTie):
        def bind(self, body):
            return super().bind(body).internal_force  # not a block

    model = tied_cables()
    model.interact(Loose([5], [6], TIE))
    with pytest.raises(ValueError, match="Loose.bind returned method: expected an Interaction"):
        model.compile()


def test_an_interaction_block_whose_methods_do_not_take_the_history_is_named():
    class OldBlock(PlaneContactBlock):
        def strain_energy(self, state):  # the protocol passes (state, history)
            return super().strain_energy(state)

    class OldContact(PlaneContact):
        def bind(self, body):
            return OldBlock(body.mesh.nodes(self.node_set), K, self.normal, body.n_nodes)

    model = cable_on_the_floor()
    model.interact(OldContact("all", K))
    with pytest.raises(ValueError, match=r"OldBlock.strain_energy must take \(state, history"):
        model.compile()


class OldProtocolFloorBlock(PlaneContactBlock):
    """The floor's block answering ``springs_at(state)`` alone, as the protocol asked before
    the explicit step handed down the step until its next evaluation."""

    def springs_at(self, state):  # type: ignore[override]
        return self.springs()


class OldProtocolFloor(PlaneContact):
    block_class = OldProtocolFloorBlock


def test_an_interaction_answering_springs_at_the_state_alone_still_runs_explicit():
    """Its springs are taken as they are (a bound at the evaluated state): the explicit run
    with the automatic step gives the step and the rest of the run that the protocol's
    default ``springs_at(state, step)`` gives (before, a TypeError)."""
    model = cable_on_the_floor()
    model.interactions[0] = OldProtocolFloor("all", K)
    old = model.compile()
    new = cable_on_the_floor().compile()
    solver = CentralDifference(0.002, damping=500.0, progress=False, kinetic_bound=None)
    ran_old, ran_new = solver.solve(old), solver.solve(new)
    assert ran_old.converged == ran_new.converged
    np.testing.assert_array_equal(ran_old.positions, ran_new.positions)


class SteppedFloorBlock(PlaneContactBlock):
    """The floor's block noting each step it is asked its springs for, with the time; its
    springs ``law(k, step, state)`` of its own k (a ply contact's grow with the step: the
    points' slide until the next evaluation)."""

    asked: list
    law: Any

    def springs_at(self, state, step=None):
        self.asked.append((state.time, step))
        nodes, stiffness = self.springs()
        return nodes, self.law(stiffness, step, state)


class SteppedFloor(PlaneContact):
    def __init__(self, node_set, stiffness, law):
        super().__init__(node_set, stiffness)
        self.law = law

    block_class = SteppedFloorBlock

    def bind(self, body: Body) -> "PlaneContactBlock":
        block = super().bind(body)
        block.asked, block.law = [], self.law
        self.block = block
        return block


def _asked_and_taken(law, height=0.0, duration=0.01):
    """The floor (1000 K: its springs keep the step at a sixth of the cable's) under ``law``,
    the cable ``height`` mm above it, run explicit for ``duration`` s: (the cable's critical
    step, per evaluation the steps asked (first, last) and the step taken until the next
    one), s."""
    from solvers.explicit import STABLE_DT_EVERY

    model = cable_on_the_floor(height)
    floor = SteppedFloor("all", 1000.0 * K, law)
    model.interactions[0] = floor
    compiled = model.compile()
    critical = float(compiled.stable_dt(compiled.initial_state()))
    run = CentralDifference(duration, damping=500.0, kinetic_bound=None, progress=False)
    assert run.solve(compiled).converged
    times, asked = np.array(floor.block.asked).T
    evaluations = np.unique(times)
    first = asked[np.searchsorted(times, evaluations, side="left")]
    last = asked[np.searchsorted(times, evaluations, side="right") - 1]
    taken = np.diff(evaluations) / STABLE_DT_EVERY
    return critical, first, last, taken


def test_the_springs_are_asked_for_the_step_taken_and_the_step_keeps_to_what_was_asked():
    """A held spring bound covers the slide of the steps until the next evaluation (the ply
    contact's grows with the step: docs/theory.md §6.2). It is asked at the elements'
    critical step at the start, then at STEP_GROWTH_HELD times the step taken since the last
    evaluation (not the critical step again: where the springs keep the step at a fraction
    of it, that counted the slide several times over), again at the step if that comes out
    larger, and the step taken until the next evaluation is at most the last step asked.
    Springs growing with the step asked (k (1 + 8 step / 0.32 ms), k the floor's own): the
    step grows from its first value to where it
    meets them, asking twice on the way (fails without the second ask or the cap)."""
    from solvers.explicit import STEP_GROWTH_HELD

    critical, first, last, taken = _asked_and_taken(
        lambda k, step, time: k * (1.0 + 8.0 * step / 3.2e-4)
    )
    assert len(taken) > 10 and taken.max() < 0.5 * critical
    assert first[0] == pytest.approx(critical, rel=1e-12)
    np.testing.assert_array_less(first[1:-1], STEP_GROWTH_HELD * taken[:-1] * (1.0 + 1e-9))
    np.testing.assert_array_less(taken, last[:-1] * (1.0 + 1e-9))
    assert np.any(last > first)  # the step grew past what was first asked, and asked again
    assert taken[-1] > 1.5 * taken[0]


def test_springs_that_vanish_at_a_short_step_are_asked_again_at_the_longer_one():
    """Springs that count only the nodes a step's reach brings to the floor (as a ply
    contact's count the points within its slide: twice the fastest speed over the held steps,
    and 0.01 mm) are zero at 1.25 times the step taken while the falling cable is out of that
    reach, and not at the step the elements alone allow: the step is asked for again there,
    and keeps to the last step asked, or to the first where that one's springs hold it (taking
    the elements' step there diverges at step 118). The cable falls 0.5 mm onto the floor,
    damped (at most g / c = 20 mm/s)."""
    from femcore.interaction import SPRINGS_HELD_STEPS

    def within_reach(k, step, state):
        speed = float(np.abs(state.velocities[:, 2]).max())
        reach = 2.0 * speed * SPRINGS_HELD_STEPS * step + 0.01
        return np.where(state.positions[:, 2] <= reach, k, 0.0)

    _, first, last, taken = _asked_and_taken(within_reach, height=0.5, duration=0.03)
    np.testing.assert_array_less(taken, np.maximum(first, last)[:-1] * (1.0 + 1e-9))
    assert np.any(last > first)


class MassWeighedFloorBlock(PlaneContactBlock):
    """The floor's block asking for the masses the step divides by, without the step."""

    masses: list

    def springs_at(self, state, mass=None):  # type: ignore[override]
        self.masses.append(mass)
        return self.springs()


class MassWeighedFloor(PlaneContact):
    block_class = MassWeighedFloorBlock

    def bind(self, body: Body) -> "PlaneContactBlock":
        block = super().bind(body)
        block.masses = []
        self.block = block
        return block


def test_an_interaction_whose_springs_at_takes_the_masses_is_handed_them():
    """``springs_at(state, mass=...)`` without the step (a TypeError before: the step was
    handed down by position into ``mass``): asked with the solver's lumped masses, and its
    springs give the step the protocol's default gives."""
    model = cable_on_the_floor()
    floor = MassWeighedFloor("all", K)
    model.interactions[0] = floor
    weighed = model.compile()
    plain = cable_on_the_floor().compile()
    state = plain.initial_state()
    mass = plain.lumped_mass(state)[0]
    step = 1e-5
    assert weighed.penalty_frequency_squared(
        mass, weighed.initial_state(), step
    ) == plain.penalty_frequency_squared(mass, state, step)
    np.testing.assert_array_equal(floor.block.masses[-1], mass)


class TwoArgumentCalibrateBlock(PlaneContactBlock):
    """A floor sized from the elements by ``calibrate(mass, stable_dt)``, the protocol's
    two-argument form (README), without the penalty's step."""

    def calibrate(self, mass, stable_dt):
        nodes = self.connectivity[:, 0]
        self.stiffness = 0.1 * mass[nodes] * (2.0 / stable_dt) ** 2


class TwoArgumentCalibrateFloor(PlaneContact):
    block_class = TwoArgumentCalibrateBlock


def test_a_user_interaction_whose_calibrate_takes_mass_and_step_alone_is_sized_by_it():
    """Its calibrate gets the lumped masses and the elements' critical step (before, a
    TypeError: the model handed it a third argument, the penalty's step)."""
    model = cable_on_the_floor()
    model.interactions[0] = TwoArgumentCalibrateFloor("all", K)
    compiled = model.compile()
    block = compiled.interactions[0]
    nodes = block.connectivity[:, 0]
    state = compiled.initial_state()
    expected = 0.1 * compiled.mass0[nodes] * (2.0 / compiled.stable_dt(state)) ** 2
    np.testing.assert_array_equal(block.stiffness, expected)
