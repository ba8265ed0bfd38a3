"""The fibrous shell's tangent a run of rows at a time (docs/theory.md §2.6, §6.2).

``tangent.tangent`` forms the membrane's J^T H J and the bending patches of all cells at once:
30 kB a triangle at its peak with nodal normals, for a bound (the explicit solver's
assembled stable step, femcore/gershgorin.py) that only sums the tangent's blocks per node
pair. Here the same tangent comes as pieces, each the complete rows of a run R of nodes
(``piece_nodes`` of them), made, given and dropped:

* the membrane's rows of R, K_R = (J^T H J)_R (row_product.RowProduct): the rows k of P = H J
  at the nodes N1 of the cells at R, from H's rows at N1 (the Hessians of the cells around
  N1) and J's rows at N1's neighbours N2 (dS_k/dx_j from the cells around N2), numbered
  locally on the cells around N2;
* the bending patches (with the normal sums' second derivatives, T_k = dW/dS_k the nodal sums
  of every cell's dW/dS from the force loops' first passes) of the cells whose patch holds a
  node of R, added to R's rows in the cells' order.

Each row is summed with the arithmetic of the whole tangent formed at once (its Hessian and
Jacobian pair blocks over every cell around, in the cells' order, the product's loops, then
the patches in the cells' order): the pieces are the whole tangent's rows to the last bit
whatever their size, so the bound does not depend on it, and the size is free to follow the
model (``piece_nodes``: a piece's work arrays a small part of the model's memory). The runs
take the nodes in the order of their first cells, so that on a mesh whose cells come in a
banded order a run's halo is a few rows of cells whatever the node numbering. The price is
the halo: its Jacobians and bending patches are formed for each run that reaches them, and
the Hessians of the cells around the ring's rows not kept from the run before (1.25 x the
bound's CPU at 100k triangles, benchmarks/model_memory.py). Element normals, or the numpy
path: the whole tangent in one piece.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp

from elements.base import SparseTangent
from elements.fibrous import bending, hessian_kernels, kernels, row_product, tangent_kernels
from elements.fibrous.geometry import normal_sums
from elements.fibrous.symmetry import on_planes
from elements.fibrous.tangent import NodePairs, tangent
from femcore.assembly import TangentPart
from femcore.state import State

if TYPE_CHECKING:
    from elements.fibrous.block import FibrousShellBlock

__all__ = ["piece_nodes", "tangent_pieces"]

# Nodes per piece: at most PIECE, and about a PIECE_SHARE of the block's nodes, at least
# PIECE_MIN (a run shorter than its halo forms mostly the halo's Hessians).
PIECE = 1024
PIECE_SHARE = 96
PIECE_MIN = 32
# Cells whose Hessians (or bending blocks, Jacobians) are held at once within a piece.
_HESSIANS = 256


def piece_nodes(n_nodes: int) -> int:
    """The nodes of a piece of ``tangent_pieces`` for a block of ``n_nodes`` nodes."""
    return int(min(PIECE, max(PIECE_MIN, n_nodes // PIECE_SHARE)))


def tangent_pieces(block: FibrousShellBlock, state: State) -> Iterator[TangentPart]:
    """``tangent.tangent`` in pieces whose sum it is: per run of ``piece_nodes`` nodes, in
    the nodes' order, the complete rows of those nodes (the membrane's J^T H J and the
    bending patches; SparseTangent, BSR with 6 x 6 blocks over all nodes, its blocks that are
    zero left out). Element normals or no compiled loops: the parts of ``tangent``."""
    if not (
        block.nodal_normals
        and block.compiled
        and hessian_kernels.AVAILABLE
        and row_product.AVAILABLE
    ):
        yield from tangent(block, state)
        return
    n = block.n_nodes
    positions = state.positions
    sums = normal_sums(block, positions)
    # T_k = dW/dS_k, the nodal sums of every cell's dW/dS (the force loops' first passes).
    pull = kernels.normal_pulls(block, positions, state.directors)
    terms = bending.tangent_terms(block, positions)
    around = _NodeCells(block.connectivity, n)
    size = piece_nodes(n)
    # The nodes in the order of the first cell at each (a cell-ordered mesh's runs then share
    # only their borders, whatever its node numbering), size at a time, each run sorted.
    order = np.argsort(_first_cells(block.connectivity, n), kind="stable")
    runs = [np.sort(order[start : start + size]) for start in range(0, n, size)]
    # H's rows of a run's ring that the next run's ring shares, kept from one to the next.
    kept = _HeldRows(np.empty(0, dtype=np.int64), np.empty((0, 9, 9)))
    rings = (_ring(block.connectivity, around, run) for run in runs)
    ring = next(rings, None)
    for run in runs:
        assert ring is not None  # one ring a run
        after = next(rings, None)
        piece, kept = _rows(block, state, sums, pull, terms, around, run, ring, kept, after)
        yield piece
        ring = after


def _first_cells(connectivity: np.ndarray, n_nodes: int) -> np.ndarray:
    """The first cell at each node (n,) (len(connectivity) at a node of no cell)."""
    first = np.full(n_nodes, len(connectivity), dtype=np.int64)
    np.minimum.at(first, connectivity.ravel(), np.repeat(np.arange(len(connectivity)), 3))
    return first


def _ring(connectivity: np.ndarray, around: _NodeCells, run: np.ndarray) -> np.ndarray:
    """The nodes of the cells at a run's nodes (sorted): the rows of H its rows read."""
    return np.unique(connectivity[around.of(run)])


class _HeldRows:
    """H's blocks (pairs, 9, 9) of whole rows of node pairs, their keys a n + b (pairs,)
    sorted: a row summed for one run and read by the next."""

    def __init__(self, keys: np.ndarray, blocks: np.ndarray):
        self.keys, self.blocks = keys, blocks


class _NodeCells:
    """The cells around each node (CSR over the nodes), to find a run's halo."""

    def __init__(self, connectivity: np.ndarray, n_nodes: int):
        flat = connectivity.ravel()
        order = np.argsort(flat, kind="stable")
        self.cells = (order // 3).astype(np.int32 if len(connectivity) < 2**31 else np.int64)
        self.offsets = np.zeros(n_nodes + 1, dtype=np.int64)
        np.cumsum(np.bincount(flat, minlength=n_nodes), out=self.offsets[1:])

    def of(self, nodes: np.ndarray) -> np.ndarray:
        """The cells around any of ``nodes``, sorted, each once."""
        first, last = self.offsets[nodes], self.offsets[nodes + 1]
        counts = last - first
        runs = np.repeat(first - np.cumsum(counts) + counts, counts)
        return np.unique(self.cells[runs + np.arange(counts.sum())])


def _rows(
    block: FibrousShellBlock,
    state: State,
    sums: np.ndarray,
    pull: np.ndarray,
    terms: dict,
    around: _NodeCells,
    run: np.ndarray,
    ring: np.ndarray,
    held: _HeldRows,
    after: np.ndarray | None,
) -> tuple[SparseTangent, _HeldRows]:
    """The rows of the nodes of ``run`` of the whole tangent (docs/theory.md §2.6,
    ``nodal_membrane_tangent`` plus the bending patches) as a (6 n, 6 n) BSR matrix; and the
    rows of H of its ``ring`` (N1, ``_ring``) that the next run's ring ``after`` holds (None:
    no next run). H's rows ``held`` from the run before are taken as they are (the same
    sums)."""
    conn = block.connectivity
    n = block.n_nodes
    at_ring = around.of(ring)  # H's rows at N1 complete
    reach = around.of(np.unique(conn[at_ring]))  # J's rows at N2 complete
    local_nodes, local = np.unique(conn[reach], return_inverse=True)
    pairs = NodePairs(local.reshape(-1, 3), len(local_nodes))
    # the run's nodes that are in cells (a node of none has no row: left out)
    run = run[np.isin(run, local_nodes)]
    rows = row_product.RowProduct(
        pairs.indptr, pairs.indices, pairs.n_nodes, np.searchsorted(local_nodes, run)
    )
    # H's blocks of the pairs read, summed over the cells around N1 (the others' to a spare
    # slot at the end, never read).
    read, read_rows = rows.h_pairs()
    read_rows = local_nodes[read_rows]
    read_keys = read_rows * n + local_nodes[pairs.indices[read]]
    h_blocks = np.zeros((len(read) + 1, 9, 9))
    at = np.minimum(np.searchsorted(held.keys, read_keys), max(len(held.keys) - 1, 0))
    taken = held.keys[at] == read_keys if len(held.keys) else np.zeros(len(read), dtype=bool)
    h_blocks[: len(read)][taken] = held.blocks[at[taken]]
    # Each pair's slot, to read (h_of) and to sum into (the held rows' to the spare one).
    h_of = np.full(pairs.n_pairs, len(read), dtype=np.int64)
    h_of[read] = np.arange(len(read))
    sum_of = np.full(pairs.n_pairs, len(read), dtype=np.int64)
    sum_of[read[~taken]] = np.flatnonzero(~taken)
    # The Hessians of the cells around the rows not held, summed into those rows alone.
    summed = around.of(np.unique(read_rows[~taken]))
    own = np.searchsorted(reach, summed)
    for part in _parts(summed):
        nodes = conn[summed[part]]
        x, v = state.positions[nodes], state.directors[nodes]
        hessian, _ = hessian_kernels.membrane_hessians(block, x, v, sums[nodes], summed[part])
        hessian_kernels.pair_sums(sum_of[pairs.slot[own[part]]], hessian, len(read) + 1, h_blocks)
        del hessian
    keep = np.isin(read_rows, after) if after is not None else np.zeros(len(read), dtype=bool)
    next_held = _HeldRows(read_keys[keep], h_blocks[: len(read)][keep])
    j_blocks = np.zeros((pairs.n_pairs, 3, 3))
    for part in _parts(reach):
        nodes = conn[reach[part]]
        ds_dx = hessian_kernels.normal_share_jacobians(
            state.positions[nodes], block.wall_nodes[nodes]
        )
        ds_dx = on_planes(block, nodes, ds_dx)
        hessian_kernels.pair_sums(pairs.slot[part], ds_dx, pairs.n_pairs, j_blocks)
    data = rows(h_blocks, h_of, j_blocks)
    del h_blocks, j_blocks
    # The bending patches holding a node of the run (all among the cells around N1).
    patch = bending.patch_nodes(block, at_ring)[0]
    bent = at_ring[np.any(np.isin(patch, run), axis=1)]
    for part in _parts(bent):
        cells = bent[part]
        blocks = bending.tangent_blocks(block, state.positions, terms, cells)
        x = state.positions[conn[cells]]
        blocks[:, :3, :, :3] += tangent_kernels.normal_pull_stiffness(x, pull[conn[cells]])
        nodes = np.searchsorted(local_nodes, bending.patch_nodes(block, cells)[0])
        row_product.row_patches(rows, data, nodes, blocks)
    # The global numbering; the blocks that are zero left out: they add nothing to any sum.
    kept = np.any(data != 0.0, axis=(1, 2))
    row_of = np.repeat(run, np.diff(rows.k_indptr))[kept]
    indptr = np.zeros(n + 1, dtype=np.int64)
    np.cumsum(np.bincount(row_of, minlength=n), out=indptr[1:])
    indices = local_nodes[rows.k_indices[kept]]
    matrix = sp.bsr_matrix((data[kept], indices, indptr), shape=(6 * n, 6 * n))
    return SparseTangent(matrix), next_held


def _parts(cells: np.ndarray) -> Iterator[slice]:
    """Slices of ``_HESSIANS`` of ``cells`` at a time."""
    for first in range(0, len(cells), _HESSIANS):
        yield slice(first, min(first + _HESSIANS, len(cells)))
