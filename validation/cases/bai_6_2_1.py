"""Bai §6.2.1 (Fig. 13, 14): the 11-ply G1151 laminate, 200 x 150 x 15 mm, the part above the
diagonal clamped, a vertical displacement imposed at the free corner by a gripper.

Source: Bai et al. (2020) §6.2, §6.2.1, Fig. 13, 14, Table 2.
Geometry: 200 x 150 x 15 mm (paper). Only the free triangle is meshed; the diagonal is clamped.
Load: gravity, then the corner lifted by 40 mm (assumed) by a gripper: the 20 x 15 mm patch at
the corner (assumed: the paper's text gives no size, only "a rigid support imposes a vertical
displacement at the corner" (§6.1.1), and its Fig. 8 is not legible in the text this project
holds; jaws about as wide as the laminate is thick, one tenth of each side, so that the
patch's edges are grid lines of the uniform meshes of 10, 20, 40, 60 cells) rises 40 mm as one
rigid patch (elements.Grip), free to slide horizontally (a carriage), its directors (Mindlin:
rotations) held as the jaws hold the plies. Earlier versions of this case lifted the corner
node alone, a point load (the measurements of both set-ups are in the module's comments).
Material: Table 2 (tension 2300 N/mm, bending 72 N mm warp along x, 68 N mm weft along y);
assumed 630 g/m^2 per ply and in-plane shear 2.2 N/mm (materials.presets.g1151_laminate).
Mindlin: MindlinShell(fabric), calibration "laws" (fibreshell.calibration): the fabric's own
laws (tension 2300 N/mm, bending 72 / 68 N mm, in-plane shear 2.2 N/mm), S = 5 B0 / h^2 =
1.6 N/mm, D_t = B0 / 2 = 36 N mm (the isotropic plate's D (1 - nu) / 2 at nu = 0, B0 = 72 N
mm; before, K0 h^2 / 12 = 41 N mm, 1.15 times as much: the deflections moved by about 1 %). Earlier
versions: the "initial-slope" section,
orthotropic E1 = 12 x 72 / h^3, E2 = 12 x 68 / h^3, nu = 0, G13 = G23 = 0.5 E1 (its membrane
E1 h = 3.8 N/mm, 600 times softer than the fibres; the old numbers are in the comments
below).
"""

from __future__ import annotations

from materials.presets import g1151_laminate
from validation.paper import corner_case
from validation.specimens import CORNER_LIFT, G1151_SIZE

__all__ = ["CASE", "SPEC"]

NAME = "bai-6.2.1"
TITLE = "11-ply G1151 laminate: corner lifted by a gripper beyond a clamped diagonal"
SECTION = "§6.2.1, Fig. 13, 14"
SOURCE = f"Bai et al. (2020) {SECTION}"
GRIP = (20.0, 15.0)  # mm along x and y: the gripped patch at the corner (assumed)
# Measured (validation.paper.orders): the deflection z at the middle of side 1 / side 2 (mm)
# and the fibrous thickness along the director there (/ h) on 5 / 10 / 20 / 40 / 60 cells (h =
# 53 / 20 / 10 / 5 / 3.3 mm), the gripped patch:
#   Mindlin (calibration "laws", MindlinShell(fabric), D_t = B0 / 2) side 1: 19.721 / 16.307 /
#     15.940 / 15.799 / 15.755 (5 to 60 cells); side 2: 22.171 / 20.280 / 19.986 / 19.873 /
#     19.842. Observed order on 10-20-40 1.38 and 1.38 (Richardson values 0.56 % and 0.35 %
#     from the 40-cell ones), on 5-10-20 2.1 and 1.7 (0.67 % and 0.63 %), on 20-40-60 1.1 and
#     1.3 (0.49 % and 0.23 %). With D_t = K0 h^2 / 12 side 1: 19.558 / 16.175 / 15.820 /
#     15.686 (5 to 40 cells); side 2: 21.956 / 20.021 / 19.744 / 19.640 (order 1.40 and 1.41
#     on 10-20-40, 0.53 % and 0.32 %; 2.2 and 1.8 on 5-10-20, 0.64 % and 0.55 %).
#   Mindlin with the old "initial-slope" section, side 1: 17.866 / 13.896 / 13.508 / 13.353 /
#     13.299 (5 to 60 cells); side 2: 20.657 / 18.466 / 18.185 / 18.072 / 18.022 (order on
#     10-20-40 1.32 and 1.32, Richardson values 0.77 % and 0.42 %; on 20-40-60 0.93 and 0.52).
#   fibrous side 1: 16.575 / 16.386 / 16.680 / 17.009 / 17.151; side 2: 21.790 / 21.972 /
#     22.087 / 22.353 / 22.501: the deflections grow as the mesh is refined, by as much from
#     20 to 40 cells as from 10 to 20 (no positive order on 10-20-40, 0.5 and 0.1 on
#     20-40-60). Thickness side 1: 1.0473 / 1.1138 / 1.1207 / 1.1269 / 1.1296, side 2: 1.0838 /
#     1.1619 / 1.1686 / 1.1735 / 1.1759 (order 0.2 and 0.5 on 10-20-40, 0.6 and 0.3 on 20-40-60).
# With the corner lifted by one node, as before (8 / 20 / 40 / 60 cells; at the corner node,
# where the thickness was largest): Mindlin side 1 6.572 / 6.268 / 6.146 / 6.106, side 2 9.869
# / 9.603 / 9.474 / 9.428 (order 1.03 and 0.85 on 20-40-60, 0.78 and 0.56 on 8-20-40); fibrous
# side 1 6.189 / 6.045 / 5.873 / 5.792, side 2 10.282 / 9.897 / 9.688 / 9.598 (order 0.37 and
# 0.54 on 20-40-60, none and 0.41 on 8-20-40), corner thickness 1.214 / 1.244 / 1.265 / 1.276
# (order 0.07 on 20-40-60, 0.09 on 8-20-40: it kept growing). With the patch's nodes free to slide
# apart (directors held, no Grip), the Mindlin deflection lost its order between 40 and 60
# cells (side 1 13.474 / 13.313 / 13.223 on 20 / 40 / 60: order 0.4): the soft membrane of
# the initial-slope calibration (E h = 3.8 N/mm) let the patch deform, which jaws do not; the
# fibrous side 1 went 16.045 / 16.608 / 17.011 on 10 / 20 / 40 (order 0.5). The grip took the
# point load away, but the fibrous deflections and mid-side thickness converge slowly with and
# without it: that slowness is the fibrous shell's on this test, not the load's, and they are
# reported, not checked. Order check (default and fine, 10-20-40 cells): the Mindlin
# deflections, tolerance 1 % (measured 0.56 % and 0.35 % with the laws section, 0.53 % and
# 0.32 % with its earlier D_t; it was 2 % for the initial-slope section's 0.77 % and 0.42 %:
# tightened, the margin staying about 2 x; unchanged with D_t = B0 / 2, margin 1.8 x).
ORDER_TOLERANCE = {"mindlin deflection": 0.01}
# Mid-surfaces (validation.paper.profiles.midsurface_gap): the largest distance between the
# same node of the fibrous and the Mindlin run along the sides, 1.87 mm on 10 cells and 2.37
# mm on 20 (4.5 % and 5.7 % of the largest displacement, 41 mm; D_t = K0 h^2 / 12: 2.15 and
# 2.64 mm, 5.2 % and 6.4 %; initial-slope: 3.94 and 4.38 mm); at the middle of the sides the
# Mindlin deflections are 16.31 / 20.28 mm (10 cells) and 15.94 / 19.99 mm (20 cells) against
# the fibrous 16.39 / 21.97 and 16.68 / 22.09 mm. The distance grows slowly with the mesh, as
# the fibrous deflections do (the 40-cell fibrous side 2 is 22.35 mm, the Mindlin 19.87):
# tolerance 12 %, about twice the 20-cell value (kept: the largest measured value went down).
# Directors where the Mindlin slope > 20 deg: fibrous - Mindlin up to 27.0 deg (10 cells),
# 26.6 deg (20 cells), as with D_t = K0 h^2 / 12 (initial-slope: 27.3, 26.8): the check (> 10
# deg) is unchanged.
MIDSURFACE_TOLERANCE = 0.12
COMPARISON_NOTE = (
    "With the same fabric the mid-surfaces are close (within 4.5 to 6 % of the 41 mm lift on "
    "10 and 20 cells, against 10 % with the old initial-slope section; the middle of the "
    "fibrous sides rises 0.1 to 2.1 mm higher than the Mindlin one), and the directors "
    "differ by about 27 deg where the sides are steepest: the Mindlin directors follow the "
    "normal (within 7 deg), the fibrous ones stay nearer the vertical."
)
# Not checked: |tilt - atan(theta)| along side 1 / side 2 (clamped and gripped nodes left
# out), measured for the default fibrous run: 0.86 / 0.91 deg on the coarse mesh (10 cells),
# 0.97 / 0.92 deg on the default one (20 cells), but for the Eq. 15 run (tilt = theta) 1.2 /
# 1.9 and 1.2 / 2.0 deg: on side 1 too close to the default run's to separate them by a
# tolerance. The paragraph reports both.
SLIP_NOTE = (
    "Both sides run from the clamped diagonal to the gripped patch, which holds the directors "
    "vertical too: the plies along a side are held at both ends, unlike a cantilever's, "
    "whose free end lets them slip all the way from the clamp. The default directors are "
    "still compared with "
    "atan(theta) at every node of the sides but the clamped and the gripped ones (seen facing "
    "the side; the surface is also bent across the sides near the corner, which the tilt in "
    "three dimensions, the node field director_tilt_deg, includes), but the relation is measured, "
    "not made a check."
)

SPEC = corner_case(
    name=NAME,
    title=TITLE,
    source=SECTION,
    fabric=g1151_laminate(),
    laws_source="Bai Table 2, G1151 (its bending tests: Bai Fig. 7)",
    size=G1151_SIZE,
    displacement=CORNER_LIFT,
    described="gripped patch lifted 40 mm, x y free (sliding as one)",
    cells={"coarse": 10, "default": 20, "fine": 40},
    slip_sides=("side_1", "side_2"),
    slip_note=SLIP_NOTE,
    grip=GRIP,
    comparison_note=COMPARISON_NOTE,
    midsurface_tolerance=MIDSURFACE_TOLERANCE,
    order_cells={"default": (10, 20, 40), "fine": (10, 20, 40)},
    order_tolerance={"default": ORDER_TOLERANCE, "fine": ORDER_TOLERANCE},
    # The two other meshes' runs, of which the orders read the last equilibrium alone, on 5
    # arc-length increments a phase instead of 10 (one thread, CPU): fibrous 10 cells 0.98 ->
    # 0.31 s, 40 cells 7.36 -> 4.27 s (21 -> 11 increments, 74 -> 46 Newton iterations),
    # Mindlin 10 / 40 cells 0.22 -> 0.12 / 1.41 -> 0.94 s; the compared quantities the same
    # equilibrium within Newton's tolerance (at most 7.4e-10 relative apart; the orders'
    # checks are at 1 %).
    order_increments=5,
)
CASE = SPEC.case(source=SOURCE, description=__doc__, order=40)
