"""Pieces shared by the solvers: errors that keep the last good result, frames, progress."""

from __future__ import annotations

import sys
import time

import numpy as np

from femcore.checks import check_positive
from femcore.model import CompiledModel
from femcore.results import Frame, Result
from femcore.state import State

__all__ = [
    "ConvergenceError",
    "DivergenceError",
    "ProgressLine",
    "SolverError",
    "check_held",
    "check_integer",
    "check_positive_or_none",
    "check_tolerance",
    "empty_result",
    "equilibrium_reactions",
    "inverse_diagonal",
    "make_frame",
    "resolve_progress",
    "unsupported_rigid_motions",
]


class SolverError(RuntimeError):
    """A solve that could not reach its goal. ``result`` holds every good frame up to the
    failure (``result.converged`` is False), so the last good state can be inspected or
    written; ``load_factor`` is the last load factor reached, where the solver has one."""

    load_factor: float | None = None

    def __init__(self, message: str, result: Result | None):
        super().__init__(message)
        self.result = result


class DivergenceError(SolverError):
    """Non-finite values or an energy blow-up: the time step is too large for the model, a
    material law left its range, or a load drives the structure unstable."""


class ConvergenceError(SolverError):
    """The iterations ran out before equilibrium was reached."""


def check_held(model: CompiledModel) -> None:
    """Raise ValueError when the loads push the model along a rigid motion that no support
    holds: no equilibrium exists, and a quasi-static solver would only report a residual that
    never falls (CompiledModel.unheld_rigid_motions)."""
    motions = model.unheld_rigid_motions()
    if motions:
        raise ValueError(
            f"the loads push the model along rigid motions that nothing holds "
            f"({'; '.join(motions)}): no equilibrium exists. Fix or prescribe DOFs that hold "
            "them (model.fix, model.displace), or balance the loads"
        )


_RIGID_NAMES = (
    "translation along x",
    "translation along y",
    "translation along z",
    "rotation about x",
    "rotation about y",
    "rotation about z",
)


def unsupported_rigid_motions(model: CompiledModel) -> list[str]:
    """The rigid motions of the whole model that its fixed and prescribed DOFs leave free,
    whatever the loads: the elementary ones (e.g. "translation along x"), or one line for a
    free combination of them; empty when the supports hold all six.

    A rigid motion (u, psi) per node (rotations about axes through the centroid, directors
    turning with the body) is held when some constrained DOF moves with it; the six motions
    restricted to the constrained DOFs span what the supports hold (their rank by an SVD,
    rotations scaled by the model size to compare with translations).
    """
    dofs = model.dofs
    x = model.reference_positions
    carried = dofs.active[:, 0]
    centre = x[carried].mean(axis=0) if carried.any() else x.mean(axis=0)
    length = max(float(np.ptp(x, axis=0).max()), 1e-300)
    axes = np.eye(3)
    translation = np.zeros((6, model.n_nodes, 3))
    translation[:3] = axes[:, None, :]
    translation[3:] = np.cross(axes[:, None, :], (x - centre)[None]) / length
    rotation = np.zeros((6, model.n_nodes, 3))
    rotation[3:] = np.where(model.has_rotation[None, :, None], axes[:, None, :], 0.0)
    frames = dofs.frames(model.reference_directors)
    v1, v2 = frames if frames is not None else (x, x)
    generalised = np.concatenate(
        [
            translation,
            np.sum(rotation * v2, axis=-1)[..., None] / length,
            np.sum(rotation * v1, axis=-1)[..., None] / length,
        ],
        axis=-1,
    )  # (6, n, 5), every motion scaled to unit size over the model
    held = generalised[:, dofs.constrained].T  # (constrained DOFs, 6)
    if not held.size:
        return list(_RIGID_NAMES)
    _, singular, vt = np.linalg.svd(held, full_matrices=True)
    rank = int(np.sum(singular > 1e-9 * max(float(singular.max()), 1.0)))
    if rank == 6:
        return []
    untouched = np.abs(held).max(axis=0) == 0.0
    named = [name for name, free in zip(_RIGID_NAMES, untouched) if free]
    return named or [
        "a rigid motion combining "
        + ", ".join(name for name, w in zip(_RIGID_NAMES, np.abs(vt[rank])) if w > 1e-6)
    ]


def make_frame(
    model: CompiledModel,
    state: State,
    reactions: np.ndarray | None = None,
    reaction_moments: np.ndarray | None = None,
) -> Frame:
    """Snapshot of a state (arrays copied) with reactions and the elements' output fields."""
    n = model.n_nodes
    return Frame(
        time=float(state.time),
        load_factor=float(state.load_factor),
        positions=state.positions.copy(),
        velocities=state.velocities.copy(),
        directors=state.directors.copy(),
        reactions=np.zeros((n, 3)) if reactions is None else reactions.copy(),
        reaction_moments=np.zeros((n, 3)) if reaction_moments is None else reaction_moments.copy(),
        fields=model.fields(state),
    )


def empty_result(model: CompiledModel, frames: list[Frame]) -> Result:
    return Result(mesh=model.mesh, frames=frames, has_rotation=model.has_rotation.copy())


def resolve_progress(progress: bool | None) -> bool:
    """Progress lines are shown on an interactive terminal unless asked otherwise; never under
    pytest unless asked (its captured stderr is not a terminal)."""
    if progress is not None:
        return bool(progress)
    return sys.stderr.isatty()


class ProgressLine:
    """Prints a status line to stderr at most every ``every`` seconds (and on demand)."""

    def __init__(self, enabled: bool, label: str, every: float = 2.0):
        self.enabled = enabled
        self.label = label
        self.every = every
        self._last = time.perf_counter()

    def __call__(self, text: str, force: bool = False) -> None:
        if not self.enabled:
            return
        now = time.perf_counter()
        if force or now - self._last >= self.every:
            self._last = now
            print(f"[{self.label}] {text}", file=sys.stderr, flush=True)


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
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be in (0, 1), got {value!r}") from None
    if not np.isfinite(number) or not (0.0 < number < 1.0):
        raise ValueError(f"{name} must be in (0, 1), got {value!r}")
    return number


def check_integer(value, name: str, minimum: int = 1) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise ValueError(f"{name} must be an integer >= {minimum}, got {value!r}")
    return int(value)


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
