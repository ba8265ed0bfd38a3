"""One Static solve in progress (``StaticRun``, made by ``Static.solve``, solvers/static.py): the
model, its tangent and linear solver, the last converged state and load factor, the frames and
the info written so far; the model evaluations (residual, energy, tangent, factorisation), the
configurations (placing, moving and predicting states) and the bookkeeping of converged
increments (frames, cuts, failures, the result) that the load path (solvers.load_path), the
arc-length path (solvers.arc_length), Newton (solvers.newton) and the stability checks
(solvers.stability) work through.
"""

from __future__ import annotations

import time
import warnings
from dataclasses import replace
from typing import TYPE_CHECKING, Any

import numpy as np
import scipy.sparse as sp

from femcore.dofs import N_COLUMNS, Frames
from femcore.model import CompiledModel
from femcore.results import Result
from femcore.rotation import cross, rotate_about
from femcore.state import State
from solvers.arc_length import Motion
from solvers.common import (
    ConvergenceError,
    ProgressLine,
    TurnedInsideOut,
    empty_result,
    equilibrium_reactions,
    make_frame,
    outside_stacklevel,
    resolve_progress,
)
from solvers.floor_acceptance import report_floor_acceptances
from solvers.force_floor import round_off_force, unloaded_floor
from solvers.interrupts import STOP, Interrupted
from solvers.kept_tangent import KeptTangent
from solvers.linear import Factorisation, LinearSolver
from solvers.neutral_modes import judge_pivots
from solvers.newton import Residual, Tangent, compression_free_ratio
from solvers.newton_fibres import FibreEdges
from solvers.newton_levels import LevelStrains
from solvers.output import FrameStream
from solvers.round_off import rounding_stop
from solvers.stabilisation import Dashpots
from solvers.stop_diagnosis import neutral_hint, still_falling, stop_hint
from solvers.tool_penetration import record_tool_penetration

if TYPE_CHECKING:
    from solvers.static import Static

__all__ = ["StaticRun"]


class StaticRun:
    """One solve in progress: the model, its tangent and linear solver, the last converged
    state and load factor, the frames and the info written so far. The Newton iterations
    (solvers.newton), the arc-length path (solvers.arc_length) and the stability checks
    (solvers.stability) work on it."""

    def __init__(self, solver: Static, model: CompiledModel):
        self.solver, self.model = solver, model
        self.started = time.perf_counter()
        self.state = model.initial_state()
        # The last converged state as Newton balanced it, before ``model.commit`` updated its
        # history: a frame's reactions and tool forces are taken there (``frame``).
        self.balanced = self.state
        self.reached = 0.0
        # The Newton iterations of the steps accepted since the last frame (``accept``): a
        # stop part way through an increment counts them in the result's steps.
        self.unframed_iterations = 0
        # The least force reference of the convergence test (solvers.convergence): 1e-300,
        # or with user amplitudes a share of the loads and reactions of the last converged
        # frame (solvers.force_floor.unloaded_floor), since such an amplitude may bring the
        # loads back to zero (a load then unload), where the reference of the level alone
        # would judge round-off against round-off. Never below the rounding of the internal
        # forces (solvers.force_floor), where the answer carries almost no force (a prescribed
        # rigid motion, a load of 1e-10 N): from the element tangents at the start whatever
        # tangent the solve takes (with finite differences too).
        own_parts = model.own_tangents(self.state) if solver.tangent == "element" else {}
        rounding_parts = own_parts if own_parts else model.own_tangents(self.state)
        self.round_off = round_off_force(model, [p for ps in rounding_parts.values() for p in ps])
        self.reference_floor = max(1e-300, self.round_off)
        # Whether the load path is in the first increment of a phase (solvers.load_path;
        # solvers/newton.py ``opens_on_ramp``).
        self.opening = False
        own = list(own_parts)
        others = [i for i in range(len(model.parts)) if i not in own]
        self._tangent = Tangent(model, own, others, (self.state, own_parts))
        self.linear = LinearSolver()
        # The updated K_ff of a predicted contact set (solvers/contact_sets.py), factorised by a
        # linear solver of its own: its patterns would replace the tangents' kept plans.
        self.updated_linear = LinearSolver()
        # The shifted K_ff whose inertia tells the negative modes from the neutral ones
        # (solvers.neutral_modes), factorised by a linear solver of its own likewise.
        self.neutral_linear = LinearSolver()
        self.compression_free = compression_free_ratio(solver.compression_free, model)
        # The steps' projections on the fibre lengths (solvers.newton_fibres) and the level strains
        # (solvers.newton_levels; not with prescribed motion: 3-14-9-29 on the bias extension).
        fibres = FibreEdges(model) if solver.fibre_projection else None
        self.fibres = fibres if fibres else None
        use_levels = solver.level_projection and not (model.has_prescribed or model.interactions)
        levels = LevelStrains(model) if use_levels else None
        self.levels = levels if levels else None
        self.frames = [make_frame(model, self.state)]
        self.stream = None
        if solver.output is not None:
            # an arc-length path's load factor (its frames' time) falls past a limit point
            by_index = solver.path == "arc_length"
            self.stream = FrameStream(
                solver.output, model.mesh, model.has_rotation.copy(), by_index=by_index
            )
            self.stream.write(self.frames[0])
        self.strain_energies = [model.strain_energy(self.state)]  # one per frame, N mm
        self.dissipations = [model.dissipated_energy(self.state)]  # friction's, N mm
        self.progress = ProgressLine(resolve_progress(solver.progress), "static")
        self.negative: int | None = 0
        # Whether an exact tangent factorised by Newton in the current attempt had a negative
        # pivot (solvers/newton.py): with a stable start and end, the load step crossed an
        # unstable stretch of the path (``note_jump``).
        self.met_indefinite = False
        # The last converged state is a saddle that no push along its negative modes descends
        # from (solvers.saddles.judged): the next increment follows it by plain Newton.
        self.on_kept_saddle = False
        # The contact sets not predicted (solvers/newton.py): the retry of an increment whose
        # attempt with predicted sets failed.
        self.sets_unpredicted = False
        self.mode: Motion | None = None  # the next arc-length increment starts along it
        self.last_motion: tuple[int, float, Motion] | None = None  # (phase, lambda, motion)
        self.phase = 0
        self.counts = {"residual": 0, "energy": 0, "tangent": 0, "stability_tangents": 0}
        # (the state, K_ff) of the last exact tangent assembled, and (the state it was
        # assembled at or None, the factorisation) of the last one factorised (``factor_at``).
        self._assembled: tuple[State | None, Any] = (None, None)
        self._factorised: tuple[State | None, Factorisation | None] = (None, None)
        # The last exact tangent and where it was made (solvers.kept_tangent): the stability
        # tangent of a converged state is the next increment's first; and (K_ff, judged, its
        # factorisation) of the last factorisation made (``factorise``).
        self.kept = KeptTangent(model)
        self._made: tuple[Any, bool, Factorisation] | None = None
        # The viscous stabilisation (solvers.stabilisation): the masses once, the dashpots of
        # the increment being solved, and the energy they dissipated so far.
        self.dashpots: Dashpots | None = None
        self.masses = model.lumped_mass(self.state) if solver.stabilise > 0.0 else None
        self.dissipated = 0.0
        # The augmented contacts' report at the last converged state (None: no augmented
        # contact; solvers.augmentation.augment_contacts).
        self.constraint: dict | None = None
        self.info: dict[str, Any] = {
            "solver": "Static",
            "path": solver.path,
            "tangent": {
                "element": [type(model.parts[i]).__name__ for i in own],
                "finite_difference": [type(model.parts[i]).__name__ for i in others],
            },
            "load_factors": [],
            "iterations_per_increment": [],
            "cuts": 0,
            "iterations_cut": 0,
            "first_turn_cuts": [],
            "soft_start_iterations": 0,
            "tangent_colours": self._tangent.graph.n_colours if self._tangent.graph else 0,
            "residual_ratio_per_increment": [],
            "negative_eigenvalues": [],
            "indefinite_at": [],
            "limit_points": [],
            "jumps": [],
            "regularised_iterations": 0,
            "imposed_alone": 0,
            "imposed_alone_retries": 0,
            "imposed_alone_opened": 0,
            "shifted": [],
            "chord_corrections": 0,
            "arc_chords": 0,
            "curved_steps": 0,
            "fibre_projections": 0,
            "fibre_projection_sweeps": 0,
            "level_projections": 0,
            "level_projection_sweeps": 0,
            "compression_free": self.compression_free,
            "compression_free_tangents": 0,
            "mode_searches": 0,
            "tangents_reused": 0,
            "round_off_probes": 0,
            "round_off_converged": 0,
            "floor_accepted": [],  # (load factor, ratio) at the round-off floor above tol
            "contact_set_updates": 0,
            "contact_set_fallbacks": 0,
            "unpredicted_retries": 0,
            "augmentations": [],
            "augmented_penetration": [],
            "augmented_slip": [],
            "augmentations_short": [],
            "branch_switches": [],
            "saddles_kept": [],
            "escapes_failed": [],
            "residual_history": [],
            "evaluations": self.counts,
        }

    # ------------------------------------------------------------------ model evaluations
    def equilibrium(self, load_factor: float) -> Residual:
        force, moment, imposed = self.solver.loads(self.model, load_factor)
        return Residual(
            self.model, force, moment, imposed, self.counts, self.dashpots, self.reference_floor
        )

    def damp(self, load_factor: float | None) -> None:
        """Stabilised runs: the dashpots of the increment from the last converged state to
        ``load_factor`` (None: none, between increments)."""
        if self.masses is None or load_factor is None:
            self.dashpots = None
            return
        mass, inertia = self.masses
        self.dashpots = Dashpots(
            self.solver.stabilise,
            mass,
            inertia,
            self.model.has_rotation,
            self.state,
            load_factor - self.reached,
        )

    def report_augmentation(self) -> None:
        """A UserWarning when increments were accepted with an augmented contact's penetration
        or elastic slip above its tolerance (``augmentations`` passes did not bring them in)."""
        short = self.info["augmentations_short"]
        if not short:
            return
        worst = max(excess for _, excess in short)
        warnings.warn(
            f"{len(short)} increment(s) kept an augmented contact's penetration or elastic slip "
            f"above its tolerance after {self.solver.augmentations} Uzawa passes (up to "
            f"{worst:.3g} x the tolerance; info['augmentations_short']): raise augmentations "
            "or the penalty",
            UserWarning,
            stacklevel=outside_stacklevel(),
        )

    def note_jump(self, start: float, end: float) -> None:
        """Record and warn that the load step from ``start`` to ``end`` crossed an unstable
        stretch of the path: both ends stable, an iterate's tangent between them not
        (docs/theory.md §6.5, "Load control past a limit point"). ``info["jumps"]`` gets the
        load factor of the last state on the near branch, ``start``."""
        self.info["jumps"].append(start)
        message = (
            f"load control jumped between load factors {start:.4g} and {end:.4g}: both states "
            "are stable but the Newton iterates between them met a tangent with a negative "
            "eigenvalue, a limit point or bifurcation the load steps passed over (a "
            "snap-through); the path in between is not followed (info['jumps']; "
            "path='arc_length' follows it)"
        )
        self.progress(message, force=True)
        warnings.warn(message, UserWarning, stacklevel=outside_stacklevel())

    def pattern(self, phase: int):
        """(forces, moments, imposed displacements) per unit load factor in a phase."""
        upper = self.solver.loads(self.model, phase + 1.0)
        lower = self.solver.loads(self.model, float(phase))
        return tuple(a - b for a, b in zip(upper, lower))

    def energy(self, state: State) -> float:
        """The strain energy at ``state`` (with the dashpots' pseudo-potential in a stabilised
        increment), N mm; inf at a trial no element can be evaluated at (a vanished normal)."""
        self.counts["energy"] += 1
        try:
            energy = self.model.strain_energy(state)
        except ZeroDivisionError:
            return np.inf
        if self.dashpots is not None:
            energy += self.dashpots.energy(state)
        return energy

    def tangent(
        self,
        state: State,
        frames: Frames,
        compression_free: bool = False,
        real: State | None = None,
    ):
        """(K_ff, K_fp) at ``state``, the dashpots' diagonal added in a stabilised
        increment; ``compression_free``, ``real``: those of solvers.newton.Tangent. Counted
        in ``info["evaluations"]["tangent"]``; ``factor_at``'s in its "stability_tangents".
        The exact tangent last assembled is given again, not assembled, where it was made at
        this very configuration (solvers.kept_tangent; ``info["tangents_reused"]``)."""
        if not compression_free:
            kept = self.kept.at(state, frames, self.dashpots)
            if kept is not None:
                self.info["tangents_reused"] += 1
                self._assembled = (state, kept[0])
                return kept
        self.counts["tangent"] += 1
        return self._assemble(state, frames, compression_free, real)

    def _assemble(
        self,
        state: State,
        frames: Frames,
        compression_free: bool = False,
        real: State | None = None,
    ):
        k_ff, k_fp = self._tangent(state, frames, compression_free, real)
        if self.dashpots is not None:
            diagonal = self.dashpots.diagonal(self.model.dofs.free_slots)
            k_ff = (k_ff + sp.diags(diagonal, format="csc")).tocsc()
        # The exact tangent only is the state's own (``factor_at``).
        self._assembled = (None if compression_free else state, k_ff)
        if compression_free:
            self.kept.forget()
        else:
            self.kept.keep(state, frames, k_ff, k_fp, self.dashpots)
        return k_ff, k_fp

    def factorise(self, k_ff, judge: bool = True) -> Factorisation:
        """The factorisation of ``k_ff``; with ``judge`` its negative pivots within the
        tangent's round-off of zero counted as neutral, not negative (solvers.neutral_modes:
        a second factorisation, by a linear solver of its own, where K_ff has any). The
        very matrix factorised last (a kept tangent given again, solvers.kept_tangent) is not
        factorised again: its factorisation is the linear solver's last, still whole."""
        made = self._made
        if made is not None and made[0] is k_ff and made[1] == judge:
            factor = made[2]
        else:
            factor = self.linear.factorise(k_ff)
            if judge:
                factor = judge_pivots(self.neutral_linear, k_ff, factor)
            self._made = (k_ff, judge, factor)
        state, assembled = self._assembled
        self._factorised = (state if k_ff is assembled else None, factor)
        return factor

    def factor_at(self, state: State, factor: Factorisation | None = None) -> Factorisation:
        """The factorisation of the exact tangent K_ff at ``state``: ``factor`` when it is the
        last one made and was made there, else a new one (an assembly and a factorisation).

        Newton converges one update after its last factorisation, so the tangent last
        factorised on the way to a converged state is an iterate's before it: its inertia is
        not the state's. A dead load past the Euler load of a strip that stays straight
        converges in one update from the straight state of the increment before, whose
        tangent has no negative pivot, and the count read there stayed 0 at every increment
        (docs/theory.md §6.5, "The stability of a converged state")."""
        made_at, last = self._factorised
        if factor is not None and factor is last and made_at is state:
            return factor
        self.counts["stability_tangents"] += 1
        frames = self.model.dofs.frames(state.directors)
        return self.factorise(self._assemble(state, frames)[0])

    @property
    def last_factorisation(self) -> Factorisation | None:
        """The last factorisation made (``factor_at`` reuses it where it was made at the
        state asked for)."""
        return self._factorised[1]

    # ------------------------------------------------------------------ configurations
    def place(self, state: State, load_factor: float) -> State:
        """The state with its prescribed translations at their values for ``load_factor``, and
        that load factor (where the tools' prescribed motions place them)."""
        model = self.model
        state = replace(state, load_factor=load_factor, time=load_factor)
        if not model.has_prescribed:
            return state
        target = model.reference_positions + self.solver.loads(model, load_factor)[2]
        positions = np.where(model.translation_prescribed, target, state.positions)
        return replace(state, positions=positions)

    def apply(self, motion: Motion, load_factor: float) -> State:
        """The last converged state moved by ``motion``, placed at ``load_factor``."""
        model, state = self.model, self.state
        directors = state.directors
        if model.dofs.any_rotation:
            turned = rotate_about(directors, motion.rotations)
            directors = np.where(model.has_rotation[:, None], turned, directors)
        moved = replace(state, positions=state.positions + motion.translations, directors=directors)
        return self.place(moved, load_factor)

    def motion_between(self, old: State, old_load, new: State, new_load) -> Motion:
        """The motion from one state to another: translations and the rotation vectors that
        take each old director to the new one about their common normal."""
        axis = cross(old.directors, new.directors)
        sine = np.linalg.norm(axis, axis=1)
        cosine = np.sum(old.directors * new.directors, axis=1)
        angle = np.arctan2(sine, cosine)
        rotations = (
            axis * np.where(sine > 0.0, angle / np.where(sine > 0.0, sine, 1.0), 0.0)[:, None]
        )
        rotations[~self.model.has_rotation] = 0.0
        return Motion(
            new.positions - old.positions,
            rotations,
            new_load - old_load,
            self.model.element_size,
        )

    def scaled_motion(self, delta: np.ndarray, frames: Frames) -> np.ndarray:
        """The scaled-norm vector (Motion.vector) of a generalised increment delta (n, 5)."""
        return self.as_motion(delta, frames, 0.0).vector

    def as_motion(self, delta: np.ndarray, frames: Frames, load: float, mode=False) -> Motion:
        rotations = np.zeros((self.model.n_nodes, 3))
        if frames is not None:
            v1, v2 = frames
            rotations = delta[:, 3:4] * v2 + delta[:, 4:5] * v1
            rotations[~self.model.has_rotation] = 0.0
        return Motion(delta[:, :3].copy(), rotations, load, self.model.element_size, mode)

    def predict(self, load_factor: float, follow: bool = False) -> State:
        """Load path: the start of the Newton iteration at ``load_factor``: the last
        increment of the same phase extrapolated (the secant), else the last state (with
        the tools followed under ``follow_tools``, or when ``follow``)."""
        if (
            not self.solver.predictor
            or self.last_motion is None
            or self.last_motion[0] != self.phase
        ):
            return self.follow_tools(self.state, load_factor, follow)
        motion = self.last_motion[2]
        if motion.load <= 0.0:
            return self.follow_tools(self.state, load_factor, follow)
        return self.apply(motion.scaled((load_factor - self.reached) / motion.load), load_factor)

    def follow_tools(self, state: State, load_factor: float, follow: bool = False) -> State:
        """With ``follow_tools`` (or ``follow``): the nodes touching a moving tool at the last
        converged state (and no tool that stays) carried by the tool's translation to
        ``load_factor`` (``InteractionBlock.carried_by_tool``), so that the increment's first
        iterate does not have the tool inside the body by the whole of its step."""
        if not (self.solver.follow_tools or follow):
            return state
        model = self.model
        shift = np.zeros((model.n_nodes, 3))
        held = np.zeros(model.n_nodes, dtype=bool)
        carried = np.zeros(model.n_nodes, dtype=bool)
        for i, part in enumerate(model.interactions, start=len(model.blocks)):
            found = part.carried_by_tool(state, state.history[i], self.reached, load_factor)
            if found is None:
                continue
            nodes, moves = found
            moving = np.abs(moves).max(axis=1, initial=0.0) > 0.0
            shift[nodes[moving]] = moves[moving]
            carried[nodes[moving]] = True
            held[nodes[~moving]] = True  # a node on a tool that stays (a die) is not carried
        carried &= ~held & ~model.translation_prescribed.any(axis=1)
        if not carried.any():
            return state
        positions = state.positions + np.where(carried[:, None], shift, 0.0)
        return replace(state, positions=positions)

    def load_rate(self, pattern, frames: Frames, k_fp) -> tuple[np.ndarray, np.ndarray]:
        """P = dR/dlambda on the free DOFs, F_pattern - K_fp U_pattern, and the prescribed
        motion per unit load factor U_pattern as a flat generalised vector (n_slots,)."""
        model, dofs = self.model, self.model.dofs
        rate = np.zeros((model.n_nodes, N_COLUMNS))
        rate[:, :3] = np.where(model.translation_prescribed, pattern[2], 0.0)
        drive = dofs.generalised(frames, pattern[0], pattern[1]).ravel()[dofs.free_slots]
        if dofs.prescribed_slots.size:
            drive = drive - k_fp @ rate.ravel()[dofs.prescribed_slots]
        return drive, rate.ravel()

    # ------------------------------------------------------------------ bookkeeping
    def refuse_inverted(self, state: State) -> None:
        """Raise IncrementFailed (the increment is cut) where a converged ``state`` has cells
        turned inside out (``CompiledModel.inverted_cells``): an equilibrium of the discrete
        energy that no material reaches. A clamped strip of 20 x 1 Mindlin elements shortened by
        20 mm in 10 increments was returned with elements 10-13 run backwards over each
        other, their directors 180 deg from their normals, the tip 36.86 mm off the axis
        against the elastica's 53.26 (docs/theory.md §6.5, "The stability of a converged
        state")."""
        inverted = self.model.inverted_cells(state)
        if inverted.size:
            shown = ", ".join(str(cell) for cell in inverted[:10])
            more = f" and {inverted.size - 10} more" if inverted.size > 10 else ""
            raise TurnedInsideOut(
                f"converged with cells turned inside out (a director at or past 90 deg from "
                f"its cell's normal): cells {shown}{more}"
            )

    def settled(self, state: State, factor: Factorisation | None) -> State:
        """A converged state: refused where it has cells turned inside out
        (``refuse_inverted``); note the inertia of the tangent at ``state`` (``factor`` when it
        was factorised there, ``factor_at``; the class docstring's Stability)."""
        self.refuse_inverted(state)
        self.negative = self.factor_at(state, factor).negative
        self.on_kept_saddle = False
        return state

    def accept(self, state: State, load_factor: float, iterations: int = 0) -> None:
        """Take ``state``, converged at ``load_factor`` in ``iterations`` Newton iterations,
        as the last converged state (its frame is kept by ``frame`` at the end of the
        increment, or by ``failure`` when the increment stops part way)."""
        self.unframed_iterations += iterations
        if self.dashpots is not None:
            self.dissipated += self.dashpots.dissipated(state)
        motion = self.motion_between(self.state, self.reached, state, load_factor)
        self.last_motion = (self.phase, load_factor, motion)
        self.reached = load_factor
        self.balanced = replace(state, load_factor=load_factor, time=load_factor)
        self.state = self.model.commit(self.balanced)

    def frame(self, iterations: int, ratio: float, history: list[float]) -> None:
        info, model = self.info, self.model
        info["load_factors"].append(self.reached)
        info["iterations_per_increment"].append(iterations)
        info["residual_ratio_per_increment"].append(ratio)
        info["residual_history"].append(history)
        info["negative_eigenvalues"].append(self.negative)
        if self.negative:
            info["indefinite_at"].append(self.reached)
            self.progress(
                f"load factor {self.reached:.4g}: the tangent stiffness has {self.negative} "
                "negative eigenvalue(s): an unstable equilibrium, past a limit point or a "
                "bifurcation",
                force=True,
            )
        self.unframed_iterations = 0
        frame = self.reached_frame()
        if model.user_amplitudes():
            f_ext, m_ext, _ = self.solver.loads(model, self.reached)
            self.reference_floor = max(
                1e-300,
                self.round_off,
                unloaded_floor(model, f_ext, m_ext, frame.reactions, frame.reaction_moments),
            )
        self.keep(frame)
        self.progress(
            f"increment {len(self.frames) - 1}: load factor {self.reached:.4g} converged in "
            f"{iterations} Newton iterations",
            fraction=self.reached / (2.0 if self.solver.step_loads_first else 1.0),
        )
        if STOP.signal is not None:  # SIGINT or SIGTERM inside interruptible()
            raise Interrupted(
                f"static solver interrupted by {STOP.signal} at load factor "
                f"{self.reached:.6g}: the {len(self.frames) - 1} converged increment(s) are "
                "kept (a static run has no checkpoint: run it again to go on)",
                self.result(False),
                STOP.signal,
            )

    def reached_frame(self):
        """A frame of the last converged state, at ``reached``, with its support reactions.

        The reactions are those of the state Newton balanced, not of the committed one: the
        commit moves a sliding ply point's anchor to the friction limit, where rounding may
        count it stuck and its stick potential adds a normal force (and a couple) that no
        iterate balanced (docs/theory.md §6.5, "Reactions of a frictional increment"). The
        positions and directors are the same; the fields and energies keep the committed
        history."""
        model = self.model
        f_ext, m_ext, _ = self.solver.loads(model, self.reached)
        reactions, reaction_moments = equilibrium_reactions(model, self.balanced, f_ext, m_ext)
        return make_frame(model, self.state, reactions, reaction_moments, self.balanced)

    def keep(self, frame) -> None:
        """Keep a frame of the last converged state (and write it, with ``output``)."""
        self.frames.append(frame)
        self.strain_energies.append(self.model.strain_energy(self.state))
        self.dissipations.append(self.model.dissipated_energy(self.state))
        if self.stream is not None:
            self.stream.write(frame)

    def cut(self, cuts: int, what: str, failure: Exception, aim: float | None = None) -> int:
        """Count one more cut of an increment (``cuts`` so far), or raise the ConvergenceError
        of ``failure`` when that makes more than the solver's max_cuts; ``aim``: the load
        factor the increment aimed at, where the stop may be the rounding's (``failure``)."""
        self.info["cuts"] += 1
        if cuts + 1 > self.solver.max_cuts:
            reason = f"{what} did not converge after {cuts} cuts ({failure})"
            # (only an attempt that used its max_iterations: a line search that found no
            # step stops a short attempt whose ratio was falling too)
            history = getattr(failure, "history", [])  # (the start's ratio, then the updates')
            capped = len(history) >= self.solver.max_iterations and still_falling(history)
            raise self.failure(reason, aim, capped) from None
        return cuts + 1

    def failure(
        self, reason: str, aim: float | None = None, capped: bool = False
    ) -> ConvergenceError:
        """The ConvergenceError of a stop for ``reason``, with its cause where one is known:
        ``capped``, the last attempt ran out of iterations with its residual ratio still
        falling (``still_falling``): the cap max_iterations, said first, not a limit point; at
        ``aim`` (the load factor the failed increment aimed at) the rounding of the internal
        forces above what the solver can take for it (solvers.round_off ``rounding_stop``:
        models without interactions or dashpots, as its floor), else ``stop_hint``'s."""
        hint = ""
        if capped:
            # (the reason names max_iterations: no limit-point hint after it to mislead)
            hint = (
                ". The iteration cap stopped it, not a limit point or buckling (those stall "
                "the ratio)"
            )
        if not hint and aim is not None and not self.model.interactions and self.dashpots is None:
            # Judged at the load the user applied (load factor 1), not at the cut increment's
            # (1e-4 N a node cut 8 times is 3.9e-7 N: a stop for another cause, the rounding
            # of the cuts' loads, read as the user's load being too small).
            frames = self.model.dofs.frames(self.balanced.directors)
            hint = rounding_stop(self.equilibrium(max(aim, 1.0)), self.balanced, frames)
        if not hint:
            hint = neutral_hint(self.last_factorisation, self.neutral_linear) or stop_hint(
                self.model,
                self.state.positions,
                self.solver.path,
                at_start=len(self.frames) <= 1,
                step_loads_first=self.solver.step_loads_first,
            )
        error = ConvergenceError(
            f"static solver stopped at load factor {self.reached:.6g}: {reason}{hint}.", None
        )
        if self.reached > self.frames[-1].load_factor:
            # The last good state, part way through an increment (a cut's converged
            # sub-increments), with the reactions that hold it like any other frame's.
            self.keep(self.reached_frame())
        error.result = self.result(False)
        error.load_factor = self.reached
        return error

    def result(self, converged: bool) -> Result:
        result = empty_result(self.model, self.frames)
        # The Newton iterations of every converged step: the framed increments' and those of
        # an increment's converged sub-increments before a stop (the failed attempts'
        # are info["iterations_cut"]).
        result.steps = int(sum(self.info["iterations_per_increment"]) + self.unframed_iterations)
        result.wall_time = time.perf_counter() - self.started
        result.converged = converged
        result.energies = {
            "time": np.array([frame.time for frame in self.frames]),
            "internal": np.array(self.strain_energies),
            "friction": np.array(self.dissipations),
        }
        self.info["linear_solver"] = {
            "symbolic_factorisations": self.linear.symbolic,
            "numeric_factorisations": self.linear.numeric,
            # the shifted tangents that told neutral pivots from negative ones
            "neutral_factorisations": self.neutral_linear.numeric,
        }
        report_floor_acceptances(self.info, self.solver.tol)  # once per solve
        result.info = dict(self.info, tol=self.solver.tol)
        record_tool_penetration(self.model, result, "Static", converged)
        return result
