"""Continuum-based shell geometry shared by the fibrous and the Mindlin shells (docs/theory.md §1).

Everything is vectorised over the triangles of a block (leading axis = cell) or over nodes.
Local nodes 1, 2, 3 of the paper are columns 0, 1, 2 here.
"""

from __future__ import annotations

import numpy as np

from femcore.rotation import drop_along, nodal_frames, rotate_about

__all__ = [
    "GUARD",
    "director_increment",
    "drop_along",
    "element_areas",
    "element_normals",
    "guarded_thickness",
    "lumped_mass",
    "nodal_frames",
    "nodal_thickness",
    "rotate_about",
    "thickness_along_director",
]

# Smallest V.n used in h_m = h / (V.n) (docs/theory.md §1.4): a director within ~78 deg of the
# surface
# would give an unbounded thickness; nodes that hit the guard are counted and reported.
GUARD = 0.2


def director_increment(directors: np.ndarray, d_alpha: np.ndarray, d_beta: np.ndarray):
    """Directors after increments (d_alpha, d_beta) of the nodal rotations, (n, 3).

    The rotation vector psi = d_beta V1 + d_alpha V2 lies in the plane normal to V; turning V
    by it (Rodrigues) is, to first order, Bai Eq. 13: V+ = V + d_alpha V1 - d_beta V2, but keeps
    |V| = 1 exactly (docs/theory.md §1.3).
    """
    v1, v2 = nodal_frames(directors)
    psi = np.asarray(d_beta)[:, None] * v1 + np.asarray(d_alpha)[:, None] * v2
    return rotate_about(directors, psi)


def _edges(positions: np.ndarray, triangles: np.ndarray):
    corners = positions[triangles]
    return corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]


def element_normals(positions: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """Unit element normals n_e = (x2 - x1) x (x3 - x1) / |...| (Bai Eq. 15), (m, 3)."""
    a, b = _edges(positions, triangles)
    cross = np.cross(a, b)
    return cross / np.linalg.norm(cross, axis=1)[:, None]


def element_areas(positions: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """Triangle areas (m,), mm^2."""
    a, b = _edges(positions, triangles)
    return 0.5 * np.linalg.norm(np.cross(a, b), axis=1)


def thickness_along_director(
    thickness: float | np.ndarray,
    directors: np.ndarray,
    triangles: np.ndarray,
    normals: np.ndarray,
    guard: float = GUARD,
) -> tuple[np.ndarray, np.ndarray]:
    """Thickness measured along the director at each node of each element (Bai Eq. 10, 14).

    h_m^{k,e} = h / max(V_k . n_e, guard), so that h_m (V . n) = h: the thickness measured
    along the normal is conserved while the director tilts.

    thickness : h, mm (scalar or (m,) per element); directors : (n, 3) unit;
    triangles : (m, 3); normals : (m, 3) unit element normals.
    Returns h_m (m, 3), mm, and a (m, 3) bool mask of the corners that hit the guard.
    """
    cosine = np.matmul(directors[triangles], normals[:, :, None])[..., 0]
    return guarded_thickness(thickness, cosine, guard)


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
