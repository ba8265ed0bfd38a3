"""The compiled force and energy of the in-plane fibre bending (elements/fibre_bending.py): one
loop over the patches calling the numpy reference's own functions compiled
(elements/fibre_bending_terms.py ``turning``), each patch's forces added into the nodes as it
goes (one thread: the patches share nodes).
"""

from __future__ import annotations

import math

import numpy as np

from elements.fibre_bending_terms import turning
from elements.jit import serial

__all__ = ["patch_forces"]


@serial
def patch_forces(positions, nodes, ends, stiffness, force):  # pragma: no cover - compiled
    """Adds each patch's k theta d theta / dx into ``force`` (n, 3), N, and returns the energy
    sum 1/2 k theta^2, N mm. positions (n, 3) mm; nodes (P, 5), ends (P, 4, 2) int;
    stiffness (P,) N mm (elements/fibre_bending_patches.py)."""
    vectors = np.empty((4, 3))
    energy = 0.0
    for patch in range(nodes.shape[0]):
        for k in range(4):
            head = nodes[patch, ends[patch, k, 1]]
            tail = nodes[patch, ends[patch, k, 0]]
            for j in range(3):
                vectors[k, j] = positions[head, j] - positions[tail, j]
        s, c, g_mc, g_pc, g_mf, g_pf = turning(
            (vectors[0, 0], vectors[0, 1], vectors[0, 2]),
            (vectors[1, 0], vectors[1, 1], vectors[1, 2]),
            (vectors[2, 0], vectors[2, 1], vectors[2, 2]),
            (vectors[3, 0], vectors[3, 1], vectors[3, 2]),
        )
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
