"""The tangent by coloured central differences of the forces, for element blocks without a
tangent of their own: the node graph of the blocks, its greedy colouring (nodes more than
twice the blocks' reach apart share a colour and are perturbed together) and the
differences (femcore.assembly re-exports them).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import scipy.sparse as sp

from femcore.dofs import N_COLUMNS, DofManager, Frames
from femcore.state import State

__all__ = ["NodeGraph", "finite_difference_tangent", "greedy_colours", "node_adjacency"]


def node_adjacency(n: int, connectivities: list[np.ndarray]) -> sp.csr_matrix:
    """(n, n) float, 1 where two nodes share a cell of any of ``connectivities`` ((m, k) int
    each), and on the diagonal."""
    rows, cols = [np.arange(n)], [np.arange(n)]
    for cells in connectivities:
        k = cells.shape[1]
        rows.append(np.repeat(cells, k, axis=1).ravel())
        cols.append(np.tile(cells, (1, k)).ravel())
    row, col = np.concatenate(rows), np.concatenate(cols)
    adjacency = sp.csr_matrix((np.ones(row.size), (row, col)), shape=(n, n))
    return adjacency.astype(bool).astype(float)


def greedy_colours(conflict: sp.csr_matrix) -> np.ndarray:
    """(n,) int, a colour per node such that no two nodes of a stored entry of ``conflict``
    ((n, n), its diagonal stored) share one: each node, in order, takes the least colour its
    coloured neighbours leave (a loop over the nodes, once per model or solve, not per step)."""
    n = conflict.shape[0]
    colour = np.full(n, -1)
    indptr, indices = conflict.indptr, conflict.indices
    for node in range(n):
        taken = set(colour[indices[indptr[node] : indptr[node + 1]]].tolist())
        c = 0
        while c in taken:
            c += 1
        colour[node] = c
    return colour


class NodeGraph:
    """Node colouring and sparsity pattern for the finite-difference tangent of some blocks.

    The force at a node depends on nodes at most ``reach`` cell-hops away (the largest reach
    of the blocks: 1 for cell-local elements, 2 for rotation-free bending patches), so the
    column of node j has entries within ``reach`` hops, and nodes more than 2 x reach hops
    apart never share a row: they get the same colour and are perturbed together.

    Parameters
    ----------
    n_nodes : int
    connectivities : list of (m, k) int
        The ``connectivity`` of each block.
    reach : int
        The largest ``reach`` of the blocks.
    """

    def __init__(self, n_nodes: int, connectivities: list[np.ndarray], reach: int):
        n = n_nodes
        adjacency = node_adjacency(n, connectivities)
        pattern = adjacency
        for _ in range(reach - 1):
            pattern = (pattern @ adjacency).astype(bool).astype(float)
        pattern = pattern.tocsr()
        colour = greedy_colours((pattern @ pattern).tocsr())  # conflicts within 2 x reach hops
        self.colour = colour
        self.n_colours = int(colour.max()) + 1 if n else 0
        coo = pattern.tocoo()
        #: Per colour: (its nodes, the rows and columns of the pattern entries in its columns).
        self.groups = []
        for c in range(self.n_colours):
            members = colour[coo.col] == c
            self.groups.append((np.flatnonzero(colour == c), coo.row[members], coo.col[members]))


def finite_difference_tangent(
    dofs: DofManager,
    internal_force: Callable[[State], tuple[np.ndarray, np.ndarray]],
    state: State,
    graph: NodeGraph,
    step: float,
    rotation_step: float = 1e-6,
    frames: Frames = None,
) -> sp.csr_matrix:
    """Sparse K = dF_int/dq (n_slots x n_slots) by coloured central differences.

    Parameters
    ----------
    dofs : DofManager
    internal_force : callable
        state -> (forces (n, 3), moments (n, 3)) of the blocks to differentiate.
    state : State
    graph : NodeGraph
        Of those blocks.
    step : float
        Perturbation of the translations (length unit).
    rotation_step : float
        Perturbation of alpha and beta (rad).
    frames : Frames
        The nodal frames held during the iteration (default: those of ``state.directors``).

    The loads are dead (fixed in global directions) and the frames are held, so the external
    loads add nothing to K. Each colour costs 2 x (5 or 3) force evaluations, whatever the mesh
    size.
    """
    n = dofs.n_nodes
    frames = dofs.frames(state.directors) if frames is None else frames
    components = N_COLUMNS if dofs.any_rotation else 3
    rows, cols, values = [], [], []

    def generalised(s: State) -> np.ndarray:
        return dofs.generalised(frames, *internal_force(s))

    for nodes, entry_rows, entry_cols in graph.groups:
        for component in range(components):
            h = step if component < 3 else rotation_step
            delta = np.zeros((n, N_COLUMNS))
            delta[nodes, component] = h
            plus = dofs.advance(state, delta, frames)
            minus = dofs.advance(state, -delta, frames)
            df = (generalised(plus) - generalised(minus)) / (2 * h)
            for a in range(components):
                rows.append(DofManager.slots(entry_rows, a))
                cols.append(DofManager.slots(entry_cols, component))
                values.append(df[entry_rows, a])
    size = dofs.n_slots
    if not rows:
        return sp.csr_matrix((size, size))
    return sp.csr_matrix(
        (np.concatenate(values), (np.concatenate(rows), np.concatenate(cols))), shape=(size, size)
    )
