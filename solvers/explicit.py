"""Explicit dynamics: the central difference scheme of Bai Eq. 22-23 (THEORY §6.1-6.3).

With a variable step, dt_bar = (dt_prev + dt)/2 and mass-proportional damping C = c M:

    v(i+1/2) = [(1 - c dt_bar/2) v(i-1/2) + dt_bar M^-1 (F_ext - F_int)(i)] / (1 + c dt_bar/2)
    x(i+1)   = x(i) + dt v(i+1/2)

Rotations follow the same update with the rotary inertia and the moment vectors, on a nodal
angular velocity kept perpendicular to the director; the director then turns by the finite
rotation dt * omega (Rodrigues, THEORY §1.3).
"""

from __future__ import annotations

import math
import time

import numpy as np

from femcore.model import CompiledModel, Model
from femcore.rotation import drop_along, rotate_about
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
        self.duration = check_positive_or_none(duration, "duration")
        if self.duration is None:
            raise ValueError("duration must be a positive number of seconds")
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
        # with xi = c / (2 w) on the highest mode w = 2 / dt_crit (THEORY §6.3).
        xi = self.damping * critical / 4.0
        return self.safety * critical * (math.sqrt(1.0 + xi * xi) - xi)

    # ------------------------------------------------------------------ solve
    def solve(self, model: Model | CompiledModel) -> object:
        """Integrate from the reference state at rest; returns a femcore.results.Result.

        Raises DivergenceError (keeping every good frame, the last one just before the
        failure) on non-finite values or an energy blow-up.
        """
        compiled = model.compile() if isinstance(model, Model) else model
        started = time.perf_counter()
        state = compiled.initial_state()
        scale = self._density_scale(compiled, state)
        mass, inertia = compiled.lumped_mass(state, scale)
        added_mass = float(mass.sum() - compiled.mass0.sum())
        rot = compiled.has_rotation
        any_rot = bool(rot.any())
        inv_mass = inverse_diagonal(mass)
        inv_inertia = inverse_diagonal(inertia)

        free = compiled.translation_free
        constrained = compiled.translation_constrained
        prescribed = compiled.translation_prescribed
        has_prescribed = compiled.has_prescribed
        reference = compiled.reference_positions
        c = self.damping
        duration = self.duration
        output_interval = self.output_interval or duration / 20.0

        dt = dt_nominal = self._step_size(compiled, state, scale)
        if not np.isfinite(dt) or dt <= 0:
            raise DivergenceError(
                "the stable time step is not a positive number: check the "
                "element stiffness and mass",
                empty_result(compiled, []),
            )
        thin = max(1, int(duration / dt / ENERGY_RECORDS))
        progress = ProgressLine(resolve_progress(self.progress), "central difference")

        velocity = np.zeros_like(state.positions)
        omega = np.zeros_like(state.positions)
        frames = [make_frame(compiled, state)]
        energy = {k: [0.0] for k in ("time", "kinetic", "internal", "external_work", "damping")}
        kinetic = internal = external = dissipated = 0.0
        work_scale = 0.0  # sum of |external work increments|: the yardstick for a blow-up
        dt_prev = 0.0
        next_output = output_interval
        step = 0
        reactions = np.zeros_like(state.positions)
        reaction_moments = np.zeros_like(state.positions)

        while state.time < duration * (1.0 - 1e-12):
            if step >= self.max_steps:
                raise DivergenceError(
                    f"central difference stopped after {step} steps at t = {state.time:.6g} s of "
                    f"{duration:.6g} s (max_steps): the step is too small for this duration",
                    self._result(
                        compiled, frames, step, started, energy, dt_nominal, added_mass, False
                    ),
                )
            if step % STABLE_DT_EVERY == 0 and step > 0:
                if any_rot:
                    # Eq. 39: I = m h_m^2 / 4 follows the thickness along the director; a stale
                    # I under a tilting director makes the director modes unstable.
                    _, inertia = compiled.lumped_mass(state, scale)
                    inv_inertia = inverse_diagonal(inertia)
                if self.dt is None:
                    dt_nominal = self._step_size(compiled, state, scale)
            dt = min(dt_nominal, duration - state.time)
            t_next = state.time + dt
            tau = state.time / duration
            dt_bar = 0.5 * (dt_prev + dt)

            f_ext, m_ext = compiled.external_load(tau)
            f_int, m_int = compiled.internal_force(state)
            residual = f_ext - f_int
            v_free = ((1.0 - 0.5 * c * dt_bar) * velocity + dt_bar * inv_mass * residual) / (
                1.0 + 0.5 * c * dt_bar
            )
            v_new = np.where(free, v_free, 0.0)
            if has_prescribed:
                target = reference + compiled.prescribed_displacement(t_next / duration)
                v_new = np.where(prescribed, (target - state.positions) / dt, v_new)
            # Support force = what the constraint adds to the momentum balance of the node.
            reactions = np.where(
                constrained,
                mass[:, None] * (v_new - v_free) * (1.0 + 0.5 * c * dt_bar) / dt_bar,
                0.0,
            )

            if any_rot:
                # Only the drilling part is dropped here, so that the update below sees what a
                # fixed alpha / beta has to hold: that difference is the support moment.
                moment = drop_along(m_ext - m_int, state.directors)
                w_free = ((1.0 - 0.5 * c * dt_bar) * omega + dt_bar * inv_inertia * moment) / (
                    1.0 + 0.5 * c * dt_bar
                )
                w_new = compiled.constrain_angular(w_free, state.directors)
                reaction_moments = (
                    inertia[:, None] * (w_new - w_free) * (1.0 + 0.5 * c * dt_bar) / dt_bar
                )

            # Work over [t(i-1/2), t(i+1/2)] with the forces at t(i) (midpoint rule).
            dx = 0.5 * (dt_prev * velocity + dt * v_new)
            v_mid = 0.5 * (velocity + v_new)
            d_ext = float(np.sum((f_ext + reactions) * dx))
            d_int = float(np.sum(f_int * dx))
            d_damp = float(np.sum(c * mass[:, None] * v_mid * dx))
            kinetic_new = 0.5 * float(np.sum(mass[:, None] * v_new * v_new))
            if any_rot:
                dpsi = 0.5 * (dt_prev * omega + dt * w_new)
                d_ext += float(np.sum((m_ext + reaction_moments) * dpsi))
                d_int += float(np.sum(m_int * dpsi))
                d_damp += float(np.sum(c * inertia[:, None] * 0.5 * (omega + w_new) * dpsi))
                kinetic_new += 0.5 * float(np.sum(inertia[:, None] * w_new * w_new))
            work_scale += abs(d_ext)

            # Energy conservation bounds the kinetic energy by the work done on the model; ten
            # times that work means the integration is unstable.
            if (
                not np.isfinite(kinetic_new)
                or kinetic_new > 10.0 * (work_scale + abs(internal)) + 1e-300
            ):
                state.velocities = velocity
                frames.append(make_frame(compiled, state, reactions, reaction_moments))
                raise DivergenceError(
                    f"central difference diverged at step {step}, t = {state.time:.6g} s "
                    f"(dt = {dt:.3g} s): kinetic energy {kinetic_new:.3g} against "
                    f"{work_scale:.3g} of external work; the last good state is the last frame. "
                    "Reduce dt or safety, or check the loads and material laws.",
                    self._result(
                        compiled, frames, step, started, energy, dt_nominal, added_mass, False
                    ),
                )

            kinetic = kinetic_new
            external += d_ext
            internal += d_int
            dissipated += d_damp
            state.positions = state.positions + dt * v_new
            state.velocities = v_new
            velocity = v_new
            if any_rot:
                state.directors = np.where(
                    rot[:, None], rotate_about(state.directors, dt * w_new), state.directors
                )
                omega = w_new
                state.angular_velocities = w_new
            state.time = t_next
            state.load_factor = t_next / duration
            dt_prev = dt
            step += 1

            if step % thin == 0:
                for key, value in zip(
                    energy, (state.time, kinetic, internal, external, dissipated)
                ):
                    energy[key].append(value)
            if state.time >= next_output * (1.0 - 1e-9) or state.time >= duration * (1.0 - 1e-12):
                frames.append(make_frame(compiled, state, reactions, reaction_moments))
                while next_output <= state.time * (1.0 + 1e-9):
                    next_output += output_interval
            progress(
                f"t = {state.time:.4g}/{duration:.4g} s, step {step}, dt = {dt:.3g} s, "
                f"KE = {kinetic:.4g}, IE = {internal:.4g}"
            )

        progress(f"done: {step} steps", force=True)
        return self._result(compiled, frames, step, started, energy, dt_nominal, added_mass, True)

    def _result(self, compiled, frames, steps, started, energy, dt, added_mass, converged):
        result = empty_result(compiled, frames)
        result.steps = steps
        result.wall_time = time.perf_counter() - started
        result.converged = converged
        result.energies = {k: np.asarray(v) for k, v in energy.items()}
        result.info = {
            "solver": "CentralDifference",
            "dt": dt,
            "added_mass": added_mass,
            "added_mass_ratio": added_mass / float(compiled.mass0.sum()),
            "damping": self.damping,
        }
        return result
