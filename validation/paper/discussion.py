"""The report's paragraph on a paper case: what its figures mean for each kinematics.

``discussion`` explains the director angle and the thickness along the director of the side
figure for the Mindlin shell and both fibrous variants, with the numbers of the run, then
compares the default fibrous run with the Mindlin one made of the same fabric (its
calibration stated): how far apart their mid-surfaces are and how far their directors, and
the case's note on what that shows; then the case's note on the atan(theta) check with the
measured differences.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from validation import specimens
from validation.paper.kinematics import LABELS, calibration_title
from validation.paper.profiles import away_from_clamp, midsurface_gap, out_of_plane, slip_errors
from validation.records import ElementRun

if TYPE_CHECKING:
    from validation.paper.case import PaperCase

__all__ = ["comparison", "discussion"]


def _largest(values: list[np.ndarray]) -> float:
    return float(max(np.abs(v).max() for v in values))


# Below this (mm) a side is taken to stay in the vertical plane the side figure projects on.
IN_PLANE_MM = 0.5


def _projection(mindlin: dict[str, float]) -> str:
    """What the Mindlin director's angle in (b) shows: 90 deg plus the slope of the profile
    (a), up to its tilt from the normal, where the sides stay in the plane the figure projects
    on; where they leave it, the projection's angles are not the surface's."""
    text = (
        "Seen facing the side, its angle in (b) is 90 deg plus the slope of the profile (a), "
        "up to that tilt, where the side stays in its vertical plane; "
    )
    if mindlin["out_of_plane"] < IN_PLANE_MM:
        return text + f"here it does, and the two differ by up to {mindlin['tilt']:.1f} deg."
    return text + (
        f"here the sides move up to {mindlin['out_of_plane']:.1f} mm out of it, and in the "
        f"projection the two differ by up to {mindlin['tilt']:.1f} deg: where that exceeds the "
        f"tilt in three dimensions, it is the projection of a side leaving its plane, not the "
        f"director leaving the normal."
    )


def comparison(
    case: PaperCase, specimen: specimens.Specimen, elements: dict[str, ElementRun]
) -> str:
    """The paragraph that compares the default fibrous run with the Mindlin one, made of the
    same fabric by the case's calibration: the calibration and its numbers, how far apart the
    mid-surfaces are (largest distance between the same nodes along the sides, against the
    largest displacement), the mid-side deflections of both, how far apart the directors are,
    and the case's ``comparison_note`` (what the numbers mean, measured)."""
    gap = midsurface_gap(specimen, elements["fibrous"], elements["mindlin"])
    deflections = []
    for side, data in elements["fibrous"].sides.items():
        s = np.asarray(data.s)
        middle = 0.5 * s.max()
        z = [
            float(np.interp(middle, s, np.asarray(elements[k].sides[side].midsurface)[:, 2]))
            for k in ("fibrous", "mindlin")
        ]
        deflections.append(
            f"{side.replace('_', ' ')} {z[0]:.2f} mm (fibrous) and {z[1]:.2f} mm (Mindlin)"
        )
    share = 100.0 * gap["distance"] / max(gap["displacement"], 1e-300)
    text = (
        f"Same material, two kinematics: the Mindlin shell here is "
        f"{calibration_title(case.calibration, case.fabric)}. Along the sides its mid-surface "
        f"lies within {gap['distance']:.2f} mm of the fibrous one (the largest distance "
        f"between the same node in both runs; {share:.0f} % of the largest displacement, "
        f"{gap['displacement']:.1f} mm); at the middle of the sides the deflections are "
        f"{'; '.join(deflections)}. The directors differ by up to {gap['director']:+.1f} deg "
        f"(fibrous - Mindlin, {gap['director_side'].replace('_', ' ')} at s = "
        f"{gap['director_s']:.0f} mm)."
    )
    if case.comparison_note:
        text += " " + case.comparison_note.strip()
    return text


def discussion(
    case: PaperCase, specimen: specimens.Specimen, elements: dict[str, ElementRun], h: float
) -> str:
    """What the director angle (b) and the thickness along the director (c) of the side figure
    mean for each kinematics, with the numbers of this run (one paragraph each), then the
    comparison of the default fibrous and the Mindlin run (``comparison``), then the case's
    note on the atan(theta) check with the measured differences of both fibrous variants."""
    # Away from the clamped node, the first of each side, where the rotation is a one-sided
    # difference over the first element while the director is held (``away_from_clamp``).
    numbers = {}
    for kinematics, record in elements.items():
        sides = list(record.sides.values())
        numbers[kinematics] = {
            "rotation": _largest([away_from_clamp(s.rotation_deg) for s in sides]),
            "tilt": _largest([away_from_clamp(s.side_tilt_deg) for s in sides]),
            "normal_tilt": _largest([away_from_clamp(s.director_tilt_deg) for s in sides]),
            "turned": _largest([np.asarray(s.director_angle_deg) - 90.0 for s in sides]),
            "thick": max(float(np.max(s.thickness)) for s in sides) / h,
            "out_of_plane": out_of_plane(specimen, record),
        }
    m, f, e = numbers["mindlin"], numbers["fibrous"], numbers["fibrous_element"]
    atan = np.degrees(np.arctan(np.radians(f["rotation"])))
    paragraphs = [
        f"{LABELS['mindlin']}: the director is the rotated normal. It follows the normal up to "
        f"the transverse shear strain: here it leaves the nodal normal by at most "
        f"{m['normal_tilt']:.1f} deg (in three dimensions) while the mid-surface turns by up "
        f"to {m['rotation']:.0f} deg. {_projection(m)} The thickness along it is h = {h:g} mm "
        f"everywhere (c): a Mindlin section neither thickens nor slips.",
        f"{LABELS['fibrous']}: the director is the material line across the plies, and the "
        f"thickness along it h_m = h / (V . N) uses the nodal normal N. Where the plies slip "
        f"freely from the clamp, a stack whose mid-surface has turned by theta tilts its "
        f"directors from the normal by atan(theta), and the thickness along them is h / "
        f"cos(tilt) = h sqrt(1 + theta^2) >= h. Here the mid-surface turns by up to "
        f"{f['rotation']:.0f} deg (atan of it: {atan:.0f} deg), the directors tilt from the "
        f"normal by up to {f['tilt']:.0f} deg seen facing the side ({f['normal_tilt']:.0f} deg "
        f"in three dimensions) and so turn from the vertical by up to {f['turned']:.1f} deg, "
        f"and the thickness along them, h / cos of the tilt in three dimensions, reaches "
        f"{f['thick']:.3f} h.",
        f"{LABELS['fibrous_element']}: with each element's own normal in h_m = h / (V . n), "
        f"parallel directors are strain-free at any curvature, so the directors keep their "
        f"initial (vertical) orientation: in (b) they stay within {e['turned']:.2f} deg of 90 "
        f"deg, their tilt from the normal is the slope itself (up to {e['tilt']:.0f} deg seen "
        f"facing the side, {e['normal_tilt']:.0f} deg in three dimensions where the surface is "
        f"also bent across the side) and the thickness along them is h / cos(slope), h / (V . "
        f"n) in each element; its nodal mean reaches {e['thick']:.3f} h.",
    ]
    paragraphs.append(comparison(case, specimen, elements))
    note = case.slip_note
    if case.slip_sides:
        measured = {
            kinematics: _largest(list(slip_errors(case, specimen, elements[kinematics]).values()))
            for kinematics in ("fibrous", "fibrous_element")
        }
        named = " and ".join(side.replace("_", " ") for side in case.slip_sides)
        note += (
            f" Measured along {named}, away from the clamped and the loaded nodes: the default "
            f"directors' tilt differs from atan(theta) by at most {measured['fibrous']:.1f} deg "
            f"({'checked' if case.slip_tolerance_deg is not None else 'not checked'}); the "
            f"Eq. 15 directors, whose tilt is theta itself, by up to "
            f"{measured['fibrous_element']:.1f} deg."
        )
    if note:
        paragraphs.append(note.strip())
    return "\n\n".join(paragraphs)
