"""The compiled force and energy of the in-plane fibre bending (elements/fibre_bending.py): one
loop over the patches calling the numpy reference's own functions compiled
(elements/fibre_bending_terms.py ``turning``), each patch's forces added into the nodes as it
goes (one thread: the patches share nodes).
"""

from __future__ import annotations

import math

import numpy as np

from elements.fibre_bending_terms import turning
from femcore.jit import serial

__all__ = ["patch_forces", "patch_spring_bounds"]


@serial
def _patch_turning(positions, nodes, ends, patch, vectors):  # pragma: no cover - compiled
    """``turning`` of patch ``patch``'s four fibre vectors (head less tail of each segment),
    written into ``vectors`` (4, 3) mm on the way."""
    for k in range(4):
        head = nodes[patch, ends[patch, k, 1]]
        tail = nodes[patch, ends[patch, k, 0]]
        for j in range(3):
            vectors[k, j] = positions[head, j] - positions[tail, j]
    return turning(
        (vectors[0, 0], vectors[0, 1], vectors[0, 2]),
        (vectors[1, 0], vectors[1, 1], vectors[1, 2]),
        (vectors[2, 0], vectors[2, 1], vectors[2, 2]),
        (vectors[3, 0], vectors[3, 1], vectors[3, 2]),
    )


@serial
def patch_forces(positions, nodes, ends, stiffness, force):  # pragma: no cover - compiled
    """Adds each patch's k theta d theta / dx into ``force`` (n, 3), N, and returns the energy
    sum 1/2 k theta^2, N mm. positions (n, 3) mm; nodes (P, 5), ends (P, 4, 2) int;
    stiffness (P,) N mm (elements/fibre_bending_patches.py)."""
    vectors = np.empty((4, 3))
    energy = 0.0
    for patch in range(nodes.shape[0]):
        s, c, g_mc, g_pc, g_mf, g_pf = _patch_turning(positions, nodes, ends, patch, vectors)
        theta = math.atan2(s, c)
        k_theta = stiffness[patch] * theta
        energy += 0.5 * k_theta * theta
        for k, g in enumerate((g_mc, g_pc, g_mf, g_pf)):
            head = nodes[patch, ends[patch, k, 1]]
            tail = nodes[patch, ends[patch, k, 0]]
            for j in range(3):
                force[head, j] += k_theta * g[j]
                force[tail, j] -= k_theta * g[j]
    return energy


@serial
def patch_spring_bounds(positions, nodes, ends, stiffness, step, springs):  # pragma: no cover
    """Adds into ``springs`` (P, 5), N/mm, each patch's bound of its stiffness
    K = k (g g^T + theta H) in the four vectors (elements/fibre_bending_terms.py
    ``vector_spring_bounds``, the numpy reference): vector k's block Gershgorin sum e_k,
    twice, at its head and its tail. H, the Hessian of theta with respect to the vectors, is
    the forward difference of ``turning``'s gradient over ``step`` (P,) mm. positions (n, 3)
    mm; nodes (P, 5), ends (P, 4, 2) int; stiffness (P,) N mm."""
    vectors = np.empty((4, 3))
    shifted = np.empty((4, 3))
    grad = np.empty(12)
    stiff = np.empty((12, 12))
    for patch in range(nodes.shape[0]):
        s, c, g0, g1, g2, g3 = _patch_turning(positions, nodes, ends, patch, vectors)
        theta = math.atan2(s, c)
        for k, g in enumerate((g0, g1, g2, g3)):
            for j in range(3):
                grad[3 * k + j] = g[j]
        h = step[patch]
        for column in range(12):
            for k in range(4):
                for j in range(3):
                    shifted[k, j] = vectors[k, j]
            shifted[column // 3, column % 3] += h
            _, _, z0, z1, z2, z3 = turning(
                (shifted[0, 0], shifted[0, 1], shifted[0, 2]),
                (shifted[1, 0], shifted[1, 1], shifted[1, 2]),
                (shifted[2, 0], shifted[2, 1], shifted[2, 2]),
                (shifted[3, 0], shifted[3, 1], shifted[3, 2]),
            )
            for k, z in enumerate((z0, z1, z2, z3)):
                for j in range(3):
                    row = 3 * k + j
                    stiff[row, column] = stiffness[patch] * (
                        grad[row] * grad[column] + theta * (z[j] - grad[row]) / h
                    )
        # vector-space block Gershgorin: e_k = sum_l |K_kl| bounds K by diag(e_k) on the
        # vectors, and |v_k|^2 = |x_head - x_tail|^2 <= 2 (|x_head|^2 + |x_tail|^2)
        for k in range(4):
            total = 0.0
            for m in range(4):
                norm2 = 0.0
                for i in range(3):
                    for j in range(3):
                        entry = stiff[3 * k + i, 3 * m + j]
                        norm2 += entry * entry
                total += math.sqrt(norm2)
            springs[patch, ends[patch, k, 1]] += 2.0 * total  # fmt: skip
            springs[patch, ends[patch, k, 0]] += 2.0 * total
