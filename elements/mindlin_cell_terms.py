"""The per-cell pieces that the compiled loops of the Mindlin triangle share: the elastic tangent
(elements/mindlin_tangent.py) and the fabric section's tangent, loads and section measures
(elements/mindlin_fabric_tangent.py, _loads.py, _measures.py); docs/theory.md §5.5, §5.7.

Each piece works on one cell ``cell`` of the loop's corner arrays, into scratch arrays the
loop allocated (once a cell or once a chunk of cells), and is spliced into its callers
(femcore/jit.py ``inline``: numba's ``inline="always"``, the helper's IR copied into every
call site): called, a helper with array arguments costs their reference counting at every
call, several times the work of these small pieces. Spliced, each loop runs the operations
it ran when it spelled them out, in the same order: the same numbers to the last bit.

The vectors of a level zeta_z, as the numpy path (elements/mindlin.py ``_vectors``) lays
them out: vec[z, 0] = g1, vec[z, 1] = g2 (the covariant vectors at the level), vec[z, 2 + t]
= g3 at the tying point t = A, B, C (the same at every level).

Each piece runs loops of fixed length only (a level, a row, a corner at a time; the callers
loop over the levels and rows): a spliced helper's array arguments are new references,
counted up where it starts and down where it ends, which numba's reference-count pruning
takes out only when the end follows the start on every path; LLVM splits a loop of variable
length into paths (none, some), and a helper with such a loop over the levels kept the counts
in every cell: the section measures' loop took 87 ns a cell against 45 with the same code
spelled out (10,000 cells, one thread).
"""

from __future__ import annotations

from femcore.jit import inline

__all__ = [
    "bending_spin_blocks",
    "clear_stress_terms",
    "level_measures",
    "level_vectors",
    "measure_entries",
    "measure_row",
    "section_stresses",
    "stress_terms",
    "turned_vectors",
    "tying_vectors",
]


@inline
def tying_vectors(v, cell, half, tying_n, g3):
    """g3 (3, 3), mm: g3 = h/2 sum_k N_k(T) V_k at the tying points T = A, B, C (§5.3) of
    cell ``cell`` of the unit directors v (m, 3, 3); ``half`` = h/2 (mm), ``tying_n`` (3, 3)
    the shape functions at the tying points."""
    for t in range(3):
        for c in range(3):
            total = 0.0
            for node in range(3):
                total += tying_n[t, node] * v[cell, node, c]
            g3[t, c] = half * total


@inline
def level_vectors(x, v, cell, zeta, z, half, g3, vec):
    """vec[z] (5, 3), mm: g1 = x_1 - x_0 + zeta_z h/2 (V_1 - V_0), g2 likewise (eq. 5.5.1) of
    cell ``cell`` of the corner positions x and unit directors v (m, 3, 3) at level zeta[z],
    and the tying points' g3 (3, 3) (``tying_vectors``)."""
    for c in range(3):
        vec[z, 0, c] = (x[cell, 1, c] - x[cell, 0, c]) + zeta[z] * half * (
            v[cell, 1, c] - v[cell, 0, c]
        )
        vec[z, 1, c] = (x[cell, 2, c] - x[cell, 0, c]) + zeta[z] * half * (
            v[cell, 2, c] - v[cell, 0, c]
        )
    for t in range(3):
        for c in range(3):
            vec[z, 2 + t, c] = g3[t, c]


@inline
def turned_vectors(v, cell, vec, z, turned):
    """turned (3, 5, 3), mm: V_a x g_u for the corners a and the five vectors g_u of level
    ``z`` of ``vec`` (``level_vectors``), the director columns' arms (eq. 5.5.3, 5.5.5)."""
    for a in range(3):
        for u in range(5):
            turned[a, u, 0] = v[cell, a, 1] * vec[z, u, 2] - v[cell, a, 2] * vec[z, u, 1]
            turned[a, u, 1] = v[cell, a, 2] * vec[z, u, 0] - v[cell, a, 0] * vec[z, u, 2]
            turned[a, u, 2] = v[cell, a, 0] * vec[z, u, 1] - v[cell, a, 1] * vec[z, u, 0]


@inline
def level_measures(vec, z, cell, ref11, ref22, ref12, ref_tying, e):
    """e[z] (7,), mm^2: the level measures (E11, E22, 2E12, and the changes of g1.g3^A,
    g1.g3^C, g2.g3^B, g2.g3^C; eq. 5.5.2) of level ``z`` of ``vec`` against the reference
    products ref11, ref22, ref12 (m, Z) and ref_tying (m, Z, 4) of cell ``cell``; each
    product summed component by component."""
    d00 = d11 = d01 = d02 = d04 = d13 = d14 = 0.0
    for c in range(3):
        d00 += vec[z, 0, c] * vec[z, 0, c]
        d11 += vec[z, 1, c] * vec[z, 1, c]
        d01 += vec[z, 0, c] * vec[z, 1, c]
        d02 += vec[z, 0, c] * vec[z, 2, c]
        d04 += vec[z, 0, c] * vec[z, 4, c]
        d13 += vec[z, 1, c] * vec[z, 3, c]
        d14 += vec[z, 1, c] * vec[z, 4, c]
    e[z, 0] = 0.5 * (d00 - ref11[cell, z])
    e[z, 1] = 0.5 * (d11 - ref22[cell, z])
    e[z, 2] = d01 - ref12[cell, z]
    e[z, 3] = d02 - ref_tying[cell, z, 0]
    e[z, 4] = d04 - ref_tying[cell, z, 1]
    e[z, 5] = d13 - ref_tying[cell, z, 2]
    e[z, 6] = d14 - ref_tying[cell, z, 3]


@inline
def measure_entries(gradient, vec, turned, z, r, a, c):
    """The entries of row ``r`` of B^psi_z (``measure_row``) in columns (a, u, c) and
    (a, psi, c): sum_u f g_u[c] and sum_u f' (V_a x g_u)[c] over the product coefficients
    ``gradient`` (Z, 7, 6, 5) (elements/mindlin_tables.py), mm."""
    along = 0.0
    turn = 0.0
    for u in range(5):
        along += gradient[z, r, a, u] * vec[z, u, c]
        turn += gradient[z, r, 3 + a, u] * turned[a, u, c]
    return along, turn


@inline
def measure_row(gradient, vec, turned, z, r, b_psi):
    """b_psi[z, r] (18,): row ``r`` of B^psi_z, the derivatives of level ``z``'s measure r in
    (corner a, u | psi, component) columns (eq. 5.5.3), from the product coefficients
    ``gradient`` (Z, 7, 6, 5) (elements/mindlin_tables.py), ``vec`` (``level_vectors``) and
    ``turned`` (``turned_vectors`` of level ``z``)."""
    for a in range(3):
        for c in range(3):
            along, turn = measure_entries(gradient, vec, turned, z, r, a, c)
            b_psi[z, r, 6 * a + c] = along
            b_psi[z, r, 6 * a + 3 + c] = turn


@inline
def section_stresses(dw_dy, cell, sigma):
    """sigma (3, 7), N mm: the level stresses P^T dW/dy of a fabric section (docs/theory.md
    §5.7) from the gradient dw_dy (m, 10) of cell ``cell``: membrane and tying at the
    mid-surface, half the bending ones at the outer levels (opposite signs), zero on the
    outer levels' tying rows."""
    for z in range(3):
        for r in range(7):
            sigma[z, r] = 0.0
    for r in range(3):
        sigma[1, r] = dw_dy[cell, r]
        sigma[2, r] = 0.5 * dw_dy[cell, 3 + r]
        sigma[0, r] = -0.5 * dw_dy[cell, 3 + r]
    for r in range(4):
        sigma[1, 3 + r] = dw_dy[cell, 6 + r]


@inline
def clear_stress_terms(director_gradient, geometric):
    """Zeroes dW/dV_a (3, 3) and G (6, 6), which a cell's ``stress_terms`` add to."""
    for a in range(3):
        for c in range(3):
            director_gradient[a, c] = 0.0
    for p in range(6):
        for q in range(6):
            geometric[p, q] = 0.0


@inline
def stress_terms(sigma, gradient, curvature, vec, z, r, director_gradient, geometric):
    """Adds the part of stress sigma[z, r] (N mm) of level ``z`` to dW/dV_a
    (``director_gradient`` (3, 3), N mm) and to the geometric coefficients G = sum_r sigma_r
    d2e_r/ds2 (``geometric`` (6, 6), N mm; eq. 5.5.4) from the product coefficients
    ``gradient`` (Z, 7, 6, 5) and ``curvature`` (Z, 7, 6, 6)."""
    s = sigma[z, r]
    for a in range(3):
        for u in range(5):
            weight = s * gradient[z, r, 3 + a, u]
            for c in range(3):
                director_gradient[a, c] += weight * vec[z, u, c]
    for p in range(6):
        for q in range(6):
            geometric[p, q] += s * curvature[z, r, p, q]


@inline
def bending_spin_blocks(v, cell, geometric, director_gradient, arms, k):
    """Completes the tangent k (18, 18) of cell ``cell`` whose upper triangle holds the
    material part B^T (d2W/de2) B: mirrors it below the diagonal, adds the geometric part
    (the block of slots (t, a), (t', b) is G P_at P_bt'^T with P_a0 = I and P_a1 = [V_a]x,
    ``arms`` (3, 2, 3, 3) scratch) and the spin term (V_a g_a^T - (g_a . V_a) I) on the
    director blocks, g_a = dW/dV_a (eq. 5.5.5); v (m, 3, 3) the unit directors."""
    for row in range(18):
        for col in range(row):
            k[row, col] = k[col, row]
    for a in range(3):
        for i in range(3):
            for j in range(3):
                arms[a, 0, i, j] = 1.0 if i == j else 0.0
            arms[a, 1, i, i] = 0.0
        arms[a, 1, 0, 1], arms[a, 1, 0, 2] = -v[cell, a, 2], v[cell, a, 1]
        arms[a, 1, 1, 0], arms[a, 1, 1, 2] = v[cell, a, 2], -v[cell, a, 0]
        arms[a, 1, 2, 0], arms[a, 1, 2, 1] = -v[cell, a, 1], v[cell, a, 0]
    for a in range(3):
        for t in range(2):
            for b in range(3):
                for t2 in range(2):
                    coefficient = geometric[3 * t + a, 3 * t2 + b]
                    if coefficient == 0.0:
                        continue
                    for i in range(3):
                        for j in range(3):
                            product = 0.0
                            for c in range(3):
                                product += arms[a, t, i, c] * arms[b, t2, j, c]
                            k[6 * a + 3 * t + i, 6 * b + 3 * t2 + j] += coefficient * product
    # turning V_a turns the arm of m_a = V_a x g_a
    for a in range(3):
        along = 0.0
        for c in range(3):
            along += director_gradient[a, c] * v[cell, a, c]
        for i in range(3):
            for j in range(3):
                k[6 * a + 3 + i, 6 * a + 3 + j] += v[cell, a, i] * director_gradient[a, j]
            k[6 * a + 3 + i, 6 * a + 3 + i] -= along
