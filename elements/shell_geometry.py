"""The fibrous shell's thickness along the directors and lumped masses (docs/theory.md §1.4,
§1.6): the guard of h_m = h / (V . n), the nodal mean of per-element values and the lumped
mass and rotary inertia of Bai Eq. 38-39. Used by elements/fibrous (the Mindlin shell keeps
its own, elements/mindlin.py).

Everything is vectorised over the triangles of a block (leading axis = cell) or over nodes.
Local nodes 1, 2, 3 of the paper are columns 0, 1, 2 here.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "GUARD",
    "guarded_thickness",
    "lumped_mass",
    "nodal_thickness",
]

# Smallest V.n used in h_m = h / (V.n) (docs/theory.md §1.4): a director within ~78 deg of the
# surface would give an unbounded thickness; nodes that hit the guard are counted and reported.
GUARD = 0.2


def guarded_thickness(
    thickness: float | np.ndarray, cosine: np.ndarray, guard: float = GUARD
) -> tuple[np.ndarray, np.ndarray]:
    """h_m = h / max(V . n, guard) from the cosines V_k . n_e (m, 3) (Bai Eq. 10, 14), and the
    (m, 3) bool mask of the corners that hit the guard."""
    h = np.asarray(thickness, dtype=float)
    h = h[:, None] if h.ndim == 1 else h
    return h / np.maximum(cosine, guard), cosine < guard


def nodal_thickness(
    per_element: np.ndarray, areas: np.ndarray, triangles: np.ndarray, n_nodes: int
) -> np.ndarray:
    """Area-weighted nodal mean (n,) of a per-element nodal value (m, 3), e.g. h_m for the
    rotary inertia (docs/theory.md §1.4); zero at nodes no triangle touches."""
    weight = np.repeat(areas, 3)
    nodes = triangles.ravel()
    total = np.bincount(nodes, weights=weight * per_element.ravel(), minlength=n_nodes)
    area = np.bincount(nodes, weights=weight, minlength=n_nodes)
    return np.divide(total, area, out=np.zeros(n_nodes), where=area > 0)


def lumped_mass(
    areal_density: float | np.ndarray,
    reference_areas: np.ndarray,
    triangles: np.ndarray,
    thickness_at_nodes: np.ndarray,
    n_nodes: int,
) -> tuple[np.ndarray, np.ndarray]:
    """Lumped translational mass and rotary inertia (Bai Eq. 38-39).

    m_k = sum over elements of rho_A A0 / 3 (HRZ: every integral of N_k^2 over a linear triangle
    is A/6, so the three nodes share equally); I_k = m_k (h_m^k)^2 / 4 for both rotations,
    with h_m^k the nodal thickness along the director.

    areal_density : rho_A, t/mm^2 (scalar or (m,)); reference_areas : A0 (m,), mm^2.
    Returns m (n,), t and I (n,), t mm^2.
    """
    share = np.broadcast_to(
        np.asarray(areal_density, dtype=float) * reference_areas / 3.0, reference_areas.shape
    )
    mass = np.bincount(triangles.ravel(), weights=np.repeat(share, 3), minlength=n_nodes)
    return mass, mass * thickness_at_nodes**2 / 4.0
