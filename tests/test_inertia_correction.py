"""The inertia correction of Newton steps on a tangent with many negative eigenvalues
(solvers/inertia.py): past the six modes the downhill turn computes, a Newton step that climbs
(r . dq <= 0) is replaced by that of K + delta diag(|K_ii|) with the smallest listed delta that
leaves no negative pivot, a descent direction of the total potential; with six or fewer
negative modes, or a Newton step that descends already, the step is left as it was."""

import numpy as np
import pytest
import scipy.sparse as sp

from solvers.inertia import MODES, SHIFTS, convexified_step
from solvers.linear import LinearSolver


class Run:
    """What convexified_step uses of a StaticRun: its factorisation, its info and the
    dashpots of a stabilised increment (``stabilised``: a stand-in, None: none)."""

    def __init__(self, stabilised: bool = False):
        self.dashpots = object() if stabilised else None
        self.linear = LinearSolver()
        self.info = {"shifted": []}

    def factorise(self, k_ff, judge: bool = True):
        """The factorisation (``judge``: StaticRun's count of neutral pivots, which the
        shifts, far above round-off, leave out)."""
        return self.linear.factorise(k_ff)


def tangent(negative: int, size: int = 40):
    """A symmetric tridiagonal-plus-diagonal tangent with ``negative`` negative eigenvalues
    (the first unknowns softened below zero) and the others positive."""
    diagonal = np.full(size, 4.0)
    diagonal[:negative] = -0.5
    coupling = np.full(size - 1, 0.1)
    return sp.diags([coupling, diagonal, coupling], [-1, 0, 1], format="csc")


def test_a_tangent_with_many_negative_modes_gets_a_descent_step_from_the_smallest_shift():
    """Ten negative eigenvalues (more than MODES): the step solves (K + delta W) dq = r for
    the first listed delta whose K + delta W is positive definite (the one before it is not),
    and r . dq > 0, a descent direction of the potential, where K's own step is not."""
    k = tangent(10)
    assert (np.linalg.eigvalsh(k.toarray()) < 0).sum() == 10 > MODES
    rhs = np.random.default_rng(1).standard_normal(k.shape[0])
    newton = np.linalg.solve(k.toarray(), rhs)
    assert rhs @ newton < 0.0  # Newton's own step climbs here
    run = Run()
    step = convexified_step(run, k, rhs, 10, newton)
    assert step is not None
    (shift,) = run.info["shifted"]
    weights = np.diag(np.abs(k.diagonal()))
    shifted = k.toarray() + shift * weights
    assert np.linalg.eigvalsh(shifted).min() > 0.0
    earlier = SHIFTS[SHIFTS < shift]
    if earlier.size:
        assert np.linalg.eigvalsh(k.toarray() + earlier[-1] * weights).min() < 0.0
    np.testing.assert_allclose(shifted @ step, rhs, atol=1e-10)
    assert rhs @ step > 0.0


def test_a_newton_step_that_descends_already_is_kept_unless_the_increment_is_stabilised():
    """Ten negative eigenvalues, but a right-hand side on the positive modes alone (a flat
    sheet's in-plane residual, its negative modes out of plane): r . dq > 0, no shift; in a
    stabilised increment (a minimum is sought) the shifted step all the same."""
    k = tangent(10)
    rhs = np.zeros(k.shape[0])
    rhs[20:] = 1.0
    newton = np.linalg.solve(k.toarray(), rhs)
    assert rhs @ newton > 0.0
    run = Run()
    assert convexified_step(run, k, rhs, 10, newton) is None
    assert run.linear.numeric == 0
    stabilised = Run(stabilised=True)
    step = convexified_step(stabilised, k, rhs, 10, newton)
    assert step is not None and len(stabilised.info["shifted"]) == 1
    assert rhs @ step > 0.0


@pytest.mark.parametrize("negative", [None, 0, 3, MODES])
def test_a_tangent_the_downhill_turn_covers_is_left_to_it(negative):
    """Six or fewer negative pivots (or none known, a non-symmetric tangent): no step, no
    factorisation."""
    run = Run()
    k = tangent(negative or 0)
    rhs = np.random.default_rng(1).standard_normal(k.shape[0])
    newton = np.linalg.solve(k.toarray(), rhs)
    assert convexified_step(run, k, rhs, negative, newton) is None
    assert run.info["shifted"] == []
    assert run.linear.numeric == 0
