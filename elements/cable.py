"""Cable: a 2-node axial element (cables, bars, chains of springs), translations only.

Axial force from the engineering stretch, N = EA (l/L0 - 1), so that a chain of cables under its
own weight is the elastic catenary of Irvine (Cable Structures, 1981), whose tension is linear
in the stretch of the unstretched length. Strain energy W = 1/2 EA L0 eps^2.
"""

from __future__ import annotations

import numpy as np

from elements import kernels
from elements.base import CellTangent, ElementBlock, ElementType, Scatter, check_positive
from femcore.checks import as_flag
from femcore.mesh import Mesh
from femcore.state import State

__all__ = ["Cable", "CableBlock"]


class Cable(ElementType):
    """Two-node cable or bar.

    axial_stiffness : EA, N (force per unit engineering strain).
    mass_per_length : t/mm, per unit unstretched length.
    tension_only : if True the cable goes slack (no force) when shorter than its rest length.
    kernel : "compiled" (default when numba is installed: elements/kernels.py) or "numpy".
    """

    dofs = ("ux", "uy", "uz")
    cell_type = "line"

    def __init__(
        self,
        axial_stiffness: float,
        mass_per_length: float,
        tension_only: bool = False,
        kernel: str | None = None,
    ):
        self.axial_stiffness = check_positive(axial_stiffness, "axial_stiffness EA", "N")
        self.mass_per_length = check_positive(mass_per_length, "mass_per_length", "t/mm")
        self.tension_only = as_flag(tension_only, "Cable tension_only")
        self.kernel = kernels.choose(kernel)

    def bind(self, mesh: Mesh, cell_ids: np.ndarray, directors: np.ndarray) -> CableBlock:
        return CableBlock(self, mesh, cell_ids)


class CableBlock(ElementBlock):
    """Cable over mesh line cells ``cell_ids``; reference lengths computed once."""

    dofs = Cable.dofs
    cell_type = Cable.cell_type
    reach = 1

    def __init__(self, cable: Cable, mesh: Mesh, cell_ids: np.ndarray):
        # Options resolved once: the block never reads its type back at run time.
        self.axial_stiffness = cable.axial_stiffness  # N
        self.mass_per_length = cable.mass_per_length  # t/mm
        self.tension_only = cable.tension_only
        self.kernel = cable.kernel
        self.cell_ids = np.asarray(cell_ids, dtype=np.int64)
        self.connectivity = mesh.lines[self.cell_ids]
        self.scatter = Scatter(self.connectivity, mesh.n_nodes)
        ends = mesh.points[self.connectivity]
        self.rest_length = np.linalg.norm(ends[:, 1] - ends[:, 0], axis=1)  # (m,) mm
        short = self.rest_length <= 1e-12 * max(1.0, float(np.ptp(mesh.points)))
        if short.any():
            raise ValueError(
                f"line cell {self.cell_ids[short][0]} has zero length: its two nodes coincide"
            )
        self.wave_speed = np.sqrt(self.axial_stiffness / self.mass_per_length)  # mm/s

    def _axial(self, state: State):
        """Chord vectors (m, 3), current lengths (m,), engineering strains (m,), forces (m,)."""
        ends = self.scatter.gather(state.positions)
        chord = ends[:, 1] - ends[:, 0]
        length = np.linalg.norm(chord, axis=1)
        strain = length / self.rest_length - 1.0
        force = self.axial_stiffness * strain
        if self.tension_only:
            force = np.maximum(force, 0.0)
        return chord, length, strain, force

    def lumped_mass(self, state: State, density_scale=None):
        half = 0.5 * self.mass_per_length * self.rest_length
        if density_scale is not None:
            half = half * density_scale
        return self.scatter.scalars(np.stack([half, half], axis=1)), None

    def internal_force(self, state: State, history=None):
        if self.kernel == "compiled":
            return kernels.cable_forces(self, state.positions), None
        chord, length, _, force = self._axial(state)
        pull = (force / length)[:, None] * chord  # on node 2 (= dW/dx2); node 1 gets the opposite
        return self.scatter.vectors(np.stack([-pull, pull], axis=1)), None

    def tangent(self, state: State, history=None) -> list[CellTangent]:
        """Exact 6 x 6 stiffness of each cable: material (EA / L0) e e^T plus geometric
        (N / l) (I - e e^T), e the unit chord; zero for a slack tension-only cable."""
        chord, length, _, force = self._axial(state)
        e = chord / length[:, None]
        along = e[:, :, None] * e[:, None, :]
        axial = self.axial_stiffness / self.rest_length
        if self.tension_only:
            axial = np.where(force > 0.0, axial, 0.0)
        k = axial[:, None, None] * along + (force / length)[:, None, None] * (np.eye(3) - along)
        blocks = np.empty((len(k), 2, 3, 2, 3))
        blocks[:, 0, :, 0] = blocks[:, 1, :, 1] = k
        blocks[:, 0, :, 1] = blocks[:, 1, :, 0] = -k
        return [CellTangent(self.connectivity, blocks)]

    def cell_stable_dt(self, state: State) -> np.ndarray:
        # Two lumped masses mu L0/2 joined by the axial stiffness EA/L0 (+ the geometric
        # stiffness N/l for transverse motion of a taut cable): omega_max^2 = 4 k / (mu L0).
        _, length, _, force = self._axial(state)
        stiffness = self.axial_stiffness / self.rest_length + np.maximum(force, 0.0) / length
        omega = np.sqrt(4.0 * stiffness / (self.mass_per_length * self.rest_length))
        return 2.0 / omega

    def strain_energy(self, state: State, history=None) -> float:
        _, _, strain, _ = self._axial(state)
        if self.tension_only:
            strain = np.maximum(strain, 0.0)
        return float(0.5 * self.axial_stiffness * np.sum(self.rest_length * strain**2))

    def cell_fields(self, state: State, history=None) -> dict[str, np.ndarray]:
        _, _, strain, force = self._axial(state)
        return {"axial_strain": strain, "axial_force": force}

    def total_mass(self) -> float:
        """Physical mass of the block (t)."""
        return float(self.mass_per_length * self.rest_length.sum())
