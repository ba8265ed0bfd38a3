"""Dynamic relaxation: the static equilibrium as the damped limit of a pseudo-dynamic motion
(docs/theory.md §6.4; an accepted state judged stable, §6.4e).

Loads and prescribed displacements are applied in ``increments`` equal load-factor steps; each
increment is relaxed to equilibrium before the next one and gives one frame.

- Masses (Underwood 1983; solvers.fictitious_masses): by default fictitious masses from a
  Gershgorin bound of the tangent stiffness, m_i = (dt^2/4) sum_j |K_ij| / safety^2 with a
  nominal dt = 1, so that every DOF has the same stability limit; shell nodes take them along
  their own tangent and normal axes, and they are re-estimated as the configuration changes.
  ``masses="lumped"``: the physical lumped masses with the stable step.
- Kinetic damping (Cundall 1976; Barnes 1999): undamped central difference (its angular and
  configuration updates are those of solvers.step); when the kinetic energy passes a peak, the
  configuration goes back to where the peak was (half a step back), all velocities are zeroed
  and the motion restarts from rest.
- Adaptive viscous damping (Underwood 1983; Papadrakakis 1981): mass-proportional damping with
  c = 2 sqrt(u.K u / u.M u), the lowest-mode estimate from a diagonal stiffness estimate and
  the masses in use.

Converged when, on the free DOFs, ||r|| <= tol F_ref and max|r_j| <= 10 tol F_ref / sqrt(n),
with F_ref = max(||F_ext||, ||F_int||, max(||M_ext||, ||M_int||) / L_e) (the internal forces
include the reactions, so a displacement-driven problem has a non-zero reference; the moments
over one element L_e give one under end moments alone). Moments are checked the same way
against their own reference (solvers.convergence.Equilibrium, the test Static uses too). A
residual that does not fall while the model travels farther than its size stops the run as a
mechanism.
"""

from __future__ import annotations

import math
import os
import time
import warnings
from dataclasses import replace
from functools import partial

import numpy as np
from numpy.typing import ArrayLike

from femcore.fingerprint import fingerprint
from femcore.model import CompiledModel, Model
from femcore.results import Frame, Result
from femcore.rotation import drop_along
from femcore.state import State
from solvers.acceptance import invalid_state
from solvers.augmentation import warn_penalty_only
from solvers.blas_threads import one_blas_thread
from solvers.common import (
    ConvergenceError,
    DivergenceError,
    ProgressLine,
    SolverError,
    check_fraction,
    check_held,
    check_integer,
    check_progress,
    check_tolerance,
    compiled_model,
    empty_result,
    inverse_diagonal,
    make_frame,
    resolve_progress,
)
from solvers.convergence import Equilibrium
from solvers.dynamics import damped_velocity
from solvers.factored_masses import FactoredMasses, factored_fallback
from solvers.fictitious_masses import GershgorinMasses, PhysicalMasses, RelaxationMasses
from solvers.force_floor import round_off_force, unloaded_floor
from solvers.interrupts import STOP, Interrupted, check_outputs, keeps_writes
from solvers.output import checkpoint_path, resume, save_checkpoint
from solvers.progress import relaxed_share
from solvers.relaxation_cuts import InvalidState, more_increments, relax_in_halves
from solvers.relaxation_stability import StabilityJudge, relaxed_stable
from solvers.relaxation_watch import PLATEAU_FACTOR, STALL_RATIO, Plateau, stall_message
from solvers.step import advance, angular_rates
from solvers.tool_penetration import record_tool_penetration

__all__ = ["DAMPING_KINDS", "MASS_KINDS", "PLATEAU_FACTOR", "DynamicRelaxation"]

DAMPING_KINDS = ("kinetic", "viscous")
MASS_KINDS = ("gershgorin", "lumped", "factored")


#: Iterations between re-estimates of the fictitious masses (``refresh``'s default).
REFRESH = 100


class DynamicRelaxation:
    """Quasi-static solver by dynamic relaxation.

    Parameters
    ----------
    increments : int
        Number of equal load-factor steps.
    tol : float
        Relative residual tolerance in (0, 1) (see the module docstring).
    max_iterations : int
        Iterations allowed per increment before a ConvergenceError.
    damping : "kinetic" (default) or "viscous"
        Kinetic damping (reset at each kinetic-energy peak) or adaptive viscous damping
        c = 2 sqrt(u.K u / u.M u) with the masses in use.
    masses : "gershgorin" (default), "factored" or "lumped"
        "gershgorin": fictitious masses from a Gershgorin bound of the tangent stiffness K of
        the free DOFs, so that every DOF has the same stability limit at the nominal step
        dt = 1 (Underwood 1983): m_i = sum_j |K_ij| / (4 safety^2), N/mm x s^2 for the
        translations (per node along two tangents and the normal of the mid-surface at shell
        nodes, one value for x, y, z elsewhere) and N mm x s^2 for the rotations (one inertia
        per node, the larger of its alpha and beta rows). K comes from the blocks' own
        tangents, or coloured finite differences for a block without one. The masses are
        re-estimated at each increment start, at a kinetic-energy reset once ``refresh``
        iterations have passed (every ``refresh`` iterations with viscous damping), when a
        surface normal has turned by 0.03 rad or a node came to a contact (its clearance;
        docs/theory.md §6.4a), after a blow-up (from the last state at rest, doubled if
        that state was already recovered once). "factored": the translations' masses the
        factorised stiffness itself, bounded as the Gershgorin masses (solvers.factored_masses;
        what a stalled "gershgorin" increment goes on with). "lumped": the physical
        lumped masses and rotary inertia with ``safety`` x the stable step of the model; the
        iterations then grow like omega_max / omega_min of the physical model.
    safety : float in (0, 1]
        Fraction of the stability limit: of the stable step ("lumped"), or of the Gershgorin
        frequency bound 2/dt ("gershgorin").
    refresh : int or None
        Iterations between re-estimates of the fictitious masses ("gershgorin" only: with
        "lumped" masses there is nothing to re-estimate, and giving it is refused); None:
        REFRESH = 100.
    stall_iterations : int or None
        Iterations the residual ratio may stay above 0.5 in one increment, while the model
        moves farther than its own size, before the run stops as a mechanism (ConvergenceError
        naming the rigid motions the supports do not hold); None: max(10 000,
        max_iterations // 10).
    plateau_iterations : int or None
        The progress watch: every this many iterations of an increment, its smallest
        residual ratio must have fallen to PLATEAU_FACTOR (0.9) of what it was at the last
        check (at the first, of the first ratio), or the run stops as stalled
        (ConvergenceError; the converged increments kept), except that a "gershgorin"
        increment goes on once with the "factored" masses, from rest where it stalled
        (``info["factored_after_stall"]`` counts them); None: no such watch. Default
        20 000: a converging relaxation gains far more (a ratio of 1e-4 in 100 000 iterations
        is a factor 6 per 20 000), but may hold its best ratio for a while (a 160-link chain
        relaxed from a box shape swings down for 10 000 iterations before improving on the
        ratio it met first).
    progress : bool or None
        Show a progress bar on stderr (None: unless under pytest or with
        FIBRESHELL_PROGRESS=0, solvers.progress.resolve_progress). Its share is the
        increments done plus, in the current one, log(r1 / r) / log(r1 / tol) of the
        residual ratio r from its first value r1 to the tolerance.
    """

    def __init__(
        self,
        increments: int = 1,
        tol: float = 1e-4,
        max_iterations: int = 200_000,
        damping: str = "kinetic",
        masses: str = "gershgorin",
        safety: float = 0.9,
        refresh: int | None = None,
        stall_iterations: int | None = None,
        progress: bool | None = None,
        plateau_iterations: int | None = 20_000,
    ):
        self.increments = check_integer(increments, "increments")
        self.tol = check_tolerance(tol)
        self.max_iterations = check_integer(max_iterations, "max_iterations")
        if damping not in DAMPING_KINDS:
            raise ValueError(f"unknown damping {damping!r}: expected one of {DAMPING_KINDS}")
        self.damping = damping
        if masses not in MASS_KINDS:
            raise ValueError(f"unknown masses {masses!r}: expected one of {MASS_KINDS}")
        self.masses = masses
        self.safety = check_fraction(safety, "safety")
        if refresh is not None and masses == "lumped":
            raise ValueError(
                f"refresh = {refresh!r} re-estimates the fictitious masses, and masses = "
                '"lumped" has none (the physical masses do not change): leave refresh out, '
                'or use masses = "gershgorin"'
            )
        self.refresh = check_integer(REFRESH if refresh is None else refresh, "refresh")
        if stall_iterations is None:
            stall_iterations = max(10_000, self.max_iterations // 10)
        self.stall_iterations = check_integer(stall_iterations, "stall_iterations")
        self.plateau_iterations = (
            None
            if plateau_iterations is None
            else check_integer(plateau_iterations, "plateau_iterations")
        )
        self.progress = check_progress(progress)

    @keeps_writes
    @one_blas_thread
    def solve(
        self,
        model: Model | CompiledModel,
        start: tuple[ArrayLike, ArrayLike, float] | None = None,
        checkpoint: str | os.PathLike[str] | None = None,
    ) -> Result:
        """Relax every increment to equilibrium.

        Parameters
        ----------
        model : Model or CompiledModel
        start : (positions (n, 3), directors (n, 3), load factor) or None
            An equilibrium already found (e.g. the last state a Static run reached before a
            limit point): the relaxation then continues from it, the increments splitting
            the remaining load.
        checkpoint : path, optional
            A file where the run is saved, atomically, after each converged increment (the
            state, its frames, iterations and residuals). If it exists, the run resumes after
            the last saved increment and ends in the same state, to the last bit, as a run
            never interrupted; the increment a kill interrupted is relaxed again.

        Returns
        -------
        femcore.results.Result
            The reference state and one frame per increment (``time`` = load factor);
            ``info`` holds the iterations and residual ratio per increment, the number of
            mass estimates and of blow-up recoveries.

        Raises
        ------
        ValueError
            When ``model`` is not a Model, or the loads have a net force along a rigid
            translation that no support holds (no equilibrium exists at any shape; the message
            names it; loaded free rotations are let through: the damped motion swings a model
            hanging from a pin down to its equilibrium, solvers.common.check_held), or
            a model held by frictionless contact leaves a rigid motion free (a slide along
            the tool; the message names it).
        ConvergenceError
            When an increment does not converge in ``max_iterations``, stalls (its smallest
            residual ratio not falling by PLATEAU_FACTOR in ``plateau_iterations``), or its
            residual ratio
            stays above 0.5 for ``stall_iterations`` while the model travels farther than its
            size (a mechanism: the message names the rigid
            motions the supports leave free, if any); the converged increments in
            ``error.result``.
        DivergenceError
            On non-finite values, or when doubling the fictitious masses repeatedly does not
            stop a blow-up.
        solvers.interrupts.Interrupted
            On SIGINT or SIGTERM inside ``solvers.interruptible()``: the iteration in progress
            ends the run, the converged increments in ``error.result``; the checkpoint (saved
            after each converged increment) resumes it, the interrupted increment relaxed
            again.
        femcore.writable.OutputError
            A checkpoint folder that cannot be written, or a checkpoint write that failed (the
            message names the file and what was kept).
        """
        compiled = compiled_model(model, "DynamicRelaxation")
        check_held(compiled, swings=True)
        saved_at = checkpoint_path(checkpoint)
        check_outputs(compiled.mesh, None, saved_at)
        started = time.perf_counter()
        state = compiled.initial_state()
        warn_penalty_only(compiled, state, "DynamicRelaxation")
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
        # The element tangents at the start, made once: the Gershgorin masses' blocks and the
        # force reference's floor, the rounding of the internal forces (solvers.force_floor:
        # a prescribed rigid motion has no other reference).
        own = compiled.own_tangents(compiled.initial_state())
        rounding = round_off_force(compiled, [part for parts in own.values() for part in parts])
        masses: RelaxationMasses = (
            GershgorinMasses(compiled, self.safety, own)
            if self.masses == "gershgorin"
            else FactoredMasses(GershgorinMasses(compiled, self.safety, own))
            if self.masses == "factored"
            else PhysicalMasses(compiled, self.safety)
        )
        judge = StabilityJudge(compiled, own)  # an accepted state's stability (§6.4e)
        iterations: list[int] = []
        residuals: list[float] = []
        done = cuts = 0  # cuts: halvings of increments (relaxation_cuts), in the checkpoint
        earlier = 0.0  # s, the wall time of the increments before a resume
        settings = {
            "solver": "DynamicRelaxation",
            "increments": self.increments,
            "tol": self.tol,
            "masses": self.masses,
            "damping": self.damping,
            "safety": self.safety,
            "refresh": self.refresh,
            "start": None if start is None else (state.positions, state.directors, first),
        }
        signature = fingerprint(compiled, settings) if saved_at is not None else None
        payload = resume(saved_at, signature)
        if payload is not None:
            state, frames, done = payload["state"], payload["frames"], payload["increment"]
            iterations, residuals = payload["iterations"], payload["residuals"]
            masses.estimates, masses.recoveries = payload["estimates"], payload["recoveries"]
            masses.switches = payload.get("switches", 0)  # (absent from older checkpoints)
            cuts = payload.get("cuts", 0)  # (absent from older checkpoints)
            # the wall time counts the increments before the stop too
            earlier = payload.get("wall_time", 0.0)  # (absent from older checkpoints)
            started -= earlier
        with ProgressLine(resolve_progress(self.progress), "dynamic relaxation") as progress:
            try:
                result = self._increments(
                    compiled, state, frames, first, done, iterations, residuals, masses,
                    progress, started, saved_at, signature, rounding, cuts, judge,
                )  # fmt: skip
            except SolverError as error:
                if error.result is not None:
                    error.result.info["wall_time_before_resume"] = earlier
                    judge.record(error.result.info)
                raise
        result.info["wall_time_before_resume"] = earlier
        judge.record(result.info)
        return result

    def _increments(
        self,
        compiled: CompiledModel,
        state: State,
        frames: list,
        first: float,
        done: int,
        iterations: list[int],
        residuals: list[float],
        masses: RelaxationMasses,
        progress: ProgressLine,
        started: float,
        saved_at,
        signature,
        rounding: float,
        cuts: int,
        judge: StabilityJudge,
    ) -> Result:
        """Relax the increments after the ``done`` ones of ``solve``, saving each; the force
        reference never below ``rounding`` (N, solvers.force_floor); ``cuts`` the halvings of
        the ``done`` ones (relaxation_cuts)."""
        ramps = bool(more_increments(compiled))  # (halving a step load changes nothing)
        for increment in range(done + 1, self.increments + 1):
            load_factor = first + (1.0 - first) * increment / self.increments
            try:
                # A blow-up is detected and recovered from (or reported) by the relaxation
                # itself; numpy's overflow warnings on the way would only be noise.
                with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
                    unloaded = _reference_floor(compiled, frames[-1])
                    floor = max(rounding, unloaded)

                    def relax(at, level, increment=increment, floor=floor, unloaded=unloaded):
                        once = partial(
                            self._relax, compiled, load_factor=level, masses=masses,
                            progress=progress, increment=increment, floor=floor, unloaded=unloaded,
                        )  # fmt: skip
                        return relaxed_stable(judge, once, at, level, increment)  # §6.4e

                    (state, count, ratio, reactions, reaction_moments), cut = relax_in_halves(
                        relax, state, frames[-1].load_factor, load_factor, increment, ramps
                    )
                    cuts += cut
            except (ConvergenceError, DivergenceError, Interrupted) as error:
                if isinstance(error, Interrupted):
                    error.checkpoint = saved_at if increment > 1 else None  # saved after each
                    error.args = (_interrupted(error, increment, self.increments, saved_at),)
                error.result = self._result(
                    compiled, frames, iterations, residuals, masses, started, False,
                    cuts + error.cuts,
                )  # fmt: skip
                # the unfinished increment's iterations count too: a stop at iteration 3910 of
                # the first increment read "after 0 steps", one by max_iterations left them out
                error.result.steps += error.steps
                raise
            iterations.append(count)
            residuals.append(ratio)
            frames.append(make_frame(compiled, state, reactions, reaction_moments))
            if saved_at is not None:
                save_checkpoint(
                    saved_at,
                    {
                        "signature": signature,
                        "state": state,
                        "frames": frames,
                        "increment": increment,
                        "iterations": iterations,
                        "residuals": residuals,
                        "estimates": masses.estimates,
                        "recoveries": masses.recoveries,
                        "switches": masses.switches,
                        "cuts": cuts,
                        "wall_time": time.perf_counter() - started,
                    },
                )
            progress(
                f"increment {increment}/{self.increments} converged in {count} iterations",
                fraction=increment / self.increments,
            )
        return self._result(compiled, frames, iterations, residuals, masses, started, True, cuts)

    def _result(self, compiled, frames, iterations, residuals, masses, started, converged, cuts):
        result = empty_result(compiled, frames)
        result.steps = int(sum(iterations))
        result.wall_time = time.perf_counter() - started
        result.converged = converged
        result.info = {
            "solver": "DynamicRelaxation",
            "damping": self.damping,
            "masses": self.masses,
            "iterations_per_increment": list(iterations),
            "residual_ratio_per_increment": list(residuals),
            "mass_estimates": masses.estimates,
            "recoveries": masses.recoveries,
            "factored_after_stall": masses.switches,
            "cuts": cuts,
            "tol": self.tol,
        }
        record_tool_penetration(compiled, result, "DynamicRelaxation", converged)
        return result

    # ------------------------------------------------------------------ one increment
    def _relax(
        self,
        model: CompiledModel,
        state: State,
        load_factor,
        masses: RelaxationMasses,
        progress,
        increment,
        floor: float = 0.0,
        unloaded: float = 0.0,
    ):
        """Relax from ``state`` (left unchanged) to equilibrium at ``load_factor``; ``floor``:
        the least force reference (the rounding of the internal forces and
        ``_reference_floor``), ``unloaded`` the latter (loads below it have been taken off).

        Returns (the state at rest in equilibrium, iterations, residual ratio, reactions (n,3),
        reaction moments (n,3)).
        """
        free = model.translation_free
        any_rot = bool(model.has_rotation.any())
        kinetic_damping = self.damping == "kinetic"
        f_ext, m_ext = model.external_load(load_factor, quasi_static=True)
        if model.has_prescribed:
            target = model.reference_positions + model.prescribed_displacement(
                load_factor, quasi_static=True
            )
            state = replace(
                state, positions=np.where(model.translation_prescribed, target, state.positions)
            )

        inflate = 1.0  # the factor on the fictitious masses after blow-ups in this increment
        mass, inertia, dt = masses(state, inflate)
        inv_inertia = inverse_diagonal(inertia)
        estimated_at = 0
        balance = _Balance(model, f_ext, m_ext, self.tol, floor)

        velocity = np.zeros_like(state.positions)
        omega = np.zeros_like(state.positions)
        kinetic_old = 0.0
        restart = True  # the first step from rest is a half step
        start_positions = state.positions.copy()
        begun = at_rest = state  # the last state the motion restarted from (blow-up recovery)
        recovered_to = None  # the state the last recovery went back to
        previous = None  # the last iteration's (displacement, residual, rate, mass) per kind
        rotation_since_start = np.zeros_like(state.positions)
        rest_rotation = rotation_since_start.copy()  # its value at ``at_rest``
        c = 0.0
        ratio = first_ratio = math.inf
        size_of_model = float(np.ptp(model.reference_positions, axis=0).max())
        first_size = None  # ||r|| + ||m|| / L_e at the first iteration (N)
        high_since = 1  # the first iteration of the current run of ratios above 0.5
        plateau = Plateau(self.plateau_iterations)

        for iteration in range(1, self.max_iterations + 1):
            if STOP.signal is not None:  # SIGINT or SIGTERM inside interruptible()
                stop = Interrupted(f"iteration {iteration}", None, STOP.signal)
                stop.steps = iteration - 1  # this increment's iterations, taken before the stop
                raise stop
            f_int, m_int = model.internal_force(state)
            residual = np.where(free, f_ext - f_int, 0.0)
            # (zero and unused without rotational DOFs)
            moment = (
                model.constrain_angular(m_ext - m_int, state.directors)
                if any_rot
                else np.zeros_like(f_int)
            )

            ratio, ok = balance.judge(f_int, m_int, residual, moment)
            if not np.isfinite(ratio) and not masses.fictitious:
                raise DivergenceError(
                    f"dynamic relaxation produced non-finite forces in increment {increment} "
                    f"(load factor {load_factor:.4g}) at iteration {iteration}",
                    None,
                    steps=iteration,
                )
            if ok and (reason := invalid_state(model, state, load_factor)):
                raise InvalidState(reason, iteration)  # not converged (solvers.acceptance)
            if ok:
                _warn_below_floor(balance.test, floor, self.tol, load_factor, unloaded)
                reactions, reaction_moments = balance.reactions(state, f_int, m_int, moment)
                rest = replace(
                    state,
                    velocities=np.zeros_like(velocity),
                    angular_velocities=np.zeros_like(omega),
                )
                return model.commit(rest), iteration, ratio, reactions, reaction_moments
            if iteration == 1:
                first_ratio = ratio
            progress(
                partial(_iteration_status, increment, iteration, ratio, self.tol),
                fraction=(increment - 1 + relaxed_share(first_ratio, ratio, self.tol))
                / self.increments,
            )
            # The size of the out-of-balance in force units. Not the ratio: a blow-up that
            # stretches the model grows F_int, the ratio's own reference, with it.
            size = float(np.linalg.norm(residual)) + (
                float(np.linalg.norm(moment)) / model.element_size if any_rot else 0.0
            )
            if first_size is None:
                first_size = size

            if masses.fictitious and not size <= _BLOW_UP * first_size:
                # The stiffness grew past the estimate the masses were made for (the motion
                # turned a stiff direction onto a DOF with a soft row): go back to the last
                # state at rest and restart with masses estimated there; if the last recovery
                # already restarted from that state, heavier and from the increment's start.
                if recovered_to is at_rest:  # (a peak taken in flight is no state at rest)
                    inflate, at_rest, rest_rotation = 2.0 * inflate, begun, 0.0 * rest_rotation
                recovered_to = at_rest
                masses.recoveries += 1
                if inflate > _MAX_INFLATION:
                    raise DivergenceError(
                        f"dynamic relaxation blew up in increment {increment} (load factor "
                        f"{load_factor:.4g}) at iteration {iteration} even with the fictitious "
                        f"masses {_MAX_INFLATION:g} times {masses.bound}",
                        None,
                        steps=iteration,
                    )
                state, rotation_since_start = at_rest, rest_rotation.copy()
                mass, inertia, dt = masses(state, inflate)
                inv_inertia = inverse_diagonal(inertia)
                estimated_at = iteration
                velocity = np.zeros_like(velocity)
                omega = np.zeros_like(omega)
                kinetic_old, restart, previous, c = 0.0, True, None, 0.0
                continue

            if plateau.stalled(iteration, ratio):
                if (factored := factored_fallback(masses)) is not None:
                    # a slow mode of the diagonal masses: on from rest with the factored
                    # stiffness as masses, a fresh watch (docs/theory.md §6.4a)
                    masses, plateau = factored, Plateau(self.plateau_iterations)
                    mass, inertia, dt = masses(state, inflate)
                    inv_inertia = inverse_diagonal(inertia)
                    estimated_at, at_rest = iteration, state
                    rest_rotation = rotation_since_start.copy()
                    velocity, omega = np.zeros_like(velocity), np.zeros_like(omega)
                    kinetic_old, restart, previous, c = 0.0, True, None, 0.0
                    continue
                raise ConvergenceError(
                    plateau.message(
                        self,
                        model,
                        increment,
                        load_factor,
                        ratio,
                        isinstance(masses, FactoredMasses),
                    ),
                    None,
                    steps=iteration,
                )
            if ratio <= STALL_RATIO:
                high_since = iteration + 1
            elif iteration - high_since >= self.stall_iterations and (
                float(np.abs(state.positions - start_positions).max()) > size_of_model
            ):
                # The out-of-balance did not fall and the model has moved farther than its own
                # size: nothing holds the motion (a slow but supported relaxation stays put).
                raise ConvergenceError(
                    stall_message(model, increment, self, load_factor), None, steps=iteration
                )

            step = 0.5 * dt if restart else dt
            if self.damping == "viscous":
                moved = state.positions - start_positions
                local = mass.local
                current = [(local(moved), local(residual), local(velocity), mass.values)]
                if any_rot:
                    current.append((rotation_since_start, moment, omega, inertia[:, None]))
                c = self._viscous_c(current, previous, dt)
                previous = current
            accelerating = mass.solve(residual)
            v_new = np.where(free, damped_velocity(velocity, accelerating, _ONE, step, c), 0.0)
            kinetic = mass.energy(v_new)
            if any_rot:
                _, w_new = angular_rates(
                    model, omega, moment, inv_inertia, step, c, state.directors
                )
                kinetic += 0.5 * float(np.sum(inertia[:, None] * w_new * w_new))

            if kinetic_damping and not restart and kinetic < kinetic_old:
                # The kinetic energy peaked half a step ago: go back there and restart from
                # rest (x* = x(i) - dt/2 v(i-1/2), docs/theory.md §6.4b).
                state = advance(model, state, -0.5 * dt, velocity, omega)
                velocity = np.zeros_like(velocity)
                omega = np.zeros_like(omega)
                kinetic_old = 0.0
                restart = True
                at_rest, rest_rotation = state, rotation_since_start.copy()
                # Lumped: the rotary inertia follows h_m (Eq. 39) and the step the geometry.
                # Fictitious: the stiffness follows the configuration.
                if masses.every_restart or iteration - estimated_at >= self.refresh:
                    mass, inertia, dt = masses(state, inflate)
                    inv_inertia = inverse_diagonal(inertia)
                    estimated_at = iteration
                continue

            state = advance(model, state, dt, v_new, w_new if any_rot else None)
            if any_rot:
                rotation_since_start += dt * w_new
                omega = w_new
            velocity = v_new
            kinetic_old = kinetic
            restart = False
            if masses.fictitious and (
                (not kinetic_damping and iteration - estimated_at >= self.refresh)
                or (iteration % _TURN_CHECK == 0 and masses.turned(state) > masses.turn)
                or masses.approached(state)
            ):
                # Viscous damping never stops the motion, a surface that turned far brings
                # its membrane stiffness onto its light normal axes, and a node that came to
                # a contact whose spring its mass does not carry would meet it too light:
                # re-estimate on the way, the kinetic energy re-measured with the new masses
                # (not a peak).
                mass, inertia, dt = masses(state, inflate)
                inv_inertia = inverse_diagonal(inertia)
                estimated_at = iteration
                previous = None
                kinetic_old = mass.energy(velocity) + 0.5 * float(
                    np.sum(inertia[:, None] * omega * omega)
                )

        raise ConvergenceError(
            f"dynamic relaxation did not converge in increment {increment}/{self.increments} "
            f"(load factor {load_factor:.4g}) within {self.max_iterations} iterations: residual "
            f"ratio {ratio:.3g}, tolerance {self.tol:g}. Raise max_iterations, "
            f"{more_increments(model)}or try the other damping ("
            f"{'kinetic' if self.damping == 'viscous' else 'viscous'}).",
            None,
            steps=self.max_iterations,
        )

    @staticmethod
    def _viscous_c(current, previous, dt) -> float:
        """Adaptive damping coefficient c = 2 sqrt(u.K u / u.M u) (Underwood 1983), over the
        translations and the rotations alike, with the local diagonal stiffness estimate
        K_jj = -(r_j(i) - r_j(i-1)) / (dt v_j(i-1/2)); u is the motion since the increment
        began. ``current`` / ``previous``: lists of (u, r, v, m) per kind of DOF, m (n, 3) or
        (n, 1) (the masses in use, physical or fictitious)."""
        if previous is None:
            return 0.0
        numerator = denominator = 0.0
        for (u, r, v, m), (_, r_old, _, _) in zip(current, previous):
            moving = np.abs(v) > 1e-300
            stiffness = np.zeros_like(v)
            stiffness[moving] = -(r[moving] - r_old[moving]) / (dt * v[moving])
            numerator += float(np.sum(stiffness * u * u))
            denominator += float(np.sum(m * u * u))
        if numerator <= 0.0 or denominator <= 0.0:
            return 0.0
        return min(2.0 * math.sqrt(numerator / denominator), 1.9 / dt)


_ONE = np.ones((1, 1))
#: An out-of-balance this many times the first one of an increment is a blow-up.
_BLOW_UP = 1e3
#: Iterations between checks of the turn of the shell normals (fictitious_masses.TURN).
_TURN_CHECK = 10
#: The fictitious masses are doubled at most until they reach this factor (2^10).
_MAX_INFLATION = 1024.0


def _iteration_status(increment: int, iteration: int, ratio: float, tol: float) -> str:
    """The status of an iteration (made only when the progress line shows it)."""
    return f"increment {increment}: iteration {iteration}, residual ratio {ratio:.3g} (tol {tol:g})"


def _interrupted(error: Interrupted, increment: int, increments: int, saved_at) -> str:
    kept = (
        f"the checkpoint {str(saved_at)!r} holds the converged increments: the same solve "
        "resumes from it"
        if error.checkpoint is not None
        else "no increment converged yet"
        if saved_at is not None
        else "no checkpoint was asked for"
    )
    return (
        f"dynamic relaxation interrupted by {error.signal} in increment {increment}/"
        f"{increments} ({error.args[0]}); {kept}"
    )


def _warn_below_floor(
    test: Equilibrium, floor: float, tol: float, load_factor: float, unloaded: float = 0.0
) -> None:
    """Warn when loads that are not zero lie below the force reference's floor: the solve
    then judges them as round-off (solvers.force_floor), accurate to tol x floor only. Not
    where they are below ``unloaded`` (a share of the last frame's loads, UNLOADED_SHARE):
    a user amplitude has taken them off (sin(pi lambda) leaves 1e-16 of the load at 1), and
    the unloaded model is what is asked."""
    loads = max(test.f_ext_norm, test.m_ext_norm / test.element_size)
    if max(0.0, unloaded) < loads < floor:
        warnings.warn(
            f"dynamic relaxation at load factor {load_factor:.4g}: the loads ({loads:.3g} N) are "
            f"below the rounding of the internal forces ({floor:.3g} N), so the equilibrium is "
            f"only as exact as {tol * floor:.3g} N; Static (tol 1e-8) resolves them",
            stacklevel=4,
        )


def _reference_floor(model: CompiledModel, last: Frame) -> float:
    """The least force reference of an increment (N) after the ``last`` frame, with user
    amplitudes (solvers.force_floor.unloaded_floor: a share of that frame's loads and
    reactions), since such an amplitude may bring the loads back to zero (a load then unload),
    where the level's own reference would judge round-off against round-off (docs/theory.md
    §6.5, "How the loads are ramped"); 0 without."""
    if not model.user_amplitudes():
        return 0.0
    f_ext, m_ext = model.external_load(last.time, quasi_static=True)
    return unloaded_floor(model, f_ext, m_ext, last.reactions, last.reaction_moments)


class _Balance:
    """Convergence and support reactions of one relaxed increment.

    Converged when, on the free DOFs, ||r|| <= tol F_ref and max|r_j| <= 10 tol F_ref / sqrt(n)
    with F_ref = max(||F_ext||, ||F_int||), and the constrained moments ||m|| <= tol M_ref with
    M_ref = max(||M_ext||, ||M_int||, F_ref L_e): director moments can all be tiny (fibre slip
    leaves them unloaded), and are then judged against the force scale times one element. The
    ratios are those of solvers.convergence.Equilibrium (moments over one element in F_ref
    only with rotational DOFs, M_ref the largest of the three, no floor on F_ref).
    """

    def __init__(
        self,
        model: CompiledModel,
        f_ext: np.ndarray,
        m_ext: np.ndarray,
        tol: float,
        floor: float = 0.0,
    ):
        self.model, self.f_ext, self.m_ext, self.tol = model, f_ext, m_ext, tol
        rot = model.has_rotation
        self.any_rotation = bool(rot.any())
        n_free = int(model.translation_free.sum()) + 2 * int(
            (rot[:, None] & ~model.rotation_fixed).sum()
        )
        self.sqrt_n = math.sqrt(max(n_free, 1))
        # Moments over one element as forces: under end moments alone (pure bending) the
        # nodal forces all tend to zero, the reactions too, and ||F_int|| alone would judge
        # round-off against round-off.
        self.test = Equilibrium(
            f_ext,
            m_ext,
            model.element_size,
            moments=self.any_rotation,
            moment_reference="largest",
            floor=floor,
        )

    def judge(self, f_int, m_int, residual, moment) -> tuple[float, bool]:
        """(residual ratio, converged) from the internal forces and the free residuals."""
        ratios = self.test.ratios(residual, moment, f_int, m_int)
        ok = ratios.force <= self.tol and float(np.abs(residual).max(initial=0.0)) <= (
            10.0 * self.tol * ratios.force_reference / self.sqrt_n
        )
        if self.any_rotation:
            ok = ok and ratios.moment <= self.tol
        return ratios.largest, ok

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
