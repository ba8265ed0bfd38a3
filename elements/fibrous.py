"""FibrousShell: the 3-node continuum-based shell for fibrous reinforcements of Bai, Colmars,
Naouar and Boisse, Composites Part A 139 (2020) 106135 (equation numbers below are Bai's;
section numbers refer to docs/theory.md).

Kinematics (§1): x(xi, eta, zeta) = sum N_k x_k + zeta/2 sum N_k h_m^k V_k (Eq. 5), directors V
free to rotate (fibre slip), thickness along the director h_m = h / (V . n) so that the
thickness along the normal is conserved (Eq. 10, 14). The normal n at node k is the
angle-weighted nodal normal of the block (default, ``thickness="nodal"``, §1.4: one h_m per
node, so a director that stays put while the surface bends stretches the fibres, and the
directors tilt by atan(theta) as a deck of cards does) or, as Bai Eq. 15 writes, the normal of
each element (``thickness="element"``: parallel directors are then strain-free at any
curvature). Warp runs along local edge 1-2 and weft along 1-3 (Eq. 9). The virtual work has
three parts:

* tension (Eq. 24-29, §2): fibres at ``levels`` positions zeta_f through the thickness, log
  strain, T(eps) per unit width, delta W = A0 sum_f w_f sum_alpha T delta eps;
* in-plane shear (Eq. 21, 30-33, §3): the warp-weft angle change gamma at each level,
  delta W = A0 sum_f w_f M_s(gamma) delta gamma;
* rotation-free bending (Eq. 34-37, §4): warp and weft curvatures of each element from the
  fold angles with its three neighbours, delta W = A0 sum_alpha M_alpha delta chi_alpha.

Everything is vectorised over the cells of a block; the reference geometry, the neighbour
tables and the fibre orientation of each triangle are computed once, at ``bind``.
Local nodes 1, 2, 3 of the paper are columns 0, 1, 2 here.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from elements import fibrous_kernels, kernels
from elements.base import (
    CellTangent,
    ElementBlock,
    ElementType,
    SparseTangent,
    local_tangent,
)
from elements.shell_geometry import guarded_thickness, lumped_mass, nodal_thickness
from femcore.assembly import Scatter, TangentPart
from femcore.mesh import Mesh
from femcore.rotation import cross
from femcore.state import State
from femcore.topology import build_topology
from materials.fabric import Fabric

__all__ = ["FibrousShell", "FibrousShellBlock", "lobatto_levels"]

# Side s of a triangle is opposite local node s and runs p -> q (counter-clockwise).
_P = np.array([1, 2, 0])
_Q = np.array([2, 0, 1])

# Bending time-step coefficient of docs/theory.md §6.2 (A3): dt_b = 0.35 L^2 sqrt(rho_A / B), the
# worst
# case (square cells) of the exact eigenvalues of the rotation-free bending stiffness.
_BENDING_DT_COEFFICIENT = 0.35


def lobatto_levels(count: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Lobatto fibre positions zeta_f in [-1, 1] and weights w_f (sum 1), ``count`` >= 2.

    Three levels give bottom, middle, top with Simpson weights 1/6, 2/3, 1/6 (docs/theory.md §2.1):
    the inextensibility acts on the physical top and bottom surfaces, and sum w zeta^2 = 1/3
    is the continuum moment of inertia of the section.
    """
    n = count
    interior = (
        np.polynomial.legendre.Legendre.basis(n - 1).deriv().roots() if n > 2 else np.zeros(0)
    )
    zeta = np.concatenate(([-1.0], np.sort(np.real(interior)), [1.0]))
    p = np.polynomial.legendre.Legendre.basis(n - 1)(zeta)
    weights = 2.0 / (n * (n - 1) * p**2)
    return zeta, weights / weights.sum()


def _levels(levels) -> tuple[np.ndarray, np.ndarray]:
    if isinstance(levels, (int, np.integer)) and not isinstance(levels, bool):
        if levels < 2:
            raise ValueError(
                f"levels must be >= 2 (fibres at the bottom and top at least: with one level "
                f"the directors have no stiffness), got {levels}"
            )
        return lobatto_levels(int(levels))
    try:
        zeta, weights = (np.array(v, dtype=float).ravel() for v in levels)
    except (TypeError, ValueError):
        raise ValueError(
            f"levels must be an integer >= 2 or a pair (positions, weights), got {levels!r}"
        ) from None
    if zeta.size != weights.size or zeta.size < 2:
        raise ValueError("levels: positions and weights must have the same length >= 2")
    if not (np.all(np.abs(zeta) <= 1.0) and np.all(weights > 0)):
        raise ValueError(
            "levels: positions must lie in [-1, 1] (zeta along the director) and weights be > 0"
        )
    if np.all(zeta == 0.0):
        raise ValueError("levels: at least one fibre level must be off the mid-surface")
    return zeta, weights / weights.sum()


class FibrousShell(ElementType):
    """Bai's fibrous shell triangle for a fabric or a stack of plies.

    fabric : materials.Fabric (thickness, areal density, tension, shear and bending laws).
    levels : number of fibre levels through the thickness (Gauss-Lobatto, default 3: bottom,
        middle, top with Simpson weights), or a pair (positions zeta in [-1, 1], weights).
    warp : warp direction in the reference configuration, (3,); default x. The weft is the
        in-plane perpendicular. Each triangle must have one edge along each (Eq. 9).
    fibre_angle_tolerance : degrees; how far an edge may deviate from a fibre direction.
    clamped : node ids (or a node-set name) of clamped edges: sides of the block whose two
        nodes are in this set bend against a rigid wall in the element's reference plane
        (docs/theory.md §4.5); on an interior line both sides do. The nodes must be held by the
        supports (translations and directors fixed with ``model.fix``, or the translations
        prescribed), else compiling the model raises ValueError. The supports clamp the
        bending by themselves (every side whose two nodes are held is clamped, every element
        whose three nodes are held carries no bending), so fixing the nodes of a line or of a
        region is a clamp with or without this option; it states the intent and is checked.
    thickness : "nodal" (default) or "element": the normal n of h_m = h / (V . n) (docs/theory.md
        §1.4). "nodal" takes the angle-weighted normal of the block's triangles around each node,
        so the thickness along the director is continuous and a bent stack's directors tilt as
        its layers slip (atan(theta) for a strip bent by theta from a clamp); the force at a
        node then reaches three rings of cells. "element" is Bai's Eq. 15, each element's own
        normal: every element sees three parallel directors as strain-free, so the directors
        keep their orientation whatever the curvature.
    thickness_variation : include the variation of h_m (docs/theory.md §2.5) in the forces, so that
        they are the exact gradient of the strain energy (default). False follows Bai Eq. 28,
        which leaves it out.
    bending_geometry : "current" (the curvature coefficients c_as of §4.2 from the current
        geometry, held fixed in the variation as Bai and S3 do) or "reference" (from the
        reference geometry: total Lagrangian, exactly conservative).
    kernel : "compiled" (default when numba is installed: the nodal normal sums and their
        forces by the loops of elements/kernels.py) or "numpy" (the vectorised reference).
    """

    dofs = ("ux", "uy", "uz", "alpha", "beta")
    cell_type = "triangle"
    defines_directors = True

    def __init__(
        self,
        fabric: Fabric,
        levels=3,
        warp=(1.0, 0.0, 0.0),
        fibre_angle_tolerance: float = 1.0,
        clamped=None,
        thickness_variation: bool = True,
        bending_geometry: str = "current",
        thickness: str = "nodal",
        kernel: str | None = None,
    ):
        self.kernel = kernels.choose(kernel)
        if not isinstance(fabric, Fabric):
            raise ValueError(f"FibrousShell needs a materials.Fabric, got {fabric!r}")
        self.fabric = fabric
        self.zeta, self.weights = _levels(levels)
        warp = np.array(warp, dtype=float).ravel()
        if warp.shape != (3,) or not np.isfinite(warp).all() or np.linalg.norm(warp) == 0:
            raise ValueError(f"warp must be a non-zero 3-vector, got {warp!r}")
        self.warp = warp / np.linalg.norm(warp)
        tolerance = float(fibre_angle_tolerance)
        if not 0.0 < tolerance < 45.0:
            raise ValueError(
                f"fibre_angle_tolerance must be in (0, 45) degrees, got {fibre_angle_tolerance!r}"
            )
        self.fibre_angle_tolerance = tolerance
        self.clamped = clamped
        self.thickness_variation = bool(thickness_variation)
        if thickness not in ("nodal", "element"):
            raise ValueError(
                f"thickness must be 'nodal' (h_m from the nodal normals) or 'element' (Bai "
                f"Eq. 15, the element normals), got {thickness!r}"
            )
        self.thickness = thickness
        if bending_geometry not in ("current", "reference"):
            raise ValueError(
                f"bending_geometry must be 'current' or 'reference', got {bending_geometry!r}"
            )
        self.bending_geometry = bending_geometry

    @property
    def half_thickness(self) -> float:
        """h / 2, mm: the contact surface's offset from the mid-surface along the normal."""
        return 0.5 * self.fabric.thickness

    def bind(self, mesh: Mesh, cell_ids: np.ndarray, directors: np.ndarray) -> FibrousShellBlock:
        return FibrousShellBlock(self, mesh, cell_ids, directors)


class FibrousShellBlock(ElementBlock):
    """FibrousShell over mesh triangles ``cell_ids``.

    Attributes (fixed at bind)
    --------------------------
    connectivity : (m, 3) node ids, reordered so that local node 0 is the fibre corner, edge
        0 -> 1 runs along one fibre family and 0 -> 2 along the other (Eq. 9).
    xi_is_warp : (m,) bool, True where edge 0 -> 1 is warp (else it is weft).
    shear_sign : (m,) +1 or -1, so that gamma = shear_sign (pi/2 - angle(g1, g2)) is the
        closing of the angle between the positive warp and weft directions in every cell,
        whichever way its edges 0 -> 1 and 0 -> 2 point along them.
    reference_area : A0 (m,), mm^2.
    neighbour, neighbour_side : (m, 3) block-local neighbour across side s and its side index
        there (-1 on free edges).

    Attributes (fixed at bind, completed by ``apply_supports``; docs/theory.md §4.5)
    -------------------------------------------------------------------------------
    clamped_side : (m, 3) bool, sides that bend against the wall of the reference plane.
    interior_side : (m, 3) bool, sides that couple the cell with its neighbour.
    held_cell : (m,) bool, cells whose three nodes are held: no bending.
    requested_clamp : (n,) bool, the nodes of the ``clamped`` option.
    """

    dofs = FibrousShell.dofs
    cell_type = FibrousShell.cell_type

    def __init__(self, shell: FibrousShell, mesh: Mesh, cell_ids, directors):
        self.fabric = fabric = shell.fabric
        self.compiled = shell.kernel == "compiled"
        # Options resolved once: the block never reads its type back at run time.
        self.thickness_variation = shell.thickness_variation
        self.nodal_normals = shell.thickness == "nodal"
        # Rotation-free bending: a cell's bending force depends on its neighbours' nodes (2
        # hops). With nodal normals a node's force also depends on the h_m of the nodes of its
        # cells, each set by the normals of the cells around that node (3 hops).
        self.reach = 3 if self.nodal_normals else 2
        self.reference_curvature_coefficients = shell.bending_geometry == "reference"
        self.n_nodes = mesh.n_nodes
        self.cell_ids = np.asarray(cell_ids, dtype=np.int64)
        self.zeta, self.weights = shell.zeta, shell.weights
        self.connectivity, self.xi_is_warp = _fibre_ordering(
            mesh.points,
            mesh.triangles[self.cell_ids],
            self.cell_ids,
            shell.warp,
            shell.fibre_angle_tolerance,
        )
        self.scatter = Scatter(self.connectivity, mesh.n_nodes)
        self.node_corners = kernels.NodeCorners(self.connectivity, mesh.n_nodes)
        self.node_in_block = np.zeros(mesh.n_nodes, dtype=bool)  # (n,): a corner of a cell here
        self.node_in_block[self.connectivity] = True
        self._pairs: _CornerPairs | None = None  # the tangent's sparse pattern, at first use
        self.shear_sign = _shear_orientation(
            mesh.points, self.connectivity, self.xi_is_warp, shell.warp
        )

        topology = build_topology(self.connectivity)
        self.neighbour = np.asarray(topology.neighbour)
        self.neighbour_side = _neighbour_sides(self.neighbour)
        # Clamps (docs/theory.md §4.5): the requested ones now, with the model's supports added
        # by apply_supports, which also recomputes the reference folds from these points.
        self.requested_clamp = self._requested_clamp(mesh, shell.clamped)
        self._reference_points = np.asarray(mesh.points, dtype=float)
        # Nodes whose normal is that of the wall they are held against (apply_supports).
        self.wall_nodes = np.zeros(mesh.n_nodes, dtype=bool)
        self.wall_node_ids = np.zeros(0, dtype=np.int64)
        self.wall_sums = np.zeros((0, 3))
        self._set_sides(self.requested_clamp)

        # Reference geometry: areas, fibre lengths and shear angles at each level, fold angles.
        x0 = np.asarray(mesh.points, dtype=float)
        v0 = np.asarray(directors, dtype=float)
        ref = self._geometry(x0, v0)
        self.reference_area = 0.5 * ref["double_area"]
        self.reference_normal = ref["normal"]
        self.reference_length1, self.reference_length2 = self._fibre_lengths(ref)  # (m, L)
        self.reference_shear = self.shear_sign[:, None] * _shear_angle(ref["g1"], ref["g2"])
        self.reference_fold = np.zeros((len(self.cell_ids), 3))
        bend0 = self._bending_geometry(x0)
        self.reference_fold = bend0["fold"]
        self.reference_coefficients = bend0["coefficients"]

        # The laws as the compiled loops read them: warp and weft tension, shear, warp and
        # weft bending (elements/fibrous_kernels.py pack_laws).
        self.packed_laws = fibrous_kernels.pack_laws(
            (fabric.tension, fabric.tension_weft, fabric.shear, fabric.bending, fabric.bending_weft)
        )
        # Largest tangent stiffnesses, for the stable step (docs/theory.md §6.2).
        self.max_tension_stiffness = max(
            fabric.tension.max_slope(), fabric.tension_weft.max_slope()
        )
        self.max_shear_stiffness = fabric.shear.max_slope()
        self.max_bending_stiffness = max(
            fabric.bending.max_slope(), fabric.bending_weft.max_slope()
        )

    # ------------------------------------------------------------------ set-up helpers
    def _requested_clamp(self, mesh: Mesh, clamped) -> np.ndarray:
        """The nodes (n,) bool of the ``clamped`` option (all False without it); they must
        make at least one edge of the block."""
        member = np.zeros(mesh.n_nodes, dtype=bool)
        if clamped is None:
            return member
        if isinstance(clamped, str):
            nodes = mesh.nodes(clamped)
        else:
            nodes = np.unique(np.asarray(clamped, dtype=np.int64).ravel())
            if nodes.size and (nodes.min() < 0 or nodes.max() >= mesh.n_nodes):
                raise ValueError(f"clamped: node ids must be in 0..{mesh.n_nodes - 1}")
        member[nodes] = True
        if not self._clamped_sides(member)[1].any():
            raise ValueError(
                "clamped: no edge of the block has both its nodes in the given set; a clamped "
                "edge is a line of mesh edges (the shell's boundary, or an interior line)"
            )
        return member

    def _clamped_sides(self, clamp: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """From the clamped nodes ``clamp`` (n,) bool: the clamped sides (m, 3) (both nodes
        clamped, in a cell with a node that is not), the sides with both nodes clamped (m, 3),
        and the held cells (m,) (all three nodes clamped)."""
        ends = clamp[self.connectivity[:, _P]] & clamp[self.connectivity[:, _Q]]
        held = clamp[self.connectivity].all(axis=1)
        return ends & ~held[:, None], ends, held

    def _set_sides(self, clamp: np.ndarray) -> None:
        """Side tables from the clamped nodes ``clamp`` (n,) bool (docs/theory.md §4.5).

        A side with both nodes clamped couples no two cells (``interior_side`` False in both)
        and is a clamped side of each cell that has a node not clamped: it bends against the
        wall of its reference plane. A held cell (three nodes clamped) has no fold at all, so
        zero curvature coefficients: its shape is imposed and it stores no bending energy.
        """
        self.clamped_side, ends, self.held_cell = self._clamped_sides(clamp)
        self.interior_side = (self.neighbour >= 0) & ~ends
        # Gather indices with free sides pointing at cell 0, masked by interior_side.
        self._across_cell = np.where(self.interior_side, self.neighbour, 0)
        self._across_side = np.where(self.interior_side, self.neighbour_side, 0)

    def apply_supports(self, held: np.ndarray) -> None:
        """Clamp the rotation-free bending where the model holds the nodes (docs/theory.md
        §4.5): every node held (translations and directors fixed or prescribed) is a clamped
        node, as are those of the ``clamped`` option, which must be held.

        Raises ValueError when a node of a requested clamped edge is not held.
        """
        held = np.asarray(held, dtype=bool)
        _, requested, _ = self._clamped_sides(self.requested_clamp)
        on_edges = np.zeros_like(held)
        on_edges[self.connectivity[:, _P][requested]] = True
        on_edges[self.connectivity[:, _Q][requested]] = True
        loose = np.flatnonzero(on_edges & ~held)
        if loose.size:
            raise ValueError(
                f"clamped nodes {loose[:5].tolist()}{'...' if loose.size > 5 else ''} must "
                "have their translations and directors fixed with model.fix (a clamped edge "
                "is held by the supports; its bending then acts against a wall)"
            )
        self._set_sides(held | self.requested_clamp)
        # A held node stays where it was: its nodal normal is the wall's, the reference one,
        # not the mean of the cells that bend away from it (docs/theory.md §1.4).
        wall = np.zeros_like(held)
        wall[np.unique(self.connectivity)] = True
        self.wall_nodes = np.zeros_like(held)
        self._wall_sums = self._normal_sums(self._reference_points)
        self.wall_nodes = wall & (held | self.requested_clamp)
        self.wall_node_ids = np.flatnonzero(self.wall_nodes)
        self.wall_sums = self._wall_sums[self.wall_node_ids]
        bend0 = self._bending_geometry(self._reference_points)
        self.reference_fold = bend0["fold"]
        self.reference_coefficients = bend0["coefficients"]

    # ------------------------------------------------------------------ kinematics
    def thickness_along_directors(self, positions: np.ndarray, directors: np.ndarray) -> dict:
        """The thickness along the directors at each corner of each cell (Bai Eq. 10, 14), from
        the nodal normals (the same value at every corner of a node) or, with
        ``thickness="element"``, from each element's normal (Eq. 15).

        Parameters
        ----------
        positions, directors : (n, 3) float
            A configuration (mm; unit directors).

        Returns
        -------
        dict
            ``cosine`` (m, 3): V . n; ``thickness`` (m, 3), mm: h_m = h / max(V . n,
            guard); ``guarded`` (m, 3) bool: the corners where the guard acted.
        """
        geo = self._geometry(positions, directors, layers=False)
        return {key: geo[key] for key in ("cosine", "thickness", "guarded")}

    def _geometry(self, positions: np.ndarray, directors: np.ndarray, layers: bool = True) -> dict:
        """Element normals, thickness along the directors, and the fibre vectors of each level.

        Returns arrays over cells: corners (m,3,3), directors (m,3,3), normal (m,3),
        double_area (m,), cosine V.n (m,3), thickness h_m (m,3), guarded (m,3) bool, and with
        ``layers`` g1, g2 (m,L,3): covariant vectors of Eq. 8 at each fibre level (warp or
        weft along edge 0 -> 1 and 0 -> 2). With nodal normals also node_normal (m,3,3) and
        normal_sum_length (m,3): N_k and |S_k| at the corners.
        """
        sums = self._normal_sums(positions)[self.connectivity] if self.nodal_normals else None
        return self._cell_geometry(
            positions[self.connectivity], directors[self.connectivity], layers, sums
        )

    def _normal_sums(self, positions: np.ndarray) -> np.ndarray:
        """S_k = sum over the block's cells e around node k of alpha_k^e n_e, (n, 3): the
        element normals weighted by the cells' angles at the node; S_k / |S_k| is the nodal
        normal (docs/theory.md §1.4)."""
        if self.compiled:
            s = fibrous_kernels.corner_shares(positions, self.connectivity)
        else:
            s, _ = _corner_normals(positions[self.connectivity])
        sums = self.scatter.vectors(s)
        if self.wall_nodes.any():
            sums[self.wall_nodes] = self._wall_sums[self.wall_nodes]
        return sums

    def _free_sums(self, nodal: np.ndarray) -> np.ndarray:
        """``nodal`` (n, 3) with the rows of the wall nodes zeroed: their S_k does not vary."""
        return np.where(self.wall_nodes[:, None], 0.0, nodal) if self.wall_nodes.any() else nodal

    def _cell_geometry(
        self, x: np.ndarray, v: np.ndarray, layers: bool = True, sums: np.ndarray | None = None
    ) -> dict:
        """``_geometry`` from the corner positions x and directors v (m, 3, 3) of each cell and,
        with nodal normals, the normal sums S_k at its corners (m, 3, 3)."""
        normal = cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0])
        double_area = np.linalg.norm(normal, axis=1)
        normal /= double_area[:, None]
        extra = {}
        if sums is None:  # Eq. 15: each element's own normal
            cosine = np.matmul(v, normal[:, :, None])[..., 0]
        else:  # the nodal normals N_k = S_k / |S_k|
            length = np.linalg.norm(sums, axis=-1)
            node_normal = sums / length[..., None]
            cosine = np.sum(v * node_normal, axis=-1)
            extra = {"node_normal": node_normal, "normal_sum_length": length}
        h_m, guarded = guarded_thickness(self.fabric.thickness, cosine)  # Eq. 10 / 14
        geo = {
            "corners": x,
            "directors": v,
            "normal": normal,
            "double_area": double_area,
            "cosine": cosine,
            "thickness": h_m,
            "guarded": guarded,
            **extra,
        }
        if layers:
            # Fibre end points x_k^f = x_k + zeta_f/2 h_m^k V_k, (m, 3, L, 3).
            offset = 0.5 * self.zeta[None, None, :, None] * (h_m[:, :, None] * v)[:, :, None, :]
            layer = x[:, :, None, :] + offset
            geo["g1"] = layer[:, 1] - layer[:, 0]
            geo["g2"] = layer[:, 2] - layer[:, 0]
        return geo

    def _fibre_lengths(self, geo: dict) -> tuple[np.ndarray, np.ndarray]:
        """The lengths (m, L) whose log strain the tension law takes, along edges 0-1, 0-2.

        With element normals (Bai), |g_a| at each level. With nodal normals, the length of
        g_a projected on the element's plane, l = |P g_a|, P = I - n n^T (docs/theory.md §2.2).
        The component of g_a = e_a + zeta d_a along n is zeta d_a . n: straight directors make
        it (h / 2) theta kappa per unit length on a stack bent by theta with curvature kappa,
        and counting it would stretch both outer layers by (h theta kappa)^2 / 8, although the
        true material lines curve and the layers keep their length: it locks a thick stack's
        bending (+8% tip x on a heavy cantilever of h / L = 0.04). Components in the plane
        (in-plane shear of the levels) still count in full.
        """
        if not self.nodal_normals:
            return np.linalg.norm(geo["g1"], axis=-1), np.linalg.norm(geo["g2"], axis=-1)
        n = geo["normal"][:, None, :]
        return tuple(
            np.linalg.norm(g - np.sum(g * n, axis=-1, keepdims=True) * n, axis=-1)
            for g in (geo["g1"], geo["g2"])
        )

    def _strains(self, geo: dict) -> dict:
        """Log fibre strains eps1, eps2 along edges 0-1 and 0-2 and shear angles (m, L), with
        the level vectors' lengths |g_a| (length1, length2) and the fibre lengths of
        ``_fibre_lengths`` (fibre1, fibre2)."""
        fibre1, fibre2 = self._fibre_lengths(geo)
        return {
            "length1": np.linalg.norm(geo["g1"], axis=-1),
            "length2": np.linalg.norm(geo["g2"], axis=-1),
            "fibre1": fibre1,
            "fibre2": fibre2,
            "eps1": np.log(fibre1 / self.reference_length1),
            "eps2": np.log(fibre2 / self.reference_length2),
            "gamma": self.shear_sign[:, None] * _shear_angle(geo["g1"], geo["g2"])
            - self.reference_shear,
        }

    def _by_family(self, along_xi, along_eta):
        """(warp, weft) values from (edge 0-1, edge 0-2) values, per cell (leading axis)."""
        flag = self.xi_is_warp.reshape((-1,) + (1,) * (np.ndim(along_xi) - 1))
        return np.where(flag, along_xi, along_eta), np.where(flag, along_eta, along_xi)

    def _layer_loads(self, geo, strain, tension=True, shear=True):
        """Derivatives P_a = dW/dg_a (m, L, 3) of the tension and/or shear energy, and with
        nodal normals the load on the element normal, dW/dn (m, 3) (else None).

        Tension (Eq. 24-27): dW/dg_a = A0 w_f T_a g_a / |g_a|^2 (d eps = g . dg / |g|^2). With
        the in-plane fibre length l = |P g| of ``_fibre_lengths``, dW/dg_a = A0 w_f T_a P g_a /
        l^2 and, n varying, dW/dn = -sum_(f, a) A0 w_f T_a (n . g_a) P g_a / l^2.
        Shear (Eq. 30-33, §3): d gamma = sign (dg1 . t1 / |g1| + dg2 . t2 / |g2|), t1 the
        unit vector normal to g1 towards g2 in their plane (and t2 likewise), sign the cell's
        ``shear_sign``.
        """
        scale = self.reference_area[:, None] * self.weights[None, :]  # A0 w_f, (m, L)
        len1, len2 = strain["length1"], strain["length2"]
        fibre1, fibre2 = strain["fibre1"], strain["fibre2"]
        g1, g2 = geo["g1"], geo["g2"]
        p1 = np.zeros_like(g1)
        p2 = np.zeros_like(g2)
        normal_load = None
        if tension:
            warp, weft = self._by_family(strain["eps1"], strain["eps2"])
            t_warp = self.fabric.tension.value(warp)
            t_weft = self.fabric.tension_weft.value(weft)
            t1 = np.where(self.xi_is_warp[:, None], t_warp, t_weft)
            t2 = np.where(self.xi_is_warp[:, None], t_weft, t_warp)
            if self.nodal_normals:
                n = geo["normal"][:, None, :]
                normal_load = np.zeros_like(geo["normal"])
                for p, g, t, fibre in ((p1, g1, t1, fibre1), (p2, g2, t2, fibre2)):
                    along = np.sum(g * n, axis=-1, keepdims=True)
                    coefficient = (scale * t / fibre**2)[..., None]
                    p += coefficient * (g - along * n)
                    normal_load -= np.sum(coefficient * along * (g - along * n), axis=1)
            else:
                p1 += (scale * t1 / fibre1**2)[..., None] * g1
                p2 += (scale * t2 / fibre2**2)[..., None] * g2
        if shear:
            u1 = g1 / len1[..., None]
            u2 = g2 / len2[..., None]
            c = np.sum(u1 * u2, axis=-1)
            s = np.sqrt(np.maximum(1.0 - c**2, 1e-24))
            moment = self.shear_sign[:, None] * self.fabric.shear.value(strain["gamma"])
            p1 += (scale * moment / (len1 * s))[..., None] * (u2 - c[..., None] * u1)
            p2 += (scale * moment / (len2 * s))[..., None] * (u1 - c[..., None] * u2)
        return p1, p2, normal_load

    def _layer_forces(self, geo, p1, p2, normal_load=None):
        """Nodal forces (m,3,3) and moment vectors (m,3,3) from the layer loads (Eq. 24, 28),
        and dW/dS_k (m,3,3) at the corners with nodal normals (else None).

        The force on fibre end point k of level f is F_k^f = sum_a N_k,a P_a (N_k,xi =
        (-1, 1, 0), N_k,eta = (-1, 0, 1)); the node takes sum_f F_k^f and the director the
        moment sum_f (zeta_f h_m^k / 2) V_k x F_k^f of the lever arm along V (Bai Fig. 3).
        With ``thickness_variation`` the work of h_m = h / (V . n) is added (docs/theory.md §2.5):
        through the director (moment), and through n: with the element normal as forces on the
        cell's nodes; with the nodal normals as dW/dS_k, which ``_membrane_forces`` turns into
        forces on every cell around node k.
        """
        v, h_m = geo["directors"], geo["thickness"]
        # Sums over the levels first (F_k^f is linear in P_a): sum_f F_k^f and sum_f zeta_f F_k^f.
        total1, total2 = p1.sum(axis=1), p2.sum(axis=1)
        force = np.stack([-(total1 + total2), total1, total2], axis=1)
        if normal_load is not None:
            # n = c / |c|, c = a x b: dW/dc = P dW/dn / |c|, pulled through the bilinear c.
            n = geo["normal"]
            load = normal_load - np.sum(normal_load * n, axis=1)[:, None] * n
            force += _cross_product_pull(geo["corners"], load / geo["double_area"][:, None])
        arm1, arm2 = np.matmul(self.zeta, p1), np.matmul(self.zeta, p2)
        lever = np.stack([-(arm1 + arm2), arm1, arm2], axis=1)
        moment = 0.5 * h_m[..., None] * cross(v, lever)
        d_sums = np.zeros_like(v) if self.nodal_normals else None
        if self.thickness_variation:
            # dW/dh_m^k = sum_f zeta_f / 2 F_k^f . V_k; h_m = h / c, c = V . n (unguarded only).
            dw_dh = 0.5 * np.sum(lever * v, axis=-1)
            c = geo["cosine"]
            dw_dc = np.where(geo["guarded"], 0.0, -dw_dh * self.fabric.thickness / c**2)
            if d_sums is not None:
                # c_k = V_k . S_k / |S_k|: dc/dpsi_k = V_k x N_k, dc/dS_k = (V_k - c N_k) / |S_k|.
                node_normal = geo["node_normal"]
                moment += dw_dc[..., None] * cross(v, node_normal)
                d_sums = (dw_dc / geo["normal_sum_length"])[..., None] * (
                    v - c[..., None] * node_normal
                )
                return force, moment, d_sums
            n = geo["normal"]
            moment += dw_dc[..., None] * cross(v, n[:, None, :])  # dc/dpsi_k = V_k x n
            # dc_k/dx through n = c / |c|: dc_k = V_perp,k . dc / |c| (V_perp = V - c n), so
            # the corners pull as d(g . c)/dx with g = sum_k (dW/dc_k) V_perp,k / |c|.
            v_perp = v - c[..., None] * n[:, None, :]
            g = np.matmul(dw_dc[:, None, :], v_perp)[:, 0] / geo["double_area"][:, None]
            force += _cross_product_pull(geo["corners"], g)
        return force, moment, d_sums

    def _membrane_forces(self, geo, strain, tension=True, shear=True):
        """Tension and/or shear forces and director moments per cell corner (m, 3, 3), the
        variation of the nodal normals included: dW/dS_k summed over the cells around node k
        (T_k), then d(S_k)/dx through every cell f around k: T_k . d(alpha_k^f n_f)/dx."""
        loads = self._layer_loads(geo, strain, tension, shear)
        force, moment, d_sums = self._layer_forces(geo, *loads)
        if d_sums is not None:
            pull = self._free_sums(self.scatter.vectors(d_sums))[self.connectivity]  # T_k
            force = force + _corner_normal_pull(geo["corners"], pull)
        return force, moment

    def _bending_geometry(self, positions: np.ndarray, geo: dict | None = None) -> dict:
        """Fold angles, curvature coefficients and fold-angle gradients (docs/theory.md §4.1-4.3).

        fold : (m, 3) theta_s per side, atan2(-n'.n^c_s, n.n'); 0 on free sides and in held
            cells; against the element's reference plane on clamped sides.
        coefficients : (m, 2, 3) c_as = 2 (g_a . n^c_s)^2 / (h_s + h_s') (0 on free sides and
            in held cells).
        gradient : (m, 3, 3) D[s, k] with d phi_s / d x_k = D[s, k] n (the element's share of
            d theta_s / dx, Eq. 36: D = -grad N_k . n^c_s).
        """
        if self.compiled:
            return fibrous_kernels.bending_geometry(self, positions)
        x = positions[self.connectivity] if geo is None else geo["corners"]
        sides = _side_geometry(x)
        n, double_area = sides["normal"], sides["double_area"]
        side_length, outward, gradient = sides["length"], sides["outward"], sides["gradient"]

        nb = self._across_cell
        n_other = np.where(self.interior_side[..., None], n[nb], 0.0)
        if self.clamped_side.any():
            wall = getattr(self, "reference_normal", n)
            n_other = np.where(self.clamped_side[..., None], wall[:, None, :], n_other)
        has_fold = self.interior_side | self.clamped_side
        fold = np.where(
            has_fold,
            np.arctan2(
                -np.sum(n_other * outward, axis=-1), np.matmul(n_other, n[:, :, None])[..., 0]
            ),
            0.0,
        )
        heights = double_area[:, None] / side_length
        other_heights = np.where(self.interior_side, double_area[nb] / side_length, 0.0)
        fibre = np.stack([x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]], axis=1)
        fibre /= np.linalg.norm(fibre, axis=-1, keepdims=True)
        projection = np.matmul(fibre, outward.transpose(0, 2, 1))  # (m, a, s)
        coefficients = np.where(
            has_fold[:, None, :],
            2.0 * projection**2 / (heights + other_heights)[:, None, :],
            0.0,
        )
        return {"fold": fold, "coefficients": coefficients, "gradient": gradient, "normal": n}

    def _curvatures(self, bend: dict) -> tuple[np.ndarray, np.ndarray]:
        """chi (m, 2) along edges 0-1 and 0-2 (Eq. 35): chi_a = -sum_s c_as (theta_s - theta_s0),
        and the coefficients used."""
        coefficients = (
            self.reference_coefficients
            if self.reference_curvature_coefficients
            else bend["coefficients"]
        )
        chi = -np.matmul(coefficients, (bend["fold"] - self.reference_fold)[:, :, None])[..., 0]
        return chi, coefficients

    def _bending_moments(self, chi: np.ndarray, slope: bool = False) -> np.ndarray:
        """M (m, 2) per unit width along edges 0-1 and 0-2 from the warp and weft laws (or,
        with ``slope``, dM/dchi)."""
        warp, weft = self._by_family(chi[:, 0], chi[:, 1])
        law = "slope" if slope else "value"
        m_warp = getattr(self.fabric.bending, law)(warp)
        m_weft = getattr(self.fabric.bending_weft, law)(weft)
        return np.stack(
            [np.where(self.xi_is_warp, m_warp, m_weft), np.where(self.xi_is_warp, m_weft, m_warp)],
            axis=1,
        )

    def _bending_forces(self, state: State, geo: dict | None = None) -> np.ndarray:
        """Nodal bending forces (m, 3, 3) (Eq. 37): the energy A0 sum_a Phi_a(chi_a) varies
        through the fold angles; each side's moment mu = -sum over its two elements of
        A0 sum_a M_a c_as multiplies d theta/dx, whose share on each element's own nodes is
        D[s, k] n, so every element scatters to its own three nodes only."""
        bend = self._bending_geometry(state.positions, geo)
        chi, coefficients = self._curvatures(bend)
        moments = self._bending_moments(chi)
        own = -self.reference_area[:, None] * np.matmul(moments[:, None, :], coefficients)[:, 0]
        across = np.where(self.interior_side, own[self._across_cell, self._across_side], 0.0)
        side_moment = own + across  # free sides: own = 0 since c = 0
        weights = np.matmul(side_moment[:, None, :], bend["gradient"])[:, 0]
        return weights[..., None] * bend["normal"][:, None, :]

    # ------------------------------------------------------------------ tangent
    def _membrane_loads(self, x: np.ndarray, v: np.ndarray):
        """Unscattered tension + shear forces and director moments (m, 3, 3) of each cell
        (element normals: cell-local)."""
        geo = self._cell_geometry(x, v)
        loads = self._layer_loads(geo, self._strains(geo))
        force, moment, _ = self._layer_forces(geo, *loads)
        return force, moment

    def _cell_gradient(self, x: np.ndarray, v: np.ndarray, sums: np.ndarray) -> np.ndarray:
        """The gradient of each cell's tension + shear energy W_e(x_e, V_e, S_e) with the
        nodal normal sums S_k of its corners as independent variables: (m, 3, 9), per corner
        (dW/dx, dW/dpsi, dW/dS)."""
        geo = self._cell_geometry(x, v, True, sums)
        loads = self._layer_loads(geo, self._strains(geo))
        force, moment, d_sums = self._layer_forces(geo, *loads)
        return np.concatenate([force, moment, d_sums], axis=-1)

    def _membrane_hessian(
        self, x: np.ndarray, v: np.ndarray, sums: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """d(``_cell_gradient``)/d(x, psi, S) of every cell (m, 3, 9, 3, 9), with nodal normals:
        row (corner, dW/dx | dW/dpsi | dW/dS), column (corner, x | psi | S); N/mm, N, N mm and
        per unit of S (the sums are angle-weighted normals, rad). Also the gradient's dW/dS
        (m, 3, 3), N mm, from the same loads.

        The cell energy reaches the 27 unknowns q through w = (e_a, d_a, n), 15 numbers:
        g_a^f = e_a + zeta_f / 2 d_a at each level f, with the edges e_a = x_a - x_0, the
        director offsets d_a = D_a - D_0 (D_k = h_m^k V_k) and n the element normal. So the
        stiffness is A^T H_w A plus the terms of the second derivatives of w: H_w from the
        9 x 9 derivatives of each level's loads (P_1, P_2, dW/dn) in (g_1, g_2, n), summed over
        the levels with weights 1, zeta_f / 2, (zeta_f / 2)^2; A = dw/dq (a director turns as
        dV = dpsi x V); the second derivatives of n(x) contracted with dW/dn and of
        D_k(psi_k, S_k) with dW/dD_k. Every term is the derivative of the gradient's own
        formulas (with ``thickness_variation=False``, of its moments without the h_m term), so
        this is what central differences of ``_cell_gradient`` converge to, in a few batched
        products instead of 54 evaluations of it.
        """
        geo = self._cell_geometry(x, v, True, sums)
        strain = self._strains(geo)
        p1, p2, normal_load = self._layer_loads(geo, strain)
        m, levels = len(x), self.zeta.size
        eye = np.eye(3)
        h0 = self.fabric.thickness
        scale = self.reference_area[:, None] * self.weights[None, :]  # A0 w_f, (m, L)

        # ---- each level's loads in (g1, g2, n): hz[m, f, out (P1, P2, dW/dn), i, in, j]
        hz = np.zeros((m, levels, 3, 3, 3, 3))
        n = geo["normal"][:, None, :]  # (m, 1, 3)
        warp, weft = self._by_family(strain["eps1"], strain["eps2"])
        flag = self.xi_is_warp[:, None]
        value = self.fabric.tension.value(warp), self.fabric.tension_weft.value(weft)
        slope = self.fabric.tension.slope(warp), self.fabric.tension_weft.slope(weft)
        tensions = (
            (np.where(flag, value[0], value[1]), np.where(flag, slope[0], slope[1])),
            (np.where(flag, value[1], value[0]), np.where(flag, slope[1], slope[0])),
        )
        projector = eye - n[..., :, None] * n[..., None, :]  # (m, 1, 3, 3)
        for edge, g, (t, t_slope), fibre in (
            (0, geo["g1"], tensions[0], strain["fibre1"]),
            (1, geo["g2"], tensions[1], strain["fibre2"]),
        ):
            # P = kappa r, dW/dn = -kappa s r: r = g - s n, s = g . n, kappa = A0 w T / l^2,
            # and d kappa = beta (r . dg - s r . dn), beta = A0 w (T' - 2 T) / l^4.
            s = np.sum(g * n, axis=-1)[..., None, None]  # (m, L, 1, 1)
            r = g - s[..., 0] * n
            kappa = (scale * t / fibre**2)[..., None, None]
            beta = (scale * (t_slope - 2.0 * t) / fibre**4)[..., None, None]
            rr = r[..., :, None] * r[..., None, :]
            ng = n[..., :, None] * g[..., None, :]
            hz[:, :, edge, :, edge, :] += beta * rr + kappa * projector
            hz[:, :, edge, :, 2, :] += -s * beta * rr - kappa * (ng + s * eye)
            hz[:, :, 2, :, edge, :] += -s * beta * rr - kappa * (
                r[..., :, None] * n[..., None, :] + s * projector
            )
            hz[:, :, 2, :, 2, :] += s**2 * beta * rr - kappa * (
                r[..., :, None] * g[..., None, :] - s * ng - s**2 * eye
            )
        # Shear: P_a = A0 w f(c) dc/dg_a, c = u1 . u2, f = M / s, s = sqrt(1 - c^2).
        len1, len2 = strain["length1"][..., None], strain["length2"][..., None]
        u1, u2 = geo["g1"] / len1, geo["g2"] / len2
        c = np.sum(u1 * u2, axis=-1)
        sine2 = 1.0 - c**2
        s = np.sqrt(np.maximum(sine2, 1e-24))
        gamma = strain["gamma"]
        moment = self.shear_sign[:, None] * self.fabric.shear.value(gamma)
        f = scale * moment / s
        # d(M / s)/dc: dM/dc = M'(gamma) / s (the sign enters M and gamma); ds/dc = -c / s.
        f_slope = scale * (
            self.fabric.shear.slope(gamma) / s**2 + np.where(sine2 > 1e-24, moment * c / s**3, 0.0)
        )
        c1 = (u2 - c[..., None] * u1) / len1  # dc/dg1
        c2 = (u1 - c[..., None] * u2) / len2
        q1 = (eye - u1[..., :, None] * u1[..., None, :]) / len1[..., None]  # du1/dg1
        q2 = (eye - u2[..., :, None] * u2[..., None, :]) / len2[..., None]
        outer = lambda a, b: a[..., :, None] * b[..., None, :]  # noqa: E731
        cc = c[..., None, None]
        # d(dc/dg_a)/dg_b (Q_a = du_a/dg_a): -(u1 c1^T + c Q1 + c1 u1^T) / |g1| for a = b = 1,
        # (Q2 - u1 c2^T) / |g1| for a = 1, b = 2, and likewise for a = 2.
        second = (
            (
                -(outer(u1, c1) + cc * q1 + outer(c1, u1)) / len1[..., None],
                (q2 - outer(u1, c2)) / len1[..., None],
            ),
            (
                (q1 - outer(u2, c1)) / len2[..., None],
                -(outer(u2, c2) + cc * q2 + outer(c2, u2)) / len2[..., None],
            ),
        )
        grads = (c1, c2)
        for a in range(2):
            for b in range(2):
                hz[:, :, a, :, b, :] += f_slope[..., None, None] * outer(grads[a], grads[b])
                hz[:, :, a, :, b, :] += f[..., None, None] * second[a][b]

        # ---- H_w (m, 15, 15) over w = (e_1, e_2, d_1, d_2, n), e_a = x_a - x_0 and
        # d_a = D_a - D_0, so that g_a = e_a + zeta_f / 2 d_a: the levels' blocks summed with
        # weights (zeta_f / 2)^p, p the number of d among the row and the column.
        half = 0.5 * self.zeta
        moments = [np.einsum("f,mfaibj->maibj", half**p, hz) for p in range(3)]
        h_w = np.empty((m, 15, 15))
        for rows, p_row in ((slice(0, 6), 0), (slice(6, 12), 1)):
            for cols, p_col in ((slice(0, 6), 0), (slice(6, 12), 1)):
                h_w[:, rows, cols] = moments[p_row + p_col][:, :2, :, :2].reshape(m, 6, 6)
            h_w[:, rows, 12:] = moments[p_row][:, :2, :, 2].reshape(m, 6, 3)
            h_w[:, 12:, rows] = moments[p_row][:, 2, :, :2].reshape(m, 3, 6)
        h_w[:, 12:, 12:] = moments[0][:, 2, :, 2]

        # ---- A = dw/dq (m, 15, 27), q = (x, psi, S) per corner: +-1 for e_a, the blocks
        # dD_k/d(psi_k, S_k) for d_a, dn/dx_k for n.
        v_cross_n = cross(v, geo["node_normal"])  # dc_k/dpsi_k, (m, 3, 3)
        node_normal, sum_length = geo["node_normal"], geo["normal_sum_length"]
        cosine, h_m = geo["cosine"], geo["thickness"]
        dh_dc = np.where(geo["guarded"], 0.0, -h0 / cosine**2)[..., None, None]  # (m, 3, 1, 1)
        dc_ds = (v - cosine[..., None] * node_normal) / sum_length[..., None]  # dc_k/dS_k
        spin = -h_m[..., None, None] * _skew(v)  # h dpsi x V
        d_psi = spin + dh_dc * outer(v, v_cross_n)  # dD_k/dpsi_k (m, 3, 3, 3)
        d_by_sums = dh_dc * outer(v, dc_ds)  # dD_k/dS_k
        area2 = geo["double_area"][:, None, None]
        a_edge, b_edge = x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]
        dc_dx = np.stack([_skew(b_edge) - _skew(a_edge), -_skew(b_edge), _skew(a_edge)], axis=1)
        dn_dx = np.matmul(projector, dc_dx) / area2[:, None]  # (m, k, 3, 3)
        d_director = np.concatenate([d_psi, d_by_sums], axis=-1)  # dD_k/d(psi_k, S_k), (m, 3, 3, 6)
        if self.thickness_variation:
            d_director_rows = d_director
        else:  # the moments are h_m V x dW/dD without the variation of h_m, and dW/dS = 0
            d_director_rows = np.concatenate([spin, np.zeros_like(spin)], axis=-1)

        def dw_dq(d_director: np.ndarray) -> np.ndarray:
            jac = np.zeros((m, 15, 3, 9))
            for a in (1, 2):
                edge = slice(3 * a - 3, 3 * a)
                jac[:, edge, a, 0:3] = eye
                jac[:, edge, 0, 0:3] = -eye
                jac[:, 6 + edge.start : 6 + edge.stop, a, 3:] = d_director[:, a]
                jac[:, 6 + edge.start : 6 + edge.stop, 0, 3:] = -d_director[:, 0]
            jac[:, 12:, :, 0:3] = dn_dx.transpose(0, 2, 1, 3)
            return jac.reshape(m, 15, 27)

        jac = dw_dq(d_director)
        jac_rows = jac if self.thickness_variation else dw_dq(d_director_rows)
        hessian = np.matmul(np.swapaxes(jac_rows, 1, 2), np.matmul(h_w, jac))
        hessian = hessian.reshape(m, 3, 9, 3, 9)
        corners = np.arange(3)

        # ---- second derivatives of n(x), dW/dn held: C^T omega, omega = P dW/dn / |c|.
        load = normal_load[:, None]
        n_load = np.sum(load * n, axis=-1)[..., None]
        omega = (load - n_load * n) / area2  # (m, 1, 3)
        basis = np.eye(9).reshape(9, 3, 3)  # x_k component i, all in one cell
        da, db = basis[:, 1] - basis[:, 0], basis[:, 2] - basis[:, 0]  # (9, 3)
        dc = cross(da, b_edge[:, None]) + cross(a_edge[:, None], db)  # (m, 9, 3)
        d_area2 = np.sum(n * dc, axis=-1)[..., None]
        dn = (dc - d_area2 * n) / area2
        d_omega = -np.sum(load * dn, axis=-1)[..., None] * n - n_load * dn - omega * d_area2
        d_omega = d_omega / area2
        d_along_a = cross(db, omega) + cross(b_edge[:, None], d_omega)
        d_along_b = cross(d_omega, a_edge[:, None]) + cross(omega, da)
        d_force = np.stack([-(d_along_a + d_along_b), d_along_a, d_along_b], axis=2)
        hessian[:, :, 0:3, :, 0:3] += d_force.reshape(m, 3, 3, 3, 3).transpose(0, 3, 4, 1, 2)

        # ---- second derivatives of D_k(psi_k, S_k), dW/dD_k = lever_k / 2 held: the same
        # unit direction in every corner at once, each corner's terms depending on its own.
        arm1, arm2 = np.matmul(self.zeta, p1), np.matmul(self.zeta, p2)
        lever = np.stack([-(arm1 + arm2), arm1, arm2], axis=1)[:, None]  # (m, 1, 3, 3)
        unit = np.eye(6)[:, None, :]  # (6, 1 (all corners), 6)
        dv = cross(unit[..., 0:3], v[:, None])  # (m, 6, 3, 3)
        ds_ = unit[..., 3:6]
        vv, nn = v[:, None], node_normal[:, None]
        length = sum_length[:, None, :, None]
        d_length = np.sum(nn * ds_, axis=-1)[..., None]
        d_nn = (ds_ - d_length * nn) / length
        cos4 = cosine[:, None, :, None]
        d_cos = np.sum(dv * nn + vv * d_nn, axis=-1)[..., None]
        guarded = geo["guarded"][:, None, :, None]
        dh = np.where(guarded, 0.0, -h0 * d_cos / cos4**2)
        hm = h_m[:, None, :, None]
        d_moment = 0.5 * (dh * cross(vv, lever) + hm * cross(dv, lever))
        d_dsums = np.zeros(d_moment.shape)
        if self.thickness_variation:
            dw_dh = 0.5 * np.sum(lever * vv, axis=-1)[..., None]
            d_dw_dh = 0.5 * np.sum(lever * dv, axis=-1)[..., None]
            dw_dc = np.where(guarded, 0.0, -dw_dh * h0 / cos4**2)
            d_dw_dc = np.where(
                guarded, 0.0, -h0 * (d_dw_dh / cos4**2 - 2.0 * dw_dh * d_cos / cos4**3)
            )
            d_moment += d_dw_dc * cross(vv, nn) + dw_dc * (cross(dv, nn) + cross(vv, d_nn))
            d_dsums = (d_dw_dc / length - dw_dc * d_length / length**2) * (vv - cos4 * nn) + (
                dw_dc / length
            ) * (dv - d_cos * nn - cos4 * d_nn)
        explicit = np.concatenate([d_moment, d_dsums], axis=-1)  # (m, 6 in, 3 corners, 6 out)
        hessian[:, corners, 3:, corners, 3:] += explicit.transpose(2, 0, 3, 1)
        _, _, d_sums_gradient = self._layer_forces(geo, p1, p2, normal_load)
        return hessian, d_sums_gradient

    def _corner_pairs(self) -> _CornerPairs:
        """The node-pair pattern of the sparse membrane tangent (built at its first use)."""
        if self._pairs is None:
            self._pairs = _CornerPairs(self.connectivity, self.n_nodes)
        return self._pairs

    def _nodal_membrane_tangent(self, state: State) -> tuple[SparseTangent, np.ndarray]:
        """Exact stiffness of tension + shear with nodal normals (docs/theory.md §2.6): a sparse
        matrix over the nodes in 6 x 6 blocks and the cell-local translation blocks of the
        second derivatives of the normal sums (m, 3, 3, 3, 3), as in CellTangent.blocks.

        W = sum_e W_e(x_e, psi_e, S_e) with S_k = sum_(f around k) alpha_k^f n_f(x_f), so
        K = J^T H J + sum_f sum_k T_k . d2(alpha_k^f n_f)/dx2: H the cells' 27 x 27 Hessians in
        (x, psi, S) per corner (``_membrane_hessian``), J the map from (u, psi) to (u, psi, S)
        (dS_k/dx_j, the sum of d(alpha_k^f n_f)/dx_j over the cells f around k holding j,
        exact), and T_k = dW/dS_k (the second term ``_corner_normal_pull_tangent``, closed form).

        H and J are block sparse on the node pairs of the cells (``_CornerPairs``, built once):
        their blocks are summed into that fixed pattern by one bincount each, and the product
        is a BSR matrix with 6 x 6 blocks.
        """
        conn = self.connectivity
        x = state.positions[conn]
        v = state.directors[conn]
        sums = self._normal_sums(state.positions)[conn]
        pairs = self._corner_pairs()
        hessian, d_sums = self._membrane_hessian(x, v, sums)  # (m, 3, 9, 3, 9), (m, 3, 3)
        h_ext = pairs.hessian(hessian)

        # J: (u, psi) of node k -> rows 9k..9k+5; S_k <- d(alpha_k^f n_f)/dx_j for k, j
        # corners of f.
        _, ds_dx = _corner_normals(x, jacobian=True)  # (m, corner k, S comp, node j, x comp)
        ds_dx = ds_dx * ~self.wall_nodes[conn][:, :, None, None, None]
        jac = pairs.jacobian(ds_dx)

        # sum_f sum_k T_k . d2(alpha_k^f n_f)/dx2, T held.
        pull = self._free_sums(self.scatter.vectors(d_sums))[conn]  # T_k (m, 3, 3)
        second = _corner_normal_pull_tangent(x, pull)
        return SparseTangent(jac.T @ (h_ext @ jac)), second

    def tangent(self, state: State, history=None) -> list[TangentPart]:
        """Stiffness of tension + shear and of bending (Eq. 37 differentiated, see
        ``_bending_tangent``). Tension + shear: with element normals each cell's own 18 x 18,
        by central differences of its loads, all cells at once; with nodal normals the sparse
        matrix of ``_nodal_membrane_tangent`` (closed form, as the bending)."""
        bending = self._bending_tangent(state)
        if self.nodal_normals:
            sparse, second = self._nodal_membrane_tangent(state)
            # The cell-local translation blocks join the bending patch's (its first 3 nodes).
            bending.blocks[:, :3, :, :3] += second
            return [sparse, bending]
        x = state.positions[self.connectivity]
        v = state.directors[self.connectivity]
        step = 1e-6 * float(np.sqrt(np.median(self.reference_area)))
        membrane = local_tangent(self._membrane_loads, x, v, step)
        return [CellTangent(self.connectivity, membrane), bending]

    def _bending_tangent(self, state: State) -> CellTangent:
        """Stiffness of the bending forces F = sum_e A0 sum_a M_a(chi_a) dchi_a/dx (Eq. 37).

        Material part: sum_e A0 sum_a (dM_a/dchi) g_a g_a^T with g_a = dchi_a/dx = -sum_s c_as
        dtheta_s/dx over the element's patch: its own three nodes (the share D[s, k] n of
        every side) and the three nodes of each neighbour (the neighbour's share), two of
        which are its own: six nodes (``_patch_nodes``), blocks (m, 6, 3, 6, 3).
        Geometric part: sum_s mu_s d2theta_s/dx2, i.e. each element's own share mu_s D[s, k] n
        differentiated (``_share_tangent``, the side moments mu_s held). The coefficients c_as
        are held too, as in the force (exact with ``bending_geometry="reference"``; with
        "current" the neglected dc/dx terms are of the order of the fold-angle change over the
        increment).
        """
        bend = self._bending_geometry(state.positions)
        chi, coefficients = self._curvatures(bend)
        slopes = self._bending_moments(chi, slope=True)
        share = bend["gradient"][..., None] * bend["normal"][:, None, None, :]  # (m, s, k, 3)
        across_share = np.where(
            self.interior_side[..., None, None], share[self._across_cell, self._across_side], 0.0
        )
        m = len(self.cell_ids)
        own = -np.einsum("mas,mskj->makj", coefficients, share)  # (m, a, 3, 3)
        across = -coefficients[..., None, None] * across_share[:, None]  # (m, a, s, 3, 3)
        # The patch has six nodes, not twelve: each neighbour shares the two nodes of its side,
        # so its share folds onto those and the node opposite (slot 3 + s); the blocks are then
        # a quarter of the size to form and to assemble.
        nodes, slot = self._patch_nodes()
        fold = (slot[..., None] == np.arange(6)).astype(float)  # (m, s * 3 + j, 6)
        g = np.matmul(fold.transpose(0, 2, 1)[:, None], across.reshape(m, 2, 9, 3))
        g[:, :, :3] += own  # (m, a, 6, 3)
        weight = self.reference_area[:, None] * slopes  # (m, a)
        flat = g.reshape(m, 2, 18)
        blocks = np.matmul(flat.transpose(0, 2, 1) * weight[:, None, :], flat)
        blocks = blocks.reshape(m, 6, 3, 6, 3)  # sum_a w_a g_a g_a^T

        moments = self._bending_moments(chi)
        own_mu = -self.reference_area[:, None] * np.matmul(moments[:, None, :], coefficients)[:, 0]
        across_mu = np.where(self.interior_side, own_mu[self._across_cell, self._across_side], 0.0)
        side_moment = own_mu + across_mu

        x = state.positions[self.connectivity]
        blocks[:, :3, :, :3] += _share_tangent(x, side_moment)
        return CellTangent(nodes, blocks)

    def _patch_nodes(self) -> tuple[np.ndarray, np.ndarray]:
        """The six nodes of each cell's bending patch (m, 6): its corners, then across each
        side s the neighbour's node opposite it (the cell's corner s where the side couples
        no neighbour: its blocks are zero there); and the patch slot (m, 9) of the
        neighbour's corner j across side s, at s * 3 + j."""
        conn = self.connectivity
        other = conn[self._across_cell]  # (m, s, j)
        slot = np.broadcast_to(3 + np.arange(3)[None, :, None], other.shape).copy()
        for end in (_P, _Q):
            ends = conn[:, end]  # (m, s): the side's end node
            slot = np.where(other == ends[..., None], end[None, :, None], slot)
        slot = np.where(self.interior_side[..., None], slot, 3 + np.arange(3)[None, :, None])
        opposite = np.where(slot == 3 + np.arange(3)[None, :, None], other, 0).max(axis=2)
        opposite = np.where(self.interior_side, opposite, conn)
        return np.concatenate([conn, opposite], axis=1), slot.reshape(len(conn), 9)

    # ------------------------------------------------------------------ protocol
    def internal_force(self, state: State, history=None):
        if self.compiled:  # the four passes of elements/fibrous_kernels.py
            return fibrous_kernels.internal_force(self, state.positions, state.directors)
        geo = self._geometry(state.positions, state.directors)
        force, moment = self._membrane_forces(geo, self._strains(geo))
        force = force + self._bending_forces(state, geo)
        return self.scatter.vectors(force), self.scatter.vectors(moment)

    def internal_force_parts(self, state: State) -> dict:
        """{"tension" | "shear": (forces (n,3), moments (n,3)), "bending": (forces, zeros)}:
        the three virtual-work terms separately (diagnostics and tests)."""
        geo = self._geometry(state.positions, state.directors)
        strain = self._strains(geo)
        parts = {}
        for name, flags in (("tension", (True, False)), ("shear", (False, True))):
            f, m = self._membrane_forces(geo, strain, *flags)
            parts[name] = (self.scatter.vectors(f), self.scatter.vectors(m))
        parts["bending"] = (
            self.scatter.vectors(self._bending_forces(state)),
            np.zeros((self.n_nodes, 3)),
        )
        return parts

    def strain_energy_parts(self, state: State) -> dict:
        """Strain energy (N mm) of each term: {"tension", "shear", "bending"}."""
        if self.compiled:
            return fibrous_kernels.strain_energy_parts(self, state.positions, state.directors)
        geo = self._geometry(state.positions, state.directors)
        strain = self._strains(geo)
        scale = self.reference_area[:, None] * self.weights[None, :]
        warp, weft = self._by_family(strain["eps1"], strain["eps2"])
        tension = np.sum(
            scale * (self.fabric.tension.energy(warp) + self.fabric.tension_weft.energy(weft))
        )
        shear = np.sum(scale * self.fabric.shear.energy(strain["gamma"]))
        chi, _ = self._curvatures(self._bending_geometry(state.positions))
        chi_warp, chi_weft = self._by_family(chi[:, 0], chi[:, 1])
        bending = np.sum(
            self.reference_area
            * (self.fabric.bending.energy(chi_warp) + self.fabric.bending_weft.energy(chi_weft))
        )
        return {"tension": float(tension), "shear": float(shear), "bending": float(bending)}

    def strain_energy(self, state: State, history=None) -> float:
        return float(sum(self.strain_energy_parts(state).values()))

    def nodal_thickness(self, state: State) -> np.ndarray:
        """Thickness along the director at the nodes (n,), mm: h_m from the nodal normal, or
        with element normals the area-weighted mean of the per-element h_m (docs/theory.md
        §1.4); 0 at nodes outside the block."""
        if self.compiled and self.nodal_normals:
            # h / max(V . N, guard) at each node of the block from the compiled normal sums
            # (the explicit solver refreshes the rotary inertia with it)
            sums = self._normal_sums(state.positions)
            length = np.linalg.norm(sums, axis=1)
            inside = self.node_in_block
            cosine = np.sum(state.directors * sums, axis=1) / np.where(inside, length, 1.0)
            h_m, _ = guarded_thickness(self.fabric.thickness, cosine)
            return np.where(inside, h_m, 0.0)
        return self._nodal_thickness(self._geometry(state.positions, state.directors, layers=False))

    def director_tilt(self, state: State) -> np.ndarray:
        """Angle between the director and the nodal normal of the block (n,), rad, in [0, pi];
        0 at nodes outside the block. A stack of freely slipping layers bent by theta from a
        clamp tilts by atan(theta) (docs/theory.md §1.7)."""
        normals = self._normal_sums(state.positions)
        length = np.linalg.norm(normals, axis=1)
        inside = length > 0
        cosine = np.sum(state.directors * normals, axis=1) / np.where(inside, length, 1.0)
        return np.where(inside, np.arccos(np.clip(cosine, -1.0, 1.0)), 0.0)

    def _nodal_thickness(self, geo: dict) -> np.ndarray:
        if self.nodal_normals:  # every corner of a node holds the same h_m
            value = np.zeros(self.n_nodes)
            value[self.connectivity] = geo["thickness"]
            return value
        return nodal_thickness(
            geo["thickness"], 0.5 * geo["double_area"], self.connectivity, self.n_nodes
        )

    def guarded_nodes(self, state: State) -> np.ndarray:
        """Ids of the nodes where V.n fell below the guard of h_m = h / max(V.n, 0.2) in some
        element (the thickness along the director is capped there at 5 h)."""
        geo = self._geometry(state.positions, state.directors, layers=False)
        return np.unique(self.connectivity[geo["guarded"]])

    def lumped_mass(self, state: State, density_scale=None):
        density: float | np.ndarray = self.fabric.areal_density
        if density_scale is not None:
            density = density * np.asarray(density_scale, dtype=float)
        return lumped_mass(
            density,
            self.reference_area,
            self.connectivity,
            self.nodal_thickness(state),
            self.n_nodes,
        )

    def cell_stable_dt(self, state: State) -> np.ndarray:
        """Critical step per cell from docs/theory.md §6.2, the three bounds combined as
        omega^2 = omega_tension^2 + omega_shear^2 + omega_bending^2 (a safe upper bound):

        * tension (A1): omega^2 = (2 + |cos phi|) C A0 / (L_min^2 m), m = rho_A A0 / 3, phi
          the warp-weft angle (two fibres in line at node 0 give the 3-mass chain value);
        * shear (A4): omega^2 = 2 K A0 (1/L1^2 + 1/L2^2) / m;
        * bending (A3): dt = 0.35 L_min^2 sqrt(rho_A / B).
        Director modes do not govern with I = m h_m^2 / 4 (A2) as long as I follows the
        current h_m (the solvers refresh the rotary inertia with the step) and the directors
        stay near the normal: at a tilt of 70 deg the exact step was 0.87 of this bound
        (docs/theory.md §6.2, measured on a pinched blank).
        """
        x = state.positions[self.connectivity]
        g1 = x[:, 1] - x[:, 0]
        g2 = x[:, 2] - x[:, 0]
        len1 = np.linalg.norm(g1, axis=1)
        len2 = np.linalg.norm(g2, axis=1)
        cosine = np.abs(np.sum(g1 * g2, axis=1)) / (len1 * len2)
        shortest = np.minimum(len1, len2)
        mass = self.fabric.areal_density * self.reference_area / 3.0
        a0 = self.reference_area
        omega2 = (2.0 + cosine) * self.max_tension_stiffness * a0 / (shortest**2 * mass)
        omega2 += 2.0 * self.max_shear_stiffness * a0 * (1 / len1**2 + 1 / len2**2) / mass
        dt_bending = (
            _BENDING_DT_COEFFICIENT
            * shortest**2
            * np.sqrt(self.fabric.areal_density / self.max_bending_stiffness)
        )
        omega2 += (2.0 / dt_bending) ** 2
        if self.nodal_normals:
            # h_m at a node follows the normals of its whole star, which couples the director
            # modes of neighbouring cells: on a jittered patch with tilted directors the
            # assembled omega_max exceeded the bound above by 1.8 % (omega^2); 10 % margin.
            omega2 *= 1.1
        return 2.0 / np.sqrt(omega2)

    def cell_fields(self, state: State, history=None) -> dict[str, np.ndarray]:
        geo = self._geometry(state.positions, state.directors)
        strain = self._strains(geo)
        warp, weft = self._by_family(strain["eps1"], strain["eps2"])
        chi, _ = self._curvatures(self._bending_geometry(state.positions))
        moments = self._bending_moments(chi)
        chi_warp, chi_weft = self._by_family(chi[:, 0], chi[:, 1])
        m_warp, m_weft = self._by_family(moments[:, 0], moments[:, 1])
        # The fields both shells write (README "Output fields"): section forces per unit
        # width in the fibre frame (1 = warp), averaged over the levels with their weights.
        t_warp = self.fabric.tension.value(warp) @ self.weights
        t_weft = self.fabric.tension_weft.value(weft) @ self.weights
        shear = self.fabric.shear.value(strain["gamma"]) @ self.weights
        return {
            "warp_strain": warp,  # (m, L), log strain, levels bottom -> top
            "weft_strain": weft,
            "shear_angle": strain["gamma"],  # (m, L), rad
            "warp_curvature": chi_warp,  # 1/mm
            "weft_curvature": chi_weft,
            "warp_moment": m_warp,  # N (N mm per mm)
            "weft_moment": m_weft,
            "membrane_force": np.column_stack([t_warp, t_weft, shear]),  # N/mm
            # no twisting moment in the fibrous shell: M12 = 0
            "bending_moment": np.column_stack([m_warp, m_weft, np.zeros_like(m_warp)]),
        }

    def node_fields(self, state: State, history=None) -> dict[str, np.ndarray]:
        geo = self._geometry(state.positions, state.directors, layers=False)
        guarded = np.zeros(self.n_nodes)
        guarded[self.connectivity[geo["guarded"]]] = 1.0
        return {
            "thickness": self._nodal_thickness(geo),
            "thickness_guarded": guarded,
            "director_tilt": self.director_tilt(state),  # rad, from the nodal normal
        }

    def total_mass(self) -> float:
        """Physical mass of the block (t)."""
        return float(self.fabric.areal_density * self.reference_area.sum())


# ---------------------------------------------------------------------- helpers
class _CornerPairs:
    """The node pairs (i, j) that share a cell, as the block structure of sparse matrices
    over the nodes whose blocks are sums of per-cell blocks (a BSR pattern, built once).

    slot : (m, 3, 3) int, the pair of (corner k, corner l) of each cell.
    indptr, indices : the BSR structure, pairs sorted by row then column.
    first_cell, first_corner : (nodes of the block,) a cell holding each node and the corner
        there, so that a per-node block is added exactly once.
    hessian_index, jacobian_index, identity_index : positions in the BSR data of the entries
        of ``hessian`` and ``jacobian``.
    """

    def __init__(self, connectivity: np.ndarray, n_nodes: int):
        m = len(connectivity)
        rows = np.broadcast_to(connectivity[:, :, None], (m, 3, 3)).ravel()
        cols = np.broadcast_to(connectivity[:, None, :], (m, 3, 3)).ravel()
        keys, slot = np.unique(rows * n_nodes + cols, return_inverse=True)
        self.n_nodes, self.n_pairs = n_nodes, keys.size
        self.slot = slot.reshape(m, 3, 3)
        pair_rows, self.indices = np.divmod(keys, n_nodes)
        self.indptr = np.searchsorted(pair_rows, np.arange(n_nodes + 1))
        _, first = np.unique(connectivity.ravel(), return_index=True)
        self.first_cell, self.first_corner = np.divmod(first, 3)

        # Where each entry of the per-cell arrays lands in the BSR data, in the layouts the
        # tangent forms them (so that a call is one bincount, with no transposed copy):
        # the Hessians (m, k, 9, l, 9) and the Jacobians dS_k/dx_j (m, k, 3, j, 3), whose
        # blocks (9 x 6) hold them in rows 6-8, columns 0-2.
        slot = self.slot[:, :, None, :, None]
        self.hessian_index = (slot * 81 + np.arange(9)[:, None, None] * 9 + np.arange(9)).ravel()
        rows = 6 + np.arange(3)[:, None, None]
        self.jacobian_index = (slot * 54 + rows * 6 + np.arange(3)).ravel()
        # The identity of (u, psi) on the diagonal blocks of J.
        diagonal = self.slot[self.first_cell, self.first_corner, self.first_corner]
        self.identity_index = (diagonal[:, None] * 54 + np.arange(6) * 7).ravel()

    def _matrix(self, data: np.ndarray, r: int, c: int) -> sp.bsr_matrix:
        return sp.bsr_matrix(
            (data.reshape(-1, r, c), self.indices, self.indptr),
            shape=(r * self.n_nodes, c * self.n_nodes),
        )

    def hessian(self, hessian: np.ndarray) -> sp.bsr_matrix:
        """The (9 n, 9 n) BSR matrix of per-cell Hessians (m, 3, 9, 3, 9) in (x, psi, S) per
        corner, summed on the node pairs."""
        data = np.bincount(self.hessian_index, hessian.ravel(), minlength=self.n_pairs * 81)
        return self._matrix(data, 9, 9)

    def jacobian(self, ds_dx: np.ndarray) -> sp.bsr_matrix:
        """The (9 n, 6 n) BSR matrix J from (u, psi) to (u, psi, S): the identity, and the
        per-cell dS_k/dx_j (m, k, 3, j, 3) summed on the node pairs."""
        data = np.bincount(self.jacobian_index, ds_dx.ravel(), minlength=self.n_pairs * 54)
        data[self.identity_index] += 1.0
        return self._matrix(data, 9, 6)


def _side_geometry(x: np.ndarray) -> dict:
    """Per-cell geometry of the sides from the corners x (m, 3, 3): unit normal n (m, 3),
    double_area (m,), side length (m, 3) and outward in-plane unit normal n^c_s (m, 3, 3), and
    gradient D (m, 3, 3), D[s, k] = -grad N_k . n^c_s: the element's share of the fold angle's
    gradient is d phi_s / d x_k = D[s, k] n (Eq. 36)."""
    normal = cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0])
    double_area = np.linalg.norm(normal, axis=1)
    n = normal / double_area[:, None]
    side = x[:, _Q] - x[:, _P]  # (m, 3, 3): side s from p to q
    length = np.linalg.norm(side, axis=-1)
    outward = cross(side, n[:, None, :]) / length[..., None]  # n^c_s
    grad_n = cross(n[:, None, :], side) / double_area[:, None, None]  # grad N_k
    gradient = -np.matmul(outward, grad_n.transpose(0, 2, 1))  # D[s, k]
    return {
        "normal": n,
        "double_area": double_area,
        "length": length,
        "outward": outward,
        "gradient": gradient,
    }


def _skew(w: np.ndarray) -> np.ndarray:
    """Cross-product matrices [w]x (..., 3, 3) with [w]x y = w x y."""
    zero = np.zeros(w.shape[:-1])
    return np.stack(
        [
            np.stack([zero, -w[..., 2], w[..., 1]], axis=-1),
            np.stack([w[..., 2], zero, -w[..., 0]], axis=-1),
            np.stack([-w[..., 1], w[..., 0], zero], axis=-1),
        ],
        axis=-2,
    )


def _corner_geometry(x: np.ndarray) -> dict:
    """What the angle-weighted normal shares need of each cell (m cells, corners k): the unit
    normal n (m, 3) and |c| (m,), c = (x1 - x0) x (x2 - x0); the angle alpha_k (m, 3); and
    d alpha_k / dx at the next and previous corners, (m, 3, 3) each: -t_u / |u| for the edge
    u = x_(k+1) - x_k (t_u the in-plane unit vector normal to u towards the other edge), and
    likewise for w = x_(k+2) - x_k; at x_k itself minus their sum."""
    c = cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0])
    size = np.linalg.norm(c, axis=1)
    n = c / size[:, None]
    u = x[:, [1, 2, 0]] - x
    w = x[:, [2, 0, 1]] - x
    u_len = np.linalg.norm(u, axis=-1, keepdims=True)
    w_len = np.linalg.norm(w, axis=-1, keepdims=True)
    return {
        "normal": n,
        "size": size,
        "angle": np.arctan2(np.linalg.norm(cross(u, w), axis=-1), np.sum(u * w, axis=-1)),
        "d_next": -cross(n[:, None, :], u / u_len) / u_len,
        "d_prev": -cross(w / w_len, n[:, None, :]) / w_len,
    }


def _corner_normals(x: np.ndarray, jacobian: bool = False):
    """Each cell's share of the nodal normal sums: s_k = alpha_k n (m, 3, 3), the unit normal
    weighted by the cell's angle at corner k, and with ``jacobian`` ds_k/dx_j
    (m, 3 k, 3, 3 j, 3), exact: d alpha_k/dx from ``_corner_geometry``, dn/dx_j =
    P dc/dx_j / |c| with P = I - n n^T."""
    geo = _corner_geometry(x)
    n, angle = geo["normal"], geo["angle"]
    shares = angle[..., None] * n[:, None, :]
    if not jacobian:
        return shares, None
    d_angle = np.zeros((len(x), 3, 3, 3))  # (m, corner k, node j, x comp)
    rows = np.arange(3)
    d_angle[:, rows, (rows + 1) % 3] = geo["d_next"]
    d_angle[:, rows, (rows + 2) % 3] = geo["d_prev"]
    d_angle[:, rows, rows] = -(geo["d_next"] + geo["d_prev"])
    a = x[:, 1] - x[:, 0]
    b = x[:, 2] - x[:, 0]
    d1, d2 = -_skew(b), _skew(a)
    dc_dx = np.stack([-(d1 + d2), d1, d2], axis=1)  # (m, node j, 3, 3)
    projector = np.eye(3) - n[:, :, None] * n[:, None, :]
    dn_dx = np.matmul(projector[:, None], dc_dx) / geo["size"][:, None, None, None]
    ds = n[:, None, :, None, None] * d_angle[:, :, None, :, :]
    ds = ds + angle[:, :, None, None, None] * dn_dx.transpose(0, 2, 1, 3)[:, None]
    return shares, ds


def _cross_product_pull(x: np.ndarray, g: np.ndarray) -> np.ndarray:
    """d(g . c)/dx at the corners (m, 3, 3) of c = (x1 - x0) x (x2 - x0), g (m, 3) held:
    b x g on x1, g x a on x2 (a = x1 - x0, b = x2 - x0), minus their sum on x0."""
    a = x[:, 1] - x[:, 0]
    b = x[:, 2] - x[:, 0]
    along_a, along_b = cross(b, g), cross(g, a)
    return np.stack([-(along_a + along_b), along_a, along_b], axis=1)


def _corner_normal_pull(x: np.ndarray, pull: np.ndarray) -> np.ndarray:
    """sum_k pull_k . d(alpha_k n)/dx_j at the corners (m, 3, 3) of each cell, pull (m, 3, 3)
    held: the forces of the nodal normals' variation. The derivatives of
    ``_corner_normals(x, jacobian=True)`` contracted as they are formed: (pull_k . n) times
    d alpha_k/dx, plus (dn/dx)^T sum_k alpha_k pull_k = (dc/dx)^T g, g = P sum_k alpha_k
    pull_k / |c|."""
    geo = _corner_geometry(x)
    n = geo["normal"]
    weight = np.sum(pull * n[:, None, :], axis=-1)[..., None]  # pull_k . n, (m, 3, 1)
    d_next = weight * geo["d_next"]  # on node k + 1
    d_prev = weight * geo["d_prev"]  # on node k + 2
    force = -(d_next + d_prev) + np.roll(d_next, 1, axis=1) + np.roll(d_prev, 2, axis=1)
    g = np.sum(geo["angle"][..., None] * pull, axis=1)
    g = (g - np.sum(g * n, axis=1)[:, None] * n) / geo["size"][:, None]
    return force + _cross_product_pull(x, g)


def _share_tangent(x: np.ndarray, side_moment: np.ndarray) -> np.ndarray:
    """d/dx of each element's own share of the bending forces, sum_s mu_s D[s, k] n (Eq. 37),
    with the side moments mu_s (m, 3) held: (m, 3, 3, 3, 3), N/mm. The formulas of
    ``_side_geometry`` differentiated in the 9 unit directions of the corners, all cells at
    once (directions on axis 1)."""
    sides = _side_geometry(x)
    n, area2 = sides["normal"][:, None], sides["double_area"][:, None, None]
    length, outward = sides["length"][:, None, :, None], sides["outward"][:, None]
    directions = np.eye(9).reshape(9, 3, 3)  # (direction, corner, component)
    a, b = x[:, None, 1] - x[:, None, 0], x[:, None, 2] - x[:, None, 0]
    da, db = directions[:, 1] - directions[:, 0], directions[:, 2] - directions[:, 0]
    dc = cross(da, b) + cross(a, db)  # (m, 9, 3)
    d_area2 = np.sum(n * dc, axis=-1)[..., None]
    dn = (dc - d_area2 * n) / area2
    nn, dnn = n[:, :, None], dn[:, :, None]
    side = (x[:, _Q] - x[:, _P])[:, None]  # (m, 1, s, 3)
    d_side = directions[:, _Q] - directions[:, _P]  # (9, s, 3)
    d_length = np.sum(side * d_side, axis=-1)[..., None] / length
    d_outward = (cross(d_side, nn) + cross(side, dnn)) / length - outward * d_length / length
    grad_n = cross(nn, side) / area2[..., None]  # grad N_k, (m, 1, k, 3)
    d_grad_n = (cross(dnn, side) + cross(nn, d_side)) / area2[..., None] - grad_n * (
        d_area2[..., None] / area2[..., None]
    )
    swap = (0, 1, 3, 2)
    d_gradient = -(
        np.matmul(d_outward, grad_n.transpose(swap)) + np.matmul(outward, d_grad_n.transpose(swap))
    )  # dD[s, k], (m, 9, s, k)
    w = np.matmul(side_moment[:, None, :], sides["gradient"])[:, 0][:, None, :, None]
    dw = np.matmul(side_moment[:, None, None, :], d_gradient)[:, :, 0][..., None]
    force = dw * nn + w * dnn  # (m, 9, k, 3)
    return force.reshape(len(x), 3, 3, 3, 3).transpose(0, 3, 4, 1, 2)


def _corner_normal_pull_tangent(x: np.ndarray, pull: np.ndarray) -> np.ndarray:
    """d(``_corner_normal_pull``(x, pull))/dx with ``pull`` (m, 3, 3) held: the stiffness
    (m, 3, 3, 3, 3) of the normal sums' second derivatives sum_k pull_k . d2(alpha_k n)/dx2,
    N (per unit of the sums). Its formulas differentiated in the 9 unit directions of the
    corners, all cells at once (directions on axis 1)."""
    geo = _corner_geometry(x)
    n, size, angle = geo["normal"][:, None], geo["size"][:, None, None], geo["angle"][:, None]
    directions = np.eye(9).reshape(9, 3, 3)  # (direction, corner, component)
    a, b = x[:, None, 1] - x[:, None, 0], x[:, None, 2] - x[:, None, 0]  # (m, 1, 3)
    da, db = directions[:, 1] - directions[:, 0], directions[:, 2] - directions[:, 0]
    dc = cross(da, b) + cross(a, db)  # (m, 9, 3)
    d_size = np.sum(n * dc, axis=-1)[..., None]
    dn = (dc - d_size * n) / size
    u = (x[:, [1, 2, 0]] - x)[:, None]  # (m, 1, corner, 3)
    w = (x[:, [2, 0, 1]] - x)[:, None]
    du = directions[:, [1, 2, 0]] - directions  # (9, corner, 3)
    dw = directions[:, [2, 0, 1]] - directions
    d_next, d_prev = geo["d_next"][:, None], geo["d_prev"][:, None]
    d_angle = np.sum(d_next * du + d_prev * dw, axis=-1)  # (m, 9, corner)
    nn, dnn = n[:, :, None], dn[:, :, None]
    u2 = np.sum(u * u, axis=-1)[..., None]
    w2 = np.sum(w * w, axis=-1)[..., None]
    # d_next = -(n x u) / |u|^2 and d_prev = -(w x n) / |w|^2, differentiated.
    dd_next = (
        -(cross(dnn, u) + cross(nn, du)) / u2
        - 2.0 * d_next * np.sum(u * du, axis=-1)[..., None] / u2
    )
    dd_prev = (
        -(cross(dw, nn) + cross(w, dnn)) / w2
        - 2.0 * d_prev * np.sum(w * dw, axis=-1)[..., None] / w2
    )
    held = pull[:, None]  # (m, 1, corner, 3)
    weight = np.sum(held * nn, axis=-1)[..., None]
    d_weight = np.sum(held * dnn, axis=-1)[..., None]
    next_ = d_weight * d_next + weight * dd_next  # on node k + 1
    prev = d_weight * d_prev + weight * dd_prev  # on node k + 2
    force = -(next_ + prev) + np.roll(next_, 1, axis=2) + np.roll(prev, 2, axis=2)
    g0 = np.sum(angle[..., None] * held, axis=2)  # (m, 1, 3)
    dg0 = np.sum(d_angle[..., None] * held, axis=2)  # (m, 9, 3)
    along = np.sum(g0 * n, axis=-1)[..., None]
    g = (g0 - along * n) / size
    dg = (
        dg0
        - (np.sum(dg0 * n, axis=-1)[..., None] + np.sum(g0 * dn, axis=-1)[..., None]) * n
        - along * dn
    ) / size - g * d_size / size
    d_along_a = cross(db, g) + cross(b, dg)
    d_along_b = cross(dg, a) + cross(g, da)
    force = force + np.stack([-(d_along_a + d_along_b), d_along_a, d_along_b], axis=2)
    return force.reshape(len(x), 3, 3, 3, 3).transpose(0, 3, 4, 1, 2)


def _shear_orientation(points, connectivity, xi_is_warp, warp) -> np.ndarray:
    """+1 where edges 0 -> 1 and 0 -> 2 of a cell point both along or both against the positive
    directions of their fibre families (warp, and weft = n x warp), else -1 (m,).

    The angle between the edges then equals the warp-weft angle or its supplement, and
    multiplying pi/2 - angle(g1, g2) by this sign gives the shear angle with one convention in
    every cell: positive when the warp-weft angle closes.
    """
    x = points[connectivity]
    edge1, edge2 = x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]
    normal = cross(edge1, edge2)
    weft = cross(normal, np.broadcast_to(warp, normal.shape))  # along n x warp (unnormalised)
    along_warp = np.where(xi_is_warp, np.sum(edge1 * warp, 1), np.sum(edge2 * warp, 1))
    along_weft = np.where(xi_is_warp, np.sum(edge2 * weft, 1), np.sum(edge1 * weft, 1))
    return np.sign(along_warp) * np.sign(along_weft)


def _shear_angle(g1: np.ndarray, g2: np.ndarray) -> np.ndarray:
    """gamma = pi/2 - angle(g1, g2) (Eq. 21), rad; > 0 when the warp-weft angle closes."""
    c = np.sum(g1 * g2, axis=-1) / (np.linalg.norm(g1, axis=-1) * np.linalg.norm(g2, axis=-1))
    return np.arcsin(np.clip(c, -1.0, 1.0))


def _neighbour_sides(neighbour: np.ndarray) -> np.ndarray:
    """For each (cell, side) with a neighbour, the side index of the shared edge in the
    neighbour (-1 on free sides)."""
    m = len(neighbour)
    nb = np.where(neighbour >= 0, neighbour, 0)
    back = neighbour[nb] == np.arange(m)[:, None, None]  # (m, 3 sides, 3 neighbour sides)
    side = np.argmax(back, axis=2)
    return np.where(neighbour >= 0, side, -1)


def _fibre_ordering(points, triangles, cell_ids, warp, tolerance_deg):
    """Rotate each triangle's local numbering (keeping it counter-clockwise) so that local
    node 0 is the corner where one edge runs along the warp and the other along the weft.

    The weft is the in-plane perpendicular of the warp projected on each triangle's plane.
    Returns the reordered (m, 3) connectivity and xi_is_warp (m,): True when edge 0 -> 1 is
    the warp edge (else it is the weft edge, and 0 -> 2 the warp).
    """
    x = points[triangles]
    normal = cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0])
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    warp_t = warp - (normal @ warp)[:, None] * normal
    size = np.linalg.norm(warp_t, axis=1)
    if np.any(size < 1e-6):
        bad = int(cell_ids[np.argmax(size < 1e-6)])
        raise ValueError(f"triangle {bad} is normal to the warp direction {warp}")
    warp_t /= size[:, None]
    weft_t = cross(normal, warp_t)
    cos_tol = np.cos(np.radians(tolerance_deg))

    corner = np.full(len(triangles), -1)
    xi_is_warp = np.zeros(len(triangles), dtype=bool)
    for k in (2, 1, 0):  # the loop is over the three local corners, not over cells
        a = x[:, (k + 1) % 3] - x[:, k]
        b = x[:, (k + 2) % 3] - x[:, k]
        a /= np.linalg.norm(a, axis=1)[:, None]
        b /= np.linalg.norm(b, axis=1)[:, None]
        along = lambda u, d: np.abs(np.sum(u * d, axis=1)) >= cos_tol  # noqa: E731
        warp_first = along(a, warp_t) & along(b, weft_t)
        weft_first = along(a, weft_t) & along(b, warp_t)
        match = warp_first | weft_first
        corner = np.where(match, k, corner)
        xi_is_warp = np.where(match, warp_first, xi_is_warp)
    if np.any(corner < 0):
        bad = int(np.argmax(corner < 0))
        raise ValueError(
            f"triangle {int(cell_ids[bad])} (nodes {triangles[bad].tolist()}) has no corner "
            f"with one edge along the warp {warp.round(6).tolist()} and one along the weft "
            f"(within {tolerance_deg} deg): FibrousShell needs a fibre-aligned mesh (Bai "
            "Eq. 9), e.g. Mesh.rectangle or Mesh.quadrilateral split into right triangles"
        )
    order = (corner[:, None] + np.arange(3)[None, :]) % 3
    return np.take_along_axis(triangles, order, axis=1), xi_is_warp
