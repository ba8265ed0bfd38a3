"""Inertia correction of the static solver's Newton steps on a tangent with more negative
eigenvalues than the stability search turns (solvers.static.Static, ``seek_stable``;
docs/theory.md §6.5).

On an indefinite tangent the Newton step heads for the nearest equilibrium, stable or not;
``solvers.stability.downhill`` turns its components along the negative modes downhill, but it
computes at most MODES of them (an eigen-solve per iteration). A flange that wrinkles under a
punch has more: the hemisphere drape by Static without a holder (8 cells, fibrous, c = 300)
met tangents with 7 to 34 negative eigenvalues in 175 of its 473 factorisations up to load
factor 0.6, the hoop compression of the flange against the dashpots; the modes past the sixth
kept their uphill components, and the watchdog's backtracking found no decrease of the energy
or the residual: the increments were cut.

Where Newton's own step is no descent direction of the total potential (r . dq <= 0: it
climbs along the modes), the step is that of the shifted tangent K_ff + delta W, W =
diag(|K_ii|) (each unknown shifted in proportion to its own stiffness, so translations and
rotations alike), with the smallest delta of SHIFTS whose LDL^T has no negative pivot (the
inertia correction of modified Newton methods: Nocedal and Wright, Numerical Optimization,
2nd ed. (2006) §3.4; Waechter and Biegler, Math. Prog. 106 (2006) 25). A positive definite
matrix makes the step a descent direction (r . dq > 0), which the line search can always
shorten to a decrease. Only the step changes: the residual is the model's, so a converged
state is an exact equilibrium, and near a stable one the tangent has no negative pivot and
Newton is Newton again.

Which steps: in a stabilised increment (``Static(stabilise=c)``, solvers.stabilisation) every
step on such a tangent, for the increment is then the minimum of the total potential plus the
dashpots' and a blank whose flange wrinkles is to settle in a minimum (the 8-cell drape with
its holder: no cut, where the sixth increment was cut once and its attempt took 98
iterations; with the climbing steps alone, the same cut). Without stabilisation only the steps
that climb: a flat fabric sheared in its plane (bias extension, picture frame) has 8 or more
negative out-of-plane modes that its in-plane residual does not load, its Newton steps descend,
and shifting them (which shortens every component of the step) made its increments fail; the
saddle is the path there (solvers.stability keeps such saddles).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp

if TYPE_CHECKING:
    from solvers.static import StaticRun

__all__ = ["MODES", "SHIFTS", "convexified_step"]

# The negative modes solvers.stability.downhill turns (lowest_modes computes at most these).
MODES = 6
# The shifts tried, relative to each unknown's own diagonal stiffness, smallest first.
SHIFTS = 10.0 ** np.arange(-6.0, 3.0)


def convexified_step(
    run: StaticRun, k_ff, rhs: np.ndarray, negative: int | None, newton: np.ndarray
):
    """The Newton step of the shifted tangent (module docstring), or None when K_ff has at
    most MODES negative eigenvalues (``downhill`` turns them all), when the increment is not
    stabilised and Newton's own step is a descent direction already (r . dq > 0), or when no
    shift of SHIFTS makes K_ff positive definite.

    run : the StaticRun (its ``factorise``); k_ff : (n_free, n_free) sparse tangent of the
    free unknowns; rhs : (n_free,) right-hand side, N and N mm; negative : the negative
    pivots of K_ff's LDL^T (None: unknown, a non-symmetric tangent); newton : (n_free,)
    K_ff's own step.

    Returns (n_free,) the step, mm and rad, with the shift used in ``run.info["shifted"]``.
    """
    if negative is None or negative <= MODES:
        return None
    stabilised = getattr(run, "dashpots", None) is not None
    if not stabilised and float(rhs @ newton) > 0.0:
        return None
    diagonal = np.abs(k_ff.diagonal())
    weights = np.maximum(diagonal, 1e-12 * diagonal.max(initial=0.0))
    for shift in SHIFTS:
        # the shifts lie far above round-off: the pivots' own count (solvers.neutral_modes)
        shifted = (k_ff + sp.diags(shift * weights, format="csc")).tocsc()
        factor = run.factorise(shifted, judge=False)
        if factor.negative != 0:
            continue
        step = factor.solve(rhs)
        if step is not None:
            run.info["shifted"].append(float(shift))
            return step
    return None
