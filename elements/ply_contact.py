"""Penalty contact between two deformable shells, frictionless or with Coulomb friction: the
lower face of an upper ply against the upper face of a lower ply (the stack as plies,
docs/theory.md §9.3a); an interaction (femcore.interaction) of points inside the upper ply's
triangles with the lower ply's triangles.

Surfaces. The upper ply's lower face is the flat triangle through its corners' offset points
x_j - a_j d_j (x the node, d its unit director, a the upper ply's half thickness, mm); the
lower ply's upper face over a triangle the flat triangle through y_k = x_k + b_k d_k (b the
lower ply's half thickness). Offsetting along the nodes' directors (not along a triangle's
normal) is the shell's own map: a Reissner-Mindlin or fibrous triangle places its faces at
x = sum N_k (x_k +- h/2 V_k) (Bai Eq. 5), so the contact faces are the elements' faces,
continuous from one triangle to the next (a facet-normal offset would open and close cracks of
h/2 times the angle between facets at every edge). The price is that the contact acts on the
directors of both plies (moments c d x F), which the tangent below carries.

Faces along the normal (``faces="normal"``). A fibrous ply's director is a material line free
to tilt (fibre slip), and the thickness the fibrous shell conserves is the one along the normal
(docs/theory.md §9.3b). Offset along such a director, a face lies only a cos(tilt) from the
mid-surface, and the contact's own moments c d x F tilt the director further, which lowers
the penalty energy: a zero-energy path by which a pressed ply passes through its neighbour.
Measured on the hemisphere with a [0/90] fibrous stack (8 cells): the directors tilted 75-90
deg from the normal, and the top ply's nodes came within 0.06 mm of the bottom ply's (0.3
apart by their thickness) and up to 1.7 mm through its face. With ``faces="normal"`` each face
lies a (b) from the mid-surface along the ply's area-weighted nodal normal at the current
positions, the gap does not depend on the directors and the contact acts on the positions
alone (no moments; the force and the tangent hold the normals fixed, an error of the order of
the ply thickness over the cell size). The faces stay continuous from one triangle to the next
(a node's normal is one for its triangles). The friction then acts on the mid-surface alone.

Curved faces (``surface="curved"``, elements/ply_surface.py). The faces above are flat
facets: on a curved tool, plies whose meshes do not match put the upper ply's points on facets
of the lower ply that are chords s^2 / (8 R) inside its true face. With ``surface="curved"``
both faces are Phong surfaces over the offset corners and the plies' nodal normals (Max's
weights), the upper points lie on the upper ply's surface, each is projected on the lower
ply's surface over the facet the flat search picked, and the force is the exact gradient of
the energy, the nodal normals' dependence on the positions included; with friction the stick
anchors lie on the curved surface too (a sliding anchor moved by projecting its new place on
it). The tangent stays the flat one at the curved
projection.

Contact points (Gauss point to surface). The contact acts at points inside the upper ply's
triangles, p = sum_j N_j (x_j - a_j d_j), N_j the triangle's shape functions at the rule's
barycentric coordinates (``RULES``: the centroid, three interior Gauss points, or the three
corners, which is node-to-surface contact), and its force on p goes back to the upper
triangle's corners by N_j. Why not at the nodes: plies are meshed alike, so every upper node
sits right above a vertex of the lower ply, where the facing triangle (and with it the normal)
switches between the facets around the vertex: a kink of the energy at the equilibrium itself,
on which Newton stalled (the 4-ply sag of tests/test_plies.py: no convergence in 8 cuts of 50
iterations). A centroid sits above the middle of the facing triangle, a third of a cell from
its edges, and stays there until the plies slide by that much.

Both ways (``points="lower"``). The points above are the upper ply's alone: nothing holds a
node of the lower ply, or a node of the upper ply between its points, off the other ply's
face. A second PlyContact with ``points="lower"`` is the mirrored pass: its points lie on the
lower ply's upper face, x + b d, at its rule's coordinates in the lower triangles, and meet
the upper ply's lower face, x - a d, whose triangles it turns so that their normal points
towards the lower ply; the rest (search, law, friction, tangent) is the same code with the
plies' roles and the offsets' signs swapped. With its points at the lower ply's nodes
("vertices") the two passes hold both plies' nodes and the upper ply's interior points.

Gap, energy and search (elements/ply_projection.py). Each point faces the triangle of the
lower face that a search over the nearest ``candidates`` triangles picks, refreshed at every
call; its gap g is its signed distance to that triangle's plane, and its energy W(g) a
one-sided penalty whose stiffness ramps up over a penetration of ``smoothing`` (C2 at
contact). A point counts as touching when g < 0 and its projection is within ``MARGIN`` of
the triangle.

The force is the exact gradient of sum W: on p, dW/dp = W' n, to the upper corners N_j W' n;
on the lower corners, dW/dy_k = -W' lambda_k n, lambda the barycentric coordinates of the
projection of p (the surface point held by them: the derivative of the distance to the plane
brings no other term, see ``PlyContactBlock.tangent``); through the offsets the moments
-a_j d_j x (N_j W' n) at the upper corners and b_k d_k x (dW/dy_k) at the lower ones.

Penalty: given (N/mm per upper node), or chosen when the model is compiled (``calibrate``):
k_j = ``PENALTY_SHARE`` m_j (2 / dt)^2, m_j the upper node's lumped mass and dt the model's
critical step without the contact, as elements/contact.py. A point gets the nodes' penalties in
proportion to the area it stands for: k_p = w_p A_T sum_j N_j(p) k_j / A_j (w_p the rule's
weight, A_T the reference area of its triangle, A_j the lumped area of node j, sum A_T / 3 over
its triangles), so that the corner rule gives each node its k_j back and a uniform penalty on a
uniform mesh adds up to the same total whatever the rule. ``springs`` reports at each upper
node 2 sum_p N_j k_p and at the lower ones 2 max(that) (times the ratio of upper to lower nodes
when above 1), so the explicit step takes the penalty in (the friction's stick spring has
the point's penalty k_p across the normal, so the bound holds).

Friction (``friction`` = mu > 0; Coulomb, penalty-regularised, return mapping as
elements/contact.py). Each touching point keeps a stick anchor on the lower face: a lower
triangle and barycentric coordinates Lambda, the anchor a = sum Lambda_k y_k sliding with the
lower ply. Its tangential offset s = (I - n n^T)(p - a), n the facing triangle's normal, loads
a spring of stiffness k_t = k_p: stuck, k_p |s| <= mu N (N = -W'(g) the point's normal force),
the force on p is -k_p s (energy |F|^2 / (2 k_p)); sliding, -mu N s / |s|. The force on p goes
to the upper corners by N_j (moments through the offsets as the normal force) and, opposite,
to the anchor triangle's corners by Lambda_k. An accepted step (``update_history``, a new
``PlyFrictionHistory``; the one given is left as it was) keeps stuck anchors, moves sliding
ones along s until the spring holds mu N and re-expresses them on the facing triangle,
anchors new contacts at their projections and forgets lost ones; the dissipation adds mu N_mid
times the slip, N_mid the mean of the last accepted and the current normal force. A point not
touching when the last step was accepted has no anchor (it slides freely for that step). The
pair F on p, -F at a is not moment-free: p and a are apart by n . (p - a) ~ g along the normal,
a couple F g, small against the moments F h/2 of the offsets. The tangent is exact (stick and
slip, through the facing triangle's normal, the normal force and the anchor's triangle;
non-symmetric in slip: ``elements.ply_friction.friction_tangent``). mu = 0: no history
(``initial_history`` is None) and the frictionless code path alone, the same numbers.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from scipy.spatial import cKDTree

from elements import ply_friction, ply_slip, ply_surface
from elements.ply_friction import PlyFrictionHistory, Sliding
from elements.ply_projection import MARGIN, Facing, closest_facing, penalty_law
from femcore.assembly import CellTangent
from femcore.field_names import name_components
from femcore.interaction import Body, Interaction, InteractionBlock
from femcore.rotation import cross_matrix
from femcore.state import State

__all__ = [
    "FACES",
    "POINTS",
    "SURFACES",
    "MARGIN",
    "PENALTY_SHARE",
    "RULES",
    "SMOOTHING",
    "Facing",
    "PlyContact",
    "join_neighbours",
    "PlyContactBlock",
    "penalty_law",
]

name_components("ply_slip_vector", ("x", "y", "z"))  # global axes, as the displacement's

PENALTY_SHARE = 0.1  # k m^-1 / omega_max^2 of the automatic penalty (as elements/contact.py)
#: Triangles examined per point (the nearest centroids).
CANDIDATES = 6
#: The default smoothing width delta as a share of the two faces' half thicknesses a + b
#: (the ply thickness for plies alike): see docs/theory.md §9.3a for the measurements.
SMOOTHING = 1e-3
#: Where the faces lie: along each node's director ("director") or along its ply's nodal normal
#: ("normal"), module docstring "Faces along the normal".
FACES = ("director", "normal")
#: The lower face over a triangle: the flat facet through its offset corners, or the curved
#: surface over them and the lower ply's nodal normals (elements/ply_surface.py).
SURFACES = ("flat", "curved")
#: Which ply carries the contact points (module docstring, "Both ways").
POINTS = ("upper", "lower")
#: Contact points of an upper triangle: name -> (barycentric coordinates (Q, 3), weights
#: (Q,) summing to 1).
RULES = {
    "centroid": (np.full((1, 3), 1.0 / 3.0), np.ones(1)),
    "gauss": (
        np.array([[2 / 3, 1 / 6, 1 / 6], [1 / 6, 2 / 3, 1 / 6], [1 / 6, 1 / 6, 2 / 3]]),
        np.full(3, 1.0 / 3.0),
    ),
    "vertices": (np.eye(3), np.full(3, 1.0 / 3.0)),
}


class PlyContact(Interaction):
    """Penalty contact of the upper ply's lower face with the lower ply's upper face at points
    inside the upper ply's triangles, frictionless or with Coulomb friction (module
    docstring).

    Parameters
    ----------
    upper : str or (u,) int
        The upper ply's triangles: a triangle cell-set name of the mesh, a node-set name (the
        triangles with all three corners in it), or triangle ids.
    lower : str or (m,) int
        The lower ply's triangles: a triangle cell-set name of the mesh or triangle ids
        (counter-clockwise about the direction towards the upper ply).
    upper_offset, lower_offset : float, optional
        The half thicknesses a and b of the upper and lower ply, mm (the faces' distances
        from the mid-surfaces along the directors); None: half the thickness of the elements
        at the nodes (``Body.half_thickness``).
    penalty : float, optional
        k, N/mm per upper node (shared out to the points by area, module docstring); None:
        chosen when the model is compiled.
    candidates : int
        Triangles examined per point by the search (the nearest centroids), >= 1.
    rule : str
        The contact points of each upper triangle, a key of ``RULES``: "centroid" (default),
        "gauss" (three interior points) or "vertices" (node-to-surface).
    smoothing : float, optional
        delta, mm, the penetration over which the penalty's stiffness ramps up (0: the plain
        k/2 min(g, 0)^2); None: ``SMOOTHING`` (a + b).
    friction : float
        The Coulomb coefficient mu >= 0 between the plies (module docstring, "Friction"); 0
        (default): frictionless, no history kept, the frictionless code path alone.
    faces : str
        "director" (default): each face h/2 from the mid-surface along the nodes' directors,
        the contact acting on the directors too; "normal": along the ply's area-weighted
        nodal normal, the contact acting on the positions alone (module docstring, "Faces
        along the normal": the choice for fibrous plies, whose directors are free to tilt).
    surface : str
        "flat" (default): each face over a triangle the flat facet through its offset
        corners; "curved": the Phong surface over them and the plies' nodal normals, the
        force the exact gradient of the energy (module docstring, "Curved faces").
    points : str
        Which ply carries the contact points: "upper" (default), the rule's points of the
        upper ply's lower face against the lower ply's upper face; "lower", the rule's points
        of the lower ply's upper face against the upper ply's lower face (module docstring,
        "Both ways": the two together hold each ply's points off the other's face).

    Raises
    ------
    ValueError
        Empty or non-integer selections, a negative or non-finite offset or smoothing, a
        penalty that is not a positive number, fewer than one candidate, an unknown rule,
        faces, surface or points; at
        bind, unknown set names, ids out of range, nodes of the upper triangles that are
        corners of the lower triangles, nodes without directors.
    """

    dofs = ("ux", "uy", "uz", "alpha", "beta")

    def __init__(
        self,
        upper: str | np.ndarray | list[int],
        lower: str | np.ndarray | list[int],
        upper_offset: float | None = None,
        lower_offset: float | None = None,
        penalty: float | None = None,
        candidates: int = CANDIDATES,
        rule: str = "centroid",
        smoothing: float | None = None,
        friction: float = 0.0,
        faces: str = "director",
        surface: str = "flat",
        points: str = "upper",
    ):
        self.upper = upper if isinstance(upper, str) else _ids(upper, "upper triangle")
        self.lower = lower if isinstance(lower, str) else _ids(lower, "lower triangle")
        for name, value in (
            ("upper_offset", upper_offset),
            ("lower_offset", lower_offset),
            ("smoothing", smoothing),
        ):
            if value is not None and not (
                isinstance(value, (int, float))
                and not isinstance(value, bool)
                and np.isfinite(value)
                and value >= 0
            ):
                raise ValueError(f"{name} must be a finite number >= 0 (mm) or None, got {value!r}")
        self.upper_offset, self.lower_offset = upper_offset, lower_offset
        self.smoothing = None if smoothing is None else float(smoothing)
        if penalty is not None and not (
            isinstance(penalty, (int, float))
            and not isinstance(penalty, bool)
            and np.isfinite(penalty)
            and penalty > 0
        ):
            raise ValueError(f"penalty must be a positive number (N/mm) or None, got {penalty!r}")
        self.penalty = penalty
        if isinstance(candidates, bool) or not isinstance(candidates, (int, np.integer)):
            raise ValueError(f"candidates must be an integer >= 1, got {candidates!r}")
        if candidates < 1:
            raise ValueError(f"candidates must be an integer >= 1, got {candidates!r}")
        self.candidates = int(candidates)
        if rule not in RULES:
            raise ValueError(f"rule must be one of {sorted(RULES)}, got {rule!r}")
        self.rule = rule
        if not (
            isinstance(friction, (int, float))
            and not isinstance(friction, bool)
            and np.isfinite(friction)
            and friction >= 0
        ):
            raise ValueError(f"friction must be a Coulomb coefficient >= 0, got {friction!r}")
        self.friction = float(friction)
        if faces not in FACES:
            raise ValueError(f"faces must be one of {FACES}, got {faces!r}")
        self.faces = faces
        if surface not in SURFACES:
            raise ValueError(f"surface must be one of {SURFACES}, got {surface!r}")
        self.surface = surface
        if points not in POINTS:
            raise ValueError(f"points must be one of {POINTS}, got {points!r}")
        self.points = points

    def bind(self, body: Body) -> PlyContactBlock:
        mesh = body.mesh
        triangles = mesh.triangles
        sets = mesh.cell_sets("triangle")
        if isinstance(self.upper, str):
            if self.upper in sets:
                upper = np.asarray(sets[self.upper], dtype=np.int64)
            elif self.upper in mesh.node_sets:
                inside = np.isin(triangles, mesh.node_sets[self.upper]).all(axis=1)
                upper = np.flatnonzero(inside)
            else:
                raise ValueError(
                    f"PlyContact: no triangle or node set named {self.upper!r}: the mesh has "
                    f"{sorted(set(sets) | set(mesh.node_sets)) or 'none'}"
                )
        else:
            upper = self.upper
        if isinstance(self.lower, str):
            if self.lower not in sets:
                raise ValueError(
                    f"PlyContact: no triangle set named {self.lower!r}: the mesh has "
                    f"{sorted(sets) or 'none'}"
                )
            lower = np.asarray(sets[self.lower], dtype=np.int64)
        else:
            lower = self.lower
        if upper.size == 0 or lower.size == 0:
            raise ValueError("PlyContact: the upper and the lower triangles must be given")
        for name, ids in (("upper", upper), ("lower", lower)):
            if ids.max() >= len(triangles):
                raise ValueError(
                    f"PlyContact: {name} triangle {int(ids.max())} out of range (mesh has "
                    f"{len(triangles)} triangles)"
                )
        above, cells = triangles[upper], triangles[lower]
        shared = np.intersect1d(above, cells)
        if shared.size:
            raise ValueError(
                f"PlyContact: node {int(shared[0])} is both a corner of an upper triangle and "
                "of a lower triangle: the plies must be separate meshes"
            )
        without = np.linalg.norm(body.directors[np.union1d(above, cells)], axis=1) == 0.0
        if without.any():
            raise ValueError(
                "PlyContact acts on shells with directors: a node of the contact has none "
                "(add the plies' shell elements before compiling)"
            )
        half = body.half_thickness()
        a = half if self.upper_offset is None else np.full(mesh.n_nodes, self.upper_offset)
        b = half if self.lower_offset is None else np.full(mesh.n_nodes, self.lower_offset)
        smoothing = self.smoothing
        if smoothing is None:
            smoothing = SMOOTHING * float(np.mean(a[above]) + np.mean(b[cells]))
        if self.points == "lower":  # the points on the lower ply's upper face, x + b d
            # against the upper ply's lower face, x - a d, its triangles turned so that their
            # normal points towards the lower ply (module docstring, "Both ways")
            return PlyContactBlock(self, cells, above[:, [0, 2, 1]], -b, -a, smoothing, body)
        return PlyContactBlock(self, above, cells, a, b, smoothing, body)


def _ids(given: Any, what: str) -> np.ndarray:
    array = np.atleast_1d(np.asarray(given))
    if array.size == 0:
        raise ValueError(f"PlyContact: empty {what} selection")
    if array.dtype == bool or not np.issubdtype(array.dtype, np.integer):
        raise ValueError(f"PlyContact: {what} ids must be integers, got {array.dtype}")
    if array.min() < 0:
        raise ValueError(f"PlyContact: {what} id {int(array.min())} is negative")
    return np.unique(array.astype(np.int64))


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

    dofs = PlyContact.dofs
    reach = 1
    n_tools = 0

    def __init__(
        self,
        contact: PlyContact,
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
        self.candidates = min(contact.candidates, len(cells))
        # The points' shares of their corners' penalties (module docstring): (P, s).
        x = body.mesh.points
        sides = np.cross(x[above[:, 1]] - x[above[:, 0]], x[above[:, 2]] - x[above[:, 0]])
        area = 0.5 * np.linalg.norm(sides, axis=1)
        lumped = np.bincount(above.ravel(), np.repeat(area / 3.0, 3), self.n_nodes)
        share = np.repeat(area, count) * np.tile(weights, len(above))
        self._share = share[:, None] * self.shape / lumped[self.above]  # (P, 3)
        self._corner_rows = np.searchsorted(self.upper, self.above)  # (P, 3) rows of upper
        given = contact.penalty
        self.node_stiffness = np.full(len(self.upper), np.nan if given is None else float(given))
        self.stiffness = self._point_stiffness()
        self.friction = contact.friction
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
        near = self._candidates(reference)[1][:, : min(3, self.candidates)]
        self.connectivity = np.column_stack([self.above, cells[near].reshape(len(self.above), -1)])
        self.lower_nodes = np.unique(cells)
        # Without smoothing, plies laid on each other (g = 0 up to the rounding of the
        # offsets) count as touching, so that Newton has the contact's stiffness from its
        # first iteration (the force, k min(g, 0), is still zero there); with it, W'' = 0 at
        # g = 0 anyway.
        size = float(np.ptp(body.mesh.points, axis=0).max(initial=0.0)) or 1.0
        self.tolerance = 0.0 if self.smoothing > 0 else 1e-9 * size

    def _point_stiffness(self) -> np.ndarray:
        return np.sum(self._share * self.node_stiffness[self._corner_rows], axis=1)

    def held_directions(self) -> tuple[np.ndarray, np.ndarray]:
        """None against the ground: the gap and the slip between two plies do not change when
        the whole stack moves as one (what holds the stack are its supports and tools)."""
        return np.zeros(0, dtype=np.int64), np.zeros((0, 3))

    def calibrate(self, mass: np.ndarray, stable_dt: float) -> None:
        if np.isnan(self.node_stiffness).any():  # the automatic penalty (module docstring)
            self.node_stiffness = PENALTY_SHARE * mass[self.upper] * (2.0 / stable_dt) ** 2
            self.stiffness = self._point_stiffness()

    # ------------------------------------------------------------------ search
    def offset_directions(self, state: State) -> np.ndarray:
        """(n, 3) the unit directions along which the faces lie at ``state``: the directors,
        or with ``faces="normal"`` the area-weighted normals of each ply's triangles (zero off
        the plies)."""
        if not self.along_normals:
            return state.directors
        x, tri = state.positions, self._own_triangles
        if self.curved:  # the curved surface's own normals (elements/ply_surface.py)
            return ply_surface.nodal_normals(x, tri, self.n_nodes)[0]
        sides = np.cross(x[tri[:, 1]] - x[tri[:, 0]], x[tri[:, 2]] - x[tri[:, 0]])
        flat = tri.ravel()
        summed = np.column_stack(
            [np.bincount(flat, np.repeat(sides[:, k], 3), self.n_nodes) for k in range(3)]
        )
        length = np.linalg.norm(summed, axis=1)
        return summed / np.where(length > 0.0, length, 1.0)[:, None]

    def surface_normals(self, state: State) -> np.ndarray:
        """(n, 3) the unit nodal normals of the curved faces (elements/ply_surface.py)."""
        return ply_surface.nodal_normals(state.positions, self._own_triangles, self.n_nodes)[0]

    def _faces(self, state: State) -> tuple[np.ndarray, np.ndarray]:
        """Contact points p (P, 3) and offset lower corners y (m, 3, 3), mm."""
        x, d = state.positions, self.offset_directions(state)
        corners = x[self.above] - self.upper_offset[..., None] * d[self.above]
        if self.curved:  # on the upper ply's own curved face (elements/ply_surface.py)
            normals = ply_surface.nodal_normals(x, self._own_triangles, self.n_nodes)[0]
            p = ply_surface.surface_point(corners, normals[self.above], self.shape)[0]
        else:
            p = np.einsum("pj,pji->pi", self.shape, corners)
        y = x[self.cells] + self.corner_offset[:, :, None] * d[self.cells]
        return p, y

    def _candidates(self, state: State):
        p, y = self._faces(state)
        tree = cKDTree(y.mean(axis=1))
        _, near = tree.query(p, k=self.candidates)
        return p, np.asarray(near).reshape(len(p), self.candidates), y

    def facing(self, state: State) -> Facing:
        """Each contact point's facing triangle, gap, normal and projection at ``state``
        (elements/ply_projection.py: the nearest of the candidates)."""
        p, near, y = self._candidates(state)
        flat = closest_facing(p, y, near, self.tolerance)
        if not self.curved:
            return flat
        # the curved surface over the facet the flat search picked (elements/ply_surface.py)
        normals = ply_surface.nodal_normals(state.positions, self._own_triangles, self.n_nodes)[0]
        lam, _, normal, gap, _, _ = ply_surface.project(
            p, y[flat.triangle], normals[self.cells[flat.triangle]], flat.weights
        )
        overshoot = np.maximum(0.0, -lam.min(axis=1))
        return Facing(
            triangle=flat.triangle,
            gap=gap,
            normal=normal,
            weights=lam,
            gradients=flat.gradients,
            touching=(gap <= self.tolerance) & (overshoot <= MARGIN),
            face=p,
        )

    def _curved_loads(self, state: State, facing: Facing) -> tuple[np.ndarray, np.ndarray]:
        """The exact gradient of sum W over the curved surface (elements/ply_surface.py):
        forces (n, 3), N, and moments (n, 3), N mm, the nodal normals' dependence on the
        positions carried back to the plies' nodes."""
        on = np.flatnonzero(facing.touching)
        law = penalty_law(facing.gap[on], self.stiffness[on], self.smoothing)
        x = state.positions
        normals, lengths = ply_surface.nodal_normals(x, self._own_triangles, self.n_nodes)
        d = normals if self.along_normals else state.directors
        rows = facing.triangle[on]
        tri = self.cells[rows]
        y = x[tri] + self.corner_offset[rows][:, :, None] * d[tri]
        lam = facing.weights[on]
        _, _, q, e = ply_surface.surface_point(y, normals[tri], lam)
        on_y, on_n = ply_surface.gap_gradients(y, normals[tri], lam, facing.normal[on], q, e)
        slope = law[1][:, None, None]
        # p on the upper triangle's curved face: dW/dp = W' nu carried to its corners
        above = self.above[on]
        z = x[above] - self.upper_offset[on][:, :, None] * d[above]
        _, _, q_up, e_up = ply_surface.surface_point(z, normals[above], self.shape[on])
        on_z, on_n_up = ply_surface.pullback(
            z, normals[above], self.shape[on], q_up, e_up, law[1][:, None] * facing.normal[on]
        )
        nodes = np.column_stack([above, tri])  # (t, 6)
        # dW/dz at the upper corners' and the lower corners' face points
        forces = np.concatenate([on_z, slope * on_y], axis=1)
        offset = np.column_stack([-self.upper_offset[on], self.corner_offset[rows]])
        flat = nodes.ravel()

        def gathered(values: np.ndarray, at: np.ndarray) -> np.ndarray:
            # float even when no point touches (bincount of no weights is integer)
            return np.column_stack(
                [np.bincount(at, values[..., k].ravel(), self.n_nodes) for k in range(3)]
            ).astype(float)

        force = gathered(forces, flat)
        on_normals = gathered(np.concatenate([on_n_up, slope * on_n], axis=1), flat)
        if self.along_normals:  # z = x + c n: dW/dn = c dW/dz
            on_normals += gathered(offset[:, :, None] * forces, flat)
            moment = np.zeros((self.n_nodes, 3))
        else:
            moment = gathered(offset[:, :, None] * np.cross(d[nodes], forces), flat)
        force += ply_surface.normal_pullback(x, self._own_triangles, normals, lengths, on_normals)
        return force, moment

    # ------------------------------------------------------------------ loads
    def _pair_loads(self, state: State, facing: Facing):
        """Per touching point: node rows (t, 6) (the upper triangle's corners, the facing
        triangle's corners), forces (t, 6, 3) N, moments (t, 6, 3) N mm (dW/dx and dW/dpsi),
        the points' rows (t,), the signed offsets c (t, 6) (z = x + c d) and the law's
        (energy, dW/dg, d2W/dg2), each (t,)."""
        on = np.flatnonzero(facing.touching)
        law = penalty_law(facing.gap[on], self.stiffness[on], self.smoothing)
        n, lam = facing.normal[on], facing.weights[on]
        tri = facing.triangle[on]
        nodes = np.column_stack([self.above[on], self.cells[tri]])
        on_face = law[1][:, None] * n  # dW/dp
        forces = np.concatenate(
            [
                self.shape[on][:, :, None] * on_face[:, None, :],
                -lam[:, :, None] * on_face[:, None, :],
            ],
            axis=1,
        )
        d = self.offset_directions(state)[nodes]  # (t, 6, 3)
        offset = self.lever * np.column_stack([-self.upper_offset[on], self.corner_offset[tri]])
        # p = sum N_j (x_j - a_j d_j), y_k = x_k + b_k d_k: dW/dpsi = c d x dW/dx.
        moments = offset[:, :, None] * np.cross(d, forces)
        return nodes, forces, moments, on, offset, law

    def _frictional(self, history: Any) -> bool:
        return history is not None and self.friction > 0.0

    def normal_law(self, gap: np.ndarray, stiffness: np.ndarray):
        """``penalty_law`` of the points with gaps ``gap`` and stiffnesses ``stiffness`` at this
        block's smoothing: (energy, dW/dg, d2W/dg2)."""
        return penalty_law(gap, stiffness, self.smoothing)

    def friction_state(
        self, state: State, history: PlyFrictionHistory | None, facing: Facing | None = None
    ) -> Sliding:
        """The return mapping at ``state`` (elements/ply_friction.py)."""
        return ply_friction.friction_state(self, state, history, facing)

    def internal_force(self, state: State, history: Any = None):
        facing = self.facing(state)
        if self.curved:
            force, moment = self._curved_loads(state, facing)
            nodes = np.zeros((0, 6), dtype=np.int64)
            forces = moments = np.zeros((0, 6, 3))
        else:
            force, moment = np.zeros((self.n_nodes, 3)), np.zeros((self.n_nodes, 3))
            nodes, forces, moments, *_ = self._pair_loads(state, facing)
        if self._frictional(history):
            sliding = self.friction_state(state, history, facing)
            extra = ply_friction.friction_loads(self, state, sliding, history)
            nodes = np.concatenate([nodes, extra[0]])
            forces = np.concatenate([forces, extra[1]])
            moments = np.concatenate([moments, extra[2]])
        flat = nodes.ravel()
        for axis in range(3):
            force[:, axis] += np.bincount(flat, forces[..., axis].ravel(), self.n_nodes)
            moment[:, axis] += np.bincount(flat, moments[..., axis].ravel(), self.n_nodes)
        return force, moment

    def strain_energy(self, state: State, history: Any = None) -> float:
        """sum W(g) over the touching points and, with friction, the stick springs' 1/2
        |F_t|^2 / k, N mm."""
        facing = self.facing(state)
        on = facing.touching
        energy = float(np.sum(penalty_law(facing.gap[on], self.stiffness[on], self.smoothing)[0]))
        if self._frictional(history):  # the tangential springs' |F_t|^2 / (2 k_t)
            force = self.friction_state(state, history, facing).force
            energy += 0.5 * float(np.sum(np.sum(force**2, axis=1) / self.stiffness))
        return energy

    def tangent(self, state: State, history: Any = None) -> list[CellTangent]:
        """Exact d(force, moment)/d(u, psi) of the touching points, (t, 6, 6, 6, 6).

        Over z = (p, y_1, y_2, y_3): Hess W = W'' G G^T + W' H with G = (n, -lambda_k n) the
        gradient of g and H its Hessian, from dn/dy_m = -grad phi_m n^T and dlambda_k =
        grad phi_k . (dp - g dn - sum_m lambda_m dy_m): H_pp = 0, H_p,m = -grad phi_m n^T,
        H_k,m = -g (grad phi_k . grad phi_m) n n^T + lambda_m n grad phi_k^T + lambda_k
        grad phi_m n^T. Carried to the nodes by dp = sum_j N_j (du_j - c_j [d_j]x psi_j) and
        dy_k = du_k - c_k [d_k]x psi_k (c = -a for the upper corners, b for the lower ones,
        psi the director's rotation), with the geometric term of the turned offset,
        d(c d x F)/dpsi = c (d F^T - (F . d) I), on each node's psi-psi block.
        """
        facing = self.facing(state)
        nodes, forces, _, on, offset, law = self._pair_loads(state, facing)
        t = len(on)
        g = facing.gap[on]
        n, lam, grad = facing.normal[on], facing.weights[on], facing.gradients[on]
        gradient = np.concatenate([n[:, None, :], -lam[:, :, None] * n[:, None, :]], axis=1)
        hessian = np.zeros((t, 4, 3, 4, 3))
        nn = n[:, :, None] * n[:, None, :]
        for m in range(3):
            hessian[:, 0, :, 1 + m, :] = -grad[:, m, :, None] * n[:, None, :]
            hessian[:, 1 + m, :, 0, :] = -n[:, :, None] * grad[:, m, None, :]
        dots = np.einsum("tki,tmi->tkm", grad, grad)
        for a_ in range(3):
            for m in range(3):
                hessian[:, 1 + a_, :, 1 + m, :] = (
                    -(g * dots[:, a_, m])[:, None, None] * nn
                    + lam[:, m, None, None] * n[:, :, None] * grad[:, a_, None, :]
                    + lam[:, a_, None, None] * grad[:, m, :, None] * n[:, None, :]
                )
        outer = gradient[:, :, :, None, None] * gradient[:, None, None, :, :]
        points = (
            law[2][:, None, None, None, None] * outer + law[1][:, None, None, None, None] * hessian
        )  # (t, 4, 3, 4, 3)
        d = self.offset_directions(state)[nodes]  # (t, 6, 3)
        # Each node's own map dz = du - c [d]x psi, (t, 6, 3, 6); the point p takes its
        # corners' maps times N_j, each lower corner its own.
        own = np.zeros((t, 6, 3, 6))
        own[:, :, :, :3] = np.eye(3)
        own[:, :, :, 3:] = -offset[:, :, None, None] * cross_matrix(d)
        maps = np.zeros((t, 4, 3, 6, 6))  # (t, z, coordinate, node, dof)
        for j in range(3):
            maps[:, 0, :, j, :] = self.shape[on][:, j, None, None] * own[:, j]
            maps[:, 1 + j, :, 3 + j, :] = own[:, 3 + j]
        carried = np.einsum("tzisj,tsjcb->tzicb", points, maps)
        blocks = np.einsum("tzira,tzicb->tracb", maps, carried)
        # The moment c d x F turns with the director (F held): d(c d x F)/dpsi =
        # c (psi x d) x F = c (d F^T - (F . d) I) psi.
        geometric = offset[:, :, None, None] * (
            d[:, :, :, None] * forces[:, :, None, :]
            - np.sum(forces * d, axis=-1)[:, :, None, None] * np.eye(3)
        )
        for row in range(6):
            blocks[:, row, 3:, row, 3:] += geometric[:, row]
        parts = [CellTangent(nodes, blocks)]
        if self._frictional(history):
            parts.append(ply_friction.friction_tangent(self, state, history, facing))
        return parts

    # ------------------------------------------------------------------ history
    def initial_history(self) -> PlyFrictionHistory | None:
        """None without friction, else the reference contacts anchored
        (elements/ply_friction.py)."""
        return ply_friction.initial_history(self)

    def update_history(self, state: State, history: Any) -> Any:
        """The return mapping accepted, a new history (elements/ply_friction.py)."""
        return ply_friction.updated_history(self, state, history)

    def dissipated_energy(self, history: Any = None) -> float:
        """Energy dissipated by friction since the start, N mm."""
        return 0.0 if history is None else history.dissipated

    # ------------------------------------------------------------------ protocol extras
    def _lumped(self, values: np.ndarray) -> np.ndarray:
        """(n,) sum over the points of N_j values_p at their upper corners."""
        return np.bincount(self.above.ravel(), (self.shape * values[:, None]).ravel(), self.n_nodes)

    def springs(self) -> tuple[np.ndarray, np.ndarray]:
        """2 sum_p N_j k_p at the upper nodes and 2 max of that (times the ratio of upper to
        lower nodes when above 1) at the lower ones, N/mm (module docstring)."""
        upper = 2.0 * self._lumped(self.stiffness)[self.upper]
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
        facing = self.facing(state)
        overshoot = np.maximum(0.0, -facing.weights.min(axis=1))
        facing_any = overshoot <= MARGIN
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


def join_neighbours(
    model: Any, count: int, half_thickness: float, lower_rule: str | None = None, **options: Any
) -> None:
    """Add to ``model`` a ``PlyContact`` of ply k + 1 on ply k for k = 1 .. count - 1 (the
    triangle sets "ply_k"), both faces ``half_thickness`` (mm) from the mid-surfaces;
    ``options`` (penalty, rule, smoothing, friction, ...) go to every one. With
    ``lower_rule`` (a key of ``RULES``), each is followed by its mirrored pass
    (``points="lower"``) with the lower ply's points at that rule. The stacks of
    elements.plies and elements.layup join their plies so."""
    for k in range(1, count):
        model.interact(
            PlyContact(f"ply_{k + 1}", f"ply_{k}", half_thickness, half_thickness, **options)
        )
        if lower_rule is not None:  # the mirrored pass (module docstring, "Both ways")
            mirrored = dict(options, rule=lower_rule, points="lower")
            model.interact(
                PlyContact(f"ply_{k + 1}", f"ply_{k}", half_thickness, half_thickness, **mirrored)
            )
