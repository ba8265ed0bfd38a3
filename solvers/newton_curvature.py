"""The curved Newton step of the static solver (``Static(curved=True)``, docs/theory.md §6.5).

A Newton step delta moves the nodes along straight lines. Where it turns a part of the
structure by an angle theta, the straight update stretches that part by about theta^2 / 2 (a
chord is longer than its arc), and on a thin shell that stretch, times the membrane (and
transverse shear) stiffness, dwarfs the bending forces the step was solving for: the next
iterations spend themselves taking the stretch back (the residual ratio stays near 1 for two
or three of them) before Newton's quadratic phase begins. The curved step adds the
second-order term of the path: along q(t) = q + t delta (the finite rotations of the update
included), the residual is

    r(t) = r(0) - t K delta + t^2 / 2 D + O(t^3),   D = d^2 r / dt^2 at t = 0,

and K delta = r(0) on the free DOFs, so that the step delta + w with K w = D / 2 leaves a
residual of third order in the step: the stretch of a turned chord drops from theta^2 / 2 to
about theta^4 / 8 (the second-order Taylor expansion of a rotation keeps lengths to that order).
D comes from central differences of the residual at t = +-h (h = CURVATURE_PROBE: two force
evaluations) and w from the factorisation the step was solved with (one more solve); no
tangent is formed. This is the "geodesic acceleration" of Transtrum and Sethna
(arXiv:1201.5885, 2012) on Newton's equations, the Chebyshev-type third-order step.

The whole correction overshoots where the third-order remainder opposes it: on the first
update of every increment of the Mindlin cantilevers (the elastica, the 20 x 2 and 80 x 16
cell strips of benchmarks/kratos_cantilever.py) the residual after delta + a w is least at a
= 0.6-0.7, 2-7 times below its value at a = 1, where the strip's membrane is compressed (1-14
negative pivots, each costing a mode search, a shifted factorisation and the increment's
jump check, solvers.load_jumps). So the correction is scaled by the a in [LEAST_SCALE, 1] at
which the parabola through ||r||^2 at a = 0, 1/2, 1 (three force evaluations) is least: a
line search on the correction alone; the Newton step itself stays whole and the watchdog
(solvers.line_search) judges the step as before. Measured (benchmarks/newton_iterations.py):
the 2560-triangle cantilever 4-5-5-5-4 -> 5-4-4-4-4 Newton iterations (19 -> 17 tangents,
no indefinite iterate), the elastica 4-6-5-4-4 -> 4-4-4-4-4, the roll-up 5-4-5-4 -> 5-4-4-4,
the same equilibria. Not on models with a block that offers the compression-free tangent
(the fibrous shell): there the residual is ruled by the fibres' tension, and the fit of its
norm cost iterations (Peirce's strip without the level projection 9-9-10 -> 9-25-6) and
stopped the imperfect fibrous column of tests/test_compression_free_tangent.py at load factor
0.667; the fibrous models take the whole correction, as before. Nor with interactions (the
curved steps of ``Static(curved_with_contact=True)``): the Mindlin plies of
validation/cases/plies_deck_of_cards.py took 924 Newton iterations with the share fitted
against 882 with the whole correction, the same results to 1e-9.

On by default (``Static(correction="fitted")``); ``correction="whole"`` takes the whole
correction, the solver before. The tests that were written on the whole correction's iterates
were moved to what they specify (tests/test_static_first_turn.py, test_static_stall.py,
test_static_stop.py, test_fibre_projection.py, test_newton_orders.py: docs/theory.md §6.5).

The correction is trusted only while the expansion it comes from converges: it is taken when
its scaled norm (rotations times the element size, as the arc length counts them) is at most
CURVATURE_LIMIT of the step's (Transtrum and Sethna's acceptance test; a far, badly curved
step keeps its straight form), and it is computed only for steps that turn a director by more
than CURVED_FROM rad or move a node by more than CURVED_FROM element sizes (smaller steps
stretch nothing that matters, and the finite differences of their residual would be
round-off).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from femcore.dofs import N_COLUMNS, Frames
from femcore.state import State
from solvers.linear import Factorisation

if TYPE_CHECKING:
    from solvers.newton import Residual
    from solvers.static import StaticRun

__all__ = [
    "CURVATURE_LIMIT",
    "CURVATURE_PROBE",
    "CORRECTIONS",
    "CURVED_FROM",
    "LEAST_SCALE",
    "correction_scale",
    "curved_step",
]

# A step is curved when it turns a director by more than this (rad) or moves a node by more
# than this many element sizes.
CURVED_FROM = 1e-3
# The fraction of the step at which the residual is probed for its second derivative: the
# truncation error of the central difference is of order h^2 = 1e-4 of the correction, and
# the residual differences at +-h delta stay far above round-off for the steps that are curved.
CURVATURE_PROBE = 1e-2
# The largest ratio of the correction's scaled norm to the step's for which it is taken.
CURVATURE_LIMIT = 0.5
# The least share of the correction a step takes with Static(correction="fitted") (module
# docstring): the fit of ||r||^2 chooses the share within [LEAST_SCALE, 1]. A floor of 0 cost
# iterations (the 40-cell heavy fibrous cantilever 12-5-4 against 8-5-4).
LEAST_SCALE = 0.25
# Static's ``correction`` options: the share of the correction fitted, or the whole of it.
CORRECTIONS = ("fitted", "whole")


def curved_step(
    run: StaticRun,
    equilibrium: Residual,
    state: State,
    frames: Frames,
    delta: np.ndarray,
    r: np.ndarray,
    factor: Factorisation,
) -> np.ndarray | None:
    """The Newton step delta (n, 5) from ``state`` with its second-order correction (module
    docstring), or None when the step is too small to need one or the correction is not
    trusted.

    Parameters
    ----------
    run : the static solve in progress (its model, evaluation counts and info).
    equilibrium : the residual at the increment's load factor (solvers.newton.Residual).
    state : the iterate the step starts from.
    frames : the nodal frames (V1, V2), (n, 3) each, of the iteration (those of delta, r and
        the factorisation).
    delta : (n, 5) the Newton step, mm and rad: K_ff delta_f = r_f - K_fp delta_p.
    r : (n, 5) the residual at ``state``, N and N mm.
    factor : the factorisation of K_ff the step was solved with.

    Returns
    -------
    numpy.ndarray (n, 5) or None
        delta + w, w zero on the constrained DOFs.
    """
    model = run.model
    dofs = model.dofs
    size = model.element_size
    turned = float(np.abs(delta[:, 3:]).max(initial=0.0))
    moved = float(np.abs(delta[:, :3]).max(initial=0.0)) / size
    if max(turned, moved) <= CURVED_FROM:
        return None
    h = CURVATURE_PROBE
    ahead, _, _ = equilibrium.residual(dofs.advance(state, h * delta, frames), frames)
    behind, _, _ = equilibrium.residual(dofs.advance(state, -h * delta, frames), frames)
    second = (ahead - 2.0 * r + behind) / h**2
    index = dofs.free_slots
    w = factor.solve(0.5 * second.ravel()[index])
    if w is None or not np.all(np.isfinite(w)):
        return None
    flat = np.zeros(dofs.n_slots)
    flat[index] = w
    correction = flat.reshape(-1, N_COLUMNS)
    if scaled_norm(correction, size) > CURVATURE_LIMIT * scaled_norm(delta, size):
        return None
    run.info["curved_steps"] += 1
    fitted = run.solver.correction == "fitted" and not model.interactions
    if not fitted or any(block.compression_free_tangent for block in model.blocks):
        return delta + correction
    return delta + correction_scale(equilibrium, state, frames, delta, correction) * correction


def correction_scale(
    equilibrium: Residual,
    state: State,
    frames: Frames,
    delta: np.ndarray,
    correction: np.ndarray,
) -> float:
    """The share a in [LEAST_SCALE, 1] of the ``correction`` w (n, 5) at which the parabola
    through ||r(delta + a w)||^2 at a = 0, 1/2, 1 is least (module docstring); 1 where a
    residual there is not finite (the watchdog then judges the whole step, as before)."""
    dofs = equilibrium.model.dofs
    squares = []
    for share in (0.0, 0.5, 1.0):
        r, _, _ = equilibrium.residual(
            dofs.advance(state, delta + share * correction, frames), frames
        )
        squares.append(float(np.sum(r * r)))
    if not np.all(np.isfinite(squares)):
        return 1.0
    f0, f_half, f1 = squares
    curvature = 2.0 * (f0 - 2.0 * f_half + f1)  # f(a) = f0 + slope a + curvature a^2
    slope = 4.0 * f_half - 3.0 * f0 - f1
    shares = [1.0, LEAST_SCALE]  # the whole correction where the fit ties
    if curvature > 0.0:
        shares.append(float(np.clip(-slope / (2.0 * curvature), LEAST_SCALE, 1.0)))
    return min(shares, key=lambda a: f0 + slope * a + curvature * a * a)


def scaled_norm(delta: np.ndarray, size: float) -> float:
    """The norm of a generalised increment delta (n, 5) with its rotations counted as arcs
    of one element size (mm)."""
    return float(np.hypot(np.linalg.norm(delta[:, :3]), size * np.linalg.norm(delta[:, 3:])))
