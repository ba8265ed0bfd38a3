"""The lower ply's face as a curved surface over its nodes and nodal normals (``PlyContact``
with ``surface="curved"``, elements/ply_contact.py): the projection of a contact point on
it, the gap, and the gap's exact gradient, the nodal normals' own dependence on the
positions included.

Why. Two plies meshed alike put every upper point over the same flat facet as the ply
below, and a flat facet is as good as the surface. Plies at different angles do not: on a
sphere of radius R a facet of size s is a chord that cuts s^2 / (8 R) inside the lower ply's
true face (1-3 mm at 25 mm cells on the 50-mm punch), and an upper ply laid on the curved
tool sits that deep in it. A correction of the gap alone, without its gradient, breaks the
explicit energy balance (measured: at 3 % of the stroke).

Surface. Over a lower triangle with offset corners y_i and unit nodal normals n_i, at
barycentric coordinates lambda (Phong tessellation, Boubekeur and Alexa 2008, with shape
factor 1/2):

    y(lambda) = q - 1/2 sum_i lambda_i e_i n_i,   q = sum_k lambda_k y_k,
    e_i = (q - y_i) . n_i,

q minus half of q's distances to the corners' tangent planes, each along its normal. On a
sphere with the corners and their normals exact, the factor 1/2 makes y exact to second order
in the cell's angle (the flat facet's sag s^2 / (8 R) becomes O(s^4 / R^3)); along an edge y
depends on that edge's two corners alone, so the surface is continuous from one triangle to
the next. y is quadratic in lambda; n_i are the lower ply's area-weighted nodal normals at
the current positions (``nodal_normals``).

Projection and gap. From the flat facet's barycentric projection, Gauss-Newton on
1/2 |p - y(lambda)|^2 over (lambda_1, lambda_2) (lambda_3 = 1 - lambda_1 - lambda_2) to the
point where p - y is normal to the surface's tangents t_a = dy/dlambda_a - dy/dlambda_3
(``ITERATIONS`` steps; the correction is of the order of the sag over the cell, so it
converges in a few). The unit normal nu = t_1 x t_2 / |t_1 x t_2| (the orientation of the
flat facet), the gap g = (p - y) . nu, the signed distance to the surface.

Gradient. At the projection the gap is stationary in lambda (p - y is along nu, nu is a unit
vector orthogonal to the tangents), so its derivative in any of the surface's data is that of
-(y . nu) at fixed lambda:

    dg/dp = nu,
    dg/dy_k = -lambda_k [nu - 1/2 sum_i lambda_i (n_i . nu) n_i + 1/2 (n_k . nu) n_k],
    dg/dn_i = 1/2 lambda_i [e_i nu + (n_i . nu)(q - y_i)].

The nodal normal n = s / |s|, s = sum over the node's triangles of (x_2 - x_1) x (x_3 - x_1),
carries dW/dn to dW/ds = (I - n n^T) dW/dn / |s| and over each triangle to its corners
(``normal_pullback``): what the contact's force owes the normals' dependence on the
neighbours of the lower corners. The force is then the exact gradient of the contact
energy, checked by finite differences in tests/test_ply_surface.py. Its tangent is the
exact derivative of that force (elements/ply_curved_tangent.py): the gap's Hessian through
the projection's own motion (elements/ply_curved_hessian.py) and the normals' second
derivatives (elements/ply_normal_hessian.py).
"""

from __future__ import annotations

import numpy as np

from elements import ply_projection, ply_surface_kernels

__all__ = [
    "ITERATIONS",
    "gap_gradients",
    "nodal_normals",
    "normal_pullback",
    "project",
    "pullback",
    "surface_point",
    "surface_point_numpy",
]

#: Gauss-Newton steps of the projection on the curved surface.
ITERATIONS = 6


def _fans(x: np.ndarray, triangles: np.ndarray):
    """Each triangle's corners as fans (3m,) with the edges a (to the next corner) and b (to
    the previous one), (3m, 3), mm."""
    node = triangles.ravel()
    after = np.roll(triangles, -1, axis=1).ravel()
    before = np.roll(triangles, 1, axis=1).ravel()
    return node, after, before, x[after] - x[node], x[before] - x[node]


def nodal_normals(x: np.ndarray, triangles: np.ndarray, n_nodes: int):
    """Unit nodal normals (n, 3) by Max's weights (zero off ``triangles``) and the lengths
    |s| (n,) of the sums they normalise (1 off the triangles).

    s = sum over the node's triangles of (a x b) / (|a|^2 |b|^2), a and b the edges from the
    node to the triangle's next and previous corners (N. Max, J. Graphics Tools 4 (1999)):
    exact at an interior node whose neighbours lie on a sphere through it, where the
    area-weighted normal of a right-triangle or diamond grid is off by 1-2 deg at 10-mm
    cells on the 50-mm punch, enough to put the curved surface 0.05 mm off (measured, module
    docstring).

    x : (n, 3) float, mm; triangles : (m, 3) int, counter-clockwise about the normal.
    """
    node, _, _, a, b = _fans(x, triangles)
    weight = np.sum(a * a, axis=1) * np.sum(b * b, axis=1)
    terms = np.cross(a, b) / weight[:, None]
    summed = np.column_stack([np.bincount(node, terms[:, k], n_nodes) for k in range(3)])
    length = np.linalg.norm(summed, axis=1)
    length = np.where(length > 0.0, length, 1.0)
    return summed / length[:, None], length


def normal_pullback(
    x: np.ndarray,
    triangles: np.ndarray,
    normals: np.ndarray,
    lengths: np.ndarray,
    on_normals: np.ndarray,
) -> np.ndarray:
    """The nodal forces (n, 3), N, of an energy's derivative ``on_normals`` (n, 3), N mm
    (dW/dn at each node), through the unit nodal normals of ``triangles`` (``nodal_normals``
    at ``x``: ``normals``, ``lengths``)."""
    on_sums = (on_normals - np.sum(on_normals * normals, axis=1)[:, None] * normals) / lengths[
        :, None
    ]
    node, after, before, a, b = _fans(x, triangles)
    g = on_sums[node]  # (3m, 3)
    aa, bb = np.sum(a * a, axis=1), np.sum(b * b, axis=1)
    weight = aa * bb
    # d[G . (a x b) / (|a|^2 |b|^2)]: on a, b x G / w - 2 (G . a x b) a / (w |a|^2); on b alike
    triple = np.sum(g * np.cross(a, b), axis=1) / weight
    on_a = np.cross(b, g) / weight[:, None] - 2.0 * (triple / aa)[:, None] * a
    on_b = np.cross(g, a) / weight[:, None] - 2.0 * (triple / bb)[:, None] * b
    rows = np.concatenate([after, before, node])
    values = np.concatenate([on_a, on_b, -on_a - on_b])
    return np.column_stack([np.bincount(rows, values[:, k], len(x)) for k in range(3)])


def surface_point(y: np.ndarray, n: np.ndarray, lam: np.ndarray):
    """The surface's point (P, 3), its tangents t_1, t_2 (P, 2, 3) and q (P, 3), e (P, 3)
    (module docstring) at barycentric coordinates ``lam`` (P, 3) over corners ``y`` and unit
    normals ``n`` (P, 3, 3), mm: compiled (elements/ply_surface_kernels.py, the same bits as
    ``surface_point_numpy``) where the ply kernels are."""
    if ply_projection.COMPILED:
        return ply_surface_kernels.surface_point(y, n, lam)
    return surface_point_numpy(y, n, lam)


def surface_point_numpy(y: np.ndarray, n: np.ndarray, lam: np.ndarray):
    """``surface_point`` in numpy: the reference of the compiled pass. Each sum is spelled
    out, its terms added from the first (einsum's order would depend on numpy's build: its
    contiguous loops fuse a product and a sum where the CPU can, its others do not)."""

    def summed(terms):
        total = terms(0)
        for k in (1, 2):
            total = total + terms(k)
        return total

    q = summed(lambda k: lam[:, k, None] * y[:, k])
    gone = q[:, None, :] - y  # q - y_k
    e = summed(lambda i: gone[:, :, i] * n[:, :, i])
    point = q - 0.5 * summed(lambda k: (lam[:, k] * e[:, k])[:, None] * n[:, k])
    dots = summed(lambda i: y[:, :, None, i] * n[:, None, :, i])  # (P, a, k): y_a . n_k
    along = summed(lambda k: (lam[:, k, None] * dots[:, :, k])[:, :, None] * n[:, None, k])
    partial = (y - 0.5 * e[:, :, None] * n) - 0.5 * along  # dy/dlambda_a, taken apart
    tangents = partial[:, :2, :] - partial[:, 2:3, :]
    return point, tangents, q, e


def project(
    p: np.ndarray,
    y: np.ndarray,
    n: np.ndarray,
    start: np.ndarray,
    steps: int = ITERATIONS,
    settled: float = 1e-6,
):
    """The projection of points ``p`` (P, 3) on the surfaces over corners ``y`` and normals
    ``n`` (P, 3, 3) from barycentric coordinates ``start`` (P, 3), by ``steps`` Gauss-Newton
    steps: (lambda (P, 3), the surface point (P, 3), unit normal nu (P, 3), gap g (P,) mm,
    q (P, 3), e (P, 3)); NaN where the last step exceeded ``settled`` (barycentric: not
    converged; a folded patch, far past its edges)."""
    lam = start.copy()
    step = np.zeros((len(lam), 2))
    for _ in range(steps):
        point, tangents, _, _ = surface_point(y, n, lam)
        metric = np.einsum("pai,pbi->pab", tangents, tangents)
        rhs = np.einsum("pai,pi->pa", tangents, p - point)
        # the 2 x 2 normal equations solved in closed form; a folded patch (far past its
        # edges, where the quadratic surface turns over) has a singular metric: no step
        det = metric[:, 0, 0] * metric[:, 1, 1] - metric[:, 0, 1] * metric[:, 1, 0]
        scale = metric[:, 0, 0] * metric[:, 1, 1]
        ok = np.abs(det) > 1e-12 * np.where(scale > 0.0, scale, 1.0)
        inverse = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
        step[:, 0] = inverse * (metric[:, 1, 1] * rhs[:, 0] - metric[:, 0, 1] * rhs[:, 1])
        step[:, 1] = inverse * (metric[:, 0, 0] * rhs[:, 1] - metric[:, 1, 0] * rhs[:, 0])
        step[~ok] = np.nan
        lam[:, :2] += step
        lam[:, 2] = 1.0 - lam[:, 0] - lam[:, 1]
    # not converged (the last step above ``settled`` of the cell): NaN, the caller's to judge
    lam[~(np.abs(step).max(axis=1) <= settled)] = np.nan
    point, tangents, q, e = surface_point(y, n, lam)
    normal = np.cross(tangents[:, 0], tangents[:, 1])
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    gap = np.sum((p - point) * normal, axis=1)
    return lam, point, normal, gap, q, e


def pullback(
    y: np.ndarray, n: np.ndarray, lam: np.ndarray, q: np.ndarray, e: np.ndarray, v: np.ndarray
):
    """(dy/dy_k)^T v (P, 3, 3) and (dy/dn_i)^T v (P, 3, 3): a vector v (P, 3) on the surface's
    point y(lambda) carried to its corners and normals at fixed lambda (module docstring)."""
    along = np.einsum("pki,pi->pk", n, v)  # n_i . v
    mixed = np.einsum("pk,pk,pki->pi", lam, along, n)
    on_y = lam[:, :, None] * (v[:, None, :] - 0.5 * mixed[:, None, :] + 0.5 * along[:, :, None] * n)
    on_n = (
        -0.5
        * lam[:, :, None]
        * (e[:, :, None] * v[:, None, :] + along[:, :, None] * (q[:, None, :] - y))
    )
    return on_y, on_n


def gap_gradients(
    y: np.ndarray, n: np.ndarray, lam: np.ndarray, normal: np.ndarray, q: np.ndarray, e: np.ndarray
):
    """dg/dy_k (P, 3, 3) and dg/dn_i (P, 3, 3) at a projection (module docstring,
    "Gradient"; dg/dp is ``normal``): ``pullback`` of -nu."""
    return pullback(y, n, lam, q, e, -normal)
