"""How a ply contact's point meets the lower ply's face (elements/ply_contact.py): the penalty
law of its gap, and the facing triangle its search picks among the candidates.

Gap and energy. Each point faces the triangle of the lower face found below; its gap is the
signed distance of p to that triangle's plane, g = (p - y_1) . n, n the unit normal of the
offset triangle (towards the upper ply: the lower ply's triangles must be counter-clockwise
about the direction from the lower ply to the upper). The energy of a point is a one-sided
penalty whose stiffness ramps up over a penetration of ``smoothing`` delta (mm):

    W'' = k for g <= -delta,   k (-g / delta) for -delta < g < 0,   0 for g >= 0,

so W' = k (g + delta/2) and W = k/2 (g + delta/2)^2 + k delta^2 / 24 in penetration past
delta, W' = -k g^2 / (2 delta) and W = -k g^3 / (6 delta) on the ramp, nothing apart: W is
C2, the contact force and its stiffness are continuous at contact. Why: frictionless plies
that sag together carry almost no contact force, so the equilibrium sits at g ~ 0, where the
second derivative of the plain k/2 min(g, 0)^2 jumps from k to 0 and Newton's tangent switches
the contact on and off from one iteration to the next. Why not a softplus s(g) in k/2 s^2
(smooth on both sides): it pushes plies that merely touch apart by k delta log(2) / 2, and the
automatic penalty of a ply stack is so stiff against its weight (the 2-ply sag of
tests/test_plies.py: 0.96 N at delta = 1e-3 h/N against 2.5e-3 N of gravity per ply) that the
plies came apart by 170 delta. The price of the ramp: a pressed contact penetrates delta / 2
further than the plain penalty at the same force (F = k (|g| - delta / 2)). ``smoothing=0``
is the plain k/2 min(g, 0)^2. A point counts as touching when g < 0 (g <= 1e-9 of the mesh
size without smoothing: plies laid on each other then have the contact's stiffness from the
first iteration) and its projection is within ``MARGIN`` of the triangle.

Measured with solvers.Static (docs/theory.md §9.3a): the 4-ply sag of tests/test_plies.py
took no convergence (nodes, plain penalty), 30 iterations and a cut (centroids, plain), 24
(centroids and the ramp; 26 at 8 plies); the 4-ply bai-5.1 strip fails with the plain
penalty at nodes or centroids and with the ramp at nodes, and converges with centroids and
the ramp. The ramp has its own cost: where plies need no contact force, points near g = 0
step in and out of it and Newton converges linearly (up to ~100 iterations in an increment).

Search. Each point's candidates hold its nearest triangle and every near tie, proven
(elements/ply_search.py: bounding spheres and exact distances, lists kept between calls
while the plies move less than their skin); over them (vectorised, no loop over
points) the barycentric projection of p, and the point faces the nearest candidate: by the
distance to its plane where the triangle holds the projection (the gap g the signed distance
to that plane, n its normal, lambda the projection's coordinates), else by the distance to
its closest point q on an edge or at a vertex (g = +-|p - q|, signed by the triangle's
normal; n = (p - q) / g, the gap's gradient in p; lambda those of q); ties to the lowest
triangle row. A triangle whose edge lies on the lower ply's outline (``open_edges``) reaches
``MARGIN`` past that edge, so a point just past the outline keeps the distance to the
triangle's plane (as the extended plane carried it before). Why: a distance to a set is
1-Lipschitz, so the gap and the force move no more than the point where the facing triangle
changes. Before, the point faced the deepest of the triangles holding its projection, else
the nearest triangle's extended plane, and both jumped where the choice changed: measured on
the [0/45] Mindlin plies on the hemisphere (validation/studies/hemisphere_plies.py, coarse), a
top-ply point pressed by the holder into a wrinkle crest of the bottom ply and past both crest
triangles' edges went from -0.45 to -2.24 mm in one step, +55.5 N mm of energy with no work
(tests/test_ply_facet_switch.py). Over a fold or at an inner vertex the sign is the
feature's (p - q lies in the cone of its triangles' normals there, on which a triangle's own
normal can be negative where the fold is sharper than a right angle: "The sign at an edge"
below); past the outline it would flip where p passes the face's plane beside the edge,
which ``MARGIN`` keeps out of the contact. The gap's Hessian at an edge or a vertex
(elements/ply_edge_gap.py) enters the tangent. The answer is that of a search over every triangle,
bit for bit (tests/test_ply_search.py); the k nearest centroids of before missed a near
triangle whose centroid is far (a wrinkle's flank). Where the facing triangle does not change
the energy is smooth.

The sign at an edge. Where q lies on an edge or at a vertex shared by several triangles,
the sign of g = +-|p - q| is taken from that edge's or vertex's pseudonormal
(elements/ply_facets.py ``pseudonormals``: the sum of the unit normals of an edge's two
triangles; at a vertex its triangles' unit normals weighted by their angles there), not from
the facing triangle's normal. The pseudonormal gives a closest point's side of the surface
exactly (Baerentzen and Aanaes,
"Signed distance computation using the angle weighted pseudonormal", IEEE TVCG 11 (2005)
243-253): p - q lies in the cone of the feature's normals, on which the pseudonormal is
positive outside and negative inside. A single triangle's normal gives the same sign only
where the fold is gentler than a right angle: across a sharper ridge p - q can point
against one of its triangles' normals while outside (n_1 . (a n_1 + b n_2) = a + b cos
theta < 0), and which triangle faces the point is a tie on q. Measured on the two-ply
Mindlin [0/90] hemisphere (validation/studies/hemisphere_plies.py, 10 cells, 20 N): the
bottom ply's nodes of the mirrored pass beside the flange's folded wrinkles, 0.2-0.3 mm from
an edge of the top ply's face, went from -0.29 to +0.21 mm and back within a few steps,
3-6 N mm of penalty energy made at each switch into contact, +115 N mm over the run
against -50 N mm lost, which stopped the run on its energy balance at 98.5 % of the stroke
(tests/test_ply_edge_sign.py). On a growth past the outline (one triangle) and where the
pseudonormal vanishes (a fold pressed flat, "A layer turned away") the triangle's normal
still signs the gap, but on an edge's extension that two growths hold ("Growths joined"). The
sign then changes only where p passes through the face (g = 0), where W = 0: the energy is
continuous where the facing triangle changes on an edge. A contact sums the pseudonormals only
at the edges and vertices its closest points touch (``pseudonormals_at``, over tables of the
face's topology made once at bind, elements/ply_topology.py), with the whole face's bits.

Growths joined. Two outline triangles A and B that share an inner edge ending at an outline
vertex v, each grown past its own outline edge there (A's and B's outline edges both end at
v, the fan of v holding A and B alone), both hold that edge's extension past v: their growths
meet along it as their faces meet along the edge, a fold of the grown face. A closest point
on that extension is signed by the edge's pseudonormal n_A + n_B, as on the edge itself, and
the fade has no angle factor there (the face has a side); a growth's edge that no
neighbour's growth continues keeps the triangle's normal and the angle factor ("Past the
outline, faded"). Before, the facing triangle's normal (the lower row of the two, tied on q)
signed it, and past a fold sharper than a right angle (a wrinkle's crest at the outline) a
point outside the fold had p - q against that normal: its gap flipped from -|p - q| on the
extension to +|p - q| on the other growth's plane, W(-|p - q|) with no work: a point round a
ridge of 127 deg between its sides' normals, 0.05 mm past the outline, went from -0.080 mm on
the extension to +0.080 mm on the other side's plane, the whole of its energy in one step
(tests/test_ply_growth_sign.py).

The wedge cut (elements/ply_wedge.py). At an outline vertex of three or more triangles (the
middle ones touching the outline there alone, not grown) A's and B's growths reached past the
vertex up to the lines of their inner edges, each on its outline edge's side, so both held the
wedge between those lines (the middle triangles' angle mirrored through the vertex): across a
fold their planes signed a point between them oppositely and the sign flipped where the nearer
changed (on the two-ply hemisphere every outline vertex but two corners; tests/test_ply_wedge.py:
the whole of a point's energy in one step). Each growth is now cut by a ray from the vertex
fixed at bind in its own barycentric coordinates, near the wedge's bisector (or the line where
A's and B's planes meet, where they are folded at bind), leaning GAP of the wedge's angle to
its own side: a candidate holds the projection where every cut keeps it too, and else faces
the cut growth's closest point, on a cut a growth's edge like the others (the triangle's
normal signs the gap, the angle's fade beside it, its Hessian that of a segment,
elements/ply_edge_gap.py). The wedge is then held by at most one growth, with a thin gap
between the two (docs/hemisphere_plies.md, "The wedge is an overlap").

Beside the outline. The growth past an outline edge extends the triangle's other two edges
too, and past their ends (beside the outline, next to an outline vertex) a point can be
nearest to such an extended edge while no candidate holds its projection: there p passes the
triangle's plane at a distance from q, and the sign of g = +-|p - q| flips in one step.
Measured on the [0/45] Mindlin plies on the hemisphere (validation/studies/hemisphere_plies.py,
coarse, 10 N): a top-ply point 6 mm past the bottom ply's outline went from +2.80 to -2.83 mm,
+92 N mm in one step (tests/test_ply_facet_switch.py). Such a point was first made beside the
ply (no contact), then allowed to touch while its closest point lay within ``depth`` of the
triangle: plies meshed alike put the mirrored pass's nodes right at the other ply's outline
vertices, in the thin wedge the growths leave there where the face folds, and the fibrous
[0/90] hemisphere (8 cells, 40 N) stopped at 22 % of the stroke on their toggles in and out
of contact. Both rules switched a point's contact at a gap away from zero: on the Mindlin
[0/90] hemisphere at 10 cells (validation/studies/hemisphere_plies_jumps.py) the mirrored
pass's outline nodes came into contact at -0.27 to -0.30 mm (2-3 N mm in a step) and flipped
sign beside an outline vertex (1-1.5 N mm): 18 steps above +1 N mm, +34.7 N mm in all.

Past the outline, faded (elements/ply_fade.py). A point's energy is w W(g), its force the exact
gradient w W' dg/dz + W dw/dz, w in [0, 1] a continuous function of the point and its facing
triangle's corners and the outline's nearest edge: 1 on the face; past an outline edge it falls
(a smoothstep) to 0 over a length D (``FADE`` of the outline triangles' least height) of the
distance d of the point's foot from the outline, d^2 = |p - q_o|^2 - g^2 (q_o the outline's
closest point), before the growths' far edges: one function of the point, whichever growth
faces it (the barycentric overshoot of before differed from one growth to the next); and where
the closest point lies on a growth's edge off the triangle, or at a vertex of the outline,
where the face has no side (there the facing triangle's normal signs the gap), it is also a
smoothstep of |h| / (``SIDEWAYS`` |p - q|), h the gap to the triangle's plane: 0 where p passes
the plane beside q, the one place where the sign flips at a distance. So the energy is
continuous where a point leaves the face past the outline and where its sign flips beside it; a
point touches where w > 0. What is left: a change of facing triangle between a growth (w < 1)
and a triangle whose face holds the point (w = 1), where a growth overlaps another triangle's
face, and between growths whose side factors w_a differ, and the depth bounds below (at most
W(-depth)). The growths still keep the gap a distance where the facing triangle changes past
the outline. The mortar methods' contact (segment to segment, Puso and Laursen, CMAME 193
(2004) 601) fades so by construction, the contact integrated over the two faces' overlap, which
shrinks to nothing at an outline; a point-to-face contact needs the weight. The tangent takes
w's second derivative in closed form (elements/ply_fade_hessian.py).

Past the outline, deeper than the plies. A point held by a growth's plane (its projection
past the outline, within MARGIN) deeper than ``depth`` touches as on the face: the fade
carries its energy w W(g) from the face's full W at the outline edge to 0 at ``FADE`` past
it, continuously, before the growth's far edge, where it used to pass between touching on
the plane and beside on the edge at any depth (measured on the Mindlin [0/45] two-ply
hemisphere, 8 cells, 20 N: the bottom ply's corner node, 3.35 mm behind the top ply's face on
a growth's far edge, came into contact in one step, +146 N mm at k = 26 N/mm, and stopped the
run at 67 % of the stroke; tests/test_ply_facet_switch.py). Before, such a point was beside
the ply, a switch at the outline edge itself: on the Mindlin [0/90] hemisphere at 10 cells
(validation/studies/hemisphere_plies_jumps.py) a mirrored-pass point 2.21 mm deep moved from
a growth's plane onto the face of the same triangle and came into contact at full depth,
+169.8 N mm in one step, and the run stopped on its energy balance at 99 % of the stroke
(tests/test_ply_outline_fade.py). A point beside a growth's edge or at an outline vertex keeps
the bound of an edge ("Deeper than the plies"), so a deep point passing there from a growth's
plane still loses w W(g) in a step: without that bound too, the same run stopped at 83 % of
the stroke on a point that passed from facing an outline triangle off its growths, +3.20 mm,
onto a growth's edge, -3.20 mm signed by the triangle's normal, +109.9 N mm in a step. The price: a
deep point in the band carries w W(g) and w's gradient, a stiffness growing as (|g| / D)^2
(elements/ply_fade.py, "Stiffness"; ``PlyContactBlock.springs_at`` takes each touching
point's own depth); passing between growths it keeps w, one function of its distance to the
outline.

Deeper than the plies. Where the lower ply is folded back onto itself (a wrinkle's flap laid
over, the two triangles of the fold with opposite normals), a point past the fold's edge is
as near to the one as to the other and its sign by the one is the opposite of its sign by
the other: measured on the [0/90] Mindlin plies on the hemisphere (coarse, 10 N) at 92 % of
the stroke, a top-ply point 9.6 mm beside a flap standing on the flange went from +9.67 mm
(held by one triangle of the fold) to -9.56 mm (the other's, tied on their shared edge),
+1060 N mm in one step. No choice among the tied candidates is right everywhere (taking the
one the point is outside of mends the fold and flips the sign where a point passes a
ridge's end vertex). So a point facing an edge or a vertex touches only down to a gap of
-``depth``, the two faces' half thicknesses (``PlyContactBlock`` gives them): a point that
deep in a ply and past its triangles has gone past the ply's edge.

A layer turned away. Where the flap is pressed flat, two of its triangles lie on each other
with opposite normals and both hold a point's projection at nearly the same distance, one
giving +g and the other -g: measured on the same run at 97.2 % of the stroke, the nearest
switched between them (+4.97 to -4.98 mm, +546 N mm in one step), where the point faces the
triangles' planes. No choice among such candidates keeps the gap continuous where it
switches between opposite signs (keeping the last facing triangle while it holds the
projection needs a history; the contact keeps each point's side, elements/ply_sides.py,
which holds off a point found behind a sheet it did not touch). But the one whose normal
points against the point's own ply (``toward``: from the lower ply to the point's,
n . toward < 0) is the layer turned away: its upper face looks away from the point, which
faces its lower face, carried by no contact. So a point facing such a triangle's plane also
touches only down to -``depth``; deeper, it lies beyond that layer. The energy then jumps by
at most W(-depth) = k (depth + delta / 2)^2 / 2 where a point crosses -depth or flips,
whatever the flip's size (1.04 N mm at the plies' 0.3 mm and 23 N/mm of the coarse
hemisphere). Why not bound every point so: Newton's trial states press points deeper than
the plies into a layer that does face them, and lost there they stalled the Static solver
(the holder pressing a layup onto the die and the ply pulled on another, tests/test_plies.py
and tests/test_ply_layups.py: no convergence in 8 cuts). The curved faces
(elements/ply_curved.py) have no such bound.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from elements import ply_chosen, ply_edge_kernels, ply_kernels, ply_penalty
from elements.ply_edge_gap import towards_closest
from elements.ply_facets import (  # noqa: F401 (re-exported)
    INSIDE,
    _feature_normals,
    closest_on_edges,
    facets,
    pseudonormals,
    pseudonormals_at,
    triangle_frames,
)
from elements.ply_topology import FaceTopology, edge_ids, open_edges  # noqa: F401 (re-exported)
from elements.ply_wedge import WedgeCuts
from femcore.jit import SMALL_LOOP

if TYPE_CHECKING:  # ply_fade imports this module
    from elements.ply_fade import OutlineTree

__all__ = [
    "COMPILED",
    "INSIDE",
    "MARGIN",
    "Facing",
    "choose",
    "closest_facing",
    "closest_on_edges",
    "edge_ids",
    "open_edges",
    "facets",
    "grown_corners",
    "penalty_law",
    "pseudonormals",
    "pseudonormals_at",
    "triangle_frames",
]

#: How far past a triangle's edges (in barycentric units) its plane still carries a point.
MARGIN = 0.5
#: Whether ``closest_facing`` takes its candidates' planes, choice, edges' signs and flags,
#: and the fade from the compiled passes (elements/ply_kernels.py, ply_choice.py,
#: ply_edge_kernels.py, ply_fade_kernels.py: the same bits), or from numpy (``facets``,
#: ``closest_on_edges``, ply_fade.py: their reference, kept for the tests); and whether
#: ``PlyContactBlock.internal_force`` sums the flat faces' loads in one compiled pass
#: (elements/ply_load_kernels.py, the same bits) or by numpy (``_pair_loads``, ``_end_loads``,
#: ``ply_friction.friction_loads`` and ``np.bincount``), and its friction's return mapping and
#: history (elements/ply_friction_kernels.py) or ``ply_friction``'s numpy.
COMPILED = True
WHOLE = True  # closest_facing's small compiled path in two calls (ply_facing_whole.py)


def penalty_law(gap: np.ndarray, stiffness: np.ndarray, smoothing: float):
    """The energy W of one contact point and its first two derivatives in the gap.

    Parameters
    ----------
    gap : (t,) float
        g, mm (< 0: penetration).
    stiffness : (t,) float
        k, N/mm.
    smoothing : float
        delta, mm: the penetration over which the stiffness ramps from 0 to k (module
        docstring); 0: W = k/2 min(g, 0)^2.

    Returns
    -------
    energy (t,) N mm, force (t,) N (dW/dg, <= 0), stiffness (t,) N/mm (d2W/dg2, >= 0).
    """
    if smoothing == 0.0:
        g = np.minimum(gap, 0.0)
        return 0.5 * stiffness * g**2, stiffness * g, np.where(gap <= 0.0, stiffness, 0.0)
    if COMPILED and np.ndim(gap) == 1 and np.shape(stiffness) == np.shape(gap):
        # one pass, the same bits (elements/ply_penalty.py)
        return ply_penalty.smoothed_law(gap, stiffness, smoothing)
    delta = smoothing
    g = np.minimum(gap, 0.0)
    deep = g <= -delta
    energy = np.where(
        deep, 0.5 * stiffness * (g + 0.5 * delta) ** 2 + stiffness * delta**2 / 24.0, 0.0
    )
    energy = np.where(deep, energy, -stiffness * g**3 / (6.0 * delta))
    force = np.where(deep, stiffness * (g + 0.5 * delta), -stiffness * g**2 / (2.0 * delta))
    curvature = np.where(deep, stiffness, -stiffness * g / delta)
    return energy, force, curvature


@dataclass(frozen=True)
class Facing:
    """Each contact point's facing triangle at a state (``PlyContactBlock.facing``).

    triangle : (P,) int
        Row of the block's lower triangles facing each point.
    gap : (P,) float
        g, mm: signed distance of the point from the facing offset triangle's plane (< 0:
        penetration).
    normal : (P, 3) float
        Unit normal n of the facing offset triangle (towards the upper ply).
    weights : (P, 3) float
        Barycentric coordinates lambda of the projection of the point.
    gradients : (P, 3, 3) float
        In-plane gradients of the triangle's barycentric functions, 1/mm (row k: grad phi_k).
    touching : (P,) bool
        g < 0 (g <= 1e-9 of the mesh's size with no smoothing) and the projection within
        ``MARGIN`` of the triangle.
    face : (P, 3) float
        The contact points p = sum_j N_j (x_j - a_j d_j), mm.
    hessian : (P, 4, 3, 4, 3) float or None
        d2g/dz2 over z = (p, y_1, y_2, y_3), 1/mm, where the gap is to the closest point q on
        an edge or at a vertex (module docstring, "Search"; elements/ply_edge_gap.py); zero where it
        is to a triangle's plane (whose Hessian ``PlyContactBlock.tangent`` builds); None when
        not asked for (``closest_facing(second=False)``) or every gap is to a plane.
    fade : (P,) float or None
        The fade w past the outline (elements/ply_fade.py; None on the curved faces).
    fade_gradient : (P, 6, 3) float or None
        dw/dz over z = (p, y_1, y_2, y_3, a, b), 1/mm, a and b the ends of the outline's
        edge nearest the point (``fade_edge``).
    reach : (P, 3) float or None
        How far the facing triangle reaches past its edges (``MARGIN`` on the outline).
    on_growth : (P,) bool or None
        The closest point lies on a growth's edge off the triangle (a cut's too,
        elements/ply_wedge.py) or at an outline vertex.
    on_edge : (P,) bool or None
        The gap is to the closest point on an edge or at a vertex, not to the facing
        triangle's plane (the rows of ``hessian`` it gives); None on the curved faces.
    joined : (P,) bool or None
        Of those, the closest point lies on the extension past the outline of an edge whose
        two triangles both grow past it (module docstring, "Growths joined"): the edge's
        pseudonormal signs the gap and the fade has no angle factor there.
    fade_edge : (P,) int or None
        The outline's edge nearest the point (its row in ``open_edges``' nonzero order,
        elements/ply_fade.py ``outline_segments``), -1 where w is not computed.
    """

    triangle: np.ndarray
    gap: np.ndarray
    normal: np.ndarray
    weights: np.ndarray
    gradients: np.ndarray
    touching: np.ndarray
    face: np.ndarray
    hessian: np.ndarray | None = None
    fade: np.ndarray | None = None
    fade_gradient: np.ndarray | None = None
    reach: np.ndarray | None = None
    on_growth: np.ndarray | None = None
    fade_edge: np.ndarray | None = None
    joined: np.ndarray | None = None
    on_edge: np.ndarray | None = None


def choose(
    gap: np.ndarray, weights: np.ndarray, area2: np.ndarray, deepest: bool = True
) -> np.ndarray:
    """(P,) the column of each point's facing candidate on the curved faces
    (elements/ply_curved.py; the flat faces take ``closest_facing``'s nearest): among those
    whose projection lies in the patch, the one the point penetrates most (``deepest``) or
    the nearest, else the nearest by sqrt(g^2 + (o sqrt(2 A))^2), o the projection's
    overshoot past the edges.

    gap : (P, K) float, mm; weights : (P, K, 3) barycentric coordinates of the projections;
    area2 : (P, K) float, twice the candidates' areas, mm^2.
    """
    overshoot = np.maximum(0.0, -weights.min(axis=-1))
    distance = np.hypot(gap, overshoot * np.sqrt(area2))
    # Over a concave fold two triangles hold the projection: the deeper penetration
    # counts (W = k/2 max(p_A, p_B)^2 is convex in the pair, a kink Newton crosses);
    # over a convex one none holds it: the nearest triangle.
    inside = overshoot <= INSIDE
    return np.where(
        inside.any(axis=1),
        np.argmin(np.where(inside, gap, np.inf), axis=1)
        if deepest
        else np.argmin(np.where(inside, np.abs(gap), np.inf), axis=1),
        np.argmin(distance, axis=1),
    )


def grown_corners(corners: np.ndarray, reach: np.ndarray) -> np.ndarray:
    """Corners (..., 3, 3) of triangles grown by ``reach`` (..., 3) barycentric units past the
    edges opposite each corner: corner i of the grown one at lambda_j = -reach_j (j != i).
    Compiled (``COMPILED``, the same bits) for (m, 3, 3) corners."""
    if COMPILED and corners.ndim == 3 and reach.shape == corners.shape[:2]:
        return ply_kernels.grown_corners(corners, reach)
    grow = np.eye(3) * (1.0 + reach.sum(axis=-1))[..., None, None] - reach[..., None, :]
    return np.einsum("...ij,...jc->...ic", grow, corners)


def closest_facing(
    p: np.ndarray,
    y: np.ndarray,
    near: np.ndarray,
    tolerance: float,
    outline: np.ndarray | None = None,
    second: bool = False,
    depth: float = np.inf,
    toward: np.ndarray | None = None,
    nodes: np.ndarray | None = None,
    edges: np.ndarray | None = None,
    fade_distance: float | None = None,
    topology: FaceTopology | None = None,
    outline_tree: OutlineTree | None = None,
    cuts: WedgeCuts | None = None,
) -> Facing:
    """Each contact point's facing triangle, gap, normal and projection (module docstring,
    "Search": among the candidates, the one holding the projection that the point
    penetrates most, else the closest point of the candidates).

    Parameters
    ----------
    p : (P, 3) float
        The contact points, mm.
    y : (m, 3, 3) float
        The lower face's triangles' corners, mm.
    near : (P, K) int
        Each point's candidate triangles (rows of ``y``).
    tolerance : float
        The gap (mm) at or below which a point counts as touching.
    outline : (m, 3) bool, optional
        ``open_edges`` of the lower face: a triangle reaches ``MARGIN`` past those edges.
        None: no edge is on the outline.
    second : bool
        Give the gap's Hessian where a point faces an edge or a vertex (``Facing.hessian``,
        for the tangent); else None.
    depth : float
        mm: a point with a gap below -depth does not touch where it faces an edge, a vertex
        or, with ``toward``, a triangle turned away from it (module docstring, "Deeper than
        the plies"; the contact passes both faces' half thicknesses); held by a growth's
        plane, the fade carries it ("Past the outline, deeper than the plies").
    toward : (P, 3) float, optional
        Each point's direction from the lower ply to its own (any length; the side towards
        which a facing triangle's normal points): a triangle whose normal points against it
        is a layer turned away. None: no triangle counts as turned.
    nodes : (m, 3) int, optional
        The node ids of the lower face's triangles (shared by neighbours): a gap to a closest
        point on an edge or at a vertex takes its sign from that edge's or vertex's
        pseudonormal (module docstring, "The sign at an edge"). None: from the facing
        triangle's normal.
    edges : (m, 3) int, optional
        ``edge_ids(nodes)``, kept by a caller that searches the same mesh many times
        (computed when None).
    fade_distance : float, optional
        The fade's length D past the outline, mm (elements/ply_fade.py ``fade_length``, which
        gives it from ``y`` when None; a contact keeps its reference state's).
    topology : FaceTopology, optional
        ``FaceTopology.of(nodes, outline, edges)`` (elements/ply_topology.py), made once by a
        caller that searches the same mesh many times (made here from ``nodes`` when None;
        given, it stands for ``nodes`` and ``edges``, and its outline must be ``outline``).
    outline_tree : OutlineTree, optional
        The outline's KD-tree kept between calls (elements/ply_fade.py ``OutlineTree``) by a
        caller that searches the same mesh many times; None: built at the call if needed.
    cuts : WedgeCuts, optional
        The growths' cuts past outline vertices of three or more triangles
        (elements/ply_wedge.py, made at bind; "The wedge cut"). None: no cut.
    """
    if topology is None and nodes is not None:
        topology = FaceTopology.of(nodes, outline, edges)
    elif topology is not None and topology.outline is not outline:
        raise ValueError("closest_facing: the topology's outline must be the outline given")
    if near.ndim != 2 or len(near) != len(p) or (len(p) and near.shape[1] < 1):
        # the compiled passes size their loops by ``near``, their outputs by ``p``
        raise ValueError(
            f"closest_facing: near must hold K >= 1 candidates for each of the {len(p)} "
            f"points, shape ({len(p)}, K); got {near.shape}"
        )
    small = COMPILED and topology is not None and len(p) < SMALL_LOOP
    if WHOLE and small and outline is not None and not second:  # the same bits, two calls
        from elements.ply_facing_whole import whole_facing

        given = (tolerance, outline, depth, toward, fade_distance, topology, outline_tree, cuts)
        return whole_facing(p, y, near, *given)
    if small:
        # the three passes below in one compiled call, the same bits (ply_facing_pass.py);
        # the candidates' planes are read only by the numpy path's edges
        from elements.ply_facing_pass import facing_choice

        choice, picked = facing_choice(p, y, near, outline, MARGIN, INSIDE, cuts, toward)
    else:
        if COMPILED:  # the same bits as the numpy reference below (elements/ply_kernels.py)
            n, gradients, gap, weights, reach, inside, past = ply_kernels.candidates_at(
                p, y, near, outline, MARGIN, INSIDE
            )
        else:
            n, _, gradients, gap, weights = facets(p, y[near])
            reach = (
                np.zeros(weights.shape) if outline is None else np.where(outline[near], MARGIN, 0.0)
            )
            inside = (weights >= -reach - INSIDE).all(axis=-1)
            # a lower bound of the distance to a triangle that does not hold the projection:
            # its plane's gap and the projection's distance -(lambda_k + reach_k) /
            # |grad phi_k| to the farthest edge line it lies past
            past = np.max(-(weights + reach) / np.linalg.norm(gradients, axis=-1), axis=-1)
        # the nearest candidate and its closest point ("Search", "The wedge cut")
        from elements import ply_choice

        choose = ply_choice.choose_facing if COMPILED else ply_choice.choose_facing_numpy
        choice = choose(p, y, near, n, gradients, gap, weights, reach, inside, past, cuts)
        # its arrays (elements/ply_chosen.py; ``lam`` the projection's, then the closest
        # point's)
        pick = ply_chosen.chosen if COMPILED else ply_chosen.chosen_numpy  # the same bits
        picked = pick(choice[0], near, n, gap, weights, gradients, reach, toward)
    best, on_edge, closest_at, cut_at, segment_at, along_at = choice
    triangle, chosen_gap, normal, lam, chosen_gradients, chosen_reach = picked[:6]
    overshoot, reached, turned = picked[6:]
    hessian = np.zeros((len(p), 4, 3, 4, 3)) if second else None
    # the chosen planes, which the fade's pass reads where the closest point is off them
    planes = (normal.copy(), chosen_gradients, chosen_gap.copy(), lam.copy()) if COMPILED else ()
    at_rim = np.zeros(len(p), dtype=bool)  # closest at a vertex of the lower ply's outline
    joined = np.zeros(len(p), dtype=bool)  # on an edge's extension that two growths hold
    if COMPILED and topology is not None:  # the same bits, two passes (ply_edge_kernels.py)
        joined, at_rim, on_growth, beside, near, touching = ply_edge_kernels.edge_sides(
            p, y, topology, (on_edge, closest_at, cut_at, segment_at, along_at), triangle,
            chosen_gap, normal, lam, chosen_gradients, chosen_reach, reached, turned,
            overshoot, (INSIDE, depth, tolerance, MARGIN), hessian,
        )  # fmt: skip
    elif on_edge.any():
        edge = np.flatnonzero(on_edge)
        at = best[edge]
        signing = n[edge, at]
        closest = closest_at[edge]
        cutting = cut_at[edge]
        reach_at, facing_at = chosen_reach[edge], triangle[edge]
        if topology is not None:  # the sign by the feature's pseudonormal ("The sign at an edge")
            # q's barycentric coordinates on the facing triangle: on which edge or at which
            # vertex it lies
            on_q = np.einsum("pki,pi->pk", chosen_gradients[edge], closest - y[facing_at, 0])
            on_q[:, 0] += 1.0
            # (numpy's: the compiled facing takes the passes above)
            signing, joined[edge] = _feature_normals(
                y, topology, facing_at, on_q, reach_at, signing
            )
            if outline is not None:
                # at a vertex of the outline the face has no side either: the facing
                # triangle's normal signs the gap, and the point is faded as beside a
                # growth's edge ("Past the outline, faded")
                bound = on_q <= -reach_at + 1e-9
                corner = topology.nodes[facing_at, np.argmin(bound, axis=1)]
                at_rim[edge] = (bound.sum(axis=1) == 2) & topology.rim[corner]
                signing = np.where(at_rim[edge][:, None], n[edge, at], signing)
                joined[edge] &= ~at_rim[edge]
            # on a cut the face has no side either: as beside a growth's edge ("The wedge cut")
            signing = np.where(cutting[:, None], n[edge, at], signing)
            joined[edge] &= ~cutting
            at_rim[edge] |= cutting
        chosen_gap[edge], normal[edge], lam[edge], bend = towards_closest(
            p[edge],
            closest,
            signing,
            y[facing_at],
            chosen_gradients[edge],
            reach_at,
            second,
            (cutting, segment_at[edge], None if along_at is None else along_at[edge]),
        )
        if hessian is not None:
            hessian[edge] = bend
    # the fade past the outline, and beside a growth's edge or an outline vertex ("Past the
    # outline, faded"): a point whose closest point lies there, off the face's sides, signed
    # by the facing triangle's normal
    from elements import ply_fade

    if not (COMPILED and topology is not None):
        on_growth = on_edge & (lam.min(axis=-1) < -INSIDE) & reached
        on_growth |= at_rim
        # a point deeper than the plies is on the lower ply's other side where it faces an
        # edge, a vertex or a turned layer ("Deeper than the plies"); held by a growth's plane
        # past the outline, the fade carries its energy to 0 continuously from the face's full
        # W ("Past the outline, deeper than the plies")
        deep = chosen_gap < -depth
        beside = on_edge & deep
        beside |= turned & deep  # a layer turned away from its ply ("Deeper than the plies")
        near = on_growth | reached
        # touching within MARGIN of the facing triangle, by the overshoot of the plane's
        # projection (and where the fade below is above 0)
        touching = (chosen_gap <= tolerance) & (overshoot <= MARGIN) & ~beside
    # w = 1 off the outline triangles and their growths: computed where it can differ
    fade, fade_gradient = np.ones(len(p)), np.zeros((len(p), 6, 3))
    fade_edge = np.full(len(p), -1)
    near_outline = np.flatnonzero(near)
    if near_outline.size and outline is not None:
        if topology is None:
            segment_rows, segment_ends = ply_fade.outline_segments(outline)
        else:
            segment_rows, segment_ends = topology.segment_rows, topology.segment_ends
        starts = y[segment_rows, segment_ends[:, 0]]
        ends = y[segment_rows, segment_ends[:, 1]]
        length = ply_fade.fade_length(y, outline) if fade_distance is None else fade_distance
        every = COMPILED and near_outline.size * len(starts) <= ply_fade.EVERY_PAIR  # each pair
        nearest = ply_fade.nearest_segments
        chosen = None if every else nearest(p[near_outline], starts, ends, outline_tree)
        if COMPILED:  # the edges, inputs, growths' closest points, fade: one pass, the same bits
            from elements.ply_fade_kernels import outline_fade_at

            out = (fade, fade_gradient, fade_edge)
            outline_fade_at(
                near_outline, p, y, triangle, planes, chosen_reach, on_growth, joined, chosen,
                starts, ends, cuts, length, out,
            )  # fmt: skip
        else:
            fade_edge[near_outline] = chosen
            at_p, corners, at_reach, at_beside, at_ends, at_joined, lines, cut_ends = (
                ply_chosen.fade_inputs_numpy(
                    near_outline, p, y, triangle, chosen_reach, on_growth, joined, starts,
                    ends, chosen, cuts,
                )
            )  # fmt: skip
            fade[near_outline], fade_gradient[near_outline] = ply_fade.outline_fade(
                at_p, corners, at_reach, at_beside, at_ends, length, at_joined, lines, cut_ends
            )
    touching &= fade > 0.0
    return Facing(
        triangle=triangle,
        gap=chosen_gap,
        normal=normal,
        weights=lam,
        gradients=chosen_gradients,
        touching=touching,
        face=p,
        hessian=hessian,
        fade=fade,
        fade_gradient=fade_gradient,
        reach=chosen_reach,
        on_growth=on_growth,
        fade_edge=fade_edge,
        joined=joined,
        on_edge=np.asarray(on_edge, dtype=bool),
    )
