"""The fabric section's response (elements/fabric_section.py) as one compiled loop over the cells.

``section_response`` gives, per cell, the energy W, its gradient dW/dy and Hessian d2W/dy2 in
the ten section measures y, and the fibre-frame quantities the outputs write, from the same
formulas as the numpy reference ``elements.fabric_section.numpy_response`` (docs/theory.md
§5.7), term by term. Why: a Mindlin ply of a stack has a few tens of cells, where the numpy
path's hundred or so array operations per call cost about 0.7 ms whatever the cell count
(Python and numpy's per-call overhead), and Static on a ply stack calls it for every ply at
every residual, line-search energy and tangent; the loop costs microseconds.

The laws are read from ``elements.fibrous.packed_laws.pack_laws`` arrays in the order
``LAW_ORDER``; their value and energy are the fibrous kernels' (``law_value``,
``law_energy``) and their slope too (``law_slope``: materials.Law.slope, the right derivative
at a table's knots, its end segments' slopes beyond them).
"""

from __future__ import annotations

import numpy as np

from elements.fibrous.packed_laws import law_energy, law_slope, law_value
from femcore.jit import AVAILABLE, serial

__all__ = ["LAW_ORDER", "law_slope", "section_response"]

#: The fabric's laws in the packed arrays' order (attributes of materials.Fabric).
LAW_ORDER = ("tension", "tension_weft", "shear", "bending", "bending_weft")
_TENSION, _TENSION_WEFT, _SHEAR, _BENDING, _BENDING_WEFT = range(5)


@serial
def _response_cells(
    integers,
    reals,
    area,
    warp_rows,
    weft_rows,
    shear_rows,
    half,
    twisting,
    transverse,
    reference_bending,
    y,
    hessian,
    energy,
    gradient,
    h2,
    tension,
    shear_moment,
    moments,
    strains,
    shear_angle,
    curvatures,
):
    """Fill the outputs (see ``section_response``) cell by cell; True when a cell's fibres
    have locked flat (|sin gamma| >= 1)."""
    locked = False
    m = y.shape[0]
    dq = np.empty((3, 3))
    second = np.empty((3, 3))
    dc_dy = np.empty(3)
    rows = np.empty((3, 3))  # bending rows: warp / (h/2), weft / (h/2), twist
    d_chi = np.empty(6)  # a fibre curvature's derivative in the membrane and bending measures
    whole = np.empty(2)  # the deformed warp and weft fibres' curvatures
    p = np.empty(2)  # the fibres' squared stretches
    chi = np.empty(3)  # the warp and weft fibres' curvature changes, the twist
    # The five laws' arguments, values and slopes, in ``LAW_ORDER``: each law function is
    # spliced once, in one loop over the laws, where a call written per law spliced the three
    # of them 11 times (numba compiles each copy again): 3.4 s of CPU to build against 8.8 s,
    # and 0.8 of the time per cell without the Hessian, 0.9 with it (the per-cell scratch
    # arrays allocated once), the same numbers to the last bit
    # (benchmarks/mindlin_kernel_pairs.py --compile).
    at = np.empty(5)
    value = np.empty(5)
    slope = np.zeros(5)
    for e in range(m):
        a = area[e]
        for j in range(3):
            dq[0, j] = warp_rows[e, j]
            dq[1, j] = weft_rows[e, j]
            dq[2, j] = shear_rows[e, j]
        # The laws' arguments first. Fibre tension: eps = log(p) / 2, p = lambda^2 = 1 + 2 E.
        for k in range(2):
            product = 0.0
            for j in range(3):
                product += dq[k, j] * y[e, j]
            p[k] = 1.0 + 2.0 * product
            eps = 0.5 * np.log(p[k])
            strains[e, k] = eps
            at[_TENSION + k] = eps
        # In-plane shear: gamma = asin(c), c = 2 E_ab / sqrt(p_a p_b).
        pa, pb = p[0], p[1]
        e_ab = 0.0
        for j in range(3):
            e_ab += dq[2, j] * y[e, j]
        root = np.sqrt(pa * pb)
        c = 2.0 * e_ab / root
        if abs(c) >= 1.0:
            locked = True
        gamma = np.arcsin(c)
        shear_angle[e] = gamma
        at[_SHEAR] = gamma
        # Bending per fibre direction: the deformed fibre's curvature chi = K_aa / ((h/2) p),
        # p = lambda^2 (docs/theory.md §5.7); the twist 2 chi_ab = 2 K_ab / (h/2), linear in y.
        for j in range(3):
            rows[0, j] = dq[0, j] / half
            rows[1, j] = dq[1, j] / half
            rows[2, j] = 2.0 * dq[2, j] / half
        for k in range(3):
            chi[k] = 0.0
        for j in range(3):
            chi[0] += dq[0, j] * y[e, 3 + j]
            chi[1] += dq[1, j] * y[e, 3 + j]
            chi[2] += rows[2, j] * y[e, 3 + j]
        # whole: the deformed fibre's curvature (K_aa + k0) / ((h/2) p); chi its change
        for k in range(2):
            whole[k] = (chi[k] + reference_bending[e, k]) / (half * p[k])
            chi[k] = whole[k] - reference_bending[e, k] / half
        for k in range(3):
            curvatures[e, k] = chi[k]
        at[_BENDING], at[_BENDING_WEFT] = chi[0], chi[1]
        # The laws, the energy summed in LAW_ORDER (tension, weft tension, shear, bending,
        # weft bending), the twist after them.
        w = 0.0
        for k in range(5):
            value[k] = law_value(integers, reals, k, at[k])
            w += law_energy(integers, reals, k, at[k])
            if hessian:
                slope[k] = law_slope(integers, reals, k, at[k])
        w += 0.5 * twisting * chi[2] ** 2
        # Fibre tension's terms.
        for k in range(2):
            t = value[_TENSION + k]
            tension[e, k] = t
            along = a * t / p[k]
            for j in range(3):
                gradient[e, j] += along * dq[k, j]
            if hessian:
                bend = a * (slope[_TENSION + k] - 2.0 * t) / p[k] ** 2
                for i in range(3):
                    for j in range(3):
                        h2[e, i, j] += bend * dq[k, i] * dq[k, j]
        # In-plane shear's.
        d_gamma = 1.0 / np.sqrt(1.0 - c**2)
        moment_s = value[_SHEAR]
        shear_moment[e] = moment_s
        dc0, dc1, dc2 = -c / pa, -c / pb, 2.0 / root
        for j in range(3):
            dc_dy[j] = dc0 * dq[0, j] + dc1 * dq[1, j] + dc2 * dq[2, j]
        pull = a * moment_s * d_gamma
        for j in range(3):
            gradient[e, j] += pull * dc_dy[j]
        if hessian:
            second[0, 0], second[1, 1], second[2, 2] = 3.0 * c / pa**2, 3.0 * c / pb**2, 0.0
            second[0, 1] = second[1, 0] = c / (pa * pb)
            second[0, 2] = second[2, 0] = -2.0 / (root * pa)
            second[1, 2] = second[2, 1] = -2.0 / (root * pb)
            d2_gamma = c * d_gamma**3
            along = a * (slope[_SHEAR] * d_gamma**2 + moment_s * d2_gamma)
            for i in range(3):
                for j in range(3):
                    second_y = 0.0
                    for q in range(3):
                        for r in range(3):
                            second_y += dq[q, i] * second[q, r] * dq[r, j]
                    h2[e, i, j] += along * dc_dy[i] * dc_dy[j] + pull * second_y
        # Bending's.
        moments[e, 0] = value[_BENDING]
        moments[e, 1] = value[_BENDING_WEFT]
        moments[e, 2] = twisting * chi[2]
        for k in range(2):
            # d chi / d(membrane, bending) = (-2 chi / p dq_k, dq_k / (half p)); second
            # derivatives 8 chi / p^2 dq dq (membrane, membrane), -2 / (half p^2) dq dq (cross)
            pk = p[k]
            for j in range(3):
                d_chi[j] = -2.0 * whole[k] / pk * dq[k, j]
                d_chi[3 + j] = rows[k, j] / pk
            along = a * moments[e, k]
            for j in range(6):
                gradient[e, j] += along * d_chi[j]
            if hessian:
                bent = a * slope[_BENDING + k]
                for i in range(6):
                    for j in range(6):
                        h2[e, i, j] += bent * d_chi[i] * d_chi[j]
                inner = along * 8.0 * whole[k] / pk**2
                cross = along * -2.0 / (half * pk**2)
                for i in range(3):
                    for j in range(3):
                        rr = dq[k, i] * dq[k, j]
                        h2[e, i, j] += inner * rr
                        h2[e, i, 3 + j] += cross * rr
                        h2[e, 3 + i, j] += cross * rr
        along = a * moments[e, 2]
        for j in range(3):
            gradient[e, 3 + j] += along * rows[2, j]
        if hessian:
            for i in range(3):
                for j in range(3):
                    h2[e, 3 + i, 3 + j] += a * twisting * rows[2, i] * rows[2, j]
        w = a * w
        # Transverse shear: a quadratic form of the tying changes.
        for i in range(4):
            q_t = 0.0
            for j in range(4):
                q_t += transverse[e, i, j] * y[e, 6 + j]
                if hessian:
                    h2[e, 6 + i, 6 + j] = transverse[e, i, j]
            gradient[e, 6 + i] = q_t
            w += 0.5 * y[e, 6 + i] * q_t
        energy[e] = w
    return locked


def section_response(
    integers: np.ndarray,
    reals: np.ndarray,
    area: np.ndarray,
    warp_rows: np.ndarray,
    weft_rows: np.ndarray,
    shear_rows: np.ndarray,
    half_thickness: float,
    twisting: float,
    transverse: np.ndarray,
    reference_bending: np.ndarray,
    y: np.ndarray,
    hessian: bool,
):
    """The section energy of each cell, its derivatives and the fibre-frame quantities.

    Parameters
    ----------
    integers, reals : the fabric's laws packed in ``LAW_ORDER`` (packed_laws.pack_laws).
    area : (m,) float, mm^2; warp_rows, weft_rows, shear_rows : (m, 3) float;
    half_thickness : float, mm; twisting : float, N mm; transverse : (m, 4, 4) float, N mm:
        reference_bending : (m, 2) float, mm: the tables of
        elements.fabric_section.FabricSection.
    y : (m, 10) float, the section measures.
    hessian : bool, also d2W/dy2.

    Returns
    -------
    tuple
        energy (m,) N mm, gradient (m, 10), hessian (m, 10, 10) or None, tension (m, 2)
        N/mm, shear moment (m,) N/mm, moments (m, 3) N, log fibre strains (m, 2), shear
        angle (m,) rad, curvatures (m, 3) 1/mm, and whether a cell's fibres locked flat.
    """
    m = len(y)
    energy = np.zeros(m)
    gradient = np.zeros((m, 10))
    h2 = np.zeros((m if hessian else 0, 10, 10))
    tension, moments, curvatures = np.zeros((m, 2)), np.zeros((m, 3)), np.zeros((m, 3))
    strains, shear_moment, shear_angle = np.zeros((m, 2)), np.zeros(m), np.zeros(m)
    locked = _response_cells(
        integers,
        reals,
        np.ascontiguousarray(area, dtype=float),
        np.ascontiguousarray(warp_rows, dtype=float),
        np.ascontiguousarray(weft_rows, dtype=float),
        np.ascontiguousarray(shear_rows, dtype=float),
        float(half_thickness),
        float(twisting),
        np.ascontiguousarray(transverse, dtype=float),
        np.ascontiguousarray(reference_bending, dtype=float),
        np.ascontiguousarray(y, dtype=float),
        bool(hessian),
        energy,
        gradient,
        h2,
        tension,
        shear_moment,
        moments,
        strains,
        shear_angle,
        curvatures,
    )
    return (
        energy,
        gradient,
        h2 if hessian else None,
        tension,
        shear_moment,
        moments,
        strains,
        shear_angle,
        curvatures,
        bool(locked),
    )


COMPILED = AVAILABLE
