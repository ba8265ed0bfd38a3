"""Conformance of every element type of the elements package to the element protocol
(femcore/element.py, DESIGN §5), through the public kit femcore.testing.

Each check of the kit is parametrised over the element cases of tests/conformance_cases.py; a
new element is done when it has a case there and passes. The kit's docstring lists what every
element must satisfy (rigid motions, objectivity, energy gradient, tangent, mass, stable step,
mesh size); every tolerance comes from the case, with the reason for its value.
"""

from __future__ import annotations

import pytest

import elements
from femcore import testing
from tests.conformance_cases import CASES, ElementCase

case_parameter = pytest.mark.parametrize("case", CASES, ids=str)
motion_parameter = pytest.mark.parametrize("motion", list(testing.RIGID_TEST_MOTIONS))


def run(check, *arguments) -> None:
    """A kit check; one that does not apply to the element is a skip."""
    try:
        check(*arguments)
    except testing.NotApplicable as why:
        pytest.skip(str(why))


# ---------------------------------------------------------------------- 0. coverage
def test_every_element_type_of_the_elements_package_has_a_conformance_case():
    # Interactions (elements.Contact) are not element types: their own kit runs on them
    # (tests/test_interaction_conformance.py).
    types = {
        value
        for value in vars(elements).values()
        if isinstance(value, type)
        and issubclass(value, elements.ElementType)
        and value is not elements.ElementType
    }
    covered = {type(case.element()) for case in CASES}
    assert types <= covered, f"no case in tests/conformance_cases.py for {types - covered}"


# ---------------------------------------------------------------------- 1. rigid motions
@case_parameter
@motion_parameter
def test_rigid_motions_of_the_reference_give_no_force_no_moment_and_no_energy(
    case: ElementCase, motion: str
):
    run(testing.assert_rigid_motion_gives_no_load, case, motion)


@case_parameter
@motion_parameter
def test_rigid_motions_leave_no_strain_or_stress_in_the_outputs(case: ElementCase, motion: str):
    run(testing.assert_rigid_motion_leaves_no_strain, case, motion)


# ---------------------------------------------------------------------- 2. objectivity
@case_parameter
@motion_parameter
def test_a_rigidly_turned_deformed_state_carries_turned_loads_and_the_same_energy(
    case: ElementCase, motion: str
):
    run(testing.assert_objective, case, motion)


# ---------------------------------------------------------------------- 3. energy gradient
@case_parameter
def test_forces_and_moments_are_the_gradient_of_the_strain_energy(case: ElementCase):
    run(testing.assert_loads_are_the_energy_gradient, case)


@case_parameter
def test_the_force_pass_with_the_energy_gives_the_two_calls(case: ElementCase):
    run(testing.assert_force_and_energy_agree, case)


# ---------------------------------------------------------------------- 4. tangent
@case_parameter
def test_element_tangent_is_the_derivative_of_the_internal_force(case: ElementCase):
    run(testing.assert_tangent_is_the_force_derivative, case)


# ---------------------------------------------------------------------- 5. mass
@case_parameter
def test_lumped_mass_sums_to_the_total_mass_and_is_positive_at_every_node(case: ElementCase):
    run(testing.assert_lumped_mass, case)


# ---------------------------------------------------------------------- 6. stable step
STEP_STATES = [(case, name) for case in CASES for name in case.states()]


@pytest.mark.parametrize(
    "case, state_name", STEP_STATES, ids=[f"{c.name}-{name}" for c, name in STEP_STATES]
)
def test_stable_step_is_safe_and_not_needlessly_small(case: ElementCase, state_name: str):
    run(testing.assert_stable_step_is_safe, case, state_name)


# ---------------------------------------------------------------------- 7. mesh size
@case_parameter
def test_stable_step_shrinks_with_the_mesh(case: ElementCase):
    run(testing.assert_stable_step_shrinks_with_the_mesh, case)


# ---------------------------------------------------------------------- 8. capabilities
@case_parameter
def test_the_capabilities_a_block_declares_are_what_the_solvers_assume(case: ElementCase):
    run(testing.assert_declared_capabilities, case)


# ---------------------------------------------------------------------- the kit's report
def test_the_kit_reports_every_check_of_a_case_and_names_a_failure():
    report = testing.check_element(CASES[0])
    assert report.passed, report
    names = [result.name for result in report.results]
    assert len(names) == len(set(names)) and "lumped mass" in names
    # A case whose stated total mass is wrong fails the mass check, and only it.
    wrong = ElementCase(**{**vars(CASES[0]), "total_mass": lambda mesh: 1.0, "name": "wrong"})
    report = testing.check_element(wrong)
    assert [result.name for result in report.failures] == ["lumped mass"]
    assert "not to the total mass 1.0" in str(report)
