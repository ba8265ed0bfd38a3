"""Bai §6.2.2 (Fig. 15, 16): the G1151 laminate of bai-6.2.1 with its diagonal clamped, an in-plane
displacement imposed at the free corner: buckling.

Source: Bai et al. (2020) §6.2.2, Fig. 15, 16, Table 2.
Geometry and material: as bai-6.2.1.
Load: gravity, and the corner pushed 20 mm in its plane along side 1 (the warp, x) towards the
clamp, free to move in y and z (assumed; see bai-6.1.2); gravity picks the buckling
direction. Static is
tried first, dynamic relaxation where Newton cannot follow the path.
Mindlin: as bai-6.2.1.
"""

from __future__ import annotations

from materials.presets import g1151_laminate
from validation.paper import corner_case
from validation.specimens import G1151_SIZE

__all__ = ["CASE", "SPEC"]

NAME = "bai-6.2.2"
TITLE = "11-ply G1151 laminate: buckling under an in-plane corner displacement"
SECTION = "§6.2.2, Fig. 15, 16"
SOURCE = f"Bai et al. (2020) {SECTION}"
PUSH = 20.0  # mm, assumed

SPEC = corner_case(
    name=NAME,
    title=TITLE,
    source=SECTION,
    fabric=g1151_laminate(),
    size=G1151_SIZE,
    displacement=(PUSH, None, None),
    described=f"{PUSH} mm along side 1 (x) to the clamp, y and z free",
    cells={"coarse": 8, "default": 12, "fine": 24},
    increments=20,
)
CASE = SPEC.case(source=SOURCE, description=__doc__, order=50)
