"""The Mindlin triangle with a fabric section (docs/theory.md §5.7): ``MindlinShell(fabric)``.

Same kinematics as the elastic MindlinShellBlock (positions and directors, MITC3 transverse
shear), but the section is the fabric itself, by stress resultants from its own laws
(elements/fabric_section.py): fibre tension along warp and weft, the in-plane shear law, the
bending laws M(chi) per direction as given (tables, bilinear, polynomials), a stated twisting
and transverse shear stiffness, the mass of the areal density. So a comparison with the
fibrous shell on the same Fabric changes the kinematics alone: normals that stay normal (up to
transverse shear) against directors that slip.

The strains are measured at three levels zeta = -1, 0, 1 through the thickness (not
integration points): the mid-surface level gives the membrane and tying measures, half the
difference of the outer ones the bending strains (exact: the level measures are quadratic in
zeta). The forces are sigma . B^psi and the tangent B^T H B plus the geometric and spin terms
of the elastic block (docs/theory.md §5.5), with sigma and H the exact gradient and Hessian of
the section energy; the section response is one compiled loop over the cells
(elements/fabric_section_kernels.py), the section measures, the forces and the tangent three
more (elements/mindlin_fabric_measures.py, mindlin_fabric_loads.py and
mindlin_fabric_tangent.py; ``section_measures``, ``numpy_cell_loads`` and
``numpy_cell_tangent`` their numpy references; the outputs keep ``section_measures``).
"""

from __future__ import annotations

import dataclasses
from typing import TYPE_CHECKING, cast

import numpy as np

from elements.base import CellTangent
from elements.fabric_section import FabricSection, fibre_rows, response
from elements.fibre_directions import block_fibre_directions, fibre_components
from elements.mindlin import _IN_PLANE, MindlinShellBlock
from elements.mindlin_fabric_loads import fabric_cell_loads
from elements.mindlin_fabric_measures import fabric_section_measures
from elements.mindlin_fabric_tangent import AVAILABLE, fabric_tangent_blocks
from elements.mindlin_tables import _TYING_N
from elements.rotary_scaling import scaled_rotary_inertia
from femcore.rotation import cross
from femcore.state import State
from materials.fabric import Fabric

if TYPE_CHECKING:
    from elements.mindlin import MindlinShell

__all__ = [
    "MindlinFabricBlock", "NoDefaultStiffness", "default_transverse_shear", "default_twisting",
]  # fmt: skip

# The shear correction of a homogeneous section, as ElasticShell uses it.
_SHEAR_FACTOR = 5.0 / 6.0
# Section measures y (10) from the level measures e (Z = 3 levels: zeta -1, 0, 1; 7 each).
_LEVELS = np.zeros((10, 3, 7))
_LEVELS[0:3, 1, 0:3] = np.eye(3)  # membrane: the mid-surface level
_LEVELS[3:6, 2, 0:3] = 0.5 * np.eye(3)  # bending: (e(+1) - e(-1)) / 2
_LEVELS[3:6, 0, 0:3] = -0.5 * np.eye(3)
_LEVELS[6:10, 1, 3:7] = np.eye(4)  # transverse shear: tying changes at the mid-surface
_PROJECTION = _LEVELS.reshape(10, 21)


class NoDefaultStiffness(ValueError):
    """The fabric's bending laws have a toe (zero initial slope B0): the defaults of the
    transverse shear and twisting stiffness, both from B0, would be 0; the caller gives both
    (fibreshell words where: a case file's part options, compare's options)."""


def _initial_slope(law) -> float:
    return float(np.asarray(law.slope(np.array(0.0))))


def _bending_slope(fabric, what: str, unit: str) -> float:
    """B0, the largest initial slope of the fabric's bending laws, N mm; a ValueError naming
    ``what`` when it is 0 (a law with a toe): a default of 0 would be a mechanism."""
    b0 = max(_initial_slope(fabric.bending), _initial_slope(fabric.bending_weft))
    if not b0 > 0.0:
        raise NoDefaultStiffness(
            f"MindlinShell(fabric): the fabric's bending laws have zero slope at zero curvature "
            f"(B0 = {b0:g} N mm: a toe), so the default {what} from B0 would be 0, a "
            f"mechanism; give transverse_shear (N/mm) and twisting (N mm) explicitly (the "
            f"defaults' rule 5 B / h^2 and B / 2 with B the law's slope past the toe, "
            f"docs/theory.md §5.7); {what} is in {unit}"
        )
    return b0


def default_transverse_shear(fabric) -> float:
    """S = 5 B0 / h^2, N/mm: kappa G h of the homogeneous isotropic plate (nu = 0, G = E / 2,
    kappa = 5/6) whose plate stiffness E h^3 / 12 is the fabric's largest initial bending
    slope B0. A solid-section Mindlin shell (Abaqus S3 on a homogeneous section) has that ratio
    of shear to bending stiffness, so the normals tilt by transverse shear as little as its do,
    of order (h / L)^2; it is also ElasticShell.equivalent's default (G13 = E / 2).

    Raises
    ------
    ValueError
        B0 = 0 (bending laws with a toe): give the value explicitly."""
    b0 = _bending_slope(fabric, "transverse_shear", "N/mm")
    return 5.0 * b0 / fabric.thickness**2


def default_twisting(fabric) -> float:
    """D_t = B0 / 2, N mm per unit engineering twist: the twisting stiffness D (1 - nu) / 2 of
    the same homogeneous isotropic plate as ``default_transverse_shear`` (nu = 0, plate
    stiffness D = B0, the fabric's largest initial bending slope).

    A stack whose plies slide has next to no twisting stiffness (the fibrous shell has no
    twisting moment; N free plies twist as N (K / N) (h / N)^2 / 12 = K h^2 / (12 N^2)), but a
    Mindlin section needs one: the plate rule keeps it of the order of the bending, where the
    shear law through a solid section (K0 h^2 / 12) would make a stiff-shear stack such as
    paper (K0 = 1000 N/mm, h = 13 mm) 280 x stiffer in twist than in bending, a different
    material.

    Raises
    ------
    ValueError
        B0 = 0 (bending laws with a toe): give the value explicitly."""
    return 0.5 * _bending_slope(fabric, "twisting", "N mm")


class MindlinFabricBlock(MindlinShellBlock):
    """MindlinShell over mesh triangles ``cell_ids`` with the fabric section of the shell's
    Fabric (the shell's ``transverse_shear`` S, N/mm, and ``twisting`` D_t, N mm)."""

    # The analytic tangent's path and the forces' (elements/mindlin_fabric_tangent.py,
    # mindlin_fabric_loads.py): the compiled loops where numba is, else the numpy ones; a
    # block's own value overrides them (the tests'). Kept by the class, not the block, so
    # that a block pickled before they were chosen (a checkpoint's model) takes them on load.
    tangent_kernel = "compiled" if AVAILABLE else "numpy"
    loads_kernel = "compiled" if AVAILABLE else "numpy"

    def __init__(self, shell: MindlinShell, mesh, cell_ids, directors):
        self.fabric = cast(Fabric, shell.material)
        self.warp = shell.warp
        self.transverse_shear = shell.transverse_shear
        self.twisting = shell.twisting
        super().__init__(shell, mesh, cell_ids, directors)
        self.kernel = "numpy"
        # the warp and weft on the reference edges, for the output's fibre directions
        self.fibre_components = fibre_components(mesh.points, self.connectivity, self.warp)

    def fibre_edges(self) -> np.ndarray:
        """(k, 2) node pairs of the cells' edges that run along the warp or the weft in the
        reference (within 1e-6 rad): the nearly inextensible lines of the fabric (the static
        solver's fibre-length projection, solvers.newton_fibres)."""
        c = self.connectivity
        pairs = np.concatenate([c[:, [0, 1]], c[:, [1, 2]], c[:, [2, 0]]])
        x = self.reference_positions
        edge = x[pairs[:, 1]] - x[pairs[:, 0]]
        edge /= np.linalg.norm(edge, axis=1)[:, None]
        corner = x[c]
        normal = np.cross(corner[:, 1] - corner[:, 0], corner[:, 2] - corner[:, 0])
        normal = np.tile(normal / np.linalg.norm(normal, axis=1)[:, None], (3, 1))
        weft = np.cross(normal, self.warp)
        weft /= np.linalg.norm(weft, axis=1)[:, None]
        along = np.maximum(np.abs(edge @ self.warp), np.abs(np.sum(edge * weft, axis=1)))
        return pairs[along >= np.cos(1e-6)]

    def _thickness_levels(self, shell: MindlinShell) -> tuple[np.ndarray, np.ndarray]:
        """Three measuring levels, zeta = -1, 0, 1; the weights are unused (the section is
        integrated by its laws)."""
        return np.array([-1.0, 0.0, 1.0]), np.zeros(3)

    def _material_matrices(self, ref: dict, v0: np.ndarray) -> None:
        """The fabric section's tables (elements/fabric_section.py): the fibre rows from the
        reference mid-surface, and the transverse shear form Q = sum_p (A0 / 3) M_p^T S M_p,
        M_p the lamina shear strains (gamma_13, gamma_23) at in-plane point p from the tying
        changes (the MITC3 interpolation of docs/theory.md §5.3, then the covariant-to-lamina
        transformation of §5.2 at the mid-surface)."""
        d1, d2 = ref["g1"][:, 1], ref["g2"][:, 1]  # mid-surface level
        warp_rows, weft_rows, shear_rows = fibre_rows(d1, d2, self.warp)
        half = 0.5 * self.h
        r, s = _IN_PLANE[:, 0], _IN_PLANE[:, 1]
        shape = np.column_stack([1 - r - s, r, s])
        g3 = half * np.einsum("pk,mkj->mpj", shape, v0)  # (m, P, 3)
        m = len(d1)
        jacobian = np.stack(
            [np.broadcast_to(d1[:, None], g3.shape), np.broadcast_to(d2[:, None], g3.shape), g3],
            axis=-1,
        )
        if np.any(np.linalg.det(jacobian) <= 0):
            bad = int(self.cell_ids[np.argmax((np.linalg.det(jacobian) <= 0).any(axis=1))])
            raise ValueError(f"triangle {bad}: the director field inverts the shell volume")
        contravariant = np.linalg.inv(jacobian)  # rows G^i
        e3 = cross(d1, d2)
        e3 /= np.linalg.norm(e3, axis=-1, keepdims=True)
        e1 = self.warp - (e3 @ self.warp)[:, None] * e3
        e1 /= np.linalg.norm(e1, axis=-1, keepdims=True)
        e2 = cross(e3, e1)
        frame = np.stack([e1, e2, e3], axis=-2)[:, None]  # (m, 1, 3, 3)
        t = np.matmul(frame, np.swapaxes(contravariant, -1, -2))  # (m, P, 3, 3): e_a . G^i
        # gamma_a3 = t_a1 t_33 (2E13) + t_a2 t_33 (2E23) (+ terms in t_31, t_32, zero where the
        # director is normal to the cell: left out, which defines the section's shear strain).
        to_lamina = t[..., :2, :2] * t[..., 2:3, 2:3]  # (m, P, 2, 2)
        tying = np.stack([self.shear_a, self.shear_b], axis=1)  # (P, 2, 4): 2E13, 2E23
        strains = np.matmul(to_lamina, tying[None])  # (m, P, 2, 4)
        weight = (self.reference_area / 3.0)[:, None, None, None] * self.transverse_shear
        transverse = np.sum(weight * np.matmul(np.swapaxes(strains, -1, -2), strains), axis=1)
        # The reference's bending measure K0 (the y[3:6] of the reference against nothing:
        # half the difference of the outer levels' E11, E22, 2 E12), its fibre products k0
        # (docs/theory.md §5.7: the curvature's change from the reference fibre's).
        metric = self._metric(ref)
        level = np.stack([0.5 * metric["11"], 0.5 * metric["22"], metric["12"]], axis=-1)
        bending0 = 0.5 * (level[:, 2] - level[:, 0])  # (m, 3)
        reference_bending = np.stack(
            [np.sum(warp_rows * bending0, 1), np.sum(weft_rows * bending0, 1)], -1
        )
        self.section = FabricSection(
            fabric=self.fabric,
            area=self.reference_area.copy(),
            warp_rows=warp_rows,
            weft_rows=weft_rows,
            shear_rows=shear_rows,
            half_thickness=half,
            twisting=self.twisting,
            transverse=transverse,
            reference_bending=reference_bending,
        )
        assert transverse.shape == (m, 4, 4)

    def _section(self, cells: slice) -> FabricSection:
        s = self.section
        return dataclasses.replace(
            s,
            area=s.area[cells],
            warp_rows=s.warp_rows[cells],
            weft_rows=s.weft_rows[cells],
            shear_rows=s.shear_rows[cells],
            transverse=s.transverse[cells],
            reference_bending=np.asarray(s.reference_bending)[cells],
        )

    def section_measures(self, vec: dict, cells: slice = slice(None)) -> np.ndarray:
        """The ten section measures y (m, 10) of elements/fabric_section.py."""
        e = self._level_measures(vec, cells)
        return e.reshape(len(e), 21) @ _PROJECTION.T

    def _measures(self, x: np.ndarray, v: np.ndarray, cells=slice(None)) -> np.ndarray:
        """The section measures y (m, 10) of the cells ``cells`` (a slice or indices) with
        corners x and unit directors v (m, 3, 3): the compiled loop
        (elements/mindlin_fabric_measures.py) with ``loads_kernel``, else
        ``section_measures``."""
        if self.loads_kernel != "compiled":
            return self.section_measures(self._vectors(x, v), cells)
        return fabric_section_measures(x, v, self.zeta, self.h, _TYING_N, self._cells_metric(cells))

    def _cells_metric(self, cells) -> dict:
        """The reference products (``reference_metric``) of the cells ``cells`` (a slice or
        indices): the block's own arrays for them all."""
        if isinstance(cells, slice) and cells == slice(None):
            return self.reference_metric
        return {key: value[cells] for key, value in self.reference_metric.items()}

    def _level_response(
        self, e: np.ndarray, b_psi: np.ndarray, cells: slice
    ) -> tuple[np.ndarray, np.ndarray]:
        """sigma = P^T dW/dy (m, 3, 7, 1) and P^T (d2W/dy2) P B^psi (m, 21, 18): the levels are
        coupled through the section measures."""
        m = len(e)
        y = e.reshape(m, 21) @ _PROJECTION.T
        answer = response(self._section(cells), y, hessian=True)
        assert answer.hessian is not None
        sigma = (answer.gradient @ _PROJECTION).reshape(m, 3, 7, 1)
        hessian = _PROJECTION.T @ answer.hessian @ _PROJECTION  # (m, 21, 21)
        return sigma, np.matmul(hessian, b_psi.reshape(m, 21, 18))

    # ------------------------------------------------------------------ tangent
    def tangent(self, state: State, history=None) -> list[CellTangent]:
        """Each triangle's consistent 18 x 18 stiffness in (u, psi) of its corners, analytic
        (docs/theory.md §5.5, §5.7): blocks (m, 3, 6, 3, 6), N/mm, N, N mm; all cells in one
        compiled loop (``tangent_kernel``), else by slices of the numpy path."""
        if self.tangent_kernel != "compiled":
            return super().tangent(state, history)
        x = state.positions[self.connectivity]
        v = state.directors[self.connectivity]
        return [CellTangent(self.connectivity, self._cell_tangent(x, v, slice(None)))]

    def _cell_tangent(self, x: np.ndarray, v: np.ndarray, cells) -> np.ndarray:
        """d(force, moment)/d(u, psi) (m, 3, 6, 3, 6) of the cells ``cells`` (a slice or
        indices: the stable step's calibration asks for some) with corners x and unit
        directors v (m, 3, 3): the compiled loop, or ``numpy_cell_tangent``."""
        if self.tangent_kernel != "compiled":
            return self.numpy_cell_tangent(x, v, cells)
        y = self._measures(x, v, cells)
        # the whole block's section as is (a slice's is packed anew)
        whole = isinstance(cells, slice) and cells == slice(None)
        section = self.section if whole else self._section(cells)
        answer = response(section, y, hessian=True)
        assert answer.hessian is not None
        return fabric_tangent_blocks(
            x, v, self.zeta, self.h, _TYING_N, self._cells_metric(cells), answer.gradient,
            answer.hessian, *self._products(),
        )  # fmt: skip

    def numpy_cell_tangent(self, x: np.ndarray, v: np.ndarray, cells: slice) -> np.ndarray:
        """The numpy reference of ``_cell_tangent`` (MindlinShellBlock's, through the
        fabric's ``_level_response``)."""
        return super()._cell_tangent(x, v, cells)

    # ------------------------------------------------------------------ forces and energy
    def _cell_loads(self, x: np.ndarray, v: np.ndarray):
        """Unscattered nodal forces and director moments (m, 3, 3): dW/du and V x dW/dV of each
        triangle, sigma . B^psi; the compiled loop (``loads_kernel``), or
        ``numpy_cell_loads``."""
        if self.loads_kernel != "compiled":
            return self.numpy_cell_loads(x, v)
        y = self._measures(x, v)
        gradient = response(self.section, y, hessian=False).gradient
        return fabric_cell_loads(x, v, self.zeta, self.h, _TYING_N, gradient, self._products()[0])

    def numpy_cell_loads(self, x: np.ndarray, v: np.ndarray):
        """The numpy reference of ``_cell_loads``: the batched B^psi (m, 21, 18) and one
        matmul."""
        m = len(x)
        vec = self._vectors(x, v)
        y = self.section_measures(vec)
        gradient = response(self.section, y, hessian=False).gradient @ _PROJECTION  # (m, 21)
        b_psi, _ = self._turned_gradients(vec, v)
        loads = np.matmul(gradient[:, None, :], b_psi.reshape(m, 21, 18))[:, 0]
        loads = loads.reshape(m, 3, 2, 3)
        return loads[:, :, 0], loads[:, :, 1]

    def internal_force(self, state: State, history=None):
        x = state.positions[self.connectivity]
        v = state.directors[self.connectivity]
        force, moment = self._cell_loads(x, v)
        return self.scatter.vectors(force), self.scatter.vectors(moment)

    def strain_energy(self, state: State, history=None) -> float:
        x = state.positions[self.connectivity]
        y = self._measures(x, state.directors[self.connectivity])
        return float(response(self.section, y, hessian=False).energy.sum())

    # ------------------------------------------------------------------ mass and step
    def _rotary_factor(self, scaling: str | None) -> np.ndarray:
        """j (m,), mm^2: the B2 scaling of docs/theory.md §6.2 (``rotary_mode``) with the
        closed form at nu = 0, kappa = 5/6."""
        return scaled_rotary_inertia(self, scaling, _SHEAR_FACTOR)

    def _closed_rotary_factor(self) -> np.ndarray:
        """B2's closed-form j (m,), mm^2, at nu = 0, kappa = 5/6, whatever rotary_scaling the
        shell was given (``penalty_stable_dt``)."""
        return scaled_rotary_inertia(self, "closed", _SHEAR_FACTOR)

    def _cheap_omega2(self, x: np.ndarray, rotary_factor: np.ndarray | None = None) -> np.ndarray:
        """The trace bound of the elastic block (docs/theory.md §6.2 B1-B2) with the section's
        largest stiffnesses per unit width: 3 / rho_A (C + K + S) sum_k 1 / h_k^2 + S / (2
        rho_A j), C the stiffest tension slope, K the shear law's, S the transverse shear; j
        ``rotary_factor`` (m,), mm^2 (default: the block's)."""
        sides = np.linalg.norm(x[:, [2, 0, 1]] - x[:, [1, 2, 0]], axis=-1)
        area2 = np.linalg.norm(cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]), axis=1)
        inverse_heights2 = np.sum((sides / area2[:, None]) ** 2, axis=1)
        f = self.fabric
        tension = max(f.tension.max_slope(), f.tension_weft.max_slope())
        rho_a = f.areal_density
        stiff = tension + f.shear.max_slope() + self.transverse_shear
        omega2 = 3.0 / rho_a * stiff * inverse_heights2
        j = self.rotary_factor if rotary_factor is None else rotary_factor
        return omega2 + self.transverse_shear / (2.0 * rho_a * j)

    # ------------------------------------------------------------------ outputs
    def cell_fields(self, state: State, history=None) -> dict[str, np.ndarray]:
        """The fields both shells write (README "Output fields"), in the fibre frame: membrane
        (warp tension, weft tension, shear moment) N/mm, bending (warp, weft, twisting
        moments) N mm/mm, and the strains the laws take: log fibre strains, shear angle
        (deg), curvatures (1/mm)."""
        y = self.section_measures(self._state_vectors(state))
        answer = response(self.section, y, hessian=False)
        return {
            "membrane_force": np.column_stack([answer.tension, answer.shear_moment]),
            "bending_moment": answer.moments,
            "warp_strain": answer.strains[:, 0],
            "weft_strain": answer.strains[:, 1],
            "shear_angle_deg": np.degrees(answer.shear_angle),
            "warp_curvature": answer.curvatures[:, 0],
            "weft_curvature": answer.curvatures[:, 1],
            "warp_moment": answer.moments[:, 0],
            "weft_moment": answer.moments[:, 1],
            # the deformed fibres (unit, global axes): what "11" and "22" are taken along
            **block_fibre_directions(self, state),
        }
