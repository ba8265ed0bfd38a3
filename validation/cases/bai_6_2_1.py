"""Bai §6.2.1 (Fig. 13, 14): the 11-ply G1151 laminate, 200 x 150 x 15 mm, the part above the
diagonal clamped, a vertical displacement imposed at the free corner.

Source: Bai et al. (2020) §6.2, §6.2.1, Fig. 13, 14, Table 2.
Geometry: 200 x 150 x 15 mm (paper). Only the free triangle is meshed; the diagonal is clamped.
Load: gravity, and the corner lifted by 40 mm (assumed), its horizontal motion free.
Material: Table 2 (tension 2300 N/mm, bending 72 N mm warp along x, 68 N mm weft along y);
assumed 630 g/m^2 per ply and in-plane shear 2.2 N/mm (materials.presets.g1151_laminate).
Mindlin: orthotropic E1 = 12 x 72 / h^3, E2 = 12 x 68 / h^3, nu = 0, G13 = G23 = 0.5 E1 (the
paper's Abaqus S3 comparison, which it says did not match the experiment).
"""

from __future__ import annotations

from materials.presets import g1151_laminate
from validation.paper import corner_case
from validation.specimens import CORNER_LIFT, G1151_SIZE

__all__ = ["CASE", "SPEC"]

NAME = "bai-6.2.1"
TITLE = "11-ply G1151 laminate: corner lifted beyond a clamped diagonal"
SECTION = "§6.2.1, Fig. 13, 14"
SOURCE = f"Bai et al. (2020) {SECTION}"
# Not checked: |tilt - atan(theta)| along side 1 / side 2 (clamped and lifted nodes left out),
# measured: 1.2 / 1.5 deg on the coarse mesh (8 cells) and at most 2.0 deg on the default one
# (20 cells) for the default fibrous run, but at most 2.1 and 2.2 deg for the Eq. 15 run (tilt
# = theta; theta <= 27 deg here), so no tolerance could separate the two. The paragraph
# reports both.
SLIP_NOTE = (
    "Both sides run from the clamped diagonal to the lifted corner, whose directors are free: "
    "the plies along them slip from the clamp as in a cantilever, so the default directors are "
    "compared with atan(theta) at every node of the sides but the clamped and the lifted "
    "ones (seen facing the side; the surface is also bent across the sides near the corner, "
    "which the tilt in three dimensions, the node field director_tilt, includes). The rotations "
    "stay moderate here, where atan(theta) and theta differ by about the discretisation error, "
    "so the relation is measured but not made a check: it would pass for both fibrous variants."
)

SPEC = corner_case(
    name=NAME,
    title=TITLE,
    source=SECTION,
    fabric=g1151_laminate(),
    size=G1151_SIZE,
    displacement=CORNER_LIFT,
    described="corner lifted 40 mm, x y free",
    cells={"coarse": 8, "default": 20, "fine": 40},
    slip_sides=("side_1", "side_2"),
    slip_note=SLIP_NOTE,
)
CASE = SPEC.case(source=SOURCE, description=__doc__, order=40)
