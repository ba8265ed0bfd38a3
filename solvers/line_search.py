"""The watchdog line search of Static's Newton iterations (solvers.newton; docs/theory.md
§6.5): full Newton steps as long as, within WATCHDOG iterations, one of them lowers the
residual norm below the best iterate's or the total potential energy by the Armijo fraction;
otherwise back to the best iterate and halving along its step (down to SMALLEST_STEP, or
SMALLEST_FIRST_STEP from an increment's first iterate in a model with interactions). Every
update is capped to MAX_ROTATION of director rotation and the model's size of translation
(``step_cap``)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from femcore.dofs import Frames
from femcore.model import CompiledModel
from femcore.state import State
from solvers.common import IncrementFailed

if TYPE_CHECKING:
    from solvers.newton import Residual
    from solvers.static import StaticRun

__all__ = [
    "ARMIJO",
    "MAX_ROTATION",
    "SMALLEST_FIRST_STEP",
    "SMALLEST_STEP",
    "WATCHDOG",
    "Watchdog",
    "model_extent",
    "step_cap",
]

# Armijo's sufficient-decrease fraction, the smallest line-search step, and how many full
# Newton steps the watchdog lets go by without a decrease before it backtracks.
ARMIJO = 1e-4
SMALLEST_STEP = 1.0 / 64.0
WATCHDOG = 4
# The smallest line-search step back from an increment's first iterate in a model with
# interactions (``Watchdog._backtrack``): there the tangent may hold no stiffness of a contact
# the step runs into (a smoothed penalty has none at g = 0, where plies are laid on each
# other), and the step is then longer than the contact lets it go by the ratio of the
# penalty to the structure's stiffness, 1e4-1e6 and more, which no 1/64 reaches.
SMALLEST_FIRST_STEP = 1e-9
# Largest director rotation of one Newton update (rad). Far from equilibrium the tangent of a
# layered shell can ask for director turns of several radians, which lead Newton into states
# with collapsed cells or fibres stretched by orders of magnitude, where a log-strain
# tension law still balances (bai-5.1, fibrous: |u| = 1e51 at "equilibrium").
MAX_ROTATION = 0.5


def model_extent(model: CompiledModel) -> float:
    """The model's size (mm): the diagonal of its reference bounding box, which bounds the
    translation of one update (``step_cap``); taken once per line search, not per update."""
    return float(np.linalg.norm(np.ptp(model.reference_positions, axis=0)))


def step_cap(extent: float, delta: np.ndarray, turn: float = MAX_ROTATION) -> float:
    """The factor (<= 1) that keeps an update delta (n, 5) within ``turn`` (rad; MAX_ROTATION
    unless ``Static(update_turn=...)``) of director rotation at every node and within
    ``extent`` (mm; the model's size, ``model_extent``) of translation."""
    translation = float(np.linalg.norm(delta[:, :3], axis=1).max(initial=0.0))
    rotation = float(np.linalg.norm(delta[:, 3:], axis=1).max(initial=0.0))
    cap = 1.0
    if rotation > turn:
        cap = turn / rotation
    if extent > 0.0 and translation > extent:
        cap = min(cap, extent / translation)
    return cap


class Watchdog:
    """The watchdog line search of the load path (module docstring; solvers.newton).

    The merits of an iterate are its residual norm on the free DOFs and its total potential
    Pi relative to the best iterate: Pi(x) - Pi(best) = W(x) - W(best) - (the dead loads' work
    along the straight updates since the best iterate; exact for forces, and for moments on
    each update, a rotation about a fixed axis). The strain energies W are evaluated only when
    the residual does not already show the decrease.
    """

    def __init__(
        self, run: StaticRun, equilibrium: Residual, enabled: bool, turn: float | None = None
    ):
        self.run, self.equilibrium, self.enabled = run, equilibrium, enabled
        self.turn = MAX_ROTATION if turn is None else turn  # Static(update_turn=...)
        self.extent = model_extent(run.model)
        self.free = run.model.dofs.free.ravel()
        self.best: dict | None = None  # the best iterate and its Newton step
        self.work = 0.0  # dead-load work along the updates since the best iterate
        self.misses = 0
        # the first iterate's step goes back as far as SMALLEST_FIRST_STEP with interactions
        self.deepest = SMALLEST_FIRST_STEP if run.model.interactions else SMALLEST_STEP

    def step(
        self,
        state: State,
        frames: Frames,
        delta: np.ndarray,
        r: np.ndarray,
        whole: bool,
        straight: np.ndarray | None = None,
    ):
        """The next iterate from ``state`` with Newton step delta (n, 5) and residual r (n, 5):
        (scale taken, new state, its internal forces); scale 0 when it went back.
        ``straight``: the Newton step itself when delta is its curved form
        (solvers.newton_curvature); the Armijo slope and the backtracking use it."""
        cap = self._cap(delta) if self.enabled else 1.0
        if not self.enabled or whole:
            self.best = None  # the imposed motion starts a new search
            # (the first free iterate after it keeps the deep backtracking: the imposed
            # step is taken whole and cannot back off)
            return self._take(state, frames, delta, cap)
        deepest, self.deepest = self.deepest, SMALLEST_STEP
        line = delta if straight is None else straight
        here = {
            "state": state,
            "frames": frames,
            "delta": line,
            "cap": cap if straight is None else self._cap(straight),
            "residual": float(np.linalg.norm(r.ravel()[self.free])),
            "slope": -float(r.ravel()[self.free] @ line.ravel()[self.free]),  # dPi/ds
            "energy": None,
            "deepest": deepest,  # the smallest step back to this iterate's backtracking
        }
        if self.best is None or self._better(here):
            self.best, self.misses, self.work = here, 0, 0.0
        else:
            self.misses += 1
            if self.misses >= WATCHDOG:
                return self._backtrack()
        scale, trial, forces = self._take(state, frames, delta, cap)
        if not np.isfinite(self.equilibrium.residual(trial, frames, forces)[1]):
            return self._backtrack()
        return scale, trial, forces

    def _cap(self, delta: np.ndarray) -> float:
        return step_cap(self.extent, delta, self.turn)

    def _take(self, state, frames, delta, scale):
        run = self.run
        trial = run.model.dofs.advance(state, scale * delta, frames)
        forces = run.model.internal_force(trial)
        run.counts["residual"] += 1
        self.work += scale * float(self.equilibrium.load(frames).ravel() @ delta.ravel())
        return scale, trial, forces

    def _energy(self, entry: dict) -> float:
        if entry["energy"] is None:
            entry["energy"] = self.run.energy(entry["state"])
        return entry["energy"]

    def _better(self, here: dict) -> bool:
        """A real decrease from the best iterate: the residual norm by the Armijo fraction, or
        the energy by that fraction of the best step's first-order decrease."""
        best = self.best
        assert best is not None
        if here["residual"] <= (1.0 - ARMIJO) * best["residual"]:
            return True
        if best["slope"] >= 0.0:
            return False
        before, after = self._energy(best), self._energy(here)
        drop = before - (after - self.work)
        noise = 1e-10 * (abs(before) + abs(after))
        return drop >= -ARMIJO * best["slope"] and drop > noise

    def _backtrack(self):
        """Back to the best iterate, then halve its Newton step until the residual or the
        energy falls (Armijo); IncrementFailed when none does down to SMALLEST_STEP (to
        SMALLEST_FIRST_STEP from the first iterate of a model with interactions)."""
        best = self.best
        assert best is not None
        state, frames, delta = best["state"], best["frames"], best["delta"]
        load_rate = float(self.equilibrium.load(frames).ravel() @ delta.ravel())
        scale = 0.5 * best["cap"]
        while scale >= best["deepest"] * best["cap"]:
            trial = self.run.model.dofs.advance(state, scale * delta, frames)
            r, ratio, forces = self.equilibrium.residual(trial, frames)
            if np.isfinite(ratio):
                residual = float(np.linalg.norm(r.ravel()[self.free]))
                accepted = residual <= (1.0 - ARMIJO * scale) * best["residual"]
                if not accepted and best["slope"] < 0.0:
                    change = self.run.energy(trial) - self._energy(best) - scale * load_rate
                    accepted = change <= ARMIJO * scale * best["slope"]
                if accepted:
                    self.best, self.misses, self.work = None, 0, 0.0
                    return 0.0, trial, forces
            scale *= 0.5
        raise IncrementFailed(
            "the line search found no step that lowers the energy or the residual"
        )
