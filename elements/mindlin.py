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
geometry, lamina frame, Jacobian) are computed once at bind. The tangent is analytic and
consistent (docs/theory.md §5.5): material and geometric Hessian of the strain energy in the
corner positions and directors, carried to the rotation vectors of the directors.
"""

from __future__ import annotations

from typing import cast

import numpy as np

from elements import kernels
from elements.base import CellTangent, ElementBlock, ElementType, check_positive, local_tangent
from elements.mindlin_tangent import mindlin_tangent_blocks
from femcore.assembly import Scatter
from femcore.checks import as_reals
from femcore.mesh import Mesh
from femcore.rotation import cross
from femcore.state import State
from femcore.topology import nodal_normals
from materials.elastic import ElasticShell
from materials.fabric import Fabric

__all__ = ["MindlinShell", "MindlinShellBlock"]

# In-plane 3-point rule (r, s), weight 1/6 each in the (r, s) triangle of area 1/2.
_IN_PLANE = np.array([[1 / 6, 1 / 6], [2 / 3, 1 / 6], [1 / 6, 2 / 3]])
# MITC3 tying points A (1/2, 0), B (0, 1/2), C (1/2, 1/2): shape functions N_k there.
_TYING_N = np.array([[0.5, 0.5, 0.0], [0.5, 0.0, 0.5], [0.0, 0.5, 0.5]])
# The seven strain measures of a thickness level (docs/theory.md §5.5), each a product
# f (g_a . g_b) of two of the vectors (g1, g2, g3^A, g3^B, g3^C) = indices 0-4: E11 = g1.g1/2,
# E22 = g2.g2/2, 2E12 = g1.g2 and the tying products g1.g3^A, g1.g3^C, g2.g3^B, g2.g3^C.
_PRODUCTS = (
    (0, 0, 0.5),
    (1, 1, 0.5),
    (0, 1, 1.0),
    (0, 2, 1.0),
    (0, 4, 1.0),
    (1, 3, 1.0),
    (1, 4, 1.0),
)
# Cells per slice of the analytic tangent (MindlinShellBlock.tangent).
_TANGENT_SLICE = 256


def _assumed_shear_coefficients() -> tuple[np.ndarray, np.ndarray]:
    """Rows a_p, b_p with e_rt(p) = a_p . t and e_st(p) = b_p . t, t = (e_rt^A, e_rt^C,
    e_st^B, e_st^C): e_rt = e_rt^A + c s, e_st = e_st^B - c r, c = (e_rt^C - e_rt^A) -
    (e_st^C - e_st^B) (docs/theory.md §5.3)."""
    r, s = _IN_PLANE[:, 0], _IN_PLANE[:, 1]
    a = np.column_stack([1 - s, s, s, -s])
    b = np.column_stack([r, -r, 1 - r, r])
    return a, b


def _strain_maps(shear_a: np.ndarray, shear_b: np.ndarray) -> np.ndarray:
    """L_p (P, 5, 7): the strain vector (E11, E22, 2E12, 2E13, 2E23) at in-plane point p from
    the level measures e = (E11, E22, 2E12, dt_A1, dt_C1, dt_B2, dt_C2) of docs/theory.md §5.5
    (dt: change of a tying product g_alpha . g3^T; 2E13 = a_p . dt, 2E23 = b_p . dt, §5.3)."""
    maps = np.zeros((len(_IN_PLANE), 5, 7))
    maps[:, :3, :3] = np.eye(3)
    maps[:, 3, 3:] = shear_a
    maps[:, 4, 3:] = shear_b
    return maps


def _product_coefficients(zeta: np.ndarray, h: float) -> tuple[np.ndarray, np.ndarray]:
    """Constant tables of the level measures e_r = f_r g_a . g_b (docs/theory.md §5.5) over the
    18 cell numbers s = (x_1, x_2, x_3, V_1, V_2, V_3).

    Each vector is linear in s, g_u = sum_k c_uk s_k, with scalar c (Z, 5, 6): g1 and g2 at the
    level zeta, g3 at the tying points. Returns

    * ``gradient`` (Z, 7, 6, 5): de_r/ds_k = sum_u gradient[r, k, u] g_u (a 3-vector), i.e.
      f_r (c_ak g_b + c_bk g_a);
    * ``curvature`` (Z, 7, 6, 6): d2e_r/ds_k ds_l = curvature[r, k, l] I3, i.e.
      f_r (c_ak c_bl + c_bk c_al), constant (the measures are quadratic in s).
    """
    half = 0.5 * h
    nz = len(zeta)
    c = np.zeros((nz, 5, 6))
    d_xi, d_eta = np.array([-1.0, 1.0, 0.0]), np.array([-1.0, 0.0, 1.0])
    c[:, 0, :3], c[:, 1, :3] = d_xi, d_eta
    c[:, 0, 3:] = half * zeta[:, None] * d_xi
    c[:, 1, 3:] = half * zeta[:, None] * d_eta
    c[:, 2:, 3:] = half * _TYING_N  # g3^T = h/2 sum_k N_k(T) V_k
    gradient = np.zeros((nz, 7, 6, 5))
    curvature = np.zeros((nz, 7, 6, 6))
    for r, (a, b, f) in enumerate(_PRODUCTS):
        gradient[:, r, :, b] += f * c[:, a]
        gradient[:, r, :, a] += f * c[:, b]
        outer = c[:, a, :, None] * c[:, b, None, :]
        curvature[:, r] = f * (outer + np.swapaxes(outer, -1, -2))
    return gradient, curvature


def _turned_gradient_table(gradient: np.ndarray) -> np.ndarray:
    """(Z, 42, 20): row (r, k, t) of B^psi (docs/theory.md §5.5) from the 20 vectors
    (g_u, V_1 x g_u, V_2 x g_u, V_3 x g_u), u = 0-4: de_r/du_k (t = 0) = sum_u c g_u and
    de_r/dpsi_k (t = 1) = V_k x de_r/dV_k = sum_u c (V_k x g_u), with the c of ``gradient``
    (Z, 7, 6, 5) from _product_coefficients."""
    nz = len(gradient)
    table = np.zeros((nz, 7, 3, 2, 4, 5))
    for k in range(3):
        table[:, :, k, 0, 0] = gradient[:, :, k]
        table[:, :, k, 1, 1 + k] = gradient[:, :, 3 + k]
    return table.reshape(nz, 42, 20)


class MindlinShell(ElementType):
    """Reissner-Mindlin shell triangle with MITC3 transverse shear.

    material : materials.ElasticShell (a homogeneous elastic section, integrated through the
        thickness), or materials.Fabric: the section is the fabric itself, by stress resultants
        from its own laws (fibre tension, in-plane shear, the bending laws as given, non-linear
        ones included; docs/theory.md §5.7, elements/mindlin_fabric.py), so that a comparison
        with the FibrousShell on the same Fabric changes the kinematics alone.
    thickness_points : Gauss points through the thickness of an elastic section (default 2; 2-5).
    rotary_scaling : scale the rotary inertia to j = max(h^2/12, kappa (1 - nu) L_e^2 / 16)
        (docs/theory.md §6.2 B2) so that thin elements do not force a tiny step (default True).
    kernel : "compiled" (default when numba is installed: the internal forces by the fused,
        parallel loop of elements/kernels.py) or "numpy" (the vectorised reference). A fabric
        section runs numpy.
    warp : a Fabric's warp direction in the reference configuration, (3,); default x. The weft
        is the in-plane perpendicular, n x warp. (An ElasticShell carries its own.)
    transverse_shear : a Fabric section's transverse shear stiffness S = kappa G h, N/mm;
        default 5 B0 / h^2 (``elements.mindlin_fabric.default_transverse_shear``: the
        homogeneous isotropic plate with the fabric's initial bending stiffness B0).
    twisting : a Fabric section's twisting stiffness D_t, N mm (moment per width per unit
        engineering twist 2 chi_12); default B0 / 2 (``default_twisting``: the isotropic plate
        of the transverse shear default, nu = 0).
    """

    dofs = ("ux", "uy", "uz", "alpha", "beta")
    cell_type = "triangle"
    defines_directors = True

    def __init__(
        self,
        material: ElasticShell | Fabric,
        thickness_points: int = 2,
        rotary_scaling: bool = True,
        kernel: str | None = None,
        warp=None,
        transverse_shear: float | None = None,
        twisting: float | None = None,
    ):
        if not isinstance(material, (ElasticShell, Fabric)):
            raise ValueError(
                f"MindlinShell needs a materials.ElasticShell or a materials.Fabric, got "
                f"{material!r}"
            )
        if isinstance(thickness_points, bool) or thickness_points not in (2, 3, 4, 5):
            raise ValueError(f"thickness_points must be 2, 3, 4 or 5, got {thickness_points!r}")
        kernel = kernels.choose(kernel)
        self.material = material
        self.thickness_points = int(thickness_points)
        self.rotary_scaling = bool(rotary_scaling)
        self.kernel = kernel
        if isinstance(material, ElasticShell):
            given = [
                name
                for name, value in (
                    ("warp", warp),
                    ("transverse_shear", transverse_shear),
                    ("twisting", twisting),
                )
                if value is not None
            ]
            if given:
                raise ValueError(
                    f"MindlinShell: {', '.join(given)} belong to a Fabric section; an "
                    "ElasticShell carries its own warp and moduli"
                )
            return
        from elements.mindlin_fabric import default_transverse_shear, default_twisting

        axis = as_reals(
            (1.0, 0.0, 0.0) if warp is None else warp, "MindlinShell warp", "a non-zero 3-vector"
        ).ravel()
        if axis.shape != (3,) or not np.isfinite(axis).all() or np.linalg.norm(axis) == 0:
            raise ValueError(f"MindlinShell warp must be a non-zero 3-vector, got {warp!r}")
        self.warp = axis / np.linalg.norm(axis)
        self.transverse_shear = (
            default_transverse_shear(material)
            if transverse_shear is None
            else check_positive(transverse_shear, "MindlinShell transverse_shear", "N/mm")
        )
        self.twisting = (
            default_twisting(material)
            if twisting is None
            else check_positive(twisting, "MindlinShell twisting", "N mm")
        )

    @property
    def half_thickness(self) -> float:
        """h / 2, mm: the contact surface's offset from the mid-surface along the normal."""
        return 0.5 * self.material.thickness

    def bind(self, mesh: Mesh, cell_ids: np.ndarray, directors: np.ndarray) -> MindlinShellBlock:
        if isinstance(self.material, Fabric):
            from elements.mindlin_fabric import MindlinFabricBlock

            return MindlinFabricBlock(self, mesh, cell_ids, directors)
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
        # An elastic section here; the fabric block (elements/mindlin_fabric.py) overrides
        # every use of it.
        self.material = material = cast(ElasticShell, shell.material)
        self.kernel = shell.kernel
        self.tying_n = _TYING_N
        self.h = material.thickness
        self.n_nodes = mesh.n_nodes
        self.cell_ids = np.asarray(cell_ids, dtype=np.int64)
        self.connectivity = mesh.triangles[self.cell_ids]
        self.scatter = Scatter(self.connectivity, mesh.n_nodes)
        # the compiled path's sums from cells to nodes (parallel over nodes)
        self.node_corners = kernels.NodeCorners(self.connectivity, mesh.n_nodes)
        self.reference_positions = np.asarray(mesh.points, dtype=float)
        zeta, weights = self._thickness_levels(shell)
        self.zeta, self.zeta_weights = zeta, weights
        self.shear_a, self.shear_b = _assumed_shear_coefficients()
        gradient, self._curvature_table = _product_coefficients(zeta, self.h)
        self._director_gradient_table = gradient[:, :, 3:].reshape(len(zeta), 7, 15)
        self._turned_gradient_table = _turned_gradient_table(gradient)
        self._level_stiffness_cache: np.ndarray | None = None
        self._product_tables: tuple[np.ndarray, np.ndarray] | None = None

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
        # The stable step's calibration (omega^2 of each element's eigenvalue problem over
        # the cheap bound), computed from these at the first call of cell_stable_dt.
        self._reference_cells = (x0, v0)
        self._step_calibration: np.ndarray | None = None

    def _thickness_levels(self, shell: MindlinShell) -> tuple[np.ndarray, np.ndarray]:
        """The levels zeta (Z,) through the thickness where the strains are measured, and
        their integration weights: Gauss points for the elastic section."""
        return np.polynomial.legendre.leggauss(shell.thickness_points)

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
        if self.kernel == "compiled":
            return kernels.mindlin_loads(self, state.positions, state.directors)
        x = state.positions[self.connectivity]
        v = state.directors[self.connectivity]
        force, moment = self._cell_loads(x, v)
        return self.scatter.vectors(force), self.scatter.vectors(moment)

    def tangent(self, state: State, history=None) -> list[CellTangent]:
        """Each triangle's consistent 18 x 18 stiffness in (u, psi) of its corners, analytic
        (docs/theory.md §5.5): blocks (m, 3, 6, 3, 6), N/mm, N, N mm."""
        x = state.positions[self.connectivity]
        v = state.directors[self.connectivity]
        # The compiled loop for the elastic section, whose level response is linear (a
        # fabric section answers by its own laws: the numpy path).
        if self.kernel == "compiled" and type(self)._level_response is _ELASTIC_RESPONSE:
            if self._product_tables is None:
                self._product_tables = _product_coefficients(self.zeta, self.h)
            blocks = mindlin_tangent_blocks(
                self, x, v, self._level_stiffness(), *self._product_tables
            )
            return [CellTangent(self.connectivity, blocks)]
        blocks = np.empty((len(x), 3, 6, 3, 6))
        # Slices of cells: the temporaries (a few times the output) then stay small and are
        # reused from one slice to the next instead of being mapped and page-faulted afresh,
        # which costs more than the arithmetic on a large block.
        for start in range(0, len(x), _TANGENT_SLICE):
            cells = slice(start, start + _TANGENT_SLICE)
            blocks[cells] = self._cell_tangent(x[cells], v[cells], cells)
        return [CellTangent(self.connectivity, blocks)]

    def difference_tangent(self, state: State) -> list[CellTangent]:
        """The blocks of ``tangent`` by central differences of the element loads (36
        evaluations of the loads of all triangles, step 1e-6 of the median element size): the
        reference the analytic tangent is checked against, and its cost.

        Parameters
        ----------
        state : State
            Positions (n, 3) and directors (n, 3) to differentiate at.

        Returns
        -------
        list of CellTangent
            One entry: blocks (m, 3, 6, 3, 6) in (u, psi) of the corners, N/mm, N, N mm.
        """
        x = state.positions[self.connectivity]
        v = state.directors[self.connectivity]
        step = 1e-6 * float(np.sqrt(np.median(self.reference_area)))
        return [CellTangent(self.connectivity, local_tangent(self._cell_loads, x, v, step))]

    def _level_stiffness(self) -> np.ndarray:
        """D^_z = sum_p L_p^T D_pz L_p (m, Z, 7, 7), N mm (docs/theory.md §5.5): the stiffness
        of the seven level measures, the in-plane points summed out. Built at the first tangent
        and kept (explicit dynamics never needs it)."""
        if self._level_stiffness_cache is None:
            maps = _strain_maps(self.shear_a, self.shear_b)[None, :, None]  # (1, P, 1, 5, 7)
            per_point = np.swapaxes(maps, -1, -2) @ self.weighted_stiffness @ maps
            self._level_stiffness_cache = per_point.sum(axis=1)
        return self._level_stiffness_cache

    def _level_measures(self, vec: dict, cells: slice = slice(None)) -> np.ndarray:
        """Level measures e (m, Z, 7) of docs/theory.md §5.5 (E11, E22, 2E12 and the changes of
        the four tying products at each level): the strains of _covariant_strains before the
        assumed shear spreads them over the in-plane points (§5.3)."""
        cur = self._metric(vec)
        ref = {key: value[cells] for key, value in self.reference_metric.items()}
        m, nz = cur["11"].shape
        e = np.empty((m, nz, 7))
        e[..., 0] = 0.5 * (cur["11"] - ref["11"])
        e[..., 1] = 0.5 * (cur["22"] - ref["22"])
        e[..., 2] = cur["12"] - ref["12"]
        e[..., 3:] = cur["tying"] - ref["tying"]
        return e

    def _turned_gradients(self, vec: dict, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """B^psi_z (m, Z, 7, 18): the derivatives of the level measures in CellTangent column
        order (node, u then psi, component), and the 20 vectors (m, Z, 20, 3) they are sums of:
        g_u and their turned copies V_k x g_u (eq. 5.5.3, 5.5.5). dV_k = psi_k x V_k turns
        de/dV_k . dV_k into (V_k x de/dV_k) . psi_k."""
        m, nz = vec["g1"].shape[:2]
        vectors = np.empty((m, nz, 20, 3))
        vectors[:, :, 0], vectors[:, :, 1] = vec["g1"], vec["g2"]
        vectors[:, :, 2:5] = vec["g3"][:, None]
        turned = cross(v[:, None, :, None, :], vectors[:, :, None, :5])  # (m, Z, 3, 5, 3)
        vectors[:, :, 5:] = turned.reshape(m, nz, 15, 3)
        b_psi = np.matmul(self._turned_gradient_table, vectors).reshape(m, nz, 7, 18)
        return b_psi, vectors

    def _level_response(
        self, e: np.ndarray, b_psi: np.ndarray, cells: slice
    ) -> tuple[np.ndarray, np.ndarray]:
        """The section's answer to the level measures e (m, Z, 7): sigma = dW/de (m, Z, 7, 1),
        N mm, and d2W/de2 B^psi (m, Z * 7, 18). The elastic section is linear and its levels
        apart: sigma_z = D^_z e_z."""
        m, nz = e.shape[:2]
        stiffness = self._level_stiffness()[cells]
        sigma = np.matmul(stiffness, e[..., None])  # (m, Z, 7, 1): dW/de, N mm
        stressed = np.matmul(stiffness, b_psi).reshape(m, nz * 7, 18)
        return sigma, stressed

    def _cell_tangent(self, x: np.ndarray, v: np.ndarray, cells: slice) -> np.ndarray:
        """Analytic d(force, moment)/d(u, psi) (m, 3, 6, 3, 6) of each triangle from its corner
        positions x and unit directors v (m, 3, 3), docs/theory.md §5.5.

        With s = (x_1..x_3, V_1..V_3) and the level measures e_z(s) (quadratic in s), the
        Hessian of W is sum_z B_z^T D^_z B_z + sum_z sigma_z . d2e_z/ds2; the rotations enter
        through dV = psi x V and the moment m = V x dW/dV, which turn the director columns of
        B_z into B_z^psi (V x each row part) and add the spin term of eq. (5.5.5)."""
        m, nz = len(x), len(self.zeta)
        vec = self._vectors(x, v)
        e = self._level_measures(vec, cells)
        b_psi, vectors = self._turned_gradients(vec, v)
        sigma, stressed = self._level_response(e, b_psi, cells)
        blocks = np.matmul(np.swapaxes(b_psi.reshape(m, nz * 7, 18), -1, -2), stressed)
        blocks = blocks.reshape(m, 3, 2, 3, 3, 2, 3)  # (a, u/psi, i, b, u/psi, j)
        # dW/dV_a = sum_z sum_r sigma_r de_r/dV_a (m, 3, 3), N: needed for the spin term.
        weights = np.matmul(np.swapaxes(sigma, -1, -2), self._director_gradient_table)
        director_gradient = np.matmul(weights.reshape(m, nz, 3, 5), vectors[:, :, :5]).sum(1)
        # Geometric part G (x) I3 in s (eq. 5.5.4) carried to (u, psi): the block of s slots
        # (t, a), (t', b) is G P_at P_bt'^T with P_a0 = I and P_a1 = [V_a]x.
        geometric = sigma.reshape(m, nz * 7) @ self._curvature_table.reshape(nz * 7, 36)
        geometric = geometric.reshape(m, 2, 3, 2, 3).transpose(0, 2, 1, 4, 3)  # (a, t, b, t')
        arms = np.zeros((m, 3, 2, 3, 3))  # P_at (a, t, i, k)
        arms[:, :, 0] = np.eye(3)
        arms[:, :, 1, 0, 1], arms[:, :, 1, 0, 2] = -v[..., 2], v[..., 1]
        arms[:, :, 1, 1, 0], arms[:, :, 1, 1, 2] = v[..., 2], -v[..., 0]
        arms[:, :, 1, 2, 0], arms[:, :, 1, 2, 1] = -v[..., 1], v[..., 0]
        stacked = arms.reshape(m, 18, 3)
        products = np.matmul(stacked, np.swapaxes(stacked, -1, -2)).reshape(blocks.shape)
        blocks += np.multiply(geometric[:, :, :, None, :, :, None], products, out=products)
        # Turning V_a also turns the arm of m_a = V_a x g_a: d m_a = (psi_a x V_a) x g_a
        # = (V_a g_a^T - (g_a . V_a) I) psi_a (eq. 5.5.5).
        g = director_gradient
        spin = v[..., :, None] * g[..., None, :]
        spin -= np.sum(g * v, -1)[..., None, None] * np.eye(3)
        corner = np.arange(3)
        blocks[:, corner, 1, :, corner, 1, :] += np.swapaxes(spin, 0, 1)  # (3, m, 3, 3)
        return blocks.reshape(m, 3, 6, 3, 6)

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
        if self.kernel == "compiled":
            return kernels.mindlin_energy(self, state.positions, state.directors)
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
        """Critical step per cell, 2 / omega (docs/theory.md §6.2, B4): omega^2 the largest
        eigenvalue of each element's K_e phi = omega^2 M_e phi (its tangent and its share of
        the lumped masses and rotary inertias), which bounds that of the assembly (Irons:
        the Rayleigh quotient of a sum is at most the largest of the elements'). It is
        computed once, in the reference configuration, as a factor on the cheap bound
        ``_cheap_omega2``, which then follows the current geometry at each call.
        """
        if self._step_calibration is None:
            x0, v0 = self._reference_cells
            self._step_calibration = self.element_omega2(x0, v0) / self._cheap_omega2(x0)
        x = state.positions[self.connectivity]
        return 2.0 / np.sqrt(self._cheap_omega2(x) * self._step_calibration)

    def _cheap_omega2(self, x: np.ndarray) -> np.ndarray:
        """omega^2 (m,) of docs/theory.md §6.2 B1-B2 from the corner positions x (m, 3, 3):
        the trace bound of M^-1 K for the translations of a linear triangle with lumped mass
        rho h A / 3, 3 / rho (max(Q11, Q22) + Q66 + kappa G) sum_k 1 / h_k^2 (h_k the
        altitudes), plus kappa G / (2 rho j) for the rotations (j the rotary factor). It
        follows the geometry, not the element's actual modes: on cells of aspect 10 it fell
        below the element eigenvalue (an unstable step), on regular cells it is above."""
        sides = np.linalg.norm(x[:, [2, 0, 1]] - x[:, [1, 2, 0]], axis=-1)  # opposite node k
        area2 = np.linalg.norm(cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]), axis=1)
        inverse_heights2 = np.sum((sides / area2[:, None]) ** 2, axis=1)
        q = self.material.plane_stress
        shear = float(np.max(self.material.transverse))
        rho = self.material.density
        omega2 = 3.0 / rho * (max(q[0, 0], q[1, 1]) + q[2, 2] + shear) * inverse_heights2
        return omega2 + shear / (2.0 * rho * self.rotary_factor)

    def element_omega2(self, x: np.ndarray, v: np.ndarray) -> np.ndarray:
        """Largest eigenvalue (m,), 1/s^2, of K_e phi = omega^2 M_e phi for each triangle with
        corners x and directors v (m, 3, 3): K_e its 18 x 18 tangent in (u, psi) (symmetric
        part), M_e its lumped share rho h A / 3 per translation and that times j per
        rotation (the drilling rotation too: a larger space only raises the maximum)."""
        share = self.material.areal_density * self.reference_area / 3.0
        node = np.stack([share] * 3 + [share * self.rotary_factor] * 3, axis=1)  # (m, 6)
        scale = 1.0 / np.sqrt(np.tile(node, 3))  # (m, 18), M_e^-1/2
        omega2 = np.empty(len(x))
        for start in range(0, len(x), _TANGENT_SLICE):
            cells = slice(start, start + _TANGENT_SLICE)
            k = self._cell_tangent(x[cells], v[cells], cells).reshape(-1, 18, 18)
            k = 0.5 * (k + np.swapaxes(k, 1, 2))
            k *= scale[cells, :, None] * scale[cells, None, :]
            omega2[cells] = np.linalg.eigvalsh(k)[:, -1]
        return omega2

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

    def node_fields(self, state: State, history=None) -> dict[str, np.ndarray]:
        """The nodal fields both shells write (README "Output fields"): ``thickness`` along
        the director, h (mm: the director is an inextensible material fibre of the section),
        and ``director_tilt``, the angle between the director and the area-weighted nodal
        normal of the block (rad; the transverse shear rotation); 0 at nodes outside it."""
        inside = np.zeros(self.n_nodes, dtype=bool)
        inside[self.connectivity] = True
        normals = nodal_normals(state.positions, self.connectivity)
        cosine = np.sum(state.directors * np.where(inside[:, None], normals, 0.0), axis=1)
        return {
            "thickness": np.where(inside, self.h, 0.0),
            "director_tilt": np.where(inside, np.arccos(np.clip(cosine, -1.0, 1.0)), 0.0),
        }

    def total_mass(self) -> float:
        return float(self.material.areal_density * self.reference_area.sum())


# The elastic section's level response (sigma = D^ e): the compiled tangent's condition.
_ELASTIC_RESPONSE = MindlinShellBlock._level_response
