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
weights), the upper points lie on the upper ply's surface, each is projected on the curved
patches over the search's candidate triangles and faces the nearest patch that holds its
projection (elements/ply_curved.py: chosen so, the gap and the energy are continuous where a
point passes from one patch to the next, which the flat facet's choice was not), a patch
reaching ``MARGIN_CURVED`` (0.05) past its edges, and the force is the exact gradient of
the energy, the nodal normals' dependence on the positions included; with friction the stick
anchors lie on the curved surface too (a sliding anchor moved by projecting its new place on
it), and a stuck point's loads are the gradient of its stick energy there, its couple across
the curved face's turning normal included (elements/ply_curved_friction.py). The tangent
is the loads' exact derivative (elements/ply_curved_tangent.py).

Contact points (Gauss point to surface). The contact acts at points inside the upper ply's
triangles, p = sum_j N_j (x_j - a_j d_j), N_j the triangle's shape functions at the rule's
barycentric coordinates (``RULES``: the centroid, three interior Gauss points, or the three
corners, which is node-to-surface contact; "nodes" the same with one point per node
carrying its triangles' shares), and its force on p goes back to the upper
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
("vertices", or "nodes" for a sixth of the searches) the two passes hold both plies' nodes and
the upper ply's interior points.

Gap, energy and search (elements/ply_projection.py). Each point faces the nearest triangle
of the lower face (among candidates proven to hold it, elements/ply_search.py): by
the distance to the triangle's plane where the triangle holds the point's projection (its gap
g the signed distance to that plane), else by the distance to its closest point on an edge or
at a vertex (g = +-|p - q|, signed by the triangle's normal), a triangle on the lower ply's
outline reaching ``MARGIN`` past it; so the gap is continuous as the point moves (a distance).
Its energy W(g) is a one-sided penalty whose stiffness ramps up over a penetration of
``smoothing`` (C2 at contact). A point counts as touching when g < 0 and its projection is
within ``MARGIN`` of the triangle; one facing an edge or a vertex only where g >= -(a + b),
as one facing a triangle whose normal points against the point's own ply (a layer of a fold
turned away from it; elements/ply_projection.py, "Deeper than the plies" and "A layer turned
away"). Past the lower ply's outline its energy fades: w W(g), w falling continuously to 0
as the point leaves the face past an outline edge or lies beside it (elements/ply_fade.py;
elements/ply_projection.py, "Past the outline, faded"; at any depth where a growth's plane
holds the point, "Past the outline, deeper than the plies"), and the force below carries w's
gradient, W dw/dz, beside w W' dg/dz.

The force is the exact gradient of sum W: on p, dW/dp = W' n, to the upper corners N_j W' n;
on the lower corners, dW/dy_k = -W' lambda_k n, lambda the barycentric coordinates of the
projection of p, the surface point held by them (the derivative of the distance to the plane
brings no other term, see ``PlyContactBlock.tangent``; where p faces an edge or a vertex, n
is (p - q) / g and lambda those of q); through the offsets the moments
-a_j d_j x (N_j W' n) at the upper corners and b_k d_k x (dW/dy_k) at the lower ones.

Penalty: given (N/mm per upper node), or chosen when the model is compiled (``calibrate``):
k_j = ``PENALTY_SHARE`` m_j (2 / dt)^2, m_j the upper node's lumped mass and dt the elements'
critical step without the contact (a Mindlin ply's at its closed-form rotary inertia, whatever
j it was given), as elements/contact.py (against its k -> infinity limit on the two-ply
hemisphere: docs/theory.md §9.3b, "The plies' penalty against its limit"). A point gets the
nodes' penalties in proportion to the area it stands for: k_p = w_p A_T sum_j N_j(p) k_j /
A_j (w_p the rule's weight, A_T the reference area of its triangle, A_j the lumped area of
node j, sum A_T / 3 over its triangles), so that the corner rule gives each node its
k_j back and a uniform penalty on a uniform mesh adds up to the same total whatever the rule.
``springs`` reports at each upper node 2 sum_p N_j k_p and at the lower ones 2 max(that)
(times the ratio of upper to lower nodes when above 1) (the friction's stick spring is at most
the point's penalty k_p across the normal); ``springs_at(state)``, which the explicit step asks,
reports per node springs that bound the contact's stiffness at every state it can reach until
the step's next evaluation: each point's c_p k_p s_p shared by N_j at the upper nodes and by
|lambda_k| at the lower ones, with the slide until then and the fade's largest reachable factor
c_p (elements/ply_springs.py; elements/ply_fade.py, "Stiffness").

Friction (``friction`` = mu > 0; Coulomb, penalty-regularised, return mapping as
elements/contact.py). Each touching point keeps a stick anchor on the lower face: a lower
triangle and barycentric coordinates Lambda, the anchor a = sum Lambda_k y_k sliding with the
lower ply. Its tangential offset s = (I - n n^T)(p - a), n the facing triangle's normal, loads
a spring of stiffness k_t: W''(g), the normal law's own (``stick="normal law"``, the default:
k_p deeper than the smoothing, k_p |g| / delta on its ramp; times w past the outline;
elements/ply_friction.py: plies laid on each other with nearly no normal force stick), or
k_p at any normal force (``stick="penalty"``): stuck,
k_t |s| <= mu N (N = -W'(g) the point's normal force), the force on p is -k_t s (energy |F|^2 /
(2 k_t)); sliding, -mu N s / |s|. The force on p goes
to the upper corners by N_j (moments through the offsets as the normal force) and, opposite,
to the anchor triangle's corners by Lambda_k. An accepted step (``update_history``, a new
``PlyFrictionHistory``; the one given is left as it was) keeps stuck anchors, moves sliding
ones along s until the spring holds mu N and re-expresses them on the facing triangle,
anchors new contacts at their projections and forgets lost ones; the dissipation adds mu N_mid
times the slip, N_mid the mean of the last accepted and the current normal force. A point not
touching when the last step was accepted has no anchor (it slides freely for that step). The
pair F on p, -F at a is not moment-free: p and a are apart by n . (p - a) ~ g along the normal,
a couple F g, small against the moments F h/2 of the offsets; a stuck point facing a plane
carries it on the facing triangle's corners, as its stick potential's gradient
(``elements.ply_friction.stick_couple``). The tangent is exact (stick and
slip, through the facing triangle's normal, the normal force and the anchor's triangle;
non-symmetric in slip: ``elements.ply_friction_tangent.friction_tangent``). mu = 0: no friction
history (``initial_history`` keeps the points' sides alone, elements/ply_sides.py) and the
frictionless code path alone, the same numbers.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from elements.ply_active_set import LAWS, ActiveSetPlyContactBlock
from elements.ply_block import DOFS, PENALTY_SHARE, RULES, PlyContactBlock
from elements.ply_projection import MARGIN, Facing, penalty_law
from femcore.interaction import Body, Interaction
from femcore.set_names import set_named
from femcore.topology import ZERO_AREA_TOL

__all__ = [
    "FACES",
    "POINTS",
    "SURFACES",
    "MARGIN",
    "PENALTY_SHARE",
    "RULES",
    "SMOOTHING",
    "STICKS",
    "Facing",
    "PlyContact",
    "PAIRS",
    "join_neighbours",
    "join_plies",
    "PlyContactBlock",
    "penalty_law",
]

#: The search before the exact one (``candidates=CANDIDATES``): the nearest centroids, which
#: miss a near triangle whose centroid is far (elements/ply_search.py).
CANDIDATES = 6
#: The default smoothing width delta as a share of the two faces' half thicknesses a + b
#: (the ply thickness for plies alike): see docs/theory.md §9.3a for the measurements.
SMOOTHING = 1e-3
#: The friction's stick spring k_t (module docstring, "Friction"): "penalty", the point's
#: penalty k_p at any normal force; "normal law", W''(g), the normal law's own stiffness.
STICKS = ("penalty", "normal law")
#: Where the faces lie: along each node's director ("director") or along its ply's nodal normal
#: ("normal"), module docstring "Faces along the normal".
FACES = ("director", "normal")
#: The lower face over a triangle: the flat facet through its offset corners, or the curved
#: surface over them and the lower ply's nodal normals (elements/ply_surface.py).
SURFACES = ("flat", "curved")
#: Which ply carries the contact points (module docstring, "Both ways").
POINTS = ("upper", "lower")


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
    candidates : int, optional
        None (default): each point's candidates hold its nearest triangle, proven
        (elements/ply_search.py: the triangles whose bounding spheres can be within a skin
        of the nearest, kept between calls while the plies move less than the skin). An
        integer >= 1: the search before it, that many nearest centroids at every call, which
        can miss a near triangle whose centroid is far (kept for comparison).
    rule : str
        The contact points of each upper triangle, a key of ``RULES``: "centroid" (default),
        "gauss" (three interior points), "vertices" (node-to-surface, a point at each
        corner of each triangle) or "nodes" (the same contact with one point per node).
    smoothing : float, optional
        delta, mm, the penetration over which the penalty's stiffness ramps up (0: the plain
        k/2 min(g, 0)^2); None: ``SMOOTHING`` (a + b).
    friction : float
        The Coulomb coefficient mu >= 0 between the plies (module docstring, "Friction"); 0
        (default): frictionless, no anchor kept (the points' sides only), the frictionless
        code path alone.
    stick : str
        The friction's stick spring k_t, one of ``STICKS``: "normal law" (default), W''(g),
        the normal law's own stiffness (elements/ply_friction.py), under which plies laid on
        each other with nearly no normal force stick; "penalty", k_p at any normal force
        (module docstring, "Friction").
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
    static_law : str
        The normal law while a quasi-static solver iterates, one of
        ``elements.ply_active_set.LAWS``: "ramp" (default), the smoothed penalty every solver
        takes; "active_set", a primal-dual active set of points under the bilateral penalty
        k/2 g^2, frozen within each Newton iteration and chosen again between them, whose
        converged state is an equilibrium of the plain k/2 min(g, 0)^2
        (elements/ply_active_set.py; frictionless flat faces only). The explicit solver and
        dynamic relaxation take the ramp with either.
    between : tuple of str or (b,) int
        The plies between the two, each a triangle cell-set name or triangle ids (default
        none: neighbours): the contact acts only at its points that face none of them
        (elements/ply_between.py; ``join_plies`` gives a pair that is not neighbours its
        plies between).

    Raises
    ------
    ValueError
        Empty or non-integer selections, a negative or non-finite offset or smoothing, a
        penalty that is not a positive number, fewer than one candidate, an unknown rule,
        faces, surface, points or static_law, static_law "active_set" with friction or
        curved faces, a ``between`` that is not a tuple or list of selections; at
        bind, unknown set names, ids out of range, triangles of no area (coincident or
        collinear corners, named), nodes of the upper triangles that are corners of the
        lower triangles, nodes without directors.
    """

    dofs = DOFS

    def __init__(
        self,
        upper: str | np.ndarray | list[int],
        lower: str | np.ndarray | list[int],
        upper_offset: float | None = None,
        lower_offset: float | None = None,
        penalty: float | None = None,
        candidates: int | None = None,
        rule: str = "centroid",
        smoothing: float | None = None,
        friction: float = 0.0,
        stick: str = "normal law",
        faces: str = "director",
        surface: str = "flat",
        points: str = "upper",
        static_law: str = "ramp",
        between: tuple[str | np.ndarray | list[int], ...] = (),
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
        if candidates is not None and (
            isinstance(candidates, bool)
            or not isinstance(candidates, (int, np.integer))
            or candidates < 1
        ):
            raise ValueError(f"candidates must be None or an integer >= 1, got {candidates!r}")
        self.candidates = None if candidates is None else int(candidates)
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
        if stick not in STICKS:
            raise ValueError(f"stick must be one of {STICKS}, got {stick!r}")
        self.stick = stick
        if faces not in FACES:
            raise ValueError(f"faces must be one of {FACES}, got {faces!r}")
        self.faces = faces
        if surface not in SURFACES:
            raise ValueError(f"surface must be one of {SURFACES}, got {surface!r}")
        self.surface = surface
        if points not in POINTS:
            raise ValueError(f"points must be one of {POINTS}, got {points!r}")
        self.points = points
        if static_law not in LAWS:
            raise ValueError(f"static_law must be one of {LAWS}, got {static_law!r}")
        if static_law == "active_set" and (self.friction > 0.0 or surface != "flat"):
            raise ValueError(
                "static_law='active_set' takes frictionless flat faces only, got "
                f"friction={self.friction!r}, surface={surface!r}"
            )
        self.static_law = static_law
        if isinstance(between, (str, np.ndarray)) or not isinstance(between, (tuple, list)):
            raise ValueError(
                "between must be a tuple of the plies between the two (triangle set names or "
                f"triangle ids), got {between!r}"
            )
        self.between = tuple(
            ply if isinstance(ply, str) else _ids(ply, "between triangle") for ply in between
        )

    def bind(self, body: Body) -> PlyContactBlock:
        mesh = body.mesh
        triangles = mesh.triangles
        sets = mesh.cell_sets("triangle")
        fold = mesh.fold_set_names  # a deck's sets, found by any spelling Abaqus takes
        if isinstance(self.upper, str):
            upper_set = set_named(sets, self.upper, fold)
            upper_nodes = set_named(mesh.node_sets, self.upper, fold)
            if upper_set in sets:
                upper = np.asarray(sets[upper_set], dtype=np.int64)
            elif upper_nodes in mesh.node_sets:
                inside = np.isin(triangles, mesh.node_sets[upper_nodes]).all(axis=1)
                upper = np.flatnonzero(inside)
            else:
                raise ValueError(
                    f"PlyContact: no triangle or node set named {self.upper!r}: the mesh has "
                    f"{sorted(set(sets) | set(mesh.node_sets)) or 'none'}"
                )
        else:
            upper = self.upper
        if isinstance(self.lower, str):
            lower_set = set_named(sets, self.lower, fold)
            if lower_set not in sets:
                raise ValueError(
                    f"PlyContact: no triangle set named {self.lower!r}: the mesh has "
                    f"{sorted(sets) or 'none'}"
                )
            lower = np.asarray(sets[lower_set], dtype=np.int64)
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
        for name, ids in (("upper", upper), ("lower", lower)):
            _refuse_flat(mesh.points, triangles, ids, name)
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
        kind = ActiveSetPlyContactBlock if self.static_law == "active_set" else PlyContactBlock
        if self.points == "lower":  # the points on the lower ply's upper face, x + b d
            # against the upper ply's lower face, x - a d, its triangles turned so that their
            # normal points towards the lower ply (module docstring, "Both ways")
            block = kind(self, cells, above[:, [0, 2, 1]], -b, -a, smoothing, body)
        else:
            block = kind(self, above, cells, a, b, smoothing, body)
        block.between = tuple(self._probe(ply).bind(body) for ply in self.between)
        return block

    def _probe(self, ply: str | np.ndarray) -> PlyContact:
        """The same contact with ``ply`` (one of the plies between) in place of the ply its
        points face, frictionless, on the ramp: its facing tells which points face that ply
        (elements/ply_between.py)."""
        upper, lower = (ply, self.lower) if self.points == "lower" else (self.upper, ply)
        return PlyContact(
            upper,
            lower,
            self.upper_offset,
            self.lower_offset,
            self.penalty,
            self.candidates,
            self.rule,
            self.smoothing,
            faces=self.faces,
            surface=self.surface,
            points=self.points,
        )


def _refuse_flat(points: np.ndarray, triangles: np.ndarray, ids: np.ndarray, name: str) -> None:
    """ValueError naming the triangles ``ids`` of no area in the reference mesh (coincident
    or collinear corners): the faces' normals, the points' barycentric coordinates and the
    penalty's share of area divide by it (elements/ply_projection.py, ply_block.py). The
    shells' own triangles are refused so when the model is compiled (femcore.topology
    ``check_triangles``); these are the contact's triangles, which need not be a shell's.

    Parameters
    ----------
    points : (n, 3) float, mm
    triangles : (t, 3) int, the mesh's triangles
    ids : (m,) int, the contact's triangles among them
    name : "upper" or "lower", for the message
    """
    corners = points[triangles[ids]]  # (m, 3, 3)
    twice = np.linalg.norm(
        np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]), axis=1
    )
    span = corners.reshape(-1, 3)
    diagonal = float(np.linalg.norm(span.max(axis=0) - span.min(axis=0)))
    # the mesh's own tolerance (femcore.topology: area <= ZERO_AREA_TOL diagonal^2)
    flat = ids[twice <= 2.0 * ZERO_AREA_TOL * diagonal**2]
    if flat.size:
        shown = ", ".join(str(int(t)) for t in flat[:10]) + (", ..." if flat.size > 10 else "")
        raise ValueError(
            f"PlyContact: {flat.size} {name} triangle(s) of no area (coincident or collinear "
            f"corners): {shown}; the ply contact needs triangles of positive area"
        )


def _ids(given: Any, what: str) -> np.ndarray:
    array = np.atleast_1d(np.asarray(given))
    if array.size == 0:
        raise ValueError(f"PlyContact: empty {what} selection")
    if array.dtype == bool or not np.issubdtype(array.dtype, np.integer):
        raise ValueError(f"PlyContact: {what} ids must be integers, got {array.dtype}")
    if array.min() < 0:
        raise ValueError(f"PlyContact: {what} id {int(array.min())} is negative")
    return np.unique(array.astype(np.int64))


#: Which pairs of a stack's plies ``join_plies`` puts in contact: "all", every ply with every
#: ply below it; "neighbours", ply k + 1 with ply k alone.
PAIRS = ("all", "neighbours")


def join_plies(
    model: Any,
    count: int,
    half_thickness: float,
    lower_rule: str | None = None,
    pairs: str = "all",
    **options: Any,
) -> None:
    """Add to ``model`` a ``PlyContact`` of ply k on ply j (the triangle sets "ply_k") for
    every j < k ("all", default) or for j = k - 1 alone ("neighbours"), both faces
    ``half_thickness`` (mm) from the mid-surfaces; ``options`` (penalty, rule, smoothing,
    friction, ...) go to every one. The neighbours come first, ply 2 on ply 1 to ply N on
    ply N - 1 (interactions 0 .. N - 2, as ``join_neighbours`` adds them), then the pairs
    that are not neighbours, ply 3 on ply 1, ply 4 on ply 2, ply 4 on ply 1, ...: each told
    the plies between (``between``), so that it acts only at its points that face none of
    them, where those plies have left (a middle ply drawn out of the stack), however far the
    penalties' give has closed its gap (docs/theory.md §9.3b, "Plies that are not
    neighbours"). With ``lower_rule`` (a key of
    ``RULES``), each contact is followed by its mirrored pass (``points="lower"``) with the
    lower ply's points at that rule."""
    if pairs not in PAIRS:
        raise ValueError(f"pairs must be one of {PAIRS}, got {pairs!r}")
    ordered = [(k, k - 1) for k in range(2, count + 1)]
    if pairs == "all":
        ordered += [(k, j) for k in range(3, count + 1) for j in range(k - 2, 0, -1)]
    for k, j in ordered:
        # a pair that is not neighbours acts only where its points face none of the plies
        # between (elements/ply_between.py): a penalty's give closes its gap under pressure
        between = tuple(f"ply_{i}" for i in range(j + 1, k))
        model.interact(
            PlyContact(
                f"ply_{k}", f"ply_{j}", half_thickness, half_thickness, between=between, **options
            )
        )
        if lower_rule is not None:  # the mirrored pass (module docstring, "Both ways")
            mirrored = dict(options, rule=lower_rule, points="lower", between=between)
            model.interact(
                PlyContact(f"ply_{k}", f"ply_{j}", half_thickness, half_thickness, **mirrored)
            )


def join_neighbours(
    model: Any, count: int, half_thickness: float, lower_rule: str | None = None, **options: Any
) -> None:
    """Add to ``model`` a ``PlyContact`` of ply k + 1 on ply k for k = 1 .. count - 1 alone
    (``join_plies`` with ``pairs="neighbours"``: plies that are not neighbours never touch)."""
    join_plies(model, count, half_thickness, lower_rule, "neighbours", **options)
