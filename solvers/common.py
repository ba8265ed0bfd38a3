"""Pieces shared by the solvers: errors that keep the last good result, an increment's
failure (Static), frames, progress."""

from __future__ import annotations

import os
import sys
import warnings
from types import FrameType

import numpy as np

from femcore.checks import as_number, check_positive
from femcore.diagnostics import unbalanced_translations, unbalanced_turns
from femcore.frame_branches import changed_meaning
from femcore.model import CompiledModel, Model
from femcore.results import Frame, Result
from femcore.rotation import FRAME_FALLBACK
from femcore.state import State
from solvers.driven_tool_checks import check_driven_tools_face_body
from solvers.progress import ProgressLine, resolve_progress

__all__ = [
    "outside_stacklevel",
    "ConvergenceError",
    "DivergenceError",
    "IncrementFailed",
    "ProgressLine",
    "SolverError",
    "StepTooLong",
    "TurnedInsideOut",
    "check_flag",
    "check_fraction",
    "check_held",
    "check_integer",
    "check_non_negative",
    "check_positive_or_none",
    "check_tolerance",
    "compiled_model",
    "empty_result",
    "equilibrium_reactions",
    "inverse_diagonal",
    "make_frame",
    "resolve_progress",
]


class SolverError(RuntimeError):
    """A solve that could not reach its goal. ``result`` holds every good frame up to the
    failure (``result.converged`` is False), so the last good state can be inspected or
    written; ``load_factor`` is the last load factor reached, where the solver has one;
    ``steps`` the iterations of an increment it did not finish, where the solver counts them
    in ``result.steps`` (dynamic relaxation); ``cuts`` the halvings of that increment
    (dynamic relaxation's ``info["cuts"]``)."""

    load_factor: float | None = None
    steps: int = 0
    cuts: int = 0

    def __init__(self, message: str, result: Result | None, steps: int = 0):
        super().__init__(message)
        self.result = result
        self.steps = steps


class SettingError(ValueError):
    """A solver setting this model cannot be run with, found as the solve starts (more steps
    than ``max_steps``, more mass scaling than ``max_added_mass``): ``option`` names the
    setting at fault, so that a case file's error can point at its key."""

    def __init__(self, option: str, message: str) -> None:
        super().__init__(message)
        self.option = option

    def __reduce__(self):
        # Rebuilt from its own arguments, not ``args`` (the message alone): it crosses a
        # process pool (a sweep's or a report's worker) as it was raised.
        return (type(self), (self.option, str(self)))


class DivergenceError(SolverError):
    """Non-finite values or an energy blow-up: the time step is too large for the model, a
    material law left its range, or a load drives the structure unstable."""


class ConvergenceError(SolverError):
    """The iterations ran out before equilibrium was reached."""


class IncrementFailed(Exception):
    """An increment that did not converge (caught to cut the increment); ``iterations`` and
    ``history`` (the residual ratios) of the attempt, when known; ``predicted``: how many
    contact sets the attempt predicted (solvers/newton.py)."""

    iterations = 0
    history: list[float] = []
    predicted = 0


class StepTooLong(IncrementFailed):
    """The first Newton step of an increment turns a director by ``turn`` (rad), more than
    the ``turn_limit`` of solvers.newton.newton: the increment is cut before it is iterated."""

    def __init__(self, turn: float):
        super().__init__(f"the first Newton step turns a director by {turn:.3g} rad")
        self.turn = turn


class TurnedInsideOut(IncrementFailed):
    """An increment that converged with cells turned inside out
    (``CompiledModel.inverted_cells``): cut, never kept (solvers/static_run.py
    ``StaticRun.refuse_inverted``)."""


def check_held(model: CompiledModel, swings: bool = False) -> None:
    """Raise ValueError when the loads push the model along a rigid motion that no support holds
    (CompiledModel.unheld_rigid_motions; a check at the starting shape, linear).

    Where the loads have a net force along a translation nothing holds, no equilibrium exists at
    any shape (femcore.diagnostics.unbalanced_translations; so where moments turn it about a
    free axis that no force can turn it back about, unbalanced_turns), and a quasi-static solver
    would only report a residual that never falls. Where the loaded free motions are rotations
    (a strip held at an edge in translations only, a cable pinned at one end, under gravity),
    the model is a mechanism at its starting shape, where Static cannot start (its tangent is
    singular along them), but it may hang in equilibrium a finite motion away: refused with
    ``swings=False`` (Static), let through with ``swings=True`` (DynamicRelaxation, whose damped
    motion swings it down there). A model held by contact is refused for any rigid motion left
    free, loaded or not: a body on a frictionless tool slides along it at the first sideways
    force (the tools' curvature, the round-off of the contact forces), and its tangent is
    singular along the slide. A force-driven tool whose force points away from the body is
    refused first (solvers/driven_tool_checks.py): no position balances it."""
    check_driven_tools_face_body(model)
    motions = model.unheld_rigid_motions()
    notes = model.interaction_notes()
    noted = "".join(f"; {note}" for note in notes)
    if motions:
        pushed = unbalanced_translations(model)
        if pushed:
            raise ValueError(
                f"the loads have a net force along rigid motions that nothing holds "
                f"({'; '.join(pushed)}){noted}: no equilibrium exists at any shape. Fix or "
                "prescribe DOFs that hold them (model.fix, model.displace), or balance the loads"
            )
        turned = unbalanced_turns(model)
        if turned:
            raise ValueError(
                f"the moments turn the model along rigid motions that nothing holds "
                f"({'; '.join(turned)}){noted}, and no force can turn it back (every force "
                "lies along that axis, or none acts): no equilibrium exists at any shape. Fix "
                "or prescribe DOFs that hold them (model.fix, model.displace), or balance the "
                "moments"
            )
        if not swings:
            raise ValueError(
                f"the loads turn the model along rigid motions that nothing holds at its "
                f"starting shape ({'; '.join(motions)}){noted}: it is a mechanism there, and "
                "Static cannot start from it (its tangent stiffness is singular along them). An "
                "equilibrium may lie a finite motion away (a model hanging from a pin): reach "
                "it with DynamicRelaxation, or fix or prescribe DOFs that hold those motions "
                "(model.fix, model.displace)"
            )
    if notes:
        motions = model.unheld_rigid_motions(loaded_only=False)
        if motions:
            raise ValueError(
                f"nothing holds the model against {_listed(motions)}: {'; '.join(notes)}. "
                "Fix or prescribe a node's DOFs along them (model.fix, model.displace), or "
                "add friction to the contact"
            )


def _listed(names: list[str]) -> str:
    """ "a", "a and b", "a, b and c"."""
    return names[0] if len(names) == 1 else ", ".join(names[:-1]) + " and " + names[-1]


def make_frame(
    model: CompiledModel,
    state: State,
    reactions: np.ndarray | None = None,
    reaction_moments: np.ndarray | None = None,
    balanced: State | None = None,
) -> Frame:
    """Snapshot of a state (arrays copied) with reactions and the elements' output fields;
    the reaction moments given gain the supports' moments on no DOF
    (``CompiledModel.support_moments``).
    ``balanced``: the state whose forces the solver balanced, where the tools' forces are
    taken (Static: the converged state before the commit updated its history; ``state``
    itself when None)."""
    n = model.n_nodes
    balanced = state if balanced is None else balanced
    warn_changed_meaning(model, state)
    if reaction_moments is not None:
        # The supports' moments on no DOF (a fibrous clamp's wall, docs/theory.md §4.5)
        # belong to the reactions as much as those on the fixed rotations.
        reaction_moments = reaction_moments + model.support_moments(balanced)
    return Frame(
        time=float(state.time),
        load_factor=float(state.load_factor),
        positions=state.positions.copy(),
        velocities=state.velocities.copy(),
        directors=state.directors.copy(),
        reactions=np.zeros((n, 3)) if reactions is None else reactions.copy(),
        reaction_moments=np.zeros((n, 3)) if reaction_moments is None else reaction_moments.copy(),
        fields=model.fields(state),
        tool_forces=model.tool_forces(balanced),
        tool_displacements=model.tool_displacements(state),
    )


def warn_changed_meaning(model: CompiledModel, state: State) -> None:
    """Warn where a director DOF fixed alone holds, at ``state``, another rotation than at the
    start (femcore.frame_branches.changed_meaning: a director that crossed the cone of the
    nodal frame's fallback, docs/theory.md §1.2); once per message, as warnings do."""
    if not model.rotation_fixed.any():
        return
    nodes = changed_meaning(model.reference_directors, state.directors, model.rotation_fixed)
    if nodes.size:
        warnings.warn(
            f"at nodes {nodes[:10].tolist()}{' ...' if nodes.size > 10 else ''} the director "
            f"turned across the cone within {np.degrees(np.arcsin(FRAME_FALLBACK)):.1f} deg "
            "of +-e2 where the nodal frame changes (docs/theory.md §1.2), and the alpha or "
            "beta fixed there alone now holds another rotation than at the start: the "
            "support is no longer the one given; turn the model so that such a plane is "
            "x = const or y = const, where one DOF names the turn out of it on both frames",
            stacklevel=outside_stacklevel(),
        )


def empty_result(model: CompiledModel, frames: list[Frame]) -> Result:
    return Result(mesh=model.mesh, frames=frames, has_rotation=model.has_rotation.copy())


def check_positive_or_none(value, name: str, unit: str = "") -> float | None:
    """None, or a finite positive float (ValueError naming the parameter otherwise)."""
    return None if value is None else check_positive(value, name, unit)


def inverse_diagonal(values: np.ndarray) -> np.ndarray:
    """1 / m as an (n, 1) column for a lumped diagonal (n,), 0 where m is not positive (nodes
    without that kind of DOF), ready to scale (n, 3) residuals."""
    positive = values > 0
    return np.where(positive, 1.0 / np.where(positive, values, 1.0), 0.0)[:, None]


def check_tolerance(value, name: str = "tol") -> float:
    """A relative tolerance strictly between 0 and 1, or ValueError naming it."""
    number = as_number(value, name, "in (0, 1)")
    if not np.isfinite(number) or not (0.0 < number < 1.0):
        raise ValueError(f"{name} must be in (0, 1), got {value!r}")
    return number


def check_integer(value, name: str, minimum: int = 1) -> int:
    """An int >= ``minimum``, or ValueError naming the option. Floats are refused, even
    whole ones (2.5 would be truncated, NaN has no count), and so are booleans (True is not a
    count of anything)."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise ValueError(f"{name} must be an integer >= {minimum}, got {value!r}")
    return int(value)


def check_non_negative(value, name: str, unit: str) -> float:
    """A finite float >= 0, or ValueError naming the option and its unit."""
    number = as_number(value, name, f"a non-negative number ({unit})")
    if not np.isfinite(number) or number < 0.0:
        raise ValueError(f"{name} must be a non-negative number ({unit}), got {value!r}")
    return number


def check_fraction(value, name: str) -> float:
    """A float in (0, 1] (a safety factor), or ValueError naming the option."""
    number = as_number(value, name, "in (0, 1]")
    if not (0.0 < number <= 1.0):
        raise ValueError(f"{name} must be in (0, 1], got {value!r}")
    return number


def check_progress(value) -> bool | None:
    """The ``progress`` option: None (the default rule of ``resolve_progress``), True or
    False; ValueError otherwise (``bool("no")`` would be True)."""
    return None if value is None else check_flag(value, "progress")


def check_flag(value, name: str) -> bool:
    """True or False, or ValueError naming the option: bool("no") would be True."""
    if not isinstance(value, (bool, np.bool_)):
        raise ValueError(f"{name} must be true or false, got {value!r}")
    return bool(value)


def compiled_model(model, solver: str) -> CompiledModel:
    """The compiled model of a Model (compiled now) or a CompiledModel, or ValueError saying
    what ``solve`` got instead."""
    if isinstance(model, Model):
        return model.compile()
    if isinstance(model, CompiledModel):
        return model
    raise ValueError(
        f"{solver}.solve expects a femcore Model or CompiledModel, got "
        f"{type(model).__name__} {model!r:.60}"
    )


def equilibrium_reactions(
    model: CompiledModel, state: State, f_ext: np.ndarray, m_ext: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Support forces (n, 3) and moments (n, 3) of a static equilibrium: F_int - F_ext on the
    constrained translations, M_int - M_ext at the nodes with a fixed rotation."""
    f_int, m_int = model.internal_force(state)
    reactions = np.where(model.translation_constrained, f_int - f_ext, 0.0)
    reaction_moments = np.where(
        model.has_rotation[:, None] & model.rotation_fixed.any(1)[:, None], m_int - m_ext, 0.0
    )
    return reactions, reaction_moments


def outside_stacklevel() -> int:
    """The ``stacklevel`` of ``warnings.warn`` that names the first frame outside the
    solvers package: the user's call of ``solve``, however many wrappers (interrupts, BLAS
    threads) and helpers lie between. Called by the function that warns."""
    package = os.path.dirname(os.path.abspath(__file__))
    frame: FrameType | None = sys._getframe(1)  # the function that warns: level 1
    level = 1
    while frame is not None:
        if os.path.dirname(os.path.abspath(frame.f_code.co_filename)) != package:
            break
        frame = frame.f_back
        level += 1
    return level
