"""The first and second derivatives of the curved faces' unit nodal normals (Max's weights,
elements/ply_surface.py ``nodal_normals``) in the positions, as sparse matrices over all the
nodes: what the curved contact's exact tangent carries its local Hessian through
(elements/ply_curved.py, docs/theory.md §9.3a "Curved faces").

The normal of node i is N_i = s_i / |s_i|, s_i = sum over its fans of f(a, b) = (a x b) / w,
w = |a|^2 |b|^2, a and b the edges from the node to the fan's next and previous corners. So

    dN_i = P_i ds_i / |s_i|,   P_i = I - N_i N_i^T,
    df = (-[b]x / w - 2 f a^T / |a|^2) da + ([a]x / w - 2 f b^T / |b|^2) db,

and an energy's second derivative through the normals, G_i . d2N_i (G_i = dW/dN_i, held), is

    G_i . d2N_i = sigma_i . d2s_i + ds_i^T Q_i ds_i,   sigma_i = P_i G_i / |s_i|,
    Q_i = -(G_i . N_i) P_i / |s_i|^2 - (N_i sigma_i^T + sigma_i N_i^T) / |s_i|,

with sigma . d2f of each fan the Hessian of phi / w, phi = sigma . (a x b) (d2phi/da db =
-[sigma]x), over (a, b): Hess phi / w - (grad phi grad w^T + grad w grad phi^T) / w^2 +
phi (2 grad w grad w^T / w^3 - Hess w / w^2), grad w = (2 |b|^2 a, 2 |a|^2 b), Hess w =
((2 |b|^2 I, 4 a b^T), (4 b a^T, 2 |a|^2 I)).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from femcore.rotation import cross_matrix

__all__ = ["normal_jacobian", "normal_second", "sum_jacobian"]


def _fans(x: np.ndarray, triangles: np.ndarray):
    node = triangles.ravel()
    after = np.roll(triangles, -1, axis=1).ravel()
    before = np.roll(triangles, 1, axis=1).ravel()
    return node, after, before, x[after] - x[node], x[before] - x[node]


def _blocks(rows: np.ndarray, columns: np.ndarray, values: np.ndarray, size: int) -> sp.csr_matrix:
    """The (3 size, 3 size) sparse matrix summing the 3 x 3 ``values`` (b, 3, 3) at node
    ``rows`` (b,) and ``columns`` (b,)."""
    r = (3 * rows[:, None, None] + np.arange(3)[None, :, None]).repeat(3, axis=2)
    c = (3 * columns[:, None, None] + np.arange(3)[None, None, :]).repeat(3, axis=1)
    return sp.csr_matrix((values.ravel(), (r.ravel(), c.ravel())), shape=(3 * size, 3 * size))


def sum_jacobian(x: np.ndarray, triangles: np.ndarray) -> sp.csr_matrix:
    """ds/dx (3 n, 3 n) of the unnormalised nodal normals s (module docstring), x (n, 3)
    mm, triangles (m, 3) int; 1/mm^2."""
    node, after, before, a, b = _fans(x, triangles)
    aa, bb = np.sum(a * a, axis=1), np.sum(b * b, axis=1)
    w = aa * bb
    f = np.cross(a, b) / w[:, None]
    on_a = -cross_matrix(b) / w[:, None, None] - 2.0 * f[:, :, None] * (a / aa[:, None])[:, None]
    on_b = cross_matrix(a) / w[:, None, None] - 2.0 * f[:, :, None] * (b / bb[:, None])[:, None]
    rows = np.concatenate([node, node, node])
    columns = np.concatenate([after, before, node])
    return _blocks(rows, columns, np.concatenate([on_a, on_b, -on_a - on_b]), len(x))


def normal_jacobian(
    x: np.ndarray, triangles: np.ndarray, normals: np.ndarray, lengths: np.ndarray
) -> sp.csr_matrix:
    """dN/dx (3 n, 3 n), 1/mm, of the unit nodal normals ``normals`` (n, 3) with the sums'
    lengths ``lengths`` (n,) (``nodal_normals`` at x)."""
    n = len(x)
    across = (np.eye(3) - normals[:, :, None] * normals[:, None, :]) / lengths[:, None, None]
    scale = _blocks(np.arange(n), np.arange(n), across, n)
    return scale @ sum_jacobian(x, triangles)


def normal_second(
    x: np.ndarray,
    triangles: np.ndarray,
    normals: np.ndarray,
    lengths: np.ndarray,
    on_normals: np.ndarray,
) -> sp.csr_matrix:
    """sum_i G_i . d2N_i/dx2 (3 n, 3 n), N/mm, for G = ``on_normals`` (n, 3), N mm, held
    (module docstring)."""
    n = len(x)
    dot = np.sum(on_normals * normals, axis=1)
    across = np.eye(3) - normals[:, :, None] * normals[:, None, :]
    sigma = np.einsum("nij,nj->ni", across, on_normals) / lengths[:, None]
    q = (
        -(dot / lengths**2)[:, None, None] * across
        - (normals[:, :, None] * sigma[:, None, :] + sigma[:, :, None] * normals[:, None, :])
        / lengths[:, None, None]
    )
    jac = sum_jacobian(x, triangles)
    second = jac.T @ (_blocks(np.arange(n), np.arange(n), q, n) @ jac)
    # sigma . d2f over each fan's (a, b), carried to its (node, after, before)
    node, after, before, a, b = _fans(x, triangles)
    s = sigma[node]
    aa, bb = np.sum(a * a, axis=1), np.sum(b * b, axis=1)
    w = aa * bb
    phi = np.sum(s * np.cross(a, b), axis=1)
    grad_phi = np.concatenate([np.cross(b, s), np.cross(s, a)], axis=1)  # (f, 6)
    grad_w = np.concatenate([2.0 * bb[:, None] * a, 2.0 * aa[:, None] * b], axis=1)
    eye = np.eye(3)
    hess_phi = np.zeros((len(w), 6, 6))
    hess_phi[:, :3, 3:] = -cross_matrix(s)
    hess_phi[:, 3:, :3] = cross_matrix(s)
    hess_w = np.zeros((len(w), 6, 6))
    hess_w[:, :3, :3] = 2.0 * bb[:, None, None] * eye
    hess_w[:, 3:, 3:] = 2.0 * aa[:, None, None] * eye
    hess_w[:, :3, 3:] = 4.0 * a[:, :, None] * b[:, None, :]
    hess_w[:, 3:, :3] = 4.0 * b[:, :, None] * a[:, None, :]
    mixed = grad_phi[:, :, None] * grad_w[:, None, :]
    fan = (
        hess_phi / w[:, None, None]
        - (mixed + np.swapaxes(mixed, 1, 2)) / (w**2)[:, None, None]
        + phi[:, None, None]
        * (
            2.0 * grad_w[:, :, None] * grad_w[:, None, :] / (w**3)[:, None, None]
            - hess_w / (w**2)[:, None, None]
        )
    )
    # a = x_after - x_node, b = x_before - x_node: over (node, after, before)
    carry = np.zeros((6, 9))
    carry[:3, :3] = carry[3:, :3] = -eye
    carry[:3, 3:6] = eye
    carry[3:, 6:] = eye
    nodal = np.einsum("ai,fab,bj->fij", carry, fan, carry)  # (f, 9, 9)
    ends = np.stack([node, after, before], axis=1)
    rows = np.repeat(ends, 3, axis=1)
    columns = np.tile(ends, (1, 3))
    blocks = nodal.reshape(-1, 3, 3, 3, 3).transpose(0, 1, 3, 2, 4).reshape(-1, 3, 3)
    return second + _blocks(rows.ravel(), columns.ravel(), blocks, n)
