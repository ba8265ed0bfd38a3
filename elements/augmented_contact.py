"""The augmented Lagrangian (Uzawa) of the node-to-tool contact of elements/contact.py, for the
static solver, Static (``Contact(augmented=True)``; docs/theory.md §9.6).

A penalty spring lets a node into the tool by its normal force over k, and a stick spring lets
a stuck node creep by its friction force over k_t (the elastic slip). Each node here carries
two multipliers in the contact's history: lambda_N (N), the normal force the spring does not
have to make, and lambda_T (N, a vector), the stick traction. The forces at fixed multipliers
are

    f_N = max(0, lambda_N + k p) n,  p = h / 2 - d the penetration,
    t = P lambda_T - k_t P (x - a),   f_T = t if |t| <= mu f_N, else mu f_N t / |t|,

(P the projector on the tool's tangent plane, a the point the node stuck to), and after each
converged solve Static updates them (Uzawa; Simo and Laursen, Computers &
Structures 42 (1992) 97; Wriggers, Computational Contact Mechanics, 2nd ed. (2006) §6.3.3):

    lambda_N <- max(0, lambda_N + k p),   lambda_T <- f_T (the trial traction on the cone),

and solves again until every pressed node's |p| and every stuck node's |P (x - a)| is within
``tolerance``: the constraint of no penetration and no slip in stick is then met to that
tolerance whatever the penalty, which only sets how many passes it takes.

How it is carried. A multiplier is the penalty spring moved: lambda_N + k p = k (h / 2 +
lambda_N / k - d), the spring of a surface lambda_N / k farther out (``surface_offset``), and
P lambda_T - k_t P (x - a) = -k_t P (x - a - lambda_T / k_t), the stick spring of an anchor
moved by lambda_T / k_t. The history's ``anchor`` holds that moved anchor, so that the forces,
the return mapping, the frozen sets and the exact tangent of elements/contact.py apply as they
are; the point the node stuck to is ``anchor - traction / k_t``. When a step is accepted a node
that slid sticks where it is, its traction the friction force it had (the anchor stays where
the spring holds that force), a new contact too if it slid, the traction of the last pass if
it stuck (none without a pass); a lost one forgets it. A new contact's anchor, the point of its
way where it touched (off the tool on a round one), is put level with the node by each pass
and when the step is accepted.
The explicit solver and dynamic relaxation never update the multipliers: there the contact
is the penalty's.

The stored energy is that of the moved springs, 1/2 (lambda_N + k p)^2 / k and the stick
spring's: the augmented Lagrangian's potential less the constant lambda^2 / 2k of each node,
so the same forces, and >= 0 as the interaction protocol asks; it reports lambda_N^2 / 2k
at a node that its multiplier alone holds on the surface, an energy the constraint does not
store.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np

from elements.contact import ContactBlock, FrictionHistory
from elements.contact_history import landing, start_anchors
from femcore.mesh import Mesh
from femcore.state import State

__all__ = ["AugmentedContactBlock", "default_tolerance"]

# The penetration and the elastic slip accepted by default, as a fraction of the contact
# thickness (of the median cell edge for a body of no thickness).
TOLERANCE_SHARE = 1e-3


def default_tolerance(mesh: Mesh, offset: np.ndarray) -> float:
    """The default ``augmented_tolerance``, mm: TOLERANCE_SHARE of the contact thickness 2 h / 2
    (its largest), or of the median cell edge where the offset is 0 (a cable)."""
    thickness = 2.0 * float(np.max(offset, initial=0.0))
    if thickness > 0.0:
        return TOLERANCE_SHARE * thickness
    edges = []
    for cells in (mesh.lines, mesh.triangles):
        if len(cells):
            corners = mesh.points[cells]
            edges.append(np.linalg.norm(corners - np.roll(corners, 1, axis=1), axis=2).ravel())
    length = float(np.median(np.concatenate(edges))) if edges else 1.0
    return TOLERANCE_SHARE * length


class AugmentedContactBlock(ContactBlock):
    """A ContactBlock whose history carries the augmented Lagrangian's multipliers (module
    docstring); ``tolerance`` (mm) the penetration and elastic slip ``augment`` accepts."""

    def __init__(self, contact, nodes, offset, n_nodes, points, area, tool_node, tolerance):
        super().__init__(contact, nodes, offset, n_nodes, points, area, tool_node)
        self.augmented_tolerance = float(tolerance)

    def surface_offset(self, history: FrictionHistory | None) -> np.ndarray:
        """h / 2 + lambda_N / k: the spring of the multiplier's surface (module docstring)."""
        if history is None or history.multiplier is None:
            return self.offset
        return self.offset + history.multiplier / self.stiffness

    def initial_history(self) -> FrictionHistory:
        """The penalty contact's history (anchors where nodes touch at the start; none without
        friction) with zero multipliers."""
        count = len(self.offset)
        history = super().initial_history()
        if history is None:  # frictionless: no anchor, only the normal multipliers
            none = np.full((count, 3), np.nan)
            history = FrictionHistory(none, np.zeros(count), np.zeros(count), 0.0)
        return replace(history, multiplier=np.zeros(count), traction=np.zeros((count, 3)))

    def thaw(self, history: Any):
        """The history without its frozen set, its multipliers kept."""
        return replace(history, active=None, sliding=None, direction=None, normal=None)

    def update_history(self, state: State, history: Any) -> Any:
        """The penalty contact's update (elements/contact.py), the multipliers carried: a node
        that slid sticks where it is with the friction force it had as its traction (its
        anchor, moved by the update to where the spring holds that force, is that traction
        over k_t from the node), a new contact that slides too; one that sticks keeps the
        traction the last ``augment`` gave it (none without a pass), a lost one has none; a
        new contact's anchor is put level with the node (elements/contact.py)."""
        updated = super().update_history(state, history)
        p, n, touching = self.touch(state, history)
        _, _, stuck, sliding = self.tangential(state, history, p, n, touching)
        where = self._positions(state) - self.tool.offset(state.load_factor)
        stick = (self.stiffness * self.stick_ratio)[:, None]
        traction = np.where(stuck[:, None], history.traction, 0.0)
        traction = np.where(sliding[:, None], stick * (updated.anchor - where), traction)
        return replace(updated, multiplier=history.multiplier.copy(), traction=traction)

    def augment(self, state: State, history: Any) -> tuple[Any, dict]:
        """The Uzawa update at a converged ``state`` (module docstring): (the history with the
        multipliers updated, {"penetration": the largest |p| of a pressed node, mm; "slip":
        the largest elastic slip |P (x - a)| of a stuck node, mm; "tolerance": mm; "within":
        both within the tolerance at ``state``, before the update}). A node is pressed when
        lambda_N + k p > 0."""
        history = self.thaw(history)
        x = self._positions(state)
        d, n = self.tool.distance(x, state.load_factor)
        k = self.stiffness
        depth = self.offset - d  # p, of either sign
        normal = history.multiplier + k * depth
        pressed = normal > 0.0
        penetration = float(np.abs(np.where(pressed, depth, 0.0)).max(initial=0.0))
        multiplier = np.maximum(normal, 0.0)
        anchor, traction, slip = history.anchor, history.traction, 0.0
        if self.friction > 0.0:
            p, n, touching = self._touching(d, n, history)
            force, s, stuck, sliding = self.tangential(state, history, p, n, touching)
            stick = (k * self.stick_ratio)[:, None]
            origin = self.tool.offset(state.load_factor)
            # (a new contact's anchor: where its way over the step touched the tool)
            anchors = start_anchors(history, x - origin, p, touching, self)
            stuck_at = anchors - history.traction / stick  # where the nodes stuck
            r = x - origin - stuck_at
            creep = r - np.sum(r * n, axis=1)[:, None] * n
            slip = float(np.linalg.norm(np.where(stuck[:, None], creep, 0.0), axis=1).max())
            held = stuck | sliding
            traction = np.where(held[:, None], force, 0.0)
            # A landing node's anchor, where it touched, is off a round tool: put it level with
            # the node (the same tangential offset s), as the accepted step's is (docs/theory.md
            # §9.2), else its spring is (R + that height) / (R + h / 2) too stiff there.
            new = held & landing(history)
            anchors = np.where(new[:, None], x - origin - s, anchors)
            moved = anchors + (traction - history.traction) / stick
            anchor = np.where(held[:, None], moved, history.anchor)
        within = max(penetration, slip) <= self.augmented_tolerance
        report = {
            "penetration": penetration,
            "slip": slip,
            "tolerance": self.augmented_tolerance,
            "within": within,
        }
        return replace(history, multiplier=multiplier, traction=traction, anchor=anchor), report
