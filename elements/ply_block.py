"""The bound ply contact (``PlyContact.bind``, elements/ply_contact.py, whose docstring
describes the mechanics): its contact points and their penalties, the search of the facing
triangles, the normal loads, the friction's history and the protocol's extras (springs, node
fields). The loads' exact tangent is in elements/ply_block_tangent.py, the curved faces'
projection and loads in elements/ply_curved.py, the friction's return mapping in
elements/ply_friction.py, the facing search and the penalty law in elements/ply_projection.py.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

import numpy as np
from scipy.spatial import cKDTree

from elements import (
    ply_between,
    ply_block_tangent,
    ply_commit_pass,
    ply_curved,
    ply_curved_friction,
    ply_face_points,
    ply_facing_front,
    ply_friction,
    ply_friction_kernels,
    ply_landing_kept,
    ply_load_kernels,
    ply_projection,
    ply_sides,
    ply_slip,
    ply_springs,
    ply_surface,
)
from elements.contact_penalty import PENALTY_SHARE, automatic_penalty
from elements.kept_bits import same_bits
from elements.ply_fade import OutlineTree, fade_length, outline_segments
from elements.ply_fade import point_fade as _fade  # the name the block's loads call
from elements.ply_friction import PlyFrictionHistory, Sliding
from elements.ply_projection import (
    MARGIN,
    Facing,
    closest_facing,
    edge_ids,
    open_edges,
    penalty_law,
)
from elements.ply_search import FacingSearch
from elements.ply_start import check_ply_start
from elements.ply_topology import FaceTopology
from elements.ply_wedge import WedgeCuts
from femcore.assembly import CellTangent, TangentPart
from femcore.field_names import name_components
from femcore.interaction import Body, InteractionBlock
from femcore.rotation import cross
from femcore.state import State

__all__ = ["DOFS", "PENALTY_SHARE", "RULES", "PlyContactBlock"]

name_components("ply_slip_vector", ("x", "y", "z"))  # global axes, as the displacement's

#: The degrees of freedom a ply contact acts on: the positions and the directors' rotations.
DOFS = ("ux", "uy", "uz", "alpha", "beta")
#: The loads' facings carry the gap's Hessian while Newton's tangents follow them at their
#: state (``PlyContactBlock.facing``); False: the tangent makes its facing again (the same
#: values: benchmarks/static_plies.py compares the two).
HESSIAN_WITH_LOADS = True
#: The facing before the last kept too (``PlyContactBlock.facing``); False: the last alone, as
#: before (benchmarks/ply_static_parts.py compares the two).
KEEP_FACING_BEFORE = True
#: Contact points of an upper triangle: name -> (barycentric coordinates (Q, 3), weights
#: (Q,) summing to 1).
RULES = {
    "centroid": (np.full((1, 3), 1.0 / 3.0), np.ones(1)),
    "gauss": (
        np.array([[2 / 3, 1 / 6, 1 / 6], [1 / 6, 2 / 3, 1 / 6], [1 / 6, 1 / 6, 2 / 3]]),
        np.full(3, 1.0 / 3.0),
    ),
    "vertices": (np.eye(3), np.full(3, 1.0 / 3.0)),
    # the corners too, but one point per node (PlyContactBlock: the same loads)
    "nodes": (np.eye(3), np.full(3, 1.0 / 3.0)),
}


class PlyContactBlock(InteractionBlock):
    """The bound ply contact: one row of ``connectivity`` per contact point, the corners of
    its upper triangle then the corners of the lower triangles it faces in the reference
    state (the node graph of a finite-difference tangent while the plies have slid less than
    a cell; the block's own ``tangent`` follows the sliding).

    Attributes
    ----------
    above : (P, 3) int
        Each point's upper triangle's corners.
    shape : (P, 3) float
        N_j of each point at those corners.
    stiffness : (P,) float
        k_p, N/mm (NaN until ``calibrate`` when the penalty is automatic).
    node_stiffness : (s,) float
        k_j of the upper nodes ``upper``, N/mm.
    smoothing : float
        delta, mm.
    along_normals : bool
        The faces lie along the plies' nodal normals (``faces="normal"``).
    lever : float
        1 with faces along the directors, 0 along the normals: the factor of the offsets in
        the moments on the directors and in their tangent.
    """

    dofs = DOFS
    reach = 1
    n_tools = 0

    def __init__(
        self,
        contact: Any,
        above: np.ndarray,
        cells: np.ndarray,
        upper_offset: np.ndarray,
        lower_offset: np.ndarray,
        smoothing: float,
        body: Body,
    ):
        coordinates, weights = RULES[contact.rule]
        count = len(weights)
        self.above = np.repeat(above, count, axis=0)  # (P, 3)
        self.shape = np.tile(coordinates, (len(above), 1))  # (P, 3)
        # At the corners ("vertices") the points of a node's triangles all lie at the node and
        # face, touch and slide alike: one point per node ("nodes"), in the first of its
        # triangles, carrying their summed shares (the node's whole penalty), gives the same
        # energy, forces and tangent for a sixth of the searches on a structured mesh.
        at_nodes = contact.rule == "nodes"
        if at_nodes:
            node = self.above[np.arange(len(self.above)), np.argmax(self.shape, axis=1)]
            kept = np.unique(node, return_index=True)[1]
            self.above, self.shape = self.above[kept], self.shape[kept]
        self.upper = np.unique(above)
        self.cells = cells
        self.n_nodes = body.n_nodes
        # Faces along the nodal normals: the plies' own triangles give them, and the contact
        # leaves the directors alone (a lever of 0 on the moments and their tangent).
        self.along_normals = contact.faces == "normal"
        self.curved = contact.surface == "curved"
        self.lever = 0.0 if self.along_normals else 1.0
        # the plies' own triangles, in their own orientation, give the nodal normals (the
        # points' ply's and the facing ply's): the mirrored pass turned its facing triangles
        self.mirrored = contact.points == "lower"
        self._own_triangles = np.vstack([above, cells[:, [0, 2, 1]] if self.mirrored else cells])
        self.smoothing = float(smoothing)
        self.upper_offset = np.asarray(upper_offset, dtype=float)[self.above]  # (P, 3)
        self.corner_offset = np.asarray(lower_offset, dtype=float)[cells]  # (m, 3)
        # the lower face's outline, which its triangles' planes reach past (ply_projection.py)
        self.outline = open_edges(cells)
        # its edges' end nodes and offsets (E, 2): the fade's distance to the outline
        # (elements/ply_fade.py) moves with them
        segment_rows, segment_ends = outline_segments(self.outline)
        self.outline_nodes = cells[segment_rows[:, None], segment_ends]
        self.outline_offsets = self.corner_offset[segment_rows[:, None], segment_ends]
        # its edges' ids, shared by neighbours: the pseudonormals that sign a gap to an edge
        # or a vertex (ply_projection.py, "The sign at an edge")
        self.edges = edge_ids(cells)
        # the rest of its topology the search reads at every call (its half-edges, the edges'
        # and vertices' tables of the pseudonormals, the outline's vertices and edges):
        # elements/ply_topology.py
        self.topology = FaceTopology.of(cells, self.outline, self.edges)
        # the KD-tree of its outline's edges (the fade's nearest edge), kept while they move
        # little (elements/ply_fade.py, ``OutlineTree``)
        self.outline_tree = OutlineTree()
        # the deepest a point touches: both faces' half thicknesses (ply_projection.py,
        # "Deeper than the plies")
        self.depth = float(np.abs(self.upper_offset).max() + np.abs(self.corner_offset).max())
        # the facing search (elements/ply_search.py), or the nearest centroids of before
        self.candidates = (
            None if contact.candidates is None else min(contact.candidates, len(cells))
        )
        # The points' shares of their corners' penalties (elements/ply_contact.py, "Penalty"):
        # (P, s).
        x = body.mesh.points
        sides = np.cross(x[above[:, 1]] - x[above[:, 0]], x[above[:, 2]] - x[above[:, 0]])
        area = 0.5 * np.linalg.norm(sides, axis=1)
        lumped = np.bincount(above.ravel(), np.repeat(area / 3.0, 3), self.n_nodes)
        if at_nodes:  # sum over the node's triangles of (A / 3) / (sum A / 3)
            self._share = self.shape.copy()
        else:
            share = np.repeat(area, count) * np.tile(weights, len(above))
            self._share = share[:, None] * self.shape / lumped[self.above]  # (P, 3)
        self._corner_rows = np.searchsorted(self.upper, self.above)  # (P, 3) rows of upper
        given = contact.penalty
        self.node_stiffness = np.full(len(self.upper), np.nan if given is None else float(given))
        self.stiffness = self._point_stiffness()
        self.friction = contact.friction
        self.stick = contact.stick
        # the critical step without contact (``calibrate``): the springs' reach (ply_springs.py)
        self.calibrated_dt = float("inf")
        # the lumped masses the springs weigh their nodes by (elements/ply_springs.py)
        self.calibrated_mass: np.ndarray | None = None
        reference = State(
            body.mesh.points.copy(),
            body.directors.copy(),
            np.zeros((self.n_nodes, 3)),
            np.zeros((self.n_nodes, 3)),
        )
        self._reference = reference
        self.slip_anchors = ply_slip.anchor(
            reference.positions,
            self.offset_directions(reference),
            self.upper,
            np.asarray(upper_offset, dtype=float)[self.upper],
            cells,
            self.corner_offset,
        )
        # the node graph: the three nearest centroids' triangles in the reference state
        p, y = self._faces(reference)
        # the growths' cuts past outline vertices of three or more triangles, fixed in their
        # triangles' barycentric coordinates here (elements/ply_wedge.py)
        self.cuts = WedgeCuts.of(y, cells, self.outline, np.where(self.outline, MARGIN, 0.0))
        self.search = FacingSearch.of(y, self.outline, self.cuts)
        # the fade's length past the outline, mm: FADE of the least height of the outline
        # triangles in the reference state (elements/ply_fade.py, ``fade_length``)
        self.fade_length = fade_length(y, self.outline)
        near = np.asarray(cKDTree(y.mean(axis=1)).query(p, k=min(3, len(cells)))[1])
        near = near.reshape(len(p), -1)
        self.connectivity = np.column_stack([self.above, cells[near].reshape(len(self.above), -1)])
        self.lower_nodes = np.unique(cells)
        # Without smoothing, plies laid on each other (g = 0 up to the rounding of the
        # offsets) count as touching, so that Newton has the contact's stiffness from its
        # first iteration (the force, k min(g, 0), is still zero there); with it, W'' = 0 at
        # g = 0 anyway.
        size = float(np.ptp(body.mesh.points, axis=0).max(initial=0.0)) or 1.0
        self.tolerance = 0.0 if self.smoothing > 0 else 1e-9 * size
        # the loads' facings computed with the gap's Hessian for the tangent that follows
        # them (``facing``), and whether the last one with it served a tangent
        self._hessian_with_loads = False
        self._hessian_used = False
        # the friction's return mapping from the history last committed, at its state, which
        # the next loads take (elements/ply_friction_kernels.py ``updated_history``)
        self._next_sliding: tuple | None = None
        # the next loads made with that mapping (elements/ply_commit_pass.py ``kept_loads``)
        self._next_loads: tuple | None = None
        self._held_at: tuple | None = None  # the last facing held by sides (ply_sides.py)
        # the probes of the plies between a pair that are not neighbours, each the same
        # points on one of them (``PlyContact.bind``, elements/ply_between.py); none: a pair of
        # neighbours, its facing as it was
        self.between: tuple[PlyContactBlock, ...] = ()

    def check_start(self) -> None:
        """Refuse plies that start through each other, report a visible overlap
        (elements/ply_start.py); called once when the model is compiled."""
        size = float(np.ptp(self._reference.positions, axis=0).max(initial=0.0)) or 1.0
        check_ply_start(self, self.facing(self._reference), 1e-9 * size)

    def _point_stiffness(self) -> np.ndarray:
        return np.sum(self._share * self.node_stiffness[self._corner_rows], axis=1)

    def held_directions(self) -> tuple[np.ndarray, np.ndarray]:
        """None against the ground: the gap and the slip between two plies do not change when
        the whole stack moves as one (what holds the stack are its supports and tools)."""
        return np.zeros(0, dtype=np.int64), np.zeros((0, 3))

    def calibrate(self, mass: np.ndarray, stable_dt: float, penalty_step=None) -> None:
        # the springs' reach until the step's next evaluation (elements/ply_springs.py)
        self.calibrated_dt = float(stable_dt)
        self.calibrated_mass = np.asarray(mass, dtype=float).copy()
        # the automatic penalty (elements/ply_contact.py, "Penalty"), on the step at the
        # closed-form rotary inertia where it is given (elements/contact_penalty.py)
        if np.isnan(self.node_stiffness).any():
            self.node_stiffness = automatic_penalty(mass[self.upper], stable_dt, penalty_step)
            self.stiffness = self._point_stiffness()

    def set_penalty(self, node_stiffness: np.ndarray) -> None:
        """The upper nodes' penalties k_j (u,) N/mm from now on, the points' with them (a
        Static increment's soft start, ``softened_penalty``)."""
        self.node_stiffness = np.asarray(node_stiffness, dtype=float)
        self.stiffness = self._point_stiffness()

    @contextmanager
    def softened_penalty(self, share: float) -> Iterator[bool]:
        """femcore.interaction: a frictionless ply contact's node penalties k_j times
        ``share`` inside the block, the points' with them (``set_penalty``), and k_j restored
        after it; a frictional one keeps its penalty (its stick anchors and return mapping
        hold the penalty's history: solvers/penalty_start.py)."""
        if self.friction != 0.0:
            yield False
            return
        kept = self.node_stiffness
        try:
            self.set_penalty(share * kept)
            yield True
        finally:
            self.set_penalty(kept)

    @contextmanager
    def stiff_stick(self) -> Iterator[bool]:
        """femcore.interaction: a frictional contact's stick spring k_p at any normal force
        (``stick="penalty"``) inside the block where it is the normal law's W''(g), which
        vanishes at zero penetration (plies laid on each other, not yet pressed: no stick
        stiffness at Newton's first iterate); restored after it."""
        if self.friction == 0.0 or self.stick == "penalty":
            yield False
            return
        kept = self.stick
        try:
            self.stick = "penalty"
            yield True
        finally:
            self.stick = kept

    def gaps_decide(self, history: Any) -> bool:
        """femcore.interaction: True without a history and with the sides alone
        (elements/ply_sides.py ``PlySides``, the set of the active set's ``FrozenSides``
        included): the loads at any state are then the gaps' alone, the sides held until a
        state is accepted; not with friction's history (its anchors)."""
        return history is None or isinstance(history, ply_sides.PlySides)

    # ------------------------------------------------------------------ search
    def offset_directions(self, state: State) -> np.ndarray:
        """(n, 3) the unit directions along which the faces lie at ``state``: the directors,
        or with ``faces="normal"`` the area-weighted normals of each ply's triangles (zero off
        the plies)."""
        if not self.along_normals:
            return state.directors
        x, tri = state.positions, self._own_triangles
        # a step asks for them some ten times at the same positions (the search, the loads,
        # the friction): kept for the last positions, compared by their bits (a caller may
        # move the same array in place: elements/kept_bits.py), read-only
        kept = getattr(self, "_directions_at", None)
        if kept is not None and same_bits(kept[0], x):
            return kept[1]
        if self.curved:  # the curved surface's own normals (elements/ply_surface.py)
            directions = ply_surface.nodal_normals(x, tri, self.n_nodes)[0]
        elif ply_projection.COMPILED:  # the same bits (elements/ply_face_points.py)
            directions = ply_face_points.offset_normals(x, tri, self.n_nodes)
        else:
            sides = cross(x[tri[:, 1]] - x[tri[:, 0]], x[tri[:, 2]] - x[tri[:, 0]])
            flat = tri.ravel()
            summed = np.column_stack(
                [np.bincount(flat, np.repeat(sides[:, k], 3), self.n_nodes) for k in range(3)]
            )
            length = np.linalg.norm(summed, axis=1)
            directions = summed / np.where(length > 0.0, length, 1.0)[:, None]
        directions.setflags(write=False)
        self._directions_at = (x.copy(), directions)
        return directions

    def surface_normals(self, state: State) -> np.ndarray:
        """(n, 3) the unit nodal normals of the curved faces (elements/ply_surface.py)."""
        return ply_surface.nodal_normals(state.positions, self._own_triangles, self.n_nodes)[0]

    def _faces(self, state: State) -> tuple[np.ndarray, np.ndarray]:
        """Contact points p (P, 3) and offset lower corners y (m, 3, 3), mm (read-only)."""
        # a step asks for them four times at the same state (the search, the friction's
        # return mapping and loads, the committed history): kept for the last positions and
        # directors, compared bit for bit as the facing is
        kept = getattr(self, "_faces_at", None)
        if (
            kept is not None
            and same_bits(kept[0], state.positions)
            and same_bits(kept[1], state.directors)
        ):
            return kept[2], kept[3]
        x, d = state.positions, self.offset_directions(state)
        if ply_projection.COMPILED and not self.curved:  # the same bits (ply_face_points.py)
            p, y, finite = ply_face_points.face_points(
                x, d, self.above, self.upper_offset, self.shape, self.cells, self.corner_offset
            )
            return self._kept_faces(state, p, y, finite)
        corners = x[self.above] - self.upper_offset[..., None] * d[self.above]
        if self.curved:  # on the upper ply's own curved face (elements/ply_surface.py)
            normals = ply_surface.nodal_normals(x, self._own_triangles, self.n_nodes)[0]
            p = ply_surface.surface_point(corners, normals[self.above], self.shape)[0]
        else:
            p = np.einsum("pj,pji->pi", self.shape, corners)
        y = x[self.cells] + self.corner_offset[:, :, None] * d[self.cells]
        return self._kept_faces(state, p, y, bool(np.isfinite(p).all() and np.isfinite(y).all()))

    def _kept_faces(self, state: State, p: np.ndarray, y: np.ndarray, finite: bool):
        """``_faces``' p and y, kept for ``state`` (read-only); a ValueError where some are
        not finite."""
        if not finite:
            # the searches' own errors differ with the block's size (a k-d tree's "x must be
            # finite", the small search's empty rows): one message that names the cause
            raise ValueError(
                "the plies' positions or directors hold NaN or infinite values: the ply "
                "contact cannot find the faces their points touch (a diverged state)"
            )
        p.setflags(write=False)
        y.setflags(write=False)
        self._faces_at = (state.positions.copy(), state.directors.copy(), p, y)
        return p, y

    def _candidates(self, state: State):
        """The points p (P, 3), their candidate triangles (P, K) and the lower corners y
        (m, 3, 3) at ``state``."""
        p, y = self._faces(state)
        if self.candidates is None:  # curved faces: made at this state alone (ply_search.py)
            return p, (self.search.fresh if self.curved else self.search.near)(p, y), y
        _, near = cKDTree(y.mean(axis=1)).query(p, k=self.candidates)
        return p, np.asarray(near).reshape(len(p), self.candidates), y

    def facing(self, state: State, second: bool = False) -> Facing:
        """Each contact point's facing triangle, gap, normal and projection at ``state``
        (elements/ply_projection.py: the nearest of the candidates), with ``second`` the gap's
        Hessian where a point faces an edge or a vertex (flat faces)."""
        # a step asks twice at the same state (the loads, then the friction's history at the
        # committed state, the next step's loads): kept for the last state, compared by its
        # bits (a caller may move the same arrays in place), read-only. A facing with the
        # Hessian serves one without: ``second`` adds it and changes nothing else.
        asked = second
        kept = getattr(self, "_facing_at", None)
        same = (
            kept is not None
            and same_bits(kept[1], state.positions)
            and same_bits(kept[2], state.directors)
        )
        if kept is not None and same and (kept[0] or not second):
            self._hessian_used |= second
            return kept[3]
        # Newton's watchdog asks at its trial, its best iterate's energy, the trial again (a
        # sixth of the coarse plies-bai-5.1's facings): the one before the last is kept and
        # taken back as the last (not once ``_facing_at`` is set to None: asked afresh).
        before = getattr(self, "_facing_before", None)
        if (
            KEEP_FACING_BEFORE
            and kept is not None
            and not same
            and before is not None
            and (before[0] or not second)
            and same_bits(before[1], state.positions)
            and same_bits(before[2], state.directors)
        ):
            self._facing_before, self._facing_at = kept, before
            self._hessian_used |= second
            return before[3]
        # Newton's tangent follows its force pass at the same state: there the facing of
        # the loads was made again with the Hessian (half the ply contact's facings of a
        # Static solve). Once a tangent finds the loads' facing at its state, the loads'
        # facings carry the Hessian, until one is left unused by a tangent (explicit steps,
        # which ask for a tangent only with the stable step's bound).
        if same and second:
            self._hessian_with_loads = HESSIAN_WITH_LOADS
        elif kept is not None and kept[0] and not self._hessian_used:
            self._hessian_with_loads = False
        second = second or self._hessian_with_loads
        self._hessian_used = asked
        # a state not seen before: its faces, ``toward`` and the lists' moves in one compiled
        # call where it serves (elements/ply_facing_front.py; None: the chained calls)
        begun = ply_facing_front.begun(self, state, choose=not second)
        if isinstance(begun, Facing):  # the choice made in that call too
            found = begun
        else:
            found = self._found(state, second, begun)
        # a pair that is not neighbours: silent at the points facing a ply between
        # (elements/ply_between.py), for every consumer of this facing alike
        found = ply_between.shielded(self.between, state, found, self.curved)
        for value in vars(found).values():
            if isinstance(value, np.ndarray):
                value.setflags(write=False)
        self._facing_before = kept
        self._facing_at = (second, state.positions.copy(), state.directors.copy(), found)
        return found

    def _found(self, state: State, second: bool, begun: tuple | None) -> Facing:
        """``facing``'s new Facing at ``state`` from ``begun``'s (p, near, y, toward) (None:
        the chained calls')."""
        p, near, y = self._candidates(state) if begun is None else begun[:3]
        if self.curved:  # the nearest of the candidates' curved patches (elements/ply_curved.py)
            found = ply_curved.curved_facing(self, state, p, y, near)
        else:
            # the points' plies' side: their faces' offsets from the mid-surfaces point away
            # from the lower ply (x - a d with a > 0 above it, the mirrored pass's -b below it)
            found = closest_facing(
                p,
                y,
                near,
                self.tolerance,
                self.outline,
                second,
                depth=self.depth,
                toward=ply_facing_front.toward(self, state) if begun is None else begun[3],
                fade_distance=self.fade_length,
                topology=self.topology,
                outline_tree=self.outline_tree,
                cuts=self.cuts,
            )
        return found

    # ------------------------------------------------------------------ loads
    def _pair_loads(self, state: State, facing: Facing):
        """Per touching point: node rows (t, 6) (the upper triangle's corners, the facing
        triangle's corners), forces (t, 6, 3) N, moments (t, 6, 3) N mm (dW/dx and dW/dpsi),
        the points' rows (t,), the signed offsets c (t, 6) (z = x + c d) and the law's
        (energy, dW/dg, d2W/dg2), each (t,)."""
        on, law, nodes, offset = self._pair_rows(facing)
        n, lam = facing.normal[on], facing.weights[on]
        fade, fading = _fade(facing, on)
        # the energy w W(g) past the outline (elements/ply_fade.py): d(w W)/dz = w W' dg/dz +
        # W dw/dz
        on_face = (fade * law[1])[:, None] * n + law[0][:, None] * fading[:, 0]  # dW/dp
        forces = np.concatenate(
            [
                self.shape[on][:, :, None] * on_face[:, None, :],
                -(fade * law[1])[:, None, None] * lam[:, :, None] * n[:, None, :]
                + law[0][:, None, None] * fading[:, 1:4],
            ],
            axis=1,
        )
        d = self.offset_directions(state)[nodes]  # (t, 6, 3)
        # p = sum N_j (x_j - a_j d_j), y_k = x_k + b_k d_k: dW/dpsi = c d x dW/dx.
        moments = offset[:, :, None] * cross(d, forces)
        return nodes, forces, moments, on, offset, law

    def _pair_rows(self, facing: Facing) -> tuple:
        """The touching points' rows (t,), the law's (energy, dW/dg, d2W/dg2) (t,) each, their
        node rows (t, 6) and signed offsets c (t, 6) (``_pair_loads``)."""
        on = np.flatnonzero(facing.touching)
        tri = facing.triangle[on]
        offset = self.lever * np.column_stack([-self.upper_offset[on], self.corner_offset[tri]])
        law = penalty_law(facing.gap[on], self.stiffness[on], self.smoothing)
        return on, law, np.column_stack([self.above[on], self.cells[tri]]), offset

    def fade_ends(self, facing: Facing, on: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The node ids (t, 2) and signed offsets (t, 2) (y = x + c d) of the ends a, b of the
        outline's edge nearest each point ``on`` (t,), which its fade moves with
        (elements/ply_fade.py). Where the fade does not move with them (dw/dz = 0: w = 1 off
        the outline's band, or no nearest edge), the point's own facing corners y_1, y_2
        instead: the tangent's and the loads' node lists then hold no node the point does
        not act on (the outline's first edge there tied every such point to two far nodes,
        in the node graph and the band the solver factorises)."""
        tri = facing.triangle[on]
        nodes = self.cells[tri, :2]
        offset = self.lever * self.corner_offset[tri, :2]
        if facing.fade_edge is None or facing.fade_gradient is None or not len(self.outline_nodes):
            return nodes, offset
        edge = facing.fade_edge[on]
        moving = (edge >= 0) & np.any(facing.fade_gradient[on] != 0.0, axis=(1, 2))
        chosen = np.maximum(edge, 0)
        nodes = np.where(moving[:, None], self.outline_nodes[chosen], nodes)
        offset = np.where(moving[:, None], self.lever * self.outline_offsets[chosen], offset)
        return nodes, offset

    def _end_loads(self, state: State, facing: Facing, on: np.ndarray, law) -> tuple:
        """The fade's forces W dw/da, W dw/db (t, 2, 3) N on the ends of the outline's edge
        nearest each touching point ``on`` (t,), their nodes (t, 2) and moments (t, 2, 3)."""
        nodes, offset = self.fade_ends(facing, on)
        forces = law[0][:, None, None] * _fade(facing, on)[1][:, 4:]
        moments = offset[:, :, None] * cross(self.offset_directions(state)[nodes], forces)
        return nodes, forces, moments

    def _frictional(self, history: Any) -> bool:
        return isinstance(history, PlyFrictionHistory) and self.friction > 0.0

    def _held(self, state: State, history: Any, second: bool = False) -> Facing:
        """``facing`` with the points ``history``'s sides keep off not touching."""
        return ply_sides.held_facing(self, state, history, second)

    def normal_law(self, gap: np.ndarray, stiffness: np.ndarray):
        """``penalty_law`` of the points with gaps ``gap`` and stiffnesses ``stiffness`` at this
        block's smoothing: (energy, dW/dg, d2W/dg2)."""
        return penalty_law(gap, stiffness, self.smoothing)

    def touching(self, state: State, history: Any = None) -> np.ndarray:
        """(P,) bool: the points that touch at ``state``, those ``history``'s sides keep off
        their faces not (the protocol's ``touching``)."""
        return self._held(state, history).touching.copy()

    def friction_state(
        self, state: State, history: PlyFrictionHistory | None, facing: Facing | None = None
    ) -> Sliding:
        """The return mapping at ``state`` (elements/ply_friction.py; compiled on flat faces,
        the same bits: elements/ply_friction_kernels.py)."""
        if ply_projection.COMPILED:
            return ply_friction_kernels.friction_state(self, state, history, facing)
        return ply_friction.friction_state(self, state, history, facing)

    def internal_force(self, state: State, history: Any = None):
        facing = self._held(state, history)
        if self._frictional(history):
            history = ply_landing_kept.landed_at(self, state, history, facing)
        if ply_projection.COMPILED and not self.curved:  # the same bits (ply_load_kernels.py)
            if not self._frictional(history):  # (law: a frozen active set's, ply_active_set.py)
                law = getattr(facing, "law", "ramp")
                return ply_load_kernels.ply_loads(self, state, facing, law=law)
            # made in the commit's history pass where it served this history and facing
            # (elements/ply_commit_pass.py: the same bits)
            kept = ply_commit_pass.kept_loads(self, history, facing)
            if kept is not None:
                return kept
            sliding = self.friction_state(state, history, facing)
            return ply_load_kernels.ply_loads(self, state, facing, sliding, history.anchor)
        if self.curved:
            force, moment = ply_curved.curved_loads(self, state, facing)
            nodes = np.zeros((0, 6), dtype=np.int64)
            forces = moments = np.zeros((0, 6, 3))
        else:
            force, moment = np.zeros((self.n_nodes, 3)), np.zeros((self.n_nodes, 3))
            nodes, forces, moments, on, _, law = self._pair_loads(state, facing)
            ends = self._end_loads(state, facing, on, law)
            for axis in range(3):
                force[:, axis] += np.bincount(
                    ends[0].ravel(), ends[1][..., axis].ravel(), self.n_nodes
                )
                moment[:, axis] += np.bincount(
                    ends[0].ravel(), ends[2][..., axis].ravel(), self.n_nodes
                )
        if self._frictional(history) and self.curved:  # elements/ply_curved_friction.py
            sliding = self.friction_state(state, history, facing)
            extra_force, extra_moment = ply_curved_friction.curved_friction_loads(
                self, state, sliding, history, facing
            )
            return force + extra_force, moment + extra_moment
        if self._frictional(history):
            sliding = self.friction_state(state, history, facing)
            extra = ply_friction.friction_loads(self, state, sliding, history, facing)
            # the pairs' rows (6 nodes) then the friction's (11): summed in that order
            nodes = np.concatenate([nodes.ravel(), extra[0].ravel()])
            forces = np.concatenate([forces.reshape(-1, 3), extra[1].reshape(-1, 3)])
            moments = np.concatenate([moments.reshape(-1, 3), extra[2].reshape(-1, 3)])
        flat = nodes.ravel()
        for axis in range(3):
            force[:, axis] += np.bincount(flat, forces[..., axis].ravel(), self.n_nodes)
            moment[:, axis] += np.bincount(flat, moments[..., axis].ravel(), self.n_nodes)
        return force, moment

    def strain_energy(self, state: State, history: Any = None) -> float:
        """sum W(g) over the touching points and, with friction, the stick springs' 1/2
        |F_t|^2 / k, N mm."""
        facing = self._held(state, history)
        on = np.flatnonzero(facing.touching)
        law = penalty_law(facing.gap[on], self.stiffness[on], self.smoothing)
        energy = float(np.sum(_fade(facing, on)[0] * law[0]))
        if self._frictional(history):  # the tangential springs' |F_t|^2 / (2 k_t)
            history = ply_landing_kept.landed_at(self, state, history, facing)
            sliding = self.friction_state(state, history, facing)
            spring = np.where(sliding.spring > 0, sliding.spring, 1.0)  # k_t = 0: no force
            energy += 0.5 * float(np.sum(np.sum(sliding.force**2, axis=1) / spring))
        return energy

    def tangent(self, state: State, history: Any = None) -> list[TangentPart]:
        """Exact d(force, moment)/d(u, psi) of the touching points, (t, 6, 6, 6, 6)
        (elements/ply_block_tangent.py, ``tangent``)."""
        return ply_block_tangent.tangent(self, state, history)

    def _fade_tangent(
        self,
        state: State,
        facing: Facing,
        rows: np.ndarray,
        gradient: np.ndarray,
        law: tuple,
        faded: np.ndarray,
    ) -> CellTangent:
        """The fade's part of the tangent of the points ``rows`` (f,)
        (elements/ply_block_tangent.py, ``fade_tangent``)."""
        return ply_block_tangent.fade_tangent(self, state, facing, rows, gradient, law, faded)

    def fade_hessian_at(self, state: State, facing: Facing, rows: np.ndarray) -> np.ndarray:
        """Hess w (f, 6, 3, 6, 3), 1/mm^2, of the fade of the points ``rows`` (f,) whose fade
        moves (elements/ply_block_tangent.py, ``fade_hessian_at``)."""
        return ply_block_tangent.fade_hessian_at(self, state, facing, rows)

    # ------------------------------------------------------------------ history
    def initial_history(self) -> PlyFrictionHistory | ply_sides.PlySides:
        """Each point's side of the lower face in the reference state (elements/ply_sides.py)
        and, with friction, the reference contacts anchored (elements/ply_friction.py)."""
        if self.friction > 0.0:
            return ply_friction.initial_history(self)  # type: ignore[return-value]
        return ply_sides.initial_sides(self)

    def update_history(self, state: State, history: Any) -> Any:
        """Each point's side at ``state`` (elements/ply_sides.py) and, with friction, the
        return mapping accepted (elements/ply_friction.py, compiled on flat faces the same
        bits: ply_friction_kernels.py), a new history; None for None (no side kept)."""
        if history is None:
            return None
        if ply_sides.sides_of(history) is None:
            facing, sides = self._held(state, history), None
        else:
            facing, sides = ply_sides.accepted_sides(self, state, history)
        if not isinstance(history, PlyFrictionHistory):
            return history if sides is None else sides
        if self.friction > 0.0:  # the landing points anchored where they touched
            history = ply_landing_kept.landed_at(self, state, history, facing)
        if ply_projection.COMPILED:
            return ply_friction_kernels.updated_history(self, state, history, facing, sides)
        return ply_friction.updated_history(self, state, history, facing, sides)

    def dissipated_energy(self, history: Any = None) -> float:
        """Energy dissipated by friction since the start, N mm."""
        return 0.0 if history is None else float(history.dissipated)

    # ------------------------------------------------------------------ protocol extras
    def _lumped(self, values: np.ndarray) -> np.ndarray:
        """(n,) sum over the points of N_j values_p at their upper corners."""
        return np.bincount(self.above.ravel(), (self.shape * values[:, None]).ravel(), self.n_nodes)

    def springs(self) -> tuple[np.ndarray, np.ndarray]:
        """2 sum_p N_j k_p at the upper nodes and 2 max of that (times the ratio of upper to
        lower nodes when above 1) at the lower ones, N/mm (elements/ply_contact.py, "Penalty")."""
        return self._springs(self.stiffness)

    def springs_at(
        self, state: State, step: float | None = None, mass: np.ndarray | None = None
    ) -> tuple[np.ndarray, np.ndarray]:
        """The springs per node that bound the contact's stiffness at every state it can reach
        until the step's next evaluation (elements/ply_springs.py): each point counted while
        it may touch by then, its penalty k_p times the largest bound c_p of its faded
        energy's stiffness it can reach (elements/ply_fade.py, "Stiffness"), the lower nodes'
        from the points that face or may face their triangles. The curved faces carry no
        fade: ``springs`` there. ``step`` (s) the largest step until then (None: twice the
        critical step the contact was calibrated with); ``mass`` (n,) t the masses the step
        divides the springs by, which weigh the nodes (None: those of ``calibrate``)."""
        facing = self.facing(state)
        if facing.fade is None or facing.reach is None or facing.on_growth is None:
            return self.springs()
        y = self._faces(state)[1]
        return ply_springs.reachable_springs(self, state, facing, y, step, mass)

    def _springs(self, stiffness: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        upper = 2.0 * self._lumped(stiffness)[self.upper]
        ratio = max(1.0, len(self.upper) / len(self.lower_nodes))
        lower = np.full(len(self.lower_nodes), ratio * float(np.max(upper)))
        return np.concatenate([self.upper, self.lower_nodes]), np.concatenate([upper, lower])

    def node_fields(self, state: State, history: Any = None) -> dict[str, np.ndarray]:
        """ply_gap (mm, the mean signed gap of the contact points around each upper node,
        weighted by N_j, < 0 a penetration; NaN off the upper nodes and where no point faces
        a triangle), ply_contact_force (sum_p N_j (-dW/dg), the pressing force lumped to
        the upper nodes, N; 0 off them), ply_slip_vector (n, 3) and ply_slip (n,): the
        tangential displacement of each upper node's face against the lower ply's face since
        the start and its length, mm (elements/ply_slip.py; NaN off the upper nodes and
        where no ply is below). None for the mirrored pass (``points="lower"``): the fields
        are the upper ply's, given by the pass of its own points."""
        if self.mirrored:
            return {}
        facing = self._held(state, history)
        overshoot = np.maximum(0.0, -facing.weights.min(axis=1))
        facing_any = overshoot <= (ply_curved.MARGIN_CURVED if self.curved else MARGIN)
        weight = self._lumped(facing_any.astype(float))
        total = self._lumped(np.where(facing_any, facing.gap, 0.0))
        gap = np.full(self.n_nodes, np.nan)
        with np.errstate(invalid="ignore", divide="ignore"):
            gap[self.upper] = np.where(
                weight[self.upper] > 0, total[self.upper] / weight[self.upper], np.nan
            )
        pressing = np.zeros(len(facing.gap))
        on = facing.touching
        pressing[on] = -penalty_law(facing.gap[on], self.stiffness[on], self.smoothing)[1]
        pressing[on] *= _fade(facing, np.flatnonzero(on))[0]
        force = np.zeros(self.n_nodes)
        force[self.upper] = self._lumped(pressing)[self.upper]
        vectors = np.full((self.n_nodes, 3), np.nan)
        vectors[self.upper] = ply_slip.slip_vectors(
            self.slip_anchors,
            state.positions,
            self.offset_directions(state),
            self.cells,
            self.corner_offset,
        )
        return {
            "ply_gap": gap,
            "ply_contact_force": force,
            "ply_slip": np.linalg.norm(vectors, axis=1),
            "ply_slip_vector": vectors,
        }
