"""The ply contact's normal law under Static as a primal-dual active set
(``PlyContact(static_law="active_set")``; docs/theory.md §9.3a, "An active set under Static").

Why. The ramped penalty (elements/ply_projection.py ``penalty_law``) has W'' = -k g / delta on
its ramp, which vanishes at the weakly active points of a sliding stack (g ~ 0, W' ~ 0): the
tangent cannot see a point step on or off, and Newton's contact-only iterations converge
linearly there (docs/theory.md §9.3a, "Where the bai-5.1 stack's Newton iterations go").
Here, while a quasi-static solver iterates, each point is either in the active set A, where
its energy is the bilateral k/2 g^2 whatever the sign of g (the perturbed Lagrangian: the
condensed multiplier lambda = -k g, a pressure where g < 0 and a pull where g > 0), or out of
it, where it has none. A is frozen within an iteration, so that the forces are smooth, the
tangent K + k G_A^T G_A exact and the energy of the fixed set the line search's merit; between
iterations (``freeze(grow=True)``, solvers/newton.py) it is chosen again by the rule of the
primal-dual active set (Hintermueller, Ito and Kunisch, SIAM J. Optim. 13 (2002) 865; the
augmented Lagrangian of Alart and Curnier, CMAME 92 (1991) 353, in its condensed form):

    A_{k+1} = {p : lambda_k + c (-g_{k+1}) > 0},   lambda_k = -k g_k on A_k, 0 off it,

c = k the point's penalty, lambda_k the multiplier stored where A_k was chosen and g_{k+1}
the gap at the new iterate (femcore.interaction ``ACTIVE_SET_HYSTERESIS``, which the
static solver's prediction of the set reads too): a point off A joins at g < 0; a pressed point
leaves only once its gap has opened by more than it was pressed in (a point the last step
pulled, lambda < 0, at once), which keeps points at nearly zero force from stepping on and
off at every iterate. A fixed point of the rule is an equilibrium of the plain unilateral
penalty k/2 min(g, 0)^2: a state converged with A frozen is checked under that law
(``thaw``, solvers/newton.py ``settle_contacts``).

Where the law applies. The block keeps the ramped penalty of its options wherever no
quasi-static solver has frozen it: the explicit solver and dynamic relaxation never call
``freeze``, so their forces are the ramp's to the bit. ``freeze`` puts the set in the
history (``FrozenSides``, the points' sides of elements/ply_sides.py with ``active`` and
``pressure``); ``thaw`` and the accepted state's ``update_history`` keep the marker with no
set (``active`` None): the unilateral plain penalty, whose equilibrium the solve reached.

The points that can be in A are those the facing search lets touch at any gap (its rules of
depth, outline, fade and sides, elements/ply_projection.py and ply_sides.py, with the gap's
own test left out: the block searches with an infinite gap tolerance and takes g <= 0 back
for every other use, sides included). Frictionless flat faces only (a ValueError otherwise:
the frictional pairs' multipliers, a return map on lambda_T, are not done).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from elements import ply_sides
from elements.ply_block import PlyContactBlock
from elements.ply_fade import point_fade
from elements.ply_projection import Facing, penalty_law
from femcore import interaction
from femcore.state import State

__all__ = ["LAWS", "ActiveSetPlyContactBlock", "FrozenSides", "ReachFacing"]

#: The normal laws a ply contact may take under Static (``PlyContact(static_law=...)``):
#: "ramp", the penalty with its stiffness ramped over delta (the explicit solver's); and
#: "active_set", this module's.
LAWS = ("ramp", "active_set")


@dataclass(frozen=True)
class FrozenSides(ply_sides.PlySides):
    """The sides of elements/ply_sides.py (``PlySides``) of a block whose normal law a
    quasi-static solver has taken over: with ``active`` (P,) bool the frozen set A and
    ``pressure`` (P,) N the multipliers lambda = -k g where it was chosen (0 off A); with
    ``active`` None the unilateral plain penalty (thawed, or at an accepted state)."""

    active: np.ndarray | None = None
    pressure: np.ndarray | None = None


@dataclass(frozen=True)
class ReachFacing(Facing):
    """A ``Facing`` whose ``touching`` holds the points of g <= 0 (as the ramp's facing) and
    ``reach`` the points that may touch at any gap; ``law`` the normal law its touching
    points take: "ramp" (the block's smoothed penalty), "plain" (k/2 min(g, 0)^2) or
    "bilateral" (k/2 g^2, the frozen set's)."""

    reaching: np.ndarray | None = None
    law: str = "ramp"


def bilateral_law(gap: np.ndarray, stiffness: np.ndarray):
    """(energy k/2 g^2 (t,) N mm, dW/dg = k g (t,) N, d2W/dg2 = k (t,) N/mm) of the points
    in the frozen set, gaps ``gap`` (t,) mm of either sign, penalties ``stiffness`` (t,) N/mm."""
    gap = np.asarray(gap, dtype=float)
    return 0.5 * stiffness * gap**2, stiffness * gap, np.array(stiffness, dtype=float)


class ActiveSetPlyContactBlock(PlyContactBlock):
    """``PlyContactBlock`` whose normal law under a quasi-static solver is the primal-dual
    active set of the module docstring; the ramped penalty elsewhere."""

    #: An attempt with the set frozen that fails is not tried again under the unilateral law
    #: (solvers/newton.py ``newton``): that law is the plain penalty, which stalls on plies
    #: laid on each other (docs/theory.md §9.3a); the increment is cut at once.
    unilateral_fallback = False
    #: The law of the first increment of each phase of Static's load path (solvers/newton.py
    #: ``opens_on_ramp``): "ramp", the explicit solver's, the history ``released``; None, the
    #: active set there too. plies-bai-5.1's default stack (benchmarks/static_plies_active_set.py):
    #: there the set changes by hundreds of points an iterate and the
    #: predicted set stalls (64 iterations and 125 cut in the first displacement increment).
    opening_law: str | None = "ramp"

    def __init__(self, *args: Any, **kwargs: Any):
        super().__init__(*args, **kwargs)
        if self.curved or self.friction > 0.0:
            raise ValueError(
                "PlyContact(static_law='active_set') takes frictionless flat faces only "
                f"(friction={self.friction!r}, surface={'curved' if self.curved else 'flat'})"
            )
        # The gap's own test, kept for every use but the set's (the ramp's sides, the
        # unilateral law); the search itself lets every point that may touch through.
        self.touch_tolerance = self.tolerance
        self.tolerance = np.inf
        self._reach_of: tuple[Facing, ReachFacing] | None = None

    # ------------------------------------------------------------------ facings
    def facing(self, state: State, second: bool = False) -> Facing:
        """``PlyContactBlock.facing`` with ``touching`` the points of g <= 0 (the ramp's
        test) and ``reaching`` those that may touch at any gap (a ``ReachFacing``); kept
        for the base facing it is made from, so that the sides' caches find one object."""
        found = super().facing(state, second)
        kept = self._reach_of
        if kept is not None and kept[0] is found:
            return kept[1]
        reaching = np.asarray(found.touching, dtype=bool)
        touching = reaching & (found.gap <= self.touch_tolerance)
        touching.setflags(write=False)
        fields = {name: getattr(found, name) for name in Facing.__dataclass_fields__}
        fields["touching"] = touching
        made = ReachFacing(**fields, reaching=reaching, law="ramp")
        self._reach_of = (found, made)
        return made

    def _held(self, state: State, history: Any, second: bool = False) -> Facing:
        """The held facing (elements/ply_sides.py) with the points ``history``'s law lets
        touch: the frozen set's among those that may touch and no side keeps off
        ("bilateral"), those of g <= 0 ("plain"), or the ramp's."""
        held = ply_sides.held_facing(self, state, history, second)
        if not isinstance(history, FrozenSides):
            return held
        assert isinstance(held, ReachFacing)  # this block's facings
        if history.active is None:
            return replace(held, law="plain")
        return replace(held, touching=self._frozen_touching(state, held, history), law="bilateral")

    def _frozen_touching(self, state: State, held: Facing, history: FrozenSides) -> np.ndarray:
        """(P,) bool: the points of the frozen set that may touch at ``held`` and no side
        keeps off."""
        assert isinstance(held, ReachFacing) and held.reaching is not None
        assert history.active is not None
        # the points the sides keep off are those of g <= 0 ``held`` no longer lets touch
        raw = self.facing(state)
        off = np.asarray(raw.touching) & ~np.asarray(held.touching)
        touching = held.reaching & ~off & history.active
        touching.setflags(write=False)
        return touching

    def _reachable(self, state: State, history: Any) -> tuple[Facing, np.ndarray]:
        """(the held facing, (P,) bool the points that may touch at any gap and no side keeps
        off) at ``state``."""
        held = ply_sides.held_facing(self, state, history)
        assert isinstance(held, ReachFacing) and held.reaching is not None
        off = np.asarray(self.facing(state).touching) & ~np.asarray(held.touching)
        return held, held.reaching & ~off

    # ------------------------------------------------------------------ the law
    def _pair_rows(self, facing: Facing) -> tuple:
        law = getattr(facing, "law", "ramp")
        if law == "ramp":
            return super()._pair_rows(facing)
        on = np.flatnonzero(facing.touching)
        tri = facing.triangle[on]
        offset = self.lever * np.column_stack([-self.upper_offset[on], self.corner_offset[tri]])
        nodes = np.column_stack([self.above[on], self.cells[tri]])
        return on, self._law(facing, on), nodes, offset

    def _law(self, facing: Facing, on: np.ndarray):
        """The law of ``facing``'s touching points ``on`` (t,): (energy, dW/dg, d2W/dg2)."""
        if getattr(facing, "law", "ramp") == "bilateral":
            return bilateral_law(facing.gap[on], self.stiffness[on])
        return penalty_law(facing.gap[on], self.stiffness[on], 0.0)

    def strain_energy(self, state: State, history: Any = None) -> float:
        if not isinstance(history, FrozenSides):
            return super().strain_energy(state, history)
        facing = self._held(state, history)
        on = np.flatnonzero(facing.touching)
        return float(np.sum(point_fade(facing, on)[0] * self._law(facing, on)[0]))

    # ------------------------------------------------------------------ the set
    def freeze(self, state: State, history: Any = None, grow: bool = False) -> tuple[Any, int]:
        """(the history with the set A frozen at ``state``, the number of points whose
        membership changed from the set ``history`` holds; all of A when it holds none).
        Without ``grow`` A is the points of g < 0 that may touch; with it, the primal-dual
        rule from the multipliers ``history`` holds (module docstring)."""
        sides = ply_sides.sides_of(history)
        if sides is None:  # no sides kept (a caller without a history): nothing to freeze
            return history, 0
        held, reachable = self._reachable(state, history)
        gap = np.asarray(held.gap, dtype=float)
        last = history.active if isinstance(history, FrozenSides) else None
        stiffness = self.stiffness
        if grow and last is not None and history.pressure is not None:
            # the set's rule (femcore.interaction): with False, g_{k+1} < 0 alone, the rule
            # with the multiplier of the same iterate, lambda_{k+1} = -k g_{k+1}, to which the
            # primal-dual rule of a condensed penalty reduces
            pull = history.pressure if interaction.ACTIVE_SET_HYSTERESIS else 0.0
            active = reachable & (pull - stiffness * gap > 0.0)
        else:
            active = reachable & (gap < 0.0)
        active.setflags(write=False)
        pressure = np.where(active, -stiffness * gap, 0.0)
        pressure.setflags(write=False)
        changed = (
            int(np.count_nonzero(active)) if last is None else int(np.count_nonzero(active != last))
        )
        frozen = FrozenSides(sides.sides, sides.faces, sides.corners, active, pressure)
        return frozen, changed

    def set_model(self, state: State, history: Any, frames: Any, dofs: Any) -> dict | None:
        """The frozen set's linear model at ``state`` for a prediction of the next set
        (solvers/contact_sets.py): None without a frozen set, else {"points": (r,) the rows of
        the points it may switch (those that may touch, off the fade: w = 1, dw = 0),
        "slots": (r, 30) int and "values": (r, 30) the entries of dg/dq in the generalised
        unknowns of ``dofs`` in the frames ``frames`` (row i's entry k at unknown slots[i, k]
        of the n 5 slots' layout; entries at one slot add up), "gap": (r,) mm, "stiffness":
        (r,) N/mm, "active": (r,) bool, "pressure": (r,) N}: a point of the set adds k g dg/dq
        to the internal forces and k dg/dq dg/dq^T (+ k g d2g/dq2) to the tangent."""
        if not isinstance(history, FrozenSides) or history.active is None:
            return None
        assert history.pressure is not None
        held, reachable = self._reachable(state, history)
        assert held.fade is not None and held.fade_gradient is not None
        plain = (held.fade == 1.0) & ~np.any(held.fade_gradient != 0.0, axis=(1, 2))
        rows = np.flatnonzero(reachable & plain)
        tri = held.triangle[rows]
        n, lam = held.normal[rows], held.weights[rows]
        nodes = np.column_stack([self.above[rows], self.cells[tri]])  # (r, 6)
        offset = self.lever * np.column_stack([-self.upper_offset[rows], self.corner_offset[tri]])
        weights = np.column_stack([self.shape[rows], -lam])  # dg/dx_j = weight_j n
        along = weights[:, :, None] * n[:, None, :]  # (r, 6, 3)
        d = self.offset_directions(state)[nodes]
        turn = offset[:, :, None] * np.cross(d, along)  # dg/dpsi_j = c_j d_j x dg/dx_j
        v1, v2 = frames
        columns = np.zeros((len(rows), 6, 5))
        columns[:, :, :3] = along
        rotating = dofs.has_rotation[nodes]
        columns[:, :, 3] = np.where(rotating, np.sum(turn * v2[nodes], axis=2), 0.0)
        columns[:, :, 4] = np.where(rotating, np.sum(turn * v1[nodes], axis=2), 0.0)
        slots = nodes[:, :, None] * 5 + np.arange(5)
        return {
            "points": rows,
            "slots": slots.reshape(len(rows), 30),
            "values": columns.reshape(len(rows), 30),
            "gap": np.asarray(held.gap[rows], dtype=float),
            "stiffness": self.stiffness[rows],
            "active": np.asarray(history.active[rows]),
            "pressure": np.asarray(history.pressure[rows]),
        }

    def with_set(
        self, history: FrozenSides, points: np.ndarray, active: np.ndarray, pressure: np.ndarray
    ) -> FrozenSides:
        """``history`` with the set's members ``active`` (r,) bool and multipliers ``pressure``
        (r,) N at the rows ``points`` (r,) (the others as they were)."""
        assert history.active is not None and history.pressure is not None
        members, multipliers = history.active.copy(), history.pressure.copy()
        members[points], multipliers[points] = active, pressure
        members.setflags(write=False)
        multipliers.setflags(write=False)
        return FrozenSides(history.sides, history.faces, history.corners, members, multipliers)

    def released(self, history: Any) -> Any:
        """``history`` without a set or the plain penalty's marker: the sides alone, under
        which this block's law is the ramp (``opening_law``)."""
        if isinstance(history, FrozenSides):
            return ply_sides.PlySides(history.sides, history.faces, history.corners)
        return history

    def thaw(self, history: Any) -> Any:
        """The history with no set: the unilateral plain penalty (module docstring)."""
        if isinstance(history, FrozenSides) and history.active is not None:
            return FrozenSides(history.sides, history.faces, history.corners)
        return history

    def update_history(self, state: State, history: Any) -> Any:
        """``PlyContactBlock.update_history``: the sides at ``state``, which keep the plain
        penalty's marker where ``history`` had it (a state the quasi-static solver
        accepted)."""
        updated = super().update_history(state, history)
        if isinstance(history, FrozenSides) and not isinstance(updated, FrozenSides):
            return FrozenSides(updated.sides, updated.faces, updated.corners)
        return updated

    def node_fields(self, state: State, history: Any = None) -> dict[str, np.ndarray]:
        fields = super().node_fields(state, history)
        if not isinstance(history, FrozenSides) or self.mirrored:
            return fields
        facing = self._held(state, history)
        on = np.flatnonzero(facing.touching)
        pressing = np.zeros(len(facing.gap))
        pressing[on] = -self._law(facing, on)[1] * point_fade(facing, on)[0]
        force = np.zeros(self.n_nodes)
        force[self.upper] = self._lumped(pressing)[self.upper]
        return {**fields, "ply_contact_force": force}
