"""The fibre-length projection of a Newton step of the static solver
(``Static(fibre_projection=True)``, docs/theory.md §6.5).

On a fabric the fibres' tension stiffness per element is thousands of times the bending's
(T L_e^2 / B ~ 7800 on the heavy cantilever of validation/cases). A Newton step that turns a
part of the strip stretches the fibres there by its higher-order remainder (a chord is longer
than its arc; the curved step of solvers.newton_curvature leaves the third-order part), and
the residual of that stretch, times the tension stiffness, dwarfs the bending forces the step
was solving for: the next iterates start from a residual ratio ~1 on tangents with dozens of
negative eigenvalues.

The projection moves the step's end back onto the lengths the step's first order asks for:
with the fibre edges e = (a, b) of the fabric blocks (``fibre_edges``), their lengths l_e at
the iterate and the straight step delta, the target lengths are

    l_e* = l_e + u_e . (delta_b - delta_a),   u_e = (x_b - x_a) / l_e,

(the first-order change of each length along the step, which the tangent's membrane
stiffness has already judged), and a few Gauss-Newton sweeps on the constraints
c_e(x) = |x_b - x_a| - l_e* = 0 find the smallest translation correction that restores
them, in the row space of the constraints' gradient J only (the membrane-stiff directions):

    dx = -J^T (J J^T)^-1 c,

J (k, 3 n_free translations) with rows -u_e at a and +u_e at b, J J^T a sparse (k, k) matrix
on the edge graph (factorised by a sparse LU each sweep; k is two edges per cell). The
bending shape the step found is left as it is to first order (the correction is orthogonal to
every motion that keeps the fibre lengths), the directors are not touched.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from femcore.element import are_node_pairs
from femcore.model import CompiledModel

if TYPE_CHECKING:
    from solvers.static import StaticRun

__all__ = ["PROJECTION_SWEEPS", "PROJECTION_TOLERANCE", "FibreEdges", "fibre_edges"]

# Gauss-Newton sweeps of one projection, and the relative length error (of each edge's
# length) at which they stop: the constraints are quadratic, so each sweep squares the error
# of a remainder that starts at (step / element)^3 ~ 1e-3.
PROJECTION_SWEEPS = 4
PROJECTION_TOLERANCE = 1e-12


def fibre_edges(model: CompiledModel) -> np.ndarray:
    """(k, 2) node pairs of the fibre edges of every element block that gives them (its
    ``fibre_edges()``, femcore.element), each edge once; (0, 2) when there are none."""
    pairs = []
    for block in model.blocks:
        edges = np.asarray(block.fibre_edges())
        if edges.size == 0:
            continue
        # a user block's edges, checked where they are first read: a bare IndexError deep in
        # the projection, or a third column silently dropped, otherwise
        if not are_node_pairs(edges) or edges.min() < 0 or edges.max() >= model.n_nodes:
            raise ValueError(
                f"{type(block).__name__}.fibre_edges() gave an array of shape {edges.shape} "
                f"and type {edges.dtype}: expected (k, 2) int node ids in 0..{model.n_nodes - 1}"
            )
        pairs.append(edges)
    if not pairs:
        return np.zeros((0, 2), dtype=np.int64)
    edges = np.sort(np.concatenate(pairs).astype(np.int64), axis=1)
    return np.unique(edges, axis=0)


class FibreEdges:
    """The fibre-length projection of a model's Newton steps (module docstring).

    model : the compiled model; its fibre edges are those of ``fibre_edges``, and only the
        free translations move (a fixed or prescribed node's position is left as it is).
    """

    def __init__(self, model: CompiledModel):
        self.model = model
        self.edges = fibre_edges(model)
        free = model.dofs.free[:, :3]  # (n, 3) free translations
        self.free = free
        self.column = np.full(free.shape, -1, dtype=np.int64)
        self.column[free] = np.arange(int(free.sum()))
        # Edges with no free end cannot move.
        a, b = self.edges[:, 0], self.edges[:, 1]
        self.edges = self.edges[free[a].any(axis=1) | free[b].any(axis=1)]

    def __bool__(self) -> bool:
        return len(self.edges) > 0

    def project(
        self,
        run: StaticRun,
        positions: np.ndarray,
        straight: np.ndarray,
        delta: np.ndarray,
    ) -> np.ndarray:
        """The step delta (n, 5) with its translations corrected so that the fibre edges end at
        the lengths the first order of ``straight`` (n, 5; the Newton step itself) asks for.

        positions : (n, 3) the iterate's node positions, mm.
        Returns a new (n, 5) step (the rotations of delta unchanged).
        """
        a, b = self.edges[:, 0], self.edges[:, 1]
        chord = positions[b] - positions[a]
        length = np.linalg.norm(chord, axis=1)
        target = length + np.sum(chord * (straight[b, :3] - straight[a, :3]), axis=1) / length
        moved = positions + delta[:, :3]
        for _ in range(PROJECTION_SWEEPS):
            chord = moved[b] - moved[a]
            now = np.linalg.norm(chord, axis=1)
            error = now - target
            if np.abs(error).max(initial=0.0) <= PROJECTION_TOLERANCE * length.max(initial=1.0):
                break
            gradient = self._gradient(chord / now[:, None])
            normal = (gradient @ gradient.T).tocsc()
            try:
                multiplier = spla.splu(normal).solve(error)
            except RuntimeError:  # dependent constraints: no projection
                return delta
            correction = -(gradient.T @ multiplier)
            step = np.zeros_like(moved)
            step[self.free] = correction
            moved = moved + step
            run.info["fibre_projection_sweeps"] += 1
        projected = delta.copy()
        projected[:, :3] = moved - positions
        return projected

    def _gradient(self, unit: np.ndarray) -> sp.csr_matrix:
        """J (k, free translations): the gradient of the edge lengths, rows -u at a, +u at b."""
        k = len(self.edges)
        rows = np.repeat(np.arange(k), 6)
        ends = np.concatenate([self.column[self.edges[:, 0]], self.column[self.edges[:, 1]]], 1)
        values = np.concatenate([-unit, unit], axis=1).ravel()
        columns = ends.ravel()
        held = columns < 0
        return sp.csr_matrix(
            (values[~held], (rows[~held], columns[~held])), shape=(k, int(self.free.sum()))
        )
