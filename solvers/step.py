"""One explicit central-difference step, public for a solver loop of one's own (docs/theory.md
§6.1): Bai Eq. 22-23 with a variable step, dt_bar = (dt_prev + dt)/2 and mass-proportional
damping C = c M,

    v(i+1/2) = [(1 - c dt_bar/2) v(i-1/2) + dt_bar M^-1 (F_ext - F_int)(i)] / (1 + c dt_bar/2)
    x(i+1)   = x(i) + dt v(i+1/2)

Rotations follow the same update with the rotary inertia and the moment vectors, on a nodal
angular velocity kept perpendicular to the director; the director then turns by the finite
rotation dt * omega (Rodrigues, docs/theory.md §1.3).

``explicit_step`` is the whole step of CentralDifference (loads, internal forces, the fused
update of the velocities with the support reactions and the energy terms, the rotations, the
configuration update). Its two last phases are public on their own, for a loop that computes
its forces itself (DynamicRelaxation: it judges convergence on them first and moves with
fictitious masses): ``angular_rates``, the damped update of the angular velocities with the
director constraints, and ``advance``, the configuration update.

A loop of one's own, with a fixed step and damping::

    masses = LumpedMasses.of(model, model.initial_state())
    state, previous = model.initial_state(), 0.0  # from rest: the first step is a half step
    for _ in range(steps):
        step = explicit_step(model, state, dt, masses, dt_prev=previous, damping=50.0,
                             duration=steps * dt)
        state, previous = model.commit(step.state), dt
    print(state.positions[tip] - model.reference_positions[tip])
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from femcore.model import CompiledModel
from femcore.rotation import drop_along
from femcore.state import State
from solvers.common import inverse_diagonal
from solvers.dynamics import EnergyAccount, damped_velocity, update_rates
from solvers.turning import COMPILED, move, rates, turn

__all__ = [
    "LumpedMasses",
    "Step",
    "advance",
    "angular_rates",
    "explicit_step",
    "rotational_update",
]


@dataclass(frozen=True, eq=False)
class LumpedMasses:
    """The lumped masses a step moves with.

    mass : (n,) nodal masses, t (N s^2 / mm).
    inertia : (n,) rotary inertia per node, t mm^2 (0 at nodes without rotations).
    inverse_mass, inverse_inertia : (n, 1) 1/m and 1/I, 0 where not positive (derived).
    """

    mass: np.ndarray
    inertia: np.ndarray
    inverse_mass: np.ndarray = field(init=False)
    inverse_inertia: np.ndarray = field(init=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "inverse_mass", inverse_diagonal(self.mass))
        object.__setattr__(self, "inverse_inertia", inverse_diagonal(self.inertia))

    @classmethod
    def of(
        cls, model: CompiledModel, state: State, density_scale: list | None = None
    ) -> LumpedMasses:
        """The model's lumped masses and rotary inertia at ``state`` (``density_scale``: one
        (cells,) factor array per block, selective mass scaling, or None)."""
        mass, inertia = model.lumped_mass(state, density_scale)
        return cls(mass, inertia)


@dataclass(frozen=True, eq=False)
class Step:
    """The outcome of one explicit step.

    state : the State at t + dt (velocities v(i+1/2), time and load factor advanced), not yet
        committed: ``model.commit(step.state)`` updates the element histories once accepted.
    reactions : (n, 3) support forces at t, N: what the constraints add to the momentum balance.
    reaction_moments : (n, 3) support moments at t, N mm.
    energy : the 8 energy terms of ``solvers.dynamics.EnergyAccount.increments``, N mm:
        external, internal and damping work over [t - dt_prev/2, t + dt/2], the new kinetic
        energy, and for the checks at t (zeros unless ``checking``) the kinetic energy
        1/2 v(i-1/2) . M v(i+1/2), that of the mean velocity, and the external and damping
        work done before t.
    strain_energy : the model's strain energy at t, N mm, on the steps taken with
        ``checking`` (met by the force pass: ``CompiledModel.internal_force_and_energy``);
        None on the others.
    """

    state: State
    reactions: np.ndarray
    reaction_moments: np.ndarray
    energy: tuple[float, ...]
    strain_energy: float | None = None

    @property
    def external_work(self) -> float:
        """The external work of the step (tools and reactions included), N mm."""
        return self.energy[0]

    @property
    def kinetic_energy(self) -> float:
        """1/2 v.M v + 1/2 omega.I omega at t + dt/2, N mm."""
        return self.energy[3]


def explicit_step(
    model: CompiledModel,
    state: State,
    dt: float,
    masses: LumpedMasses,
    *,
    dt_prev: float | None = None,
    damping: float = 0.0,
    duration: float = 1.0,
    checking: bool = False,
) -> Step:
    """One central-difference step from ``state`` (left unchanged).

    Parameters
    ----------
    model : CompiledModel
    state : State
        At t(i), with the velocities v(i-1/2).
    dt : float
        s, the step to t(i+1).
    masses : LumpedMasses
    dt_prev : float or None
        s, the step that led to t(i) (None: dt, a constant step). The first step from rest
        takes 0: v(1/2) = (dt/2) M^-1 F(0), as CentralDifference does.
    damping : float
        c of the mass-proportional damping C = c M, 1/s.
    duration : float
        s, the length of the loading: loads and prescribed displacements are taken at
        t / duration of their amplitudes, and the new state's load factor is t(i+1) / duration.
    checking : bool
        Compute the energy terms of the checks at t(i) too (``Step.energy``), and the strain
        energy at t(i) with the internal forces (``Step.strain_energy``).

    Returns
    -------
    Step
    """
    dt_prev = dt if dt_prev is None else dt_prev
    c = damping
    inertia = masses.inertia
    dofs = model.dofs
    t_next = state.time + dt
    dt_bar = 0.5 * (dt_prev + dt)
    velocity, omega = state.velocities, state.angular_velocities

    f_ext, m_ext = model.external_load(state.time / duration)
    strain = None
    if checking:
        f_int, m_int, strain = model.internal_force_and_energy(state)
    else:
        f_int, m_int = model.internal_force(state)
    target = None
    if model.has_prescribed:
        goal = model.reference_positions + model.prescribed_displacement(t_next / duration)
        target = np.where(model.translation_prescribed, (goal - state.positions) / dt, np.nan)
    v_new, reactions, work = update_rates(
        velocity,
        f_ext,
        f_int,
        masses.mass,
        model.translation_free,
        model.translation_constrained,
        target,
        (dt_bar, dt, dt_prev),
        c,
        checking,
        masses.inverse_mass,
    )
    if model.n_tools:
        work = _tool_work(model, state, dt, dt_prev, work, checking, duration)
    if dofs.any_rotation:
        # One pass over the nodes (solvers/turning.py): what ``rotational_update`` does.
        w_new, reaction_moments, directors, positions, turning = turn(
            omega,
            (m_ext, m_int),
            state.directors,
            (state.positions, v_new),
            inertia,
            model.has_rotation,
            model.rotation_fixed,
            (dt_bar, dt, dt_prev),
            c,
            checking,
        )
        work = tuple(a + b for a, b in zip(work, turning))
    else:
        w_new, reaction_moments = omega, np.zeros_like(reactions)
        moved = advance(model, state, dt, v_new)
        positions, directors = moved.positions, moved.directors
    # made at once (not two dataclass replaces: a step's Python is most of a small model's)
    new = State(positions, directors, v_new, w_new, t_next, t_next / duration, state.history)
    return Step(new, reactions, reaction_moments, work, strain)


def rotational_update(
    model: CompiledModel,
    state: State,
    dt: float,
    masses: LumpedMasses,
    moments: tuple[np.ndarray, np.ndarray],
    velocities: np.ndarray,
    dt_prev: float,
    damping: float = 0.0,
    checking: bool = False,
) -> tuple[State, np.ndarray, tuple[float, ...]]:
    """The rotational half of ``explicit_step`` in numpy passes over (n, 3) arrays: the
    reference that solvers/turning.py's one compiled pass is tested against.

    moments : (external, internal) moment vectors (n, 3) at t(i), N mm. velocities : (n, 3)
    v(i+1/2), mm/s. Returns (the state moved to t(i+1) with omega(i+1/2), the support
    moments (n, 3), the 8 energy terms of the rotations)."""
    c, inertia = damping, masses.inertia
    dt_bar = 0.5 * (dt_prev + dt)
    m_ext, m_int = moments
    # Only the drilling part is dropped here, so that the update below sees what a fixed
    # alpha / beta has to hold: that difference is the support moment.
    moment = drop_along(m_ext - m_int, state.directors)
    omega = state.angular_velocities
    w_free = damped_velocity(omega, moment, masses.inverse_inertia, dt_bar, c)
    w_new = model.constrain_angular(w_free, state.directors)
    reaction_moments = inertia[:, None] * (w_new - w_free) * (1.0 + 0.5 * c * dt_bar) / dt_bar
    turning = EnergyAccount.increments(
        (m_ext + reaction_moments, m_int),
        (state.angular_velocities, w_new),
        inertia,
        c,
        dt_prev,
        dt,
        checking,
    )
    moved = model.dofs.move(state, dt * velocities, dt * w_new)
    moved = replace(moved, angular_velocities=w_new)
    return moved, reaction_moments, turning


def angular_rates(
    model: CompiledModel,
    omega: np.ndarray,
    moment: np.ndarray,
    inverse_inertia: np.ndarray,
    dt_bar: float,
    damping: float,
    directors: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """The damped central-difference update of the angular velocities (``damped_velocity``)
    and the same with the constraints applied (no drilling part, the fixed alpha / beta
    removed: CompiledModel.constrain_angular).

    omega : (n, 3) omega(i-1/2), rad/s. moment : (n, 3) out-of-balance moments at t(i), N mm.
    inverse_inertia : (n, 1) 1/I. dt_bar : s. damping : c, 1/s. directors : (n, 3) at t(i).
    Returns (free, constrained) omega(i+1/2), (n, 3) each.
    """
    if COMPILED:  # one pass over the nodes (solvers/turning.py), the numpy formulas
        return rates(
            omega,
            moment,
            inverse_inertia,
            model.has_rotation,
            model.rotation_fixed,
            directors,
            dt_bar,
            damping,
        )
    free = damped_velocity(omega, moment, inverse_inertia, dt_bar, damping)
    return free, model.constrain_angular(free, directors)


def advance(
    model: CompiledModel,
    state: State,
    dt: float,
    velocities: np.ndarray,
    angular_velocities: np.ndarray | None = None,
) -> State:
    """The configuration update: positions + dt v (n, 3), directors turned by the finite
    rotations dt omega (n, 3) at the nodes that have them (None: not turned); the rates of
    the returned state are those of ``state``."""
    if COMPILED and angular_velocities is not None and model.dofs.any_rotation:
        positions, directors = move(
            state.positions,
            state.directors,
            velocities,
            angular_velocities,
            dt,
            model.has_rotation,
        )
        return replace(state, positions=positions, directors=directors)
    return model.dofs.move(
        state, dt * velocities, None if angular_velocities is None else dt * angular_velocities
    )


def _tool_work(
    model: CompiledModel, state: State, dt, dt_prev, work, checking: bool, duration: float
) -> tuple:
    """The step's energy terms with the work of moving tools added to the external work:
    their motion over [t(i - 1/2), t(i + 1/2)] (and [t(i - 1/2), t(i)] for the checks)
    against the contact forces at t(i), the midpoint rule of the other terms.

    The internal work gets it too: the contact springs are parts of the model, and the work
    of their forces on the nodes alone, -f.dx, is their energy change less the tool's work
    (d(1/2 k p^2) = -f.dx + f.dx_tool); with the tool's work added back it is the change of
    the strain energy, so that the internal work is U and the tool's work is counted once,
    in the external work."""
    tau = state.time / duration
    before = tau - 0.5 * dt_prev / duration
    d_tool = model.tool_work(state, before, tau + 0.5 * dt / duration)
    terms = list(work)
    terms[0] += d_tool
    terms[1] += d_tool
    if checking:  # the checks need the work done before t(i) too
        terms[6] += model.tool_work(state, before, tau)
    return tuple(terms)
