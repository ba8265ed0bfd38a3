"""The exact tangent of the curved faces' normal contact (``PlyContact(surface="curved")``,
docs/theory.md §9.3a "Curved faces"): the derivative of ``curved_loads``
(elements/ply_curved.py), the projection's own motion and the nodal normals' dependence on
the positions included.

Each touching point's energy W(g) is a function of its local data v (36,): the upper patch's
offset corners and normals, the lower patch's (elements/ply_curved_hessian.py), whose
gradient G and Hessian H of the gap give Hess_v W = W'' G G^T + W' H. The data depend on the
nodes: an offset corner z = x + c D (D the director, turned by psi as dD = psi x D, or the
nodal normal with ``faces="normal"``), a normal N(x) through its node's star. With E = dv/d(u,
psi) (the direct part and, through the normals, S dN/dx: elements/ply_normal_hessian.py) the
tangent is

    K = E^T blockdiag(Hess_v W) E + sum_i G_i . d2N_i/dx2 + sum_nodes c (D F^T - (F . D) I),

G_i = dW/dN_i summed over the points (the loads' ``on_normals``), the last term the turned
offsets' (F = dW/dz, on the psi-psi block of faces along the directors). One sparse matrix
over all the nodes (``SparseTangent``): a normal reaches a node's star, so dense blocks per
point would hold the two rings of every corner.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp

from elements import ply_surface
from elements.ply_curved_hessian import gap_derivatives
from elements.ply_normal_hessian import normal_jacobian, normal_second
from elements.ply_projection import Facing, penalty_law
from femcore.assembly import SparseTangent
from femcore.rotation import cross_matrix
from femcore.state import State

if TYPE_CHECKING:
    from elements.ply_block import PlyContactBlock

__all__ = [
    "carried_loads",
    "carried_tangent",
    "curved_tangent",
    "local_energy_derivatives",
    "surface_normals",
]

#: The local slots' kinds: an offset corner (True) or a normal (False), module docstring.
CORNER_SLOTS = np.array([True] * 3 + [False] * 3 + [True] * 3 + [False] * 3)


def surface_normals(block: PlyContactBlock, state: State) -> tuple[np.ndarray, np.ndarray]:
    """The block's own face's unit nodal normals (n, 3) and their sums' lengths (n,) at
    ``state`` (elements/ply_surface.py ``nodal_normals``): made once a call and handed to the
    local data's and the carried loads' steps, which both need them."""
    return ply_surface.nodal_normals(state.positions, block._own_triangles, block.n_nodes)


def local_energy_derivatives(
    block: PlyContactBlock,
    state: State,
    facing: Facing,
    surface: tuple[np.ndarray, np.ndarray],
):
    """The touching points' local data and the derivatives of their energies over it;
    ``surface`` the nodal normals and lengths (``surface_normals``).

    Returns
    -------
    on (t,) int the points; nodes (t, 12) int, each slot's node; offset (t, 12) float, c of
    each corner slot (z = x + c D), mm (0 on the normals' slots); gradient (t, 36) dW/dv,
    N or N mm, and hessian (t, 36, 36) d2W/dv2.
    """
    on = np.flatnonzero(facing.touching)
    x = state.positions
    normals = surface[0]
    d = normals if block.along_normals else state.directors
    rows = facing.triangle[on]
    tri = block.cells[rows]
    above = block.above[on]
    z = x[above] - block.upper_offset[on][:, :, None] * d[above]
    y = x[tri] + block.corner_offset[rows][:, :, None] * d[tri]
    gap = facing.gap[on]
    g_grad, g_hess = gap_derivatives(
        z, normals[above], block.shape[on], y, normals[tri], facing.weights[on],
        facing.normal[on], gap,
    )  # fmt: skip
    _, slope, curvature = penalty_law(gap, block.stiffness[on], block.smoothing)
    gradient = slope[:, None] * g_grad
    hessian = (
        curvature[:, None, None] * g_grad[:, :, None] * g_grad[:, None, :]
        + slope[:, None, None] * g_hess
    )
    nodes = np.column_stack([above, above, tri, tri])
    zero = np.zeros((len(on), 3))
    offset = np.column_stack([-block.upper_offset[on], zero, block.corner_offset[rows], zero])
    return on, nodes, offset, gradient, hessian


def curved_tangent(block: PlyContactBlock, state: State, facing: Facing) -> SparseTangent:
    """d(force, moment)/d(u, psi) (6 n, 6 n) of the curved faces' normal loads (module
    docstring)."""
    surface = surface_normals(block, state)
    _, nodes, offset, gradient, hessian = local_energy_derivatives(block, state, facing, surface)
    corner = np.broadcast_to(CORNER_SLOTS, nodes.shape)
    return carried_tangent(block, state, surface, nodes, corner, offset, gradient, hessian)


def carried_loads(
    block: PlyContactBlock,
    state: State,
    surface: tuple[np.ndarray, np.ndarray],
    nodes: np.ndarray,
    corner: np.ndarray,
    offset: np.ndarray,
    loads: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """Nodal forces (n, 3), N, and moments (n, 3), N mm, of local loads ``loads`` (t, 3 S),
    the derivative of an energy (or a virtual work) over S local slots: each slot's node
    ``nodes`` (t, S), whether it is an offset corner (``corner``, (t, S) bool: z = x + c D,
    c = ``offset`` (t, S), mm) or a nodal normal (module docstring); ``surface`` the nodal
    normals and lengths (``surface_normals``)."""
    n = block.n_nodes
    x = state.positions
    normals, lengths = surface
    d = normals if block.along_normals else state.directors
    slots = loads.reshape(len(loads), nodes.shape[1], 3)  # -1 fails on no points
    force = np.zeros((n, 3))
    moment = np.zeros((n, 3))
    on_normals = np.zeros((n, 3))
    np.add.at(force, nodes[corner], slots[corner])
    np.add.at(on_normals, nodes[~corner], slots[~corner])
    if block.along_normals:  # z = x + c N: dW/dN = c dW/dz
        np.add.at(on_normals, nodes[corner], offset[corner][:, None] * slots[corner])
    else:  # z = x + c d: the moment c d x dW/dz
        np.add.at(
            moment,
            nodes[corner],
            offset[corner][:, None] * np.cross(d[nodes[corner]], slots[corner]),
        )
    force += ply_surface.normal_pullback(x, block._own_triangles, normals, lengths, on_normals)
    return force, moment


def carried_tangent(
    block: PlyContactBlock,
    state: State,
    surface: tuple[np.ndarray, np.ndarray],
    nodes: np.ndarray,
    corner: np.ndarray,
    offset: np.ndarray,
    loads: np.ndarray,
    jacobian: np.ndarray,
) -> SparseTangent:
    """d(force, moment)/d(u, psi) (6 n, 6 n) of ``carried_loads`` with the local loads'
    derivative ``jacobian`` (t, 3 S, 3 S) (row: the load, column: the datum): E^T J E,
    the normals' second derivatives times the loads on them and the turned offsets' terms
    (module docstring)."""
    n, t = block.n_nodes, len(nodes)
    if t == 0:
        return SparseTangent(sp.csr_matrix((6 * n, 6 * n)))
    x = state.positions
    normals, lengths = surface
    d = normals if block.along_normals else state.directors
    size = 3 * nodes.shape[1]
    comp = np.arange(3)
    local_rows = (
        size * np.arange(t)[:, None, None] + 3 * np.arange(nodes.shape[1])[None, :, None]
    ) + comp
    # the direct part: dz = du (+ c psi x D along the directors); dN and c dN below
    r_u = local_rows[corner]  # (b, 3)
    c_u = 6 * nodes[corner][:, None] + comp
    parts_r, parts_c = [r_u.ravel()], [c_u.ravel()]
    parts_v = [np.ones(r_u.size)]
    if not block.along_normals:  # dz/dpsi = -c [D]x
        turn = -offset[corner][:, None, None] * cross_matrix(d[nodes[corner]])  # (b, 3, 3)
        parts_r.append(np.repeat(r_u[:, :, None], 3, axis=2).ravel())
        parts_c.append(np.repeat((6 * nodes[corner][:, None] + 3 + comp)[:, None, :], 3, 1).ravel())
        parts_v.append(turn.ravel())
    direct = sp.csr_matrix(
        (np.concatenate(parts_v), (np.concatenate(parts_r), np.concatenate(parts_c))),
        shape=(size * t, 6 * n),
    )
    # the normals' selection: a normal slot takes N at its node, a corner slot along the
    # normals c N
    weight = np.where(corner, offset if block.along_normals else 0.0, 1.0)
    chosen = weight != 0.0
    select = sp.csr_matrix(
        (
            np.repeat(weight[chosen], 3),
            (local_rows[chosen].ravel(), (3 * nodes[chosen][:, None] + comp).ravel()),
        ),
        shape=(size * t, 3 * n),
    )
    # the u columns of a 3 n-wide matrix in the 6 n-wide one
    widen = sp.csr_matrix(
        (np.ones(3 * n), (np.arange(3 * n), (6 * np.arange(n)[:, None] + comp).ravel())),
        shape=(3 * n, 6 * n),
    )
    normal_jac = normal_jacobian(x, block._own_triangles, normals, lengths)
    carry = (direct + select @ (normal_jac @ widen)).tocsr()
    local = sp.bsr_matrix(
        (jacobian, np.arange(t), np.arange(t + 1)), shape=(size * t, size * t)
    ).tocsr()
    matrix = carry.T @ (local @ carry)
    on_normals = (select.T @ loads.ravel()).reshape(n, 3)
    second = normal_second(x, block._own_triangles, normals, lengths, on_normals)
    matrix = matrix + widen.T @ (second @ widen)
    if not block.along_normals:  # the turned offsets: c (D F^T - (F . D) I) on psi-psi
        forces = loads.reshape(t, -1, 3)[corner]
        summed = np.zeros((n, 3))
        np.add.at(summed, nodes[corner], offset[corner][:, None] * forces)
        blocks = d[:, :, None] * summed[:, None, :] - np.sum(summed * d, axis=1)[
            :, None, None
        ] * np.eye(3)
        r = (6 * np.arange(n)[:, None, None] + 3 + comp[:, None]).repeat(3, axis=2)
        c = (6 * np.arange(n)[:, None, None] + 3 + comp[None, :]).repeat(3, axis=1)
        matrix = matrix + sp.csr_matrix(
            (blocks.ravel(), (r.ravel(), c.ravel())), shape=(6 * n, 6 * n)
        )
    return SparseTangent(sp.csr_matrix(matrix))
