"""The fibrous shell's tangent a slice of cells at a time (docs/theory.md §2.6, §6.2).

``tangent.tangent`` forms the membrane's J^T H J and the bending patches of all cells at once:
30 kB a triangle at its peak with nodal normals, for a bound (the explicit solver's
assembled stable step, femcore/gershgorin.py) that only sums the tangent's blocks per node
pair. Here the same tangent comes as pieces whose sum it is, each made, given and dropped:

* the membrane of a slice C of cells: K_C = J^T H_C J with H_C the Hessians of C's cells
  alone (W is a sum of cell energies, so K = sum_C K_C) and J the rows dS_k/dx_j of the
  nodes k of C, complete (every cell around k), found on the cells around C's nodes
  (``_NodeCells``) numbered locally and multiplied by the compiled product of the whole
  (tangent_kernels.MembraneProduct) on that local pattern;
* the bending patches of C's cells with the normal sums' second derivatives (T_k = dW/dS_k,
  the nodal sums of every cell's dW/dS, from the force loops' first passes).

The pieces sum to the whole tangent to round-off (a node pair's blocks added slice by slice
instead of all at once). Element normals, or the numpy path: the whole tangent in one piece.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp

from elements.base import CellTangent, SparseTangent
from elements.fibrous import bending, hessian_kernels, kernels, tangent_kernels
from elements.fibrous.geometry import normal_sums
from elements.fibrous.tangent import CornerPairs, tangent
from femcore.assembly import TangentPart
from femcore.state import State

if TYPE_CHECKING:
    from elements.fibrous.block import FibrousShellBlock

__all__ = ["tangent_pieces"]

# Cells per piece: a piece's local membrane product and bending blocks, a few tens of MB.
PIECE = 4096
# Cells whose Hessians are held at once within a piece (6 MB).
_HESSIANS = 1024


def tangent_pieces(block: FibrousShellBlock, state: State) -> Iterator[TangentPart]:
    """``tangent.tangent`` in pieces whose sum it is: per slice of ``PIECE`` cells, in the
    cells' order, the membrane's J^T H_C J (SparseTangent, BSR with 6 x 6 blocks over all
    nodes, its blocks that are zero left out) then the slice's bending patches
    (CellTangent). Element normals or no compiled loops: the parts of ``tangent``."""
    if not (block.nodal_normals and block.compiled and hessian_kernels.AVAILABLE):
        yield from tangent(block, state)
        return
    conn = block.connectivity
    m, n = len(conn), block.n_nodes
    positions = state.positions
    sums = normal_sums(block, positions)
    # T_k = dW/dS_k, the nodal sums of every cell's dW/dS (the force loops' first passes).
    pull = kernels.normal_pulls(block, positions, state.directors)
    terms = bending.tangent_terms(block, positions)
    around = _NodeCells(conn, n)
    for start in range(0, m, PIECE):
        cells = slice(start, min(start + PIECE, m))
        blocks = bending.tangent_blocks(block, positions, terms, cells)
        x = positions[conn[cells]]
        blocks[:, :3, :, :3] += tangent_kernels.normal_pull_stiffness(x, pull[conn[cells]])
        patch = CellTangent(bending.patch_nodes(block, cells)[0], blocks)
        yield _piece(block, state, sums, around, cells, patch)


class _NodeCells:
    """The cells around each node (CSR over the nodes), to find a slice's halo."""

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


def _piece(
    block: FibrousShellBlock,
    state: State,
    sums: np.ndarray,
    around: _NodeCells,
    cells: slice,
    bend: CellTangent,
) -> SparseTangent:
    """J^T H_C J of the slice ``cells`` (docs/theory.md §2.6, ``nodal_membrane_tangent``) plus
    the slice's bending blocks ``bend`` (translations, on the patch nodes) as a (6 n, 6 n)
    BSR matrix: H_C from the slice's cells, J's rows of their nodes from every cell around
    those nodes (the halo F, numbered locally). J's rows of the halo's other nodes are
    incomplete but meet only H_C's zero rows and columns. One piece, not two: the bound
    sums a node's row once no piece holds it, and the bending's narrower patch would let
    go of the nodes the next slice's membrane reaches back to."""
    conn = block.connectivity
    n = block.n_nodes
    halo = around.of(np.unique(conn[cells]))  # sorted: the slice is a run of it
    local_nodes, local = np.unique(conn[halo], return_inverse=True)
    local = local.reshape(-1, 3)
    pairs = CornerPairs(local, len(local_nodes))
    own = np.searchsorted(halo, np.arange(cells.start, cells.stop))
    h_blocks = np.zeros((pairs.n_pairs, 9, 9))
    # The slice's Hessians (5.8 kB a cell) formed and summed ``_HESSIANS`` cells at a time.
    for first in range(cells.start, cells.stop, _HESSIANS):
        part = slice(first, min(first + _HESSIANS, cells.stop))
        nodes = conn[part]
        x, v = state.positions[nodes], state.directors[nodes]
        hessian, _ = hessian_kernels.membrane_hessians(block, x, v, sums[nodes], part)
        within = own[part.start - cells.start : part.stop - cells.start]
        hessian_kernels.pair_sums(pairs.slot[within], hessian, pairs.n_pairs, h_blocks)
        del hessian
    x_halo = state.positions[conn[halo]]
    ds_dx = hessian_kernels.normal_share_jacobians(x_halo, block.wall_nodes[conn[halo]])
    j_blocks = hessian_kernels.pair_sums(pairs.slot, ds_dx, pairs.n_pairs)
    product = tangent_kernels.MembraneProduct(pairs.indptr, pairs.indices, pairs.n_nodes)
    matrix = product(h_blocks, j_blocks)
    tangent_kernels.add_patches(matrix, np.searchsorted(local_nodes, bend.nodes), bend.blocks)
    data = matrix.data.reshape(-1, 6, 6)
    # The global numbering; the blocks that are zero (the halo's rows beyond J's reach of
    # C) left out: they add nothing to any sum, and a node they named would stay open.
    kept = np.any(data != 0.0, axis=(1, 2))
    rows = np.repeat(local_nodes, np.diff(matrix.indptr))[kept]
    indptr = np.zeros(n + 1, dtype=np.int64)
    np.cumsum(np.bincount(rows, minlength=n), out=indptr[1:])
    indices = local_nodes[matrix.indices[kept]]
    global_matrix = sp.bsr_matrix((data[kept], indices, indptr), shape=(6 * n, 6 * n))
    return SparseTangent(global_matrix)
