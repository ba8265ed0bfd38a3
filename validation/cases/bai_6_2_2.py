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
from validation import specimens
from validation.paper import PaperCase, run_paper_case

NAME = "bai-6.2.2"
TITLE = "11-ply G1151 laminate: buckling under an in-plane corner displacement"
SOURCE = "Bai et al. (2020) §6.2.2, Fig. 15, 16"
PUSH = 20.0  # mm, assumed
LENGTH, WIDTH = 200.0, 150.0


CASE = PaperCase(
    name=NAME,
    title=TITLE,
    source="§6.2.2, Fig. 15, 16",
    make_specimen=lambda cells: specimens.corner(LENGTH, WIDTH, cells),
    fabric=g1151_laminate(),
    displacement=(PUSH, None, None),
    increments=20,
    cells={"coarse": 8, "default": 12, "fine": 24},
    parameters={
        "length_mm": LENGTH,
        "width_mm": WIDTH,
        "corner displacement (assumed)": f"{PUSH} mm along side 1 (x) to the clamp, y and z free",
    },
)


def run(resolution: str, out_dir) -> dict:
    return run_paper_case(CASE, resolution, out_dir)
