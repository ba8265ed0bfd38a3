"""The stability of a state dynamic relaxation would accept (docs/theory.md §6.4e).

Why. Dynamic relaxation stops where the out-of-balance is small, and a saddle of the total
potential is as balanced as a minimum. Kinetic damping restarts the motion from rest at every
kinetic-energy peak, so a state the motion reaches with the instability's mode hardly excited
(a symmetric start, a straight strip) is accepted like any other: a 60 x 10 mm fibrous strip
clamped at one end and pushed 2 mm at the other relaxed to the straight compressed strip
(350.7 N with 4 cells across), or to an in-plane zig-zag of its node columns (5.06 N with one),
where the strip's Euler load is 0.056 N and Static leaves the same states along the buckling
mode. So an accepted state is judged as Static judges one (solvers.saddles, docs/theory.md
§6.5): the inertia of the LDL^T of its tangent K_ff on the free DOFs, the negative pivots
within the tangent's round-off of zero counted as neutral (solvers.neutral_modes). A state
with a negative eigenvalue is pushed along its lowest mode, its largest translation
solvers.stability.PUSH elements (then PUSH_SHRINK times shorter, the other side, at each next
escape), and relaxed again, at most ESCAPES times in an increment; a state still unstable after
them stops the run with a ConvergenceError naming it, never reported converged.

The cost: one assembly of the tangent and one sparse LDL^T per accepted increment (a second,
shifted one where K_ff has negative pivots, and the eigenvectors of the lowest modes where one
is unstable), against the thousands of iterations an increment takes.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from femcore.assembly import tangent_matrix
from femcore.dofs import N_COLUMNS
from femcore.model import CompiledModel
from femcore.state import State
from solvers.common import ConvergenceError
from solvers.linear import LinearSolver
from solvers.neutral_modes import judge_pivots, unstable_modes
from solvers.stability import PUSH, PUSH_SHRINK, lowest_modes

__all__ = ["ESCAPES", "StabilityJudge", "relaxed_stable"]

#: The most pushes off unstable states in one increment before the run stops.
ESCAPES = 3


class StabilityJudge:
    """The inertia of the tangent at a relaxed state, and the push off a saddle.

    Parameters
    ----------
    model : CompiledModel
    own : dict
        The element tangents of the model's parts that give one (``own_tangents``); the other
        parts' stiffness by coloured finite differences, as the Gershgorin masses take it.
    """

    def __init__(self, model: CompiledModel, own: dict):
        self.model = model
        self.own = list(own)
        self.others = [i for i in range(len(model.parts)) if i not in own]
        self.graph = model.node_graph(self.others) if self.others else None
        self.linear = LinearSolver()
        self.shifted_linear = LinearSolver()  # the shifted K_ff's (solvers.neutral_modes)
        self.factorisations = 0  # tangents factorised (info["stability_tangents"])
        self.pushes = 0  # pushes off unstable states (info["unstable_pushes"])

    def record(self, info: dict) -> None:
        """Put the counts in a result's ``info``: ``stability_tangents`` (the tangents
        factorised) and ``unstable_pushes`` (the pushes off unstable states)."""
        info["stability_tangents"] = self.factorisations
        info["unstable_pushes"] = self.pushes

    def tangent(self, state: State, frames) -> sp.csc_matrix:
        """K_ff (n_free, n_free) at ``state`` in the DOF manager's frames."""
        model, dofs = self.model, self.model.dofs
        parts = model.tangent_parts(state, self.own) if self.own else []
        k = tangent_matrix(dofs, parts or [], frames)
        if self.graph is not None:
            k = k + model.finite_difference_stiffness(state, self.others, self.graph, frames)
        index = dofs.free_slots
        return sp.csr_matrix(k)[index][:, index].tocsc()

    def unstable(self, state: State) -> tuple[int, float, np.ndarray | None]:
        """(the negative eigenvalues of K_ff at ``state`` beyond round-off, the lowest
        eigenvalue found (N/mm; 0 where none is negative), the lowest unstable mode as a
        (n_free,) unit vector or None). An LDL^T that gives no inertia (None: K_ff far from
        symmetric, a frictional contact's) counts as stable: nothing is read from it."""
        dofs = self.model.dofs
        frames = dofs.frames(state.directors)
        k_ff = self.tangent(state, frames)
        if k_ff.shape[0] == 0:
            return 0, 0.0, None
        self.factorisations += 1
        factor = judge_pivots(self.shifted_linear, k_ff, self.linear.factorise(k_ff))
        negative = factor.negative or 0
        if not negative:
            return 0, 0.0, None
        values, vectors = unstable_modes(
            k_ff, lowest_modes(k_ff, negative + factor.neutral, factor.inverse())
        )
        if values.size == 0:
            return negative, 0.0, None
        return negative, float(values[0]), vectors[:, 0]

    def pushed(self, state: State, mode: np.ndarray, escape: int) -> State | None:
        """``state`` pushed along ``mode`` (n_free,), its largest translation PUSH elements,
        PUSH_SHRINK times shorter and on the other side at each next ``escape`` (0, 1, ...);
        None where the mode moves no translation (nothing sizes a push)."""
        dofs = self.model.dofs
        index = dofs.free_slots
        translation = index % N_COLUMNS < 3
        reach = float(np.abs(mode[translation]).max(initial=0.0))
        if reach <= 0.0:
            return None
        side = 1.0 if escape % 2 == 0 else -1.0
        amplitude = side * PUSH / PUSH_SHRINK**escape * self.model.element_size / reach
        flat = np.zeros(dofs.n_slots)
        flat[index] = amplitude * mode
        return dofs.advance(state, flat.reshape(-1, N_COLUMNS), dofs.frames(state.directors))


def relaxed_stable(judge: StabilityJudge, relax, state: State, load_factor: float, increment: int):
    """``relax(state)`` (dynamic relaxation's one relaxation to equilibrium: (state,
    iterations, ratio, reactions, reaction moments)), its relaxed state judged by ``judge``
    and, where unstable, pushed along its lowest mode and relaxed again, at most ESCAPES times
    (the module docstring). Returns relax's tuple at a stable state, its iterations summed over
    the relaxations.

    Raises
    ------
    ConvergenceError
        Where the state is still unstable after ESCAPES pushes, or its mode moves no
        translation: the negative eigenvalues, the load factor and the remedies.
    """
    relaxed = relax(state)
    iterations = relaxed[1]
    for escape in range(ESCAPES + 1):
        negative, lowest, mode = judge.unstable(relaxed[0])
        if not negative:
            return (relaxed[0], iterations, *relaxed[2:])
        pushed = judge.pushed(relaxed[0], mode, escape) if mode is not None else None
        if escape == ESCAPES or pushed is None:
            raise ConvergenceError(
                f"dynamic relaxation reached an unstable equilibrium in increment {increment} "
                f"(load factor {load_factor:.4g}): its tangent stiffness has {negative} negative "
                f"eigenvalue(s) (the lowest {lowest:.3g}), a saddle of the energy, not a state "
                f"at rest, and {escape} push(es) along its buckling mode relaxed back to one. "
                "Not reported as converged: a small imperfection or out-of-plane load that "
                'starts the buckle, more increments, or kind = "static" (which follows the '
                "buckling mode) find the stable branch.",
                None,
                steps=iterations,
            )
        judge.pushes += 1
        relaxed = relax(pushed)
        iterations += relaxed[1]
    raise AssertionError("unreachable")  # (the loop returns or raises)
