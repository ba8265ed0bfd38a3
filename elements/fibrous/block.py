"""FibrousShellBlock: the FibrousShell bound to the triangles of a mesh. It holds the tables
fixed at bind (fibre frame, neighbours, reference geometry, side tables and wall normals of
the supports) and answers the element protocol by the functions of the package: geometry.py
(normals, thickness along the directors), membrane.py (tension and shear, Eq. 19, 21,
24-33), bending.py (rotation-free bending, Eq. 20, 34-37), tangent.py (the stiffness),
supports.py (the clamps), and kernels.py (the same forces and energy by compiled loops).
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING

import numpy as np

from elements import kernels as node_kernels
from elements.base import ElementBlock
from elements.fibre_directions import block_fibre_directions, fibre_components
from elements.fibrous import (
    bending,
    geometry,
    kernels,
    level_jacobian,
    membrane,
    supports,
    symmetry,
)
from elements.fibrous import tangent as stiffness
from elements.fibrous import tangent_pieces as pieces
from elements.fibrous.compression_floor import real_compression
from elements.fibrous.fibres import by_family, fibre_ordering, shear_orientation
from elements.fibrous.fold_branch import branch_view, initial_branch, updated_branch
from elements.fibrous.packed_laws import pack_laws
from elements.fibrous.stable_steps import cell_steps
from elements.fibrous.tangent import CornerPairs
from elements.fibrous.twist_check import warn_if_twist_bends
from elements.shell_geometry import GUARD, guarded_thickness, lumped_mass
from femcore.assembly import Scatter, TangentPart
from femcore.field_names import LEVELS, name_components
from femcore.mesh import Mesh
from femcore.state import State
from femcore.topology import build_topology
from femcore.workspace import Workspace
from materials.tension_peak import softening_strains

if TYPE_CHECKING:
    from elements.fibrous.element import FibrousShell

__all__ = ["FibrousShellBlock"]

# The components ParaView names (README "Output fields"): sections forces in the fibre frame
# (1 = warp, 2 = weft), the per-level fields from the bottom level to the top.
for _name in ("membrane_force", "bending_moment"):
    name_components(_name, ("11", "22", "12"))
for _name in ("warp_strain", "weft_strain", "shear_angle_deg"):
    name_components(_name, LEVELS)

# Bending time-step coefficient of docs/theory.md §6.2 (A3): dt_b = 0.35 L^2 sqrt(rho_A / B), the
# worst case (square cells) of the exact eigenvalues of the rotation-free bending stiffness.
_BENDING_DT_COEFFICIENT = 0.35

#: Cells whose reference geometry is formed at once at bind (a few MB of temporaries).
REFERENCE_SLICE = 8192


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
    reference_points : (n, 3) mm, the mesh's points at bind (the reference configuration).

    Attributes (fixed at bind, completed by ``apply_supports``; docs/theory.md §4.5)
    -------------------------------------------------------------------------------
    clamped_side : (m, 3) bool, sides that bend against a wall: of the reference plane, or
        on a symmetry plane the wall through the side perpendicular to it.
    mirror_normal : (m, 3, 3), on a symmetry side (a clamped side whose nodes are not both
        held) the plane's normal p signed so that (p x t) / |p x t| is its wall, t the side;
        0 on the others (symmetry.py).
    symmetry_normal : (m, 3, 3), the same on every side of the ``symmetric`` option.
    plane_node_ids, plane_keep : (p,) int and (p, 3), the nodes of those sides and the
        factors (0 along their planes' normals, else 1) that project their normal sums on
        the planes (symmetry.py ``plane_projection``).
    reference_directors : (n, 3), the directors at bind.
    interior_side : (m, 3) bool, sides that couple the cell with its neighbour.
    held_cell : (m,) bool, cells whose three nodes are held: no bending.
    across_cell, across_side : (m, 3) int, the neighbour and its side where ``interior_side``,
        0 elsewhere (gather indices, masked by ``interior_side``).
    shared_sides, shared_sign : (e, 2) int32 and (e,) int8, each interior side once (its
        cell and side), for the fold angles evaluated once per side (supports.py
        ``shared_sides``).
    requested_clamp : (n,) bool, the nodes of the ``clamped`` option; ``clamped_option`` the
        option as given, ``clamped_sets`` its sets' node ids (a list of (k,) int) and
        ``clamp_mesh`` the mesh (None without the option), for the advice of a loose clamp.
    wall_nodes : (n,) bool, the held nodes whose nodal normal is the wall's (the reference
        one); wall_node_ids their ids and wall_sums (len(wall_node_ids), 3) their normal sums.
    reference_sums : (n, 3), the normal sums of the reference configuration (set by
        ``apply_supports``).
    reference_fold, reference_coefficients : (m, 3) and (m, 2, 3), the fold angles and
        curvature coefficients of the reference configuration (bending.py ``geometry``).
    """

    dofs = ("ux", "uy", "uz", "alpha", "beta")
    cell_type = "triangle"

    # Set by supports.set_sides and supports.apply_supports.
    clamped_side: np.ndarray
    mirror_normal: np.ndarray
    interior_side: np.ndarray
    held_cell: np.ndarray
    across_cell: np.ndarray
    across_side: np.ndarray
    shared_sides: np.ndarray
    shared_sign: np.ndarray
    reference_sums: np.ndarray

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
        # The corners on a common node (level_jacobian.sums_pairs), made at the first call.
        self._sums_pairs: tuple[np.ndarray, ...] | None = None
        self.reference_curvature_coefficients = shell.bending_geometry == "reference"
        self.n_nodes = mesh.n_nodes
        self.cell_ids = np.asarray(cell_ids, dtype=np.int64)
        self.zeta, self.weights = shell.zeta, shell.weights
        self.connectivity, self.xi_is_warp = fibre_ordering(
            mesh.points,
            mesh.triangles[self.cell_ids],
            self.cell_ids,
            shell.warp,
            shell.fibre_angle_tolerance,
            compiled=self.compiled,
        )
        self.scatter = Scatter(self.connectivity, mesh.n_nodes)
        self.node_corners = node_kernels.NodeCorners(self.connectivity, mesh.n_nodes)
        self.node_in_block = np.zeros(mesh.n_nodes, dtype=bool)  # (n,): a corner of a cell here
        self.node_in_block[self.connectivity] = True
        self._pairs: CornerPairs | None = None  # the tangent's sparse pattern
        # The bending patch's nodes, slots and fold with the side tables they were made of
        # (bending.py ``_whole_patch``), made at the first tangent.
        self.bending_patch: tuple | None = None
        # the force passes' work arrays (per cell and per node), kept between calls
        # (femcore/workspace.py)
        self._workspace = Workspace()
        self.shear_sign = shear_orientation(
            mesh.points, self.connectivity, self.xi_is_warp, shell.warp, compiled=self.compiled
        )
        # the warp and weft on the reference edges, for the output's fibre directions
        self.fibre_components = fibre_components(mesh.points, self.connectivity, shell.warp)

        topology = build_topology(self.connectivity)
        self.neighbour = np.asarray(topology.neighbour)
        self.neighbour_side = supports.neighbour_sides(self.neighbour)
        # Bai's curvature estimate reads a twist as fibre curvature on meshes not cut
        # one way (docs/theory.md §4.2): say so before a two-way bending converges wrong.
        self.twist_reading = warn_if_twist_bends(mesh.points, self.connectivity, self.neighbour)
        # Clamps (docs/theory.md §4.5): the requested ones now, with the model's supports added
        # by apply_supports, which also recomputes the reference folds from these points.
        self.requested_clamp = supports.requested_clamp(mesh, self.connectivity, shell.clamped)
        self.clamped_option = shell.clamped  # as given: named in the refusal of a loose clamp
        # its sets (node ids, each) and the mesh (its sets and points), for the advice of
        # that refusal: the [[fix]] tables a case file takes (supports._fix_tables)
        self.clamped_sets = supports.node_sets(mesh, shell.clamped, "clamped")
        self.clamp_mesh = mesh if shell.clamped is not None else None
        self.reference_points = np.asarray(mesh.points, dtype=float)
        # Nodes whose normal is that of the wall they are held against (apply_supports).
        self.wall_nodes = np.zeros(mesh.n_nodes, dtype=bool)
        self.wall_node_ids = np.zeros(0, dtype=np.int64)
        self.wall_sums = np.zeros((0, 3))
        # Symmetry sides (docs/theory.md §4.5): their plane normals from the reference
        # normals, below.
        self.symmetry_normal = np.zeros(self.connectivity.shape + (3,))
        self.plane_node_ids = np.zeros(0, dtype=np.int64)
        self.plane_keep = np.zeros((0, 3))
        supports.set_sides(self, self.requested_clamp)

        # Reference geometry: areas, fibre lengths and shear angles at each level, fold angles.
        # (a writable copy of the read-only points: the compiled loops then see the states'
        # array type and compile once, supports.apply_supports)
        x0 = np.array(mesh.points, dtype=float)
        v0 = np.asarray(directors, dtype=float)
        self.reference_directors = v0
        corners = x0[self.connectivity]
        normal = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
        self.symmetry_normal = symmetry.symmetry_sides(
            mesh,
            self.connectivity,
            self.neighbour,
            normal / np.linalg.norm(normal, axis=1, keepdims=True),
            shell.symmetric,
        )
        # The normal sums at the planes' nodes are the mirrored whole's (symmetry.py), the
        # reference ones too.
        self.plane_node_ids, self.plane_keep = symmetry.plane_projection(
            self.connectivity, self.symmetry_normal, mesh.n_nodes
        )
        supports.set_sides(self, self.requested_clamp)
        self._reference_geometry(x0, v0)
        self.reference_fold = np.zeros((len(self.cell_ids), 3))
        bend0 = bending.geometry(self, x0)
        self.reference_fold = bend0["fold"]
        self.reference_coefficients = bend0["coefficients"]

        # The laws as the compiled loops read them: warp and weft tension, shear, warp and
        # weft bending (elements/fibrous/packed_laws.py).
        self.packed_laws = pack_laws(
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

    def _reference_geometry(self, x0: np.ndarray, v0: np.ndarray) -> None:
        """``reference_area`` (m,), ``reference_normal`` (m, 3), ``reference_length1`` and
        ``2`` (m, L) (membrane.py ``fibre_lengths``) and ``reference_shear`` (m, L) from the
        reference points and directors (n, 3), ``REFERENCE_SLICE`` cells at a time: every
        quantity is a cell's own (the nodal normal sums made once beforehand), so the slices
        give the bits of the whole, without its (m, 3, L, 3) level temporaries (0.6 kB a
        triangle at the bind's peak)."""
        m, levels = len(self.connectivity), len(self.zeta)
        self.reference_area = np.empty(m)
        self.reference_normal = np.empty((m, 3))
        self.reference_length1 = np.empty((m, levels))
        self.reference_length2 = np.empty((m, levels))
        self.reference_shear = np.empty((m, levels))
        sums = geometry.normal_sums(self, x0) if self.nodal_normals else None
        for start in range(0, m, REFERENCE_SLICE):
            cells = slice(start, start + REFERENCE_SLICE)
            corners = self.connectivity[cells]
            ref = geometry.cell_geometry(
                self, x0[corners], v0[corners], True, None if sums is None else sums[corners]
            )
            self.reference_area[cells] = 0.5 * ref["double_area"]
            self.reference_normal[cells] = ref["normal"]
            self.reference_length1[cells], self.reference_length2[cells] = membrane.fibre_lengths(
                self, ref
            )
            self.reference_shear[cells] = self.shear_sign[cells, None] * membrane.shear_angle(
                ref["g1"], ref["g2"]
            )

    def apply_supports(self, held: np.ndarray, constrained: np.ndarray | None = None) -> None:
        """Clamp the rotation-free bending where the model holds the nodes (docs/theory.md
        §4.5): every node held (translations and directors fixed or prescribed) is a clamped
        node, as are those of the ``clamped`` option, which must be held (supports.py).
        ``constrained`` (n, 5) bool, the DOFs fixed or prescribed, is checked against the
        symmetry planes (symmetry.py).

        Raises ValueError when a node of a requested clamped edge is not held, or a node of
        a symmetry plane is free to leave it.
        """
        supports.apply_supports(self, held, constrained)

    def corner_pairs(self) -> CornerPairs:
        """The node-pair pattern of the sparse membrane tangent (built at its first use)."""
        if self._pairs is None:
            self._pairs = CornerPairs(self.connectivity, self.n_nodes)
        return self._pairs

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
        geo = geometry.geometry(self, positions, directors, layers=False)
        return {key: geo[key] for key in ("cosine", "thickness", "guarded")}

    def _nodal_cosine(self, state: State) -> np.ndarray:
        """V . N at each node (n,) from the compiled normal sums (nodal normals); meaningless,
        but finite, at nodes outside the block."""
        sums = geometry.normal_sums(self, state.positions)
        length = np.where(self.node_in_block, np.linalg.norm(sums, axis=1), 1.0)
        return np.sum(state.directors * sums, axis=1) / length

    def nodal_thickness(self, state: State) -> np.ndarray:
        """Thickness along the director at the nodes (n,), mm: h_m from the nodal normal, or
        with element normals the area-weighted mean of the per-element h_m (docs/theory.md
        §1.4); 0 at nodes outside the block."""
        if self.compiled and self.nodal_normals:
            # h / max(V . N, guard) at each node of the block from the compiled normal sums
            # (the explicit solver refreshes the rotary inertia with it)
            cosine = self._nodal_cosine(state)
            h_m, _ = guarded_thickness(self.fabric.thickness, cosine)
            return np.where(self.node_in_block, h_m, 0.0)
        geo = geometry.geometry(self, state.positions, state.directors, layers=False)
        return geometry.node_thickness(self, geo)

    def director_tilt(self, state: State) -> np.ndarray:
        """Angle between the director and the nodal normal of the block (n,), rad, in [0, pi];
        0 at nodes outside the block. A stack of freely slipping layers bent by theta from a
        clamp tilts by atan(theta) (docs/theory.md §1.7)."""
        normals = geometry.normal_sums(self, state.positions)
        length = np.linalg.norm(normals, axis=1)
        inside = length > 0
        cosine = np.sum(state.directors * normals, axis=1) / np.where(inside, length, 1.0)
        return np.where(inside, np.arccos(np.clip(cosine, -1.0, 1.0)), 0.0)

    def guarded_nodes(self, state: State) -> np.ndarray:
        """Ids of the nodes where V.n fell below the guard of h_m = h / max(V.n, 0.2) in some
        element (the thickness along the director is capped there at 5 h)."""
        geo = geometry.geometry(self, state.positions, state.directors, layers=False)
        return np.unique(self.connectivity[geo["guarded"]])

    # ------------------------------------------------------------------ protocol
    has_fibre_strains = True

    def fibre_strains(self, state: State) -> np.ndarray:
        """(m, 3 L) each level's fibre strains ln(lambda) along the cell's edges 0 -> 1 and 0 ->
        2 (the warp and the weft where ``xi_is_warp``, the weft and the warp elsewhere) and its
        shear angle (rad), per cell: the measures the static solver's level projection keeps
        at their first order (solvers.newton_levels)."""
        if self.compiled:
            strain = kernels.strains(self, state.positions, state.directors)
        else:
            strain = membrane.strains(
                self, geometry.geometry(self, state.positions, state.directors)
            )
        return np.concatenate([strain["eps1"], strain["eps2"], strain["gamma"]], axis=1)

    def fibre_strain_range(self) -> tuple[np.ndarray, np.ndarray]:
        """(lower (m, 3 L), upper (m, 3 L)) per cell, the strains of ``fibre_strains``'
        columns past which the fibre's tension per unit reference width T / lambda falls (its
        law's ``materials.tension_peak.softening_strains``: eps = 1 for a linear law, never
        for a stiffening one); the shear angles unbounded (docs/theory.md §6.4d). Per cell:
        the first L columns are along the cell's edge 0 -> 1, the warp where ``xi_is_warp``
        and the weft elsewhere, so each takes its own family's law."""
        levels, cells = len(self.weights), len(self.connectivity)
        warp = softening_strains(self.fabric.tension)
        weft = softening_strains(self.fabric.tension_weft)
        bounds = []
        for side in (0, 1):  # lower, upper
            along_warp = np.full((cells, 1), warp[side])
            along_weft = np.full((cells, 1), weft[side])
            # (the swap by xi_is_warp is its own inverse: warp/weft -> edge 0-1/edge 0-2)
            along_xi, along_eta = by_family(self.xi_is_warp, along_warp, along_weft)
            bound = np.full((cells, 3 * levels), np.inf if side else -np.inf)
            bound[:, :levels] = along_xi
            bound[:, levels : 2 * levels] = along_eta
            bounds.append(bound)
        return bounds[0], bounds[1]

    def fibre_strain_gradient(self, state: State) -> tuple:
        """The derivatives of ``fibre_strains`` at each cell's corners (direct, turns, and
        with nodal normals the pull on the normal sums and the cells' shares' derivatives)
        and the pairs of corners on a common node they are combined over
        (level_jacobian.py ``level_strain_gradient``, ``sums_pairs``; None with element
        normals)."""
        pieces = level_jacobian.level_strain_gradient(self, state.positions, state.directors)
        if self._sums_pairs is None and self.nodal_normals:
            self._sums_pairs = level_jacobian.sums_pairs(self)
        return pieces, self._sums_pairs

    def initial_history(self):
        """The folds of the reference state and no turns (fold_branch.py): each interior
        side's fold is followed through a flat fold."""
        return initial_branch(self)

    def update_history(self, state: State, history):
        """The folds at ``state`` with the turns of the sides that crossed pi (fold_branch.py
        ``updated_branch``)."""
        return None if history is None else updated_branch(self, state.positions, history)

    def internal_force(self, state: State, history=None):
        block = branch_view(self, history)  # the folds past a flat fold (fold_branch.py)
        if self.compiled:  # the passes of elements/fibrous/kernels.py
            return kernels.internal_force(block, state.positions, state.directors)
        geo = geometry.geometry(self, state.positions, state.directors)
        force, moment = membrane.forces(self, geo, membrane.strains(self, geo))
        force = force + bending.forces(block, state.positions, geo)
        return self.scatter.vectors(force), self.scatter.vectors(moment)

    def support_moments(self, state: State, history=None):
        """The clamp walls' moments on the nodes of their sides (n, 3), N mm (supports.py
        ``wall_moments``, docs/theory.md §4.5); None without a clamped side."""
        if not self.clamped_side.any():
            return None
        block = branch_view(self, history)
        return self.scatter.vectors(supports.wall_moments(block, state.positions))

    def internal_force_and_energy(self, state: State, history=None):
        """``internal_force`` and ``strain_energy`` at ``state`` in one call: (force (n, 3) N,
        moment (n, 3) N mm, energy N mm). The compiled loops meet the energy on their way to
        the forces and return both from one pass over the cells (kernels.py), the energy the
        same to the last bit as ``strain_energy``; the numpy path makes the two calls."""
        if self.compiled:
            force, moment, parts = kernels.internal_force_and_energy(
                branch_view(self, history), state.positions, state.directors
            )
            return force, moment, float(sum(parts.values()))
        force, moment = self.internal_force(state, history)
        return force, moment, self.strain_energy(state, history)

    def internal_force_parts(self, state: State) -> dict:
        """{"tension" | "shear": (forces (n,3), moments (n,3)), "bending": (forces, zeros)}:
        the three virtual-work terms separately (diagnostics and tests)."""
        geo = geometry.geometry(self, state.positions, state.directors)
        strain = membrane.strains(self, geo)
        parts = {}
        for name, flags in (("tension", (True, False)), ("shear", (False, True))):
            f, m = membrane.forces(self, geo, strain, *flags)
            parts[name] = (self.scatter.vectors(f), self.scatter.vectors(m))
        parts["bending"] = (
            self.scatter.vectors(bending.forces(self, state.positions)),
            np.zeros((self.n_nodes, 3)),
        )
        return parts

    def strain_energy_parts(self, state: State, history=None) -> dict:
        """Strain energy (N mm) of each term: {"tension", "shear", "bending"}; ``history``
        the folds' turns (fold_branch.py; None: the principal branch)."""
        block = branch_view(self, history)
        if self.compiled:
            return kernels.strain_energy_parts(block, state.positions, state.directors)
        geo = geometry.geometry(self, state.positions, state.directors)
        tension, shear = membrane.energies(self, membrane.strains(self, geo))
        bend = bending.energy(block, state.positions)
        return {"tension": float(tension), "shear": float(shear), "bending": float(bend)}

    def strain_energy(self, state: State, history=None) -> float:
        return float(sum(self.strain_energy_parts(state, history).values()))

    # The static solver may ask for the compression-free tangent of its iterates far from
    # equilibrium (femcore.compiled_tangent ``tangent_parts``, docs/theory.md §6.5).
    compression_free_tangent = True

    def tangent(
        self,
        state: State,
        history=None,
        compression_free: bool = False,
        real: State | None = None,
    ) -> list[TangentPart]:
        """Stiffness of tension + shear and of bending (tangent.py ``tangent``): with nodal
        normals a sparse matrix and the bending patches, closed form; with element normals
        each cell's tension + shear by central differences of its loads.
        ``compression_free``: the tension's stress terms with the fibres' strains raised to
        at least zero, or with ``real`` (a state whose compression is real: the last
        converged one) to at least their compression there (tangent.py ``membrane_hessian``,
        compression_floor.py)."""
        floors = None
        if compression_free and real is not None:
            floors = real_compression(self, real)
        return stiffness.tangent(branch_view(self, history), state, compression_free, floors)

    def tangent_compression_free(
        self, state: State, history=None, real: State | None = None
    ) -> list[TangentPart]:
        """``tangent`` with ``compression_free`` (femcore.element)."""
        return self.tangent(state, history, compression_free=True, real=real)

    def tangent_pieces(self, state: State, history=None) -> Iterator[TangentPart]:
        """``tangent`` a slice of cells at a time (tangent_pieces.py): with nodal normals the
        whole tangent is 30 kB a triangle at its peak; a slice's pieces are made, given and
        dropped."""
        return pieces.tangent_pieces(branch_view(self, history), state)

    def rotary_lever(self, state: State) -> np.ndarray:
        """How far (n,), mm, the outer fibre levels move per radian of director rotation,
        times 2: h_m / max(V . n, guard) = h / max(V . n, guard)^2 with the nodal normal (or,
        with element normals, its area-weighted mean over the node's cells); 0 at nodes
        outside the block.

        The levels sit at (zeta / 2) h_m V, and h_m = h / (V . n) turns with the director:
        d(h_m V)/dpsi has the length h_m / cos(tilt), not h_m (docs/theory.md §6.2 A2). Past
        the guard h_m no longer follows the tilt, and the value is kept at that of the guard
        (continuous, and above the lever h_m there)."""
        if self.compiled and self.nodal_normals:
            cosine = self._nodal_cosine(state)
            h_m, _ = guarded_thickness(self.fabric.thickness, cosine)
            return np.where(self.node_in_block, h_m / np.maximum(cosine, GUARD), 0.0)
        geo = geometry.geometry(self, state.positions, state.directors, layers=False)
        per_corner = geo["thickness"] / np.maximum(geo["cosine"], GUARD)
        return geometry.node_thickness(self, {**geo, "thickness": per_corner})

    def lumped_mass(self, state: State, density_scale=None):
        """Nodal mass (n,), t, and rotary inertia (n,), t mm^2: Bai Eq. 38-39 with the lever
        of ``rotary_lever`` in place of h_m, I = m (h_m / cos(tilt))^2 / 4, so that a director
        mode is no faster than the tension mode of its cell at any tilt (A2; with h_m alone,
        directors tilted 69 deg had an exact critical step 0.76 of the cells' bound, and a
        formed blank's corner director, flapping up to that tilt, went unstable)."""
        density: float | np.ndarray = self.fabric.areal_density
        if density_scale is not None:
            density = density * np.asarray(density_scale, dtype=float)
        return lumped_mass(
            density,
            self.reference_area,
            self.connectivity,
            self.rotary_lever(state),
            self.n_nodes,
        )

    def cell_stable_dt(self, state: State) -> np.ndarray:
        """Critical step per cell from docs/theory.md §6.2, the three bounds combined as
        omega^2 = omega_tension^2 + omega_shear^2 + omega_bending^2 (a safe upper bound):

        * tension (A1): omega^2 = (2 + |cos phi|) C A0 / (L_min^2 m), m = rho_A A0 / 3, phi
          the warp-weft angle (two fibres in line at node 0 give the 3-mass chain value);
        * shear (A4): omega^2 = 2 K A0 (1/L1^2 + 1/L2^2) / m;
        * bending (A3): dt = 0.35 L_min^2 sqrt(rho_A / B).
        Director modes do not govern with I = m (h_m / cos(tilt))^2 / 4 (A2, ``lumped_mass``)
        as long as I follows the geometry (the solvers refresh the rotary inertia with the
        step); with I = m h_m^2 / 4 they did once the directors tilted past about 60 deg
        (docs/theory.md §6.2).

        One compiled pass over the cells (stable_steps.py) with the compiled kernels, the
        numpy formulas of ``cell_stable_dt_numpy`` to the last bit.
        """
        if self.compiled:
            out = np.empty(len(self.connectivity))
            cell_steps(
                self.connectivity, np.ascontiguousarray(state.positions, dtype=float),
                self.reference_area, float(self.fabric.areal_density),
                float(self.max_tension_stiffness), float(self.max_shear_stiffness),
                _BENDING_DT_COEFFICIENT,
                float(np.sqrt(self.fabric.areal_density / self.max_bending_stiffness)),
                self.nodal_normals, out,
            )  # fmt: skip
            return out
        return self.cell_stable_dt_numpy(state)

    def cell_stable_dt_numpy(self, state: State) -> np.ndarray:
        """``cell_stable_dt`` in numpy passes over the cells (the reference of the compiled
        pass; the numpy kernels' path)."""
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
        if self.compiled:  # the strains alone, not the level vectors (m, L, 3) and corners
            strain = kernels.strains(self, state.positions, state.directors)
        else:
            strain = membrane.strains(
                self, geometry.geometry(self, state.positions, state.directors)
            )
        warp, weft = by_family(self.xi_is_warp, strain["eps1"], strain["eps2"])
        block = branch_view(self, history)
        chi, _ = bending.curvatures(block, bending.geometry(self, state.positions))
        moments = bending.moments(self, chi)
        chi_warp, chi_weft = by_family(self.xi_is_warp, chi[:, 0], chi[:, 1])
        m_warp, m_weft = by_family(self.xi_is_warp, moments[:, 0], moments[:, 1])
        # The fields both shells write (README "Output fields"): section forces per unit
        # width in the fibre frame (1 = warp), averaged over the levels with their weights.
        t_warp = self.fabric.tension.value(warp) @ self.weights
        t_weft = self.fabric.tension_weft.value(weft) @ self.weights
        shear = self.fabric.shear.value(strain["gamma"]) @ self.weights
        return {
            "warp_strain": warp,  # (m, L), log strain, levels bottom -> top
            "weft_strain": weft,
            "shear_angle_deg": np.degrees(strain["gamma"]),  # (m, L)
            "warp_curvature": chi_warp,  # 1/mm
            "weft_curvature": chi_weft,
            "warp_moment": m_warp,  # N (N mm per mm)
            "weft_moment": m_weft,
            "membrane_force": np.column_stack([t_warp, t_weft, shear]),  # N/mm
            # no twisting moment in the fibrous shell: M12 = 0
            "bending_moment": np.column_stack([m_warp, m_weft, np.zeros_like(m_warp)]),
            # the deformed fibres (unit, global axes): what "11" and "22" are taken along
            **block_fibre_directions(self, state),
        }

    def node_fields(self, state: State, history=None) -> dict[str, np.ndarray]:
        if self.compiled and self.nodal_normals:  # from the compiled normal sums
            h_m, at_guard = guarded_thickness(self.fabric.thickness, self._nodal_cosine(state))
            thickness = np.where(self.node_in_block, h_m, 0.0)
            guarded = np.where(self.node_in_block & at_guard, 1.0, 0.0)
        else:
            geo = geometry.geometry(self, state.positions, state.directors, layers=False)
            guarded = np.zeros(self.n_nodes)
            guarded[self.connectivity[geo["guarded"]]] = 1.0
            thickness = geometry.node_thickness(self, geo)
        return {
            "thickness": thickness,
            "thickness_guarded": guarded,
            "director_tilt_deg": np.degrees(self.director_tilt(state)),  # from the nodal normal
        }

    def total_mass(self) -> float:
        """Physical mass of the block (t)."""
        return float(self.fabric.areal_density * self.reference_area.sum())
