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
from scipy.sparse.linalg import ArpackNoConvergence, MatrixRankWarning, eigsh, splu

from elements.base import ElementBlock
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

__all__ = ["Static", "element_tangent", "finite_difference_tangent"]


class _Graph:
    """Node colouring and the sparsity pattern of the finite-difference tangent of ``blocks``.

    The force at a node depends on nodes at most ``reach`` cell-hops away (the largest reach
    of the blocks: 1 for cell-local elements, 2 for rotation-free bending patches), so the
    column of node j has entries within ``reach`` hops, and nodes more than 2 x reach hops
    apart never share a row: they get the same colour and are perturbed together.
    """

    def __init__(self, model: CompiledModel, blocks=None):
        blocks = model.blocks if blocks is None else blocks
        n = model.n_nodes
        reach = max((getattr(block, "reach", 2) for block in blocks), default=1)
        rows, cols = [np.arange(n)], [np.arange(n)]
        for block in blocks:
            cells = block.connectivity
            k = cells.shape[1]
            rows.append(np.repeat(cells, k, axis=1).ravel())
            cols.append(np.tile(cells, (1, k)).ravel())
        rows, cols = np.concatenate(rows), np.concatenate(cols)
        adjacency = sp.csr_matrix((np.ones(rows.size), (rows, cols)), shape=(n, n))
        adjacency = adjacency.astype(bool).astype(float)
        pattern = adjacency
        for _ in range(reach - 1):
            pattern = (pattern @ adjacency).astype(bool).astype(float)
        pattern = pattern.tocsr()
        conflict = (pattern @ pattern).tocsr()  # within 2 x reach hops
        colour = np.full(n, -1)
        indptr, indices = conflict.indptr, conflict.indices
        for node in range(n):  # greedy colouring, once per model
            taken = set(colour[indices[indptr[node] : indptr[node + 1]]].tolist())
            c = 0
            while c in taken:
                c += 1
            colour[node] = c
        self.colour = colour
        self.n_colours = int(colour.max()) + 1 if n else 0
        coo = pattern.tocoo()
        self.groups = []
        for c in range(self.n_colours):
            members = colour[coo.col] == c
            self.groups.append((np.flatnonzero(colour == c), coo.row[members], coo.col[members]))


def _unknowns(model: CompiledModel) -> np.ndarray:
    """(n, 5) bool: the free unknowns (ux uy uz alpha beta)."""
    rotation_free = model.has_rotation[:, None] & ~model.rotation_fixed
    return np.column_stack([model.translation_free, rotation_free])


def _prescribed(model: CompiledModel) -> np.ndarray:
    """(n, 5) bool: the unknowns with a prescribed value (translations only)."""
    out = np.zeros((model.n_nodes, 5), dtype=bool)
    if model.has_prescribed:
        out[:, :3] = model.translation_prescribed
    return out


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


def _has_own_tangent(block) -> bool:
    return type(block).tangent is not ElementBlock.tangent


def _block_force(blocks, n_nodes: int, state) -> tuple[np.ndarray, np.ndarray]:
    """Internal forces and moments (n, 3) of some of the model's blocks."""
    force = np.zeros((n_nodes, 3))
    moment = np.zeros((n_nodes, 3))
    for block in blocks:
        f, m = block.internal_force(state)
        force += f
        if m is not None:
            moment += m
    return force, moment


def finite_difference_tangent(
    model: CompiledModel,
    state,
    graph: _Graph | None = None,
    step: float | None = None,
    blocks=None,
) -> sp.csr_matrix:
    """Sparse K = dF_int/dq (5n x 5n) of ``blocks`` (default: all) at ``state`` by coloured
    central differences, q = (ux, uy, uz, alpha, beta) per node.

    The loads are dead (fixed in global directions) and the frames are those of the current
    directors, held during the iteration, so the external loads add nothing to K.

    step : perturbation of the translations (length unit; default 1e-6 x the median element
    edge); rotations are perturbed by 1e-6 rad.
    """
    blocks = model.blocks if blocks is None else blocks
    graph = graph or _Graph(model, blocks)
    n = model.n_nodes
    h_x = step if step is not None else 1e-6 * model.element_size
    h_r = 1e-6
    rows, cols, values = [], [], []
    has_rot = model.has_rotation.any()
    frames = _frames(model, state.directors)

    def generalised(s):
        return _generalised(model, frames, *_block_force(blocks, n, s))

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
    if not rows:
        return sp.csr_matrix((5 * n, 5 * n))
    return sp.csr_matrix(
        (np.concatenate(values), (np.concatenate(rows), np.concatenate(cols))),
        shape=(5 * n, 5 * n),
    )


def _generalised_blocks(part, maps: np.ndarray) -> np.ndarray:
    """(m, p, c_q, p, c_q) blocks in q = (ux, uy, uz, alpha, beta) of a CellTangent."""
    nodes, k = part.nodes, part.blocks
    if k.shape[2] == 3:
        return k
    t = maps[nodes]  # (m, p, 6, 5)
    m, p = nodes.shape
    # K T on the right, then T^T on the left, with batched matmuls (einsum is slow here).
    right = np.matmul(k[:, :, :, :, None, :], t[:, None, None])  # (m, p, 6, p, 1, 5)
    right = right.reshape(m, p, 6, p * 5)
    left = np.matmul(np.swapaxes(t, -1, -2), right)  # (m, p, 5, 6) @ (m, p, 6, p*5)
    return left.reshape(m, p, 5, p, 5)


def element_tangent(model: CompiledModel, state, frames, blocks=None) -> sp.csr_matrix:
    """Sparse K (5n x 5n) of the blocks' own ``tangent`` (default: every block that has one).

    The element blocks are in (u, psi) per node, psi a rotation vector of the director in
    global components; with psi = alpha V2 + beta V1 (the frames of the iteration) each node's
    6 x 5 map T = [[I, 0], [0, (V2 V1)]] gives K_q = T^T K T."""
    blocks = [b for b in model.blocks if _has_own_tangent(b)] if blocks is None else blocks
    n = model.n_nodes
    rows, cols, values = [], [], []
    maps = _maps(n, frames)
    for part in _parts(blocks, state):
        kq = _generalised_blocks(part, maps)
        r, c = _entry_indices(part.nodes, kq.shape[2])
        rows.append(r)
        cols.append(c)
        values.append(kq.ravel())
    if not rows:
        return sp.csr_matrix((5 * n, 5 * n))
    return sp.csr_matrix(
        (np.concatenate(values), (np.concatenate(rows), np.concatenate(cols))),
        shape=(5 * n, 5 * n),
    )


def _parts(blocks, state):
    return [part for block in blocks for part in block.tangent(state)]


def _maps(n: int, frames) -> np.ndarray:
    """(n, 6, 5): per node, (u, psi) = T q with psi = alpha V2 + beta V1."""
    maps = np.zeros((n, 6, 5))
    maps[:, :3, :3] = np.eye(3)
    if frames is not None:
        v1, v2 = frames
        maps[:, 3:, 3] = v2
        maps[:, 3:, 4] = v1
    return maps


def _entry_indices(nodes: np.ndarray, cq: int) -> tuple[np.ndarray, np.ndarray]:
    """Global row and column of every entry of (m, p, c_q, p, c_q) blocks."""
    index = 5 * nodes[:, :, None] + np.arange(cq)  # (m, p, c_q)
    shape = index.shape + index.shape[1:]
    rows = np.broadcast_to(index[:, :, :, None, None], shape).ravel()
    cols = np.broadcast_to(index[:, None, None, :, :], shape).ravel()
    return rows, cols


class _FreeAssembler:
    """Sums element tangent blocks straight into K_ff (free x free, CSC) and K_fp (free x
    prescribed, CSR): the entry pattern is the same at every iteration, so the map from the
    block entries to the sparse storage is built once and each assembly is one bincount."""

    def __init__(self, model: CompiledModel, blocks, state, free_index, moved_index):
        self.model, self.blocks = model, blocks
        size = 5 * model.n_nodes
        position = np.full(size, -1)
        position[free_index] = np.arange(free_index.size)
        moved = np.full(size, -1)
        moved[moved_index] = np.arange(moved_index.size)
        self.n_free, self.n_moved = free_index.size, moved_index.size
        rows, cols = [], []
        for part in _parts(blocks, state):
            cq = 3 if part.blocks.shape[2] == 3 else 5
            r, c = _entry_indices(part.nodes, cq)
            rows.append(r)
            cols.append(c)
        rows = np.concatenate(rows) if rows else np.zeros(0, dtype=np.int64)
        cols = np.concatenate(cols) if cols else np.zeros(0, dtype=np.int64)
        r_f, c_f, c_p = position[rows], position[cols], moved[cols]
        ff = (r_f >= 0) & (c_f >= 0)
        fp = (r_f >= 0) & (c_p >= 0)
        # CSC order of K_ff: by column, then row.
        self.ff_select = np.flatnonzero(ff)
        keys, self.ff_map = np.unique(c_f[ff] * self.n_free + r_f[ff], return_inverse=True)
        self.ff_cols, self.ff_rows = np.divmod(keys, self.n_free)
        self.fp_select = np.flatnonzero(fp)
        keys, self.fp_map = np.unique(r_f[fp] * max(self.n_moved, 1) + c_p[fp], return_inverse=True)
        self.fp_rows, self.fp_cols = np.divmod(keys, max(self.n_moved, 1))

    def __call__(self, state, frames):
        """(K_ff, K_fp) of the blocks at ``state`` in the iteration's frames."""
        maps = _maps(self.model.n_nodes, frames)
        values = np.concatenate(
            [_generalised_blocks(part, maps).ravel() for part in _parts(self.blocks, state)]
            or [np.zeros(0)]
        )
        ff = np.bincount(self.ff_map, values[self.ff_select], minlength=self.ff_rows.size)
        k_ff = sp.csc_matrix((ff, (self.ff_rows, self.ff_cols)), shape=(self.n_free, self.n_free))
        fp = np.bincount(self.fp_map, values[self.fp_select], minlength=self.fp_rows.size)
        k_fp = sp.csr_matrix((fp, (self.fp_rows, self.fp_cols)), shape=(self.n_free, self.n_moved))
        return k_ff, k_fp


class Static:
    """Quasi-static solver: Newton-Raphson on the free DOFs with a sparse tangent.

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
    seek_stable : when an update meets an indefinite tangent (det K_ff < 0), turn it downhill
        along the negative modes (their components of the Newton step get the sign that lowers
        the energy, a "saddle-free" step), and push a converged unstable equilibrium (a
        compressed plate that stayed flat) along its buckling mode by half an element, up to
        three times per increment: the solver then settles on the stable, buckled branch.
        Each push is listed in ``info["branch_switches"]``.
    step_loads_first : apply the loads whose amplitude is "step" (gravity by default) first,
        over load factors 0 to 1 in ``increments`` increments with the prescribed displacements
        held at zero, then the other loads and the prescribed displacements over 1 to 2 (a
        specimen hangs under its weight before a support moves it). Frames then run over load
        factors 0 to 2.
    tangent : "element" (default): each block's own ``tangent`` where it has one, coloured
        finite differences of ``internal_force`` for the others; "finite_difference": coloured
        finite differences for every block.
    progress : print status lines (None: only on an interactive terminal).

    Prescribed displacements enter each iteration consistently: the update solves
    K_ff dq_f = r_f - K_fp dq_p for the part dq_p of the prescribed motion not yet applied, so
    the first iteration of an increment moves the structure with the imposed nodes instead of
    dragging them alone.

    Stability: a converged state whose tangent has det(K_ff) < 0 (an odd number of negative
    eigenvalues: an unstable equilibrium, past a limit point or a bifurcation) is reported in
    ``info["indefinite_at"]`` (load factors) and on the progress line; an even number of
    negative eigenvalues escapes this test. A singular tangent is regularised for one update
    (see ``_newton``) and reported if the increment then fails. There is no arc-length option:
    with ``seek_stable`` a limit point is passed by turning the steps downhill, which lands on
    the stable branch beyond a snap-through (the jump a quasi-static test shows), not on the
    unstable part of the path; with ``seek_stable=False`` a run that cannot pass a limit point
    stops with the load factor it reached, and DynamicRelaxation or CentralDifference remain
    the tools for a path that needs dynamics.
    """

    def __init__(
        self,
        increments: int = 10,
        tol: float = 1e-8,
        max_iterations: int = 50,
        line_search: bool = True,
        max_cuts: int = 8,
        tangent: str = "element",
        seek_stable: bool = True,
        step_loads_first: bool = False,
        progress: bool | None = None,
    ):
        self.increments = check_integer(increments, "increments")
        self.tol = check_tolerance(tol)
        self.max_iterations = check_integer(max_iterations, "max_iterations")
        self.line_search = bool(line_search)
        self.max_cuts = check_integer(max_cuts, "max_cuts", minimum=0)
        if tangent not in ("element", "finite_difference"):
            raise ValueError(f"tangent must be 'element' or 'finite_difference', got {tangent!r}")
        self.tangent = tangent
        self.seek_stable = bool(seek_stable)
        self.step_loads_first = bool(step_loads_first)
        self.progress = progress

    def solve(self, model: Model | CompiledModel):
        """Solve every increment; returns a femcore.results.Result with the reference state
        and one frame per increment (``time`` = load factor). Raises ConvergenceError, with
        the converged frames in ``error.result``, when an increment cannot be completed."""
        # Trial states of a wild update may overflow; every residual is checked for
        # finiteness and such an update is cut back, so numpy's warnings would only be noise.
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            return self._solve(model)

    def _solve(self, model: Model | CompiledModel):
        compiled = model.compile() if isinstance(model, Model) else model
        started = time.perf_counter()
        own = [b for b in compiled.blocks if self.tangent == "element" and _has_own_tangent(b)]
        others = [b for b in compiled.blocks if b not in own]
        graph = _Graph(compiled, others) if others else None
        state = compiled.initial_state()
        frames = [make_frame(compiled, state)]
        progress = ProgressLine(resolve_progress(self.progress), "static")
        info = {
            "solver": "Static",
            "tangent": {
                "element": [type(b).__name__ for b in own],
                "finite_difference": [type(b).__name__ for b in others],
            },
            "iterations_per_increment": [],
            "cuts": 0,
            "tangent_colours": graph.n_colours if graph else 0,
            "residual_ratio_per_increment": [],
            "indefinite_at": [],
            "regularised_iterations": 0,
            "branch_switches": [],
            "residual_history": [],
        }

        free_index = np.flatnonzero(_unknowns(compiled).ravel())
        moved_index = np.flatnonzero(_prescribed(compiled).ravel())
        assemble = _FreeAssembler(compiled, own, state, free_index, moved_index)

        def tangent(s, frames):
            """(K_ff, K_fp) at s."""
            k_ff, k_fp = assemble(s, frames)
            if others:
                k = finite_difference_tangent(compiled, s, graph, blocks=others)
                k_ff = (k_ff + k[free_index][:, free_index]).tocsc()
                k_fp = k_fp + k[free_index][:, moved_index]
            return k_ff, k_fp

        phases = 2 if self.step_loads_first else 1
        total = phases * self.increments
        step = 1.0 / self.increments
        reached = 0.0
        for increment in range(1, total + 1):
            target = increment / self.increments
            iterations = 0
            cuts_here = 0
            while reached < target - 1e-12:
                trial = min(target, reached + step)
                saved = state.copy()
                try:
                    count, ratio, history = self._newton(
                        compiled, tangent, state, trial, progress, info
                    )
                except _Failed as failure:
                    state = saved
                    cuts_here += 1
                    info["cuts"] += 1
                    if cuts_here > self.max_cuts:
                        error = ConvergenceError(
                            f"static solver stopped at load factor {reached:.6g}: increment "
                            f"{increment}/{total} did not converge after {cuts_here - 1}"
                            f" cuts ({failure}). A limit point or buckling may be near: try "
                            "DynamicRelaxation or CentralDifference for this path.",
                            None,
                        )
                        # Keep the last good state, also when it is part of an increment.
                        if reached > frames[-1].load_factor:
                            frames.append(make_frame(compiled, state))
                        error.result = self._result(compiled, frames, info, started, False)
                        error.load_factor = reached
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
            info["residual_history"].append(history)
            reactions, reaction_moments = self._reactions(compiled, state, reached)
            frames.append(make_frame(compiled, state, reactions, reaction_moments))
            progress(
                f"increment {increment}/{total} converged in {iterations} Newton iterations",
                force=True,
            )
        return self._result(compiled, frames, info, started, True)

    # ------------------------------------------------------------------ one increment
    def _newton(self, model, tangent, state, load_factor, progress, info):
        """Newton-Raphson at one load factor: (iterations, final ratio, ratio per iteration,
        starting with the ratio before the first update)."""
        free = _unknowns(model)
        f_ext, m_ext, imposed = self._loads(model, load_factor)
        prescribed = _prescribed(model)
        target = None
        if model.has_prescribed:
            target = model.reference_positions + imposed

        def remaining(s):
            """(n, 5) prescribed motion not yet applied."""
            out = np.zeros((model.n_nodes, 5))
            if target is not None:
                out[:, :3] = np.where(model.translation_prescribed, target - s.positions, 0.0)
            return out

        def residual(s, frames, forces=None):
            """(r, ratio, internal forces) at s; ``forces`` reuses an evaluation at s."""
            f_int, m_int = forces if forces is not None else model.internal_force(s)
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
            return r, ratio, (f_int, m_int)

        index = np.flatnonzero(free.ravel())
        moved_index = np.flatnonzero(prescribed.ravel())
        size = model.element_size
        singular = False
        escapes = 0
        translation = index % 5 < 3
        forces = None  # the internal forces of the accepted trial, reused next iteration
        for iteration in range(1, self.max_iterations + 1):
            frames = _frames(model, state.directors)
            r, ratio, _ = residual(state, frames, forces)
            left = remaining(state)
            if iteration == 1:
                history = [ratio]
            if not np.isfinite(ratio):
                raise _Failed("non-finite residual")
            push = False
            if ratio <= self.tol and np.abs(left).max(initial=0.0) <= 1e-9 * size:
                if iteration == 1:  # no factorisation yet: one for the stability report
                    k_ff = tangent(state, frames)[0]
                    negative = _solve(k_ff, np.zeros(index.size))[1]
                if self.seek_stable and escapes < 3 and not negative:
                    # det K > 0 misses an even number of negative modes: look for them.
                    negative = _lowest_modes(k_ff)[0].min(initial=np.inf) < 0.0
                if not (negative and self.seek_stable and escapes < 3):
                    self._report_stability(negative, load_factor, info, progress)
                    return iteration - 1, ratio, history
                # An unstable equilibrium: leave it along its buckling mode.
                escapes += 1
                push = True
                info["branch_switches"].append(load_factor)
                progress(
                    f"load factor {load_factor:.4g}: unstable equilibrium, leaving it along "
                    "the buckling mode",
                    force=True,
                )
            k_ff, k_fp = tangent(state, frames)
            rhs = r.ravel()[index]
            if moved_index.size:
                rhs = rhs - k_fp @ left.ravel()[moved_index]
            delta_free, negative = _solve(k_ff, rhs)
            if delta_free is None:
                # Exactly singular: a straight stress-free cable or membrane has no transverse
                # stiffness until it sags. A spring of 1e-6 x the largest diagonal on every
                # free unknown, for this update only, gives a finite step; the residual stays
                # exact, so a converged state is still an exact equilibrium. A mechanism or a
                # rigid motion under load keeps failing and is reported as singular.
                shift = 1e-6 * np.abs(k_ff.diagonal()).max(initial=0.0)
                delta_free, negative = _solve(
                    k_ff + shift * sp.identity(index.size, format="csc"), rhs
                )
                singular = True
                info["regularised_iterations"] += 1
                if delta_free is None:
                    raise _Failed(
                        "singular tangent stiffness: a mechanism, an unconstrained rigid "
                        "motion or a bifurcation"
                    )
            if (negative or escapes) and self.seek_stable:
                load = _generalised(model, frames, f_ext, m_ext).ravel()[index]
                delta_free = _downhill(k_ff, rhs, delta_free, load, translation, size, push)
            delta = left.ravel().copy()
            delta[index] = delta_free
            delta = delta.reshape(-1, 5)
            # Backtracking: the full Newton step of a large rotation first moves along the
            # tangent and stretches the structure, so a growing residual is normal for one
            # iteration; only a blow-up (or a non-finite state) is cut back.
            scale = 1.0
            for _ in range(6 if self.line_search else 1):
                trial = state.copy()
                with np.errstate(all="ignore"):  # a wild trial is judged, then cut back
                    _apply(model, trial, scale * delta, frames)
                    _, ratio_new, forces = residual(trial, frames)
                if (
                    not self.line_search
                    or push
                    or (np.isfinite(ratio_new) and ratio_new <= 10.0 * max(ratio, self.tol))
                ):
                    break
                scale *= 0.5
            if not np.isfinite(ratio_new):
                raise _Failed("non-finite residual after the line search")
            state.positions, state.directors = trial.positions, trial.directors
            ratio = ratio_new
            history.append(ratio)
            # Round-off floor: the internal forces come from differences of nearly equal
            # metrics, so a tiny load on a stiff shell can leave a residual of ~1e-4 of the
            # load that no update removes. A full step that moves nothing (1e-9 of an element,
            # 1e-9 rad) with the residual already small is converged.
            moved = scale * np.abs(delta)
            if (
                scale == 1.0
                and ratio <= 1e-3
                and moved[:, :3].max() <= 1e-9 * size
                and moved[:, 3:].max(initial=0.0) <= 1e-9
            ):
                self._report_stability(negative, load_factor, info, progress)
                return iteration, ratio, history
            progress(
                f"load factor {load_factor:.4g}: iteration {iteration}, residual ratio "
                f"{ratio:.3g} (tol {self.tol:g})"
            )
        if ratio <= self.tol and np.abs(remaining(state)).max(initial=0.0) <= 1e-9 * size:
            self._report_stability(negative, load_factor, info, progress)
            return self.max_iterations, ratio, history
        raise _Failed(
            f"residual ratio {ratio:.3g} after {self.max_iterations} iterations"
            + (
                "; the tangent was singular (a mechanism, an unconstrained rigid motion or a "
                "bifurcation)"
                if singular
                else ""
            )
        )

    @staticmethod
    def _report_stability(negative: bool, load_factor: float, info: dict, progress) -> None:
        """Record a converged state whose tangent has det(K_ff) < 0: an odd number of negative
        eigenvalues, i.e. an unstable equilibrium (past a limit point or a bifurcation)."""
        if negative:
            info["indefinite_at"].append(load_factor)
            progress(
                f"load factor {load_factor:.4g}: the tangent stiffness is indefinite "
                "(det K < 0): an unstable equilibrium, past a limit point or a bifurcation",
                force=True,
            )

    def _loads(self, model, load_factor):
        """Dead forces, moments and imposed displacements (n, 3) each at a load factor: all
        ramped together, or with ``step_loads_first`` the "step" loads over [0, 1] (imposed
        displacements held at zero) and then the rest over [1, 2]."""
        force, moment = model.external_load(1.0, quasi_static=True)
        imposed = model.prescribed_displacement(1.0, quasi_static=True)
        if not self.step_loads_first:
            return load_factor * force, load_factor * moment, load_factor * imposed
        # A "step" amplitude is 1 for any positive progress, a ramped one is proportional.
        step_force, step_moment = model.external_load(1e-300, quasi_static=True)
        first = min(load_factor, 1.0)
        then = max(load_factor - 1.0, 0.0)
        return (
            first * step_force + then * (force - step_force),
            first * step_moment + then * (moment - step_moment),
            then * imposed,
        )

    def _reactions(self, model, state, load_factor):
        f_ext, m_ext, _ = self._loads(model, load_factor)
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


def _downhill(k_ff, rhs, delta, load, translation, size, push) -> np.ndarray:
    """The Newton step with its components along the negative modes of K_ff turned downhill.

    A Newton step heads for the nearest equilibrium, stable or not. Along a mode phi with
    eigenvalue lambda < 0 (of the symmetric part), its component (phi . r) / lambda climbs
    the energy towards the saddle; the step is given the component (phi . r) / |lambda|
    instead, at least half an element long when ``push`` (leaving a converged saddle), in the
    direction where the external load does positive work (gravity picks the buckling side).
    """
    values, vectors = _lowest_modes(k_ff)
    delta = delta.copy()
    for value, phi in zip(values, vectors.T):
        if value >= 0.0:
            continue
        along = phi @ rhs
        wanted = along / abs(value)
        reach = np.abs(phi[translation]).max(initial=0.0)
        if push and reach > 0.0 and abs(wanted) < 0.5 * size / reach:
            side = np.sign(phi @ load) or np.sign(along) or 1.0
            wanted = side * 0.5 * size / reach
        delta += (wanted - phi @ delta) * phi
    return delta


def _lowest_modes(k_ff) -> tuple[np.ndarray, np.ndarray]:
    """The (up to) 6 eigenvalues of the symmetric part of K_ff nearest zero, with their unit
    eigenvectors (columns); empty when ARPACK fails or the matrix is tiny."""
    n = k_ff.shape[0]
    if n <= 200:  # small: all of them, densely (ARPACK needs k < n - 1)
        values, vectors = np.linalg.eigh(0.5 * (k_ff + k_ff.T).toarray())
        return values[:6], vectors[:, :6]
    count = 6
    symmetric = (0.5 * (k_ff + k_ff.T)).tocsc()
    try:
        return eigsh(symmetric, k=count, sigma=0.0, which="LM")
    except (RuntimeError, ArpackNoConvergence):
        return np.zeros(0), np.zeros((n, 0))


def _solve(k_ff: sp.csc_matrix, rhs: np.ndarray) -> tuple[np.ndarray | None, bool]:
    """Sparse LU solve, or None when the matrix is (numerically) singular; and whether
    det(K) < 0, from the signs of U's diagonal and of the two permutations (L has a unit
    diagonal)."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", MatrixRankWarning)
        try:
            lu = splu(k_ff)
            solution = lu.solve(rhs)
        except (RuntimeError, MatrixRankWarning):
            return None, False
    if not np.all(np.isfinite(solution)):
        return None, False
    odd = np.count_nonzero(lu.U.diagonal() < 0) + _odd(lu.perm_r) + _odd(lu.perm_c)
    return solution, bool(odd % 2)


def _odd(permutation: np.ndarray) -> int:
    """1 if the permutation is odd (n minus its number of cycles is odd), else 0."""
    seen = np.zeros(permutation.size, dtype=bool)
    cycles = 0
    for start in range(permutation.size):
        if not seen[start]:
            cycles += 1
            j = start
            while not seen[j]:
                seen[j] = True
                j = permutation[j]
    return (permutation.size - cycles) % 2


class _Failed(Exception):
    """An increment that did not converge (caught to cut the increment)."""
