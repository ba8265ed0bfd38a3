"""Static: Newton-Raphson on the free DOFs with a sparse finite-difference tangent.

Loads and prescribed displacements are applied in ``increments`` equal load-factor steps, all of
them (gravity and "step" loads included) ramped linearly with the load factor, as a static step
does: amplitudes shape time histories in dynamics only, and an increment that has to be cut can
then always be made smaller. Each increment is solved by Newton-Raphson and gives one frame; an
increment that does not converge is cut in half and retried from the last converged state.

Unknowns per node: ux uy uz and, at shell nodes, alpha beta: small rotations of the director
about V2 and V1 of its nodal frame (Bai Eq. 7, 13; THEORY §1.3), applied as finite rotations.

Tangent: any element that has ``internal_force`` works. The stiffness K = dF_int/dq is built by
central differences with a colouring of the node graph: nodes more than four cell-hops apart
share no cell and no bending patch (a rotation-free bending force at a node depends on nodes at
most two hops away), so all nodes of one colour are perturbed together, and each perturbation
gives the columns of all of them. The cost is 10 x (number of colours) force evaluations,
independent of the mesh size.
"""

from __future__ import annotations

import time
import warnings

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import MatrixRankWarning, splu

from femcore.model import CompiledModel, Model
from femcore.rotation import nodal_frames, rotate_about
from solvers.common import (
    ConvergenceError,
    ProgressLine,
    check_integer,
    check_tolerance,
    empty_result,
    make_frame,
    resolve_progress,
)

__all__ = ["Static", "finite_difference_tangent"]


class _Graph:
    """Node colouring and the sparsity pattern (node pairs within two hops) of a model."""

    def __init__(self, model: CompiledModel):
        n = model.n_nodes
        rows, cols = [], []
        for block in model.blocks:
            cells = block.connectivity
            k = cells.shape[1]
            rows.append(np.repeat(cells, k, axis=1).ravel())
            cols.append(np.tile(cells, (1, k)).ravel())
        rows, cols = np.concatenate(rows), np.concatenate(cols)
        adjacency = sp.csr_matrix((np.ones(rows.size), (rows, cols)), shape=(n, n))
        adjacency = (adjacency + sp.identity(n, format="csr")).astype(bool).astype(float)
        pattern = (adjacency @ adjacency).astype(bool).tocsr()  # within 2 hops
        conflict = (pattern.astype(float) @ pattern.astype(float)).tocsr()  # within 4 hops
        colour = np.full(n, -1)
        indptr, indices = conflict.indptr, conflict.indices
        for node in range(n):  # greedy colouring, once per model
            taken = set(colour[indices[indptr[node] : indptr[node + 1]]].tolist())
            c = 0
            while c in taken:
                c += 1
            colour[node] = c
        self.colour = colour
        self.n_colours = int(colour.max()) + 1
        coo = pattern.tocoo()
        self.groups = []
        for c in range(self.n_colours):
            members = colour[coo.col] == c
            self.groups.append((np.flatnonzero(colour == c), coo.row[members], coo.col[members]))


def _unknowns(model: CompiledModel) -> np.ndarray:
    """(n, 5) bool: the free unknowns (ux uy uz alpha beta)."""
    rotation_free = model.has_rotation[:, None] & ~model.rotation_fixed
    return np.column_stack([model.translation_free, rotation_free])


def _frames(model: CompiledModel, directors: np.ndarray):
    """Nodal frames (V1, V2), (n, 3) each, of the directors (Bai Eq. 7 with its fallback).

    A Newton iteration keeps one set of frames for its residual, tangent and update: near the
    fallback of Eq. 7 a frame may switch between two nearby states, and mixing frames would
    make the tangent inconsistent with the residual."""
    if not model.has_rotation.any():
        return None
    return nodal_frames(np.where(model.has_rotation[:, None], directors, [0, 0, 1.0]))


def _generalised(model: CompiledModel, frames, force, moment) -> np.ndarray:
    """(n, 5): forces and the moment components conjugate to alpha (about V2) and beta (V1)."""
    out = np.zeros((model.n_nodes, 5))
    out[:, :3] = force
    if frames is not None:
        v1, v2 = frames
        out[:, 3] = np.sum(moment * v2, axis=1)
        out[:, 4] = np.sum(moment * v1, axis=1)
        out[~model.has_rotation, 3:] = 0.0
    return out


def _apply(model: CompiledModel, state, increment: np.ndarray, frames) -> None:
    """Add an (n, 5) increment: translations, and rotations of the directors about V2 (alpha)
    and V1 (beta) of the given frames."""
    state.positions = state.positions + increment[:, :3]
    if frames is not None:
        v1, v2 = frames
        psi = increment[:, 3:4] * v2 + increment[:, 4:5] * v1
        rot = model.has_rotation
        state.directors = np.where(
            rot[:, None], rotate_about(state.directors, psi), state.directors
        )


def finite_difference_tangent(
    model: CompiledModel,
    state,
    graph: _Graph | None = None,
    step: float | None = None,
    external=None,
) -> sp.csr_matrix:
    """Sparse K = d(F_int - F_ext)/dq (5n x 5n) at ``state`` by coloured central differences.

    external : (forces (n,3), moments (n,3)) of the dead loads, or None. Dead moments still
    change their alpha/beta components when the director frame turns (a load stiffness).

    step : perturbation of the translations (length unit; default 1e-6 x the median element
    edge); rotations are perturbed by 1e-6 rad.
    """
    graph = graph or _Graph(model)
    n = model.n_nodes
    h_x = step if step is not None else 1e-6 * model.element_size
    h_r = 1e-6
    rows, cols, values = [], [], []
    has_rot = model.has_rotation.any()
    f_ext, m_ext = external if external is not None else (0.0, 0.0)
    frames = _frames(model, state.directors)

    def generalised(s):
        f_int, m_int = model.internal_force(s)
        return _generalised(model, frames, f_int - f_ext, m_int - m_ext)

    for nodes, entry_rows, entry_cols in graph.groups:
        for component in range(5 if has_rot else 3):
            h = h_x if component < 3 else h_r
            delta = np.zeros((n, 5))
            delta[nodes, component] = h
            plus, minus = state.copy(), state.copy()
            _apply(model, plus, delta, frames)
            _apply(model, minus, -delta, frames)
            df = (generalised(plus) - generalised(minus)) / (2 * h)
            for a in range(5 if has_rot else 3):
                rows.append(5 * entry_rows + a)
                cols.append(5 * entry_cols + component)
                values.append(df[entry_rows, a])
    return sp.csr_matrix(
        (np.concatenate(values), (np.concatenate(rows), np.concatenate(cols))),
        shape=(5 * n, 5 * n),
    )


class Static:
    """Quasi-static solver: Newton-Raphson with a sparse finite-difference tangent.

    increments : number of equal load-factor steps (one frame each).
    tol : convergence when ||r_forces|| <= tol F_ref and ||r_moments|| <= tol F_ref L_e (or,
        at the round-off floor, when a full Newton step moves no DOF by more than 1e-9 of an
        element or 1e-9 rad while the ratio is below 1e-3), with
        F_ref = max(||F_ext||, ||F_int||, ||M_ext|| / L_e, ||M_int|| / L_e) (the internal
        forces include the reactions) and L_e the median element edge.
    max_iterations : Newton iterations per (sub-)increment before it is cut in half.
    line_search : backtrack (halve the update, up to 5 times) while the residual ratio of the
        trial exceeds 10 x the current one.
    max_cuts : how many times an increment may be halved before a ConvergenceError.
    progress : print status lines (None: only on an interactive terminal).
    """

    def __init__(
        self,
        increments: int = 10,
        tol: float = 1e-8,
        max_iterations: int = 50,
        line_search: bool = True,
        max_cuts: int = 8,
        progress: bool | None = None,
    ):
        self.increments = check_integer(increments, "increments")
        self.tol = check_tolerance(tol)
        self.max_iterations = check_integer(max_iterations, "max_iterations")
        self.line_search = bool(line_search)
        self.max_cuts = check_integer(max_cuts, "max_cuts", minimum=0)
        self.progress = progress

    def solve(self, model: Model | CompiledModel):
        """Solve every increment; returns a femcore.results.Result with the reference state
        and one frame per increment (``time`` = load factor). Raises ConvergenceError, with
        the converged frames in ``error.result``, when an increment cannot be completed."""
        compiled = model.compile() if isinstance(model, Model) else model
        started = time.perf_counter()
        graph = _Graph(compiled)
        state = compiled.initial_state()
        frames = [make_frame(compiled, state)]
        progress = ProgressLine(resolve_progress(self.progress), "static")
        info = {
            "solver": "Static",
            "iterations_per_increment": [],
            "cuts": 0,
            "tangent_colours": graph.n_colours,
            "residual_ratio_per_increment": [],
        }
        step = 1.0 / self.increments
        reached = 0.0
        for increment in range(1, self.increments + 1):
            target = increment / self.increments
            iterations = 0
            cuts_here = 0
            while reached < target - 1e-12:
                trial = min(target, reached + step)
                saved = state.copy()
                try:
                    count, ratio = self._newton(compiled, graph, state, trial, progress)
                except _Failed as failure:
                    state = saved
                    cuts_here += 1
                    info["cuts"] += 1
                    if cuts_here > self.max_cuts:
                        error = ConvergenceError(
                            f"static solver stopped at load factor {reached:.6g}: increment "
                            f"{increment}/{self.increments} did not converge after {cuts_here - 1}"
                            f" cuts ({failure}). A limit point or buckling may be near: try "
                            "DynamicRelaxation or CentralDifference for this path.",
                            None,
                        )
                        error.result = self._result(compiled, frames, info, started, False)
                        raise error from None
                    step = 0.5 * (trial - reached)
                    continue
                iterations += count
                reached = trial
                state.load_factor = state.time = reached
                # After a cut, grow the step back towards the nominal one.
                step = min(1.0 / self.increments, 2.0 * step)
            info["iterations_per_increment"].append(iterations)
            info["residual_ratio_per_increment"].append(ratio)
            reactions, reaction_moments = self._reactions(compiled, state, reached)
            frames.append(make_frame(compiled, state, reactions, reaction_moments))
            progress(
                f"increment {increment}/{self.increments} converged in {iterations} "
                "Newton iterations",
                force=True,
            )
        return self._result(compiled, frames, info, started, True)

    # ------------------------------------------------------------------ one increment
    def _newton(self, model, graph, state, load_factor, progress) -> tuple[int, float]:
        free = _unknowns(model)
        f_ext, m_ext = (load_factor * a for a in model.external_load(1.0, quasi_static=True))
        if model.has_prescribed:
            target = model.reference_positions + load_factor * model.prescribed_displacement(
                1.0, quasi_static=True
            )
            state.positions = np.where(model.translation_prescribed, target, state.positions)

        def residual(s, frames):
            f_int, m_int = model.internal_force(s)
            r = np.where(free, _generalised(model, frames, f_ext - f_int, m_ext - m_int), 0.0)
            # One scale for both: a moment M counts as the force M / (element size), so that a
            # pure-moment load (zero forces at equilibrium) has a force reference too.
            size = model.element_size
            force_ref = max(
                np.linalg.norm(f_ext),
                np.linalg.norm(f_int),
                np.linalg.norm(m_ext) / size,
                np.linalg.norm(m_int) / size,
                1e-300,
            )
            moment_ref = force_ref * size
            ratio = max(np.linalg.norm(r[:, :3]) / force_ref, np.linalg.norm(r[:, 3:]) / moment_ref)
            return r, ratio

        r, ratio = residual(state, _frames(model, state.directors))
        index = np.flatnonzero(free.ravel())
        for iteration in range(1, self.max_iterations + 1):
            frames = _frames(model, state.directors)
            if iteration > 1:  # the same residual, in this iteration's frames
                r, ratio = residual(state, frames)
            if not np.isfinite(ratio):
                raise _Failed("non-finite residual")
            if ratio <= self.tol:
                return iteration - 1, ratio
            tangent = finite_difference_tangent(model, state, graph, external=(f_ext, m_ext))
            k_ff = tangent[index][:, index].tocsc()
            with warnings.catch_warnings():
                warnings.simplefilter("error", MatrixRankWarning)
                try:
                    delta_free = splu(k_ff).solve(r.ravel()[index])
                except (RuntimeError, MatrixRankWarning) as err:
                    raise _Failed(
                        f"singular tangent stiffness ({err}): a mechanism, an "
                        "unconstrained rigid motion or a bifurcation"
                    ) from None
            delta = np.zeros(free.size)
            delta[index] = delta_free
            delta = delta.reshape(-1, 5)
            # Backtracking: the full Newton step of a large rotation first moves along the
            # tangent and stretches the structure, so a growing residual is normal for one
            # iteration; only a blow-up (or a non-finite state) is cut back.
            scale = 1.0
            for _ in range(6 if self.line_search else 1):
                trial = state.copy()
                _apply(model, trial, scale * delta, frames)
                r_new, ratio_new = residual(trial, frames)
                if not self.line_search or (
                    np.isfinite(ratio_new) and ratio_new <= 10.0 * max(ratio, self.tol)
                ):
                    break
                scale *= 0.5
            state.positions, state.directors = trial.positions, trial.directors
            r, ratio = r_new, ratio_new
            # Round-off floor: the internal forces come from differences of nearly equal
            # metrics, so a tiny load on a stiff shell can leave a residual of ~1e-4 of the
            # load that no update removes. A full step that moves nothing (1e-9 of an element,
            # 1e-9 rad) with the residual already small is converged.
            moved = scale * np.abs(delta)
            if (
                scale == 1.0
                and ratio <= 1e-3
                and moved[:, :3].max() <= 1e-9 * model.element_size
                and moved[:, 3:].max(initial=0.0) <= 1e-9
            ):
                return iteration, ratio
            progress(
                f"load factor {load_factor:.4g}: iteration {iteration}, residual ratio "
                f"{ratio:.3g} (tol {self.tol:g})"
            )
        if ratio <= self.tol:
            return self.max_iterations, ratio
        raise _Failed(f"residual ratio {ratio:.3g} after {self.max_iterations} iterations")

    @staticmethod
    def _reactions(model, state, load_factor):
        f_ext, m_ext = (load_factor * a for a in model.external_load(1.0, quasi_static=True))
        f_int, m_int = model.internal_force(state)
        reactions = np.where(model.translation_constrained, f_int - f_ext, 0.0)
        reaction_moments = np.where(
            model.has_rotation[:, None] & model.rotation_fixed.any(1)[:, None], m_int - m_ext, 0.0
        )
        return reactions, reaction_moments

    def _result(self, compiled, frames, info, started, converged):
        result = empty_result(compiled, frames)
        result.steps = int(sum(info["iterations_per_increment"]))
        result.wall_time = time.perf_counter() - started
        result.converged = converged
        result.info = dict(info, tol=self.tol)
        return result


class _Failed(Exception):
    """An increment that did not converge (caught to cut the increment)."""
