"""The MITC3 Mindlin triangle's strain energy, corner forces and director moments of one cell
(docs/theory.md §5.5), spliced into the compiled passes over the cells (elements/kernels.py):
``_mindlin_cells``, which writes each cell's loads into a buffer that a pass over the nodes
sums (on any number of threads), and ``_mindlin_nodal``, which adds them to the nodes as it
goes, in cell order (on one thread).

The corner loads of ``_mindlin_nodal`` reach each node in the order of its cells, from 0.0,
as ``_node_sums6`` adds them: the two give the same numbers to the last bit
(tests/test_mindlin_nodal.py). On one thread the loads need no buffer: the (m, 3, 6) array of
144 bytes a cell that the cells' pass wrote and the nodes' pass read again at every step
(benchmarks/explicit_step.py).
"""

from __future__ import annotations

from femcore.jit import inline, serial

__all__ = ["cell_loads", "edge", "mindlin_nodal"]


@inline
def edge(positions, a, b):
    """The edge x_b - x_a between nodes a and b of positions (n, 3): three scalars."""
    return (
        positions[b, 0] - positions[a, 0],
        positions[b, 1] - positions[a, 1],
        positions[b, 2] - positions[a, 2],
    )


@inline
def _director_moment(ux, uy, uz, vx, vy, vz, na, nb, nc, half, q):
    """The moment V x dW/dV of a corner (three scalars): ``u`` the in-plane levels' part of
    dW/dV, to which g3^T = h/2 sum_k N_k(T) V_k adds h/2 (N_A q_A + N_B q_B + N_C q_C), ``q``
    the nine sums dW/dg3 at A, B, C; (na, nb, nc) the corner's N_k at A, B, C."""
    qax, qay, qaz, qbx, qby, qbz, qcx, qcy, qcz = q
    ux += half * (na * qax + nb * qbx + nc * qcx)
    uy += half * (na * qay + nb * qby + nc * qcy)
    uz += half * (na * qaz + nb * qbz + nc * qcz)
    return vy * uz - vz * uy, vz * ux - vx * uz, vx * uy - vy * ux


@inline
def cell_loads(positions, directors, n0, n1, n2, c, zeta, half, reference, stiffness, tying_n,
               with_forces, with_energy):  # fmt: skip
    """Cell c's strain energy and, with ``with_forces``, its corner forces and director
    moments, of corners n0, n1, n2.

    By level (docs/theory.md §5.5): the seven level measures e = (E11, E22, 2E12, and the
    changes of the tying products g1.g3^A, g1.g3^C, g2.g3^B, g2.g3^C) from the products of
    the current vectors less ``reference`` (m, Z, 7), their conjugates sigma = D^ e with the
    level stiffness ``stiffness`` (m, Z, 28, the packed upper triangle of the symmetric
    7 x 7, the in-plane points and the assumed shear summed in at bind), W = 1/2 sum e . sigma,
    and the loads sigma . de/ds. Three-vectors are kept in scalars.

    Returns 16 scalars: 2 W (N mm; 0 without ``with_energy``, its sums left out); dW/dx1
    and dW/dx2 (the forces on corners 1 and 2, N; on corner 0 minus their sum); the director
    moments of corners 0, 1, 2 (N mm). Without ``with_forces`` all but the first are 0."""
    nz = zeta.shape[0]
    d1x, d1y, d1z = edge(positions, n0, n1)
    d2x, d2y, d2z = edge(positions, n0, n2)
    v0x, v0y, v0z = directors[n0, 0], directors[n0, 1], directors[n0, 2]
    v1x, v1y, v1z = directors[n1, 0], directors[n1, 1], directors[n1, 2]
    v2x, v2y, v2z = directors[n2, 0], directors[n2, 1], directors[n2, 2]
    w1x, w1y, w1z = half * (v1x - v0x), half * (v1y - v0y), half * (v1z - v0z)
    w2x, w2y, w2z = half * (v2x - v0x), half * (v2y - v0y), half * (v2z - v0z)
    # g3 at the tying points A, B, C: h/2 sum_k N_k(T) V_k
    ax = half * (tying_n[0, 0] * v0x + tying_n[0, 1] * v1x + tying_n[0, 2] * v2x)
    ay = half * (tying_n[0, 0] * v0y + tying_n[0, 1] * v1y + tying_n[0, 2] * v2y)
    az = half * (tying_n[0, 0] * v0z + tying_n[0, 1] * v1z + tying_n[0, 2] * v2z)
    bx = half * (tying_n[1, 0] * v0x + tying_n[1, 1] * v1x + tying_n[1, 2] * v2x)
    by = half * (tying_n[1, 0] * v0y + tying_n[1, 1] * v1y + tying_n[1, 2] * v2y)
    bz = half * (tying_n[1, 0] * v0z + tying_n[1, 1] * v1z + tying_n[1, 2] * v2z)
    cx = half * (tying_n[2, 0] * v0x + tying_n[2, 1] * v1x + tying_n[2, 2] * v2x)
    cy = half * (tying_n[2, 0] * v0y + tying_n[2, 1] * v1y + tying_n[2, 2] * v2y)
    cz = half * (tying_n[2, 0] * v0z + tying_n[2, 1] * v1z + tying_n[2, 2] * v2z)
    t1x = t1y = t1z = t2x = t2y = t2z = 0.0  # sums over z of p1, p2
    a1x = a1y = a1z = a2x = a2y = a2z = 0.0  # sums over z of zeta p1, zeta p2
    qax = qay = qaz = qbx = qby = qbz = qcx = qcy = qcz = 0.0  # dW/dg3 at A, B, C
    stored = 0.0  # 2 W
    for z in range(nz):
        zz = zeta[z]
        g1x, g1y, g1z = d1x + zz * w1x, d1y + zz * w1y, d1z + zz * w1z
        g2x, g2y, g2z = d2x + zz * w2x, d2y + zz * w2y, d2z + zz * w2z
        r = reference[c, z]
        e0 = 0.5 * (g1x * g1x + g1y * g1y + g1z * g1z - r[0])
        e1 = 0.5 * (g2x * g2x + g2y * g2y + g2z * g2z - r[1])
        e2 = g1x * g2x + g1y * g2y + g1z * g2z - r[2]
        e3 = g1x * ax + g1y * ay + g1z * az - r[3]
        e4 = g1x * cx + g1y * cy + g1z * cz - r[4]
        e5 = g2x * bx + g2y * by + g2z * bz - r[5]
        e6 = g2x * cx + g2y * cy + g2z * cz - r[6]
        k = stiffness[c, z]
        s0 = k[0] * e0 + k[1] * e1 + k[2] * e2 + k[3] * e3 + k[4] * e4 + k[5] * e5 + k[6] * e6
        s1 = k[1] * e0 + k[7] * e1 + k[8] * e2 + k[9] * e3 + k[10] * e4 + k[11] * e5
        s1 += k[12] * e6
        s2 = k[2] * e0 + k[8] * e1 + k[13] * e2 + k[14] * e3 + k[15] * e4 + k[16] * e5
        s2 += k[17] * e6
        s3 = k[3] * e0 + k[9] * e1 + k[14] * e2 + k[18] * e3 + k[19] * e4 + k[20] * e5
        s3 += k[21] * e6
        s4 = k[4] * e0 + k[10] * e1 + k[15] * e2 + k[19] * e3 + k[22] * e4 + k[23] * e5
        s4 += k[24] * e6
        s5 = k[5] * e0 + k[11] * e1 + k[16] * e2 + k[20] * e3 + k[23] * e4 + k[25] * e5
        s5 += k[26] * e6
        s6 = k[6] * e0 + k[12] * e1 + k[17] * e2 + k[21] * e3 + k[24] * e4 + k[26] * e5
        s6 += k[27] * e6
        if with_energy:
            stored += e0 * s0 + e1 * s1 + e2 * s2 + e3 * s3 + e4 * s4 + e5 * s5 + e6 * s6
        if not with_forces:
            continue
        # dW/dg1, dW/dg2 at this level; dW/dg3 at A, B, C
        p1x = s0 * g1x + s2 * g2x + s3 * ax + s4 * cx
        p1y = s0 * g1y + s2 * g2y + s3 * ay + s4 * cy
        p1z = s0 * g1z + s2 * g2z + s3 * az + s4 * cz
        p2x = s1 * g2x + s2 * g1x + s5 * bx + s6 * cx
        p2y = s1 * g2y + s2 * g1y + s5 * by + s6 * cy
        p2z = s1 * g2z + s2 * g1z + s5 * bz + s6 * cz
        t1x += p1x
        t1y += p1y
        t1z += p1z
        t2x += p2x
        t2y += p2y
        t2z += p2z
        a1x += zz * p1x
        a1y += zz * p1y
        a1z += zz * p1z
        a2x += zz * p2x
        a2y += zz * p2y
        a2z += zz * p2z
        qax += s3 * g1x
        qay += s3 * g1y
        qaz += s3 * g1z
        qbx += s5 * g2x
        qby += s5 * g2y
        qbz += s5 * g2z
        qcx += s4 * g1x + s6 * g2x
        qcy += s4 * g1y + s6 * g2y
        qcz += s4 * g1z + s6 * g2z
    if not with_forces:
        return (stored, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    q = (qax, qay, qaz, qbx, qby, qbz, qcx, qcy, qcz)
    m0x, m0y, m0z = _director_moment(
        -half * (a1x + a2x), -half * (a1y + a2y), -half * (a1z + a2z), v0x, v0y, v0z,
        tying_n[0, 0], tying_n[1, 0], tying_n[2, 0], half, q,
    )  # fmt: skip
    m1x, m1y, m1z = _director_moment(
        half * a1x, half * a1y, half * a1z, v1x, v1y, v1z,
        tying_n[0, 1], tying_n[1, 1], tying_n[2, 1], half, q,
    )  # fmt: skip
    m2x, m2y, m2z = _director_moment(
        half * a2x, half * a2y, half * a2z, v2x, v2y, v2z,
        tying_n[0, 2], tying_n[1, 2], tying_n[2, 2], half, q,
    )  # fmt: skip
    return (
        stored, t1x, t1y, t1z, t2x, t2y, t2z,
        m0x, m0y, m0z, m1x, m1y, m1z, m2x, m2y, m2z,
    )  # fmt: skip


@serial
def _mindlin_nodal(
    positions, directors, connectivity, zeta, half, reference, stiffness, tying_n, with_forces,
    with_energy, force, moment, energy,
):  # fmt: skip
    """``_mindlin_cells`` on one thread with its corner loads added to the nodes as each cell
    is done: ``force``, ``moment`` (n, 3), zeros on entry, get each cell's corner forces and
    director moments in cell order; with ``with_energy``, ``energy`` (m,) each cell's strain
    energy, N mm (without, ``energy`` is not written: a step that does not check the energy
    balance skips the sums e . sigma)."""
    for c in range(connectivity.shape[0]):
        n0, n1, n2 = connectivity[c, 0], connectivity[c, 1], connectivity[c, 2]
        (
            stored, t1x, t1y, t1z, t2x, t2y, t2z,
            m0x, m0y, m0z, m1x, m1y, m1z, m2x, m2y, m2z,
        ) = cell_loads(
            positions, directors, n0, n1, n2, c, zeta, half, reference, stiffness, tying_n,
            with_forces, with_energy,
        )  # fmt: skip
        if with_energy:
            energy[c] = 0.5 * stored
        if not with_forces:
            continue
        force[n0, 0] += -(t1x + t2x)
        force[n0, 1] += -(t1y + t2y)
        force[n0, 2] += -(t1z + t2z)
        force[n1, 0] += t1x
        force[n1, 1] += t1y
        force[n1, 2] += t1z
        force[n2, 0] += t2x
        force[n2, 1] += t2y
        force[n2, 2] += t2z
        moment[n0, 0] += m0x
        moment[n0, 1] += m0y
        moment[n0, 2] += m0z
        moment[n1, 0] += m1x
        moment[n1, 1] += m1y
        moment[n1, 2] += m1z
        moment[n2, 0] += m2x
        moment[n2, 1] += m2y
        moment[n2, 2] += m2z


mindlin_nodal = _mindlin_nodal
