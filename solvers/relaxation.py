"""Dynamic relaxation: the static equilibrium as the damped limit of a pseudo-dynamic motion
(docs/theory.md §6.4).

Loads and prescribed displacements are applied in ``increments`` equal load-factor steps; each
increment is relaxed to equilibrium before the next one and gives one frame.

- Kinetic damping (Cundall 1976; Barnes 1999): undamped central difference; when the kinetic
  energy passes a peak, the configuration goes back to where the peak was (half a step back),
  all velocities are zeroed and the motion restarts from rest.
- Adaptive viscous damping (Underwood 1983; Papadrakakis 1981): mass-proportional damping with
  c = 2 sqrt(u.K u / u.M u), the lowest-mode estimate from a diagonal stiffness estimate.

Converged when, on the free DOFs, ||r|| <= tol F_ref and max|r_j| <= 10 tol F_ref / sqrt(n),
with F_ref = max(||F_ext||, ||F_int||) (the internal forces include the reactions, so a
displacement-driven problem has a non-zero reference). Moments are checked the same way
against their own reference.
"""

from __future__ import annotations

import math
import time
from dataclasses import replace

import numpy as np
from numpy.typing import ArrayLike

from femcore.model import CompiledModel, Model
from femcore.results import Result
from femcore.rotation import drop_along
from femcore.state import State
from solvers.common import (
    ConvergenceError,
    DivergenceError,
    ProgressLine,
    check_held,
    check_integer,
    check_tolerance,
    empty_result,
    inverse_diagonal,
    make_frame,
    resolve_progress,
)
from solvers.dynamics import damped_velocity

__all__ = ["DAMPING_KINDS", "DynamicRelaxation"]

DAMPING_KINDS = ("kinetic", "viscous")


class DynamicRelaxation:
    """Quasi-static solver by dynamic relaxation.

    increments : number of equal load-factor steps.
    tol : relative residual tolerance (see the module docstring).
    max_iterations : iterations allowed per increment before a ConvergenceError.
    damping : "kinetic" (default) or "viscous" (adaptive).
    safety : factor on the stable step of the lumped-mass model.
    progress : print status lines (None: only on an interactive terminal).
    """

    def __init__(
        self,
        increments: int = 1,
        tol: float = 1e-4,
        max_iterations: int = 200_000,
        damping: str = "kinetic",
        safety: float = 0.9,
        progress: bool | None = None,
    ):
        self.increments = check_integer(increments, "increments")
        self.tol = check_tolerance(tol)
        self.max_iterations = check_integer(max_iterations, "max_iterations")
        if damping not in DAMPING_KINDS:
            raise ValueError(f"unknown damping {damping!r}: expected one of {DAMPING_KINDS}")
        self.damping = damping
        if not (0.0 < float(safety) <= 1.0):
            raise ValueError(f"safety must be in (0, 1], got {safety!r}")
        self.safety = float(safety)
        self.progress = progress

    def solve(
        self,
        model: Model | CompiledModel,
        start: tuple[ArrayLike, ArrayLike, float] | None = None,
    ) -> Result:
        """Relax every increment to equilibrium.

        Parameters
        ----------
        model : Model or CompiledModel
        start : (positions (n, 3), directors (n, 3), load factor) or None
            An equilibrium already found (e.g. the last state a Static run reached before a
            limit point): the relaxation then continues from it, the increments splitting
            the remaining load.

        Returns
        -------
        femcore.results.Result
            The reference state and one frame per increment (``time`` = load factor).

        Raises
        ------
        ValueError
            When the loads push the model along a rigid motion that no support holds (no
            equilibrium exists; the message names the motion).
        ConvergenceError
            When an increment does not converge in ``max_iterations`` (the converged
            increments in ``error.result``).
        DivergenceError
            On non-finite values.
        """
        compiled = model.compile() if isinstance(model, Model) else model
        check_held(compiled)
        started = time.perf_counter()
        state = compiled.initial_state()
        frames = [make_frame(compiled, state)]
        first = 0.0
        if start is not None:
            positions, directors, first = start
            first = float(first)
            if not 0.0 <= first < 1.0:
                raise ValueError(f"start load factor must be in [0, 1), got {first!r}")
            positions = np.array(positions, dtype=float)
            directors = np.array(directors, dtype=float)
            if positions.shape != (compiled.n_nodes, 3) or directors.shape != (
                compiled.n_nodes,
                3,
            ):
                raise ValueError(
                    f"start positions and directors must be ({compiled.n_nodes}, 3) arrays"
                )
            state = replace(
                state, positions=positions, directors=directors, load_factor=first, time=first
            )
            frames.append(make_frame(compiled, state))
        progress = ProgressLine(resolve_progress(self.progress), "dynamic relaxation")
        iterations: list[int] = []
        residuals: list[float] = []
        for increment in range(1, self.increments + 1):
            load_factor = first + (1.0 - first) * increment / self.increments
            state = replace(state, load_factor=load_factor, time=load_factor)
            try:
                state, count, ratio, reactions, reaction_moments = self._relax(
                    compiled, state, load_factor, progress, increment
                )
            except (ConvergenceError, DivergenceError) as error:
                error.result = self._result(compiled, frames, iterations, residuals, started, False)
                raise
            iterations.append(count)
            residuals.append(ratio)
            frames.append(make_frame(compiled, state, reactions, reaction_moments))
            progress(
                f"increment {increment}/{self.increments} converged in {count} iterations",
                force=True,
            )
        return self._result(compiled, frames, iterations, residuals, started, True)

    def _result(self, compiled, frames, iterations, residuals, started, converged):
        result = empty_result(compiled, frames)
        result.steps = int(sum(iterations))
        result.wall_time = time.perf_counter() - started
        result.converged = converged
        result.info = {
            "solver": "DynamicRelaxation",
            "damping": self.damping,
            "iterations_per_increment": list(iterations),
            "residual_ratio_per_increment": list(residuals),
            "tol": self.tol,
        }
        return result

    # ------------------------------------------------------------------ one increment
    def _relax(self, model: CompiledModel, state: State, load_factor, progress, increment):
        """Relax from ``state`` (left unchanged) to equilibrium at ``load_factor``.

        Returns (the state at rest in equilibrium, iterations, residual ratio, reactions (n,3),
        reaction moments (n,3)).
        """
        dofs = model.dofs
        free = model.translation_free
        rot = model.has_rotation
        any_rot = bool(rot.any())
        f_ext, m_ext = model.external_load(load_factor, quasi_static=True)
        if model.has_prescribed:
            target = model.reference_positions + model.prescribed_displacement(
                load_factor, quasi_static=True
            )
            state = replace(
                state, positions=np.where(model.translation_prescribed, target, state.positions)
            )

        mass, inertia = model.lumped_mass(state)
        inv_mass = inverse_diagonal(mass)
        inv_inertia = inverse_diagonal(inertia)
        dt = self.safety * model.stable_dt(state)
        balance = _Balance(model, f_ext, m_ext, self.tol)

        velocity = np.zeros_like(state.positions)
        omega = np.zeros_like(state.positions)
        kinetic_old = 0.0
        restart = True  # the first step from rest is a half step
        start_positions = state.positions.copy()
        previous = None  # the last iteration's (displacement, residual, rate, mass) per kind
        rotation_since_start = np.zeros_like(state.positions)
        c = 0.0
        ratio = math.inf

        for iteration in range(1, self.max_iterations + 1):
            f_int, m_int = model.internal_force(state)
            residual = np.where(free, f_ext - f_int, 0.0)
            # (zero and unused without rotational DOFs)
            moment = (
                model.constrain_angular(m_ext - m_int, state.directors)
                if any_rot
                else np.zeros_like(f_int)
            )

            ratio, ok = balance.judge(f_int, m_int, residual, moment)
            if not np.isfinite(ratio):
                raise DivergenceError(
                    f"dynamic relaxation produced non-finite forces in increment {increment} "
                    f"(load factor {load_factor:.4g}) at iteration {iteration}",
                    None,
                )
            if ok:
                reactions, reaction_moments = balance.reactions(state, f_int, m_int, moment)
                at_rest = replace(
                    state,
                    velocities=np.zeros_like(velocity),
                    angular_velocities=np.zeros_like(omega),
                )
                return model.commit(at_rest), iteration, ratio, reactions, reaction_moments

            step = 0.5 * dt if restart else dt
            if self.damping == "viscous":
                current = [(state.positions - start_positions, residual, velocity, mass)]
                if any_rot:
                    current.append((rotation_since_start, moment, omega, inertia))
                c = self._viscous_c(current, previous, dt)
                previous = current
            v_new = np.where(free, damped_velocity(velocity, residual, inv_mass, step, c), 0.0)
            kinetic = 0.5 * float(np.sum(mass[:, None] * v_new * v_new))
            if any_rot:
                w_new = model.constrain_angular(
                    damped_velocity(omega, moment, inv_inertia, step, c), state.directors
                )
                kinetic += 0.5 * float(np.sum(inertia[:, None] * w_new * w_new))

            if self.damping == "kinetic" and not restart and kinetic < kinetic_old:
                # The kinetic energy peaked half a step ago: go back there and restart from
                # rest (x* = x(i) - dt/2 v(i-1/2), docs/theory.md §6.4a).
                state = dofs.move(state, -0.5 * dt * velocity, -0.5 * dt * omega)
                velocity = np.zeros_like(velocity)
                omega = np.zeros_like(omega)
                kinetic_old = 0.0
                restart = True
                # The rotary inertia follows h_m (Eq. 39) and the step follows the geometry.
                mass, inertia = model.lumped_mass(state)
                inv_inertia = inverse_diagonal(inertia)
                dt = self.safety * model.stable_dt(state)
                progress(
                    f"increment {increment}: iteration {iteration}, residual ratio "
                    f"{ratio:.3g} (tol {self.tol:g})"
                )
                continue

            state = dofs.move(state, dt * v_new, dt * w_new if any_rot else None)
            if any_rot:
                rotation_since_start += dt * w_new
                omega = w_new
            velocity = v_new
            kinetic_old = kinetic
            restart = False

        raise ConvergenceError(
            f"dynamic relaxation did not converge in increment {increment}/{self.increments} "
            f"(load factor {load_factor:.4g}) within {self.max_iterations} iterations: residual "
            f"ratio {ratio:.3g}, tolerance {self.tol:g}. Raise max_iterations, use more "
            "increments, or try the other damping ("
            f"{'kinetic' if self.damping == 'viscous' else 'viscous'}).",
            None,
        )

    @staticmethod
    def _viscous_c(current, previous, dt) -> float:
        """Adaptive damping coefficient c = 2 sqrt(u.K u / u.M u) (Underwood 1983), over the
        translations and the rotations alike, with the local diagonal stiffness estimate
        K_jj = -(r_j(i) - r_j(i-1)) / (dt v_j(i-1/2)); u is the motion since the increment
        began. ``current`` / ``previous``: lists of (u, r, v, m) per kind of DOF."""
        if previous is None:
            return 0.0
        numerator = denominator = 0.0
        for (u, r, v, m), (_, r_old, _, _) in zip(current, previous):
            moving = np.abs(v) > 1e-300
            stiffness = np.zeros_like(v)
            stiffness[moving] = -(r[moving] - r_old[moving]) / (dt * v[moving])
            numerator += float(np.sum(stiffness * u * u))
            denominator += float(np.sum(m[:, None] * u * u))
        if numerator <= 0.0 or denominator <= 0.0:
            return 0.0
        return min(2.0 * math.sqrt(numerator / denominator), 1.9 / dt)


class _Balance:
    """Convergence and support reactions of one relaxed increment.

    Converged when, on the free DOFs, ||r|| <= tol F_ref and max|r_j| <= 10 tol F_ref / sqrt(n)
    with F_ref = max(||F_ext||, ||F_int||), and the constrained moments ||m|| <= tol M_ref with
    M_ref = max(||M_ext||, ||M_int||, F_ref L_e): director moments can all be tiny (fibre slip
    leaves them unloaded), and are then judged against the force scale times one element.
    """

    def __init__(self, model: CompiledModel, f_ext: np.ndarray, m_ext: np.ndarray, tol: float):
        self.model, self.f_ext, self.m_ext, self.tol = model, f_ext, m_ext, tol
        rot = model.has_rotation
        self.any_rotation = bool(rot.any())
        n_free = int(model.translation_free.sum()) + 2 * int(
            (rot[:, None] & ~model.rotation_fixed).sum()
        )
        self.sqrt_n = math.sqrt(max(n_free, 1))
        self.f_ext_norm = float(np.linalg.norm(f_ext))
        self.m_ext_norm = float(np.linalg.norm(m_ext))

    def judge(self, f_int, m_int, residual, moment) -> tuple[float, bool]:
        """(residual ratio, converged) from the internal forces and the free residuals."""
        force_ref = max(self.f_ext_norm, float(np.linalg.norm(f_int)))
        r_norm = float(np.linalg.norm(residual))
        ratio = r_norm / force_ref if force_ref > 0 else 0.0
        ok = ratio <= self.tol and float(np.abs(residual).max(initial=0.0)) <= (
            10.0 * self.tol * force_ref / self.sqrt_n
        )
        if self.any_rotation:
            moment_ref = max(
                self.m_ext_norm, float(np.linalg.norm(m_int)), force_ref * self.model.element_size
            )
            m_ratio = float(np.linalg.norm(moment)) / moment_ref if moment_ref > 0 else 0.0
            ok = ok and m_ratio <= self.tol
            ratio = max(ratio, m_ratio)
        return ratio, ok

    def reactions(self, state: State, f_int, m_int, moment) -> tuple[np.ndarray, np.ndarray]:
        """Support forces (n, 3) on the constrained translations and support moments (n, 3):
        what the constraints removed from the (drilling-free) out-of-balance moments."""
        model = self.model
        reactions = np.where(model.translation_constrained, f_int - self.f_ext, 0.0)
        reaction_moments = np.zeros_like(reactions)
        if self.any_rotation:
            full = drop_along(self.m_ext - m_int, state.directors)
            reaction_moments = np.where(model.has_rotation[:, None], moment - full, 0.0)
        return reactions, reaction_moments
