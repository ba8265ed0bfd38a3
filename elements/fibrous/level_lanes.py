"""The fibre levels of a chunk of cells as loops across the cells (structure of arrays), for the
fibrous cells' pass (kernels.py ``_cells_pass``): the pass gathers ``CHUNK`` cells' edges,
levers and normals into the rows of one scratch array (``lanes``: ROWS * CHUNK doubles, a row
a quantity, a column a cell), then runs, level by level, three loops over the chunk's cells:

1. ``level_lanes``: each cell's fibre vectors, log strains and shear angle (cell_terms.py
   ``level_strains``: the same arithmetic as the strains pass, its log and arcsine
   branch-free, elements/lane_maths.py), straight-line code that LLVM runs as many cells at a
   time as its tuning of the host asks: 8 on the AMD EPYC (znver4), 4 on the Intel Xeon of
   AVX-512 that LLVM names rocketlake (256-bit vectors preferred; benchmarks/vector_width.py),
   4 with AVX2;
2. ``law_lanes``: the laws' values (and energies) of those strains: three linear laws (the
   presets' tension and shear) in one loop across the cells (``linear_lanes``); else each
   law over the strains of its family (warp, weft, shear) at once (``law_row``): an odd
   polynomial by loops across the cells, one a coefficient, vectorised as 1; a table cell
   by cell (its segment searched);
3. ``load_lanes``: the tension and shear loads dW/dg_a of the level and their sums over the
   levels (Eq. 24-33), vectorised as 1;

and, once the levels are summed, ``moment_lanes``: the director moments, dW/dS_k and the
corner forces from those sums and the corners' frames (gathered with the edges), vectorised
as 1, the pass copying them cell by cell into its outputs: the force takes 0.85 of the time
it took with them formed cell by cell after the levels, the frames read again (the same
numbers to the last bit; benchmarks/explicit_step.py). Each is compiled without reference
counting (femcore/jit.py ``lane_rows``): the arrays it is given are the pass's own, and
their increfs and decrefs at every call cost the force 4 %.

Each cell's sums run over the levels in the order of the scalar pass, and every operation is
the one it did, so that the cells' pass gives the numbers it gave cell by cell (but for the
log and arcsine, within 1 and 2 units in the last place of the library's).
"""

from __future__ import annotations

import numpy as np

from elements.fibrous.cell_terms import director_moment, level_strains
from elements.fibrous.packed_laws import _POLYNOMIAL, law_energy, law_value
from femcore.jit import lane_rows

__all__ = [
    "CHUNK",
    "ROWS",
    "law_lanes",
    "level_lanes",
    "linear_lanes",
    "load_lanes",
    "moment_lanes",
]

# Cells a chunk: the scratch array (ROWS x CHUNK doubles, 27 kB) stays in the level-1 cache.
# (A change here needs the kernels' numba caches cleared: the cache of kernels.py does not see
# a change of this module's constants.)
CHUNK = 32
# The rows of the scratch array (``lanes``: ROWS * CHUNK doubles, one dimension, row k at
# k * CHUNK: the rows' distances are constants, from which LLVM knows that no two rows
# overlap; with a 2-D array's run-time stride it would test each pair of rows first, too many
# tests to vectorise): the cell's inputs (gathered by the cells' pass) ...
R1X, R1Y, R1Z, R2X, R2Y, R2Z = (k * CHUNK for k in range(0, 6))  # edges x1 - x0, x2 - x0
L1X, L1Y, L1Z, L2X, L2Y, L2Z = (k * CHUNK for k in range(6, 12))  # cell_terms.corner_levers
NX, NY, NZ, AREA, SIGN = (k * CHUNK for k in range(12, 17))  # normal, reference area, sign
# ... a level's strains (level_lanes) ...
G1X, G1Y, G1Z, G2X, G2Y, G2Z = (k * CHUNK for k in range(17, 23))
SQUARE1, SQUARE2, Q1, Q2 = (k * CHUNK for k in range(23, 27))
E1X, E1Y, E1Z, E2X, E2Y, E2Z = (k * CHUNK for k in range(27, 33))
OVER1, OVER2, INVERSE, COS, EPS1, EPS2, GAMMA = (k * CHUNK for k in range(33, 40))
# ... its laws' values (law_lanes) ...
TENSION1, TENSION2, SHEAR = (k * CHUNK for k in range(40, 43))
# ... and the sums over the levels (load_lanes, law_lanes; zeroed by the cells' pass) ...
S1X, S1Y, S1Z, S2X, S2Y, S2Z = (k * CHUNK for k in range(43, 49))  # sum_f dW/dg_a
A1X, A1Y, A1Z, A2X, A2Y, A2Z = (k * CHUNK for k in range(49, 55))  # sum_f zeta_f dW/dg_a
LX, LY, LZ = (k * CHUNK for k in range(55, 58))  # dW/dn
TENSION_ENERGY, SHEAR_ENERGY = (k * CHUNK for k in range(58, 60))
# ... and the level's references (gathered by level_lanes).
REFERENCE1, REFERENCE2, REFERENCE_SHEAR = (k * CHUNK for k in range(60, 63))
# ... and the laws' rows (law_lanes): 1 where edge 0 -> 1 is warp (else 0; gathered by the
# cells' pass), the strains by family, a power and a square, each law's value and energy.
WARP_FIRST, WARP, WEFT, POWER, SQUARE = (k * CHUNK for k in range(63, 68))
VALUE0, VALUE1, VALUE2, ENERGY0, ENERGY1, ENERGY2 = (k * CHUNK for k in range(68, 74))
# The corners' frames (cell_terms.py ``corner_frame``; gathered by the cells' pass for
# ``moment_lanes``): corner k's rows from FRAME0, FRAME1, FRAME2, each quantity at its offset:
# V, V . N, h_m, N, 1 / |S|, 1 / max(V . N, guard); and the cell's double area |c|.
FRAME0, FRAME1, FRAME2 = (k * CHUNK for k in range(74, 104, 10))
VX, VY, VZ, COSINE, HM, WX, WY, WZ, LENGTH, OVER = (k * CHUNK for k in range(10))
DOUBLE_AREA = 104 * CHUNK
# ``moment_lanes``' results, in the level's rows (free once the last level's loads are
# summed): corner k's director moment (3 rows from MOMENT + 3 k rows) and dW/dS_k (from
# D_SUM), the forces on corners 1 and 2 (F1X ...; corner 0's is minus their sum).
MOMENT, D_SUM = 17 * CHUNK, 26 * CHUNK
F1X, F1Y, F1Z, F2X, F2Y, F2Z = (k * CHUNK for k in range(35, 41))
ROWS = 105


@lane_rows
def level_lanes(
    lanes, count, start, f, z, nodal, reference_length1, reference_length2, reference_shear
):  # fmt: skip
    """Level f (zeta_f = ``z``) of the chunk's ``count`` cells (cells start, start + 1, ...):
    cell_terms.py ``level_strains`` of each from its inputs' rows, its results written in
    their rows. Returns how many of the cells have a fibre of zero length in their plane
    (their strains are then inf or nan: the pass raises)."""
    # the level's references first, in rows of their own: LLVM does not vectorise a loop that
    # reads a column of a 2-D argument (it cannot bound the addresses it would check)
    for i in range(count):
        lanes[REFERENCE1 + i] = reference_length1[start + i, f]
        lanes[REFERENCE2 + i] = reference_length2[start + i, f]
        lanes[REFERENCE_SHEAR + i] = reference_shear[start + i, f]
    zero = 0
    for i in range(count):
        (
            g1x, g1y, g1z, g2x, g2y, g2z, square1, square2, q1, q2, e1x, e1y, e1z, e2x,
            e2y, e2z, over1, over2, inverse, cos, eps1, eps2, gamma,
        ) = level_strains(
            z, lanes[R1X + i], lanes[R1Y + i], lanes[R1Z + i], lanes[R2X + i], lanes[R2Y + i],
            lanes[R2Z + i], lanes[L1X + i], lanes[L1Y + i], lanes[L1Z + i], lanes[L2X + i],
            lanes[L2Y + i], lanes[L2Z + i], nodal, lanes[NX + i], lanes[NY + i], lanes[NZ + i],
            lanes[REFERENCE1 + i], lanes[REFERENCE2 + i], lanes[SIGN + i],
            lanes[REFERENCE_SHEAR + i],
        )  # fmt: skip
        # l_1^2 l_2^2, the divisor of level_strains' one division (times L_1^2 L_2^2 > 0)
        fibres = (e1x * e1x + e1y * e1y + e1z * e1z) * (e2x * e2x + e2y * e2y + e2z * e2z)
        zero += fibres == 0.0
        lanes[G1X + i], lanes[G1Y + i], lanes[G1Z + i] = g1x, g1y, g1z
        lanes[G2X + i], lanes[G2Y + i], lanes[G2Z + i] = g2x, g2y, g2z
        lanes[SQUARE1 + i], lanes[SQUARE2 + i] = square1, square2
        lanes[Q1 + i], lanes[Q2 + i] = q1, q2
        lanes[E1X + i], lanes[E1Y + i], lanes[E1Z + i] = e1x, e1y, e1z
        lanes[E2X + i], lanes[E2Y + i], lanes[E2Z + i] = e2x, e2y, e2z
        lanes[OVER1 + i], lanes[OVER2 + i], lanes[INVERSE + i] = over1, over2, inverse
        lanes[COS + i], lanes[EPS1 + i], lanes[EPS2 + i], lanes[GAMMA + i] = cos, eps1, eps2, gamma
    return zero


@lane_rows
def law_lanes(lanes, count, weight, law_integers, law_reals, with_forces, with_energy):
    """The packed laws (packed_laws.py; 0, 1, 2: warp tension, weft tension, shear) of the
    level's strains: with ``with_forces`` their values in the rows TENSION1, TENSION2 (along
    edges 0-1 and 0-2) and SHEAR; with ``with_energy`` the level's energies A0 w_f W added to
    the cells' sums (``weight`` w_f). Three linear laws (odd polynomials of one coefficient,
    the presets' tension and shear) by one loop across the chunk (``linear_lanes``); else
    each law over the chunk's strains of its family at once (``law_row``), then each cell's
    values and energies by its edges' families."""
    if (
        law_integers[0, 0] == _POLYNOMIAL
        and law_integers[1, 0] == _POLYNOMIAL
        and law_integers[2, 0] == _POLYNOMIAL
        and law_integers[0, 1] == 1
        and law_integers[1, 1] == 1
        and law_integers[2, 1] == 1
    ):
        linear_lanes(lanes, count, weight, law_integers, law_reals, with_forces, with_energy)
        return
    for i in range(count):
        warp_first = lanes[WARP_FIRST + i] != 0.0
        eps1, eps2 = lanes[EPS1 + i], lanes[EPS2 + i]
        lanes[WARP + i] = eps1 if warp_first else eps2
        lanes[WEFT + i] = eps2 if warp_first else eps1
    # The law and its rows as constants: numba builds law_row once per row k (0, 1, 2: three
    # builds, about 1.1 s of CPU each from an empty cache), each with its rows' offsets known; the
    # force is 5 % faster for it than with one build given them as int64 values (the same
    # bits; benchmarks/suite_signatures.py)
    law_row(lanes, count, law_integers, law_reals, 0, WARP, VALUE0, ENERGY0, with_forces,
            with_energy)  # fmt: skip
    law_row(lanes, count, law_integers, law_reals, 1, WEFT, VALUE1, ENERGY1, with_forces,
            with_energy)  # fmt: skip
    law_row(lanes, count, law_integers, law_reals, 2, GAMMA, VALUE2, ENERGY2, with_forces,
            with_energy)  # fmt: skip
    for i in range(count):
        warp_first = lanes[WARP_FIRST + i] != 0.0
        if with_energy:
            w = lanes[AREA + i] * weight  # A0 w_f
            # W(law 1, eps1) + W(law 2, eps2): the warp's and the weft's, in either order
            lanes[TENSION_ENERGY + i] += w * (lanes[ENERGY0 + i] + lanes[ENERGY1 + i])
            lanes[SHEAR_ENERGY + i] += w * lanes[ENERGY2 + i]
        if with_forces:
            warp, weft = lanes[VALUE0 + i], lanes[VALUE1 + i]
            lanes[TENSION1 + i] = warp if warp_first else weft
            lanes[TENSION2 + i] = weft if warp_first else warp
            lanes[SHEAR + i] = lanes[VALUE2 + i]


@lane_rows
def linear_lanes(lanes, count, weight, law_integers, law_reals, with_forces, with_energy):
    """``law_lanes`` for three linear laws y = c x (W = c x^2 / 2; 0 below 0 where a law is
    tension-only) in one loop across the chunk, each value and energy by ``law_row``'s
    operations (0 + c x, 0 + c x^2 / 2: the same numbers to the last bit, -0 included). The
    eleven loops of the force's laws (two here, three in each ``law_row``) and their rows'
    loads and stores took 0.030 µs a cell of the three levels' lanes run alone, this loop
    0.005; the force takes 0.98 of its time (benchmarks/explicit_step.py)."""
    warp_c, weft_c, shear_c = law_reals[0, 0, 0], law_reals[1, 0, 0], law_reals[2, 0, 0]
    warp_both = law_integers[0, 3] != 0  # acts in compression too
    weft_both = law_integers[1, 3] != 0
    shear_both = law_integers[2, 3] != 0
    for i in range(count):
        warp_first = lanes[WARP_FIRST + i] != 0.0
        eps1, eps2, gamma = lanes[EPS1 + i], lanes[EPS2 + i], lanes[GAMMA + i]
        warp = eps1 if warp_first else eps2
        weft = eps2 if warp_first else eps1
        if with_energy:
            warp_w = 0.0 + warp_c * (warp * warp) / 2
            weft_w = 0.0 + weft_c * (weft * weft) / 2
            shear_w = 0.0 + shear_c * (gamma * gamma) / 2
            warp_w = warp_w if warp_both or not warp < 0.0 else 0.0
            weft_w = weft_w if weft_both or not weft < 0.0 else 0.0
            shear_w = shear_w if shear_both or not gamma < 0.0 else 0.0
            w = lanes[AREA + i] * weight  # A0 w_f
            lanes[TENSION_ENERGY + i] += w * (warp_w + weft_w)
            lanes[SHEAR_ENERGY + i] += w * shear_w
        if with_forces:
            warp_t = 0.0 + warp_c * warp
            weft_t = 0.0 + weft_c * weft
            shear_t = 0.0 + shear_c * gamma
            warp_t = warp_t if warp_both or not warp < 0.0 else 0.0
            weft_t = weft_t if weft_both or not weft < 0.0 else 0.0
            lanes[TENSION1 + i] = warp_t if warp_first else weft_t
            lanes[TENSION2 + i] = weft_t if warp_first else warp_t
            lanes[SHEAR + i] = shear_t if shear_both or not gamma < 0.0 else 0.0


@lane_rows
def law_row(lanes, count, integers, reals, k, source, value, energy, with_forces, with_energy):
    """Packed law k's value and energy (packed_laws.py ``law_value``, ``law_energy``: the same
    operations in the same order) of the row ``source`` in the rows ``value`` and
    ``energy``: an odd polynomial by loops across the cells, one a coefficient; a table cell
    by cell (its segment searched)."""
    if integers[k, 0] != _POLYNOMIAL:
        for i in range(count):
            x = lanes[source + i]
            if with_forces:
                lanes[value + i] = law_value(integers, reals, k, x)
            if with_energy:
                lanes[energy + i] = law_energy(integers, reals, k, x)
        return
    for i in range(count):
        x = lanes[source + i]
        lanes[SQUARE + i] = x * x
    if with_forces:  # y = sum c_j x^(2j+1)
        for i in range(count):
            lanes[value + i] = 0.0
            lanes[POWER + i] = lanes[source + i]
        for j in range(integers[k, 1]):
            coefficient = reals[k, 0, j]
            for i in range(count):
                lanes[value + i] += coefficient * lanes[POWER + i]
                lanes[POWER + i] *= lanes[SQUARE + i]
    if with_energy:  # W = sum c_j x^(2j+2) / (2j+2)
        for i in range(count):
            lanes[energy + i] = 0.0
            lanes[POWER + i] = lanes[SQUARE + i]
        for j in range(integers[k, 1]):
            coefficient = reals[k, 0, j]
            for i in range(count):
                lanes[energy + i] += coefficient * lanes[POWER + i] / (2 * j + 2)
                lanes[POWER + i] *= lanes[SQUARE + i]
    if integers[k, 3] == 0:  # tension only: nothing below 0
        for i in range(count):
            negative = lanes[source + i] < 0.0
            if with_forces:
                lanes[value + i] = 0.0 if negative else lanes[value + i]
            if with_energy:
                lanes[energy + i] = 0.0 if negative else lanes[energy + i]


@lane_rows
def load_lanes(lanes, count, z, weight):
    """The level's loads on each cell of the chunk, added to the sums over the levels: tension
    (Eq. 24-27) dW/dg_a = A0 w_f T_a P g_a / l_a^2 (P g = g without nodal normals) and its
    pull on n; shear (Eq. 30-33) d gamma = sign (dg1 . t1 / |g1| + dg2 . t2 / |g2|), t1 /
    |g1| = (g2 / (|g1| |g2|) - cos g1 / |g1|^2) / sin, and t2 / |g2| likewise."""
    for i in range(count):
        w = lanes[AREA + i] * weight  # A0 w_f
        k1 = w * lanes[TENSION1 + i] * lanes[OVER1 + i]
        k2 = w * lanes[TENSION2 + i] * lanes[OVER2 + i]
        e1x, e1y, e1z = lanes[E1X + i], lanes[E1Y + i], lanes[E1Z + i]
        e2x, e2y, e2z = lanes[E2X + i], lanes[E2Y + i], lanes[E2Z + i]
        q1, q2 = lanes[Q1 + i], lanes[Q2 + i]
        p1x, p1y, p1z = k1 * e1x, k1 * e1y, k1 * e1z
        p2x, p2y, p2z = k2 * e2x, k2 * e2y, k2 * e2z
        lanes[LX + i] -= k1 * q1 * e1x + k2 * q2 * e2x
        lanes[LY + i] -= k1 * q1 * e1y + k2 * q2 * e2y
        lanes[LZ + i] -= k1 * q1 * e1z + k2 * q2 * e2z
        cos, inverse = lanes[COS + i], lanes[INVERSE + i]
        sin = np.sqrt(max(1.0 - cos * cos, 1e-24))
        shear_moment = w * lanes[SIGN + i] * lanes[SHEAR + i] / sin
        c1 = cos * inverse * inverse  # cos / (|g1| |g2|)^2: cos / |g1|^2 and cos / |g2|^2
        c1, c2 = c1 * lanes[SQUARE2 + i], c1 * lanes[SQUARE1 + i]
        g1x, g1y, g1z = lanes[G1X + i], lanes[G1Y + i], lanes[G1Z + i]
        g2x, g2y, g2z = lanes[G2X + i], lanes[G2Y + i], lanes[G2Z + i]
        p1x += shear_moment * (g2x * inverse - c1 * g1x)
        p1y += shear_moment * (g2y * inverse - c1 * g1y)
        p1z += shear_moment * (g2z * inverse - c1 * g1z)
        p2x += shear_moment * (g1x * inverse - c2 * g2x)
        p2y += shear_moment * (g1y * inverse - c2 * g2y)
        p2z += shear_moment * (g1z * inverse - c2 * g2z)
        lanes[S1X + i] += p1x
        lanes[S1Y + i] += p1y
        lanes[S1Z + i] += p1z
        lanes[S2X + i] += p2x
        lanes[S2Y + i] += p2y
        lanes[S2Z + i] += p2z
        lanes[A1X + i] += z * p1x
        lanes[A1Y + i] += z * p1y
        lanes[A1Z + i] += z * p1z
        lanes[A2X + i] += z * p2x
        lanes[A2Y + i] += z * p2y
        lanes[A2Z + i] += z * p2z


@lane_rows
def moment_lanes(lanes, count, nodal, guard, variation):
    """The director moments (Eq. 28) and corner forces (Eq. 24) of the chunk's cells from the
    sums over their levels and their corners' frames (rows from FRAME0), as the cells' pass
    wrote them cell by cell (cell_terms.py ``director_moment``: the same operations in the
    same order), in the rows from MOMENT, D_SUM (dW/dS_k with nodal normals) and F1X: one
    loop across the cells, vectorised as ``level_lanes``. The pull of the normal n = c / |c|
    on c = a x b is g = P dW/dn / |c| with nodal normals, else the corners' pulls on n
    divided by |c| (dc_k = (V_k - c_k n) . dc / |c|)."""
    for i in range(count):
        a1x, a1y, a1z = lanes[A1X + i], lanes[A1Y + i], lanes[A1Z + i]
        a2x, a2y, a2z = lanes[A2X + i], lanes[A2Y + i], lanes[A2Z + i]
        m0x, m0y, m0z, d0x, d0y, d0z = director_moment(
            -(a1x + a2x), -(a1y + a2y), -(a1z + a2z), lanes[FRAME0 + VX + i],
            lanes[FRAME0 + VY + i], lanes[FRAME0 + VZ + i], lanes[FRAME0 + HM + i],
            lanes[FRAME0 + COSINE + i], lanes[FRAME0 + WX + i], lanes[FRAME0 + WY + i],
            lanes[FRAME0 + WZ + i], lanes[FRAME0 + LENGTH + i], lanes[FRAME0 + OVER + i],
            guard, variation,
        )  # fmt: skip
        m1x, m1y, m1z, d1x, d1y, d1z = director_moment(
            a1x, a1y, a1z, lanes[FRAME1 + VX + i], lanes[FRAME1 + VY + i],
            lanes[FRAME1 + VZ + i], lanes[FRAME1 + HM + i], lanes[FRAME1 + COSINE + i],
            lanes[FRAME1 + WX + i], lanes[FRAME1 + WY + i], lanes[FRAME1 + WZ + i],
            lanes[FRAME1 + LENGTH + i], lanes[FRAME1 + OVER + i], guard, variation,
        )  # fmt: skip
        m2x, m2y, m2z, d2x, d2y, d2z = director_moment(
            a2x, a2y, a2z, lanes[FRAME2 + VX + i], lanes[FRAME2 + VY + i],
            lanes[FRAME2 + VZ + i], lanes[FRAME2 + HM + i], lanes[FRAME2 + COSINE + i],
            lanes[FRAME2 + WX + i], lanes[FRAME2 + WY + i], lanes[FRAME2 + WZ + i],
            lanes[FRAME2 + LENGTH + i], lanes[FRAME2 + OVER + i], guard, variation,
        )  # fmt: skip
        lanes[MOMENT + i], lanes[MOMENT + CHUNK + i], lanes[MOMENT + 2 * CHUNK + i] = m0x, m0y, m0z
        lanes[MOMENT + 3 * CHUNK + i] = m1x
        lanes[MOMENT + 4 * CHUNK + i] = m1y
        lanes[MOMENT + 5 * CHUNK + i] = m1z
        lanes[MOMENT + 6 * CHUNK + i] = m2x
        lanes[MOMENT + 7 * CHUNK + i] = m2y
        lanes[MOMENT + 8 * CHUNK + i] = m2z
        over_size = 1.0 / lanes[DOUBLE_AREA + i]
        nx, ny, nz = lanes[NX + i], lanes[NY + i], lanes[NZ + i]
        if nodal:
            lanes[D_SUM + i], lanes[D_SUM + CHUNK + i], lanes[D_SUM + 2 * CHUNK + i] = d0x, d0y, d0z
            lanes[D_SUM + 3 * CHUNK + i] = d1x
            lanes[D_SUM + 4 * CHUNK + i] = d1y
            lanes[D_SUM + 5 * CHUNK + i] = d1z
            lanes[D_SUM + 6 * CHUNK + i] = d2x
            lanes[D_SUM + 7 * CHUNK + i] = d2y
            lanes[D_SUM + 8 * CHUNK + i] = d2z
            lx, ly, lz = lanes[LX + i], lanes[LY + i], lanes[LZ + i]
            along = lx * nx + ly * ny + lz * nz
            gx = (lx - along * nx) * over_size
            gy = (ly - along * ny) * over_size
            gz = (lz - along * nz) * over_size
        else:
            gx = (d0x + d1x + d2x) * over_size
            gy = (d0y + d1y + d2y) * over_size
            gz = (d0z + d1z + d2z) * over_size
        # F_k = sum_a N_k,a dW/dg_a (Eq. 24) and the pull on c: b x g on x1, g x a on x2,
        # minus their sum on x0 (a = r1 = x1 - x0, b = r2 = x2 - x0)
        r1x, r1y, r1z = lanes[R1X + i], lanes[R1Y + i], lanes[R1Z + i]
        r2x, r2y, r2z = lanes[R2X + i], lanes[R2Y + i], lanes[R2Z + i]
        lanes[F1X + i] = lanes[S1X + i] + (r2y * gz - r2z * gy)
        lanes[F1Y + i] = lanes[S1Y + i] + (r2z * gx - r2x * gz)
        lanes[F1Z + i] = lanes[S1Z + i] + (r2x * gy - r2y * gx)
        lanes[F2X + i] = lanes[S2X + i] + (gy * r1z - gz * r1y)
        lanes[F2Y + i] = lanes[S2Y + i] + (gz * r1x - gx * r1z)
        lanes[F2Z + i] = lanes[S2Z + i] + (gx * r1y - gy * r1x)
