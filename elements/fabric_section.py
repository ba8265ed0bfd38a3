"""The section of a fabric as a Mindlin shell sees it: the fabric's own laws as stress resultants
(docs/theory.md §5.7), pure functions of the section strains of each cell.

A Mindlin triangle's kinematics give, per cell, ten section measures ``y`` (m, 10):

* ``y[0:3]`` the covariant membrane strains of the mid-surface (E11, E22, 2 E12);
* ``y[3:6]`` the covariant bending strains (K11, K22, 2 K12), mm: the coefficient of zeta in
  the strains of the level zeta h/2, i.e. x_,i . V_,j h/2 less its reference value;
* ``y[6:10]`` the changes of the four MITC3 tying products (transverse shear).

Carried to the fibre frame of the cell (warp a, weft b = n x a in the reference) by constant
rows, they give the quantities the fabric's laws take, the same ones the fibrous shell gives its
laws: the log fibre strains eps = log(lambda) with lambda^2 = 1 + 2 E_aa, the shear angle
gamma = asin(2 E_ab / (lambda_a lambda_b)) (pi/2 less the warp-weft angle, Bai Fig. 4, between
fibres that start orthogonal),
the changes of the deformed fibres' curvatures chi_aa = (K_aa + k0) / ((h/2) lambda_a^2) -
k0 / (h/2) (k0 the reference's, ``FabricSection.reference_bending``), chi_bb, and the
engineering twist 2 chi_ab = 2 K_ab / (h/2). The strain
energy of the cell is

    W = A0 [Phi_T,warp(eps_a) + Phi_T,weft(eps_b) + Phi_S(gamma)
            + Phi_B,warp(chi_aa) + Phi_B,weft(chi_bb) + D_t (2 chi_ab)^2 / 2]
        + t^T Q t / 2,

Phi the laws' energies, D_t the twisting stiffness and Q the transverse shear form on the tying
changes t = y[6:10]. ``response`` returns W, dW/dy and d2W/dy2 exactly, so that the element's
forces and tangent follow by the chain rule.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from elements import fabric_section_kernels
from elements.fibrous.packed_laws import pack_laws
from materials.fabric import Fabric

__all__ = ["FabricSection", "SectionResponse", "numpy_response", "response"]

MEASURES = 10


@dataclass(frozen=True)
class FabricSection:
    """The constant tables of a fabric section over the cells of a block.

    Attributes
    ----------
    fabric : materials.Fabric
    area : (m,) float, mm^2, reference area A0 of each cell.
    warp_rows, weft_rows, shear_rows : (m, 3) float
        E_aa = warp_rows . (E11, E22, 2 E12), E_bb likewise, E_ab = shear_rows . (...): the
        contravariant components of the unit fibre vectors in the reference basis.
    half_thickness : float, mm, h / 2 (curvature = bending strain / (h / 2)).
    twisting : float, N mm, D_t: the moment per unit width per unit engineering twist.
    transverse : (m, 4, 4) float, N mm, Q: the transverse shear energy form on the tying
        changes, integrated over the cell.
    reference_bending : (m, 2) float, mm, optional
        k0 = rows . K0 of the warp and the weft, K0 the bending measure of the reference
        (x_,i . V_,j h / 4 + sym. at the reference, the value y[3:6] are changes of): (h/2)
        times the reference fibre's curvature; None: zeros (a flat reference, directors
        normal to it).
    laws : (integers, reals)
        The fabric's laws packed for the compiled response (elements/fabric_section_kernels.py,
        ``LAW_ORDER``), set from ``fabric``.
    """

    fabric: Fabric
    area: np.ndarray
    warp_rows: np.ndarray
    weft_rows: np.ndarray
    shear_rows: np.ndarray
    half_thickness: float
    twisting: float
    transverse: np.ndarray
    reference_bending: np.ndarray | None = None
    laws: tuple[np.ndarray, np.ndarray] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        if self.reference_bending is None:
            object.__setattr__(self, "reference_bending", np.zeros((len(self.area), 2)))
        order = fabric_section_kernels.LAW_ORDER
        packed = pack_laws([getattr(self.fabric, name) for name in order])
        object.__setattr__(self, "laws", packed)


@dataclass(frozen=True)
class SectionResponse:
    """energy (m,) N mm, gradient dW/dy (m, 10), hessian d2W/dy2 (m, 10, 10) (None when not
    asked for), and the generalised stresses of the fibre frame for output: tension (m, 2) N/mm
    (warp, weft), shear moment (m,) N/mm, moments (m, 3) N (warp, weft, twist), strains: log
    fibre strains (m, 2), shear angle (m,) rad, curvatures (m, 3) 1/mm (warp, weft, 2 chi_ab)."""

    energy: np.ndarray
    gradient: np.ndarray
    hessian: np.ndarray | None
    tension: np.ndarray
    shear_moment: np.ndarray
    moments: np.ndarray
    strains: np.ndarray
    shear_angle: np.ndarray
    curvatures: np.ndarray


def fibre_rows(
    g1: np.ndarray, g2: np.ndarray, warp: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The rows that take the covariant strains (E11, E22, 2 E12) to the fibre frame.

    Parameters
    ----------
    g1, g2 : (m, 3) float, mm
        The reference covariant basis of each cell's mid-surface (its edges 0-1 and 0-2).
    warp : (3,) float
        The warp direction; projected on each cell's plane, the weft is n x warp.

    Returns
    -------
    warp_rows, weft_rows, shear_rows : (m, 3) float
        With alpha, beta the contravariant components of the unit warp and weft (a = alpha^i
        G_i): (alpha1^2, alpha2^2, alpha1 alpha2), the same for beta, and (alpha1 beta1,
        alpha2 beta2, (alpha1 beta2 + alpha2 beta1) / 2), so that E_aa = alpha^i alpha^j E_ij.
    """
    normal = np.cross(g1, g2)
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    a = warp[None, :] - (normal @ warp)[:, None] * normal
    size = np.linalg.norm(a, axis=1)
    if np.any(size < 1e-6):
        raise ValueError(f"a cell of the block is normal to the warp direction {warp.tolist()}")
    a /= size[:, None]
    b = np.cross(normal, a)
    metric = np.stack(
        [
            np.stack([np.sum(g1 * g1, 1), np.sum(g1 * g2, 1)], -1),
            np.stack([np.sum(g1 * g2, 1), np.sum(g2 * g2, 1)], -1),
        ],
        axis=-2,
    )
    inverse = np.linalg.inv(metric)

    def components(u):
        return np.einsum(
            "mij,mj->mi", inverse, np.stack([np.sum(g1 * u, 1), np.sum(g2 * u, 1)], -1)
        )

    alpha, beta = components(a), components(b)
    warp_rows = np.stack([alpha[:, 0] ** 2, alpha[:, 1] ** 2, alpha[:, 0] * alpha[:, 1]], -1)
    weft_rows = np.stack([beta[:, 0] ** 2, beta[:, 1] ** 2, beta[:, 0] * beta[:, 1]], -1)
    shear_rows = np.stack(
        [
            alpha[:, 0] * beta[:, 0],
            alpha[:, 1] * beta[:, 1],
            0.5 * (alpha[:, 0] * beta[:, 1] + alpha[:, 1] * beta[:, 0]),
        ],
        -1,
    )
    return warp_rows, weft_rows, shear_rows


def _outer(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    return u[:, :, None] * v[:, None, :]


def response(section: FabricSection, y: np.ndarray, hessian: bool = True) -> SectionResponse:
    """Energy, gradient and Hessian of each cell's section energy in its measures y (m, 10):
    the compiled loop of elements/fabric_section_kernels.py (``numpy_response`` without
    numba), the same formulas term by term (tests/test_fabric_section_kernels.py: within
    1e-12 of ``numpy_response``).

    Parameters
    ----------
    section : FabricSection
    y : (m, 10) float
        The section measures of the module docstring.
    hessian : bool
        Also d2W/dy2 (the tangent needs it, the forces do not).

    Returns
    -------
    SectionResponse

    Raises
    ------
    ValueError
        A cell whose fibres have locked flat (|gamma| = 90 deg).
    """
    if not fabric_section_kernels.COMPILED:
        return numpy_response(section, y, hessian)
    integers, reals = section.laws
    *answer, locked = fabric_section_kernels.section_response(
        integers,
        reals,
        section.area,
        section.warp_rows,
        section.weft_rows,
        section.shear_rows,
        section.half_thickness,
        section.twisting,
        section.transverse,
        np.asarray(section.reference_bending),
        y,
        hessian,
    )
    if locked:
        raise ValueError(
            "the fibres of a Mindlin fabric section have locked flat (|gamma| = 90 deg)"
        )
    return SectionResponse(*answer)


def numpy_response(section: FabricSection, y: np.ndarray, hessian: bool = True) -> SectionResponse:
    """``response`` in numpy: the reference the compiled loop is tested against.

    Parameters
    ----------
    section : FabricSection
    y : (m, 10) float
        The section measures of the module docstring.
    hessian : bool
        Also d2W/dy2 (the tangent needs it, the forces do not).

    Returns
    -------
    SectionResponse
    """
    fabric, area = section.fabric, section.area
    m = len(y)
    membrane, bending, tying = y[:, 0:3], y[:, 3:6], y[:, 6:10]
    gradient = np.zeros((m, MEASURES))
    h2 = np.zeros((m, MEASURES, MEASURES)) if hessian else None
    rows = (section.warp_rows, section.weft_rows)

    # Fibre tension: eps = log(lambda) = log(1 + 2 E) / 2, d eps/dE = 1/p, d2 = -2/p^2.
    stretch = [1.0 + 2.0 * np.sum(r * membrane, 1) for r in rows]  # p = lambda^2
    # A fibre crushed to zero length or fibres locked flat (|gamma| = 90 deg) give NaN, which
    # the solvers stop on with their last good state (no exception from inside a step).
    with np.errstate(invalid="ignore", divide="ignore"):
        strains = np.stack([0.5 * np.log(p) for p in stretch], -1)
    tension = np.stack(
        [fabric.tension.value(strains[:, 0]), fabric.tension_weft.value(strains[:, 1])], -1
    )
    energy = fabric.tension.energy(strains[:, 0]) + fabric.tension_weft.energy(strains[:, 1])
    for k, (law, r, p) in enumerate(zip((fabric.tension, fabric.tension_weft), rows, stretch)):
        gradient[:, 0:3] += (area * tension[:, k] / p)[:, None] * r
        if h2 is not None:
            curvature = area * (law.slope(strains[:, k]) - 2.0 * tension[:, k]) / p**2
            h2[:, 0:3, 0:3] += curvature[:, None, None] * _outer(r, r)

    # In-plane shear: gamma = asin(c), c = 2 E_ab / sqrt(p_a p_b) in (E_aa, E_bb, E_ab).
    pa, pb = stretch
    e_ab = np.sum(section.shear_rows * membrane, 1)
    root = np.sqrt(pa * pb)
    c = 2.0 * e_ab / root
    if np.any(np.abs(c) >= 1.0):
        raise ValueError(
            "the fibres of a Mindlin fabric section have locked flat (|gamma| = 90 deg)"
        )
    gamma = np.arcsin(c)
    d_gamma = 1.0 / np.sqrt(1.0 - c**2)
    moment_s = fabric.shear.value(gamma)
    energy = energy + fabric.shear.energy(gamma)
    # dc/dq, q = (E_aa, E_bb, E_ab), and dq/dy: the rows.
    dq = np.stack(rows + (section.shear_rows,), axis=1)  # (m, 3 q, 3 y)
    dc = np.stack([-c / pa, -c / pb, 2.0 / root], -1)
    dc_dy = np.einsum("mq,mqj->mj", dc, dq)
    gradient[:, 0:3] += (area * moment_s * d_gamma)[:, None] * dc_dy
    if h2 is not None:
        second = np.zeros((m, 3, 3))
        second[:, 0, 0], second[:, 1, 1] = 3.0 * c / pa**2, 3.0 * c / pb**2
        second[:, 0, 1] = second[:, 1, 0] = c / (pa * pb)
        second[:, 0, 2] = second[:, 2, 0] = -2.0 / (root * pa)
        second[:, 1, 2] = second[:, 2, 1] = -2.0 / (root * pb)
        second_y = np.einsum("mqi,mqr,mrj->mij", dq, second, dq)
        d2_gamma = c * d_gamma**3
        along = area * (fabric.shear.slope(gamma) * d_gamma**2 + moment_s * d2_gamma)
        h2[:, 0:3, 0:3] += along[:, None, None] * _outer(dc_dy, dc_dy)
        h2[:, 0:3, 0:3] += (area * moment_s * d_gamma)[:, None, None] * second_y

    # Bending per fibre direction: the change of the deformed fibre's curvature, chi =
    # (K_aa + k0) / ((h/2) p_a) - k0 / (h/2), K_aa + k0 = rows . K + k0 the product x_,a .
    # V_,a h/2 (per reference length squared), p_a = lambda_a^2 (docs/theory.md §5.7: the
    # fibrous shell's 1/R at every stretch); the twist 2 chi_ab = 2 K_ab / (h/2), linear in y.
    half = section.half_thickness
    k0 = np.asarray(section.reference_bending)
    twist_row = 2.0 * section.shear_rows / half
    # q = the deformed fibre's curvature (k0 = 0: chi itself)
    whole = [(np.sum(rows[k] * bending, 1) + k0[:, k]) / (half * p) for k, p in enumerate(stretch)]
    curvatures = np.stack(
        [whole[0] - k0[:, 0] / half, whole[1] - k0[:, 1] / half, np.sum(twist_row * bending, 1)],
        -1,
    )
    moments = np.stack(
        [
            fabric.bending.value(curvatures[:, 0]),
            fabric.bending_weft.value(curvatures[:, 1]),
            section.twisting * curvatures[:, 2],
        ],
        -1,
    )
    energy = energy + fabric.bending.energy(curvatures[:, 0])
    energy = energy + fabric.bending_weft.energy(curvatures[:, 1])
    energy = energy + 0.5 * section.twisting * curvatures[:, 2] ** 2
    slopes = (fabric.bending.slope(curvatures[:, 0]), fabric.bending_weft.slope(curvatures[:, 1]))
    for k, (r, p) in enumerate(zip(rows, stretch)):
        # d chi / d(membrane, bending) = (-2 q / p r, r / (half p)); the second derivatives
        # 8 q / p^2 r r (membrane, membrane), -2 / (half p^2) r r (membrane, bending).
        chi = whole[k]
        d_chi = np.concatenate([(-2.0 * chi / p)[:, None] * r, r / (half * p)[:, None]], 1)
        gradient[:, 0:6] += (area * moments[:, k])[:, None] * d_chi
        if h2 is not None:
            h2[:, 0:6, 0:6] += (area * slopes[k])[:, None, None] * _outer(d_chi, d_chi)
            pull = area * moments[:, k]
            rr = _outer(r, r)
            h2[:, 0:3, 0:3] += (pull * 8.0 * chi / p**2)[:, None, None] * rr
            cross = (pull * -2.0 / (half * p**2))[:, None, None] * rr
            h2[:, 0:3, 3:6] += cross
            h2[:, 3:6, 0:3] += cross
    gradient[:, 3:6] += (area * moments[:, 2])[:, None] * twist_row
    if h2 is not None:
        h2[:, 3:6, 3:6] += (area * section.twisting)[:, None, None] * _outer(twist_row, twist_row)
    energy = area * energy

    # Transverse shear: a quadratic form of the tying changes.
    q_t = np.einsum("mij,mj->mi", section.transverse, tying)
    gradient[:, 6:10] = q_t
    energy = energy + 0.5 * np.sum(tying * q_t, 1)
    if h2 is not None:
        h2[:, 6:10, 6:10] = section.transverse
    return SectionResponse(
        energy=energy,
        gradient=gradient,
        hessian=h2,
        tension=tension,
        shear_moment=moment_s,
        moments=moments,
        strains=strains,
        shear_angle=gamma,
        curvatures=curvatures,
    )
