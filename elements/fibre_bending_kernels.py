"""The compiled force and energy of the in-plane fibre bending (elements/fibre_bending.py): one
loop over the patches, the same arithmetic as the numpy reference
(elements/fibre_bending_terms.py), each patch's forces added into the nodes as it goes (one
thread: the patches share nodes).
"""

from __future__ import annotations

import math

import numpy as np

from elements.jit import serial

__all__ = ["patch_forces"]


@serial
def _view(m, p, seen, d_m, d_p, d_seen, weight):  # pragma: no cover - compiled
    """atan2(S, C) of ``seen`` in the frame of (m, p) (3,) each; adds ``weight`` times its
    gradients with respect to m, p, seen into d_m, d_p, d_seen (3,) and returns the angle."""
    length = math.sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2])
    t0, t1, t2 = m[0] / length, m[1] / length, m[2] / length
    p_t = p[0] * t0 + p[1] * t1 + p[2] * t2
    u0, u1, u2 = p[0] - p_t * t0, p[1] - p_t * t1, p[2] - p_t * t2
    u_length = math.sqrt(u0 * u0 + u1 * u1 + u2 * u2)
    b0, b1, b2 = u0 / u_length, u1 / u_length, u2 / u_length
    s = seen[0] * b0 + seen[1] * b1 + seen[2] * b2
    c = seen[0] * t0 + seen[1] * t1 + seen[2] * t2
    d = s * s + c * c
    a_s, a_c = c / d, -s / d
    n0 = seen[0] - s * b0 - c * t0
    n1 = seen[1] - s * b1 - c * t1
    n2 = seen[2] - s * b2 - c * t2
    f_m = a_s / (u_length * length)
    g_m = a_c / length
    f_p = a_s / u_length
    d_seen[0] += weight * (a_s * b0 + a_c * t0)
    d_seen[1] += weight * (a_s * b1 + a_c * t1)
    d_seen[2] += weight * (a_s * b2 + a_c * t2)
    d_m[0] += weight * (f_m * (-c * u0 - p_t * n0) + g_m * (seen[0] - c * t0))
    d_m[1] += weight * (f_m * (-c * u1 - p_t * n1) + g_m * (seen[1] - c * t1))
    d_m[2] += weight * (f_m * (-c * u2 - p_t * n2) + g_m * (seen[2] - c * t2))
    d_p[0] += weight * f_p * n0
    d_p[1] += weight * f_p * n1
    d_p[2] += weight * f_p * n2
    return math.atan2(s, c)


@serial
def patch_forces(positions, nodes, ends, stiffness, force):  # pragma: no cover - compiled
    """Adds each patch's k theta d theta / dx into ``force`` (n, 3), N, and returns the energy
    sum 1/2 k theta^2, N mm. positions (n, 3) mm; nodes (P, 5), ends (P, 4, 2) int;
    stiffness (P,) N mm (elements/fibre_bending_patches.py)."""
    vectors = np.empty((4, 3))
    grads = np.empty((4, 3))
    energy = 0.0
    for patch in range(nodes.shape[0]):
        for k in range(4):
            head = nodes[patch, ends[patch, k, 1]]
            tail = nodes[patch, ends[patch, k, 0]]
            for j in range(3):
                vectors[k, j] = positions[head, j] - positions[tail, j]
                grads[k, j] = 0.0
        # theta = (phi_cf - phi_fc) / 2: vectors m_c, p_c, m_f, p_f are rows 0-3
        phi_cf = _view(vectors[0], vectors[1], vectors[2], grads[0], grads[1], grads[2], 0.5)
        phi_fc = _view(vectors[2], vectors[3], vectors[0], grads[2], grads[3], grads[0], -0.5)
        theta = 0.5 * (phi_cf - phi_fc)
        k_theta = stiffness[patch] * theta
        energy += 0.5 * k_theta * theta
        for k in range(4):
            head = nodes[patch, ends[patch, k, 1]]
            tail = nodes[patch, ends[patch, k, 0]]
            for j in range(3):
                g = k_theta * grads[k, j]
                force[head, j] += g
                force[tail, j] -= g
    return energy
