"""The warp and weft directions of each cell in the deformed state, for output: the fibres
convected with the cell's mid-surface (docs/theory.md §9.3b, "The plies' fields").

A fibre of unit reference direction a in a cell's plane is a = alpha^1 G_1 + alpha^2 G_2 on
the reference edges G_1 = X_1 - X_0, G_2 = X_2 - X_0; the cell maps it to alpha^1 g_1 + alpha^2
g_2 on the current edges, whose unit vector is the fibre's current direction. The components
(alpha, beta) are found once from the reference; the directions cost two edge differences per
cell. The weft is the cell normal's turn of the warp, n x a, at the reference."""

from __future__ import annotations

import numpy as np

from femcore.field_names import name_components

__all__ = ["block_fibre_directions", "fibre_components", "fibre_directions"]

for _name in ("warp_direction", "weft_direction"):
    name_components(_name, ("x", "y", "z"))  # global axes


def fibre_components(points: np.ndarray, triangles: np.ndarray, warp: np.ndarray) -> np.ndarray:
    """The contravariant components of the unit warp and weft on each cell's reference edges.

    Parameters
    ----------
    points : (n, 3) float, mm
        Reference positions.
    triangles : (m, 3) int
        The cells' nodes.
    warp : (3,) float
        The warp direction, projected on each cell's plane (a cell normal to it has no
        component and gets NaN directions).

    Returns
    -------
    (m, 2, 2) float, 1/mm
        [cell, family (0 warp, 1 weft), edge (G_1, G_2)].
    """
    x = np.asarray(points, dtype=float)[triangles]
    g1, g2 = x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]
    normal = np.cross(g1, g2)
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    a = np.asarray(warp, dtype=float)[None, :] - (normal @ warp)[:, None] * normal
    with np.errstate(invalid="ignore", divide="ignore"):
        a /= np.linalg.norm(a, axis=1, keepdims=True)
    b = np.cross(normal, a)
    metric = np.stack(
        [
            np.stack([np.sum(g1 * g1, 1), np.sum(g1 * g2, 1)], -1),
            np.stack([np.sum(g1 * g2, 1), np.sum(g2 * g2, 1)], -1),
        ],
        axis=-2,
    )  # (m, 2, 2)
    right = np.stack(
        [
            np.stack([np.sum(a * g1, 1), np.sum(a * g2, 1)], -1),
            np.stack([np.sum(b * g1, 1), np.sum(b * g2, 1)], -1),
        ],
        axis=-1,
    )  # (m, 2 edges, 2 families)
    return np.swapaxes(np.linalg.solve(metric, right), -1, -2)


def fibre_directions(
    positions: np.ndarray, triangles: np.ndarray, components: np.ndarray
) -> dict[str, np.ndarray]:
    """{"warp_direction", "weft_direction"}: (m, 3) unit vectors in global axes, the fibres of
    ``fibre_components`` carried by each cell to ``positions`` (n, 3), mm."""
    x = positions[triangles]
    edges = np.stack([x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]], axis=1)  # (m, 2, 3)
    fibres = np.einsum("mfe,mej->mfj", components, edges)
    with np.errstate(invalid="ignore", divide="ignore"):
        fibres /= np.linalg.norm(fibres, axis=-1, keepdims=True)
    return {"warp_direction": fibres[:, 0], "weft_direction": fibres[:, 1]}


def block_fibre_directions(block, state) -> dict[str, np.ndarray]:
    """A fabric block's warp_direction and weft_direction (m, 3) at ``state`` (its cells'
    ``fibre_components`` on its ``connectivity``); none for a block pickled before it kept
    their components (a checkpoint of an earlier run)."""
    components = getattr(block, "fibre_components", None)
    if components is None:
        return {}
    return fibre_directions(state.positions, block.connectivity, components)
