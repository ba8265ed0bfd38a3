"""The level-strain projection of a Newton step of the static solver
(``Static``'s default on a fibrous model, docs/theory.md §6.5).

The fibrous shell's fibres run at several levels through the thickness, x + zeta h_m V / 2:
their lengths follow the directors' differences from node to node as well as the mid-surface,
so the mid-surface projection of solvers.newton_fibres does not restore them (it made Peirce's
cantilever slower). Here the measures the block calls nearly inextensible (``fibre_strains``:
each level's warp and weft strains and shear angle, per cell) are brought back, after the
(curved) Newton step delta, towards what the step's first order asks for,

    s* = s(q) + ds/dq . straight        (a central difference along the straight step),

by the correction that costs the least energy in the iteration's tangent K: up to SWEEPS
sweeps of

    minimise 1/2 dc^T K dc + rho / 2 |J dc + c|^2,   c = s(q + delta) - s*,

i.e. (K + rho J^T J) dc = -rho J^T c, with rho = PENALTY times the ratio of the largest
diagonals of K and J^T J (the constraints are dependent: three measures at each of several
levels over five unknowns a node, which the penalty form takes as they are). Where the
Euclidean least-norm correction of the same constraints moved the nodes across the strip and
changed the bending (Peirce 6-10-15 and cuts), the energy metric keeps the bending the step
found: Peirce's cantilever 9-9-10 -> 6-5-6 iterations per increment
(benchmarks/newton_iterations.py line 7).

Only the measures that the step itself keeps nearly constant are held, |ds/dq . straight| <=
CHANGE (1e-4): the fibres of a bent strip (at most 1.6e-5 a step on the fibrous cantilevers).
A measure the step changes by more is the load's own (the shear of a bias specimen pulled by
a force, 0.1-0.16 rad a step): its first-order target is off by about the change squared,
as far as the remainder the projection would remove, and holding it fought the load
(6-5-13-19 iterations against 4-4-4-4 without the projection; 6-4-4-4 with the rule at
1e-3; the same iterations on the cantilevers). At 1e-3 the bias specimen's fibres near its
clamps, whose first-order changes reach 7e-4 to 9e-4 a step, were held to targets off by
about 5e-7 (fibres of 120000 N/mm): a step of its first increment projected to them left a
ratio of 7.7e-2 where plain Newton reached 2.5e-4; at 1e-4 the bias takes 5-4-3-3 (15
tangents against 17 without the projection; 6-4-4-3 against 4-4-4-4, 17 tangents against 16,
since its factorisations are the band's, whose last bits differ from QDLDL's), at 3e-5 and
3e-4 5-4-4-3, and Peirce's and the heavy cantilevers the same iterations from 3e-5 to 1e-3
(benchmarks/newton_iterations.py line 7).

J = ds/d(delta) at each sweep's end, in the iteration's frames, is exact (the block's
``fibre_strain_gradient``, elements/fibrous/level_jacobian.py), summed into a CSR pattern
made once per solve by one compiled pass (solvers.level_gather). The coloured one-sided
differences it replaced (``_jacobian``: nodes that move a common cell get different colours)
are kept as its reference for the tests and
benchmarks/newton_iterations.py: 2.3-2.7 ms a sweep on Peirce's strip against 0.56-0.59 ms,
the same iterations there; on the force-pulled bias specimen their error (one-sided steps of
1e-7 element on fibres of 120000 N/mm) took 28-29-27-34 iterations. K + rho J^T J is
symmetric positive definite where the projection runs: the band LDL^T of solvers.linear
solves it, on a pattern kept over the solve (SuperLU's LU of before: 1.7 ms a sweep), J^T J
summed into it by a compiled loop over each cell's block of J (solvers.level_system; scipy's
diagonal scaling, product, sum and placement took 1.1 ms a sweep on Peirce's strip, now 0.3).

Where a sweep's CPU goes on Peirce's strip (3 increments, 23 sweeps in 8 projected steps, one
thread, load 9-14; benchmarks/newton_iterations.py line 7): the gradient 0.8-0.9 ms (the
numpy of level_strain_gradient 0.35-0.38 of it), the system 0.3, its factorisation and solve
0.4, the strains at the sweep's end 0.1; each projected step's target (two strain
evaluations) 0.3. 40-50 ms a solve in all, against 11 tangents and their factorisations saved
(28 -> 17): 1.09-1.15 times the CPU of the solve without (1.21-1.23 before the compiled sums).
The gradient's pieces are now a compiled cell loop (elements/fibrous/level_kernels.py): 0.34
-> 0.07 ms a sweep, the whole gradient 0.51 -> 0.24 (load 9): 0.95-0.97 times the CPU of the
solve without in 3 increments, 1.02-1.07 in 12 (47 sweeps against 17 tangents saved). Over
every fibrous Static solve of the tests and validation cases, the same results (to 1e-9 of
each checked value), fewer iterations and the same CPU in sum (benchmarks/newton_iterations.py
line 7, docs/theory.md §6.5): the projection is Static's default on a fibrous model
(``level_projection=False`` turns it off).
"""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp

from femcore.assembly import greedy_colours, node_adjacency
from femcore.dofs import N_COLUMNS
from femcore.model import CompiledModel
from solvers.level_gather import gather
from solvers.level_system import PenaltySystem, locate
from solvers.linear import LinearSolver

if TYPE_CHECKING:
    from femcore.dofs import Frames
    from femcore.element import ElementBlock
    from femcore.state import State
    from solvers.static import StaticRun

__all__ = ["CHANGE", "LEVEL_GATE", "PENALTY", "SWEEPS", "TOLERANCE", "LevelStrains"]

# Sweeps of one projection and the strain error (of the held measures) at which they stop.
# The projection only brings the step near the levels' first order; the Newton steps that
# follow take what it leaves: stopping at 1e-7 (a strain error of 1e-4 to 1e-1 before the
# first sweep) instead of 1e-12 (below the residual test itself) took the same iterations on
# the cantilevers in 2/3 of the sweeps: Peirce 3 increments 36 -> 23 sweeps, 0.179 -> 0.143 s
# CPU (0.125 s without the projection), 12 increments 88 -> 47 sweeps, 0.412 -> 0.267 s
# (0.246 s; 52 iterations instead of 51), the heavy cantilever (20, 40 cells) 0.127 -> 0.116,
# 0.207 -> 0.205 s, the force-pulled bias 0.403 -> 0.329 s (0.207 s) (load 2.2-2.3); 1e-6:
# Peirce 6-8-5, 12 increments 54 iterations.
SWEEPS = 4
TOLERANCE = 1e-7
# rho of the penalty form over the ratio of the diagonals of K and J^T J: the constraints
# are met to ~1 / PENALTY of their error by each sweep.
PENALTY = 1e2
# The largest first-order change of a measure along the step (strain, rad) for which the
# measure is held: the target's second-order error, of its square (1e-8), stays below the
# remainders the projection removes (1e-5 to 1e-1 on the fibrous cantilevers) and below what
# the stiffest fibres make a residual of (module docstring: 1e-3 held the bias specimen's
# fibres near its clamps to targets off by 5e-7).
CHANGE = 1e-4
# Only steps that move a node by more than this many element sizes are projected: near the
# equilibrium the remainder is below the residual test and the projection's own rounding
# (the strains' central differences, ~1e-12) would be the larger.
LEVEL_GATE = 1e-2
# Central-difference steps: along the Newton step (a fraction of it) and of each unknown
# (of the element size, and rad).
ALONG = 1e-4
PERTURB = 1e-7


class LevelStrains:
    """The level-strain projection of a model's Newton steps (module docstring), over the
    element blocks that give ``fibre_strains(state) -> (m, p)`` and
    ``fibre_strain_gradient(state)`` (``has_fibre_strains``, femcore.element;
    elements/fibrous/level_jacobian.py); false when there are none."""

    def __init__(self, model: CompiledModel):
        self.model = model
        # The blocks that give their level measures and those measures' gradient.
        self.parts: list[ElementBlock] = [p for p in model.blocks if p.has_fibre_strains]
        if not self.parts:
            return
        dofs = model.dofs
        self.slot = np.full(dofs.n_slots, -1, dtype=np.int64)
        self.slot[dofs.free_slots] = np.arange(dofs.free_slots.size)
        self.solver = LinearSolver()
        self.pattern: tuple | None = None
        self.system = PenaltySystem(int(dofs.free_slots.size))
        # The colouring of the coloured differences (``_jacobian``), made at their first use:
        # the solves take the exact gradient and need none of it.
        self.groups: list[np.ndarray] = []
        self.node_of = np.zeros((0, 0), dtype=np.int64)

    def __bool__(self) -> bool:
        return bool(self.parts)

    def strains(self, state: State) -> np.ndarray:
        """(cells, p) the blocks' nearly inextensible measures, stacked over the blocks."""
        return np.concatenate([part.fibre_strains(state) for part in self.parts])

    def project(
        self,
        run: StaticRun,
        state: State,
        frames: Frames,
        straight: np.ndarray,
        delta: np.ndarray,
        k_ff,
    ) -> np.ndarray:
        """The step delta (n, 5) corrected so that the measures at its end are those of the
        first order of ``straight`` (n, 5, the Newton step), at the least energy in K_ff (the
        iteration's tangent on the free unknowns). Returns a new (n, 5) step, or delta when
        it moves no node by LEVEL_GATE element sizes or the correction cannot be solved."""
        model, dofs = self.model, self.model.dofs
        size = model.element_size
        if float(np.abs(delta[:, :3]).max(initial=0.0)) <= LEVEL_GATE * size:
            return delta
        forward = self.strains(dofs.advance(state, ALONG * straight, frames))
        backward = self.strains(dofs.advance(state, -ALONG * straight, frames))
        change = (forward - backward) / (2.0 * ALONG)
        target = self.strains(state) + change
        # Only the measures the step itself keeps nearly constant are held (the fibres of a
        # bent strip, ds/dq . straight <= 1.6e-5): where the step changes a measure by
        # more, as the shear of a bias specimen pulled by a force (0.1-0.16 rad a step), its
        # first-order target is off by the change squared, as far as the remainder the
        # projection would remove (1e-2), and holding it fought the load (6-5-13-19
        # iterations against 4-4-4-4 without the projection; 6-4-4-3 with this rule).
        held = (np.abs(change) <= CHANGE).ravel().astype(float)
        if not held.any():
            return delta
        free = dofs.free_slots
        k_ff = k_ff if isinstance(k_ff, sp.csc_matrix) else sp.csc_matrix(k_ff)
        projected, swept = delta.copy(), False
        for _ in range(SWEEPS):
            error = (self.strains(dofs.advance(state, projected, frames)) - target).ravel()
            if np.abs(held * error).max(initial=0.0) <= TOLERANCE:
                break
            # The gradient at each sweep's end: kept from the first sweep on, the sweeps
            # stalled (Peirce 11-9-7 against 6-5-5, with PENALTY 1e3).
            jacobian = self.gradient(state, frames, projected)
            # K + rho J^T J is symmetric positive definite where the projection runs (a
            # positive definite K): the band LDL^T of solvers.linear, its symbolic part kept
            # while the pattern holds (SuperLU's pivoting LU took 1.7 ms a sweep on Peirce's),
            # the pattern and J^T J's sums kept by solvers.level_system.
            assembled = self.system.assemble(k_ff, jacobian, held, PENALTY)
            if assembled is None:
                return delta
            system, rho = assembled
            pull = self.system.pull(jacobian, held, error)
            correction = self.solver.factorise(system).solve(-rho * pull)
            if correction is None or not np.all(np.isfinite(correction)):  # singular
                return delta
            flat = projected.ravel().copy()
            flat[free] += correction
            projected = flat.reshape(-1, N_COLUMNS)
            run.info["level_projection_sweeps"] += 1
            swept = True
        run.info["level_projections"] += swept
        return projected

    def gradient(self, state: State, frames: Frames, delta: np.ndarray) -> sp.csr_matrix:
        """d(measures)/d(free unknowns) (cells p, free) at the end of the step delta (n, 5),
        exact (elements/fibrous/level_jacobian.py): the translations' columns as they are,
        the directors' turned about the iteration's frame vectors (V2 for alpha, V1 for
        beta), as ``_jacobian``'s differences turn them. Its entries are summed into the
        pattern made once per solve (``_pattern``) by one compiled pass
        (solvers.level_gather)."""
        if self.pattern is None:
            self.pattern = self._pattern()
        place, indices, indptr, shape = self.pattern
        end = self.model.dofs.advance(state, delta, frames)
        v1, v2 = frames if frames is not None else (None, None)
        data = np.zeros(indices.size)
        start = 0
        for part in self.parts:
            conn = part.connectivity
            (direct, turns, through_sums, shares), pairs = part.fibre_strain_gradient(end)
            m = conn.shape[0]
            if v1 is not None and v2 is not None:
                axes = np.stack([v2[conn], v1[conn]])
            else:
                axes = np.zeros((0, m, 3, 3))
            if pairs is not None and through_sums is not None and shares is not None:
                corners = np.stack(pairs)
            else:
                through_sums, shares = direct, np.zeros((m, 3, 3, 3, 3))
                corners = np.zeros((4, 0), dtype=np.int64)
            start = gather(direct, turns, axes, through_sums, shares, corners, place, start, data)
        return sp.csr_matrix((data, indices, indptr), shape=shape)

    def _pattern(self):
        """(place, indices, indptr, shape): where each value of ``gradient``'s goes in the
        CSR pattern of J over the free unknowns (-1: a value at a held unknown, dropped), in
        the order ``gradient`` makes them."""
        frames = self.model.dofs.any_rotation
        rows, cols = [], []
        offset = 0
        for part in self.parts:
            conn = part.connectivity
            # The gradient's pieces once, for their shapes (m, p) and the corner pairs.
            pieces, pairs = part.fibre_strain_gradient(self.model.initial_state())
            m, p = pieces[0].shape[:2]
            row = offset + np.arange(m)[:, None] * p + np.arange(p)[None, :]  # (m, p)
            slot = conn[:, None, :, None] * N_COLUMNS + np.arange(3)  # (m, 1, 3, 3)
            shape = (m, p, 3, 3)
            rows.append(np.broadcast_to(row[:, :, None, None], shape).ravel())
            cols.append(np.broadcast_to(self.slot[slot], shape).ravel())
            if frames:
                for column in (3, 4):
                    rows.append(np.broadcast_to(row[:, :, None], (m, p, 3)).ravel())
                    turned = self.slot[conn * N_COLUMNS + column][:, None, :]
                    cols.append(np.broadcast_to(turned, (m, p, 3)).ravel())
            if pairs is not None:
                cell, _, other, _ = pairs
                shape = (cell.size, p, 3, 3)
                rows.append(np.broadcast_to(row[cell][:, :, None, None], shape).ravel())
                slot = conn[other][:, None, :, None] * N_COLUMNS + np.arange(3)
                cols.append(np.broadcast_to(self.slot[slot], shape).ravel())
            offset += m * p
        row, col = np.concatenate(rows), np.concatenate(cols)
        keep = col >= 0
        n_free = int(self.model.dofs.free_slots.size)
        # The pattern by scipy's sums of duplicates, each value's place in it by a bisection
        # within its row (numpy's unique over the keys, a sort of every value: 20-25 ms once
        # a solve on the force-pulled bias specimen's 282 000 values).
        row, col = row[keep].astype(np.int64), col[keep].astype(np.int64)
        ones = sp.csr_matrix((np.ones(row.size), (row, col)), shape=(offset, n_free))
        ones.sum_duplicates()
        indptr, indices = ones.indptr.astype(np.int64), ones.indices.astype(np.int64)
        place = np.full(keep.size, -1, dtype=np.int64)
        place[keep] = locate(indptr, indices, col, row)
        return place, indices, indptr, (offset, n_free)

    def _colour(self) -> None:
        """The colour groups and each cell's node of each colour (``groups``, ``node_of``)
        of ``_jacobian``'s coloured differences."""
        n = self.model.n_nodes
        connectivities = [p.connectivity for p in self.parts]
        pairs_cell, pairs_node = [], []
        offset = 0
        ring = node_adjacency(n, connectivities)
        for part in self.parts:
            cells = part.connectivity
            m = len(cells)
            corners = sp.csr_matrix(
                (np.ones(cells.size), (np.repeat(np.arange(m), cells.shape[1]), cells.ravel())),
                shape=(m, n),
            )
            near = (corners @ ring).tocoo()  # (cell, node one cell from a corner)
            pairs_cell.append(near.row + offset)
            pairs_node.append(near.col)
            offset += m
        cell, node = np.concatenate(pairs_cell), np.concatenate(pairs_node)
        # Nodes that move a common cell get different colours (a greedy colouring of that
        # graph, once per projection; the strains of a cell reach the nodes one cell from its
        # corners through the nodal normals).
        reach = sp.csr_matrix((np.ones(cell.size), (cell, node)), shape=(offset, n))
        colour = greedy_colours((reach.T @ reach).tocsr())
        self.groups = [np.flatnonzero(colour == c) for c in range(int(colour.max()) + 1)]
        # The node of each colour that moves each cell (unique by the colouring).
        self.node_of = np.full((offset, len(self.groups)), -1, dtype=np.int64)
        self.node_of[cell, colour[node]] = node

    def _jacobian(
        self, state: State, frames: Frames, delta: np.ndarray, size: float, k: int
    ) -> sp.csr_matrix:
        """d(measures)/d(free unknowns) at the end of the step delta (n, 5), (k = cells p,
        free): coloured one-sided differences at that end, translations by PERTURB element
        sizes, the directors turned by PERTURB rad about the iteration's frame vectors
        (V2 for alpha, V1 for beta; the derivative of the turn composed with the step's own
        turn differs from it by the step's rotation times the perturbation, which the sweeps
        absorb)."""
        end = self.model.dofs.advance(state, delta, frames)
        positions, directors = end.positions, end.directors
        axes = (frames[1], frames[0]) if frames is not None else (None, None)
        base = self.strains(end)
        if not self.groups:
            self._colour()
        rows, cols, values = [], [], []
        for colour, members in enumerate(self.groups):
            node = self.node_of[:, colour]
            cells = np.flatnonzero(node >= 0)
            for component in range(N_COLUMNS):
                held = self.slot[members * N_COLUMNS + component] < 0
                moved = members[~held]
                if moved.size == 0:
                    continue
                if component < 3:
                    h = PERTURB * size
                    bump = np.zeros_like(positions)
                    bump[moved, component] = h
                    plus = replace(end, positions=positions + bump)
                else:
                    h = PERTURB
                    axis = axes[component - 3]
                    assert axis is not None
                    turn = np.zeros_like(directors)
                    turn[moved] = h * np.cross(axis[moved], directors[moved])
                    plus = replace(end, directors=directors + turn)
                change = (self.strains(plus) - base) / h
                column = self.slot[node[cells] * N_COLUMNS + component]
                keep = column >= 0
                on, column = cells[keep], column[keep]
                p = change.shape[1]
                rows.append((on[:, None] * p + np.arange(p)).ravel())
                cols.append(np.repeat(column, p))
                values.append(change[on].ravel())
        return sp.csr_matrix(
            (np.concatenate(values), (np.concatenate(rows), np.concatenate(cols))),
            shape=(k, int(self.model.dofs.free_slots.size)),
        )
