"""Coulomb friction on the curved faces (``PlyContact(surface="curved", friction=mu)``,
docs/theory.md §9.3a "Curved faces"): the tangential loads as the exact gradient of the
stuck points' reported energy, the couple included, and their exact tangent.

A touching point with an anchor measures s = (I - nu nu^T) r, r = p - a, p its place on the
upper ply's curved face, a = P(Lambda; y^a, n^a) the anchor on the lower ply's curved face
(fixed coordinates Lambda on its patch), nu the lower surface's normal at the point's
projection (elements/ply_friction.py's return mapping gives F: k_t s stuck, mu N s / |s|
sliding). Over the point's local data v (54,): the facing data of elements/ply_curved_hessian.py
(the upper patch's z, N, the facing patch's y, n) then the anchor patch's y^a, n^a:

* stuck, the gradient of E = k_t(g) |s|^2 / 2: with d(|s|^2 / 2) = s . dr - (nu . r)(s . dnu),
  dE/dv = F^T dr/dv - (nu . r) F^T dnu/dv + W'''(g) |s|^2 / 2 dg/dv (k_t = W'', the normal
  law's; the last term 0 with ``stick="penalty"``): the force, the couple of F and -F a
  distance nu . r apart across the turning normal (dnu/dv: elements/ply_curved_hessian.py
  ``gap_gradient_and_turning``, the projection's motion on the patch included), and the lift;
* sliding, the virtual work F . dr, F = mu N s / |s| (no gradient: friction dissipates;
  no couple nor lift, as on the flat faces).

dr/dv holds the Phong map's Jacobians (elements/ply_curved_hessian.py ``phong_jacobian``) of
p over the upper patch's corners and normals and of a over the anchor patch's, so the loads
act on the normals too, carried to the nodes as the normal loads are
(elements/ply_curved_tangent.py ``carried_loads``). Their derivative over v is taken by the
complex step (Squire and Trapp, SIAM Rev. 40 (1998) 110; Martins, Sturdza and Alonso, ACM
TOMS 29 (2003) 245): the same loads evaluated in complex arithmetic at v + i h e_j give
d(loads)/dv_j = Im / h with no difference taken, so to rounding for h = 1e-30 (the
truncation, h^2 times the third derivative, is 1e-60 of it); the projection is made again in
complex arithmetic from the converged one (``STEPS`` Gauss-Newton steps; their matrix is
the patch's metric M, not the gap's Hessian M - g B, so the derivative's error shrinks only
linearly, by ~ |g| / R a step: with 3 steps (g / R)^3 of the largest entry, 8.6e-11 on the
tests' [0/45] pair on the 50-mm sphere, 1.9e-7 with gaps of 0.35 mm on a 12-mm radius:
enough for Newton, not to rounding). The stick/slip state and the
normal law's branch are those of the real point. The tangent then carries the local
derivative to the nodes (``carried_tangent``).

A point landing in the step (elements/ply_landing.py) has its anchor where its way crossed
the face, Lambda_a = Lambda - (1 - theta)(Lambda_nu - Lambda_nu,0), which moves with the
state: the complex steps make it again from v (``landing_anchor``: Lambda the projection
made again above, its normal nu, the places on the facing triangle's planes now and then
along nu, theta = g_0 / (g_0 + pen) with pen from the gap; the places then and g_0 held), and
take its motion alone (the imaginary part) onto the anchor given, so the loads stay those of
the given anchor to the bit and the tangent carries dLambda_a/dv through the anchor patch's
Phong map.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from elements import (
    ply_curved_friction_kernels,
    ply_landing_kept,
    ply_projection,
    ply_surface,
)
from elements.ply_curved_hessian import gap_gradient_and_turning, phong_jacobian
from elements.ply_curved_tangent import carried_loads, carried_tangent, surface_normals
from femcore.assembly import SparseTangent
from femcore.state import State

if TYPE_CHECKING:
    from elements.ply_block import PlyContactBlock
    from elements.ply_friction import PlyFrictionHistory, Sliding
    from elements.ply_landing import Landing
    from elements.ply_projection import Facing

__all__ = ["curved_friction_loads", "curved_friction_tangent", "local_loads_numpy"]

#: Gauss-Newton steps of the projection made again from the converged one (module docstring).
STEPS = 3
#: The complex step, mm (module docstring).
STEP = 1e-30
#: The local slots' kinds: an offset corner (True) or a normal (False), module docstring.
CORNER_SLOTS = np.array(([True] * 3 + [False] * 3) * 3)


def _split(v: np.ndarray) -> list[np.ndarray]:
    return [v[:, 9 * k : 9 * k + 9].reshape(len(v), 3, 3) for k in range(6)]


def _project(p: np.ndarray, y: np.ndarray, n: np.ndarray, start: np.ndarray) -> np.ndarray:
    """``STEPS`` Gauss-Newton steps of the projection of p on the patches (y, n) from
    ``start``, in plain arithmetic (real or complex; elements/ply_surface.py ``project``)."""
    lam = start.astype(np.result_type(p, y, n))
    for _ in range(STEPS):
        point, tangents, _, _ = ply_surface.surface_point_numpy(y, n, lam)
        metric = np.einsum("pai,pbi->pab", tangents, tangents)
        rhs = np.einsum("pai,pi->pa", tangents, p - point)
        step = np.linalg.solve(metric, rhs[:, :, None])[:, :, 0]
        lam = np.column_stack([lam[:, 0] + step[:, 0], lam[:, 1] + step[:, 1]])
        lam = np.column_stack([lam, 1.0 - lam[:, 0] - lam[:, 1]])
    return lam


def _law(gap: np.ndarray, branch_gap: np.ndarray, stiffness: np.ndarray, smoothing: float):
    """-W'(g), W''(g) and W'''(g) of the penalty law (elements/ply_projection.py
    ``penalty_law``) on the branch the real gaps ``branch_gap`` lie on, in plain
    arithmetic."""
    if smoothing == 0.0:
        return -stiffness * gap, stiffness + 0.0 * gap, 0.0 * gap
    deep = branch_gap <= -smoothing
    pressing = np.where(
        deep, -stiffness * (gap + 0.5 * smoothing), stiffness * gap**2 / (2 * smoothing)
    )
    spring = np.where(deep, stiffness + 0.0 * gap, -stiffness * gap / smoothing)
    slope = np.where(deep, 0.0 * gap, -stiffness / smoothing + 0.0 * gap)
    return pressing, spring, slope


def _plane_places(
    corners: np.ndarray, point: np.ndarray, direction: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """(places (r, 3), height (r,) mm): the barycentric places on the planes of the
    triangles ``corners`` (r, 3, 3) of ``point`` (r, 3) moved onto them along ``direction``
    (r, 3), along their normals where it lies within 60 deg of the planes (the landing's
    places, elements/ply_landing.py ``landing`` and ``_onto_plane``), and its height over
    them; in plain arithmetic, real or complex (the normal's length sqrt(c . c), not |c|)."""
    y1, y2, y3 = corners[:, 0], corners[:, 1], corners[:, 2]
    c = np.cross(y2 - y1, y3 - y1)
    area2 = np.sqrt(np.sum(c * c, axis=1))
    normal = c / area2[:, None]
    edges = np.stack([y3 - y2, y1 - y3], axis=1)  # grad phi_1 and grad phi_2 only
    gradients = np.cross(normal[:, None, :], edges) / area2[:, None, None]
    height = np.sum(normal * (point - y1), axis=1)
    slant = np.sum(normal * direction, axis=1)
    usable = np.abs(slant.real) > 0.5
    direction = np.where(usable[:, None], direction, normal)
    slant = np.where(usable, slant, 1.0)
    moved = point - (height / slant)[:, None] * direction
    first = np.sum(gradients[:, 0] * (moved - y2), axis=1)
    second = np.sum(gradients[:, 1] * (moved - y1), axis=1)
    return np.column_stack([first, second, 1.0 - first - second]), height


def landing_anchor(
    p: np.ndarray,
    y: np.ndarray,
    lam: np.ndarray,
    nu: np.ndarray,
    gap: np.ndarray,
    then: np.ndarray,
) -> np.ndarray:
    """(r, 3) the landing anchor Lambda_a = Lambda - (1 - theta)(Lambda_nu - Lambda_nu,0) of
    points landing on curved faces (elements/ply_landing.py), in plain arithmetic, real or
    complex (its derivative over the local data by the complex step): p (r, 3) the points,
    y (r, 3, 3) the facing triangles' corners now, lam (r, 3) the projections' coordinates
    on their patches, nu (r, 3) the patches' normals there, gap (r,) mm the gaps, then
    (r, 4, 3) the triangles' corners and the points' face points at the last accepted
    state; theta = g_0 / (g_0 + pen), g_0 the height then over T's plane (held, real)."""
    now = _plane_places(y, p, nu)[0]
    before, height = _plane_places(then[:, :3], then[:, 3], nu)
    g0 = np.maximum(height.real, 0.0)
    pen = np.where(gap.real < 0.0, -gap, 0.0 * gap)
    way = g0 + pen
    landed = way.real > 0.0
    theta = np.where(landed, g0 / np.where(landed, way, 1.0), 1.0 + 0.0 * way)
    return lam - (1.0 - theta)[:, None] * (now - before)


def local_loads_numpy(
    block: PlyContactBlock,
    v: np.ndarray,
    sigma: np.ndarray,
    anchor: np.ndarray,
    start: np.ndarray,
    stiffness: np.ndarray,
    branch_gap: np.ndarray,
    stuck: np.ndarray,
    landing: np.ndarray,
    then: np.ndarray,
) -> np.ndarray:
    """The local loads (t, 54), N or N mm, of the frictional points (module docstring) at
    their data v (t, 54), real or complex: sigma (t, 3) the points' coordinates on the upper
    patch, anchor (t, 3) the anchors' Lambda, start (t, 3) the converged projection's
    coordinates, stiffness (t,) k_p N/mm, branch_gap (t,) the real gap (the law's branch),
    mm, stuck (t,) bool, landing (t,) bool the points landing in this step and then
    (t, 4, 3) mm their facing triangle's corners and their face point at the last accepted
    state (read where ``landing``). A landing point's anchor moves with v as
    ``landing_anchor`` (its derivative), its value ``anchor`` (the same to rounding: the
    loads are those of the real anchor to the bit)."""
    z, upper_normals, y, n, ya, na = _split(v)
    p = ply_surface.surface_point_numpy(z, upper_normals, sigma)[0]
    lam = _project(p, y, n, start)
    point, tangents, _, _ = ply_surface.surface_point_numpy(y, n, lam)
    c = np.cross(tangents[:, 0], tangents[:, 1])
    nu = c / np.sqrt(np.sum(c * c, axis=1))[:, None]
    gap = np.sum((p - point) * nu, axis=1)
    lands = np.flatnonzero(landing)
    if len(lands) and np.iscomplexobj(v):  # its motion only: the value is ``anchor``'s
        moving = landing_anchor(p[lands], y[lands], lam[lands], nu[lands], gap[lands], then[lands])
        anchor = anchor.astype(complex)
        anchor[lands] += 1j * moving.imag
    a = ply_surface.surface_point_numpy(ya, na, anchor)[0]
    pressing, spring, slope = _law(gap, branch_gap, stiffness, block.smoothing)
    if block.stick == "penalty":
        spring, slope = stiffness + 0.0 * gap, 0.0 * gap
    r = p - a
    along = np.sum(nu * r, axis=1)
    s = r - along[:, None] * nu
    half = 0.5 * np.sum(s * s, axis=1)
    length = np.sqrt(2.0 * half + (half.real == 0.0))  # |s|, 1 where s = 0 (no direction)
    scale = np.where(stuck, spring, block.friction * pressing / length)
    force = scale[:, None] * s
    gradient, turning = gap_gradient_and_turning(z, upper_normals, sigma, y, n, lam, nu, gap)
    loads = np.zeros(v.shape, dtype=v.dtype)
    loads[:, :18] = np.einsum("ti,tiv->tv", force, phong_jacobian(z, upper_normals, sigma))
    loads[:, 36:] = -np.einsum("ti,tiv->tv", force, phong_jacobian(ya, na, anchor))
    potential = (
        -along[:, None] * np.einsum("ti,tiv->tv", force, turning)
        + (slope * half)[:, None] * gradient
    )
    loads[:, :36] += np.where(stuck[:, None], potential, 0.0)
    return loads


def _local_loads(
    block: PlyContactBlock,
    v: np.ndarray,
    sigma: np.ndarray,
    anchor: np.ndarray,
    start: np.ndarray,
    stiffness: np.ndarray,
    branch_gap: np.ndarray,
    stuck: np.ndarray,
    landing: np.ndarray,
    then: np.ndarray,
) -> np.ndarray:
    """``local_loads_numpy``, compiled where the ply kernels are
    (elements/ply_curved_friction_kernels.py)."""
    if ply_projection.COMPILED:
        return ply_curved_friction_kernels.local_loads(
            v, sigma, anchor, start, stiffness, branch_gap, stuck, landing, then,
            block.smoothing, block.friction, block.stick == "penalty", STEPS,
        )  # fmt: skip
    return local_loads_numpy(
        block, v, sigma, anchor, start, stiffness, branch_gap, stuck, landing, then
    )


def _frictional_points(
    block: PlyContactBlock,
    state: State,
    sliding: Sliding,
    history: PlyFrictionHistory,
    facing: Facing,
    surface: tuple[np.ndarray, np.ndarray],
    found: Landing | None = None,
):
    """The stuck or sliding points' rows (t,), slot nodes (t, 18), corner mask and offsets
    (t, 18), local data (t, 54) and what ``_local_loads`` takes beside them; ``surface`` the
    nodal normals and lengths (elements/ply_curved_tangent.py ``surface_normals``), ``found``
    the points landing in this step (``history`` the one ``found``'s anchors are in; None:
    their anchors held)."""
    on = np.flatnonzero(sliding.stuck | sliding.sliding)
    x = state.positions
    normals = surface[0]
    d = normals if block.along_normals else state.directors
    rows, anchor_rows = facing.triangle[on], sliding.triangle[on]
    above, tri, anchor_tri = block.above[on], block.cells[rows], block.cells[anchor_rows]
    z = x[above] - block.upper_offset[on][:, :, None] * d[above]
    y = x[tri] + block.corner_offset[rows][:, :, None] * d[tri]
    ya = x[anchor_tri] + block.corner_offset[anchor_rows][:, :, None] * d[anchor_tri]
    data = np.concatenate(
        [
            a.reshape(len(on), 9)
            for a in (z, normals[above], y, normals[tri], ya, normals[anchor_tri])
        ],
        axis=1,
    )
    nodes = np.column_stack([above, above, tri, tri, anchor_tri, anchor_tri])
    zero = np.zeros((len(on), 3))
    offset = np.column_stack(
        [
            -block.upper_offset[on],
            zero,
            block.corner_offset[rows],
            zero,
            block.corner_offset[anchor_rows],
            zero,
        ]
    )
    corner = np.broadcast_to(CORNER_SLOTS, nodes.shape)
    landing = np.zeros(len(on), dtype=bool)
    then = np.zeros((len(on), 4, 3))
    if found is not None and history.sides is not None:
        # every landing point touches: stuck or sliding, in ``on``
        lands = np.searchsorted(on, found.rows)
        landing[lands] = True
        then[lands, :3] = history.sides.corners[facing.triangle[found.rows]]
        then[lands, 3] = history.sides.faces[found.rows]
    arguments = (
        block.shape[on], history.anchor[on], facing.weights[on], block.stiffness[on],
        facing.gap[on], sliding.stuck[on], landing, then,
    )  # fmt: skip
    return on, nodes, corner, offset, data, arguments


def curved_friction_loads(
    block: PlyContactBlock,
    state: State,
    sliding: Sliding,
    history: PlyFrictionHistory,
    facing: Facing,
) -> tuple[np.ndarray, np.ndarray]:
    """The frictional points' forces (n, 3), N, and moments (n, 3), N mm (module
    docstring)."""
    surface = surface_normals(block, state)
    _, nodes, corner, offset, data, arguments = _frictional_points(
        block, state, sliding, history, facing, surface
    )
    loads = _local_loads(block, data, *arguments)
    return carried_loads(block, state, surface, nodes, corner, offset, loads)


def curved_friction_tangent(
    block: PlyContactBlock, state: State, history: PlyFrictionHistory, facing: Facing
) -> SparseTangent:
    """d(force, moment)/d(u, psi) (6 n, 6 n) of ``curved_friction_loads`` (module
    docstring: the local derivative by the complex step), ``history`` the accepted one: the
    points landing in this step anchored where their way crossed the face, their anchors
    moving with the state (elements/ply_landing.py)."""
    found, history = ply_landing_kept.kept_landing(block, state, history, facing)
    sliding = block.friction_state(state, history, facing)
    surface = surface_normals(block, state)
    _, nodes, corner, offset, data, arguments = _frictional_points(
        block, state, sliding, history, facing, surface, found
    )
    loads = _local_loads(block, data, *arguments)
    t, size = data.shape
    # every column's complex step at once: row (point, column) of the repeated data
    moved = np.repeat(data, size, axis=0).astype(complex)
    moved[np.arange(t * size), np.tile(np.arange(size), t)] += 1j * STEP
    repeated = tuple(np.repeat(argument, size, axis=0) for argument in arguments)
    stepped = _local_loads(block, moved, *repeated).imag / STEP  # (t size, size)
    jacobian = np.swapaxes(stepped.reshape(t, size, size), 1, 2)
    return carried_tangent(block, state, surface, nodes, corner, offset, loads, jacobian)
