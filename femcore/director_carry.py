"""Directors carried with the body where nothing holds their tilt (docs/theory.md §1.7,
"Directors carried with the body").

A uniform tilt of the fibrous shell's directors stretches no fibre level (over a flat region the
levels translate in their planes; over a bent one each level slips along itself by the same
amount): a zero-energy mode of every body none of whose directors a support holds. A solver that
moves the nodes leaves that mode where its start put it, fixed in space while the body turns (a
free strip turned rigidly by 30 deg: tilt 30 deg from the normal, thickness along the director
h / cos 30). The quasi-static solvers turn the directors of each such body with the body
instead, by the rotation that fits its nodes' motion best (Kabsch: the polar part of the
covariance of the old and new positions about their centroids), so that a rigid motion carries
its material lines and the tilt relative to the body is what the mechanics decides. Bodies with
a held director (a clamp) are left alone: the support decides the mode there, and the deck of
cards' tilt atan(theta) is nearly the clamp's orientation, not the normal's.

The blocks say which of their cells leave that tilt free (``ElementBlock.free_tilt_cells``).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

if TYPE_CHECKING:
    from femcore.compiled import CompiledModel

__all__ = ["DirectorCarrier", "fitted_rotation"]


def fitted_rotation(before: np.ndarray, after: np.ndarray) -> np.ndarray:
    """The proper rotation (3, 3) that best carries the points ``before`` onto ``after`` (m, 3
    each, mm) about their centroids, in the least-squares sense (Kabsch; the identity for
    fewer than three points or points on a line, whose rotation is not fixed by them)."""
    old = before - before.mean(axis=0)
    new = after - after.mean(axis=0)
    covariance = old.T @ new
    u, singular, vt = np.linalg.svd(covariance)
    if len(before) < 3 or singular[1] <= 1e-12 * max(singular[0], 1e-300):
        return np.eye(3)
    sign = np.sign(np.linalg.det(vt.T @ u.T)) or 1.0
    return vt.T @ np.diag([1.0, 1.0, sign]) @ u.T


class DirectorCarrier:
    """Turns the directors of each free-tilting body of a compiled model with the body.

    Parameters
    ----------
    model : the compiled model. ``DirectorCarrier.of`` gives None for a model with no such body.

    Attributes
    ----------
    bodies : list of (k,) int arrays, the nodes of each connected body of free-tilt cells none
        of whose directors a support holds (alpha or beta fixed or prescribed).
    carried : (n,) bool, the nodes of those bodies.
    """

    def __init__(self, model: CompiledModel):
        cells = [block.free_tilt_cells() for block in model.blocks]
        given = [c for c in cells if c is not None and len(c)]
        self.bodies: list[np.ndarray] = []
        self.carried = np.zeros(model.n_nodes, dtype=bool)
        if not given:
            return
        connectivity = np.concatenate(given)
        n = model.n_nodes
        rows = np.repeat(connectivity, connectivity.shape[1], axis=1).ravel()
        cols = np.tile(connectivity, (1, connectivity.shape[1])).ravel()
        graph = sp.coo_matrix((np.ones(rows.size), (rows, cols)), shape=(n, n))
        _, label = connected_components(graph, directed=False)
        in_body = np.zeros(n, dtype=bool)
        in_body[connectivity] = True
        held = model.dofs.constrained[:, 3:].any(axis=1)
        for body in np.unique(label[in_body]):
            nodes = np.flatnonzero(in_body & (label == body))
            if model.has_rotation[nodes].all() and not held[nodes].any():
                self.bodies.append(nodes)
                self.carried[nodes] = True

    @classmethod
    def of(cls, model: CompiledModel) -> DirectorCarrier | None:
        """A carrier for ``model``, or None where no body's director tilt is free."""
        carrier = cls(model)
        return carrier if carrier.bodies else None

    def carry(self, directors: np.ndarray, before: np.ndarray, after: np.ndarray) -> np.ndarray:
        """``directors`` (n, 3), unit, with those of each body turned by the rotation that
        best fits its nodes' motion from positions ``before`` to ``after`` (mm, (n, 3) each)."""
        out = directors.copy()
        for nodes in self.bodies:
            turn = fitted_rotation(before[nodes], after[nodes])
            turned = directors[nodes] @ turn.T
            out[nodes] = turned / np.linalg.norm(turned, axis=1)[:, None]
        return out
