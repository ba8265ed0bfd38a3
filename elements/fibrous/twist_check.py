"""Does the rotation-free bending read a pure twist as fibre curvature on this mesh
(docs/theory.md §4.2, "Twist and the mesh's pattern")?

Bai's curvature estimate (Eq. 35) takes each cell's warp and weft curvatures from the fold
angles across its three sides. A twist of the fibres, w = (n x g1 . r)(n x g2 . r) /
|n x g1 . g2| (zero curvature along both fibres, unit twist), folds every side; on the
one-way pattern of split quads (every cell cut along the same diagonal, Bai's meshes) the
folds of an interior cell cancel in chi_1 and chi_2, on other patterns they do not: on the
alternating pattern (a checkerboard of both diagonals) every interior cell reads chi = +-1
per unit twist, a spurious twisting stiffness H = (B1 + B2) / 2 that refinement keeps, and
two-way bending converges to the wrong plate. This module measures that reading on the
reference geometry, linearised (a fold of a small lift is the jump of the two cells' slopes
across their side), and the block warns when it is not small.
"""

from __future__ import annotations

import warnings

import numpy as np

from elements.fibrous.bending import side_geometry
from femcore.rotation import cross

__all__ = ["TWIST_TOLERANCE", "twist_curvatures", "warn_if_twist_bends"]

#: Root mean square of the fibre curvatures a unit twist gives over the interior cells above
#: which the block warns: 0.1 is a spurious twisting stiffness of about 1 % of (B1 + B2) / 2
#: (the energy is quadratic in the curvature); the one-way pattern gives 1e-15, the
#: alternating one 1.
TWIST_TOLERANCE = 0.1


def twist_curvatures(
    points: np.ndarray,
    connectivity: np.ndarray,
    neighbour: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """The warp-and-weft-ordered curvatures (chi_1, chi_2) each cell reads under a unit twist
    of its own fibres, linearised about the reference.

    Parameters
    ----------
    points : (n, 3) reference positions, mm.
    connectivity : (m, 3) cells, the fibres along sides 0-1 and 0-2.
    neighbour : (m, 3) the cell across side s (opposite corner s), -1 on the boundary.

    Returns
    -------
    chi : (m, 2) fibre curvatures per unit twist (dimensionless: 1/mm per 1/mm); exact
        bending gives 0. Only cells with three neighbours are meaningful (``interior``).
    interior : (m,) bool, the cells whose three sides have a neighbour.
    """
    x = points[connectivity]  # (m, 3 corners, 3)
    geo = side_geometry(x)
    n, outward = geo["normal"], geo["outward"]
    g1 = x[:, 1] - x[:, 0]
    g2 = x[:, 2] - x[:, 0]
    g1 /= np.linalg.norm(g1, axis=1, keepdims=True)
    g2 /= np.linalg.norm(g2, axis=1, keepdims=True)
    p, q = cross(n, g1), cross(n, g2)  # in-plane normals of the fibres
    scale = 1.0 / np.abs(np.sum(p * g2, axis=1))  # unit twist for any fibre angle
    centre = x.mean(axis=1)
    interior = np.asarray((neighbour >= 0).all(axis=1))
    across = np.where(neighbour >= 0, neighbour, np.arange(len(x))[:, None])  # (m, s)

    def lift(y: np.ndarray) -> np.ndarray:
        """The twist of each cell's own frame at points y (m, ..., 3)."""
        shape = (len(x),) + (1,) * (y.ndim - 2) + (3,)
        r = y - centre.reshape(shape)
        return (
            np.sum(r * p.reshape(shape), axis=-1)
            * np.sum(r * q.reshape(shape), axis=-1)
            * scale.reshape(shape[:-1])
        )

    def slope(cells: np.ndarray, values: np.ndarray) -> np.ndarray:
        """Gradient (..., 3) of the linear interpolant of ``values`` (..., 3 corners) on
        ``cells`` (...): sum_k w_k grad N_k, grad N_k = n x (x_q - x_p) / 2A."""
        corners = x[cells]
        normal = n[cells][..., None, :]
        side = corners[..., [2, 0, 1], :] - corners[..., [1, 2, 0], :]
        grad_n = cross(normal, side) / geo["double_area"][cells][..., None, None]
        return np.sum(values[..., None] * grad_n, axis=-2)

    own = slope(np.arange(len(x)), lift(x))  # (m, 3)
    other = slope(across, lift(x[across]))  # (m, s, 3)
    fold = np.sum((other - own[:, None, :]) * outward, axis=-1)  # theta_s, linearised
    # c_as = 2 (g_a . n^c_s)^2 / (h_s + h_s') over the mesh's neighbours (§4.2)
    heights = (geo["double_area"][:, None] + geo["double_area"][across]) / geo["length"]
    fibres = np.stack([g1, g2], axis=1)  # (m, a, 3)
    projection = np.matmul(fibres, outward.transpose(0, 2, 1))  # (m, a, s)
    coefficients = 2.0 * projection**2 / heights[:, None, :]
    chi = -np.matmul(coefficients, fold[:, :, None])[..., 0]
    return chi, interior


def warn_if_twist_bends(
    points: np.ndarray,
    connectivity: np.ndarray,
    neighbour: np.ndarray,
    tolerance: float = TWIST_TOLERANCE,
) -> float:
    """Warn (UserWarning) when a unit twist gives the interior cells fibre curvatures of root
    mean square above ``tolerance`` and a reading sum_e A_e |chi_e|^2 over them above the
    boundary cells' (those with a side without neighbour, which read a twist on every
    pattern: the one-way pattern's first-order error, docs/theory.md §4.2). A line of
    flipped diagonals (a mesh mirrored across a symmetry plane) reads it along the line, a
    share of the cells that falls as the cell, as the boundary does; a mesh that mixes the
    diagonals throughout reads it in every cell, and refinement keeps it.

    Returns the interior cells' root mean square (0 without interior cells). Arguments as
    in :func:`twist_curvatures`."""
    chi, interior = twist_curvatures(points, connectivity, neighbour)
    if not interior.any():
        return 0.0
    rms = float(np.sqrt(np.mean(chi[interior] ** 2)))
    x = points[connectivity]
    area = np.linalg.norm(cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]), axis=1)
    reading = area * np.sum(chi**2, axis=1)
    inside, edge = float(reading[interior].sum()), float(reading[~interior].sum())
    if rms > tolerance and inside > edge:
        warnings.warn(
            f"FibrousShell: on this mesh the rotation-free bending reads a pure twist as fibre "
            f"curvature throughout (root mean square {rms:.3g} per unit twist over "
            f"{int(interior.sum())} interior cells, {inside / max(edge, 1e-300):.3g} times the "
            f"boundary cells' reading; 0 inside the one-way pattern of split quads): two-way "
            f"bending then converges to a plate with a spurious twisting stiffness of about "
            f"{rms**2:.3g} (B1 + B2) / 2 (on Mesh.rectangle(..., diagonals='alternating') 0.50 "
            f"of the Navier deflection of a pinned square plate). Mesh the sheet as "
            f"Mesh.rectangle's default one-way diagonals, every cell cut alike "
            f"(docs/theory.md §4.2).",
            UserWarning,
            stacklevel=2,
        )
    return rms
