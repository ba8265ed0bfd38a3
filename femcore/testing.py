"""Conformance kits: the checks every element type (here) and every interaction
(femcore.interaction_checks, re-exported here) must pass, for any test suite.

An element type (a subclass of ``femcore.element.ElementType``, the project's or a user's)
conforms to the element protocol when, on a small free-floating model of it:

1. rigid motions of the reference (a translation, large rotations about oblique axes) give no
   force, no moment, no energy and no strain or stress in the outputs;
2. objectivity: a deformed state turned rigidly carries the turned forces and moments and the
   same energy;
3. the internal force and the moments are the gradient of the strain energy (central
   differences over the translations and over the two rotations of each director), and
   ``internal_force_and_energy`` (one pass where a block fuses them) gives what
   ``internal_force`` and ``strain_energy`` give;
4. the element tangent, if the element has one, is the derivative of the internal force
   (against the coloured finite differences of the assembled force);
5. the lumped mass sums to the total mass and every node has a positive mass (and a positive
   rotary inertia where it has rotations);
6. the stable step is safe (below 2 / omega_max of the assembled lumped system) and not
   needlessly small, at the reference and at deformed states;
7. the stable step shrinks with the mesh;
8. the capabilities the block declares through the protocol (a compression-free tangent,
   fibre strains, fibre edges: femcore.capability_checks) are of their type and do what the
   solvers assume.

Usage, in a user's own tests (pytest or not; the kit does not import pytest)::

    from femcore.testing import check_element

    def test_my_membrane_conforms():
        report = check_element(MyMembrane(film), lambda refine: Mesh.rectangle(
            40.0, 30.0, nx=4 * refine, ny=3 * refine), total_mass=rho * t * 40.0 * 30.0)
        assert report.passed, report

``check_element`` builds an ``ElementCase`` with the default tolerances; an ``ElementCase``
built by hand sets each of them, and each ``assert_*`` function runs one check of a case
(raising AssertionError with the tolerance's reason, or ``NotApplicable`` when the check does
not apply to the element, e.g. no tangent of its own), for a suite that parametrises them.

The module has sections: helpers any kit of the project shares (rigid motions of a state,
finite-difference gradient of an energy, exact stable step, reports), then the element kit.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass, field
from functools import partial
from typing import NamedTuple

import numpy as np
import scipy.linalg

from femcore.capability_checks import check_element_capabilities
from femcore.dofs import N_COLUMNS
from femcore.element import ElementType
from femcore.mesh import Mesh
from femcore.model import CompiledModel, Model
from femcore.rotation import rotate_about
from femcore.state import State

__all__ = [
    "CENTRAL_DIFFERENCE",
    "ENERGY_ROUND_OFF",
    "FIELD_ROUND_OFF",
    "HALVED_CELLS",
    "MASS_SUM",
    "RIGID_TEST_MOTIONS",
    "ROUND_OFF",
    "ROUND_OFF_SQUARED",
    "TANGENT_DIFFERENCES",
    "WITHIN_TWO",
    "Bound",
    "CheckResult",
    "ConformanceReport",
    "ElementCase",
    "EnergyPart",
    "NotApplicable",
    "assert_declared_capabilities",
    "assert_lumped_mass",
    "assert_force_and_energy_agree",
    "assert_loads_are_the_energy_gradient",
    "assert_objective",
    "assert_rigid_motion_gives_no_load",
    "assert_rigid_motion_leaves_no_strain",
    "assert_stable_step_is_safe",
    "assert_stable_step_shrinks_with_the_mesh",
    "assert_tangent_is_the_force_derivative",
    "check_element",
    "element_checks",
    "energy_gradient",
    "exact_stable_step",
    "jitter",
    "largest",
    "moved_rigidly",
    "rotation_matrix",
    "run_checks",
]


# ====================================================================== shared helpers
class Bound(NamedTuple):
    """A tolerance and why it is what it is (shown when an assertion fails)."""

    value: float
    why: str


class NotApplicable(Exception):
    """A check that does not apply to the element (its message says why): not a failure.
    Under pytest, turn it into a skip: ``except NotApplicable as why: pytest.skip(str(why))``."""


def rotation_matrix(axis, angle: float) -> np.ndarray:
    """(3, 3) rotation by ``angle`` (rad) about ``axis`` (3,), any length (Rodrigues)."""
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


# Large rigid motions, name -> (rotation (3, 3), translation (3,) mm): a translation, and 90
# degrees about two oblique axes, with and without a translation.
_SHIFT = [3.0, -7.0, 11.0]
_TURN_A = rotation_matrix([1.0, -2.0, 0.5], np.pi / 2)
_TURN_B = rotation_matrix([0.3, 1.0, -0.7], np.pi / 2)
RIGID_TEST_MOTIONS: dict[str, tuple[np.ndarray, list[float]]] = {
    "translation": (np.eye(3), _SHIFT),
    "rotation-a": (_TURN_A, [0.0, 0.0, 0.0]),
    "rotation-a-translation": (_TURN_A, _SHIFT),
    "rotation-b-translation": (_TURN_B, [5.0, 1.0, -2.0]),
}


def moved_rigidly(state: State, motion: str) -> State:
    """A copy of ``state`` moved by the rigid motion ``motion`` (a name of
    ``RIGID_TEST_MOTIONS``): positions x -> R x + c, directors v -> R v."""
    rotation, shift = RIGID_TEST_MOTIONS[motion]
    moved = state.copy()
    moved.positions = state.positions @ rotation.T + shift
    moved.directors = state.directors @ rotation.T
    return moved


def largest(array) -> float:
    """The largest absolute entry of ``array``; 0 for None or an empty array."""
    return float(np.abs(array).max()) if array is not None and np.size(array) else 0.0


def jitter(amplitude: float, tilt: float = 0.0, seed: int = 0) -> Callable[[CompiledModel], State]:
    """A deformed-state maker: random nodal displacements and director tilts.

    Parameters
    ----------
    amplitude : float
        Standard deviation of each displacement component, mm.
    tilt : float
        Standard deviation of the director tilts, rad (0: directors left as they are).
    seed : int
        Of ``numpy.random.default_rng``: the same state at every call.

    Returns
    -------
    callable
        ``model -> State`` from the model's initial state.
    """

    def build(model: CompiledModel) -> State:
        rng = np.random.default_rng(seed)
        state = model.initial_state()
        state.positions = state.positions + rng.normal(scale=amplitude, size=state.positions.shape)
        if tilt:
            turn = np.cross(state.directors, rng.normal(scale=tilt, size=state.positions.shape))
            state.directors = rotate_about(state.directors, turn)
        return state

    return build


def energy_gradient(
    model: CompiledModel, energy: Callable[[State], float], state: State, step: float = 1e-6
) -> np.ndarray:
    """Central differences of an energy over the generalised coordinates.

    Parameters
    ----------
    model : CompiledModel
    energy : callable
        ``state -> W`` (N mm).
    state : State
    step : float
        Perturbation, mm for translations and rad for rotations.

    Returns
    -------
    numpy.ndarray, shape (n, 5)
        dW/d(ux, uy, uz, alpha, beta), alpha and beta the rotations of each director about
        the axes V2, V1 of its nodal frame (femcore.dofs); zero where a node lacks the DOF.
    """
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


def exact_stable_step(model: CompiledModel, state: State) -> float:
    """2 / omega_max (s) of K phi = omega^2 M phi on the free DOFs: K the finite-difference
    stiffness at ``state`` (symmetrised), M the lumped mass (translations) and rotary inertia
    (rotations). Dense: for the small models of a conformance check."""
    free = model.dofs.free_slots
    stiffness = model.stiffness(state, "finite_difference").toarray()[np.ix_(free, free)]
    stiffness = 0.5 * (stiffness + stiffness.T)
    mass, inertia = model.lumped_mass(state)
    diagonal = np.column_stack([mass, mass, mass, inertia, inertia]).ravel()[free]
    omega2 = scipy.linalg.eigh(stiffness, np.diag(diagonal), eigvals_only=True)
    return 2.0 / np.sqrt(omega2.max())


def _close(actual: float, expected: float, rel: float) -> bool:
    return abs(actual - expected) <= rel * abs(expected)


@dataclass(frozen=True)
class CheckResult:
    """One check of a report: its name, "passed", "failed" or "not applicable", and why."""

    name: str
    status: str
    message: str = ""


@dataclass(repr=False)
class ConformanceReport:
    """The checks run on one case, in order (``str`` and ``repr`` of it: one line per check,
    so that ``assert report.passed, report`` shows them all)."""

    case: str
    results: list[CheckResult] = field(default_factory=list)

    @property
    def passed(self) -> bool:
        """True when no check failed (checks that do not apply do not count)."""
        return not self.failures

    @property
    def failures(self) -> list[CheckResult]:
        return [result for result in self.results if result.status == "failed"]

    def __str__(self) -> str:
        lines = [f"{self.case}: {len(self.failures)} of {len(self.results)} checks failed"]
        for result in self.results:
            lines.append(f"  {result.status:>14}  {result.name}" + (
                f": {result.message}" if result.message else ""))  # fmt: skip
        return "\n".join(lines)

    __repr__ = __str__


def run_checks(case: str, checks: Iterator[tuple[str, Callable[[], None]]]) -> ConformanceReport:
    """Run ``(name, check)`` pairs into a report: an AssertionError or any other exception is
    a failure (with its message), ``NotApplicable`` is recorded as such."""
    report = ConformanceReport(case)
    for name, check in checks:
        try:
            check()
        except NotApplicable as why:
            report.results.append(CheckResult(name, "not applicable", str(why)))
        except AssertionError as failure:
            report.results.append(CheckResult(name, "failed", str(failure)))
        except Exception as error:  # the element itself raised: that is a failure too
            report.results.append(CheckResult(name, "failed", f"{type(error).__name__}: {error}"))
        else:
            report.results.append(CheckResult(name, "passed"))
    return report


# ====================================================================== element kit
# ---------------------------------------------------------------------- default tolerances
# (The values the project's element types are held to; "seen" is the largest value they give.)
ROUND_OFF = Bound(
    1e-10, "round-off of the loads relative to those of the deformed state (seen: 8e-15)"
)
ROUND_OFF_SQUARED = Bound(
    1e-25, "the energy is quadratic in round-off strains, relative to the deformed one (2e-29)"
)
FIELD_ROUND_OFF = Bound(
    3e-14, "strains and stresses from round-off positions, relative to the deformed (6e-15)"
)
ENERGY_ROUND_OFF = Bound(1e-12, "one sum of cell energies: round-off (seen: 1.3e-15)")
CENTRAL_DIFFERENCE = Bound(
    1e-6, "central differences of step 1e-6: truncation and cancellation (seen: 3.5e-9)"
)
TANGENT_DIFFERENCES = Bound(
    1e-6, "both tangents are central differences of step 1e-6, or exact (seen: 4e-10)"
)
MASS_SUM = Bound(1e-13, "a sum of positive shares: round-off (seen: 3e-16)")
WITHIN_TWO = Bound(
    0.5, "docs/theory.md §6.2: the bound is safe and within a factor 2 (seen: >= 0.58)"
)
HALVED_CELLS = (1.9, 4.1, "cells halved: dt ~ L (axial, membrane, shear) to ~ L^2 (bending)")

# An energy and the loads that must be its gradient: state -> W, state -> (force, moment).
EnergyPart = tuple[Callable[[State], float], Callable[[State], tuple]]


@dataclass(frozen=True)
class ElementCase:
    """One element type set up for the conformance checks.

    Parameters
    ----------
    name : str
        For messages and reports.
    element : callable
        ``() -> ElementType``: a fresh element type (material and options).
    mesh : callable
        ``refine -> Mesh``: the case's patch with every cell divided by ``refine`` (1, and 2
        for the mesh-size check). Small: the step check solves a dense eigenproblem.
    total_mass : callable, float or None
        ``mesh -> t``, or the mass (t) of the refine-1 mesh: the physical mass from the mesh
        geometry and the material data, independently of the element's own bookkeeping. None:
        only positivity (and the block's own ``total_mass()``, if it has one) is checked.
    deform : callable or None
        ``model -> State``: a deformed state away from any symmetry an error could hide
        behind. None: ``jitter`` by 5 % of the median cell edge, directors tilted 0.2 rad.
    step_states : mapping or None
        name -> (model -> State): where the stable step is compared with the exact
        eigenvalues. None: "reference" and "deformed".
    rigid_fields : tuple of str
        Cell output fields (strains, stresses) that must vanish under rigid motions.
    rigid, rigid_energy, rigid_field, objectivity, objective_energy, gradient, tangent, mass,
    step_floor : Bound
        Tolerances, relative to the deformed state's loads, energy, fields; ``step_floor`` the
        smallest element step allowed as a fraction of the exact one.
    shrink : (float, float, str)
        Bounds of the stable-step ratio of the refine-1 to the refine-2 mesh, and why.
    energy_parts : callable or None
        ``model -> {name: (energy, loads)}``: energies whose gradient the loads must be
        (None: the whole strain energy and internal force of the model).
    not_a_potential : str or None
        Why the whole internal force is not the exact gradient of the strain energy, or None;
        with a reason, only ``energy_parts`` are checked and the tangent comparison does not
        apply (the element tangent is then consistent with the force only to first order).
    """

    name: str
    element: Callable[[], ElementType]
    mesh: Callable[[int], Mesh]
    total_mass: Callable[[Mesh], float] | float | None = None
    deform: Callable[[CompiledModel], State] | None = None
    step_states: Mapping[str, Callable[[CompiledModel], State]] | None = None
    rigid_fields: tuple[str, ...] = ()
    rigid: Bound = ROUND_OFF
    rigid_energy: Bound = ROUND_OFF_SQUARED
    rigid_field: Bound = FIELD_ROUND_OFF
    objectivity: Bound = ROUND_OFF
    objective_energy: Bound = ENERGY_ROUND_OFF
    gradient: Bound = CENTRAL_DIFFERENCE
    tangent: Bound = TANGENT_DIFFERENCES
    mass: Bound = MASS_SUM
    step_floor: Bound = WITHIN_TWO
    shrink: tuple[float, float, str] = HALVED_CELLS
    energy_parts: Callable[[CompiledModel], Mapping[str, EnergyPart]] | None = None
    not_a_potential: str | None = None

    def model(self, refine: int = 1) -> CompiledModel:
        """The compiled model of the case (no supports: every DOF is free)."""
        model = Model(self.mesh(refine))
        model.add(self.element())
        return model.compile()

    def deformed(self, model: CompiledModel) -> State:
        """The case's deformed state of ``model``."""
        if self.deform is not None:
            return self.deform(model)
        rotations = bool(model.dofs.has_rotation.any())
        return jitter(0.05 * _cell_size(model), tilt=0.2 if rotations else 0.0)(model)

    def states(self) -> Mapping[str, Callable[[CompiledModel], State]]:
        """The states of the stable-step check, name -> (model -> State)."""
        if self.step_states is not None:
            return self.step_states
        return {"reference": lambda model: model.initial_state(), "deformed": self.deformed}

    def parts(self, model: CompiledModel) -> Mapping[str, EnergyPart]:
        """The energies and the loads that must be their gradients."""
        if self.energy_parts is not None:
            return self.energy_parts(model)
        return {"whole": (model.strain_energy, model.internal_force)}

    def __str__(self) -> str:
        return self.name


def _cell_size(model: CompiledModel) -> float:
    """The median edge length (mm) of the model's cells (its extent / 10 without cells)."""
    points = model.reference_positions
    edges = [
        np.linalg.norm(points[c] - points[np.roll(c, -1, axis=1)], axis=-1).ravel()
        for c in (block.connectivity for block in model.blocks)
        if c.ndim == 2 and c.shape[1] > 1
    ]
    if edges:
        return float(np.median(np.concatenate(edges)))
    return 0.1 * float(np.ptp(points, axis=0).max())


# ---------------------------------------------------------------------- 1. rigid motions
def assert_rigid_motion_gives_no_load(case: ElementCase, motion: str) -> None:
    """Check 1: the reference moved by ``motion`` (a name of ``RIGID_TEST_MOTIONS``) carries no
    force, no moment and no energy (relative to the deformed state's), and a block without
    rotations returns None for its moments. Raises AssertionError."""
    model = case.model()
    deformed = case.deformed(model)
    force_scale, moment_scale = (largest(a) for a in model.internal_force(deformed))
    energy_scale = model.strain_energy(deformed)
    assert force_scale > 0 and energy_scale > 0, f"{case}: the deformed state must load it"

    state = moved_rigidly(model.initial_state(), motion)
    force, moment = model.internal_force(state)
    assert force.shape == moment.shape == (model.n_nodes, 3), f"{case}: loads must be (n, 3)"
    for what, value, scale in (("force", force, force_scale), ("moment", moment, moment_scale)):
        assert largest(value) <= case.rigid.value * scale, (
            f"{case}, {motion}: largest {what} {largest(value):.3g} > {case.rigid.value:g} x "
            f"{scale:.3g} ({case.rigid.why})"
        )
    energy = model.strain_energy(state)
    assert abs(energy) <= case.rigid_energy.value * energy_scale, (
        f"{case}, {motion}: energy {energy:.3g} > {case.rigid_energy.value:g} x "
        f"{energy_scale:.3g} ({case.rigid_energy.why})"
    )
    for block in model.blocks:
        if "alpha" not in block.dofs:
            assert block.internal_force(state)[1] is None, (
                f"{case}: {type(block).__name__} has no rotations: its moment must be None"
            )


def assert_rigid_motion_leaves_no_strain(case: ElementCase, motion: str) -> None:
    """Check 1: the case's ``rigid_fields`` vanish on the reference moved by ``motion``
    (relative to their values at the deformed state). Raises AssertionError."""
    model = case.model()
    deformed = model.fields(case.deformed(model))
    fields = model.fields(moved_rigidly(model.initial_state(), motion))
    for name in case.rigid_fields:
        kind = next((k for k in fields if isinstance(fields[k], dict) and name in fields[k]), None)
        assert kind is not None, f"{case}: no output field named {name!r}"
        scale = largest(deformed[kind][name])
        assert scale > 0, f"{case}: {name} vanishes at the deformed state too"
        value = largest(fields[kind][name])
        assert value <= case.rigid_field.value * scale, (
            f"{case}, {motion}: {name} {value:.3g} > {case.rigid_field.value:g} x {scale:.3g} "
            f"({case.rigid_field.why})"
        )


# ---------------------------------------------------------------------- 2. objectivity
def assert_objective(case: ElementCase, motion: str) -> None:
    """Check 2: the deformed state moved by ``motion`` carries the turned forces and moments
    and the same energy. Raises AssertionError."""
    model = case.model()
    state = case.deformed(model)
    force, moment = model.internal_force(state)
    rotation, _ = RIGID_TEST_MOTIONS[motion]
    turned = moved_rigidly(state, motion)
    force_t, moment_t = model.internal_force(turned)
    bound = case.objectivity
    for what, value, reference in (("force", force_t, force), ("moment", moment_t, moment)):
        error = largest(value - reference @ rotation.T)
        assert error <= bound.value * largest(reference), (
            f"{case}, {motion}: turned {what} off by {error:.3g} > {bound.value:g} x "
            f"{largest(reference):.3g} ({bound.why})"
        )
    energy, energy_t = model.strain_energy(state), model.strain_energy(turned)
    assert _close(energy_t, energy, case.objective_energy.value), (
        f"{case}, {motion}: energy {energy_t!r} turned, {energy!r} not "
        f"({case.objective_energy.why})"
    )


# ---------------------------------------------------------------------- 3. energy gradient
def assert_loads_are_the_energy_gradient(case: ElementCase) -> None:
    """Check 3: at the deformed state, the forces and moments of each of the case's energy
    parts match the central differences of its energy (``energy_gradient``; moments without
    their drilling part about the director). Raises AssertionError."""
    model = case.model()
    state = case.deformed(model)
    frames = model.dofs.frames(state.directors)
    bound = case.gradient
    for part, (energy, part_loads) in case.parts(model).items():
        force, moment = part_loads(state)
        numeric = energy_gradient(model, energy, state)
        fd_force = numeric[:, :3]
        assert largest(fd_force) > 0, f"{case}, {part}: the deformed state must load it"
        error = largest(force - fd_force)
        assert error <= bound.value * largest(fd_force), (
            f"{case}, {part}: force off the energy gradient by {error:.3g} > {bound.value:g} x "
            f"{largest(fd_force):.3g} ({bound.why})"
        )
        if frames is None:
            assert moment is None or not np.any(moment), f"{case}: moments without rotations"
            continue
        v1, v2 = frames
        # dW/dpsi without its drilling part (about the director), from dW/d(alpha, beta).
        fd_moment = numeric[:, 3:4] * v2 + numeric[:, 4:5] * v1
        fd_moment[~model.dofs.has_rotation] = 0.0
        error = largest(moment - fd_moment)
        assert error <= bound.value * max(largest(fd_moment), 1e-12), (
            f"{case}, {part}: moment off the energy gradient by {error:.3g} > {bound.value:g} "
            f"x {largest(fd_moment):.3g} ({bound.why})"
        )


def assert_force_and_energy_agree(case: ElementCase) -> None:
    """Check 3b: at the deformed state, each block's ``internal_force_and_energy`` gives the
    forces, moments and strain energy of its ``internal_force`` and ``strain_energy``, to
    round-off of the largest force and of the energy (a fused pass sums in its own order).
    Raises AssertionError."""
    model = case.model()
    state = case.deformed(model)
    for index, block in enumerate(model.blocks):
        history = state.history[index] if index < len(state.history) else None
        force, moment, energy = block.internal_force_and_energy(state, history)
        alone_force, alone_moment = block.internal_force(state, history)
        alone_energy = block.strain_energy(state, history)
        scale = max(largest(alone_force), 1e-300)
        error = largest(np.asarray(force) - alone_force)
        assert error <= 1e-12 * scale, (
            f"{case}: internal_force_and_energy's force off internal_force by {error:.3g} "
            f"(largest force {scale:.3g})"
        )
        if alone_moment is None:
            assert moment is None or not np.any(moment), f"{case}: moments without rotations"
        else:
            error = largest(np.asarray(moment) - alone_moment)
            assert error <= 1e-12 * max(largest(alone_moment), 1e-300), (
                f"{case}: internal_force_and_energy's moment off internal_force by {error:.3g}"
            )
        assert _close(float(energy), float(alone_energy), ENERGY_ROUND_OFF.value), (
            f"{case}: internal_force_and_energy's energy {energy!r} against strain_energy "
            f"{alone_energy!r} ({ENERGY_ROUND_OFF.why})"
        )


# ---------------------------------------------------------------------- 4. tangent
def assert_tangent_is_the_force_derivative(case: ElementCase) -> None:
    """Check 4: at the deformed state, the element tangent matches the finite-difference
    stiffness of the assembled force on the free DOFs. Raises AssertionError, or
    NotApplicable for an element without a tangent of its own or not a potential."""
    if case.not_a_potential is not None:
        raise NotApplicable(case.not_a_potential)
    model = case.model()
    state = case.deformed(model)
    if any(block.tangent(state) is None for block in model.blocks):
        raise NotApplicable("the element has no tangent of its own: solvers use finite differences")
    free = model.dofs.free_slots
    own = model.stiffness(state, "element").toarray()[np.ix_(free, free)]
    reference = model.stiffness(state, "finite_difference").toarray()[np.ix_(free, free)]
    assert largest(reference) > 0, f"{case}: no stiffness at the deformed state"
    error = largest(own - reference)
    assert error <= case.tangent.value * largest(reference), (
        f"{case}: element tangent off the finite differences by {error:.3g} > "
        f"{case.tangent.value:g} x {largest(reference):.3g} ({case.tangent.why})"
    )


# ---------------------------------------------------------------------- 5. mass
def assert_lumped_mass(case: ElementCase) -> None:
    """Check 5: at the reference and the deformed state, each block's lumped mass sums to the
    case's total mass (and to the block's own ``total_mass()`` if it has one), every node of
    the block has a positive mass, and a positive rotary inertia where it has rotations (None
    without). Raises AssertionError."""
    model = case.model()
    total = case.total_mass(model.mesh) if callable(case.total_mass) else case.total_mass
    bound = case.mass
    for state in (model.initial_state(), case.deformed(model)):
        for block in model.blocks:
            mass, inertia = block.lumped_mass(state)
            nodes = np.unique(block.connectivity)
            own = block.total_mass() if hasattr(block, "total_mass") else None
            if total is not None:
                assert _close(mass.sum(), total, bound.value), (
                    f"{case}: lumped mass sums to {mass.sum()!r}, not to the total mass "
                    f"{total!r} ({bound.why})"
                )
                assert own is None or _close(own, total, bound.value), (
                    f"{case}: the block's total_mass() {own!r} is not the total mass {total!r}"
                )
            elif own is not None:
                assert _close(mass.sum(), own, bound.value), (
                    f"{case}: lumped mass sums to {mass.sum()!r}, not to the block's "
                    f"total_mass() {own!r} ({bound.why})"
                )
            assert (mass[nodes] > 0).all(), f"{case}: a node of the block has no mass"
            if "alpha" in block.dofs:
                assert inertia is not None and (inertia[nodes] > 0).all(), (
                    f"{case}: a node with rotations has no rotary inertia"
                )
            else:
                assert inertia is None, f"{case}: an element without rotations has no inertia"


# ---------------------------------------------------------------------- 6. stable step
def assert_stable_step_is_safe(case: ElementCase, state_name: str) -> None:
    """Check 6: at the step state ``state_name`` (of ``case.states()``), the smallest cell
    step is at most the exact 2 / omega_max of the assembled model and at least
    ``case.step_floor`` of it. Raises AssertionError."""
    model = case.model()
    state = case.states()[state_name](model)
    exact = exact_stable_step(model, state)
    dt = min(float(np.min(block.cell_stable_dt(state))) for block in model.blocks)
    assert dt <= exact, (
        f"{case}, {state_name}: the element step {dt:.4g} s exceeds 2 / omega_max = "
        f"{exact:.4g} s of the assembly: explicit runs would diverge"
    )
    assert dt >= case.step_floor.value * exact, (
        f"{case}, {state_name}: the element step {dt:.4g} s < {case.step_floor.value:g} x the "
        f"exact {exact:.4g} s ({case.step_floor.why})"
    )


# ---------------------------------------------------------------------- 7. mesh size
def assert_stable_step_shrinks_with_the_mesh(case: ElementCase) -> None:
    """Check 7: the stable step of the refine-1 mesh over that of the refine-2 mesh lies in
    ``case.shrink``. Raises AssertionError."""
    coarse, fine = case.model(1), case.model(2)
    ratio = coarse.stable_dt(coarse.initial_state()) / fine.stable_dt(fine.initial_state())
    low, high, why = case.shrink
    assert low <= ratio <= high, f"{case}: step ratio {ratio:.4g} not in [{low}, {high}] ({why})"


# ---------------------------------------------------------------------- 8. capabilities
def assert_declared_capabilities(case: ElementCase) -> None:
    """Check 8: the capabilities each block declares beyond forces, energies and tangents
    (femcore.capability_checks ``check_element_capabilities``), at the reference and the
    case's deformed state."""
    model = case.model()
    reference = model.initial_state()
    deformed = case.deformed(model)
    for i, block in enumerate(model.blocks):
        check_element_capabilities(block, reference, deformed, deformed.history[i])


# ---------------------------------------------------------------------- all of them
def element_checks(case: ElementCase) -> Iterator[tuple[str, Callable[[], None]]]:
    """Every check of the element kit on ``case``, as (name, check) pairs in order."""
    for motion in RIGID_TEST_MOTIONS:
        yield f"rigid {motion}: no load", partial(assert_rigid_motion_gives_no_load, case, motion)
        if case.rigid_fields:
            yield (
                f"rigid {motion}: no strain",
                partial(assert_rigid_motion_leaves_no_strain, case, motion),
            )
        yield f"objective under {motion}", partial(assert_objective, case, motion)
    yield "loads are the energy gradient", partial(assert_loads_are_the_energy_gradient, case)
    yield "force and energy in one call", partial(assert_force_and_energy_agree, case)
    yield "tangent is the force derivative", partial(assert_tangent_is_the_force_derivative, case)
    yield "lumped mass", partial(assert_lumped_mass, case)
    for name in case.states():
        yield f"stable step at {name}", partial(assert_stable_step_is_safe, case, name)
    yield (
        "stable step shrinks with the mesh",
        partial(assert_stable_step_shrinks_with_the_mesh, case),
    )
    yield "declared capabilities", partial(assert_declared_capabilities, case)


def check_element(
    element: ElementType | Callable[[], ElementType] | ElementCase,
    mesh: Mesh | Callable[[int], Mesh] | None = None,
    **case_options,
) -> ConformanceReport:
    """Run every check of the element kit and report (never raises for a failed check).

    Parameters
    ----------
    element : ElementType, callable or ElementCase
        The element type to check (an instance, or a function making one), or a whole case
        (then ``mesh`` and ``case_options`` are not given).
    mesh : Mesh or callable
        A small mesh of the element's cells, or ``refine -> Mesh`` (refine 1 and 2); a single
        mesh leaves out the mesh-size check (reported not applicable).
    **case_options
        Any other field of ``ElementCase`` (``name``, ``total_mass``, ``deform``,
        ``rigid_fields``, the tolerances, ...).

    Returns
    -------
    ConformanceReport
        ``report.passed``; ``str(report)`` lists every check with its outcome.
    """
    if isinstance(element, ElementCase):
        if mesh is not None or case_options:
            raise TypeError("check_element(case) takes no mesh or other options")
        case = element
    else:
        if mesh is None:
            raise TypeError("check_element needs a mesh (or refine -> Mesh)")
        make = element if not isinstance(element, ElementType) else (lambda: element)
        instance = make()
        case_options.setdefault("name", type(instance).__name__)
        case = ElementCase(element=make, mesh=_mesh_maker(mesh), **case_options)
    return run_checks(case.name, element_checks(case))


def _mesh_maker(mesh: Mesh | Callable[[int], Mesh]) -> Callable[[int], Mesh]:
    if not isinstance(mesh, Mesh):
        return mesh

    def fixed(refine: int) -> Mesh:
        if refine != 1:
            raise NotApplicable("give the mesh as refine -> Mesh for the mesh-size check")
        return mesh

    return fixed


# ---------------------------------------------------------------------- interactions
# The interaction kit lives in its own module (one idea per file); its checks are importable
# from here too, so that a user's suite finds both kits in one place.
from femcore import interaction_checks  # noqa: E402
from femcore.interaction_checks import *  # noqa: E402, F403

__all__ += interaction_checks.__all__
