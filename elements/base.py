"""The element protocol (DESIGN §4).

An element *type* (``Cable``, ``FibrousShell``, ...) holds only material and options. Adding it
to a model and compiling binds it to the mesh: ``bind`` returns an element *block*, one element
type over many cells, holding the reference geometry and index arrays computed once. Every block
method is vectorised over the cells of the block (leading axis = cell); none loops in Python over
cells or nodes.

Sign convention: ``internal_force`` returns F_int = dW/dx and the moment vectors dW/dpsi (the
paper's F_int of Eq. 22-23), so that the residual a solver drives to zero is F_ext - F_int.
"""

from __future__ import annotations

from abc import ABC, abstractmethod

import numpy as np

from femcore.assembly import Scatter
from femcore.checks import check_positive  # noqa: F401  (re-exported for element types)
from femcore.mesh import Mesh
from femcore.state import State


class ElementType(ABC):
    """Material and options of one element family; ``bind`` makes a block over mesh cells.

    Class attributes
    ----------------
    dofs : DOF names each node of the element needs, e.g. ("ux", "uy", "uz").
    cell_type : "line" (2-node cells, mesh.lines) or "triangle" (mesh.triangles).
    """

    dofs: tuple[str, ...] = ()
    cell_type: str = ""

    @abstractmethod
    def bind(self, mesh: Mesh, cell_ids: np.ndarray, directors: np.ndarray) -> ElementBlock:
        """Block over the given cells of the mesh.

        mesh : the model's mesh; cell_ids : (m,) ids into mesh.lines or mesh.triangles;
        directors : (n, 3) reference unit directors (zero rows at nodes without rotations).
        """


class ElementBlock(ABC):
    """One element type over many cells, bound to a mesh.

    Attributes set by subclasses: ``dofs``, ``cell_type``, ``cell_ids`` (m,), ``connectivity``
    (m, k) global node ids, ``scatter`` (femcore.assembly.Scatter over the connectivity).
    """

    dofs: tuple[str, ...]
    cell_type: str
    cell_ids: np.ndarray
    connectivity: np.ndarray
    scatter: Scatter

    @abstractmethod
    def lumped_mass(
        self, state: State, density_scale: np.ndarray | None = None
    ) -> tuple[np.ndarray, np.ndarray | None]:
        """Nodal translational mass (n,) (t) and rotary inertia (n,) (t mm^2, or None).

        density_scale : (m,) factor >= 1 per cell for selective mass scaling, or None.
        """

    @abstractmethod
    def internal_force(self, state: State) -> tuple[np.ndarray, np.ndarray | None]:
        """Nodal internal forces F_int = dW/dx (n, 3) (N) and moment vectors (n, 3) (N mm) or
        None for elements without rotational DOFs; already scattered to the nodes."""

    @abstractmethod
    def cell_stable_dt(self, state: State) -> np.ndarray:
        """Critical time step of each cell (m,) (s), lumped mass, no damping."""

    def stable_dt(self, state: State) -> float:
        """Critical time step of the block (s)."""
        return float(np.min(self.cell_stable_dt(state)))

    @abstractmethod
    def strain_energy(self, state: State) -> float:
        """Strain energy stored in the block (N mm)."""

    def cell_fields(self, state: State) -> dict[str, np.ndarray]:
        """Per-cell outputs {name: (m, ...)} for results and VTU files."""
        return {}

    def node_fields(self, state: State) -> dict[str, np.ndarray]:
        """Nodal outputs {name: (n, ...)} for results and VTU files."""
        return {}
