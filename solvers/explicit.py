"""Explicit dynamics: the central difference scheme of Bai Eq. 22-23 (docs/theory.md §6.1-6.3).

With a variable step, dt_bar = (dt_prev + dt)/2 and mass-proportional damping C = c M:

    v(i+1/2) = [(1 - c dt_bar/2) v(i-1/2) + dt_bar M^-1 (F_ext - F_int)(i)] / (1 + c dt_bar/2)
    x(i+1)   = x(i) + dt v(i+1/2)

Rotations follow the same update with the rotary inertia and the moment vectors, on a nodal
angular velocity kept perpendicular to the director; the director then turns by the finite
rotation dt * omega (Rodrigues, docs/theory.md §1.3).
"""

from __future__ import annotations

import math
import time
from dataclasses import replace

import numpy as np

from femcore.model import CompiledModel, Model
from femcore.results import Result
from femcore.rotation import drop_along
from femcore.state import State
from solvers.common import (
    DivergenceError,
    ProgressLine,
    check_positive_or_none,
    empty_result,
    inverse_diagonal,
    make_frame,
    resolve_progress,
)
from solvers.dynamics import EnergyAccount, FrameSchedule, damped_velocity

__all__ = ["CentralDifference"]

# The step is re-evaluated every this many steps: geometry and tension change slowly per step.
STABLE_DT_EVERY = 10
# Energy records kept for the history (more steps are thinned to about this many records).
ENERGY_RECORDS = 4000
# The assembled (Gershgorin) stable step is evaluated again every this many steps (it costs a
# tangent assembly, tens of force evaluations); in between it follows the cells' bound.
ASSEMBLED_DT_EVERY = 500
# The energy balance is checked every this many steps (it costs one strain-energy evaluation,
# about a force evaluation) and on the last step.
BALANCE_EVERY = 10
# The checks of a run (EnergyAccount.check, docs/theory.md §6.1): the largest energy balance
# error |KE* + U + D - W_ext| / (largest energy of the run) (a good run: 1e-7 on a sagging
# cable, 2e-3 on the G1151 strip, 1e-2 on a bar under a step load); the largest (KE + U) /
# (work supplied) (a stable linear run stays below 1 / (1 - (omega dt / 2)^2), 10 at omega dt =
# 1.9: 0.95 of an exact critical step) and the largest at which a state is still kept as the
# last good one (2: omega dt = 1.4 may reach it with all the energy in the highest mode); the
# largest motion of a node in one step, in median element edges.
BALANCE_TOLERANCE = 0.05
GROWTH_LIMIT = 10.0
GOOD_GROWTH = 2.0
MAX_STEP_MOTION = 0.5


class CentralDifference:
    """Explicit central-difference dynamics over ``duration`` seconds.

    duration : s, the length of the step; loads reach their amplitude at its end.
    dt : s, a fixed time step, or None for safety x the stable step (re-evaluated as the
        geometry changes).
    safety : factor on the stable step (0 < safety <= 1).
    damping : c of the mass-proportional damping C = c M, 1/s.
    mass_scaling_dt : s, a target step: cells whose stable step is smaller get their density
        scaled by (target / dt_cell)^2 so that the step is the target; the added mass is
        reported in ``result.info``.
    output_interval : s between frames (default duration / 20).
    progress : print status lines (None: only on an interactive terminal).
    """

    def __init__(
        self,
        duration: float,
        dt: float | None = None,
        safety: float = 0.9,
        damping: float = 0.0,
        mass_scaling_dt: float | None = None,
        output_interval: float | None = None,
        progress: bool | None = None,
        max_steps: int = 50_000_000,
    ):
        checked = check_positive_or_none(duration, "duration")
        if checked is None:
            raise ValueError("duration must be a positive number of seconds")
        self.duration: float = checked
        self.dt = check_positive_or_none(dt, "dt")
        if not (0.0 < float(safety) <= 1.0):
            raise ValueError(f"safety must be in (0, 1], got {safety!r}")
        self.safety = float(safety)
        if not np.isfinite(damping) or damping < 0:
            raise ValueError(f"damping must be a non-negative number (1/s), got {damping!r}")
        self.damping = float(damping)
        self.mass_scaling_dt = check_positive_or_none(mass_scaling_dt, "mass_scaling_dt")
        self.output_interval = check_positive_or_none(output_interval, "output_interval")
        self.progress = progress
        self.max_steps = int(max_steps)
        # (assembled Gershgorin step, the cells' bound when it was evaluated), set by solve
        self._assembled: tuple[float, float] | None = None

    # ------------------------------------------------------------------ time step
    def _density_scale(self, model: CompiledModel, state: State):
        if self.mass_scaling_dt is None:
            return None
        target = self.mass_scaling_dt / self.safety
        return [np.maximum(1.0, (target / dt) ** 2) for dt in model.cell_stable_dt(state)]

    def _step_size(self, model: CompiledModel, state: State, scale, masses=None) -> float:
        """safety x the critical step: the larger of two safe bounds, the cells' own (cheap,
        every STABLE_DT_EVERY steps) and the assembly's Gershgorin bound (``masses`` = (mass,
        inertia) given: evaluated now; else the last one, carried along with the cells'
        bound as the geometry changes)."""
        if self.dt is not None:
            return self.dt
        cell_dt = model.cell_stable_dt(state)
        if scale is not None:
            cell_dt = [dt * np.sqrt(s) for dt, s in zip(cell_dt, scale)]
        critical = min(float(dt.min()) for dt in cell_dt)
        if masses is not None:
            assembled = model.assembled_stable_dt(state, *masses)
            self._assembled = None if assembled is None else (assembled, critical)
        if self._assembled is not None:
            assembled, cells_then = self._assembled
            critical = max(critical, assembled * critical / cells_then)
        # Mass-proportional damping shortens the stable step: dt <= (2/w)(sqrt(1+xi^2) - xi)
        # with xi = c / (2 w) on the highest mode w = 2 / dt_crit (docs/theory.md §6.3).
        xi = self.damping * critical / 4.0
        return self.safety * critical * (math.sqrt(1.0 + xi * xi) - xi)

    # ------------------------------------------------------------------ solve
    def solve(self, model: Model | CompiledModel) -> Result:
        """Integrate from the reference state at rest.

        Returns
        -------
        femcore.results.Result
            Frames every ``output_interval``, energies, ``info`` (step, added mass).

        Raises
        ------
        DivergenceError
            On non-finite values or an energy blow-up, keeping every good frame (the last one
            just before the failure) in ``error.result``.
        """
        compiled = model.compile() if isinstance(model, Model) else model
        started = time.perf_counter()
        state = compiled.initial_state()
        scale = self._density_scale(compiled, state)
        mass, inertia = compiled.lumped_mass(state, scale)
        inv_mass, inv_inertia = inverse_diagonal(mass), inverse_diagonal(inertia)
        added_mass = float(mass.sum() - compiled.mass0.sum())
        duration = self.duration
        self._assembled = None
        dt_nominal = self._step_size(compiled, state, scale, (mass, inertia))
        if not np.isfinite(dt_nominal) or dt_nominal <= 0:
            raise DivergenceError(
                "the stable time step is not a positive number: check the "
                "element stiffness and mass",
                empty_result(compiled, []),
            )
        energy = EnergyAccount(thin=max(1, int(duration / dt_nominal / ENERGY_RECORDS)))
        schedule = FrameSchedule(self.output_interval or duration / 20.0, duration)
        progress = ProgressLine(resolve_progress(self.progress), "central difference")
        frames = [make_frame(compiled, state)]

        def result(steps: int, converged: bool) -> Result:
            return self._result(
                compiled, frames, steps, started, energy, dt_nominal, added_mass, converged
            )

        strain_at_start = compiled.strain_energy(state)
        good = (state, None, None)  # the last state that passed the checks, its reactions
        worst = grown = 0.0  # the largest energy balance error and growth met

        def diverged(message: str, steps: int):
            """The run stops: the frames end with the last state that passed the checks."""
            kept = [f for f in frames if f.time <= good[0].time * (1.0 + 1e-12)]
            if kept[-1].time < good[0].time:
                kept.append(make_frame(compiled, *good))
            frames[:] = kept
            return DivergenceError(
                f"central difference diverged at step {steps}, t = {state.time:.6g} s (dt = "
                f"{dt:.3g} s): {message}; the last frame is the last state that passed the "
                f"checks (t = {good[0].time:.6g} s). Reduce dt or safety, or check the loads "
                "and material laws.",
                result(steps, False),
            )

        dt_prev = 0.0
        dt = dt_nominal
        step = 0
        while state.time < duration * (1.0 - 1e-12):
            if step >= self.max_steps:
                raise DivergenceError(
                    f"central difference stopped after {step} steps at t = {state.time:.6g} s of "
                    f"{duration:.6g} s (max_steps): the step is too small for this duration",
                    result(step, False),
                )
            if step % STABLE_DT_EVERY == 0 and step > 0:
                if compiled.dofs.any_rotation:
                    # Eq. 39: I = m h_m^2 / 4 follows the thickness along the director; a stale
                    # I under a tilting director makes the director modes unstable.
                    _, inertia = compiled.lumped_mass(state, scale)
                    inv_inertia = inverse_diagonal(inertia)
                if self.dt is None:
                    fresh = step % ASSEMBLED_DT_EVERY == 0
                    dt_nominal = self._step_size(
                        compiled, state, scale, (mass, inertia) if fresh else None
                    )
            dt = min(dt_nominal, duration - state.time)
            new, reactions, reaction_moments, work = self._step(
                compiled, state, dt, dt_prev, (mass, inertia, inv_mass, inv_inertia)
            )
            if energy.blows_up(*work):
                raise diverged(
                    f"kinetic energy {work[3]:.3g} against {energy.work_scale:.3g} of external "
                    "work",
                    step,
                )
            energy.accept(*work)
            last = state.time + dt >= duration * (1.0 - 1e-12)
            if (step > 0 and step % BALANCE_EVERY == 0) or last:
                # The state at t(i), whose forces this step used, against the energies.
                balance, growth = energy.check(
                    work, compiled.strain_energy(state) - strain_at_start
                )
                worst = max(worst, balance)
                grown = max(grown, growth)
                moved = dt * float(np.abs(new.velocities).max(initial=0.0))
                if balance > BALANCE_TOLERANCE:
                    raise diverged(
                        f"the energy balance |KE + U + D - W_ext| is off by {balance:.3g} of the "
                        f"largest energy of the run (tolerance {BALANCE_TOLERANCE:g})",
                        step,
                    )
                if growth > GROWTH_LIMIT:
                    raise diverged(
                        f"kinetic and strain energy have grown to {growth:.3g} times the work "
                        f"done on the model (limit {GROWTH_LIMIT:g})",
                        step,
                    )
                if moved > MAX_STEP_MOTION * compiled.element_size:
                    raise diverged(
                        f"a node moved {moved:.3g} mm in one step, more than "
                        f"{MAX_STEP_MOTION:g} of the median element edge",
                        step,
                    )
                if growth <= GOOD_GROWTH:
                    good = (state, reactions, reaction_moments)
            state = compiled.commit(new)
            dt_prev = dt
            step += 1
            energy.record(step, state.time)
            if schedule.due(state.time):
                frames.append(make_frame(compiled, state, reactions, reaction_moments))
            progress(
                f"t = {state.time:.4g}/{duration:.4g} s, step {step}, dt = {dt:.3g} s, "
                f"KE = {energy.kinetic:.4g}, IE = {energy.internal:.4g}"
            )

        progress(f"done: {step} steps", force=True)
        done = result(step, True)
        done.info["energy_balance_error"] = worst
        done.info["energy_growth"] = grown
        return done

    def _step(self, model: CompiledModel, state: State, dt: float, dt_prev: float, lumped):
        """One central-difference step from ``state`` (left unchanged); ``lumped`` = (mass,
        inertia, 1/mass, 1/inertia) per node.

        Returns the new State, the support forces (n, 3) and moments (n, 3) of the step, and
        its energy terms (external work, internal work, damping work, kinetic energy).
        """
        c = self.damping
        mass, inertia, inv_mass, inv_inertia = lumped
        dofs = model.dofs
        t_next = state.time + dt
        dt_bar = 0.5 * (dt_prev + dt)
        velocity, omega = state.velocities, state.angular_velocities

        f_ext, m_ext = model.external_load(state.time / self.duration)
        f_int, m_int = model.internal_force(state)
        v_free = damped_velocity(velocity, f_ext - f_int, inv_mass, dt_bar, c)
        v_new = np.where(model.translation_free, v_free, 0.0)
        if model.has_prescribed:
            target = model.reference_positions + model.prescribed_displacement(
                t_next / self.duration
            )
            v_new = np.where(model.translation_prescribed, (target - state.positions) / dt, v_new)
        # Support force = what the constraint adds to the momentum balance of the node.
        reactions = np.where(
            model.translation_constrained,
            mass[:, None] * (v_new - v_free) * (1.0 + 0.5 * c * dt_bar) / dt_bar,
            0.0,
        )
        work = EnergyAccount.increments(
            (f_ext + reactions, f_int), (velocity, v_new), mass, c, dt_prev, dt
        )
        w_new = None
        reaction_moments = np.zeros_like(reactions)
        if dofs.any_rotation:
            # Only the drilling part is dropped here, so that the update below sees what a
            # fixed alpha / beta has to hold: that difference is the support moment.
            moment = drop_along(m_ext - m_int, state.directors)
            w_free = damped_velocity(omega, moment, inv_inertia, dt_bar, c)
            w_new = model.constrain_angular(w_free, state.directors)
            reaction_moments = (
                inertia[:, None] * (w_new - w_free) * (1.0 + 0.5 * c * dt_bar) / dt_bar
            )
            turning = EnergyAccount.increments(
                (m_ext + reaction_moments, m_int), (omega, w_new), inertia, c, dt_prev, dt
            )
            work = tuple(a + b for a, b in zip(work, turning))
        moved = dofs.move(state, dt * v_new, None if w_new is None else dt * w_new)
        new = replace(
            moved,
            velocities=v_new,
            angular_velocities=omega if w_new is None else w_new,
            time=t_next,
            load_factor=t_next / self.duration,
        )
        return new, reactions, reaction_moments, work

    def _result(self, compiled, frames, steps, started, energy, dt, added_mass, converged):
        result = empty_result(compiled, frames)
        result.steps = steps
        result.wall_time = time.perf_counter() - started
        result.converged = converged
        result.energies = energy.arrays()
        result.info = {
            "solver": "CentralDifference",
            "dt": dt,
            "added_mass": added_mass,
            "added_mass_ratio": added_mass / float(compiled.mass0.sum()),
            "damping": self.damping,
        }
        return result
