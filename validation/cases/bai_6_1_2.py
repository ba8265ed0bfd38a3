"""Bai §6.1.2 (Fig. 8c, 11, 12): the paper stack of §6.1.1 with its diagonal clamped, an in-plane
displacement imposed at the free corner: the free triangle buckles.

Source: Bai et al. (2020) §6.1.2, Fig. 8c, 11, 12.
Geometry and material: as bai-6.1.1 (A5, 13 mm, all material data assumed).
Load: gravity, and the corner pushed 20 mm in its plane along side 1 (the warp, x) towards the
clamp, free to move in y and z (assumed: the paper gives the direction only in a
sketch). Side 1's fibres cannot shorten, so the free triangle must buckle out of its plane; a
push along the diagonal could instead be taken up by in-plane shear of the fabric, which with
the assumed shear law is softer than bending. Gravity is the imperfection that picks the
buckling direction (down). Static is tried first; where Newton cannot follow the path the case
falls back to dynamic relaxation and says so.
Mindlin: E = 12 B / h^3, nu = 0, G13 = G23 = 0.5 E.
"""

from __future__ import annotations

from materials.presets import paper_stack
from validation import specimens
from validation.paper import PaperCase, run_paper_case

NAME = "bai-6.1.2"
TITLE = "130-sheet paper stack: buckling under an in-plane corner displacement"
SOURCE = "Bai et al. (2020) §6.1.2, Fig. 8c, 11, 12"
PUSH = 20.0  # mm, assumed
LENGTH, WIDTH = 210.0, 148.0


CASE = PaperCase(
    name=NAME,
    title=TITLE,
    source="§6.1.2, Fig. 8c, 11, 12",
    make_specimen=lambda cells: specimens.corner(LENGTH, WIDTH, cells),
    fabric=paper_stack(),
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
