"""Compiled per-element kernels (numba): fused loops over the cells of a block that gather the
nodal values, compute each cell's forces and scatter them, with no temporary arrays over all
cells. Each kernel has a numpy reference in its element class (the ``kernel="numpy"`` path),
and the tests hold the two to 1e-12 of the largest force.

The loops over cells run in parallel (numba's ``prange``, as many threads as
``numba.set_num_threads`` allows) into per-cell buffers; the sums to the nodes are a parallel
loop over nodes after them (``NodeCorners``), each node adding the corners of its cells in cell
order, so that no two threads add to the same node and the sums are those of numpy.bincount.
On one thread the Mindlin shell's pass adds each cell's loads to its nodes as it goes, in cell
order (elements/mindlin_cell_loads.py ``mindlin_nodal``): the same sums, no buffer.
The fibrous shell's loops are in elements/fibrous/kernels.py; the compilation helpers
(``jit``, ``serial``, ``prange``) in femcore/jit.py.
"""

from __future__ import annotations

import numpy as np

from elements.kernel_inputs import read_only
from elements.mindlin_cell_loads import cell_loads, mindlin_nodal
from elements.mindlin_cell_loads import edge as _edge
from femcore.jit import AVAILABLE, jit, prange, serial, threads_for
from femcore.workspace import workspace_of

__all__ = [
    "AVAILABLE",
    "NodeCorners",
    "cable_forces",
    "mindlin_cell_steps",
    "mindlin_energy",
    "mindlin_fields",
    "mindlin_loads",
    "mindlin_loads_and_energy",
    "mindlin_tables",
]


def choose(kernel: str | None) -> str:
    """An element's ``kernel`` option checked: "compiled" (the default when numba is
    installed) or "numpy"."""
    if kernel is None:
        return "compiled" if AVAILABLE else "numpy"
    if kernel not in ("compiled", "numpy"):
        raise ValueError(f"kernel must be 'compiled' or 'numpy', got {kernel!r}")
    if kernel == "compiled" and not AVAILABLE:
        raise ValueError("kernel='compiled' needs numba: pip install numba, or use 'numpy'")
    return kernel


# ---------------------------------------------------------------------- nodes from corners
class NodeCorners:
    """The corners (cell c, local node k) of each node, in cell order: the pattern of the
    parallel passes from cells to nodes.

    Parameters
    ----------
    connectivity : (m, k) int, node ids of each cell.
    n_nodes : number of nodes.
    """

    def __init__(self, connectivity: np.ndarray, n_nodes: int):
        flat = np.asarray(connectivity, dtype=np.int64).ravel()
        self.corners = np.argsort(flat, kind="stable").astype(np.int64)  # c * 3 + k
        self.offsets = np.zeros(n_nodes + 1, dtype=np.int64)
        np.cumsum(np.bincount(flat, minlength=n_nodes), out=self.offsets[1:])

    def sum(self, per_corner: np.ndarray, out: np.ndarray | None = None) -> np.ndarray:
        """sum over the corners of each node of per_corner (m, k, 3) -> (n, 3), into ``out``
        when given."""
        out = np.empty((len(self.offsets) - 1, 3)) if out is None else out
        _node_sums(self.offsets, self.corners, per_corner.reshape(-1, 3), out)
        return out


@jit
def _node_sums(offsets, corners, per_corner, out):
    """out[node] = sum of per_corner[j] (m * 3, 3) over the node's corners j."""
    for node in prange(out.shape[0]):
        sx = sy = sz = 0.0
        for j in range(offsets[node], offsets[node + 1]):
            corner = corners[j]
            sx += per_corner[corner, 0]
            sy += per_corner[corner, 1]
            sz += per_corner[corner, 2]
        out[node, 0], out[node, 1], out[node, 2] = sx, sy, sz


# The packed upper triangle of a symmetric 7 x 7 level stiffness: entry (r, s), r <= s, row
# by row (elements/mindlin.py ``MindlinShellBlock.level_stiffness``).
PACKED_ROWS, PACKED_COLUMNS = np.triu_indices(7)


@jit
def _mindlin_cells(
    positions, directors, connectivity, zeta, half, reference, stiffness, tying_n, with_forces,
    loads, energy,
):  # fmt: skip
    """The strain energy (m,) of each MITC3 Mindlin triangle into ``energy`` and, with
    ``with_forces``, its nodal forces and director moments into ``loads`` (m, 3, 6): forces
    in [..., :3], moments in [..., 3:] (elements/mindlin_cell_loads.py ``cell_loads``, each
    cell on its own: the loop runs on the threads). No array is allocated inside the loop."""
    for c in prange(connectivity.shape[0]):
        n0, n1, n2 = connectivity[c, 0], connectivity[c, 1], connectivity[c, 2]
        (
            stored, t1x, t1y, t1z, t2x, t2y, t2z,
            m0x, m0y, m0z, m1x, m1y, m1z, m2x, m2y, m2z,
        ) = cell_loads(
            positions, directors, n0, n1, n2, c, zeta, half, reference, stiffness, tying_n,
            with_forces, True,
        )  # fmt: skip
        energy[c] = 0.5 * stored
        if not with_forces:
            continue
        loads[c, 0, 0] = -(t1x + t2x)
        loads[c, 0, 1] = -(t1y + t2y)
        loads[c, 0, 2] = -(t1z + t2z)
        loads[c, 1, 0] = t1x
        loads[c, 1, 1] = t1y
        loads[c, 1, 2] = t1z
        loads[c, 2, 0] = t2x
        loads[c, 2, 1] = t2y
        loads[c, 2, 2] = t2z
        loads[c, 0, 3], loads[c, 0, 4], loads[c, 0, 5] = m0x, m0y, m0z
        loads[c, 1, 3], loads[c, 1, 4], loads[c, 1, 5] = m1x, m1y, m1z
        loads[c, 2, 3], loads[c, 2, 4], loads[c, 2, 5] = m2x, m2y, m2z


@jit
def _node_sums6(offsets, corners, per_corner, force, moment):
    """force[node], moment[node] = sums of per_corner[j] (m * 3, 6) over the node's corners j,
    its columns :3 and 3: in one pass: two contiguous (n, 3) arrays, which the step's node
    passes take as they are (the (n, 6) array's halves were views that each pass copied)."""
    for node in prange(force.shape[0]):
        s0 = s1 = s2 = s3 = s4 = s5 = 0.0
        for j in range(offsets[node], offsets[node + 1]):
            corner = corners[j]
            s0 += per_corner[corner, 0]
            s1 += per_corner[corner, 1]
            s2 += per_corner[corner, 2]
            s3 += per_corner[corner, 3]
            s4 += per_corner[corner, 4]
            s5 += per_corner[corner, 5]
        force[node, 0], force[node, 1], force[node, 2] = s0, s1, s2
        moment[node, 0], moment[node, 1], moment[node, 2] = s3, s4, s5


def _cell_inputs(block, positions, directors) -> tuple:
    """The Mindlin cell passes' first arguments (``_mindlin_cells`` and ``mindlin_nodal``
    take the same): positions and directors (n, 3) as C-contiguous float64, the connectivity,
    the thickness points, the half thickness (mm), the reference measures, the levels'
    stiffness and the tying points' normals."""
    return (
        np.ascontiguousarray(positions, dtype=np.float64),
        np.ascontiguousarray(directors, dtype=np.float64),
        block.connectivity,
        block.zeta,
        0.5 * block.h,
        block.reference_measures,
        block.level_stiffness,
        block.tying_n,
    )


def _run_mindlin(block, positions, directors, with_forces: bool, work):
    """The cell pass: each cell's corner loads (m, 3, 6) (empty without ``with_forces``) and
    strain energy (m,), in ``work``'s arrays (a lease of femcore/workspace.py)."""
    m = len(block.connectivity)
    loads = work.empty("loads", (m, 3, 6) if with_forces else (0, 3, 6))
    energy = work.empty("energy", (m,))
    _mindlin_cells(
        *_cell_inputs(block, positions, directors),
        with_forces,
        loads,
        energy,
    )
    return loads, energy


def _nodal(block, loads):
    """The corner loads (m, 3, 6) summed to the nodes: (force, moment), (n, 3) each,
    C-contiguous."""
    corners = block.node_corners
    n = len(corners.offsets) - 1
    force, moment = np.empty((n, 3)), np.empty((n, 3))
    _node_sums6(corners.offsets, corners.corners, loads.reshape(-1, 6), force, moment)
    return force, moment


def _mindlin_forces(block, positions, directors, work, with_energy: bool = True):
    """The nodal forces and director moments (n, 3) of the block and its cells' strain
    energies (m,), in ``work``'s arrays (the energies; a lease of femcore/workspace.py).

    On one thread (femcore/jit.py ``threads_for``) one pass over the cells adds each cell's
    loads to its nodes (``mindlin_nodal``); on more, the cells' pass writes them to a buffer
    (m, 3, 6) that a pass over the nodes sums (``_node_sums6``). Each node gets its corners'
    loads in cell order from 0.0 either way: the same numbers to the last bit. Without
    ``with_energy`` the one pass leaves the energies out (their array is not written)."""
    m = len(block.connectivity)
    if threads_for(m) > 1:
        loads, energy = _run_mindlin(block, positions, directors, True, work)
        force, moment = _nodal(block, loads)
        return force, moment, energy
    n = len(block.node_corners.offsets) - 1
    force, moment = np.zeros((n, 3)), np.zeros((n, 3))
    energy = work.empty("energy", (m,))
    mindlin_nodal(
        *_cell_inputs(block, positions, directors),
        True,
        with_energy,
        force,
        moment,
        energy,
    )
    return force, moment, energy


def mindlin_loads(block, positions: np.ndarray, directors: np.ndarray):
    """Nodal internal forces and director moments (n, 3) of a MindlinShellBlock by the
    compiled kernel."""
    with workspace_of(block).lease() as work:  # the cells' arrays kept between calls
        force, moment, _ = _mindlin_forces(block, positions, directors, work, False)
        return force, moment


def mindlin_loads_and_energy(block, positions: np.ndarray, directors: np.ndarray):
    """Nodal internal forces and director moments (n, 3) and the strain energy (N mm) of a
    MindlinShellBlock, from one pass of the compiled kernel."""
    with workspace_of(block).lease() as work:
        force, moment, energy = _mindlin_forces(block, positions, directors, work)
        return force, moment, float(energy.sum())


def mindlin_energy(block, positions: np.ndarray, directors: np.ndarray) -> float:
    """Strain energy (N mm) of a MindlinShellBlock by the compiled kernel."""
    with workspace_of(block).lease() as work:
        return float(_run_mindlin(block, positions, directors, False, work)[1].sum())


@jit
def _cell_steps(positions, connectivity, reference_steps, inverse_metric, out):
    """The Mindlin cells' stable steps into out (m,): each cell's reference step over its
    largest in-plane stretch (at least 1), lambda^2 the larger eigenvalue of G^-1 g, g and G
    the metrics of the edges x1 - x0, x2 - x0 now and in the reference, inverse_metric (m, 4)
    = (G22, G12, G11, 1) / det G: elements/mindlin.py ``cell_stable_dt`` in one loop."""
    for c in prange(connectivity.shape[0]):
        n0, n1, n2 = connectivity[c, 0], connectivity[c, 1], connectivity[c, 2]
        ax, ay, az = _edge(positions, n0, n1)
        bx, by, bz = _edge(positions, n0, n2)
        g11 = ax * ax + ay * ay + az * az
        g22 = bx * bx + by * by + bz * bz
        g12 = ax * bx + ay * by + az * bz
        w = inverse_metric[c]
        half = 0.5 * (w[0] * g11 - 2.0 * w[1] * g12 + w[2] * g22)
        det = w[3] * (g11 * g22 - g12 * g12)
        stretch2 = half + np.sqrt(max(half * half - det, 0.0))
        out[c] = reference_steps[c] / np.sqrt(max(stretch2, 1.0))


def mindlin_cell_steps(block, positions: np.ndarray, reference_steps, inverse_metric):
    """Stable steps (m,) of a MindlinShellBlock's cells by the compiled loop."""
    out = np.empty(len(block.connectivity))
    _cell_steps(
        np.ascontiguousarray(positions, dtype=np.float64),
        block.connectivity,
        reference_steps,
        inverse_metric,
        out,
    )
    return out


def _point_transform(jac, warp, has_warp, t, transform):
    """At one integration point with covariant base vectors jac (3, 3) (rows G1, G2, G3):
    t[a, i] = e_a . G^i with the lamina frame e (e3 along G1 x G2, e1 along the warp, or
    G1 without one, made normal to e3) and the contravariant vectors G^i, and the
    covariant-to-lamina map of the engineering strains (11, 22, 12, 13, 23) into transform
    (5, 5) (elements/mindlin.py ``_material_matrices``). Returns det J."""
    g1x, g1y, g1z = jac[0, 0], jac[0, 1], jac[0, 2]
    g2x, g2y, g2z = jac[1, 0], jac[1, 1], jac[1, 2]
    g3x, g3y, g3z = jac[2, 0], jac[2, 1], jac[2, 2]
    # G^1 = G2 x G3 / det, G^2 = G3 x G1 / det, G^3 = G1 x G2 / det
    c23x, c23y, c23z = g2y * g3z - g2z * g3y, g2z * g3x - g2x * g3z, g2x * g3y - g2y * g3x
    c31x, c31y, c31z = g3y * g1z - g3z * g1y, g3z * g1x - g3x * g1z, g3x * g1y - g3y * g1x
    c12x, c12y, c12z = g1y * g2z - g1z * g2y, g1z * g2x - g1x * g2z, g1x * g2y - g1y * g2x
    det = g1x * c23x + g1y * c23y + g1z * c23z
    inverse = 1.0 / det if det != 0.0 else 0.0
    norm = np.sqrt(c12x * c12x + c12y * c12y + c12z * c12z)
    e3x, e3y, e3z = c12x / norm, c12y / norm, c12z / norm
    if has_warp:
        ux, uy, uz = warp[0], warp[1], warp[2]
    else:
        ux, uy, uz = g1x, g1y, g1z
    along = ux * e3x + uy * e3y + uz * e3z
    ux, uy, uz = ux - along * e3x, uy - along * e3y, uz - along * e3z
    norm = np.sqrt(ux * ux + uy * uy + uz * uz)
    e1x, e1y, e1z = ux / norm, uy / norm, uz / norm
    e2x, e2y, e2z = e3y * e1z - e3z * e1y, e3z * e1x - e3x * e1z, e3x * e1y - e3y * e1x
    for a in range(3):
        if a == 0:
            ex, ey, ez = e1x, e1y, e1z
        elif a == 1:
            ex, ey, ez = e2x, e2y, e2z
        else:
            ex, ey, ez = e3x, e3y, e3z
        t[a, 0] = (ex * c23x + ey * c23y + ez * c23z) * inverse
        t[a, 1] = (ex * c31x + ey * c31y + ez * c31z) * inverse
        t[a, 2] = (ex * c12x + ey * c12y + ez * c12z) * inverse
    for row in range(5):
        a, b = _PAIR_A[row], _PAIR_B[row]
        factor = 1.0 if a == b else 2.0
        for col in range(5):
            i, j = _PAIR_A[col], _PAIR_B[col]
            if i == j:
                value = t[a, i] * t[b, i]
            else:
                value = 0.5 * (t[a, i] * t[b, j] + t[a, j] * t[b, i])
            transform[row, col] = factor * value
    return det


# The strain components (11, 22, 12, 13, 23) as index pairs.
_PAIR_A = np.array([0, 1, 0, 0, 1])
_PAIR_B = np.array([0, 1, 1, 2, 2])
_point_transform = serial(_point_transform)


def _base_vectors(x, v, conn, c, zz, half, r, s, jac):
    """The covariant base vectors of cell c at level zz and in-plane point (r, s) into jac
    rows G1, G2, G3 (elements/mindlin.py ``_vectors`` and ``_material_matrices``)."""
    n0, n1, n2 = conn[c, 0], conn[c, 1], conn[c, 2]
    for i in range(3):
        jac[0, i] = x[n1, i] - x[n0, i] + zz * half * (v[n1, i] - v[n0, i])
        jac[1, i] = x[n2, i] - x[n0, i] + zz * half * (v[n2, i] - v[n0, i])
        jac[2, i] = half * ((1.0 - r - s) * v[n0, i] + r * v[n1, i] + s * v[n2, i])


_base_vectors = serial(_base_vectors)


@jit
def _mindlin_tables(
    points, directors, connectivity, zeta, zeta_weights, half, in_plane, warp, has_warp,
    lamina, shear_a, shear_b, stiffness, smallest_det, measures, area,
):  # fmt: skip
    """The packed level stiffness (m, Z, 28) of each triangle in its reference configuration
    (points, directors (n, 3)): D^_z = sum_p L_p^T (w_p det J T^T C T) L_p
    (elements/mindlin.py ``_level_stiffness_of``), the smallest det J of its points into
    ``smallest_det`` (m,), the reference products of its level measures into ``measures``
    (m, Z, 7: g1.g1, g2.g2, g1.g2, g1.g3^A, g1.g3^C, g2.g3^B, g2.g3^C) and its area into
    ``area`` (m,)."""
    m = connectivity.shape[0]
    chunks = (m + _CHUNK - 1) // _CHUNK
    for chunk in prange(chunks):
        # scratch per chunk of cells: allocated once, not once a cell
        jac = np.empty((3, 3))
        t = np.empty((3, 3))
        transform = np.empty((5, 5))
        ct = np.empty((5, 5))
        w = np.empty((5, 5))
        level = np.empty((7, 7))
        tying = np.empty((3, 3))
        for c in range(chunk * _CHUNK, min(m, (chunk + 1) * _CHUNK)):
            lowest = np.inf
            for q in range(3):  # g3 at the tying points A (1/2, 0), B (0, 1/2), C (1/2, 1/2)
                _base_vectors(
                    points, directors, connectivity, c, 0.0, half, (0.5, 0.0, 0.5)[q],
                    (0.0, 0.5, 0.5)[q], jac,
                )  # fmt: skip
                tying[q, 0], tying[q, 1], tying[q, 2] = jac[2, 0], jac[2, 1], jac[2, 2]
            cx = jac[0, 1] * jac[1, 2] - jac[0, 2] * jac[1, 1]
            cy = jac[0, 2] * jac[1, 0] - jac[0, 0] * jac[1, 2]
            cz = jac[0, 0] * jac[1, 1] - jac[0, 1] * jac[1, 0]
            area[c] = 0.5 * np.sqrt(cx * cx + cy * cy + cz * cz)  # (zeta = 0: the edges)
            for z in range(zeta.shape[0]):
                _base_vectors(points, directors, connectivity, c, zeta[z], half, 0.0, 0.0, jac)
                products = measures[c, z]
                products[0] = jac[0, 0] * jac[0, 0] + jac[0, 1] * jac[0, 1] + jac[0, 2] * jac[0, 2]
                products[1] = jac[1, 0] * jac[1, 0] + jac[1, 1] * jac[1, 1] + jac[1, 2] * jac[1, 2]
                products[2] = jac[0, 0] * jac[1, 0] + jac[0, 1] * jac[1, 1] + jac[0, 2] * jac[1, 2]
                for q in range(4):  # g1.g3^A, g1.g3^C, g2.g3^B, g2.g3^C
                    row, point = (0, 0, 1, 1)[q], (0, 2, 1, 2)[q]
                    products[3 + q] = (
                        jac[row, 0] * tying[point, 0]
                        + jac[row, 1] * tying[point, 1]
                        + jac[row, 2] * tying[point, 2]
                    )
                for i in range(7):
                    for j in range(7):
                        level[i, j] = 0.0
                for p in range(in_plane.shape[0]):
                    _base_vectors(
                        points, directors, connectivity, c, zeta[z], half, in_plane[p, 0],
                        in_plane[p, 1], jac,
                    )  # fmt: skip
                    det = _point_transform(jac, warp, has_warp, t, transform)
                    lowest = min(lowest, det)
                    weight = zeta_weights[z] * det / 6.0
                    # C T, C = diag(Q, kappa G13, kappa G23) (blocks: a third of the work)
                    for j in range(5):
                        for i in range(3):
                            ct[i, j] = (
                                lamina[i, 0] * transform[0, j]
                                + lamina[i, 1] * transform[1, j]
                                + lamina[i, 2] * transform[2, j]
                            )
                        ct[3, j] = lamina[3, 3] * transform[3, j]
                        ct[4, j] = lamina[4, 4] * transform[4, j]
                    for i in range(5):
                        for j in range(5):
                            total = 0.0
                            for k in range(5):
                                total += transform[k, i] * ct[k, j]
                            w[i, j] = weight * total
                    # L_p: identity on (E11, E22, 2E12); 2E13 = a_p . dt, 2E23 = b_p . dt
                    for i in range(3):
                        for j in range(3):
                            level[i, j] += w[i, j]
                        for j in range(4):
                            value = w[i, 3] * shear_a[p, j] + w[i, 4] * shear_b[p, j]
                            level[i, 3 + j] += value
                            level[3 + j, i] += w[3, i] * shear_a[p, j] + w[4, i] * shear_b[p, j]
                    for i in range(4):
                        for j in range(4):
                            level[3 + i, 3 + j] += shear_a[p, i] * (
                                w[3, 3] * shear_a[p, j] + w[3, 4] * shear_b[p, j]
                            ) + shear_b[p, i] * (w[4, 3] * shear_a[p, j] + w[4, 4] * shear_b[p, j])
                index = 0
                for i in range(7):
                    for j in range(i, 7):
                        stiffness[c, z, index] = 0.5 * (level[i, j] + level[j, i])
                        index += 1
            smallest_det[c] = lowest


@jit
def _mindlin_fields(
    positions, directors, points, directors0, connectivity, zeta, zeta_weights, half,
    in_plane, warp, has_warp, lamina, shear_a, shear_b, reference, out,
):  # fmt: skip
    """Section forces of each triangle into out (m, 8): membrane (N11, N22, N12) N/mm,
    bending (M11, M22, M12) N mm/mm, shear (Q1, Q2) N/mm in the lamina frame, averaged over
    the in-plane points (elements/mindlin.py ``cell_fields``): the lamina map of each point
    from the reference configuration (points, directors0), the strains from the current one."""
    m = connectivity.shape[0]
    nz, npts = zeta.shape[0], in_plane.shape[0]
    chunks = (m + _CHUNK - 1) // _CHUNK
    for chunk in prange(chunks):
        jac = np.empty((3, 3))
        now = np.empty((3, 3))
        t = np.empty((3, 3))
        transform = np.empty((5, 5))
        strain = np.empty(5)
        engineering = np.empty(5)
        e = np.empty(7)
        sums = np.empty(8)
        for c in range(chunk * _CHUNK, min(m, (chunk + 1) * _CHUNK)):
            for k in range(8):
                sums[k] = 0.0
            for z in range(nz):
                _base_vectors(positions, directors, connectivity, c, zeta[z], half, 0.0, 0.0, now)
                g1x, g1y, g1z = now[0, 0], now[0, 1], now[0, 2]
                g2x, g2y, g2z = now[1, 0], now[1, 1], now[1, 2]
                r = reference[c, z]
                e[0] = 0.5 * (g1x * g1x + g1y * g1y + g1z * g1z - r[0])
                e[1] = 0.5 * (g2x * g2x + g2y * g2y + g2z * g2z - r[1])
                e[2] = g1x * g2x + g1y * g2y + g1z * g2z - r[2]
                for q in range(4):  # tying points A, C, B, C against g1, g1, g2, g2
                    point = (0.5, 0.5, 0.0, 0.5)[q]
                    other = (0.0, 0.5, 0.5, 0.5)[q]
                    _base_vectors(
                        positions, directors, connectivity, c, 0.0, half, point, other, now
                    )  # fmt: skip
                    if q < 2:
                        e[3 + q] = g1x * now[2, 0] + g1y * now[2, 1] + g1z * now[2, 2] - r[3 + q]
                    else:
                        e[3 + q] = g2x * now[2, 0] + g2y * now[2, 1] + g2z * now[2, 2] - r[3 + q]
                through = half * zeta_weights[z]
                for p in range(npts):
                    _base_vectors(
                        points, directors0, connectivity, c, zeta[z], half, in_plane[p, 0],
                        in_plane[p, 1], jac,
                    )  # fmt: skip
                    _point_transform(jac, warp, has_warp, t, transform)
                    strain[0], strain[1], strain[2] = e[0], e[1], e[2]
                    strain[3] = 0.0
                    strain[4] = 0.0
                    for j in range(4):
                        strain[3] += shear_a[p, j] * e[3 + j]
                        strain[4] += shear_b[p, j] * e[3 + j]
                    for k in range(5):
                        total = 0.0
                        for j in range(5):
                            total += transform[k, j] * strain[j]
                        engineering[k] = total
                    for i in range(5):
                        stress = 0.0
                        for k in range(5):
                            stress += lamina[i, k] * engineering[k]
                        sums[i] += through * stress / npts
                        if i < 3:
                            sums[5 + i] += through * half * zeta[z] * stress / npts
            out[c, 0], out[c, 1], out[c, 2] = sums[0], sums[1], sums[2]
            out[c, 3], out[c, 4], out[c, 5] = sums[5], sums[6], sums[7]
            out[c, 6], out[c, 7] = sums[3], sums[4]


def _section(block) -> tuple:
    """The section arguments the Mindlin bind-time and output loops share, in their order:
    levels and weights, half thickness, the in-plane rule, the warp (vector and whether
    given), the lamina stiffness and the assumed-shear coefficients."""
    warp = block.material.warp
    return (
        block.zeta,
        block.zeta_weights,
        0.5 * block.h,
        IN_PLANE,
        np.zeros(3) if warp is None else np.asarray(warp, dtype=np.float64),
        warp is not None,
        block.lamina_stiffness,
        block.shear_a,
        block.shear_b,
    )


def mindlin_tables(block, points, directors, cells: slice = slice(None)):
    """(level stiffness (c, Z, 28), smallest det J (c,), reference products of the level
    measures (c, Z, 7), areas (c,)) of a MindlinShellBlock's cells by the compiled kernel,
    from the reference points and directors (n, 3)."""
    connectivity = np.ascontiguousarray(block.connectivity[cells])
    m = len(connectivity)
    stiffness = np.empty((m, len(block.zeta), 28))
    smallest = np.empty(m)
    measures = np.empty((m, len(block.zeta), 7))
    area = np.empty(m)
    _mindlin_tables(
        # reference and current positions and directors reach _base_vectors read-only (the
        # mesh's points are): one build of it (elements/kernel_inputs.py)
        read_only(points),
        read_only(directors),
        connectivity,
        *_section(block),
        stiffness,
        smallest,
        measures,
        area,
    )
    return stiffness, smallest, measures, area


def mindlin_fields(block, positions: np.ndarray, directors: np.ndarray) -> np.ndarray:
    """Section forces (m, 8) of a MindlinShellBlock by the compiled kernel: membrane (3),
    bending (3), shear (2)."""
    out = np.empty((len(block.connectivity), 8))
    _mindlin_fields(
        read_only(positions),
        read_only(directors),
        read_only(block.reference_positions),
        read_only(block.reference_directors),
        block.connectivity,
        *_section(block),
        block.reference_measures,
        out,
    )
    return out


# Cells per chunk of the bind-time and output loops: their scratch arrays are made once a
# chunk (an allocation per cell cost more than the arithmetic).
_CHUNK = 256

# In-plane 3-point rule (r, s) of the Mindlin triangle, weight 1/6 each in the (r, s)
# triangle of area 1/2 (elements/mindlin_tables.py).
IN_PLANE = np.array([[1 / 6, 1 / 6], [2 / 3, 1 / 6], [1 / 6, 2 / 3]])


@serial
def _cable_forces(positions, connectivity, rest_length, axial_stiffness, tension_only, out):
    """Nodal forces (n, 3) of 2-node cables, N = EA (l / L0 - 1) along the chord (elements/
    cable.py), gathered, computed and scattered in one serial loop (a cell's work is too small
    to share between threads)."""
    for c in range(connectivity.shape[0]):
        a, b = connectivity[c, 0], connectivity[c, 1]
        dx = positions[b, 0] - positions[a, 0]
        dy = positions[b, 1] - positions[a, 1]
        dz = positions[b, 2] - positions[a, 2]
        length = np.sqrt(dx * dx + dy * dy + dz * dz)
        force = axial_stiffness * (length / rest_length[c] - 1.0)
        if tension_only and force < 0.0:
            force = 0.0
        scale = force / length
        out[a, 0] -= scale * dx
        out[a, 1] -= scale * dy
        out[a, 2] -= scale * dz
        out[b, 0] += scale * dx
        out[b, 1] += scale * dy
        out[b, 2] += scale * dz


def cable_forces(block, positions: np.ndarray) -> np.ndarray:
    """Nodal internal forces (n, 3) of a CableBlock by the compiled kernel."""
    out = np.zeros((block.scatter.n_nodes, 3))
    _cable_forces(
        np.ascontiguousarray(positions, dtype=np.float64),
        block.connectivity,
        block.rest_length,
        float(block.axial_stiffness),
        bool(block.tension_only),
        out,
    )
    return out
