"""Negative pivots within the tangent's round-off of zero: neutral modes, not instabilities
(solvers.static.Static, ``seek_stable``; docs/theory.md §6.5, "Neutral modes").

A tangent with a zero-energy mode has an eigenvalue that is zero in exact arithmetic and the
rounding of K_ff once computed: either sign, and its LDL^T pivot as well. A fibrous body whose
directors no support holds has one (the uniform tilt of docs/theory.md §1.7, which moves each
fibre level in its own plane): a flat strip pulled along its warp has two eigenvalues of 1e-14
to 5e-13 against a diagonal of 1e3 to 5e3, counted as 0, 1 or 2 negative pivots as the
rounding fell. Counted as an instability, the search turned the Newton steps "downhill" along
it, a component (phi . r) / |lambda| of the residual's round-off over the eigenvalue's, and the
strip converged with every director tilted 51 deg, or not at all.

An eigenvalue lambda of K_ff with unit eigenvector phi is taken as negative only below

    -sum_i phi_i^2 (ROUND_OFF |K_ii| + noise_i),

the rounding of its second variation phi . K phi: ROUND_OFF of the stiffness of the unknowns
the mode moves (each unknown against its own diagonal, so translations and rotations alike,
and a local mode of a large model against its own cells), and ``noise_i`` the error of a
tangent made by finite differences in the rows the mode moves, measured by its asymmetry (a
tangent that should be symmetric, within solvers.linear.SYMMETRY_TOLERANCE): noise_i =
sum_j |E_ij| with |E| = |K - K^T| / 2, so that |phi . E phi| <= sum_ij |E_ij| (phi_i^2 +
phi_j^2) / 2 = sum_i phi_i^2 noise_i, and diag(noise) - E is diagonally dominant, positive
semi-definite. A global noise (the largest row's) called a soft part's real negative mode
neutral for the rounding of a stiff part it does not move (1e-9 of 1e6 N/mm against -1e-3
N/mm). The count of such eigenvalues is the inertia of K_ff + diag(ROUND_OFF W + noise), W =
diag(|K_ii|) (Sylvester: the congruence D^-1/2 (K + t D) D^-1/2 = D^-1/2 K D^-1/2 + t I),
factorised only where K_ff's own LDL^T has a negative pivot.

ROUND_OFF = 1e3 eps, the factor of the force floor (solvers.force_floor): the tilt modes of the
strip above lie at 1e-16 to 3e-15 of their diagonal, the zero modes of the frictional plies of
tests/test_static_friction_start.py at 1e-19 to 1e-14; the smallest negative eigenvalue of the
tests' buckled or post-buckled states lies at 7e-12 of its diagonal (the elastica's column by
the arc length, an iterate beside its bifurcation), the next ones at 1.7e-10 and 1e-9.
"""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp

from solvers.linear import SYMMETRY_TOLERANCE

if TYPE_CHECKING:
    from solvers.linear import Factorisation, LinearSolver

__all__ = ["ROUND_OFF", "Rounding", "judge_pivots", "unstable_modes", "zero_modes"]

# The relative rounding of a second variation against the diagonal stiffness of the unknowns
# it moves (module docstring).
ROUND_OFF = 1e3 * np.finfo(float).eps


class Rounding:
    """The rounding of K_ff's second variations (module docstring): ``weights`` (n,) the
    diagonal |K_ii| (N/mm, N mm/rad^2 ...; each at least 1e-12 of the largest, so that an
    unknown without stiffness of its own is shifted too), ``noise`` (n,) each row's sum of
    |K - K^T| / 2, the antisymmetric part of a tangent meant symmetric (N/mm ...; zeros for
    one that is not: a frictional tangent's asymmetry is physics, not error)."""

    def __init__(self, k_ff: sp.spmatrix) -> None:
        k = sp.csr_matrix(k_ff)
        diagonal = np.abs(k.diagonal())
        self.weights = np.maximum(diagonal, 1e-12 * diagonal.max(initial=0.0))
        antisymmetric = abs(k - k.T)
        scale = float(np.abs(k.data).max(initial=0.0))
        largest = float(antisymmetric.data.max(initial=0.0)) if antisymmetric.nnz else 0.0
        meant_symmetric = largest <= SYMMETRY_TOLERANCE * scale
        rows = np.asarray(antisymmetric.sum(axis=1)).ravel()
        self.noise = 0.5 * rows if meant_symmetric else np.zeros_like(rows)

    def floor(self, phi: np.ndarray) -> float:
        """The rounding of phi . K phi for a unit ``phi`` (n,): an eigenvalue above minus this
        is neutral."""
        return float(phi**2 @ (ROUND_OFF * self.weights + self.noise))

    def shifted(self, k_ff: sp.spmatrix) -> sp.csc_matrix:
        """K_ff + diag(ROUND_OFF W + noise), whose negative pivots are K_ff's negative modes."""
        shift = ROUND_OFF * self.weights + self.noise
        return (k_ff + sp.diags(shift, format="csc")).tocsc()


def judge_pivots(linear: LinearSolver, k_ff: sp.spmatrix, factor: Factorisation) -> Factorisation:
    """``factor`` (K_ff's) with ``negative`` the count of its eigenvalues below the rounding of
    their second variation and ``neutral`` the negative pivots beyond it (within round-off of
    zero): the inertia of the shifted K_ff (``Rounding.shifted``) by ``linear``, a solver of its
    own (factorising there leaves ``factor``'s factors as they are). Unchanged where K_ff has
    no negative pivot or its inertia is unknown (None), or the shifted LDL^T fails."""
    if not factor.negative:
        return factor
    shifted = linear.factorise(Rounding(k_ff).shifted(k_ff))
    if shifted.negative is None:
        return factor
    unstable = min(shifted.negative, factor.negative)
    return replace(factor, negative=unstable, neutral=factor.negative - unstable)


def zero_modes(linear: LinearSolver, factor: Factorisation | None) -> int:
    """How many eigenvalues of ``factor``'s K_ff lie within the rounding of their second
    variation of zero, of either sign (module docstring): the zero-stiffness modes a stopped
    solve can name (solvers.stop_diagnosis ``neutral_hint``). ``judge_pivots`` counts only the
    negative ones (``neutral``), the others being harmless to a stability count; a zero mode
    whose rounding fell positive (the K = 0 fibrous strip on 4 x 1 cells: eigenvalues 0, 0 and
    1e-15 against a diagonal of 100) is as much a mechanism the load does not drive. The count
    is the difference of the inertias of K_ff - diag(s) and K_ff + diag(s), s the shift of
    ``Rounding.shifted`` (Sylvester, as there), each factorised by ``linear``, a solver of its
    own. An exactly singular K_ff (neither an LDL^T nor an LU of it) counts 1 where those
    inertias are unknown; 0 without ``factor``, or where the inertias are unknown otherwise
    (a frictional tangent far from symmetric has none)."""
    if factor is None:
        return 0
    singular = factor.kind == "lu" and factor._lu is None
    k_ff = factor.matrix
    rounding = Rounding(k_ff)
    shift = sp.diags(ROUND_OFF * rounding.weights + rounding.noise, format="csc")
    below = linear.factorise((k_ff - shift).tocsc()).negative
    above = linear.factorise((k_ff + shift).tocsc()).negative
    if below is None or above is None:
        return int(singular)
    return max(below - above, int(singular), factor.neutral)


def unstable_modes(k_ff: sp.spmatrix, modes: tuple[np.ndarray, np.ndarray]):
    """Of ``modes`` (eigenvalues (k,), unit eigenvectors (n, k) of solvers.stability.lowest_modes),
    those whose eigenvalue lies below the rounding of its second variation (module docstring):
    the negative modes the search may turn along or push along; the neutral ones are left out."""
    values, vectors = modes
    if values.size == 0:
        return modes
    rounding = Rounding(k_ff)
    keep = np.array([value < -rounding.floor(phi) for value, phi in zip(values, vectors.T)])
    if keep.all():
        # the arrays as they came: a copy changes their layout, and the dot products of the
        # downhill turn then round differently (a sensitive path, the fibrous column of
        # tests/test_compression_free_tangent.py, took 12 more iterations and 2 more cuts)
        return modes
    return values[keep], vectors[:, keep]
