"""Closed forms of the draw-in of a blank's edge middle when a hemispherical punch has pushed
it to the bottom of a die: the paths an inextensible fibre along the blank's centre line can
take from the pole to the die's flat flange through the gap of one ply between the tools.

Geometry (mm), in the plane of the centre line, r from the axis and z up, the flange's face at
z = 0: a punch of radius ``punch`` centred at the origin at the end of its stroke; a die whose
bowl (radius ``die``, centred at the origin) meets the flange through an entry round of radius
``rim`` (0: a sharp edge), its centre at (r0, -rim), r0 = sqrt(die^2 + 2 die rim) the flange's
start; a ply of ``thickness`` whose mid-surface keeps half of it off each tool; the holder's
plane on the ply's top face over the whole blank. The fibre's half length runs from the pole
to the blank's edge; its draw-in is the length its path takes from the pole to r0 less r0.
The hemisphere forming case (validation/cases/hemisphere_forming.py) checks its runs'
centre-line draw-in against these.
"""

from __future__ import annotations

import math

__all__ = [
    "chord_shortfall",
    "cornered_draw_in",
    "draw_in_range",
    "flange_start",
    "lying_draw_in",
    "taut_draw_in",
]


def flange_start(die: float, rim: float) -> float:
    """The radius (mm) where the die's flat flange starts, past its entry round of radius
    ``rim`` (mm; ``die`` on a sharp die): the ring holder's bore."""
    return math.sqrt(die**2 + 2.0 * die * rim)


def lying_draw_in(die: float, rim: float, thickness: float) -> float:
    """The draw-in (mm) of a fibre lying on the die, its mid-surface half a ply off it: from
    the pole along the bowl (radius die - h / 2) to the polar angle phi0 where the entry round
    starts, around the round (radius rim + h / 2) to the flange, then flat out to the edge.
    With r0 the flange's start and phi0 = atan(r0 / rim) (pi / 2 on a sharp rim, whose round
    is then the ply's half thickness) the path to r0 is (die + rim) phi0 long and the draw-in
    (die + rim) phi0 - r0: die (pi / 2 - 1) on a sharp die."""
    start = flange_start(die, rim)
    return (die + rim) * math.atan2(start, rim) - start


def taut_draw_in(
    punch: float, die: float, rim: float, thickness: float
) -> tuple[float, float, float]:
    """The least draw-in (mm) an inextensible fibre can have in the gap, and the arcs (mm)
    its path has on the punch and on the die's round: the shortest path of its mid-surface
    through the clearance, the taut string. It hugs the punch (a circle of radius a = punch +
    h / 2 about the origin) from the pole, leaves it along the internal common tangent to the
    die's round (a circle of radius b = rim + h / 2 about c, |c| = d = die + rim, at the polar
    angle phi0 = atan(r0 / rim)) and hugs the round to its top at the flange's start r0. The
    tangent meets each circle gamma = acos((a + b) / d) before the line of centres, so the
    path from the pole to r0 is (a + b)(phi0 - gamma) + d sin(gamma) long."""
    start = flange_start(die, rim)
    on_punch, on_round = punch + 0.5 * thickness, rim + 0.5 * thickness
    centres = die + rim
    gamma = math.acos((on_punch + on_round) / centres)
    turn = math.atan2(start, rim) - gamma
    path = (on_punch + on_round) * turn + centres * math.sin(gamma)
    return path - start, on_punch * turn, on_round * turn


def cornered_draw_in(die: float, rim: float, thickness: float) -> tuple[float, float]:
    """The draw-in (mm) of a fibre pushed off the die's round into the corner its bowl's
    sphere makes with the holder's plane over the opening, and its path's length (mm) from the
    pole to the flange's start: along the sphere of the clearance's die side (radius die - h /
    2) from the pole to its equator, then straight to the flange's start r0 at the
    mid-surface's level h / 2. No unfolded path through the clearance under the holder's plane
    is longer by more than the clearance: it is where a compressed fibre on a frictionless
    flange goes, nothing pulling it onto the round."""
    start = flange_start(die, rim)
    bowl = die - 0.5 * thickness
    path = 0.5 * math.pi * bowl + math.hypot(start - bowl, 0.5 * thickness)
    return path - start, path


def chord_shortfall(radius: float, arc: float, segment: float) -> float:
    """How much less fibre (mm) covers an ``arc`` (mm) of a circle of ``radius`` (mm) with
    chords of ``segment`` (mm) between nodes on it than lying on it: the arc less its
    inscribed chords, arc (1 - segment / (radius theta)) with theta = 2 asin(segment / (2
    radius)). A node-to-surface contact keeps the nodes out of the tools, not the cells'
    edges: a cell spanning the round cuts it by its chord."""
    theta = 2.0 * math.asin(min(1.0, 0.5 * segment / radius))
    return arc * (1.0 - segment / (radius * theta))


def draw_in_range(
    punch: float, die: float, rim: float, thickness: float, segment: float, strain: float
) -> tuple[float, float]:
    """(lowest, highest) draw-in (mm) of a centre-line fibre in the gap, its cells ``segment``
    (mm) long: from the taut fibre (``taut_draw_in``) stretched by ``strain``, its cells
    cutting the punch and the round by their chords (``chord_shortfall``), to the cornered
    one (``cornered_draw_in``) compressed by ``strain`` (chords through a corner only shorten
    it); a strain eps over a path of length L moves the draw-in by eps L."""
    taut, on_punch, on_round = taut_draw_in(punch, die, rim, thickness)
    cornered, cornered_path = cornered_draw_in(die, rim, thickness)
    chords = chord_shortfall(punch + 0.5 * thickness, on_punch, segment) + chord_shortfall(
        rim + 0.5 * thickness, on_round, segment
    )
    taut_path = taut + flange_start(die, rim)
    return taut - strain * taut_path - chords, cornered + strain * cornered_path
