"""The frictionless contact of a node set with a rigid tool (a plane, a sphere or a flat
ring, elements/annulus.py, or a meshed tool, elements/rigid_surface.py) in one compiled pass over
the nodes: the tool's signed distance and normal, the penetration and the force k p n of
each node (elements/contact.py, docs/theory.md §9), the formulas of
``ContactBlock.contact_forces`` with the tool's ``distance`` in the same order of operations.

A meshed tool (a forming die) first brings its candidate lists up to date where nodes have
moved past their margin (``RigidSurface._prepared``, numpy, a batch every few hundred
steps) and finds each node's closest facet in its list (or keeps it: the compiled loop of
elements/facet_search.py ``closest_facets_kept``); one pass then gives each node its signed
distance and normal (the open-edge correction, the far nodes' estimate of
``RigidSurface.distance``) and its force, without the arrays the numpy path makes between
those. (The two loops as one, the closest-facet loop's body a helper of the pass, made the
kept facets' loop 2.4 times slower: 2.2-2.6 against 0.9-1.1 ms on the 20k blank's 10201
nodes, one thread, load 6.4.) It keeps no facet record (that is Static's, turned on by
``ContactBlock.freeze``). The smoothed tool's normal field and the old candidate scan
(``KEEP_NEAREST`` off) keep the numpy path. Measured on the 20k-triangle forming blank, one
thread: the die's contact 5.9 against 7.3 ms CPU a call at the stroke's peak pace, 2.7
against 5.7 with the blank nearly still (benchmarks/hemisphere_forming.py).

Why: an explicit forming step asks every contact node of the punch and of the holder for its
force, and the numpy path makes a dozen (s, 3) arrays to do it (the distance, the normal, the
penetration, the zero friction, the product), about as costly as the die's compiled
closest-facet search. ``Contact.bind`` gives a ContactBlock this pass (its ``compiled_forces``)
where it gives the same numbers: frictionless, undamped, not augmented, a plane, a sphere or
a ring;
every other contact keeps the numpy formulas, as does a frozen contact set of the quasi-static
solvers (a history). Its forces agree with the numpy formulas to round-off (the plane's dot
product may be summed in another order by numpy's matrix product; tests/test_tool_contact.py
holds them to 1e-12 of the largest force).
"""

from __future__ import annotations

import math

import numpy as np

from elements import rigid_surface
from elements.annulus import RigidAnnulus
from elements.contact import ContactBlock
from elements.node_rows import same_rows, shifted
from elements.rigid_surface import RigidSurface
from elements.tools import RigidPlane, RigidSphere, RigidTool
from femcore.jit import jit, prange

__all__ = [
    "annulus_forces", "compiled_pass_applies", "contact_forces", "plane_forces", "sphere_forces",
    "surface_forces",
]  # fmt: skip


def _sphere_forces(x, origin, radius, sign, offset, stiffness, out):
    """Each node's contact force (s, 3), N, from a sphere of ``radius`` (mm) about
    ``origin`` (3,): x (s, 3) the nodes where the tool sees them (less a driven tool's free
    translation), mm; ``sign`` +1 for the body outside, -1 inside; ``offset``
    (s,) the contact offsets h / 2, mm; ``stiffness`` (s,) k, N/mm. Into ``out`` (s, 3)."""
    for i in prange(x.shape[0]):
        r0 = x[i, 0] - origin[0]
        r1 = x[i, 1] - origin[1]
        r2 = x[i, 2] - origin[2]
        length = np.sqrt(r0 * r0 + r1 * r1 + r2 * r2)
        scale = length if length > 0.0 else 1.0
        d = sign * (length - radius)
        p = max(offset[i] - d, 0.0)
        kp = stiffness[i] * p
        out[i, 0] = kp * (sign * (r0 / scale))
        out[i, 1] = kp * (sign * (r1 / scale))
        out[i, 2] = kp * (sign * (r2 / scale))


def _plane_forces(x, origin, normal, offset, stiffness, out):
    """Each node's contact force (s, 3), N, from the plane through ``origin`` (3,) with unit
    ``normal`` (3,) towards the body: x, offset, stiffness and out as
    ``_sphere_forces``."""
    for i in prange(x.shape[0]):
        d = (
            (x[i, 0] - origin[0]) * normal[0]
            + (x[i, 1] - origin[1]) * normal[1]
            + (x[i, 2] - origin[2]) * normal[2]
        )
        kp = stiffness[i] * max(offset[i] - d, 0.0)
        out[i, 0] = kp * normal[0]
        out[i, 1] = kp * normal[1]
        out[i, 2] = kp * normal[2]


def _annulus_forces(x, origin, normal, across, inner, offset, stiffness, out):
    """Each node's contact force (s, 3), N, from the flat ring through ``origin`` (3,) with
    unit ``normal`` (3,) towards the body and its bore of radius ``inner`` (mm), the signed
    distance and normal of ``RigidAnnulus.distance`` in its order of operations: in front of
    the face the plane's, in front of the bore the inner edge's, at the bore's wall (behind the
    face, or inside the solid nearer the wall than the face) inner - radius along the radius
    inwards; ``across`` (3,) the radial direction taken on the axis; x, offset, stiffness and
    out as ``_sphere_forces``."""
    for i in prange(x.shape[0]):
        r0 = x[i, 0] - origin[0]
        r1 = x[i, 1] - origin[1]
        r2 = x[i, 2] - origin[2]
        height = r0 * normal[0] + r1 * normal[1] + r2 * normal[2]
        a0 = r0 - height * normal[0]
        a1 = r1 - height * normal[1]
        a2 = r2 - height * normal[2]
        length = np.sqrt(a0 * a0 + a1 * a1 + a2 * a2)
        if length > 0.0:
            o0, o1, o2 = a0 / length, a1 / length, a2 / length
        else:
            o0, o1, o2 = across[0], across[1], across[2]
        in_bore = length < inner
        if in_bore and height >= 0.0:  # in front of the bore: the edge's circle
            span = length - inner
            e0 = span * o0 + height * normal[0]
            e1 = span * o1 + height * normal[1]
            e2 = span * o2 + height * normal[2]
            d = np.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
            unit = d if d > 0.0 else 1.0
            n0, n1, n2 = e0 / unit, e1 / unit, e2 / unit
        elif height < 0.0 and (in_bore or length - inner < -height):  # the bore's wall
            d = inner - length
            n0, n1, n2 = -o0, -o1, -o2
        else:  # the face's plane
            d = height
            n0, n1, n2 = normal[0], normal[1], normal[2]
        kp = stiffness[i] * max(offset[i] - d, 0.0)
        out[i, 0] = kp * n0
        out[i, 1] = kp * n1
        out[i, 2] = kp * n2


def _surface_forces(
    x, point, facet, gap, facet_rows, edge_start, edge_out, beside, tiny, far, searched,
    distance, normal, offset, stiffness, d, n, out,
):  # fmt: skip
    """Each node's contact force (s, 3), N, from a meshed tool, its closest points found
    (elements/facet_search.py ``closest_facets_kept``): x (s, 3) the nodes in the tool's
    frame, mm, each one's closest point ``point`` (s, 3) on facet ``facet`` (s,) at distance
    ``gap`` (s,), and that facet's corners and normal ``facet_rows[i]`` (s, 4, 3), the normal
    its last row (the closest-facet kernel's copies kept per node, read in the nodes' order).
    RigidSurface.distance's formulas in their order of operations: the side
    (+1, or -1 behind the facet's normal), d = side x gap and n = side x
    (x - point) / gap, or the facet's normal where gap <= ``tiny`` (mm); a node behind its
    facet and more than ``beside`` (mm) past one of its open edges (``edge_start``,
    ``edge_out`` (f, 3, 3), ``open_edges``) is beside the tool, its distance the gap and its
    normal turned where the gap exceeds ``tiny``; the nodes ``far`` (s,) beyond the search
    distance are told their ``distance`` (s,) at the place they were ``searched`` (s, 3) less
    how far they moved, and that ``normal`` (s, 3). Into d (s,), n (s, 3) and out: k p n with
    p = max(offset - d, 0), ``offset`` and ``stiffness`` (s,) as ``_sphere_forces``."""
    for i in prange(x.shape[0]):
        if far[i]:
            moved = math.sqrt(
                (x[i, 0] - searched[i, 0]) ** 2
                + (x[i, 1] - searched[i, 1]) ** 2
                + (x[i, 2] - searched[i, 2]) ** 2
            )
            d[i] = distance[i] - np.sign(distance[i]) * moved
            n[i, 0], n[i, 1], n[i, 2] = normal[i, 0], normal[i, 1], normal[i, 2]
        else:
            f = facet[i]
            t0 = x[i, 0] - point[i, 0]
            t1 = x[i, 1] - point[i, 1]
            t2 = x[i, 2] - point[i, 2]
            towards = t0 * facet_rows[i, 3, 0] + t1 * facet_rows[i, 3, 1] + t2 * facet_rows[i, 3, 2]
            side = -1.0 if towards < 0.0 else 1.0
            g = gap[i]
            d[i] = side * g
            if g > tiny:
                n[i, 0], n[i, 1], n[i, 2] = side * t0 / g, side * t1 / g, side * t2 / g
            else:
                n[i, 0], n[i, 1], n[i, 2] = (
                    facet_rows[i, 3, 0],
                    facet_rows[i, 3, 1],
                    facet_rows[i, 3, 2],
                )
            if math.copysign(1.0, d[i]) < 0.0:  # behind its facet: past an open edge?
                for e in range(3):
                    past = (
                        (x[i, 0] - edge_start[f, e, 0]) * edge_out[f, e, 0]
                        + (x[i, 1] - edge_start[f, e, 1]) * edge_out[f, e, 1]
                        + (x[i, 2] - edge_start[f, e, 2]) * edge_out[f, e, 2]
                    )
                    if past > beside:
                        d[i] = g
                        if g > tiny:
                            n[i, 0], n[i, 1], n[i, 2] = -n[i, 0], -n[i, 1], -n[i, 2]
                        break
        kp = stiffness[i] * max(offset[i] - d[i], 0.0)
        out[i, 0] = kp * n[i, 0]
        out[i, 1] = kp * n[i, 1]
        out[i, 2] = kp * n[i, 2]


sphere_forces = jit(_sphere_forces)
plane_forces = jit(_plane_forces)
annulus_forces = jit(_annulus_forces)
surface_pass = jit(_surface_forces)


def compiled_pass_applies(tool: RigidTool, friction: float, damping: float, augmented: bool):
    """Whether a contact with these options takes the compiled pass: frictionless, undamped,
    not augmented, and the tool exactly a plane, a sphere, a ring or a meshed tool (a
    subclass may redefine its distance)."""
    return (
        friction == 0.0
        and damping == 0.0
        and not augmented
        and type(tool) in (RigidPlane, RigidSphere, RigidAnnulus, RigidSurface)
    )


def contact_forces(block: ContactBlock, x: np.ndarray, load_factor: float) -> np.ndarray:
    """(s, 3) the forces (N) the plane, the sphere or the ring of ``block`` (a frictionless
    ContactBlock) exerts on its nodes at x (s, 3), mm, where the tool sees them (less a
    driven tool's free translation: ``ContactBlock._positions``), at ``load_factor``."""
    tool = block.tool
    if isinstance(tool, RigidSurface):
        return surface_forces(block, x, load_factor)
    forces = np.empty((len(x), 3))
    if isinstance(tool, RigidSphere):
        origin = tool.centre + tool.offset(load_factor)
        sphere_forces(x, origin, tool.radius, tool.sign, block.offset, block.stiffness, forces)
    elif isinstance(tool, RigidAnnulus):
        origin = tool.point + tool.offset(load_factor)
        annulus_forces(
            x,
            origin,
            tool.normal,
            tool.radial_on_axis,
            tool.inner,
            block.offset,
            block.stiffness,
            forces,
        )
    else:
        assert isinstance(tool, RigidPlane)
        origin = tool.point + tool.offset(load_factor)
        plane_forces(x, origin, tool.normal, block.offset, block.stiffness, forces)
    return forces


def surface_forces(block: ContactBlock, x: np.ndarray, load_factor: float) -> np.ndarray:
    """(s, 3) the forces (N) the meshed tool of ``block`` (frictionless) exerts on its nodes at
    x (s, 3), mm: ``_surface_forces`` after the candidate lists are brought up to date, with
    the tool's kept state (its hints, rooms and last answer) left as ``distance`` leaves it;
    the numpy formulas for a smoothed tool, without ``KEEP_NEAREST``, or for the points the
    tool was just asked about (its answer from memory)."""
    tool = block.tool
    assert isinstance(tool, RigidSurface)
    local = shifted(x, tool.offset(load_factor))  # x - offset, compiled
    last = tool._last
    if (
        tool.smooth
        or not rigid_surface.KEEP_NEAREST
        or (last is not None and same_rows(last[0], local))
    ):
        d, n = tool.distance(x, load_factor)
        return (block.stiffness * np.maximum(block.offset - d, 0.0))[:, None] * n
    cache = tool._prepared(local)
    point = local.copy()  # what the nodes without candidates keep (RigidSurface)
    facet = np.zeros(len(local), dtype=np.int64)
    gap = np.zeros(len(local))
    tool._closest_kept(local, cache.start, cache.facets, point, facet, gap)
    kept = tool._kept
    if kept is not None and len(kept) > 3:  # the short lists' copies, in the nodes' order
        rows = kept[3]
    else:
        rows = np.zeros((len(local), 4, 3))
        rows[:, :3] = tool.corners[facet]
        rows[:, 3] = tool.normals[facet]
    d, n, forces = np.empty(len(local)), np.empty((len(local), 3)), np.empty((len(local), 3))
    surface_pass(
        local, point, facet, gap, rows, tool.edge_start, tool.edge_out,
        tool.beside_tolerance, tool.on_surface_tolerance, cache.far, cache.points,
        cache.distance, cache.normal, block.offset, block.stiffness, d, n, forces,
    )  # fmt: skip
    tool._remember(local, d, n, facet, cache.far)
    return forces
