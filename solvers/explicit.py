"""Explicit dynamics: the central difference scheme of Bai Eq. 22-23 (docs/theory.md §6.1-6.3).

With a variable step, dt_bar = (dt_prev + dt)/2 and mass-proportional damping C = c M:

    v(i+1/2) = [(1 - c dt_bar/2) v(i-1/2) + dt_bar M^-1 (F_ext - F_int)(i)] / (1 + c dt_bar/2)
    x(i+1)   = x(i) + dt v(i+1/2)

Rotations follow the same update with the rotary inertia and the moment vectors, on a nodal
angular velocity kept perpendicular to the director; the director then turns by the finite
rotation dt * omega (Rodrigues, docs/theory.md §1.3). The step itself is
solvers.step.explicit_step; CentralDifference chooses the steps, checks the energy balance and
writes the output.
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from functools import partial

import numpy as np

from femcore.fingerprint import Fingerprint, Uncalled, fingerprint
from femcore.interaction import SPRINGS_HELD_STEPS
from femcore.model import CompiledModel, Model
from femcore.results import Frame, Result
from femcore.state import State
from solvers.augmentation import warn_penalty_only
from solvers.blas_threads import one_blas_thread
from solvers.common import (
    DivergenceError,
    ProgressLine,
    check_fraction,
    check_integer,
    check_non_negative,
    check_positive_or_none,
    check_progress,
    compiled_model,
    empty_result,
    make_frame,
    resolve_progress,
)
from solvers.dynamics import EnergyAccount, FrameSchedule, rotational_kinetic
from solvers.energy_parts import largest_part_change
from solvers.explicit_refusals import refuse_unrunnable, refuse_up_front
from solvers.explicit_step_size import (  # noqa: F401 (STEP_GROWTH_HELD re-exported)
    STEP_GROWTH_HELD,
    StableStepRule,
)
from solvers.interrupts import STOP, Interrupted, check_outputs, keeps_writes
from solvers.output import (
    FrameStream,
    HistoryWriter,
    checkpoint_path,
    output_path,
    resume,
    save_checkpoint,
)
from solvers.quasi_static import KINETIC_BOUND, kinetic_over_work, quasi_static_report
from solvers.step import LumpedMasses, Step, explicit_step
from solvers.step_limits import step_limits, warn_step_short
from solvers.tool_force_watch import ToolForceWatch
from solvers.tool_penetration import record_tool_penetration

__all__ = ["CentralDifference"]

# The step is re-evaluated every this many steps: geometry and tension change slowly per step
# (the interactions' springs_at hold their bound that long: femcore/interaction.py).
STABLE_DT_EVERY = SPRINGS_HELD_STEPS
# Energy records kept for the history (more steps are thinned to about this many records).
ENERGY_RECORDS = 4000
# The assembled (Gershgorin) stable step may be evaluated again every this many steps (it
# costs a tangent assembly, tens of force evaluations); in between it follows the cells' bound.
# (When it is: solvers/explicit_step_size.py, ASSEMBLED_DT_STEADY and ASSEMBLED_DT_MAX.)
ASSEMBLED_DT_EVERY = 500
# The energy balance is checked every this many steps (the strain energy comes with the
# step's force pass: ElementBlock.internal_force_and_energy) and on the last step.
BALANCE_EVERY = 10
# The checks of a run (EnergyAccount.check, docs/theory.md §6.1): the largest energy balance
# error |KE* + U + D - W_ext| / (largest energy of the run) (a good run: 1e-7 on a sagging
# cable, 2e-3 on the G1151 strip, 1e-2 on a bar under a step load); the largest (KE + U) /
# (work supplied) (a stable linear run stays below 1 / (1 - (omega dt / 2)^2), 10 at omega dt =
# 1.9: 0.95 of an exact critical step) and the largest at which a state is still kept as the
# last good one (2: omega dt = 1.4 may reach it with all the energy in the highest mode); the
# largest motion of a node in one step, in median element edges.
BALANCE_TOLERANCE = 0.05
# The most mass that mass scaling may add, in times the mass of the model's elements (the option
# max_added_mass): beyond it the inertia, not the model, decides the answer.
MAX_ADDED_MASS = 10.0
#: The fraction of the stable step the solver takes (``safety``'s default).
SAFETY = 0.9
GROWTH_LIMIT = 10.0
#: Kinetic energy below this share of M (h / dt)^2 (the whole mass moving an element length a
#: step) is round-off, not a blow-up: forces of order 1e-16 (a contact touching at zero gap)
#: move a model at rest by ~1e-29 N mm before any external work is counted. An instability
#: grows by orders of magnitude within a few steps, so the floor hardly delays its detection.
KINETIC_ROUNDOFF = 1e-16
GOOD_GROWTH = 2.0
MAX_STEP_MOTION = 0.5


class CentralDifference(StableStepRule):
    """Explicit central-difference dynamics over ``duration`` seconds.

    duration : s, the length of the step; loads reach their amplitude at its end.
    dt : s, a fixed time step, or None for safety x the stable step (re-evaluated as the
        geometry changes).
    safety : factor on the stable step (0 < safety <= 1; None: SAFETY = 0.9), and on mass
        scaling's target; with a fixed ``dt`` and no ``mass_scaling_dt`` nothing uses it, and
        giving it is refused.
    damping : c of the mass-proportional damping C = c M, 1/s.
    mass_scaling_dt : s, a target step: cells whose stable step is smaller get their density
        scaled by (target / dt_cell)^2 so that the step is the target; the added mass is
        reported in ``result.info``.
    max_added_mass : the most mass scaling may add, in times the elements' mass (the tools'
        masses aside; None: MAX_ADDED_MASS = 10); more is refused before the run starts
        (ValueError naming it). Given without ``mass_scaling_dt`` it is refused (nothing adds
        mass).
    max_steps : the most steps of the run; a duration / dt above it at the first step is
        refused before the run starts, and a run whose step shrinks past it stops there.
    output_interval : s between frames (default duration / 20).
    output : a ``.pvd`` path: the frames are written there as the run goes (a VTU file each,
        the ParaView index rewritten after each), and only the first and the last are kept in
        memory.
    history : a ``.csv`` path: a row per energy record (about 4000 in a run), appended as the
        run goes, written at each frame (solvers.output.HistoryWriter): ``time``,
        ``energy_kinetic``, ``energy_internal`` (stored: the internal forces' work less the
        friction's), ``energy_external_work``, ``energy_damping``, ``energy_friction`` (N mm;
        kinetic + internal + damping + friction = external work, docs/theory.md §6.1 "The
        energy records"), ``reaction_all_x/y/z`` the sum of the support reactions (N),
        ``tool<k>_force_x/y/z`` (N), ``tool<k>_displacement_x/y/z`` (mm) and
        ``displacement_node<i>_x/y/z`` (mm) of
        ``history_nodes``.
    history_nodes : node indices (>= 0, of the model's nodes: checked as the run starts)
        whose displacements the history records.
    frame_summary : callable Frame -> dict, optional
        Called on every output frame (the first included, streamed or not); the dicts are
        ``result.info["frame_summaries"]``, one per frame of the series, also after a resume
        (they are part of the checkpoint): how a streamed run, which keeps only two frames in
        memory, gives a history row per frame. A checkpoint knows it by what it is made of
        (its code, defaults, closure values and the globals it reads; an object's public
        attributes), never by calling it: a resume with another is refused, as the rows kept
        before the stop would have other columns than those after it. (One that appends to a
        list it reads is another once the list has grown: return the row instead.)
    progress : show a progress bar on stderr, its share the time reached (None: unless under
        pytest or with FIBRESHELL_PROGRESS=0, solvers.progress.resolve_progress).
    kinetic_bound : the largest kinetic energy over external work KE / W of a quasi-static run
        (solvers/quasi_static.py): above it for more than a tenth (KINETIC_SHARE) of the judged time
        (after the first tenth of the duration, where the work done has reached 1 % of the run's),
        one UserWarning at the end of a run that completes, with the time, the ratio and the share
        (a shorter burst is reported, not warned); None for a dynamic run (reported, not warned).
        Default "auto": KINETIC_BOUND = 0.1 (the upper end of the field's 5-10 %) for a model with
        rigid tools (a forming run, quasi-static by intent), None for one without (a wave, a
        swinging cable: dynamic by intent). KE / W per energy record is
        ``result.energies["kinetic_over_work"]``, and ``result.info["quasi_static"]`` reports it
        with the mass and time scaling. KE counts every mass in use, the directors' rotation on the
        (scaled) rotary inertia too; its rotational part is
        ``result.energies["kinetic_rotational"]`` (docs/theory.md §6.3). The same switch
        governs the force-driven tools' warning (solvers/tool_force_watch.py): over the last
        half of the run, each tool's contact force along its free axes against the force
        prescribed on it, at every step, is ``result.info["quasi_static"]["driven_tools"]``,
        and a departure above TOOL_FORCE_SHARE = 0.2 (its ringing, its inertia) warns once
        unless the bound is None.
    process_duration : s, the duration of the real process, when ``duration`` is shorter
        (time scaling): the factor process_duration / duration (>= 1; a shorter process is
        refused) is reported with its KE / W.
    """

    def __init__(
        self,
        duration: float,
        dt: float | None = None,
        safety: float | None = None,
        damping: float = 0.0,
        mass_scaling_dt: float | None = None,
        output_interval: float | None = None,
        progress: bool | None = None,
        max_steps: int = 50_000_000,
        output: str | os.PathLike[str] | None = None,
        history: str | os.PathLike[str] | None = None,
        history_nodes=(),
        frame_summary: Callable[[Frame], dict] | None = None,
        max_added_mass: float | None = None,
        kinetic_bound: float | str | None = "auto",
        process_duration: float | None = None,
    ):
        checked = check_positive_or_none(duration, "duration", "s")
        if checked is None:
            raise ValueError("duration must be a positive number of seconds")
        self.duration: float = checked
        self.dt = check_positive_or_none(dt, "dt", "s")
        self.damping = check_non_negative(damping, "damping", "1/s, of C = c M")
        self.mass_scaling_dt = check_positive_or_none(mass_scaling_dt, "mass_scaling_dt", "s")
        # options that only act through another: given without it, they would be ignored
        if safety is not None and self.dt is not None and self.mass_scaling_dt is None:
            raise ValueError(
                f"safety = {safety!r} scales the solver's own stable step, and dt = {dt!r} "
                "fixes the step: leave one of them out (safety also scales mass scaling's "
                "target, mass_scaling_dt)"
            )
        if max_added_mass is not None and self.mass_scaling_dt is None:
            raise ValueError(
                f"max_added_mass = {max_added_mass!r} bounds the mass that mass scaling adds, "
                "and no mass_scaling_dt asks for mass scaling: give mass_scaling_dt, or leave "
                "max_added_mass out"
            )
        self.safety = check_fraction(SAFETY if safety is None else safety, "safety")
        self.max_added_mass = check_non_negative(
            MAX_ADDED_MASS if max_added_mass is None else max_added_mass,
            "max_added_mass",
            "a ratio",
        )
        self.output_interval = check_positive_or_none(output_interval, "output_interval", "s")
        self.progress = check_progress(progress)
        self.max_steps = check_integer(max_steps, "max_steps")
        self.output = None if output is None else output_path(output, ".pvd", "output")
        self.history = None if history is None else output_path(history, ".csv", "history")
        nodes = np.asarray(history_nodes)
        if nodes.size and (nodes.ndim != 1 or not np.issubdtype(nodes.dtype, np.integer)):
            raise ValueError(f"history_nodes must be node indices, got {history_nodes!r}")
        if nodes.size and nodes.min() < 0:
            raise ValueError(
                f"history_nodes must be node indices >= 0, got {int(nodes.min())} (a negative "
                "index would record another node than the one named)"
            )
        self.history_nodes = nodes.astype(np.int64).reshape(-1)
        if frame_summary is not None and not callable(frame_summary):
            raise ValueError(
                f"frame_summary must be a function of a Frame, got {type(frame_summary).__name__}"
            )
        self.frame_summary = frame_summary
        if isinstance(kinetic_bound, str) and kinetic_bound != "auto":
            raise ValueError(
                'kinetic_bound must be "auto", None or a positive ratio KE / W, '
                f"got {kinetic_bound!r}"
            )
        self.kinetic_bound: float | str | None = (
            "auto"
            if isinstance(kinetic_bound, str)
            else check_positive_or_none(kinetic_bound, "kinetic_bound", "a ratio KE / W")
        )
        self.process_duration = check_positive_or_none(process_duration, "process_duration", "s")
        if self.process_duration is not None and self.process_duration < self.duration:
            raise ValueError(
                f"process_duration = {process_duration!r} s is shorter than the run's duration "
                f"= {duration!r} s: it is the real process's duration, of which a time-scaled "
                "run is the faster version (time scaling = process_duration / duration >= 1)"
            )
        # (assembled Gershgorin step, the cells' bound and the step when it was evaluated),
        # set by solve
        self._assembled: tuple[float, float, int] | None = None

    # ------------------------------------------------------------------ solve
    @keeps_writes
    @one_blas_thread
    def solve(
        self,
        model: Model | CompiledModel,
        checkpoint: str | os.PathLike[str] | None = None,
        checkpoint_interval: float = 60.0,
    ) -> Result:
        """Integrate from the reference state at rest, or from ``checkpoint``.

        Parameters
        ----------
        model : Model or CompiledModel
        checkpoint : path, optional
            A file where the whole state of the run (positions, directors, velocities, angular
            velocities, element histories, time, step, energies, frames) is written, atomically,
            every ``checkpoint_interval`` seconds of wall time and at the end. If the file
            exists, the run resumes from it: a run killed at any moment and started again with
            the same call ends in the same state, to the last bit, as if never interrupted.
        checkpoint_interval : float
            Wall-clock seconds between checkpoints (0: at every chance, every 10 steps).

        Returns
        -------
        femcore.results.Result
            Frames every ``output_interval`` (only the first and the last when they are
            streamed to ``output``: ``info["output"]`` names the series that holds every one,
            ``info["streamed_frames"]`` counts them), energies, ``info`` (step, added mass,
            energy checks).

        Raises
        ------
        DivergenceError
            On non-finite values, an energy blow-up or a failed energy check, keeping the
            frames up to the last state that passed the checks in ``error.result``.
        solvers.interrupts.Interrupted
            On SIGINT or SIGTERM inside ``solvers.interruptible()``: the run stops before its
            next step, saves its checkpoint and keeps its frames in ``error.result``; the same
            call resumes it.
        femcore.writable.OutputError
            An output or checkpoint folder that cannot be written or is too full for the first
            frames (before the run), or a write that failed during it (the message names the
            file and what was kept).
        ValueError
            ``model`` not a Model; a checkpoint written by another model or other solver
            settings; a ``checkpoint_interval`` that is not a number >= 0; a run that would
            take more than ``max_steps`` steps or add more than ``max_added_mass`` times the
            elements' mass (both before the first step).
        """
        compiled = compiled_model(model, "CentralDifference")
        checkpoint_interval = check_non_negative(checkpoint_interval, "checkpoint_interval", "s")
        refuse_unrunnable(self, compiled)
        saved_at = checkpoint_path(checkpoint)
        check_outputs(compiled.mesh, self.output, self.history, saved_at)
        started = time.perf_counter()
        # The fingerprint only matters to a checkpoint (it samples the amplitudes, hashes
        # the model): a run without one skips it.
        signature = self._signature(compiled) if saved_at is not None else None
        payload = resume(saved_at, signature)
        if payload is not None:
            run: _Run = payload["run"]
            self._assembled = payload["assembled"]
            # the wall time counts the parts before the stop (up to the checkpoint) too
            run.wall_before = getattr(run, "wall_time", 0.0)  # (absent from older checkpoints)
            started -= run.wall_before
        else:
            run = self._start(compiled)
        warn_penalty_only(compiled, run.state, "CentralDifference")
        stream, history = self._outputs(compiled, run)
        with ProgressLine(resolve_progress(self.progress), "central difference") as progress:
            try:
                result = self._march(
                    compiled, run, stream, history, progress, started, saved_at, signature,
                    checkpoint_interval,
                )  # fmt: skip
            except BaseException as error:
                # the rows kept in memory since the last write, whatever ended the run; a
                # failing write must not hide the error on its way out (its result, its state)
                if history is not None:
                    try:
                        history.flush()
                    except OSError as failed:
                        error.add_note(f"the history's last rows were not written: {failed}")
                raise
            if history is not None:
                history.flush()
            return result

    def _march(
        self,
        compiled: CompiledModel,
        run: _Run,
        stream,
        history,
        progress: ProgressLine,
        started: float,
        saved_at,
        signature,
        checkpoint_interval: float,
    ) -> Result:
        """The time steps of ``solve`` from ``run``'s state to the end of the duration."""
        last_saved = time.perf_counter()
        duration = self.duration
        # The time of the state the checkpoint holds (a resumed run's: the state it resumed
        # from), None before one is written.
        saved_time = [run.state.time if saved_at is not None and saved_at.exists() else None]

        def result(converged: bool) -> Result:
            made = self._result(compiled, run, started, converged)
            if stream is not None:  # (Result.write warns that it holds two of these)
                made.info["streamed_frames"] = len(stream.entries)
            return made

        def diverged(message: str, dt: float):
            """The run stops: the frames end with the last state that passed the checks."""
            good_time = run.good[0].time
            scaled = (
                f" Mass scaling added {run.added_mass / compiled.element_mass:.3g} times "
                "the elements' mass."
                if run.added_mass > 0.0
                else ""
            )
            kept = [f for f in run.frames if f.time <= good_time * (1.0 + 1e-12)]
            if kept[-1].time < good_time:
                kept.append(make_frame(compiled, *run.good))
                if stream is not None:
                    stream.drop_after(good_time)
                    stream.write(kept[-1])
            elif stream is not None:
                stream.drop_after(good_time)
            run.frames[:] = kept[:1] + kept[-1:] if stream is not None else kept
            run.summaries[:] = [s for s in run.summaries if s[0] <= good_time * (1.0 + 1e-12)]
            run.energy.drop_after(good_time)  # the failed steps' records go with their frames
            if run.summaries and kept[-1].time > run.summaries[-1][0]:
                self._summarise(run, kept[-1])
            removed = ""
            if saved_time[0] is not None and saved_time[0] > good_time * (1.0 + 1e-12):
                # The checkpoint holds a state the checks had not passed (a save comes every
                # 10 steps, before the step that checks it): a resume would start past the
                # last good state, from outputs trimmed back to it, and diverge again.
                assert saved_at is not None
                saved_at.unlink(missing_ok=True)
                removed = (
                    f" The checkpoint held the state at t = {saved_time[0]:.6g} s, past the "
                    "last good one, and was removed: resuming the run as it is would diverge "
                    "again."
                )
            failure = DivergenceError(
                f"central difference diverged at step {run.step}, t = {run.state.time:.6g} s "
                f"(dt = {dt:.3g} s): {message}; the last frame is the last state that passed "
                f"the checks (t = {good_time:.6g} s). Reduce dt or safety, or check the loads "
                f"and material laws.{scaled}{removed}",
                result(False),
            )
            if history is not None:
                try:
                    history.drop_after(good_time)
                except OSError as failed:  # (not to hide why the run stopped)
                    failure.add_note(
                        f"the history was not cut back to t = {good_time:.6g} s: {failed}"
                    )
            return failure

        def save() -> None:
            if saved_at is not None:
                if stream is not None:
                    run.written = list(stream.entries)
                if history is not None:
                    history.flush()  # the rows the checkpoint counts are in the file
                    run.history_rows = history.rows
                run.wall_time = time.perf_counter() - started
                payload = {"signature": signature, "run": run, "assembled": self._assembled}
                save_checkpoint(saved_at, payload)
                saved_time[0] = run.state.time

        masses = LumpedMasses(run.mass, run.inertia)  # rebuilt when the inertia follows h_m
        while run.state.time < duration * (1.0 - 1e-12):
            step, state = run.step, run.state
            if STOP.signal is not None:  # SIGINT or SIGTERM inside interruptible()
                save()
                raise Interrupted(
                    _stopped_by(STOP.signal, step, state.time, duration, saved_at),
                    result(False),
                    STOP.signal,
                    saved_at,
                )
            if step >= self.max_steps:
                raise DivergenceError(
                    f"central difference stopped after {step} steps at t = {state.time:.6g} s of "
                    f"{duration:.6g} s (max_steps): the step is too small for this duration",
                    result(False),
                )
            if step % STABLE_DT_EVERY == 0 and step > 0:
                if time.perf_counter() - last_saved >= checkpoint_interval:
                    save()  # before the refresh below, which a resumed run repeats
                    last_saved = time.perf_counter()
                if compiled.dofs.any_rotation:
                    # Eq. 39: I = m h_m^2 / 4 follows the thickness along the director (and its
                    # lever, docs/theory.md §1.6); a stale I under a tilting director makes the
                    # director modes unstable. It only grows: a larger I is as stable, and a
                    # director flapping about the guard would otherwise have it drop 600-fold.
                    inertia = np.maximum(run.inertia, compiled.lumped_mass(state, run.scale)[1])
                    run.state = state = _keep_rotary_energy(state, run.inertia, inertia)
                    run.inertia = inertia
                    masses = LumpedMasses(run.mass, run.inertia)
                if self.dt is None:
                    fresh = step % ASSEMBLED_DT_EVERY == 0
                    run.dt_nominal = self._step_size(
                        compiled,
                        state,
                        run.scale,
                        run.mass,
                        run.inertia if fresh else None,
                        step,
                        run.dt_nominal,
                    )
            dt = min(run.dt_nominal, duration - state.time)
            last = state.time + dt >= duration * (1.0 - 1e-12)
            checking = (step > 0 and step % BALANCE_EVERY == 0) or last
            outcome = explicit_step(
                compiled,
                state,
                dt,
                masses,
                dt_prev=run.dt_prev,
                damping=self.damping,
                duration=duration,
                checking=checking,
            )
            new, work = outcome.state, outcome.energy
            tools = getattr(run, "tools", None)  # (absent from a run checkpointed without it)
            if tools is not None:
                tools.observe(compiled, state, dt)  # the step's forces, kept by the contacts
            reactions, reaction_moments = outcome.reactions, outcome.reaction_moments
            energy = run.energy
            # (the round-off's scale asked only of a step whose energy looks like a blow-up)
            if energy.blows_up(*work) and not work[3] <= _roundoff(compiled, run, dt):
                raise diverged(
                    f"kinetic energy {work[3]:.3g} against {energy.work_scale:.3g} of external "
                    "work",
                    dt,
                )
            energy.accept(*work)
            if checking:
                self._check(compiled, run, outcome, dt, diverged)
            run.state = state = compiled.commit(new)
            if compiled.interactions:  # (ply contacts dissipate without a tool)
                energy.dissipate(compiled.dissipated_energy(state))
            run.dt_prev = dt
            run.step = step = step + 1
            rotational = partial(rotational_kinetic, run.inertia, state.angular_velocities)
            if energy.record(step, state.time, rotational) and history is not None:
                history.append(
                    energy.latest(),
                    reactions,
                    state.positions - compiled.reference_positions,
                    compiled.tool_forces(state),
                    compiled.tool_displacements(state),
                )
            if run.schedule.due(state.time):
                if history is not None:
                    history.flush()  # written at the frame rate (solvers.output.HistoryWriter)
                frame = make_frame(compiled, state, reactions, reaction_moments)
                if stream is not None:
                    stream.write(frame)
                    run.frames[1:] = [frame]
                else:
                    run.frames.append(frame)
                self._summarise(run, frame)
            progress(
                partial(_status, state.time, duration, step, dt, energy.kinetic, energy.stored),
                fraction=state.time / duration,
            )

        save()
        progress(f"done: {run.step} steps", fraction=1.0)
        return result(True)

    def _signature(self, model: CompiledModel) -> Fingerprint:
        """What a checkpoint must match to be resumed: the model's fingerprint and the solver
        settings that change the run or its files (not ``max_steps`` nor ``progress``)."""
        settings = {
            "solver": "CentralDifference",
            "duration": self.duration,
            "dt": self.dt,
            "safety": self.safety,
            "damping": self.damping,
            "mass_scaling_dt": self.mass_scaling_dt,
            "output_interval": self.output_interval,
            "output": self.output is not None,
            "history": self.history is not None,
            "history_nodes": self.history_nodes,
            # what the rows kept before a stop were made by: another would mix their columns
            # (read, never called: it takes a Frame)
            "frame_summary": Uncalled(self.frame_summary),
        }
        return fingerprint(model, settings)

    def _start(self, compiled: CompiledModel) -> _Run:
        state = compiled.initial_state()
        scale = self._density_scale(compiled, state)
        mass, inertia = compiled.lumped_mass(state, scale)
        self._assembled = None
        dt_nominal = self._step_size(compiled, state, scale, mass, inertia)
        if not np.isfinite(dt_nominal) or dt_nominal <= 0:
            raise DivergenceError(
                "the stable time step is not a positive number: check the "
                "element stiffness and mass",
                empty_result(compiled, []),
            )
        duration = self.duration
        added_mass = float(mass.sum() - compiled.mass0.sum())
        refuse_up_front(self, compiled, added_mass, dt_nominal)
        limits = None
        if self.mass_scaling_dt is not None:  # what holds the step below the scaling's aim
            limits = step_limits(compiled, state, scale, mass, self, dt_nominal)
            warn_step_short(limits)
        run = _Run(
            state=state,
            scale=scale,
            mass=mass,
            inertia=inertia,
            added_mass=added_mass,
            dt_nominal=dt_nominal,
            energy=EnergyAccount(thin=max(1, int(duration / dt_nominal / ENERGY_RECORDS))),
            schedule=FrameSchedule(self.output_interval or duration / 20.0, duration),
            frames=[make_frame(compiled, state)],
            strain_at_start=compiled.strain_energy(state),
            good=(state, None, None),
            tools=ToolForceWatch(compiled, duration) if len(compiled.driven_tools) else None,
            step_limits=limits,
        )
        self._summarise(run, run.frames[0])
        return run

    def _summarise(self, run: _Run, frame: Frame) -> None:
        """Keep ``frame_summary(frame)`` with the frame's time (when there is one)."""
        if self.frame_summary is not None:
            run.summaries.append((frame.time, self.frame_summary(frame)))

    def _outputs(self, compiled: CompiledModel, run: _Run):
        """The frame stream and the history writer of this run (None when not asked for),
        carried on from the checkpoint ``run`` was restored from."""
        stream = history = None
        if self.output is not None:
            stream = FrameStream(self.output, compiled.mesh, compiled.has_rotation.copy())
            stream.entries = list(run.written)
            if not stream.entries:
                stream.write(run.frames[0])
            else:
                stream.check_written()
                stream.drop_after(run.state.time)
        if self.history is not None:
            history = HistoryWriter(self.history, self.history_nodes, compiled.n_tools)
            history.rows = run.history_rows
            history.start()
        return stream, history

    def _check(self, compiled, run: _Run, outcome: Step, dt, diverged):
        """The energy checks of docs/theory.md §6.1 on the state at t(i), whose forces the
        step used (and whose strain energy it met on the way, ``Step.strain_energy``);
        raises ``diverged(...)``, or notes the state as the last good one."""
        state, new = run.state, outcome.state
        reactions, reaction_moments = outcome.reactions, outcome.reaction_moments
        strain = outcome.strain_energy
        if strain is None:  # a step taken without ``checking``
            strain = compiled.strain_energy(state)
        onset = 0.0
        if compiled.n_tools:  # the tools' work over [t(i-1/2), t(i)] (EnergyAccount.check)
            tau = state.time / self.duration
            onset = abs(compiled.tool_work(state, tau - 0.5 * run.dt_prev / self.duration, tau))
        balance, growth = run.energy.check(
            outcome.energy,
            strain - run.strain_at_start,
            compiled.dissipated_energy(state),
            onset,
        )
        if run.energy.largest <= _roundoff(compiled, run, dt):
            balance = growth = 0.0  # every energy so far is round-off: nothing to judge yet
        run.worst = max(run.worst, balance)
        run.grown = max(run.grown, growth)
        moved = dt * float(np.abs(new.velocities).max(initial=0.0))
        if balance > BALANCE_TOLERANCE:
            raise diverged(
                f"the energy balance |KE + U + D - W_ext| is off by {balance:.3g} of the "
                f"largest energy of the run (tolerance {BALANCE_TOLERANCE:g}); "
                + largest_part_change(compiled, run.good[0], state),
                dt,
            )
        if growth > GROWTH_LIMIT:
            raise diverged(
                f"kinetic and strain energy have grown to {growth:.3g} times the work "
                f"done on the model (limit {GROWTH_LIMIT:g})",
                dt,
            )
        if moved > MAX_STEP_MOTION * compiled.element_size:
            raise diverged(
                f"a node moved {moved:.3g} mm in one step, more than "
                f"{MAX_STEP_MOTION:g} of the median element edge",
                dt,
            )
        if growth <= GOOD_GROWTH:
            run.good = (state, reactions, reaction_moments)

    def _kinetic_bound(self, compiled: CompiledModel) -> float | None:
        """The KE / W bound warned about: "auto" is KINETIC_BOUND with rigid tools, else
        None."""
        if self.kinetic_bound == "auto":
            return KINETIC_BOUND if compiled.n_tools > 0 else None
        return self.kinetic_bound  # type: ignore[return-value]

    def _result(self, compiled, run: _Run, started: float, converged: bool) -> Result:
        result = empty_result(compiled, list(run.frames))
        result.steps = run.step
        result.wall_time = time.perf_counter() - started
        result.converged = converged
        result.energies = run.energy.arrays()
        tools = getattr(run, "tools", None)
        report, note = None, None
        if tools is not None:  # a loose tool's kinetic energy is its own, not the body's
            report = tools.report(run.state)
            kinetic = float(result.energies["kinetic"][-1]) if len(result.energies["time"]) else 0.0
            note = tools.kinetic_note(report, run.state, run.mass, kinetic)
        result.info = {
            "solver": "CentralDifference",
            "dt": run.dt_nominal,
            "added_mass": run.added_mass,
            "added_mass_ratio": run.added_mass / compiled.element_mass,
            "damping": self.damping,
            "energy_balance_error": run.worst,
            "energy_growth": run.grown,
            "step_limits": getattr(run, "step_limits", None),
            "wall_time_before_resume": getattr(run, "wall_before", 0.0),
            "quasi_static": quasi_static_report(
                result.energies,
                self._kinetic_bound(compiled),
                self.duration,
                run.added_mass / compiled.element_mass,
                self.process_duration,
                warn=converged,
                tool_note=note,
            ),
        }
        if tools is not None:
            result.info["quasi_static"]["driven_tools"] = report
            if converged and self._kinetic_bound(compiled) is not None:
                tools.warn(report)
        record_tool_penetration(compiled, result, "CentralDifference", converged)
        result.energies["kinetic_over_work"] = kinetic_over_work(
            result.energies["kinetic"], result.energies["external_work"]
        )
        if self.output is not None:
            result.info["output"] = str(self.output)
        if self.frame_summary is not None:
            result.info["frame_summaries"] = [summary for _, summary in run.summaries]
        return result


def _keep_rotary_energy(state: State, before: np.ndarray, after: np.ndarray) -> State:
    """``state`` with its angular velocities (n, 3) scaled by sqrt(I_before / I_after) at each
    node, so that 1/2 I omega^2 is the same with the refreshed rotary inertia ``after`` (n,),
    t mm^2. The inertia follows the geometry (the fibrous director's lever h / cos^2(tilt)
    grows to 25 h at the guard): without the scaling the energy balance would see rotational
    kinetic energy made without work (a formed blank's flipped corner directors: 2 -> 119
    N mm at one refresh)."""
    ratio = np.sqrt(np.divide(before, after, out=np.ones_like(after), where=after > 0.0))
    return replace(state, angular_velocities=state.angular_velocities * ratio[:, None])


def _status(
    time: float, duration: float, step: int, dt: float, kinetic: float, internal: float
) -> str:
    """The status of a step (made only when the progress line shows it)."""
    return (
        f"t = {time:.4g}/{duration:.4g} s, step {step}, dt = {dt:.3g} s, "
        f"KE = {kinetic:.4g}, IE = {internal:.4g}"
    )


def _stopped_by(signal_name: str, step: int, time: float, duration: float, saved_at) -> str:
    kept = (
        f"the checkpoint {str(saved_at)!r} holds it: the same solve resumes it"
        if saved_at is not None
        else "no checkpoint was asked for"
    )
    return (
        f"central difference interrupted by {signal_name} after step {step}, t = {time:.6g} s of "
        f"{duration:.6g} s; {kept}"
    )


@dataclass
class _Run:
    """Everything that changes during a run: what a checkpoint holds."""

    state: State
    scale: list | None
    mass: np.ndarray
    inertia: np.ndarray
    added_mass: float
    dt_nominal: float
    energy: EnergyAccount
    schedule: FrameSchedule
    frames: list[Frame]
    strain_at_start: float
    good: tuple  # the last state that passed the checks, with its reactions and moments
    step: int = 0
    dt_prev: float = 0.0
    worst: float = 0.0  # the largest energy balance error met
    grown: float = 0.0  # the largest energy growth met
    written: list = field(default_factory=list)  # the frame files of the stream
    history_rows: int = 0
    summaries: list = field(default_factory=list)  # (time, frame_summary(frame)) per frame
    tools: ToolForceWatch | None = None  # the force-driven tools' forces over the last half
    wall_time: float = 0.0  # s, the run's wall time up to its last checkpoint
    wall_before: float = 0.0  # s, the wall time of the parts before the resume (0: none)
    step_limits: dict | None = None  # with mass scaling: the step's bounds at the start


def _roundoff(compiled: CompiledModel, run: _Run, dt: float) -> float:
    """The kinetic energy (N mm) below which the energy checks see round-off: KINETIC_ROUNDOFF
    of the whole mass moving an element length a step."""
    return KINETIC_ROUNDOFF * float(np.sum(run.mass)) * (compiled.element_size / dt) ** 2
