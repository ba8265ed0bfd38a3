"""What a paper case measures along the filmed sides of its specimen.

``side_data`` projects each run on the vertical plane of each side (the camera's view of Bai
Figs. 9-16): the mid-surface, the director angle to the horizontal, the thickness along the
director, the mid-surface rotation from the clamp and the director's tilt from the normal.
``key_numbers`` condenses them into the figures the report quotes, ``slip_errors`` compares the
tilt with atan(theta) where the plies slip freely, ``midsurface_gap`` how far apart two runs'
mid-surfaces and directors are, and ``fibre_statistics`` gives the fibrous runs' largest fibre
strain and shear angle.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from femcore.topology import nodal_normals
from validation import specimens
from validation.paper.kinematics import ELEMENT, Kinematics
from validation.records import ElementRun, SideProfile, SideSummary

if TYPE_CHECKING:
    from validation.paper.case import PaperCase

__all__ = [
    "away_from_clamp",
    "fibre_statistics",
    "key_numbers",
    "midsurface_gap",
    "out_of_plane",
    "side_data",
    "slip_errors",
]


def away_from_clamp(values: Any) -> np.ndarray:
    """A side's values without its first node, the clamped one: there the director is held
    while the profile's slope is a one-sided difference over the first element, so its tilt
    from the normal is the discretisation's, not the run's (bai-5.1's Mindlin strip: 27.7 deg
    there, 18.1 in three dimensions at the next node)."""
    return np.asarray(values)[1:]


def side_data(
    result: Any, specimen: specimens.Specimen, kinematics: Kinematics, thickness: float
) -> dict[str, SideProfile]:
    """Along each filmed side, seen by a camera facing it (everything projected on the side's
    vertical plane): s, mid-surface, director angle to the horizontal (deg, 90 = vertical), the
    thickness along the director (mm), the mid-surface rotation theta from the clamp's
    (horizontal) orientation, i.e. the slope of the side profile (central differences; deg)
    and the director's tilt from the normal of the profile, 90 + theta - director angle (deg);
    also the director's angle to the nodal normal in three dimensions (deg)."""
    out = {}
    positions, directors = result.positions, result.directors
    nodal = result.thickness if ELEMENT[kinematics] == "fibrous" else None
    normals = nodal_normals(positions, specimen.mesh.triangles)
    normal_tilt = np.degrees(np.arccos(np.clip(np.sum(directors * normals, axis=1), -1.0, 1.0)))
    for name, (nodes, s) in specimen.sides.items():
        x0 = specimen.mesh.points[nodes]
        along = x0[-1] - x0[0]
        along = along / np.linalg.norm(along)  # horizontal direction from the clamp outwards
        d = directors[nodes]
        angle = np.degrees(np.arctan2(d[:, 2], d @ along))
        x = positions[nodes]
        rotation = np.degrees(np.arctan2(np.gradient(x[:, 2]), np.gradient(x @ along)))
        h = nodal[nodes] if nodal is not None else np.full(len(nodes), thickness)
        out[name] = SideProfile(
            s=s,
            midsurface=x,
            director_angle_deg=angle,
            thickness=h,
            rotation_deg=rotation,
            side_tilt_deg=90.0 + rotation - angle,
            director_tilt_deg=normal_tilt[nodes],
        )
    return out


def fibre_statistics(result: Any, specimen: specimens.Specimen) -> dict[str, float]:
    """The fibrous run's largest fibre strain, also away from the loaded nodes, and its largest
    in-plane shear angle (deg)."""
    strain = np.maximum(
        np.abs(result.field("warp_strain")).max(axis=1),
        np.abs(result.field("weft_strain")).max(axis=1),
    )
    # The support acts on the loaded nodes (one node, or a gripped patch): the triangles
    # touching them carry its load.
    at_support = np.isin(specimen.mesh.triangles, specimen.loaded).any(axis=1)
    return {
        "max_fibre_strain": float(strain.max()),
        "max_fibre_strain_away_from_support": float(strain[~at_support].max()),
        "max_shear_angle_deg": float(np.abs(result.field("shear_angle_deg")).max()),
    }


def key_numbers(elements: dict[str, ElementRun], h: float) -> dict[str, SideSummary]:
    """Per kinematics and side: the director angle range, the largest mid-surface slope, the
    thickness range along the director, the largest tilt of the director from the normal, seen
    facing the side and in three dimensions, away from the clamped node (``away_from_clamp``;
    the numbers the report quotes)."""
    out = {}
    for kinematics, record in elements.items():
        for side in ("side_1", "side_2"):
            if side not in record.sides:
                continue
            data = record.sides[side]
            x = np.asarray(data.midsurface)
            run = np.linalg.norm(np.diff(x[:, :2], axis=0), axis=1)
            slope = np.degrees(np.arctan2(np.abs(np.diff(x[:, 2])), run)).max()
            angle = np.asarray(data.director_angle_deg)
            out[f"{kinematics} {side}"] = SideSummary(
                max_midsurface_slope_deg=float(slope),
                director_angle_min_deg=float(angle.min()),
                director_angle_max_deg=float(angle.max()),
                thickness_max_over_h=float(np.max(data.thickness) / h),
                side_tilt_max_deg=float(np.abs(away_from_clamp(data.side_tilt_deg)).max()),
                normal_tilt_max_deg=float(np.abs(away_from_clamp(data.director_tilt_deg)).max()),
            )
    return out


def slip_errors(
    case: PaperCase, specimen: specimens.Specimen, record: ElementRun
) -> dict[str, np.ndarray]:
    """Per side of ``case.slip_sides``: |tilt - atan(theta)| (deg) at the nodes of the side
    that are neither clamped nor loaded."""
    out = {}
    for side in case.slip_sides:
        nodes, _ = specimen.sides[side]
        free = ~np.isin(nodes, np.r_[specimen.clamp, specimen.loaded])
        data = record.sides[side]
        expected = np.degrees(np.arctan(np.radians(np.asarray(data.rotation_deg))))
        out[side] = np.abs(np.asarray(data.side_tilt_deg) - expected)[free]
    return out


def out_of_plane(specimen: specimens.Specimen, record: ElementRun) -> float:
    """How far the run's side nodes move out of their side's vertical plane, the plane the
    side figure projects on (mm, the largest over the sides): where they do, the projected
    profile's slope and director angle are no longer those of the surface (bai-6.1.2's Mindlin
    sheet: 21.5 mm at the pushed corner, where the tilt seen facing the side is 21 deg and the
    tilt in three dimensions 2.1)."""
    largest = 0.0
    for side, data in record.sides.items():
        nodes, _ = specimen.sides[side]
        x0 = specimen.mesh.points[nodes]
        along = x0[-1] - x0[0]
        across = np.array([-along[1], along[0], 0.0]) / np.linalg.norm(along[:2])
        moved = (np.asarray(data.midsurface) - x0) @ across
        largest = max(largest, float(np.abs(moved).max()))
    return largest


def midsurface_gap(
    specimen: specimens.Specimen, fibrous: ElementRun, mindlin: ElementRun
) -> dict[str, float]:
    """How far apart the two runs' mid-surfaces are along the filmed sides: the largest
    distance between the same node in both (mm, "distance"), the largest displacement of the
    fibrous run's side nodes (mm, "displacement") and the largest difference of the director
    angles, fibrous - Mindlin (deg, signed, "director"), with the side and the s (mm) where
    it is ("director_side", "director_s")."""
    distance = displacement = 0.0
    director, where = 0.0, ("", 0.0)
    for side, data in fibrous.sides.items():
        nodes, s = specimen.sides[side]
        x_f = np.asarray(data.midsurface)
        x_m = np.asarray(mindlin.sides[side].midsurface)
        distance = max(distance, float(np.linalg.norm(x_f - x_m, axis=1).max()))
        moved = np.linalg.norm(x_f - specimen.mesh.points[nodes], axis=1)
        displacement = max(displacement, float(moved.max()))
        gap = np.asarray(data.director_angle_deg) - np.asarray(
            mindlin.sides[side].director_angle_deg
        )
        k = int(np.argmax(np.abs(gap)))
        if abs(gap[k]) > abs(director):
            director, where = float(gap[k]), (side, float(np.asarray(s)[k]))
    return {
        "distance": distance,
        "displacement": displacement,
        "director": director,
        "director_side": where[0],
        "director_s": where[1],
    }
