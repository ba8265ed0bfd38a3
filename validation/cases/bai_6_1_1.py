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
laws, S = 5 B0 / h^2 = 1.48 N/mm, D_t = B0 / 2 = 25 N mm (the isotropic plate's D (1 - nu) / 2
at nu = 0). Before, D_t = K0 h^2 / 12 = 1.41e4 N mm: the in-plane shear of 1000 N/mm through a
solid section, 280 times the bending, with which the Mindlin sheet took another shape. Earlier
still: E = 12 B / h^3, nu = 0, G13 = G23 = 0.5 E. The old numbers are in the comments below.
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
# at the middle of the sides (mm), Mindlin (calibration "laws", D_t = B0 / 2) side 1 6.571 /
# 6.308 / 6.200 / 6.146 / 5.990 / 5.848 (order 0.13 on 10-20-40: the differences, 0.16 and
# 0.14 mm, barely shrink, its Richardson value 25 % from the 40-cell one; 1.6 on 4-6-8), side
# 2 10.238 / 10.383 / 10.407 / 10.399 / 10.304 / 10.192 (none on 10-20-40: the differences,
# 0.10 and 0.11 mm, grow); the sheet drifts down by about 2 % per halving of the cells, no
# limit point on any mesh. With D_t = K0 h^2 / 12 side 1 10.360 / 10.079 / 9.861 / 9.586 /
# 8.857 / 8.614 (order 1.6 on 10-20-40, 1.4 %), side 2 7.866 / 6.469 / 5.718 / 5.411 / 4.977
# / 6.358 (none: a limit point near the end of the lift on 20 and 40 cells, at load factor
# 1.96 and 1.59, the arc length stepping to another branch); with the old "initial-slope"
# section side 1 10.722 / 10.600 / 10.497 / 10.372 / 9.823 / 9.424 (order 0.5
# on 10-20-40, 11 %), side 2 8.412 / 7.921 / 7.906 / 8.008 / 8.375 / 8.351 (none); fibrous side 1
# 4.015 / 4.066 / 4.175 / 4.242 / 4.273 / 4.102 (none), side 2 9.492 / 10.000 / 10.017 / 9.975
# / 9.815 / 9.618 (none: they grow); the fibrous thickness along the director there / h,
# side 1 1.0160 / 1.0177 / 1.0188 / 1.0194 / 1.0200 / 1.0188, side 2 1.0534 / 1.0601 / 1.0628
# / 1.0643 / 1.0659 / 1.0645: no order, but within 0.14 % on 10-20-40. Checked (default and
# fine): the fibrous thickness, 1 % (it passes as converged); the deflections are reported
# (no order on 10-20-40, Mindlin or fibrous).
ORDER_TOLERANCE = {"fibrous thickness": 0.01}
# Mid-surfaces (validation.paper.profiles.midsurface_gap): the largest distance between the
# same node of the fibrous and the Mindlin run along the sides, 2.13 mm on 8 cells, 1.81 mm
# on 20 and 1.85 mm on 40 (5.1 %, 4.4 % and 4.5 % of the largest displacement, 41.5 mm). At
# the middle of the sides the Mindlin sheet stands 2.0 and 1.7 mm higher than the fibrous one
# on side 1 (6.20 against 4.17 mm on 8 cells, 5.99 against 4.27 mm on 20) and 0.4 and 0.5 mm
# on side 2 (10.41 against 10.02, 10.30 against 9.82 mm). Its directors leave the normal by
# at most 1.5 deg (8 cells) and 2.9 deg (20 cells). With D_t = K0 h^2 / 12 = 1.4e4 N mm (280
# times the bending B = 50 N mm, against S = 5 B0 / h^2 = 1.5 N/mm of transverse shear) the
# distance was 5.74 and 5.49 mm (13.8 % and 13.2 %; initial-slope: 6.45 and 5.84 mm): the
# Mindlin side 1 stood twice as high as the fibrous one (8.86 mm on 20 cells), side 2 half as
# high (4.98 mm), and the normals tilted from the directors by up to 25 and 36 deg rather
# than twist. Tolerance 10 % (every resolution), twice the largest measured 5.1 % (it was 20
# %, 1.5 times 13.8 %: tightened with the plate's D_t). Directors where the Mindlin slope >
# 20 deg: fibrous - Mindlin up to 29.0 deg (8 cells), 28.9 deg (20 cells), 28.8 deg (40
# cells) (D_t = K0 h^2 / 12: 26.6, 29.2; initial-slope: 28.7, 33.7): the check (> 10 deg) is
# unchanged.
MIDSURFACE_TOLERANCE = 0.1
COMPARISON_NOTE = (
    "With the same fabric the two sheets take nearly the same shape: their mid-surfaces lie "
    "within 4 to 5 % of the 41.5 mm lift of each other, the middle of the Mindlin side 1 "
    "about 2 mm above the fibrous one and of side 2 about 0.5 mm. The Mindlin section's "
    "twisting stiffness is the plate's, D_t = B0 / 2 = 25 N mm; with the earlier default, "
    "the in-plane shear through a solid section (K0 h^2 / 12 = 1.4e4 N mm, 280 times the "
    "bending), the Mindlin sheet sheared through its thickness instead of twisting (its "
    "directors up to 36 deg from the normal, now within 3 deg) and the mid-surfaces were 13 "
    "to 14 % apart. The directors differ by about 29 deg where the sides are steep: the "
    "Mindlin ones follow the normal, the fibrous ones stay nearer the vertical."
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
