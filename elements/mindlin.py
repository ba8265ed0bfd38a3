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

from collections.abc import Iterator
from typing import cast

import numpy as np

from elements import kernels
from elements.base import CellTangent, ElementBlock, ElementType, check_positive, local_tangent
from elements.mindlin_folds import turned_inside_out, warn_folds
from elements.mindlin_steps import cell_stable_dt, cheap_omega2, element_omega2, penalty_stable_dt
from elements.mindlin_tables import (
    _IN_PLANE,
    _PACKED_COLUMNS,
    _PACKED_ROWS,
    _TYING_N,
    _assumed_shear_coefficients,
    _check_volume,
    _level_stiffness_of,
    _packed,
    _product_coefficients,
    _turned_gradient_table,
)
from elements.mindlin_tangent import mindlin_tangent_blocks
from elements.rotary_scaling import rotary_mode, scaled_rotary_inertia
from femcore.assembly import Scatter
from femcore.checks import as_reals
from femcore.field_names import name_components
from femcore.gershgorin import banded_piece
from femcore.mesh import Mesh
from femcore.rotation import cross
from femcore.state import State
from femcore.topology import nodal_normals
from femcore.workspace import Workspace
from materials.elastic import ElasticShell
from materials.fabric import Fabric

__all__ = ["MindlinShell", "MindlinShellBlock"]

# The components ParaView names (README "Output fields"): the lamina frame, 3 the normal.
name_components("membrane_force", ("11", "22", "12"))
name_components("bending_moment", ("11", "22", "12"))
name_components("shear_force", ("13", "23"))

# Cells per slice of the analytic tangent (MindlinShellBlock.tangent).
_TANGENT_SLICE = 256
# Cells per piece of ``tangent_pieces``: about a _PIECE_SHARE-th of the block's, between
# _PIECE_MIN and _PIECE (a piece's blocks 2.6 kB a cell: at most 10 MB, and a small part of
# the model's memory), grown to the cells' band where that is longer (up to a quarter of the
# block: femcore/gershgorin.py `banded_piece`; the bound the same to the last bit whatever
# the pieces).
_PIECE = 4096
_PIECE_SHARE = 24
_PIECE_MIN = 256


class MindlinShell(ElementType):
    """Reissner-Mindlin shell triangle with MITC3 transverse shear.

    material : materials.ElasticShell (a homogeneous elastic section, integrated through the
        thickness), or materials.Fabric: the section is the fabric itself, by stress resultants
        from its own laws (fibre tension, in-plane shear, the bending laws as given, non-linear
        ones included; docs/theory.md §5.7, elements/mindlin_fabric.py), so that a comparison
        with the FibrousShell on the same Fabric changes the kinematics alone.
    thickness_points : Gauss points through the thickness of an elastic section (default 2; 2-5).
    rotary_scaling : scale the rotary inertia to j = max(h^2/12, kappa (1 - nu) L_e^2 / 16)
        ("closed") or that held to the membrane's step on the element ("element";
        docs/theory.md §6.2 B2) so that thin elements do not force a tiny step; True
        (default): "closed"; False: h^2/12.
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
        of the transverse shear default, nu = 0). Both must be given when B0 = 0 (bending
        laws with a toe): a ValueError otherwise, the defaults would be a mechanism.
    """

    dofs = ("ux", "uy", "uz", "alpha", "beta")
    cell_type = "triangle"
    defines_directors = True

    def __init__(
        self,
        material: ElasticShell | Fabric,
        thickness_points: int = 2,
        rotary_scaling: bool | str = True,
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
        self.rotary_scaling = rotary_mode(rotary_scaling)
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

    Precomputed at bind: ``level_stiffness`` (m, Z, 28), the packed upper triangle of
    the symmetric D^_z (7 x 7) acting on the seven level measures of each thickness level
    (docs/theory.md §5.5: the material matrices of the in-plane points, their weights and
    det J and the assumed shear summed in, W = 1/2 sum_z e_z . D^_z e_z), N mm; and
    ``reference_measures`` (m, Z, 7), the products the measures are changes of. Those are
    all a step reads (560 bytes a triangle at Z = 2). The point-wise tables of the numpy
    reference path (``weighted_stiffness`` (m, 3, Z, 5, 5): the material matrix acting on
    the covariant strains (E11, E22, 2E12, 2E13, 2E23) at each in-plane and thickness point
    times its weight and det J; ``to_lamina``) are built when it first needs them.
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
        self._scatter: Scatter | None = None
        self._workspace = Workspace()  # the compiled cell pass's corner loads and energies
        # the compiled path's sums from cells to nodes (parallel over nodes)
        self.node_corners = kernels.NodeCorners(self.connectivity, mesh.n_nodes)
        self.reference_positions = np.asarray(mesh.points, dtype=float)
        zeta, weights = self._thickness_levels(shell)
        self.zeta, self.zeta_weights = zeta, weights
        self.shear_a, self.shear_b = _assumed_shear_coefficients()
        gradient, self._curvature_table = _product_coefficients(zeta, self.h)
        self._director_gradient_table = gradient[:, :, 3:].reshape(len(zeta), 7, 15)
        self._turned_gradient_table = _turned_gradient_table(gradient)
        self._point_tables: tuple[np.ndarray, np.ndarray] | None = None
        self._weighted: np.ndarray | None = None
        # Kept by reference (the model's arrays, never written): the point-wise tables, the
        # fields and the stable step's calibration are computed from them when needed.
        self.reference_directors = np.asarray(directors, dtype=float)
        self._product_tables: tuple[np.ndarray, np.ndarray] | None = None

        # before the tables: a fold sharp enough to invert the volume is named first
        warn_folds(self.reference_positions, self.connectivity, self.reference_directors)
        self._bind_tables()
        measures = self.reference_measures
        self.reference_metric = {
            "11": measures[..., 0],
            "22": measures[..., 1],
            "12": measures[..., 2],
            "tying": measures[..., 3:],
        }
        self.rotary_factor = self._rotary_factor(shell.rotary_scaling)
        # The stable step's calibration (omega^2 of each element's eigenvalue problem over
        # the cheap bound), computed at the first call of cell_stable_dt.
        self._step_calibration: np.ndarray | None = None
        self._reference_steps = np.empty(0)  # s, (m,): 2 / sqrt(omega^2) at the reference
        self._inverse_metric = np.empty((0, 4))  # (m, 4): ``inverse_metric`` of the cells

    def _bind_tables(self) -> None:
        """``reference_area`` (m,), ``reference_measures`` (m, Z, 7) (the products the level
        measures are changes of: g1.g1, g2.g2, g1.g2, g1.g3^A, g1.g3^C, g2.g3^B, g2.g3^C)
        and the section's tables (``_material_matrices``). The elastic section's come from
        one compiled loop over the cells where numba is installed: no (m, ...) temporaries
        (a fifth of the model's build at 400k triangles); a section of its own (a subclass
        with its own ``_material_matrices``) gets the reference vectors from numpy."""
        compiled = type(self)._material_matrices is MindlinShellBlock._material_matrices
        if compiled and kernels.AVAILABLE:
            self._set_lamina_stiffness()
            stiffness, smallest, measures, area = kernels.mindlin_tables(
                self, self.reference_positions, self.reference_directors
            )
            _check_volume(smallest, self.cell_ids)
            self.level_stiffness, self.reference_measures = stiffness, measures
            self.reference_area = area
            return
        x0, v0 = self._reference_cells()
        self.reference_area = 0.5 * np.linalg.norm(
            cross(x0[:, 1] - x0[:, 0], x0[:, 2] - x0[:, 0]), axis=1
        )
        ref = self._vectors(x0, v0)
        metric = self._metric(ref)
        measures = np.empty(metric["11"].shape + (7,))
        measures[..., 0], measures[..., 1] = metric["11"], metric["22"]
        measures[..., 2], measures[..., 3:] = metric["12"], metric["tying"]
        self.reference_measures = measures
        self._material_matrices(ref, v0)

    @property
    def scatter(self) -> Scatter:
        """Gather / scatter over ``connectivity`` (the numpy path's sums; made at its first
        use: its index table is 72 bytes a triangle the compiled path does not read)."""
        if self._scatter is None:
            self._scatter = Scatter(self.connectivity, self.n_nodes)
        return self._scatter

    @scatter.setter
    def scatter(self, value: Scatter) -> None:
        self._scatter = value

    def _reference_cells(self, cells: slice = slice(None)) -> tuple[np.ndarray, np.ndarray]:
        """Corner positions and directors (c, 3, 3) of the cells in the reference state."""
        connectivity = self.connectivity[cells]
        return self.reference_positions[connectivity], self.reference_directors[connectivity]

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
        """The level stiffness ``level_stiffness`` (m, Z, 28) of docs/theory.md §5.5, packed:
        D^_z = sum_p L_p^T D_pz L_p with D_pz = w det(J) T^T C T at every point, T the
        covariant-to-lamina transformation (§5.2) and C = diag(Q rotated to the lamina frame,
        kappa G13, kappa G23), from the point-wise tables of the numpy path (numba's loop in
        ``_bind_tables`` forms the same cell by cell)."""
        self._set_lamina_stiffness()
        self.level_stiffness = _packed(_level_stiffness_of(self.weighted_stiffness))

    def _set_lamina_stiffness(self) -> None:
        """C (5, 5) = diag(Q rotated to the lamina frame, kappa G13, kappa G23), MPa."""
        c = np.zeros((5, 5))
        c[:3, :3] = self.material.plane_stress
        c[3, 3], c[4, 4] = self.material.transverse
        self.lamina_stiffness = c

    @property
    def weighted_stiffness(self) -> np.ndarray:
        """D_pz = w det(J) T^T C T (m, P, Z, 5, 5), N mm: the material matrix acting on the
        covariant strains at each in-plane and thickness point, times the point's weight and
        det J (W = 1/2 sum E . D E): the numpy reference path's table, built at its first
        use and kept."""
        if self._weighted is None:
            weight, transform = self._tables()
            weighted = np.swapaxes(transform, -1, -2) @ self.lamina_stiffness @ transform
            self._weighted = weight[..., None, None] * weighted
        return self._weighted

    @property
    def to_lamina(self) -> np.ndarray:
        """T (m, P, Z, 5, 5): covariant to lamina-frame engineering strains at each point."""
        return self._tables()[1]

    def _tables(self) -> tuple[np.ndarray, np.ndarray]:
        """(point weights (m, P, Z), transformations T (m, P, Z, 5, 5)), built once."""
        if self._point_tables is None:
            self._point_tables = self._point_tables_of(*self._reference_cells())
        return self._point_tables

    def _point_tables_of(self, x0: np.ndarray, v0: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(w det J (c, P, Z), T (c, P, Z, 5, 5)) of cells with reference corners x0 and
        directors v0 (c, 3, 3), by numpy."""
        ref = self._vectors(x0, v0)
        m, nz = len(x0), len(self.zeta)
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
        weight = (1.0 / 6.0) * self.zeta_weights[None, None, :] * det
        _check_volume(det.reshape(m, -1).min(axis=1), self.cell_ids)
        return weight, transform

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

    def _products(self) -> tuple[np.ndarray, np.ndarray]:
        """The product coefficients (gradient (3, 7, 6, 5), curvature (3, 7, 6, 6)) of the
        compiled tangents and forces (elements/mindlin_tables.py ``_product_coefficients``),
        made at the first call and kept."""
        if self._product_tables is None:
            self._product_tables = _product_coefficients(self.zeta, self.h)
        return self._product_tables

    def internal_force_and_energy(self, state: State, history=None):
        """Forces, moments (n, 3) and strain energy (N mm) from one pass of the compiled
        kernel (the energy is summed where the stresses are formed); the two numpy passes
        on the numpy path."""
        if self.kernel == "compiled":
            return kernels.mindlin_loads_and_energy(self, state.positions, state.directors)
        return super().internal_force_and_energy(state, history)

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
        # fabric section has its own loop: elements/mindlin_fabric_tangent.py).
        if self.kernel == "compiled" and type(self)._level_response is _ELASTIC_RESPONSE:
            blocks = mindlin_tangent_blocks(self, x, v, self._level_stiffness(), *self._products())
            return [CellTangent(self.connectivity, blocks)]
        blocks = np.empty((len(x), 3, 6, 3, 6))
        # Slices of cells: the temporaries (a few times the output) then stay small and are
        # reused from one slice to the next instead of being mapped and page-faulted afresh,
        # which costs more than the arithmetic on a large block.
        for start in range(0, len(x), _TANGENT_SLICE):
            cells = slice(start, start + _TANGENT_SLICE)
            blocks[cells] = self._cell_tangent(x[cells], v[cells], cells)
        return [CellTangent(self.connectivity, blocks)]

    def tangent_pieces(self, state: State, history=None) -> Iterator[CellTangent]:
        """``tangent`` a slice of cells at a time (the blocks of all cells are 2.6 kB a
        triangle; a slice's are made, given and dropped)."""
        m = len(self.connectivity)
        # at least the cells' band, so that the bound streams (thin strips)
        size = banded_piece(self.connectivity, min(_PIECE, max(_PIECE_MIN, m // _PIECE_SHARE)))
        for start in range(0, m, size):
            nodes = self.connectivity[start : start + size]
            # the piece's corners only (all cells' would be 0.14 kB a triangle)
            x, v = state.positions[nodes], state.directors[nodes]
            blocks = np.empty((len(nodes), 3, 6, 3, 6))
            for first in range(start, start + len(nodes), _TANGENT_SLICE):
                rows = slice(first, min(first + _TANGENT_SLICE, start + len(nodes)))
                within = slice(rows.start - start, rows.stop - start)
                blocks[within] = self._cell_tangent(x[within], v[within], rows)
            yield CellTangent(nodes, blocks)

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

    def _level_stiffness(self, cells: slice = slice(None)) -> np.ndarray:
        """D^_z = sum_p L_p^T D_pz L_p (c, Z, 7, 7), N mm (docs/theory.md §5.5) of the cells:
        the stiffness of the seven level measures, the in-plane points summed out, unpacked
        from ``level_stiffness``."""
        packed = self.level_stiffness[cells]
        full = np.empty(packed.shape[:-1] + (7, 7))
        full[..., _PACKED_ROWS, _PACKED_COLUMNS] = packed
        full[..., _PACKED_COLUMNS, _PACKED_ROWS] = packed
        return full

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
        stiffness = self._level_stiffness(cells)
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
    def _rotary_factor(self, scaling: str | None) -> np.ndarray:
        """j (m,), mm^2: I = m j, the B2 scaling of docs/theory.md §6.2 (``rotary_mode``),
        from the reference configuration (computed once at bind)."""
        kappa, nu = self.material.shear_factor, _rotary_poisson(self.material.poisson)
        return scaled_rotary_inertia(self, scaling, kappa * (1 - nu))

    def _closed_rotary_factor(self) -> np.ndarray:
        """B2's closed-form j (m,), mm^2, whatever rotary_scaling the shell was given: the one
        the automatic penalty's step is taken at (``penalty_stable_dt``)."""
        kappa, nu = self.material.shear_factor, _rotary_poisson(self.material.poisson)
        return scaled_rotary_inertia(self, "closed", kappa * (1 - nu))

    def _altitude(self, positions: np.ndarray | None = None) -> np.ndarray:
        """Smallest altitude 2A / L_max of each triangle (m,), mm."""
        points = self.reference_positions if positions is None else positions
        x0, x1, x2 = (points[self.connectivity[:, k]] for k in range(3))
        longest = np.maximum(
            np.maximum(np.linalg.norm(x1 - x0, axis=1), np.linalg.norm(x2 - x1, axis=1)),
            np.linalg.norm(x0 - x2, axis=1),
        )
        return np.linalg.norm(cross(x1 - x0, x2 - x0), axis=1) / longest

    def lumped_mass(self, state: State, density_scale=None):
        share = self.material.areal_density * self.reference_area / 3.0
        if density_scale is not None:
            share = share * np.asarray(density_scale, dtype=float)
        per_node = np.repeat(share[:, None], 3, axis=1)
        # Scatter.scalars' sums, without making the scatter's vector table
        corners, n = self.connectivity.ravel(), self.n_nodes
        mass = np.bincount(corners, weights=per_node.ravel(), minlength=n)
        weights = (per_node * self.rotary_factor[:, None]).ravel()
        inertia = np.bincount(corners, weights=weights, minlength=n)
        return mass, inertia

    def cell_stable_dt(self, state: State) -> np.ndarray:
        """Critical step per cell, 2 / omega, s (m,) (docs/theory.md §6.2, B4-B5: the
        element eigenvalue bound in the reference configuration, followed by the stretch;
        elements/mindlin_steps.py ``cell_stable_dt``)."""
        return cell_stable_dt(self, state)

    def _cheap_omega2(self, x: np.ndarray, rotary_factor: np.ndarray | None = None) -> np.ndarray:
        """omega^2 (m,) of docs/theory.md §6.2 B1-B2 from the corner positions x (m, 3, 3), j
        ``rotary_factor`` (m,) mm^2 (default: the block's) (elements/mindlin_steps.py
        ``cheap_omega2``)."""
        return cheap_omega2(self, x, rotary_factor)

    def element_omega2(
        self, x: np.ndarray, v: np.ndarray, cells: np.ndarray | None = None
    ) -> np.ndarray:
        """Largest eigenvalue (c,), 1/s^2, of each triangle's K_e phi = omega^2 M_e phi, corners
        x and directors v (c, 3, 3), ``cells`` (c,) (elements/mindlin_steps.py)."""
        return element_omega2(self, x, v, cells)

    def penalty_stable_dt(self, state: State) -> float:
        """The critical step with B2's closed-form rotary inertia, s, whatever rotary_scaling
        the shell was given: what the interactions' automatic penalty is sized on
        (elements/mindlin_steps.py)."""
        return penalty_stable_dt(self, state)

    # ------------------------------------------------------------------ outputs
    def inverted_cells(self, state: State) -> np.ndarray:
        """The cells with every corner's director at or past 90 deg from their normal
        (elements.mindlin_folds.turned_inside_out)."""
        flipped = turned_inside_out(state.positions, self.connectivity, state.directors)
        return self.cell_ids[flipped]

    def cell_fields(self, state: State, history=None) -> dict[str, np.ndarray]:
        """Section forces per unit length in the lamina frame, averaged over the element:
        membrane (N11, N22, N12) N/mm, bending (M11, M22, M12) N mm/mm, shear (Q1, Q2) N/mm.
        The compiled path forms each point's lamina map from the reference configuration as
        it goes (kept tables would cost 2.4 kB a triangle)."""
        if self.kernel == "compiled":
            fields = kernels.mindlin_fields(self, state.positions, state.directors)
            return {
                "membrane_force": fields[:, :3],
                "bending_moment": fields[:, 3:6],
                "shear_force": fields[:, 6:],
            }
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
        and ``director_tilt_deg``, the angle between the director and the area-weighted nodal
        normal of the block (deg; the transverse shear rotation); 0 at nodes outside it,
        which the compiled model's fields write as NaN (femcore.compiled: not defined there)."""
        inside = np.zeros(self.n_nodes, dtype=bool)
        inside[self.connectivity] = True
        normals = nodal_normals(state.positions, self.connectivity)
        cosine = np.sum(state.directors * np.where(inside[:, None], normals, 0.0), axis=1)
        return {
            "thickness": np.where(inside, self.h, 0.0),
            "director_tilt_deg": np.where(
                inside, np.degrees(np.arccos(np.clip(cosine, -1.0, 1.0))), 0.0
            ),
        }

    def total_mass(self) -> float:
        return float(self.material.areal_density * self.reference_area.sum())


# The elastic section's level response (sigma = D^ e): the compiled tangent's condition.
_ELASTIC_RESPONSE = MindlinShellBlock._level_response


def _rotary_poisson(nu: float) -> float:
    """The Poisson ratio of B2's factor kappa (1 - nu) (docs/theory.md §6.2), an isotropic
    plate's: an orthotropic lamina's nu12 may pass 0.5 (up to sqrt(E1 / E2)) where 1 - nu
    would shrink or turn negative; it is held to the isotropic range's end, 0.5."""
    return min(nu, 0.5)
