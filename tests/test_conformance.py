"""Conformance of every element type to the element protocol (femcore/element.py, DESIGN §5).

Each check is parametrised over the element cases of tests/conformance_cases.py; a new element
is done when it has a case there and passes. What every element must satisfy:

1. rigid motions of the reference (a translation, large rotations about oblique axes) give no
   force, no moment, no energy and no strain or stress in the outputs;
2. objectivity: a deformed state turned rigidly carries the turned forces and moments and the
   same energy;
3. the internal force and the moments are the gradient of the strain energy (central
   differences over the translations and over the two rotations of each director);
4. the element tangent is the derivative of the internal force (against the coloured
   finite differences of the assembled force);
5. the lumped mass sums to the total mass and every node has a positive mass (and a positive
   rotary inertia where it has rotations);
6. the stable step is safe (below 2 / omega_max of the assembled lumped system) and not
   needlessly small, at the reference and at deformed states;
7. the stable step shrinks with the mesh.

Every tolerance comes from the case, with the reason for its value.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg

import elements
from femcore.dofs import N_COLUMNS
from femcore.state import State
from tests.conformance_cases import CASES, ElementCase

case_parameter = pytest.mark.parametrize("case", CASES, ids=str)


def rotation_matrix(axis, angle: float) -> np.ndarray:
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


# Large rigid motions: a translation, and 90 degrees about two oblique axes, with and without a
# translation.
SHIFT = [3.0, -7.0, 11.0]
TURN_A = rotation_matrix([1.0, -2.0, 0.5], np.pi / 2)
TURN_B = rotation_matrix([0.3, 1.0, -0.7], np.pi / 2)
RIGID_MOTIONS = {
    "translation": (np.eye(3), SHIFT),
    "rotation-a": (TURN_A, [0.0, 0.0, 0.0]),
    "rotation-a-translation": (TURN_A, SHIFT),
    "rotation-b-translation": (TURN_B, [5.0, 1.0, -2.0]),
}
motion_parameter = pytest.mark.parametrize("motion", list(RIGID_MOTIONS))


def moved_rigidly(state: State, motion: str) -> State:
    rotation, shift = RIGID_MOTIONS[motion]
    moved = state.copy()
    moved.positions = state.positions @ rotation.T + shift
    moved.directors = state.directors @ rotation.T
    return moved


def largest(array) -> float:
    return float(np.abs(array).max()) if array is not None and np.size(array) else 0.0


# ---------------------------------------------------------------------- 0. coverage
# Blocks that act against something outside the model (a rigid tool that does not move with
# the body): a rigid motion of the body alone changes their energy, so the protocol's
# invariants do not hold for them; tests/test_contact.py checks their forces, tangent and
# statics against closed forms.
EXTERNAL = {elements.Contact}


def test_every_element_type_of_the_elements_package_has_a_conformance_case():
    types = {
        value
        for value in vars(elements).values()
        if isinstance(value, type)
        and issubclass(value, elements.ElementType)
        and value is not elements.ElementType
        and value not in EXTERNAL
    }
    covered = {type(case.element()) for case in CASES}
    assert types <= covered, f"no case in tests/conformance_cases.py for {types - covered}"


# ---------------------------------------------------------------------- 1. rigid motions
@case_parameter
@motion_parameter
def test_rigid_motions_of_the_reference_give_no_force_no_moment_and_no_energy(
    case: ElementCase, motion: str
):
    model = case.model()
    deformed = case.deform(model)
    force_scale, moment_scale = (largest(a) for a in model.internal_force(deformed))
    energy_scale = model.strain_energy(deformed)
    assert force_scale > 0 and energy_scale > 0

    state = moved_rigidly(model.initial_state(), motion)
    force, moment = model.internal_force(state)
    assert force.shape == moment.shape == (model.n_nodes, 3)
    assert largest(force) <= case.rigid.value * force_scale, case.rigid.why
    assert largest(moment) <= case.rigid.value * moment_scale, case.rigid.why
    assert abs(model.strain_energy(state)) <= case.rigid_energy.value * energy_scale, (
        case.rigid_energy.why
    )
    for block in model.blocks:
        if "alpha" not in block.dofs:
            assert block.internal_force(state)[1] is None, "no rotations: no moment (None)"


@case_parameter
@motion_parameter
def test_rigid_motions_leave_no_strain_or_stress_in_the_outputs(case: ElementCase, motion: str):
    model = case.model()
    deformed = model.fields(case.deform(model))
    fields = model.fields(moved_rigidly(model.initial_state(), motion))
    for name in case.rigid_fields:
        kind = next(k for k in ("triangle", "line") if name in fields[k])
        scale = largest(deformed[kind][name])
        assert scale > 0
        assert largest(fields[kind][name]) <= case.rigid_field.value * scale, (
            f"{name}: {case.rigid_field.why}"
        )


# ---------------------------------------------------------------------- 2. objectivity
@case_parameter
@motion_parameter
def test_a_rigidly_turned_deformed_state_carries_turned_loads_and_the_same_energy(
    case: ElementCase, motion: str
):
    model = case.model()
    state = case.deform(model)
    force, moment = model.internal_force(state)
    rotation, _ = RIGID_MOTIONS[motion]
    turned = moved_rigidly(state, motion)
    force_t, moment_t = model.internal_force(turned)
    tolerance = case.objectivity
    assert largest(force_t - force @ rotation.T) <= tolerance.value * largest(force), tolerance.why
    assert largest(moment_t - moment @ rotation.T) <= tolerance.value * largest(moment), (
        tolerance.why
    )
    assert model.strain_energy(turned) == pytest.approx(
        model.strain_energy(state), rel=case.objective_energy.value, abs=0.0
    ), case.objective_energy.why


# ---------------------------------------------------------------------- 3. energy gradient
def energy_gradient(model, energy, state: State, step: float = 1e-6) -> np.ndarray:
    """Central differences of the energy over the generalised coordinates (n, 5): the
    translations, and alpha, beta, the rotations of each director about the two axes V2, V1
    of its nodal frame (perpendicular to it; femcore.dofs), zero where a node lacks them."""
    dofs = model.dofs
    frames = dofs.frames(state.directors)
    gradient = np.zeros((model.n_nodes, N_COLUMNS))
    for node, column in np.argwhere(dofs.active):
        delta = np.zeros((model.n_nodes, N_COLUMNS))
        delta[node, column] = step
        plus = energy(dofs.advance(state, delta, frames))
        minus = energy(dofs.advance(state, -delta, frames))
        gradient[node, column] = (plus - minus) / (2 * step)
    return gradient


@case_parameter
def test_forces_and_moments_are_the_gradient_of_the_strain_energy(case: ElementCase):
    model = case.model()
    state = case.deform(model)
    frames = model.dofs.frames(state.directors)
    for part, (energy, part_loads) in case.parts(model).items():
        force, moment = part_loads(state)
        numeric = energy_gradient(model, energy, state)
        fd_force = numeric[:, :3]
        assert largest(fd_force) > 0, f"{part}: the deformed state must load the element"
        assert largest(force - fd_force) <= case.gradient.value * largest(fd_force), (
            f"{part}: {case.gradient.why}"
        )
        if frames is None:
            assert moment is None or not np.any(moment)
            continue
        v1, v2 = frames
        # dW/dpsi without its drilling part (about the director), from dW/d(alpha, beta).
        fd_moment = numeric[:, 3:4] * v2 + numeric[:, 4:5] * v1
        fd_moment[~model.dofs.has_rotation] = 0.0
        assert largest(moment - fd_moment) <= case.gradient.value * max(
            largest(fd_moment), 1e-12
        ), f"{part}: {case.gradient.why}"


# ---------------------------------------------------------------------- 4. tangent
@case_parameter
def test_element_tangent_is_the_derivative_of_the_internal_force(case: ElementCase):
    if case.not_a_potential is not None:
        pytest.skip(case.not_a_potential)
    model = case.model()
    state = case.deform(model)
    if any(block.tangent(state) is None for block in model.blocks):
        pytest.skip("the element has no tangent of its own: solvers use finite differences")
    free = model.dofs.free_slots
    own = model.stiffness(state, "element").toarray()[np.ix_(free, free)]
    reference = model.stiffness(state, "finite_difference").toarray()[np.ix_(free, free)]
    assert largest(reference) > 0
    assert largest(own - reference) <= case.tangent.value * largest(reference), case.tangent.why


# ---------------------------------------------------------------------- 5. mass
@case_parameter
def test_lumped_mass_sums_to_the_total_mass_and_is_positive_at_every_node(case: ElementCase):
    model = case.model()
    total = case.total_mass(model.mesh)
    for state in (model.initial_state(), case.deform(model)):
        for block in model.blocks:
            mass, inertia = block.lumped_mass(state)
            nodes = np.unique(block.connectivity)
            assert mass.sum() == pytest.approx(total, rel=case.mass.value, abs=0.0), case.mass.why
            if hasattr(block, "total_mass"):
                assert block.total_mass() == pytest.approx(total, rel=case.mass.value, abs=0.0)
            assert (mass[nodes] > 0).all()
            if "alpha" in block.dofs:
                assert (inertia[nodes] > 0).all()
            else:
                assert inertia is None, "an element without rotations has no rotary inertia"


# ---------------------------------------------------------------------- 6. stable step
def exact_stable_step(model, state: State) -> float:
    """2 / omega_max of K phi = omega^2 M phi on the free DOFs: K the finite-difference
    stiffness (symmetrised), M the lumped mass (translations) and rotary inertia (rotations)."""
    free = model.dofs.free_slots
    stiffness = model.stiffness(state, "finite_difference").toarray()[np.ix_(free, free)]
    stiffness = 0.5 * (stiffness + stiffness.T)
    mass, inertia = model.lumped_mass(state)
    diagonal = np.column_stack([mass, mass, mass, inertia, inertia]).ravel()[free]
    omega2 = scipy.linalg.eigh(stiffness, np.diag(diagonal), eigvals_only=True)
    return 2.0 / np.sqrt(omega2.max())


STEP_STATES = [(case, name) for case in CASES for name in case.step_states]


@pytest.mark.parametrize(
    "case, state_name", STEP_STATES, ids=[f"{c.name}-{name}" for c, name in STEP_STATES]
)
def test_stable_step_is_safe_and_not_needlessly_small(case: ElementCase, state_name: str):
    model = case.model()
    state = case.step_states[state_name](model)
    exact = exact_stable_step(model, state)
    dt = min(float(np.min(block.cell_stable_dt(state))) for block in model.blocks)
    assert dt <= exact, "the element bound must not exceed 2 / omega_max of the assembly"
    assert dt >= case.step_floor.value * exact, case.step_floor.why


# ---------------------------------------------------------------------- 7. mesh size
@case_parameter
def test_stable_step_shrinks_with_the_mesh(case: ElementCase):
    coarse, fine = case.model(1), case.model(2)
    ratio = coarse.stable_dt(coarse.initial_state()) / fine.stable_dt(fine.initial_state())
    low, high, why = case.shrink
    assert low <= ratio <= high, why
