"""Gather nodal arrays into per-cell arrays and scatter per-cell vectors back to the nodes.

The index arrays are built once (when an element block is bound to a mesh); a time step then
costs one fancy-indexing gather and one ``np.bincount`` per scattered field, with no Python loop
over cells or nodes.
"""

from __future__ import annotations

import numpy as np


class Scatter:
    """Precomputed scatter of per-cell nodal vectors to the global nodes.

    Parameters
    ----------
    connectivity : (m, k) int, the k nodes of each of the m cells (a cell may be a 2-node
        cable, a 3-node triangle, or a 6-node bending patch).
    n_nodes : number of global nodes.
    """

    def __init__(self, connectivity: np.ndarray, n_nodes: int):
        connectivity = np.asarray(connectivity, dtype=np.int64)
        if connectivity.ndim != 2:
            raise ValueError(f"connectivity must be (cells, nodes), got shape {connectivity.shape}")
        if connectivity.size and (connectivity.min() < 0 or connectivity.max() >= n_nodes):
            raise ValueError(f"connectivity refers to nodes outside 0..{n_nodes - 1}")
        self.connectivity = connectivity
        self.n_nodes = int(n_nodes)
        # Flat index of (node, component) for 3-vectors: one bincount scatters all components.
        self._flat3 = (connectivity[:, :, None] * 3 + np.arange(3)).ravel()
        self._flat1 = connectivity.ravel()

    def gather(self, nodal: np.ndarray) -> np.ndarray:
        """Per-cell copy of a nodal array: (n, ...) -> (m, k, ...)."""
        return nodal[self.connectivity]

    def vectors(self, per_cell: np.ndarray) -> np.ndarray:
        """Sum per-cell nodal 3-vectors into nodes: (m, k, 3) -> (n, 3)."""
        return np.bincount(
            self._flat3, weights=per_cell.ravel(), minlength=3 * self.n_nodes
        ).reshape(self.n_nodes, 3)

    def scalars(self, per_cell: np.ndarray) -> np.ndarray:
        """Sum per-cell nodal scalars into nodes: (m, k) -> (n,)."""
        return np.bincount(self._flat1, weights=per_cell.ravel(), minlength=self.n_nodes)
