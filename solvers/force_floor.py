"""The least force reference of the convergence test of Static and DynamicRelaxation: the
size of the rounding of the internal forces, so that a residual is never judged against a
reference that vanishes below the model's own round-off (docs/theory.md §6.4, §6.5).

The convergence test divides the out-of-balance by F_ref = max(||F_ext||, ||F_int||, ...)
(solvers.convergence). Where the true answer carries almost no force (a rigid motion
prescribed on every node, a load of 1e-10 N on a shell that rounds its forces to 1e-13 N) that
reference is itself round-off, and the ratio of round-off to round-off never falls: Static
cut its increments eight times and stopped. Implicit codes give the test an absolute floor
for that reason (Abaqus's "zero force" criterion: forces below a small fraction of the
time-averaged force count as zero). Here the floor is tied to the model's rounding:

    F_round = ROUND_OFF_FORCES * eps * K_max * X

eps the machine epsilon, K_max the largest diagonal of the tangent stiffness at the reference
state (translations in N/mm, rotations as K_theta,theta / L_e^2, the stiffness of a rotation
times one element), X the largest reference coordinate (mm; coordinates round to eps X, and a
stiffness K_max turns that into a force). It is a force in every consistent set of units, and
far below any load a model is built for: a 40 mm Mindlin plate of E = 1e3 MPa gets 3e-8 N,
where its forces round to about 1e-13 N (the residual Newton leaves at a load of 1e-10 N), so
that the round-off end of Newton (solvers.newton.at_round_off_floor, ratios up to 1e-3)
settles it. Every force reference of the tests and validation cases is above it, where
max(F_ref, F_round) = F_ref and the test keeps its bits.
"""

from __future__ import annotations

import numpy as np

from femcore.assembly import tangent_matrix
from femcore.dofs import N_COLUMNS
from femcore.model import CompiledModel

__all__ = ["ROUND_OFF_FORCES", "UNLOADED_SHARE", "round_off_force", "unloaded_floor"]

# The floor over the rounding estimate eps K_max X: the residual Newton leaves is below the
# estimate (1e-13 N against 1e-11 N on the plate above), so that it is at most about 1e-3 of
# the floor, where solvers.newton.at_round_off_floor ends the iterations.
ROUND_OFF_FORCES = 1e3
# With user amplitudes the loads may come back towards zero (a load then unload): an increment's
# force reference is floored by this share of the last converged frame's loads and reactions.
# Small, so that a level's own loads, where they are above it, set the test: the whole last
# frame as the floor judged a partial unload to 1e-5 of its load against the load before, and
# DynamicRelaxation ended there with the wrong sign (+1.76e-5 mm where -1.26e-5 is right).
UNLOADED_SHARE = 1e-6


def round_off_force(model: CompiledModel, parts) -> float:
    """F_round, N (module docstring): 0 without element tangents (``parts``: the tangent parts
    of the blocks that have their own, at the reference state, a sequence or None)."""
    if not parts:
        return 0.0
    dofs = model.dofs
    frames = dofs.frames(model.initial_state().directors)
    diagonal = np.abs(tangent_matrix(dofs, list(parts), frames).diagonal())
    diagonal = diagonal.reshape(dofs.n_nodes, N_COLUMNS)
    size = model.element_size
    stiffness = max(
        float(diagonal[:, :3].max(initial=0.0)), float(diagonal[:, 3:].max(initial=0.0)) / size**2
    )
    extent = float(np.abs(model.reference_positions).max(initial=0.0))
    return ROUND_OFF_FORCES * float(np.finfo(float).eps) * stiffness * extent


def unloaded_floor(model: CompiledModel, force, moment, reactions, reaction_moments) -> float:
    """The least force reference of an increment after a frame with loads ``force``,
    ``moment`` and reactions ``reactions``, ``reaction_moments`` ((n, 3) each, N and N mm):
    UNLOADED_SHARE times the largest of their norms (moments over the element size), where
    some load has a user amplitude; 0 otherwise (the loads then only grow with the load
    factor)."""
    if not model.user_amplitudes():
        return 0.0
    size = model.element_size
    return UNLOADED_SHARE * max(
        float(np.linalg.norm(force)),
        float(np.linalg.norm(reactions)),
        float(np.linalg.norm(moment)) / size,
        float(np.linalg.norm(reaction_moments)) / size,
    )
