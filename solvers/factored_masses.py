"""Fictitious masses of dynamic relaxation made of the stiffness itself, factorised
(masses="factored"; solvers.relaxation.DynamicRelaxation, docs/theory.md §6.4a, "Factored
masses").

Why. The Gershgorin masses (solvers.fictitious_masses) give every DOF the same stability limit,
but they are diagonal: the iterations still grow like omega_max / omega_min of M^-1 K, and a
shell whose fibres are quasi-inextensible against a soft bending has that ratio large. The
strip over the cylinder of cases/strip_over_cylinder.toml (fibres 1000 N/mm, bending 0.833 N
mm, 50 cells) spans 1.6e4, and took 127 814 iterations where the progress watch stopped it.
Dynamic relaxation is a three-term recursion whose mass matrix plays the part of a
preconditioner (Papadrakakis 1981): with a mass that is the stiffness itself (a positive
definite bound of it, factorised once per estimate), M^-1 K is near the identity at the
estimate, the stiff fibres and the soft bending move alike, and what is left to relax is how
far the stiffness changes before the next estimate.

The bound. With K the tangent of the free DOFs in the node axes of the Gershgorin masses,
split into translations u and rotations theta, K = [[A, B], [B^T, C]], and d = 1 on the
translations, 1 / L_e on the rotations (the scaling of the Gershgorin rows),
2 |x_i B_ij y_j| <= |B_ij| (x_i^2 d_j / d_i + y_j^2 d_i / d_j), so that

    K <= blockdiag(A + D_B, G_theta)

in the sense of quadratic forms, D_B the diagonal of the rows of |B| d_j / d_i and G_theta the
Gershgorin rows of the rotations (their inertia, as in GershgorinMasses). The translation mass
is then M_u = (A + D_B + E) / (4 s^2), E >= 0 diagonal in the node axes: the normal share
TURN^2 of the in-plane rows (a turn brings the membrane onto the normal before the next
estimate), the reachable contact springs, the isotropy of nodes in global axes, and a floor;
every eigenvalue of M^-1 K at the estimate is then at most (2 s)^2, the same bound as the
Gershgorin masses'. Where A + D_B + E is not positive definite (a compressed, buckling
region), sigma times the Gershgorin rows of A are added, sigma from 1e-6 up by factors of
100; A + diag(rows of |A|) is diagonally dominant, so sigma = 1 always is.

The cost: one sparse LDL^T (solvers.linear) per estimate and two triangular solves per
iteration, in place of a division.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from femcore.dofs import N_COLUMNS
from femcore.state import State
from solvers.fictitious_masses import GershgorinMasses, NodeMass, RelaxationMasses
from solvers.linear import Factorisation, LinearSolver

__all__ = ["FactoredMasses", "MatrixMass", "factored_fallback"]

#: The shifts sigma (times the Gershgorin rows of A) tried in turn until the mass is positive
#: definite; the last one makes it diagonally dominant.
SHIFTS = (0.0, 1e-6, 1e-4, 1e-2, 1.0)


class MatrixMass(NodeMass):
    """Translational masses as a sparse matrix in node axes: M = Q M_local Q^T, M_local over
    the free translation slots, factorised.

    axes : (n, 3, 3) node axes (columns); values : (n, 3) the diagonal of M_local (0 where
    held), for the viscous damping's estimate; matrix : M_local over ``slots`` (the free
    translation slots, 3 node + axis); factors : its factorisation.
    """

    def __init__(
        self,
        axes: np.ndarray,
        values: np.ndarray,
        matrix: sp.csc_matrix,
        factors: Factorisation,
        slots: np.ndarray,
    ):
        super().__init__(axes, values)
        self.matrix, self.factors, self.slots = matrix, factors, slots

    def solve(self, forces: np.ndarray) -> np.ndarray:
        """M^-1 F, (n, 3)."""
        rhs = self.local(forces).ravel()[self.slots]
        local = np.zeros(self.values.size)
        solved = self.factors.solve_columns(rhs)
        local[self.slots] = np.nan if solved is None else solved
        return np.einsum("nij,nj->ni", self.axes, local.reshape(-1, 3))

    def energy(self, velocities: np.ndarray) -> float:
        """1/2 v.M v."""
        local = self.local(velocities).ravel()[self.slots]
        return 0.5 * float(local @ (self.matrix @ local))


class FactoredMasses(RelaxationMasses):
    """Masses M_u = (A + D_B + E) / (4 s^2) on the translations (the module docstring), the
    Gershgorin inertia on the rotations; dt = 1. Made on the GershgorinMasses ``base``: its
    stiffness, its diagonal estimate (E and the inertia), its watches of turns and contacts
    and its counts of estimates and recoveries, which it shares."""

    fictitious = True
    every_restart = False
    bound = 'their factored bound (masses = "factored": the stiffness A + D_B + E itself)'
    switches = 0  # (factored from the start: no stall went on with them)

    def __init__(self, base: GershgorinMasses):
        self.base = base
        self.solver = LinearSolver()  # keeps the ordering while the pattern holds
        self.shifted = 0  # estimates that needed a shift to be positive definite

    @property
    def estimates(self) -> int:
        return self.base.estimates

    @estimates.setter
    def estimates(self, value: int) -> None:
        self.base.estimates = value

    @property
    def recoveries(self) -> int:
        return self.base.recoveries

    @recoveries.setter
    def recoveries(self, value: int) -> None:
        self.base.recoveries = value

    def turned(self, state: State) -> float:
        return self.base.turned(state)

    def approached(self, state: State) -> bool:
        return self.base.approached(state)

    def __call__(self, state: State, inflate: float) -> tuple[NodeMass, np.ndarray, float]:
        base = self.base
        base.estimates += 1
        k, axes, local = base.stiffness(state)
        rows = base.row_sums(k)
        # The diagonal masses of the Gershgorin estimate carry E (normal share, springs,
        # isotropy, floor) and the rotations' inertia; their translations are replaced below.
        diagonal, inertia, dt = base.diagonal(state, inflate, rows, axes, local)
        dofs = base.model.dofs
        n = dofs.n_nodes
        scale = base.scale * inflate
        held = ~dofs.free[:, :3]
        axis = np.arange(3)[None, :]
        # the free translations: their slots in K, and their places in (n, 3) arrays
        translations = (N_COLUMNS * np.arange(n)[:, None] + axis)[~held]
        places = (3 * np.arange(n)[:, None] + axis)[~held]
        rotations = dofs.free_slots[dofs.free_slots % N_COLUMNS >= 3]
        kt = k[translations]
        a = kt[:, translations]
        a = 0.5 * (a + a.T)
        # D_B: the rows of |B| d_j / d_i with d_j / d_i = 1 / L_e (module docstring)
        coupling = np.asarray(abs(kt[:, rotations]).sum(axis=1)).ravel() / base.length
        gershgorin_a = np.asarray(abs(a).sum(axis=1)).ravel()
        # E: what the diagonal estimate adds to the rows of A + D_B (the normal share, the
        # springs, the isotropy and the floor of GershgorinMasses.diagonal), >= 0 on each axis
        extra = np.maximum(diagonal.values[~held] - scale * (gershgorin_a + coupling), 0.0)
        base_matrix = scale * (a + sp.diags(coupling)) + sp.diags(extra)
        for sigma in SHIFTS:
            matrix = (base_matrix + sp.diags(scale * sigma * gershgorin_a)).tocsc()
            factors = self.solver.factorise(matrix)
            if factors.kind == "ldlt" and factors.negative == 0 and not factors.neutral:
                break
            self.shifted += 1
        values = np.zeros((n, 3))
        values[~held] = matrix.diagonal()
        return MatrixMass(axes, values, matrix, factors, places), inertia, dt


def factored_fallback(masses: RelaxationMasses) -> FactoredMasses | None:
    """The factored masses a stalled relaxation with the Gershgorin ``masses`` goes on with
    (docs/theory.md §6.4a, "Factored masses"), or None for other masses (the physical ones,
    or factored already)."""
    if type(masses) is GershgorinMasses:
        masses.switches += 1
        return FactoredMasses(masses)
    return None
