"""Bai §6.1.1 (Fig. 8b, 9, 10): a stack of 130 paper sheets, the part above the diagonal 1-3
clamped, a vertical displacement imposed at the free corner.

Source: Bai et al. (2020) §6.1.1, Fig. 8b, 9, 10.
Geometry: the paper gives no size. Assumed: A5 sheets, 210 x 148 mm; 130 sheets of 0.1 mm =
13 mm. Only the free triangle is meshed (validation.specimens.corner); the diagonal is clamped
(translations and directors fixed; fibrous clamped-edge curvature).
Load: gravity, and the corner lifted by 40 mm (assumed; a rigid support from below can only lift
it), its horizontal motion free (the corner slides on the support).
Material (all assumed, materials.presets.paper_stack): 80 g/m^2 and 0.1 mm per sheet, bending
50 N mm, tension 2300 N/mm (an inextensibility penalty), in-plane shear 1000 N/mm (the paper:
"the in-plane shear stiffness is large"). The sensitivity of the result to B and K is the
subject of the case "bai-6.1.1-sensitivity".
Mindlin: MindlinShell(fabric), calibration "laws" (fibreshell.calibration): the fabric's own
laws, S = 5 B0 / h^2 = 1.48 N/mm, D_t = K0 h^2 / 12 = 1.41e4 N mm (the in-plane shear of
1000 N/mm makes the section stiff in twist). Earlier versions: E = 12 B / h^3, nu = 0, G13 =
G23 = 0.5 E (the old numbers are in the comments below).
"""

from __future__ import annotations

from materials.presets import paper_stack
from validation.paper import corner_case
from validation.specimens import CORNER_LIFT, PAPER_STACK_SIZE

__all__ = ["CASE", "SPEC"]

NAME = "bai-6.1.1"
TITLE = "130-sheet paper stack: corner lifted beyond a clamped diagonal"
SECTION = "§6.1.1, Fig. 8b, 9, 10"
SOURCE = f"Bai et al. (2020) {SECTION}"
# Not checked: |tilt - atan(theta)| along side 1 / side 2 (clamped and lifted nodes left out),
# measured: 1.4 / 1.7 deg on the coarse mesh (8 cells), 2.0 / 2.1 deg on the default one (20
# cells) for the default fibrous run, but 1.7 / 2.0 and 2.4 / 2.6 deg for the Eq. 15 run (tilt =
# theta; theta <= 31 deg here), so no tolerance could separate the two. The paragraph reports
# both.
SLIP_NOTE = (
    "Both sides run from the clamped diagonal to the lifted corner, whose directors are free: "
    "the plies along them slip from the clamp as in a cantilever, so the default directors are "
    "compared with atan(theta) at every node of the sides but the clamped and the lifted "
    "ones (seen facing the side; the surface is also bent across the sides near the corner, "
    "which the tilt in three dimensions, the node field director_tilt, includes). The rotations "
    "stay moderate here, where atan(theta) and theta differ by about the discretisation error, "
    "so the relation is measured but not made a check: it would pass for both fibrous variants."
)

# Observed orders (validation.paper.orders), measured on 4 / 6 / 8 / 10 / 20 / 40 cells with the
# corner lifted by one node (a point load; bai-6.2.1 grips a patch instead): the deflection z
# at the middle of the sides (mm), Mindlin (calibration "laws") side 1 10.360 / 10.079 / 9.861
# / 9.586 / 8.857 / 8.614 (order 1.6 on 10-20-40, its Richardson value 1.4 % from the 40-cell
# one), side 2 7.866 / 6.469 / 5.718 / 5.411 / 4.977 / 6.358 (none: the differences change
# sign; on 20 and 40 cells the Mindlin sheet passes a limit point near the end of the lift,
# at load factor 1.96 and 1.59, and the arc length steps to another branch); with the old
# "initial-slope" section side 1 10.722 / 10.600 / 10.497 / 10.372 / 9.823 / 9.424 (order 0.5
# on 10-20-40, 11 %), side 2 8.412 / 7.921 / 7.906 / 8.008 / 8.375 / 8.351 (none); fibrous side 1
# 4.015 / 4.066 / 4.175 / 4.242 / 4.273 / 4.102 (none), side 2 9.492 / 10.000 / 10.017 / 9.975
# / 9.815 / 9.618 (none: they grow); the fibrous thickness along the director there / h,
# side 1 1.0160 / 1.0177 / 1.0188 / 1.0194 / 1.0200 / 1.0188, side 2 1.0534 / 1.0601 / 1.0628
# / 1.0643 / 1.0659 / 1.0645: no order, but within 0.14 % on 10-20-40. Checked (default and
# fine): the fibrous thickness, 1 % (it passes as converged); the deflections are reported.
ORDER_TOLERANCE = {"fibrous thickness": 0.01}
# Mid-surfaces (validation.paper.profiles.midsurface_gap): the largest distance between the
# same node of the fibrous and the Mindlin run along the sides, 5.74 mm on 8 cells and 5.49
# mm on 20 (13.8 % and 13.2 % of the largest displacement, 41.5 mm; initial-slope: 6.45 and
# 5.84 mm): the laws section hardly changes it here. At the middle of side 1 the Mindlin
# sheet stands twice as high as the fibrous one (8.86 against 4.27 mm on 20 cells), on side
# 2 half as high (4.98 against 9.82 mm). The paper stack's section is far from a solid one:
# its in-plane shear K0 = 1000 N/mm gives the Mindlin shell a twisting stiffness D_t = K0 h^2
# / 12 = 1.4e4 N mm, 280 times its bending B = 50 N mm, against S = 5 B0 / h^2 = 1.5 N/mm of
# transverse shear, so its normals tilt from the directors by up to 25 deg (8 cells) and 36
# deg (20 cells) rather than twist. Tolerance 20 % (every resolution), 1.5 times the
# measured 13.8 %. Directors where the Mindlin slope > 20 deg: fibrous - Mindlin up to 26.6
# deg (8 cells), 29.2 deg (20 cells) (initial-slope: 28.7, 33.7): the check is unchanged.
MIDSURFACE_TOLERANCE = 0.2
COMPARISON_NOTE = (
    "Here the same fabric does not make the same shape: the Mindlin side 1 stands about "
    "twice as high at its middle as the fibrous one and its side 2 half as high (mid-surfaces "
    "13 to 14 % of the 41.5 mm lift apart, as with the old initial-slope section). The paper "
    "stack's in-plane shear (K0 = 1000 N/mm) gives the Mindlin section a twisting stiffness "
    "D_t = K0 h^2 / 12 = 1.4e4 N mm, 280 times its bending, which the fibrous stack, whose "
    "directors slip, does not feel; the Mindlin sheet shears through its thickness instead "
    "(its directors leave the normal by up to 25 to 36 deg). The directors still differ by "
    "about 27 to 29 deg where the sides are steep."
)
SPEC = corner_case(
    name=NAME,
    title=TITLE,
    source=SECTION,
    fabric=paper_stack(),
    size=PAPER_STACK_SIZE,
    displacement=CORNER_LIFT,
    described="corner lifted 40 mm, x y free",
    cells={"coarse": 8, "default": 20, "fine": 40},
    order_cells={"coarse": (4, 6, 8), "default": (10, 20, 40), "fine": (10, 20, 40)},
    order_tolerance={"default": ORDER_TOLERANCE, "fine": ORDER_TOLERANCE},
    slip_sides=("side_1", "side_2"),
    slip_note=SLIP_NOTE,
    comparison_note=COMPARISON_NOTE,
    midsurface_tolerance=MIDSURFACE_TOLERANCE,
)
CASE = SPEC.case(source=SOURCE, description=__doc__, order=20)
