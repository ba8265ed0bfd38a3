"""The stick couple of a stuck ply contact point whose closest point q lies on an edge or at a
vertex of its facing triangle (elements/ply_friction.py, "The stick potential"; docs/
theory.md §9.3a, "Friction between plies").

A stuck point stores E = k_t |s|^2 / 2 with s = (I - n n^T) r, r = p - a (a its anchor) and n
the gap's gradient dg/dp. At fixed r and k_t, dE/dz = k_t s . ds/dz = -k_t (n . r) s^T dn/dz
(s . n = 0), and dn/dz_w = H_pw, the row of p of the gap's Hessian over z = (p, y_1, y_2,
y_3) (elements/ply_edge_gap.py ``edge_hessian``). With g = +-|p - q|, a = (1, -lambda)
(lambda the barycentric coordinates of q), on an edge e = sum_w m_w y_w (unit e^, length L,
m = (0, G_b - G_a) the grown triangle's ends, or a cut's):

    dn/dz_w = a_w (I - n n^T - e^ e^T) / g - m_w e^ n^T / L,

and at a vertex (q at fixed barycentric coordinates) a_w (I - n n^T) / g. So the couple on
slot w is

    C_w = -k_t (n . r) s^T dn/dz_w = -(n . r) [a_w (F - (F . e^) e^) / g - m_w (F . e^) n / L],

F = k_t s (e^ = 0 at a vertex). It sums to zero over the four slots (sum a_w = 0, sum m_w =
0), is carried by the point's upper corners and the facing corners as its normal force, and
on a plane it is the plane's couple (n . r)(F . grad phi_m) n (dn/dy_m = -grad phi_m n^T,
dn/dp = 0). Unlike the plane's it acts on p too, and across n: with the anchor near q (n . r
~ g) it takes F's part across the edge (all of F at a vertex) off p and puts it back on the
corners (a point facing a vertex turns n as it moves, keeping s). The gap's Hessian jumps
where q passes from a plane onto an edge (dn/dp = 0 on the plane, (I - n n^T - e^ e^T) / g on
the edge), so E's gradient, and these loads, jump there by that much.

The rows of the facing (``Facing``'s weights, reach and triangle) say where q is, as
``edge_hessian`` decides it: on a grown edge (one coordinate at its bound), at a corner (two),
or on a growth's cut (elements/ply_wedge.py: c . lambda = 0 for one of the triangle's cuts,
inside its segment; at its ends a vertex). ``edge_features`` and ``edge_couple`` are the numpy
reference of the compiled pass (elements/ply_edge_couple_kernels.py, the same bits).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from elements.ply_wedge import KEEP

if TYPE_CHECKING:
    from elements.ply_projection import Facing
    from elements.ply_wedge import WedgeCuts

__all__ = ["EdgeFeatures", "edge_couple", "edge_couple_tangent", "edge_features", "turning"]

#: A cut's parameter this close to 0 or 1 counts as its end (a vertex), as ``edge_hessian``'s
#: open interval (0, 1) on the search's clipped parameter.
END = 1e-12


@dataclass(frozen=True)
class EdgeFeatures:
    """Where the closest points q of some points facing an edge or a vertex lie.

    a : (t, 4) float
        (1, -lambda): dg/dz_w = a_w n.
    m : (t, 4) float
        The edge's direction over z (0, m_1, m_2, m_3), e = sum m_k y_k; 0 at a vertex.
    unit : (t, 3) float
        e^ = e / L; 0 at a vertex.
    length : (t,) float
        L = |e|, mm; 1 at a vertex.
    slide : (t,) bool
        q slides along an edge (else it is a vertex).
    live : (t,) bool
        |p - q| above round-off (else the gap's Hessian is taken as 0, as ``edge_hessian``).
    """

    a: np.ndarray
    m: np.ndarray
    unit: np.ndarray
    length: np.ndarray
    slide: np.ndarray
    live: np.ndarray


def edge_features(
    facing: Facing, y: np.ndarray, cuts: WedgeCuts | None, rows: np.ndarray
) -> EdgeFeatures:
    """The features (module docstring) of the points ``rows`` (t,) of ``facing``, each facing
    an edge or a vertex (``Facing.on_edge``); y (m, 3, 3) the lower face's offset corners, mm;
    ``cuts`` the growths' cuts (None: none)."""
    count = len(rows)
    lam = facing.weights[rows]
    reach = np.zeros_like(lam) if facing.reach is None else facing.reach[rows]
    triangle = facing.triangle[rows]
    at_bound = lam <= -reach + 1e-9
    slide = at_bound.sum(axis=1) == 1
    ends = np.argsort(at_bound, axis=1, kind="stable")[:, :2]  # the two corners off the bound
    grow = np.eye(3) * (1.0 + reach.sum(axis=-1))[:, None, None] - reach[:, None, :]
    index = np.arange(count)
    m = np.zeros((count, 4))
    m[:, 1:] = grow[index, ends[:, 1]] - grow[index, ends[:, 0]]
    cutting = np.zeros(0, dtype=np.int64)
    if cuts is not None and cuts.any:
        cutting = np.flatnonzero(cuts.cut[triangle])
    # q on a cut's segment from e_k to E_k (elements/ply_wedge.py)
    if cuts is not None and cutting.size:
        lines, far = cuts.lines[triangle[cutting]], cuts.ends[triangle[cutting]]
        held = lam[cutting]
        for k in range(3):
            present = np.any(lines[:, k] != 0.0, axis=1)
            level = np.sum(lines[:, k] * held, axis=1)
            direction = far[:, k] - np.eye(3)[k]
            squared = np.sum(direction * direction, axis=1)
            along = np.sum((held - np.eye(3)[k]) * direction, axis=1) / np.where(
                squared > 0.0, squared, 1.0
            )
            on = present & (np.abs(level) <= KEEP) & (along >= -END) & (along <= 1.0 + END)
            m[cutting[on], 1:] = direction[on]
            slide[cutting[on]] = (along[on] > END) & (along[on] < 1.0 - END)
    m = np.where(slide[:, None], m, 0.0)
    e = np.sum(m[:, 1:, None] * y[triangle], axis=1)
    length = np.linalg.norm(e, axis=1)
    length = np.where(slide & (length > 0.0), length, 1.0)
    unit = np.where(slide[:, None], e / length[:, None], 0.0)
    p = facing.face[rows]
    live = np.abs(facing.gap[rows]) > 1e-12 * (1.0 + np.linalg.norm(p, axis=1))
    a = np.concatenate([np.ones((count, 1)), -lam], axis=1)
    return EdgeFeatures(a, m, unit, length, slide, live)


def turning(features: EdgeFeatures, gap: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """dn/dz (t, 4, 3, 3), 1/mm, [w, i, j] = dn_i/dz_wj (module docstring), the row of p of
    ``edge_hessian``'s d2g/dz2; gap g (t,) mm and normal n (t, 3) of the points."""
    f = features
    safe = np.where(f.live, gap, 1.0)
    across = (
        np.eye(3)
        - normal[:, :, None] * normal[:, None, :]
        - f.unit[:, :, None] * f.unit[:, None, :]
    )
    bend = f.unit[:, :, None] * normal[:, None, :] / f.length[:, None, None]
    out = (
        f.a[:, :, None, None] * (across / safe[:, None, None])[:, None]
        - f.m[:, :, None, None] * bend[:, None]
    )
    return np.where(f.live[:, None, None, None], out, 0.0)


def edge_couple(
    features: EdgeFeatures,
    gap: np.ndarray,
    normal: np.ndarray,
    offset: np.ndarray,
    force: np.ndarray,
) -> np.ndarray:
    """The couple C_w (t, 4, 3), N, on z = (p, y_1, y_2, y_3) of stuck points facing an edge
    or a vertex (module docstring); gap g (t,) mm, normal n (t, 3), offset r = p - a (t, 3)
    mm, force F = k_t s (t, 3) N."""
    f = features
    safe = np.where(f.live, gap, 1.0)
    along = np.sum(normal * offset, axis=1)  # n . r, mm
    sigma = np.sum(force * f.unit, axis=1)  # F . e^, N
    across = force - sigma[:, None] * f.unit
    couple = -along[:, None, None] * (
        f.a[:, :, None] * (across / safe[:, None])[:, None, :]
        - f.m[:, :, None] * ((sigma / f.length)[:, None] * normal)[:, None, :]
    )
    return np.where(f.live[:, None, None], couple, 0.0)


def edge_couple_tangent(
    features: EdgeFeatures,
    gap: np.ndarray,
    normal: np.ndarray,
    offset: np.ndarray,
    slip: np.ndarray,
    big: np.ndarray,
    ds: np.ndarray,
    spring: np.ndarray,
    d_spring: np.ndarray,
    moving: np.ndarray | None = None,
) -> np.ndarray:
    """The exact derivative (t, 9, 3, 9, 3) of the couple C_w (``edge_couple``, on the slots
    w = 0..3 of z = (p, y_f1..3, y_a1..3, a, b)) over z.

    C_w = -k_t (n . r) V_w, V_w = a_w u / g - m_w sigma n / L, u = s - sigma e^, sigma = s . e^:

        dV_w = da_w u / g + a_w du / g - a_w u dg / g^2
               - m_w ((dsigma / L - sigma dL / L^2) n + sigma dn / L),

    du = ds - dsigma e^ - sigma de^, dsigma = e^ . ds + s . de^, de/dz_v = m_v I, dL = e^ . de,
    de^ = (I - e^ e^T) de / L, dg/dz_v = a_v n, dn/dz_v (``turning``), and on an edge q slides:
    lambda = alpha + t m with dt/dz_v = (a_v e + g m_v n) / L^2 (t minimises |p - u - t e|,
    d = p - q = g n), so da_w = -m_w dt (0 at a vertex, whose q is fixed); d(n . r) = r . dn +
    n . dr (dr/dp = I, dr/dy_ak = -Lambda_k I).

    gap g (t,) mm, normal n, offset r, slip s (t, 3) mm; big (t, 3) the anchor's Lambda; ds
    (t, 3, 9, 3) ds/dz; spring k_t (t,) N/mm and d_spring (t, 9, 3) dk_t/dz, N/mm^2; moving
    (t, 3, 9, 3) a landing anchor's dr/dz beyond -Lambda_k I (elements/ply_landing.py), None:
    none.
    """
    f = features
    count = len(gap)
    eye = np.eye(3)
    safe = np.where(f.live, gap, 1.0)
    turn = turning(f, gap, normal)  # (t, 4, 3, 3): [v, i, j]
    dn = np.zeros((count, 3, 9, 3))
    dn[:, :, :4, :] = np.swapaxes(turn, 1, 2)
    dg = np.zeros((count, 9, 3))
    dg[:, :4] = f.a[:, :, None] * normal[:, None, :]
    de = np.zeros((count, 3, 9, 3))  # de_i/dz_vj = m_v delta_ij
    de[:, :, :4, :] = f.m[:, None, :, None] * eye[None, :, None, :]
    plane = eye - f.unit[:, :, None] * f.unit[:, None, :]
    d_unit = np.einsum("tik,tkvj->tivj", plane, de) / f.length[:, None, None, None]
    d_length = np.einsum("ti,tivj->tvj", f.unit, de)
    sigma = np.sum(slip * f.unit, axis=1)
    d_sigma = np.einsum("ti,tivj->tvj", f.unit, ds) + np.einsum("ti,tivj->tvj", slip, d_unit)
    u = slip - sigma[:, None] * f.unit
    du = ds - f.unit[:, :, None, None] * d_sigma[:, None] - sigma[:, None, None, None] * d_unit
    e = f.unit * f.length[:, None]
    dt = np.zeros((count, 9, 3))
    dt[:, :4] = (
        f.a[:, :, None] * e[:, None, :] + (gap[:, None, None] * f.m[:, :, None]) * normal[:, None]
    ) / (f.length**2)[:, None, None]
    da = -f.m[:, :, None, None] * dt[:, None]  # (t, 4, 9, 3), 0 at a vertex (m = 0)
    along = np.sum(normal * offset, axis=1)
    d_along = np.einsum("ti,tivj->tvj", offset, dn)
    d_along[:, 0] += normal
    d_along[:, 4:7] -= big[:, :, None] * normal[:, None, :]
    if moving is not None:
        d_along += np.einsum("ti,tivj->tvj", normal, moving)
    points = np.zeros((count, 9, 3, 9, 3))
    for w in range(4):
        a_w, m_w = f.a[:, w], f.m[:, w]
        value = a_w[:, None] * u / safe[:, None] - (m_w * sigma / f.length)[:, None] * normal
        d_value = (
            u[:, :, None, None] * (da[:, w] / safe[:, None, None])[:, None]
            + (a_w / safe)[:, None, None, None] * du
            - (a_w / safe**2)[:, None, None, None] * u[:, :, None, None] * dg[:, None]
            - (m_w / f.length)[:, None, None, None]
            * (
                normal[:, :, None, None]
                * (d_sigma - (sigma / f.length)[:, None, None] * d_length)[:, None]
                + sigma[:, None, None, None] * dn
            )
        )
        points[:, w] = -(
            value[:, :, None, None]
            * (d_spring * along[:, None, None] + spring[:, None, None] * d_along)[:, None]
            + (spring * along)[:, None, None, None] * d_value
        )
    return np.where(f.live[:, None, None, None, None], points, 0.0)
