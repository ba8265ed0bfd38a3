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

SPEC = corner_case(
    name=NAME,
    title=TITLE,
    source=SECTION,
    fabric=g1151_laminate(),
    size=G1151_SIZE,
    displacement=CORNER_LIFT,
    described="corner lifted 40 mm, x y free",
    cells={"coarse": 8, "default": 20, "fine": 40},
)
CASE = SPEC.case(source=SOURCE, description=__doc__, order=40)
