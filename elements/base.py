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
from collections.abc import Callable
from typing import NamedTuple

import numpy as np

from femcore.assembly import Scatter
from femcore.checks import check_positive  # noqa: F401  (re-exported for element types)
from femcore.mesh import Mesh
from femcore.rotation import rotate_about
from femcore.state import State


class CellTangent(NamedTuple):
    """Stiffness blocks of an element block, summed into the global tangent by the solver.

    nodes : (m, p) global node ids of each block (a node may appear twice: entries add up).
    blocks : (m, p, c, p, c) d(force, moment)_(node a, comp i) / d(u, psi)_(node b, comp j),
        with c = 3 (translations only) or 6 (u then psi: a small rotation vector of the director
        in global components, V+ = V + psi x V). Units N/mm, N, N mm.
    """

    nodes: np.ndarray
    blocks: np.ndarray


def local_tangent(
    cell_force: Callable,
    x: np.ndarray,
    v: np.ndarray | None,
    step: float,
    rotation_step: float = 1e-6,
) -> np.ndarray:
    """Central-difference stiffness of a cell-local force, all cells at once.

    cell_force(x, v) -> (forces (m, k, 3), moments (m, k, 3) or None): the unscattered nodal
    loads of each cell from its own corner positions x (m, k, 3) and directors v (m, k, 3) (or
    None for translation-only elements). Each of the k x c local unknowns is perturbed in every
    cell at once (they do not interact before the scatter), so the cost is 2 k c evaluations of
    cell_force whatever the mesh size. Returns (m, k, c, k, c) as in CellTangent.blocks.

    step : translation perturbation (mm); rotation_step : rotation perturbation (rad).
    """
    m, k, _ = x.shape
    c = 3 if v is None else 6

    def loads(xx, vv):
        f, moment = cell_force(xx, vv)
        return f if v is None else np.concatenate([f, moment], axis=-1)

    blocks = np.empty((m, k, c, k, c))
    for node in range(k):
        for comp in range(c):
            if comp < 3:
                shift = np.zeros_like(x)
                shift[:, node, comp] = step
                difference = loads(x + shift, v) - loads(x - shift, v)
                blocks[:, :, :, node, comp] = difference / (2.0 * step)
            else:
                psi = np.zeros((m, 3))
                psi[:, comp - 3] = rotation_step
                plus, minus = v.copy(), v.copy()
                plus[:, node] = rotate_about(v[:, node], psi)
                minus[:, node] = rotate_about(v[:, node], -psi)
                difference = loads(x, plus) - loads(x, minus)
                blocks[:, :, :, node, comp] = difference / (2.0 * rotation_step)
    return blocks


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
    #: How many cell-hops the internal force at a node reaches: 1 when each cell's loads
    #: depend on its own nodes only, 2 for rotation-free bending over neighbour patches. The
    #: finite-difference tangent colours the nodes with it.
    reach: int = 2

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

    def tangent(self, state: State) -> list[CellTangent] | None:
        """The element's own stiffness d(internal_force)/d(u, psi) as CellTangent blocks, or
        None (the default): the static solver then differentiates ``internal_force``
        numerically with a colouring of the node graph (``reach``)."""
        return None

    def cell_fields(self, state: State) -> dict[str, np.ndarray]:
        """Per-cell outputs {name: (m, ...)} for results and VTU files."""
        return {}

    def node_fields(self, state: State) -> dict[str, np.ndarray]:
        """Nodal outputs {name: (n, ...)} for results and VTU files."""
        return {}
