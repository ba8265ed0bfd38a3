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

    # ------------------------------------------------------------------ time step
    def _density_scale(self, model: CompiledModel, state: State):
        if self.mass_scaling_dt is None:
            return None
        target = self.mass_scaling_dt / self.safety
        return [np.maximum(1.0, (target / dt) ** 2) for dt in model.cell_stable_dt(state)]

    def _step_size(self, model: CompiledModel, state: State, scale) -> float:
        if self.dt is not None:
            return self.dt
        cell_dt = model.cell_stable_dt(state)
        if scale is not None:
            cell_dt = [dt * np.sqrt(s) for dt, s in zip(cell_dt, scale)]
        critical = min(float(dt.min()) for dt in cell_dt)
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
        dt_nominal = self._step_size(compiled, state, scale)
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

        dt_prev = 0.0
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
                    dt_nominal = self._step_size(compiled, state, scale)
            dt = min(dt_nominal, duration - state.time)
            new, reactions, reaction_moments, work = self._step(
                compiled, state, dt, dt_prev, (mass, inertia, inv_mass, inv_inertia)
            )
            if energy.blows_up(*work):
                frames.append(make_frame(compiled, state, reactions, reaction_moments))
                raise DivergenceError(
                    f"central difference diverged at step {step}, t = {state.time:.6g} s "
                    f"(dt = {dt:.3g} s): kinetic energy {work[3]:.3g} against "
                    f"{energy.work_scale:.3g} of external work; the last good state is the last "
                    "frame. Reduce dt or safety, or check the loads and material laws.",
                    result(step, False),
                )
            energy.accept(*work)
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
        return result(step, True)

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
            work = (
                work[0] + turning[0],
                work[1] + turning[1],
                work[2] + turning[2],
                work[3] + turning[3],
            )
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
