"""The pulls of one fibrous cell (pass 3 of elements/fibrous/kernels.py): the forces on its
corners of the bending moments of its sides (Eq. 37) and, with nodal normals, of the nodal
sums T_k = dW/dS_k through alpha_k n; spliced into the pass over the cells that adds them to
the cells' corner forces (``_pulls_pass``, on any number of threads, a pass over the nodes
summing those after it) and into the pass that, on one thread, adds each cell's corner forces
and moments to its nodes as it goes (``pulls_nodal``).

Each node gets its corners' forces and moments in cell order from 0.0 in both, as the nodes'
pass (kernels.py ``_node_loads``) adds them: the same numbers to the last bit
(tests/test_fibrous_pulls_nodal.py), without the pass over the nodes that read the cells'
(m, 3, 3) forces and moments again at every step.
"""

from __future__ import annotations

from elements.fibrous.cell_terms import angle_pull, fold_gradient, side_squares
from femcore.jit import inline, serial

__all__ = ["cell_pulls", "pulls_nodal"]


@inline
def cell_pulls(c, connectivity, positions, normal, double_area, angles, pull, nodal, own,
               across_cell, across_side, interior):  # fmt: skip
    """The pull of cell c on its corners 0, 1, 2 (nine scalars, N): each side's moment (own
    plus the neighbour's across it) times D[s, k] n (Eq. 37) and, with ``nodal``, T_k . d(alpha_k
    n)/dx at the cell's corners (geometry.py ``corner_normal_pull``); the arguments those of
    kernels.py ``_pulls_pass``."""
    n0, n1, n2 = connectivity[c, 0], connectivity[c, 1], connectivity[c, 2]
    n0, n1, n2 = connectivity[c, 0], connectivity[c, 1], connectivity[c, 2]
    x0x, x0y, x0z = positions[n0, 0], positions[n0, 1], positions[n0, 2]
    x1x, x1y, x1z = positions[n1, 0], positions[n1, 1], positions[n1, 2]
    x2x, x2y, x2z = positions[n2, 0], positions[n2, 1], positions[n2, 2]
    nx, ny, nz, size = normal[c, 0], normal[c, 1], normal[c, 2], double_area[c]
    # the sides opposite each corner: t0 = x2 - x1, t1 = x0 - x2, t2 = x1 - x0
    t0x, t0y, t0z = x2x - x1x, x2y - x1y, x2z - x1z
    t1x, t1y, t1z = x0x - x2x, x0y - x2y, x0z - x2z
    t2x, t2y, t2z = x1x - x0x, x1y - x0y, x1z - x0z
    d00, d11, d22, i00, i11, i22 = side_squares(t0x, t0y, t0z, t1x, t1y, t1z, t2x, t2y, t2z)
    over_size = 1.0 / size
    # bending: each side's moment times D[s, k] n
    side0, side1, side2 = own[c, 0], own[c, 1], own[c, 2]
    if interior[c, 0]:
        side0 += own[across_cell[c, 0], across_side[c, 0]]
    if interior[c, 1]:
        side1 += own[across_cell[c, 1], across_side[c, 1]]
    if interior[c, 2]:
        side2 += own[across_cell[c, 2], across_side[c, 2]]
    b0 = b1 = b2 = 0.0
    if side0 != 0.0 or side1 != 0.0 or side2 != 0.0:
        g00, g01, g02, g10, g11, g12, g20, g21, g22 = fold_gradient(
            t0x, t0y, t0z, t1x, t1y, t1z, t2x, t2y, t2z, d00, d11, d22, i00, i11, i22,
            over_size,
        )  # fmt: skip
        b0 = side0 * g00 + side1 * g10 + side2 * g20
        b1 = side0 * g01 + side1 * g11 + side2 * g21
        b2 = side0 * g02 + side1 * g12 + side2 * g22
    f0x, f0y, f0z = b0 * nx, b0 * ny, b0 * nz
    f1x, f1y, f1z = b1 * nx, b1 * ny, b1 * nz
    f2x, f2y, f2z = b2 * nx, b2 * ny, b2 * nz
    if nodal:
        # T_k . d(alpha_k n)/dx: through alpha_k (d alpha_k / dx in the plane) and
        # through n (the pull on c = a x b with g = P sum_k alpha_k T_k / |c|)
        p0x, p0y, p0z = pull[n0, 0], pull[n0, 1], pull[n0, 2]
        p1x, p1y, p1z = pull[n1, 0], pull[n1, 1], pull[n1, 2]
        p2x, p2y, p2z = pull[n2, 0], pull[n2, 1], pull[n2, 2]
        # corner 0: u = x1 - x0 = t2, w = x2 - x0 = -t1
        tx, ty, tz, vx, vy, vz = angle_pull(
            nx, ny, nz, t2x, t2y, t2z, -t1x, -t1y, -t1z, i22, i11,
            p0x * nx + p0y * ny + p0z * nz,
        )  # fmt: skip
        f1x, f1y, f1z = f1x + tx, f1y + ty, f1z + tz
        f2x, f2y, f2z = f2x + vx, f2y + vy, f2z + vz
        f0x, f0y, f0z = f0x - (tx + vx), f0y - (ty + vy), f0z - (tz + vz)
        # corner 1: u = x2 - x1 = t0, w = x0 - x1 = -t2
        tx, ty, tz, vx, vy, vz = angle_pull(
            nx, ny, nz, t0x, t0y, t0z, -t2x, -t2y, -t2z, i00, i22,
            p1x * nx + p1y * ny + p1z * nz,
        )  # fmt: skip
        f2x, f2y, f2z = f2x + tx, f2y + ty, f2z + tz
        f0x, f0y, f0z = f0x + vx, f0y + vy, f0z + vz
        f1x, f1y, f1z = f1x - (tx + vx), f1y - (ty + vy), f1z - (tz + vz)
        # corner 2: u = x0 - x2 = t1, w = x1 - x2 = -t0
        tx, ty, tz, vx, vy, vz = angle_pull(
            nx, ny, nz, t1x, t1y, t1z, -t0x, -t0y, -t0z, i11, i00,
            p2x * nx + p2y * ny + p2z * nz,
        )  # fmt: skip
        f0x, f0y, f0z = f0x + tx, f0y + ty, f0z + tz
        f1x, f1y, f1z = f1x + vx, f1y + vy, f1z + vz
        f2x, f2y, f2z = f2x - (tx + vx), f2y - (ty + vy), f2z - (tz + vz)
        alpha0, alpha1, alpha2 = angles[c, 0], angles[c, 1], angles[c, 2]
        gx = alpha0 * p0x + alpha1 * p1x + alpha2 * p2x
        gy = alpha0 * p0y + alpha1 * p1y + alpha2 * p2y
        gz = alpha0 * p0z + alpha1 * p1z + alpha2 * p2z
        along = gx * nx + gy * ny + gz * nz
        gx = (gx - along * nx) * over_size
        gy = (gy - along * ny) * over_size
        gz = (gz - along * nz) * over_size
        # b x g on x1, g x a on x2, minus their sum on x0 (a = x1 - x0 = t2, b = x2 - x0)
        ux, uy, uz = t2y * gz - t2z * gy, t2z * gx - t2x * gz, t2x * gy - t2y * gx  # a x g
        wx, wy, wz = -t1y * gz + t1z * gy, -t1z * gx + t1x * gz, -t1x * gy + t1y * gx  # b x g
        f1x, f1y, f1z = f1x + wx, f1y + wy, f1z + wz
        f2x, f2y, f2z = f2x - ux, f2y - uy, f2z - uz
        f0x, f0y, f0z = f0x - (wx - ux), f0y - (wy - uy), f0z - (wz - uz)
    return f0x, f0y, f0z, f1x, f1y, f1z, f2x, f2y, f2z


@serial
def _pulls_nodal(
    connectivity, positions, normal, double_area, angles, pull, nodal, own, across_cell,
    across_side, interior, force, moment, out_force, out_moment,
):  # fmt: skip
    """kernels.py ``_pulls_pass`` and ``_node_loads`` in one pass on one thread: each cell's
    corner forces ``force`` (m, 3, 3) with its pull added, and its director moments ``moment``
    (m, 3, 3), added to its nodes' ``out_force``, ``out_moment`` (n, 3; zeros on entry) in
    cell order (``force`` is not written)."""
    for c in range(connectivity.shape[0]):
        f0x, f0y, f0z, f1x, f1y, f1z, f2x, f2y, f2z = cell_pulls(
            c, connectivity, positions, normal, double_area, angles, pull, nodal, own,
            across_cell, across_side, interior,
        )  # fmt: skip
        n0, n1, n2 = connectivity[c, 0], connectivity[c, 1], connectivity[c, 2]
        out_force[n0, 0] += force[c, 0, 0] + f0x
        out_force[n0, 1] += force[c, 0, 1] + f0y
        out_force[n0, 2] += force[c, 0, 2] + f0z
        out_force[n1, 0] += force[c, 1, 0] + f1x
        out_force[n1, 1] += force[c, 1, 1] + f1y
        out_force[n1, 2] += force[c, 1, 2] + f1z
        out_force[n2, 0] += force[c, 2, 0] + f2x
        out_force[n2, 1] += force[c, 2, 1] + f2y
        out_force[n2, 2] += force[c, 2, 2] + f2z
        for k in range(3):
            node = connectivity[c, k]
            out_moment[node, 0] += moment[c, k, 0]
            out_moment[node, 1] += moment[c, k, 1]
            out_moment[node, 2] += moment[c, k, 2]


pulls_nodal = _pulls_nodal
