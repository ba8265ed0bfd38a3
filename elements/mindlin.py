"""MindlinShell: a large-rotation Reissner-Mindlin triangle in the geometry of the fibrous shell
(docs/theory.md §5), the reference kinematics of the project (the role Abaqus S3 plays in Bai et
al.).

Same map as the fibrous shell, x = sum N_k x_k + zeta/2 h sum N_k V_k (Bai Eq. 5) with a fixed
thickness h and unit directors that start normal to the surface; 5 DOF per node (ux uy uz alpha
beta) with the director update of docs/theory.md §1.3. Total Lagrangian: covariant Green-Lagrange
strains
E_ij = (g_i . g_j - G_i . G_j) / 2 at Gauss points through the thickness, plane stress in the
lamina frame (St Venant-Kirchhoff), and MITC3 assumed transverse shear (Lee & Bathe, Comput.
Struct. 82 (2004) 945) tied at the edge mid-points so that thin shells do not lock.

Vectorised over the cells of a block; the material matrices at every integration point (reference
geometry, lamina frame, Jacobian) are computed once at bind.
"""

from __future__ import annotations

import numpy as np

from elements.base import CellTangent, ElementBlock, ElementType, local_tangent
from femcore.assembly import Scatter
from femcore.mesh import Mesh
from femcore.rotation import cross
from femcore.state import State
from materials.elastic import ElasticShell

__all__ = ["MindlinShell", "MindlinShellBlock"]

# In-plane 3-point rule (r, s), weight 1/6 each in the (r, s) triangle of area 1/2.
_IN_PLANE = np.array([[1 / 6, 1 / 6], [2 / 3, 1 / 6], [1 / 6, 2 / 3]])
# MITC3 tying points A (1/2, 0), B (0, 1/2), C (1/2, 1/2): shape functions N_k there.
_TYING_N = np.array([[0.5, 0.5, 0.0], [0.5, 0.0, 0.5], [0.0, 0.5, 0.5]])


def _assumed_shear_coefficients() -> tuple[np.ndarray, np.ndarray]:
    """Rows a_p, b_p with e_rt(p) = a_p . t and e_st(p) = b_p . t, t = (e_rt^A, e_rt^C,
    e_st^B, e_st^C): e_rt = e_rt^A + c s, e_st = e_st^B - c r, c = (e_rt^C - e_rt^A) -
    (e_st^C - e_st^B) (docs/theory.md §5.3)."""
    r, s = _IN_PLANE[:, 0], _IN_PLANE[:, 1]
    a = np.column_stack([1 - s, s, s, -s])
    b = np.column_stack([r, -r, 1 - r, r])
    return a, b


class MindlinShell(ElementType):
    """Reissner-Mindlin shell triangle with MITC3 transverse shear.

    material : materials.ElasticShell.
    thickness_points : Gauss points through the thickness (default 2; 2-5).
    rotary_scaling : scale the rotary inertia to j = max(h^2/12, kappa (1 - nu) L_e^2 / 16)
        (docs/theory.md §6.2 B2) so that thin elements do not force a tiny step (default True).
    """

    dofs = ("ux", "uy", "uz", "alpha", "beta")
    cell_type = "triangle"
    defines_directors = True

    def __init__(
        self, material: ElasticShell, thickness_points: int = 2, rotary_scaling: bool = True
    ):
        if not isinstance(material, ElasticShell):
            raise ValueError(f"MindlinShell needs a materials.ElasticShell, got {material!r}")
        if isinstance(thickness_points, bool) or thickness_points not in (2, 3, 4, 5):
            raise ValueError(f"thickness_points must be 2, 3, 4 or 5, got {thickness_points!r}")
        self.material = material
        self.thickness_points = int(thickness_points)
        self.rotary_scaling = bool(rotary_scaling)

    def bind(self, mesh: Mesh, cell_ids: np.ndarray, directors: np.ndarray) -> MindlinShellBlock:
        return MindlinShellBlock(self, mesh, cell_ids, directors)


class MindlinShellBlock(ElementBlock):
    """MindlinShell over mesh triangles ``cell_ids``.

    Precomputed: ``weighted_stiffness`` (m, 3, Z, 5, 5), the material matrix acting on the
    covariant strain vector (E11, E22, 2E12, 2E13, 2E23) at each in-plane point and thickness
    point, times the integration weight and det J (so W = 1/2 sum E . D E); ``to_lamina``
    (m, 3, Z, 5, 5) from covariant to lamina-frame engineering strains; reference vectors.
    """

    dofs = MindlinShell.dofs
    cell_type = MindlinShell.cell_type
    reach = 1

    def __init__(self, shell: MindlinShell, mesh: Mesh, cell_ids, directors):
        self.material = material = shell.material
        self.h = material.thickness
        self.n_nodes = mesh.n_nodes
        self.cell_ids = np.asarray(cell_ids, dtype=np.int64)
        self.connectivity = mesh.triangles[self.cell_ids]
        self.scatter = Scatter(self.connectivity, mesh.n_nodes)
        self.reference_positions = np.asarray(mesh.points, dtype=float)
        zeta, weights = np.polynomial.legendre.leggauss(shell.thickness_points)
        self.zeta, self.zeta_weights = zeta, weights
        self.shear_a, self.shear_b = _assumed_shear_coefficients()

        x0 = np.asarray(mesh.points, dtype=float)[self.connectivity]
        v0 = np.asarray(directors, dtype=float)[self.connectivity]
        self.reference_area = 0.5 * np.linalg.norm(
            cross(x0[:, 1] - x0[:, 0], x0[:, 2] - x0[:, 0]), axis=1
        )
        ref = self._vectors(x0, v0)
        self.reference = ref
        self.reference_metric = self._metric(ref)
        self._material_matrices(ref, v0)
        self.rotary_factor = self._rotary_factor(shell.rotary_scaling)

    # ------------------------------------------------------------------ geometry
    def _vectors(self, x: np.ndarray, v: np.ndarray) -> dict:
        """Covariant vectors: g1, g2 (m, Z, 3) at each thickness point (constant in r, s for
        the linear triangle) and g3 (m, 3 tying points A, B, C, 3); and the edge/director
        differences that the variations need."""
        half = 0.5 * self.h
        d1, d2 = x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]
        w1, w2 = half * (v[:, 1] - v[:, 0]), half * (v[:, 2] - v[:, 0])
        z = self.zeta[None, :, None]
        g1 = d1[:, None, :] + z * w1[:, None, :]
        g2 = d2[:, None, :] + z * w2[:, None, :]
        g3 = half * np.matmul(_TYING_N, v)  # (m, 3, 3): at A, B, C
        return {"g1": g1, "g2": g2, "g3": g3}

    def _metric(self, vec: dict) -> dict:
        """Products entering the covariant strains: (m, Z) in-plane and (m, Z, 4) tying values
        t = (g1.g3^A, g1.g3^C, g2.g3^B, g2.g3^C)."""
        g1, g2, g3 = vec["g1"], vec["g2"], vec["g3"]
        tying = np.stack(
            [
                np.matmul(g1, g3[:, 0, :, None])[..., 0],
                np.matmul(g1, g3[:, 2, :, None])[..., 0],
                np.matmul(g2, g3[:, 1, :, None])[..., 0],
                np.matmul(g2, g3[:, 2, :, None])[..., 0],
            ],
            axis=-1,
        )
        return {
            "11": np.sum(g1 * g1, -1),
            "22": np.sum(g2 * g2, -1),
            "12": np.sum(g1 * g2, -1),
            "tying": tying,
        }

    def _material_matrices(self, ref: dict, v0: np.ndarray) -> None:
        """D = w det(J) T^T C T at every point, with T the covariant-to-lamina transformation
        (docs/theory.md §5.2) and C = diag(Q rotated to the lamina frame, kappa G13, kappa G23)."""
        m, nz = len(self.cell_ids), len(self.zeta)
        half = 0.5 * self.h
        r, s = _IN_PLANE[:, 0], _IN_PLANE[:, 1]
        shape = np.column_stack([1 - r - s, r, s])  # (3 points, 3 nodes)
        g3_points = half * np.einsum("pk,mkj->mpj", shape, v0)  # (m, P, 3)
        g1 = np.broadcast_to(ref["g1"][:, None], (m, 3, nz, 3))
        g2 = np.broadcast_to(ref["g2"][:, None], (m, 3, nz, 3))
        g3 = np.broadcast_to(g3_points[:, :, None], (m, 3, nz, 3))
        jacobian = np.stack([g1, g2, g3], axis=-1)  # columns G1 G2 G3
        det = np.linalg.det(jacobian)
        contravariant = np.linalg.inv(jacobian)  # rows G^1, G^2, G^3
        e3 = cross(g1, g2)
        e3 /= np.linalg.norm(e3, axis=-1, keepdims=True)
        axis = g1 if self.material.warp is None else np.broadcast_to(self.material.warp, g1.shape)
        e1 = axis - np.sum(axis * e3, -1, keepdims=True) * e3
        e1 /= np.linalg.norm(e1, axis=-1, keepdims=True)
        e2 = cross(e3, e1)
        frame = np.stack([e1, e2, e3], axis=-2)  # rows e_a
        t = np.matmul(frame, np.swapaxes(contravariant, -1, -2))  # t[a, i] = e_a . G^i
        # Lamina engineering strains (11, 22, 12, 13, 23) from covariant (11, 22, 12, 13, 23)
        # (engineering shears on both sides; E33 is dropped: plane stress).
        pairs = [(0, 0), (1, 1), (0, 1), (0, 2), (1, 2)]
        transform = np.zeros((m, 3, nz, 5, 5))
        for row, (a, b) in enumerate(pairs):
            for col, (i, j) in enumerate(pairs):
                if i == j:
                    value = t[..., a, i] * t[..., b, i]
                else:
                    value = 0.5 * (t[..., a, i] * t[..., b, j] + t[..., a, j] * t[..., b, i])
                transform[..., row, col] = (1.0 if a == b else 2.0) * value
        c = np.zeros((5, 5))
        c[:3, :3] = self.material.plane_stress
        c[3, 3], c[4, 4] = self.material.transverse
        weight = (1.0 / 6.0) * self.zeta_weights[None, None, :] * det
        self.to_lamina = transform
        self.lamina_stiffness = c
        self.point_weight = weight  # (m, P, Z), mm^3
        self.weighted_stiffness = (
            weight[..., None, None] * np.swapaxes(transform, -1, -2) @ c @ transform
        )
        if np.any(det <= 0):
            bad = int(self.cell_ids[np.argmax((det <= 0).any(axis=(1, 2)))])
            raise ValueError(f"triangle {bad}: the director field inverts the shell volume")

    # ------------------------------------------------------------------ strains and forces
    def _covariant_strains(self, vec: dict) -> np.ndarray:
        """(m, P, Z, 5): E11, E22, 2E12 (uniform in r, s) and the MITC3 shears 2E13, 2E23."""
        cur, ref = self._metric(vec), self.reference_metric
        e11 = 0.5 * (cur["11"] - ref["11"])
        e22 = 0.5 * (cur["22"] - ref["22"])
        e12 = cur["12"] - ref["12"]
        tying = 0.5 * (cur["tying"] - ref["tying"])  # covariant e_rt^A, e_rt^C, e_st^B, e_st^C
        rt = 2.0 * np.matmul(tying, self.shear_a.T)  # (m, Z, P)
        st = 2.0 * np.matmul(tying, self.shear_b.T)
        m, nz = e11.shape
        in_plane = np.broadcast_to(np.stack([e11, e22, e12], -1)[:, None], (m, 3, nz, 3))
        shear = np.stack([rt, st], -1).transpose(0, 2, 1, 3)  # (m, P, Z, 2)
        return np.concatenate([in_plane, shear], axis=-1)

    def _state_vectors(self, state: State) -> dict:
        x = state.positions[self.connectivity]
        v = state.directors[self.connectivity]
        vec = self._vectors(x, v)
        vec["directors"] = v
        return vec

    def internal_force(self, state: State, history=None):
        x = state.positions[self.connectivity]
        v = state.directors[self.connectivity]
        force, moment = self._cell_loads(x, v)
        return self.scatter.vectors(force), self.scatter.vectors(moment)

    def tangent(self, state: State, history=None) -> list[CellTangent]:
        """Each triangle's 18 x 18 stiffness in (u, psi) of its corners, by central
        differences of its own loads (all triangles at once, 36 evaluations)."""
        x = state.positions[self.connectivity]
        v = state.directors[self.connectivity]
        step = 1e-6 * float(np.sqrt(np.median(self.reference_area)))
        return [CellTangent(self.connectivity, local_tangent(self._cell_loads, x, v, step))]

    def _cell_loads(self, x: np.ndarray, v: np.ndarray):
        """Unscattered nodal forces and director moments (m, 3, 3) of each triangle from its
        corner positions x and directors v (m, 3, 3)."""
        vec = self._vectors(x, v)
        vec["directors"] = v
        strain = self._covariant_strains(vec)
        stress = np.matmul(self.weighted_stiffness, strain[..., None])[..., 0]  # (m, P, Z, 5)
        g1, g2, g3 = vec["g1"], vec["g2"], vec["g3"]
        # In-plane conjugates are uniform over r, s: sum the in-plane points.
        s11, s22, s12 = (stress[..., k].sum(axis=1) for k in range(3))  # (m, Z)
        # Conjugates of the tying values (e_rt^A, e_rt^C, e_st^B, e_st^C), (m, Z, 4).
        y = 2.0 * (
            np.matmul(stress[..., 3].transpose(0, 2, 1), self.shear_a)
            + np.matmul(stress[..., 4].transpose(0, 2, 1), self.shear_b)
        )
        half_y = 0.5 * y[..., None]
        p1 = (
            s11[..., None] * g1
            + s12[..., None] * g2
            + half_y[:, :, 0] * g3[:, None, 0]
            + half_y[:, :, 1] * g3[:, None, 2]
        )
        p2 = (
            s22[..., None] * g2
            + s12[..., None] * g1
            + half_y[:, :, 2] * g3[:, None, 1]
            + half_y[:, :, 3] * g3[:, None, 2]
        )
        q = np.stack(
            [
                (half_y[:, :, 0] * g1).sum(axis=1),
                (half_y[:, :, 2] * g2).sum(axis=1),
                (half_y[:, :, 1] * g1 + half_y[:, :, 3] * g2).sum(axis=1),
            ],
            axis=1,
        )  # dW/dg3 at A, B, C: (m, 3, 3)
        t1, t2 = p1.sum(axis=1), p2.sum(axis=1)
        force = np.stack([-(t1 + t2), t1, t2], axis=1)
        half = 0.5 * self.h
        a1, a2 = np.matmul(self.zeta, p1), np.matmul(self.zeta, p2)
        d_director = half * np.stack([-(a1 + a2), a1, a2], axis=1)
        d_director += half * np.matmul(_TYING_N.T, q)  # g3^T = h/2 sum_k N_k(T) V_k
        moment = cross(vec["directors"], d_director)
        return force, moment

    def strain_energy(self, state: State, history=None) -> float:
        strain = self._covariant_strains(self._state_vectors(state))
        stress = np.matmul(self.weighted_stiffness, strain[..., None])[..., 0]
        return float(0.5 * np.sum(strain * stress))

    # ------------------------------------------------------------------ mass and step
    def _rotary_factor(self, scaling: bool) -> np.ndarray:
        """j (m,), mm^2: I = m j; h^2/12, or with ``scaling`` the B2 scaling of docs/theory.md §6.2
        (from the reference altitudes: computed once at bind)."""
        j = np.full(len(self.cell_ids), self.h**2 / 12.0)
        if scaling:
            kappa, nu = self.material.shear_factor, self.material.poisson
            j = np.maximum(j, kappa * (1 - nu) * self._altitude() ** 2 / 16.0)
        return j

    def _altitude(self, positions: np.ndarray | None = None) -> np.ndarray:
        """Smallest altitude 2A / L_max of each triangle (m,), mm."""
        x = (self.reference_positions if positions is None else positions)[self.connectivity]
        sides = np.linalg.norm(x[:, [1, 2, 0]] - x, axis=-1)
        area2 = np.linalg.norm(cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]), axis=1)
        return area2 / sides.max(axis=1)

    def lumped_mass(self, state: State, density_scale=None):
        share = self.material.areal_density * self.reference_area / 3.0
        if density_scale is not None:
            share = share * np.asarray(density_scale, dtype=float)
        per_node = np.repeat(share[:, None], 3, axis=1)
        mass = self.scatter.scalars(per_node)
        inertia = self.scatter.scalars(per_node * self.rotary_factor[:, None])
        return mass, inertia

    def cell_stable_dt(self, state: State) -> np.ndarray:
        """Critical step per cell, omega^2 = omega_in-plane^2 + omega_rotation^2 (docs/theory.md
        §6.2):

        * translations: the trace bound of M^-1 K for a linear triangle with lumped mass
          rho h A / 3, omega^2 <= 3 / rho (max(Q11, Q22) + Q66 + kappa G) sum_k 1 / h_k^2
          (h_k the altitudes; membrane and transverse-shear stiffness of each DOF);
        * rotations (B2): omega^2 = kappa G / (2 rho j) with the (scaled) rotary factor j.
        """
        x = state.positions[self.connectivity]
        sides = np.linalg.norm(x[:, [2, 0, 1]] - x[:, [1, 2, 0]], axis=-1)  # opposite node k
        area2 = np.linalg.norm(cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]), axis=1)
        inverse_heights2 = np.sum((sides / area2[:, None]) ** 2, axis=1)
        q = self.material.plane_stress
        shear = float(np.max(self.material.transverse))
        rho = self.material.density
        omega2 = 3.0 / rho * (max(q[0, 0], q[1, 1]) + q[2, 2] + shear) * inverse_heights2
        omega2 = omega2 + shear / (2.0 * rho * self.rotary_factor)
        return 2.0 / np.sqrt(omega2)

    # ------------------------------------------------------------------ outputs
    def cell_fields(self, state: State, history=None) -> dict[str, np.ndarray]:
        """Section forces per unit length in the lamina frame, averaged over the element:
        membrane (N11, N22, N12) N/mm, bending (M11, M22, M12) N mm/mm, shear (Q1, Q2) N/mm."""
        strain = self._covariant_strains(self._state_vectors(state))
        lamina = np.matmul(self.to_lamina, strain[..., None])[..., 0]
        stress = np.matmul(self.lamina_stiffness, lamina[..., None])[..., 0]  # (m, P, Z, 5)
        half = 0.5 * self.h
        through = half * self.zeta_weights  # dz = h/2 dzeta
        mean = stress.mean(axis=1)  # over the in-plane points
        resultant = np.einsum("z,mzc->mc", through, mean)
        moment = np.einsum("z,mzc->mc", through * half * self.zeta, mean)
        return {
            "membrane_force": resultant[:, :3],
            "bending_moment": moment[:, :3],
            "shear_force": resultant[:, 3:],
        }

    def total_mass(self) -> float:
        return float(self.material.areal_density * self.reference_area.sum())
