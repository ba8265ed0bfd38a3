"""Viscous stabilisation of the static solver's increments (solvers.static.Static,
``stabilise``; docs/theory.md §6.7): the quasi-static regularisation of implicit forming codes
(Abaqus's ``*STATIC, STABILIZE``).

A fabric formed by a punch is a mechanism until it touches the tools: the blank's flange rests
on the die and nothing holds it in its plane but its own stiffness, which is nearly zero in
shear and, while it is flat and stress-free, out of its plane as well; the wrinkles of the
flange are out-of-plane instabilities. Newton's tangent there is singular or indefinite, and
the steps it gives fling the flange about. Each node gets a dashpot to where it was at the
last converged increment, in the pseudo-time of the load factor: over an increment from
lambda_n to lambda (dlambda = lambda - lambda_n) the node feels

    f_i = -c m_i (x_i - x_i^n) / dlambda,   N
    M_i = -c I_i theta_i / dlambda,          N mm (theta_i: the rotation from d_i^n to d_i),

with m_i its lumped mass (t) and I_i its rotary inertia (t mm^2): a mass-proportional dashpot
(the artificial mass matrix of Abaqus's stabilisation), c in N / (t mm) = 1/s^2 per unit load
factor. The forces are those of a spring of stiffness c m_i / dlambda to the last state, so the
increment's problem is the minimum of the total potential plus D = 1/2 sum c m_i |x_i -
x_i^n|^2 / dlambda (+ the rotations'), whose tangent is the model's plus a positive diagonal:
Newton and its line search see a smooth, positive problem wherever the dashpots dominate the
mechanism, and nothing changes where the structure is stiff. A cut increment (smaller
dlambda) gets stiffer dashpots, the way a smaller time step raises the inertia of an implicit
dynamic step.

What it costs: each converged increment is an equilibrium with the dashpots' forces, which
the increment's motion sets; their work c m |dx|^2 / dlambda, summed over the increments,
is the energy they dissipated (``info["stabilisation"]``), to be judged against the strain
energy as Abaqus users judge ALLSD against ALLIE. ``Static`` warns when it exceeds
``STABILISATION_BOUND`` of the strain energy at the end of the run.
"""

from __future__ import annotations

import warnings
from typing import TYPE_CHECKING, Any

import numpy as np

from femcore.dofs import N_COLUMNS
from femcore.rotation import cross
from femcore.state import State
from solvers.common import check_non_negative, outside_stacklevel

if TYPE_CHECKING:
    from solvers.static import StaticRun

__all__ = ["STABILISATION_BOUND", "Dashpots", "report_stabilisation"]

# The dissipated energy past which a stabilised run warns: this fraction of the strain energy
# at the end of the run.
STABILISATION_BOUND = 0.05


class Dashpots:
    """The dashpots of one increment (module docstring).

    coefficient : c, 1/s^2 per unit load factor. mass, inertia : (n,) lumped mass (t) and
    rotary inertia (t mm^2). has_rotation : (n,) bool, the nodes with a director.
    reference : the last converged state. step : dlambda > 0, the increment of load factor.
    """

    def __init__(
        self,
        coefficient: float,
        mass: np.ndarray,
        inertia: np.ndarray,
        has_rotation: np.ndarray,
        reference: State,
        step: float,
    ):
        self.reference = reference
        self.translation = coefficient * mass / step  # N/mm per node
        self.rotation = np.where(has_rotation, coefficient * inertia / step, 0.0)  # N mm/rad

    def _turn(self, state: State) -> np.ndarray:
        """(n, 3) the rotation vector taking each reference director to the current one, rad."""
        old, new = self.reference.directors, state.directors
        axis = cross(old, new)
        sine = np.linalg.norm(axis, axis=1)
        angle = np.arctan2(sine, np.sum(old * new, axis=1))
        safe = np.where(sine > 0.0, sine, 1.0)
        return axis * np.where(sine > 0.0, angle / safe, 0.0)[:, None]

    def forces(self, state: State) -> tuple[np.ndarray, np.ndarray]:
        """(forces (n, 3), N; moments (n, 3), N mm) of the dashpots on the nodes at ``state``."""
        moved = state.positions - self.reference.positions
        return -self.translation[:, None] * moved, -self.rotation[:, None] * self._turn(state)

    def energy(self, state: State) -> float:
        """D, the dashpots' pseudo-potential at ``state``, N mm: the minimum of the total
        potential plus D is the increment's equilibrium."""
        moved = state.positions - self.reference.positions
        turned = self._turn(state)
        return 0.5 * float(
            np.sum(self.translation * np.sum(moved**2, axis=1))
            + np.sum(self.rotation * np.sum(turned**2, axis=1))
        )

    def diagonal(self, free_slots: np.ndarray) -> np.ndarray:
        """(n_free,) the dashpots' stiffness on each free generalised DOF: c m / dlambda on the
        translations, c I / dlambda on the director's two rotations (exact at the reference,
        where the generalised rotations are the rotation vector's components)."""
        per_node = np.zeros((len(self.translation), N_COLUMNS))
        per_node[:, :3] = self.translation[:, None]
        per_node[:, 3:] = self.rotation[:, None]
        return per_node.ravel()[free_slots]

    def dissipated(self, state: State) -> float:
        """The dashpots' work over the increment ending at ``state``, N mm: twice D (the force
        of each dashpot is constant over the increment's pseudo-time in backward Euler)."""
        return 2.0 * self.energy(state)


def check_stabilise(value: Any, path: str) -> float:
    """The ``stabilise`` coefficient, checked: a finite number >= 0, zero on the arc-length
    path (its load factor is an unknown, and the dashpots need the increment's)."""
    coefficient = check_non_negative(value, "stabilise", "1/s^2 per unit load factor")
    if coefficient > 0.0 and path != "load":
        raise ValueError(
            f"stabilise = {value!r} needs path='load' (the dashpots act over a known increment "
            f"of the load factor), got path={path!r}"
        )
    return coefficient


def report_stabilisation(run: StaticRun) -> None:
    """Stabilised runs: the energy the dashpots dissipated against the strain energy at the
    end, in ``run.info["stabilisation"]``; a UserWarning past STABILISATION_BOUND."""
    if run.masses is None:
        return
    strain = run.strain_energies[-1]
    ratio = run.dissipated / strain if strain > 0.0 else float("inf")
    run.info["stabilisation"] = {
        "coefficient_per_s2": run.solver.stabilise,
        "dissipated_N_mm": run.dissipated,
        "strain_energy_N_mm": strain,
        "dissipated_over_strain_energy": ratio,
    }
    if run.dissipated > STABILISATION_BOUND * strain:
        warnings.warn(
            f"the viscous stabilisation dissipated {run.dissipated:.4g} N mm, "
            f"{ratio:.3g} of the strain energy ({strain:.4g} N mm), more than "
            f"{STABILISATION_BOUND:g}: the dashpots, not the model, shape the result; "
            f"lower stabilise (now {run.solver.stabilise:g}) or take more increments",
            UserWarning,
            stacklevel=outside_stacklevel(),
        )
