"""The two-ply hemisphere's measures of the plies' order (validation/studies/
hemisphere_plies.py, "The gap's measure"): each top-ply node's gap to the bottom ply's face
along the radius from the die's centre (``radial_gaps``, the check's, in the die at the end)
and to a face of the bottom ply by a node-to-surface probe (``node_gaps``), and the least of
them over a run (``least_gaps``).

Why along the radius. In the die both plies lie on spheres about the die's centre (the
origin; the punch's centre ends there), the top ply on the punch, the bottom one against the
die's bowl. Interpolating the bottom ply's nodes' distances from the centre over a triangle
puts its face on their sphere wherever its nodes are, with no chord (a flat facet's sag
s^2 / (8 R), 1.5-3 mm at the coarse mesh's 25-35 mm cells) and no nodal normals: the curved
(Phong) face over the nodal normals bulges towards the top ply where the bottom ply's cells
next to the die's entry radius turn its corners' normals (13.7 deg towards the rim at the
coarse fibrous [0/45] run's end), and read -0.70 mm there where the radii give the plies in
order. The measure is the study's, not the contact's: the contact acts on its own faces.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from elements.layup import Layup
from femcore.state import State
from validation.checks import check
from validation.records import Check
from validation.studies.hemisphere_plies_setup import (
    DIE,
    FABRIC,
    HALF,
    HOLDER_RING,
    MEASURED_FACE,
    PLIES,
    PUNCH,
    THICKNESS,
)

__all__ = ["least_gaps", "node_gaps", "order_check", "radial_gaps", "through_holder"]

# The tools' clearance over the plies (the die's bowl less the punch and the plies), mm: in
# the die a top ply node can stand off the bottom ply by at most this much.
CLEARANCE = DIE - PUNCH - PLIES * THICKNESS

#: barycentric slack of a ray through a triangle's edge or vertex (shared by its neighbours)
EDGE_SLACK = 1e-9


def radial_gaps(
    layup: Layup, positions: np.ndarray, thickness: float, below: float = -5.0
) -> np.ndarray:
    """(s,) each top-ply node's gap to the bottom ply's upper face along the radius, mm.

    Parameters
    ----------
    layup : Layup
        The two-ply layup (``ply_nodes``, ``ply_cells``, ``mesh``).
    positions : (n, 3) float
        The nodes' positions, mm, the die's centre at the origin.
    thickness : float
        The two faces' half thicknesses together, mm (the plies' faces touch when the
        mid-surfaces are that far apart).
    below : float
        mm: only the bottom ply's triangles whose three corners lie below z = ``below`` (in
        the die) count.

    Returns
    -------
    (s,) float
        Over the top ply's nodes (``layup.ply_nodes[-1]``): r_b - r - ``thickness``, r the
        node's distance from the centre and r_b the bottom ply's, interpolated over the
        triangle the node's ray from the centre passes through (barycentric coordinates of
        the ray's crossing of its plane); the least where the ray passes several (a fold).
        < 0: the node lies beyond the bottom ply's face. NaN where the ray passes no such
        triangle.
    """
    x = np.asarray(positions, dtype=float)
    top = layup.ply_nodes[-1]
    triangles = layup.mesh.triangles[layup.ply_cells[0]]
    triangles = triangles[(x[triangles, 2] < below).all(axis=1)]
    gaps = np.full(len(top), np.nan)
    if len(triangles) == 0:
        return gaps
    corners = x[triangles]  # (m, 3 corners, 3)
    radii = np.linalg.norm(corners, axis=2)  # (m, 3)
    r = np.linalg.norm(x[top], axis=1)  # (s,)
    direction = x[top] / np.where(r > 0.0, r, 1.0)[:, None]
    # the ray t u meets the plane of Y = [y_1 y_2 y_3] at Y lambda with sum lambda = 1:
    # lambda = Y^-1 u / (1 . Y^-1 u), in front of the centre where that sum is positive
    columns = np.transpose(corners, (0, 2, 1))  # (m, 3 xyz, 3 corners)
    solved = np.linalg.solve(
        columns[None, :, :, :],
        np.broadcast_to(direction[:, None, :, None], (len(top), len(triangles), 3, 1)),
    )[..., 0]  # (s, m, 3)
    total = solved.sum(axis=2)
    weights = solved / np.where(np.abs(total) > 0.0, total, 1.0)[..., None]
    through = (total > 0.0) & (weights >= -EDGE_SLACK).all(axis=2)
    bottom = np.einsum("smk,mk->sm", weights, radii)
    gap = np.where(through, bottom - r[:, None] - thickness, np.inf).min(axis=1)
    gaps[np.isfinite(gap)] = gap[np.isfinite(gap)]
    return gaps


def node_gaps(
    probe: Any, layup: Layup, positions: np.ndarray, below: float | None = None
) -> np.ndarray:
    """(s,) each top-ply node's gap to the bottom ply's upper face, mm (< 0: it passed
    through): the least gap of a node-to-surface contact (``probe``, the layup's ply
    contact at the "nodes" or "vertices" rule) at the node over its points; NaN where no
    facet of the bottom ply faces the node, and with ``below`` (mm) where a corner of the
    facing bottom triangle lies above z = ``below``."""
    zero = np.zeros_like(positions)
    facing = probe.facing(State(positions, zero, zero, zero))
    corner = probe.above[np.arange(len(facing.gap)), np.argmax(probe.shape, axis=1)]
    facing_any = np.maximum(0.0, -facing.weights.min(axis=1)) <= 0.5
    if below is not None:
        facing_any &= (positions[probe.cells[facing.triangle], 2] < below).all(axis=1)
    gap = np.full(len(positions), np.inf)
    np.minimum.at(gap, corner[facing_any], facing.gap[facing_any])
    top = gap[layup.ply_nodes[-1]]
    return np.where(np.isfinite(top), top, np.nan)


def least_gaps(
    layup: Layup, result: Any, cells: int, surface: str = MEASURED_FACE, over_run: bool = True
) -> dict[str, Any]:
    """The top ply's least node gap, mm: in the die at the end along the radius
    (``radial_gaps``, "in_die"), and to the bottom ply's ``surface`` face (``node_gaps``)
    over its nodes in the die at the end, each facing a bottom triangle in the die (its
    corners 5 mm below the flange; "in_die_to_the_face"), and with ``over_run`` over every
    node and frame of the run, with when and where (the node's blank coordinates; without
    it "run" is NaN, "at_s" NaN and "where" empty: the probe over the run's hundred frames
    is most of the measure's cost, about 1 s of CPU a run at 8 cells, for a number a caller
    that wants the end alone would not read)."""
    top = layup.ply_nodes[-1]
    least, at, where = (math.inf, 0.0, "") if over_run else (math.nan, math.nan, "")
    # one point per node ("nodes"): a node's points at the "vertices" rule, one in each of
    # its triangles, lie at the same place (the face's point at a corner is the corner's,
    # bit for bit) and each point's facing is its own place's alone, so their gaps are one
    # number, which the least took; a sixth of the points (0.66 -> 0.25 s of CPU over the
    # fibrous [0/90] run's 101 frames at 8 cells, the same gaps to the bit: tests/
    # test_hemisphere_plies_gaps.py)
    probe = (
        Layup(FABRIC, tuple(layup.angles), 2 * HALF, cells=cells, rule="nodes", surface=surface)
        .model()
        .compile()
        .interactions[0]
    )
    for frame in result.frames if over_run else ():
        gap = node_gaps(probe, layup, frame.positions[: layup.mesh.n_nodes])
        if np.isfinite(gap).any() and np.nanmin(gap) < least:
            i = int(np.nanargmin(gap))
            least, at = float(gap[i]), float(frame.time)
            where = f"({layup.mesh.points[top[i], 0]:g}, {layup.mesh.points[top[i], 1]:g})"
    x = result.positions[: layup.mesh.n_nodes]
    gap = node_gaps(probe, layup, x, below=-5.0)
    deep = (x[top, 2] < -5.0) & np.isfinite(gap)
    radial = radial_gaps(layup, x, THICKNESS)  # the punch's centre ends on the die's
    inside = (x[top, 2] < -5.0) & np.isfinite(radial)
    return {
        "in_die": float(radial[inside].min(initial=math.inf)),
        "in_die_to_the_face": float(gap[deep].min(initial=math.inf)),
        "run": least,
        "at_s": at,
        "where": where,
    }


def through_holder(
    layup: Layup,
    result: Any,
    holder: int = 2,
    stiffness: np.ndarray | None = None,
    force: float | None = None,
) -> list[dict[str, float]]:
    """Per ply (bottom first), how far its face rose through the holder's plane over the run:
    the largest of z + h/2 - z_h over its nodes under the holder's ring (in plan between
    its inner and outer radius, ``HOLDER_RING``) and the run's frames, mm, z_h the holder's
    face (the plies' top at the start plus its travel), with the frame's time (s) and the
    node's blank position (mm). A holder that presses every ply keeps it near 0 (the
    contact's penetration); one on the top ply's nodes alone lets a bottom-ply node the top
    ply has drawn in off rise freely (the study's docstring, "The holder on every ply").
    ``holder`` is the holder's index among the tools.

    With ``stiffness`` ((n,) float, N/mm: each node's contact spring with the holder, NaN
    where it has none) and ``force`` (N, the holder's), also "share": the largest of that
    rise times the node's spring over the holder's force, the share of the holder's force
    the node's spring carries at that rise, with its time "share_at_s" (s). A node the holder
    presses carries a share of its force, at most all of it (1) where the run is
    quasi-static; a node it does not hold rises with no force and reads its rise over the
    penetration of the holder's whole force on its spring (docs/hemisphere_plies.md, "The
    holder's penetration"); a node under the ring with no spring, which the holder cannot
    press, reads an infinite share once its face is through the holder's (a ply the holder
    does not hold).
    """
    n = layup.mesh.n_nodes
    start = layup.heights[-1] + 0.5 * THICKNESS
    out = []
    for nodes in layup.ply_nodes:
        worst = {"mm": -math.inf, "at_s": math.nan, "x_mm": math.nan, "y_mm": math.nan}
        share = {"share": -math.inf, "share_at_s": math.nan}
        for frame in result.frames:
            x = frame.positions[:n][nodes]
            plan = np.linalg.norm(x[:, :2], axis=1)
            under = (plan >= HOLDER_RING[0]) & (plan <= HOLDER_RING[1])
            if not under.any():
                continue
            face = start + float(frame.tool_displacements[holder, 2])
            rise = np.where(under, x[:, 2] + 0.5 * THICKNESS - face, -math.inf)
            i = int(np.argmax(rise))
            if rise[i] > worst["mm"]:
                blank = layup.mesh.points[nodes[i]]
                worst = {"mm": float(rise[i]), "at_s": float(frame.time),
                         "x_mm": float(blank[0]), "y_mm": float(blank[1])}  # fmt: skip
            if stiffness is not None and force is not None:
                spring = stiffness[nodes]
                unheld = np.where(rise > 0.0, math.inf, -math.inf)
                carried = np.where(np.isnan(spring), unheld, rise * spring / force)
                carried = np.where(under, carried, -math.inf)
                j = int(np.argmax(carried))
                if carried[j] > share["share"]:
                    share = {"share": float(carried[j]), "share_at_s": float(frame.time)}
        out.append({**worst, **share} if stiffness is not None and force is not None else worst)
    return out


def order_check(key: str, gap: float) -> Check:
    """The check that the plies of the run ``key`` stay in order in the die at the end: the
    top ply's least node ``gap`` (mm) to the bottom ply along the radius (``radial_gaps``),
    as measured, within a ply thickness of touching (0). Below -THICKNESS a node has passed
    the bottom ply's mid-surface; above +THICKNESS, no more than the tools' CLEARANCE, no
    top node in the die touches the bottom ply."""
    return check(
        f"{key}: the top ply's least node gap to the bottom ply in the die along the radius "
        "(r_b - r - h, its faces' distance), within a ply thickness of touching: at -h a node "
        "has passed the bottom ply's mid-surface (the gaps to its curved face and to its flat "
        "facets, which read their chords, are in the parameters) (mm)",
        0.0,
        gap,
        THICKNESS,
        relative=False,
        source="the plies cannot pass through each other; the tools' clearance is one ply",
    )
