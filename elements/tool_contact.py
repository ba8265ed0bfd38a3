"""The frictionless contact of a node set with an analytic rigid tool (a plane, a sphere or a
flat ring, elements/annulus.py) in
one compiled pass over the nodes: the tool's signed distance and normal, the penetration and
the force k p n of each node (elements/contact.py, docs/theory.md §9), the formulas of
``ContactBlock.contact_forces`` with the tool's ``distance`` in the same order of operations.

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

import numpy as np

from elements.annulus import RigidAnnulus
from elements.contact import ContactBlock
from elements.jit import jit, prange
from elements.tools import RigidPlane, RigidSphere, RigidTool

__all__ = [
    "annulus_forces", "compiled_pass_applies", "contact_forces", "plane_forces", "sphere_forces",
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


def _annulus_forces(x, origin, normal, inner, offset, stiffness, out):
    """Each node's contact force (s, 3), N, from the flat ring through ``origin`` (3,) with
    unit ``normal`` (3,) towards the body and its bore of radius ``inner`` (mm): over the face
    the plane's, over the bore the inner edge's (``RigidAnnulus.distance``); x, offset,
    stiffness and out as ``_sphere_forces``."""
    for i in prange(x.shape[0]):
        r0 = x[i, 0] - origin[0]
        r1 = x[i, 1] - origin[1]
        r2 = x[i, 2] - origin[2]
        height = r0 * normal[0] + r1 * normal[1] + r2 * normal[2]
        a0 = r0 - height * normal[0]
        a1 = r1 - height * normal[1]
        a2 = r2 - height * normal[2]
        length = np.sqrt(a0 * a0 + a1 * a1 + a2 * a2)
        if length >= inner:
            d = height
            n0, n1, n2 = normal[0], normal[1], normal[2]
        else:
            scale = length if length > 0.0 else 1.0
            across = length - inner
            e0 = across * (a0 / scale) + height * normal[0]
            e1 = across * (a1 / scale) + height * normal[1]
            e2 = across * (a2 / scale) + height * normal[2]
            d = np.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
            unit = d if d > 0.0 else 1.0
            n0, n1, n2 = e0 / unit, e1 / unit, e2 / unit
        kp = stiffness[i] * max(offset[i] - d, 0.0)
        out[i, 0] = kp * n0
        out[i, 1] = kp * n1
        out[i, 2] = kp * n2


sphere_forces = jit(_sphere_forces)
plane_forces = jit(_plane_forces)
annulus_forces = jit(_annulus_forces)


def compiled_pass_applies(tool: RigidTool, friction: float, damping: float, augmented: bool):
    """Whether a contact with these options takes the compiled pass: frictionless, undamped,
    not augmented, and the tool exactly a plane, a sphere or a ring (a subclass may redefine
    its distance)."""
    return (
        friction == 0.0
        and damping == 0.0
        and not augmented
        and type(tool) in (RigidPlane, RigidSphere, RigidAnnulus)
    )


def contact_forces(block: ContactBlock, x: np.ndarray, load_factor: float) -> np.ndarray:
    """(s, 3) the forces (N) the plane, the sphere or the ring of ``block`` (a frictionless
    ContactBlock) exerts on its nodes at x (s, 3), mm, where the tool sees them (less a
    driven tool's free translation: ``ContactBlock._positions``), at ``load_factor``."""
    forces = np.empty((len(x), 3))
    tool = block.tool
    if isinstance(tool, RigidSphere):
        origin = tool.centre + tool.offset(load_factor)
        sphere_forces(x, origin, tool.radius, tool.sign, block.offset, block.stiffness, forces)
    elif isinstance(tool, RigidAnnulus):
        origin = tool.point + tool.offset(load_factor)
        annulus_forces(x, origin, tool.normal, tool.inner, block.offset, block.stiffness, forces)
    else:
        assert isinstance(tool, RigidPlane)
        origin = tool.point + tool.offset(load_factor)
        plane_forces(x, origin, tool.normal, block.offset, block.stiffness, forces)
    return forces
