"""Bai §6.2.2 (Fig. 15, 16): the G1151 laminate of bai-6.2.1 with its diagonal clamped, an in-plane
displacement imposed at the free corner: buckling.

Source: Bai et al. (2020) §6.2.2, Fig. 15, 16, Table 2.
Geometry and material: as bai-6.2.1.
Load: gravity, and the corner pushed 20 mm in its plane along side 1 (the warp, x) towards the
clamp, free to move in y and z (assumed; see bai-6.1.2); gravity picks the buckling
direction. Static follows the arc length of the path (load steps past a limit point).
Mindlin: as bai-6.2.1 (MindlinShell(fabric), calibration "laws", D_t = B0 / 2 = 36 N mm; before,
K0 h^2 / 12 = 41 N mm: the mid-side deflections moved by up to 3.4 %, the old numbers are in
the comments).
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
# Not checked: |tilt - atan(theta)| along side 1 / side 2 (clamped and pushed nodes left out),
# measured for the default fibrous run: 4.2 / 5.3 deg on the coarse mesh (8 cells), at most 6.0 deg
# on the default one (12 cells); the Eq. 15 run (tilt = theta) gives about as much (up to 5.3
# and 6.1 deg), so the free-slip relation does not describe this test. The paragraph reports
# both.
SLIP_NOTE = (
    "The corner is pushed towards the clamp in the plane and the free triangle buckles: the "
    "fibres along the sides carry the push in compression and the surface bends across the "
    "sides as well as along them, so the plies do not slip as in a cantilever and the relation "
    "tilt = atan(theta) is not expected to hold. It is measured along both sides, away from the "
    "clamped and the pushed nodes, but not made a check; near the clamp, where the rotation is "
    "small, atan(theta) and theta cannot be told apart."
)

# Observed orders (validation.paper.orders), measured on 4 / 6 / 8 / 12 / 24 cells: the
# deflection z at the middle of the sides (mm), Mindlin (calibration "laws", D_t = B0 / 2)
# side 1 -10.065 / -9.851 / -9.732 / -9.569 / -9.293 (order 0.02 on 6-12-24: the
# differences, 0.28 and 0.28 mm, do not shrink), side 2 -19.728 / -19.565 / -19.464 /
# -19.299 / -18.962 (none: they grow, 0.27 and 0.34 mm); with D_t = K0 h^2 / 12 side 1 -9.862
# / -9.616 / -9.478 / -9.294 / -8.990 (order 0.08), side 2 -19.757 / -19.553 / -19.426 /
# -19.228 / -18.847 (none); with the old
# "initial-slope" section side 1 -8.466 / -7.766 / -7.454 / -7.123 / -6.740 (order 0.7,
# Richardson value 8.5 % from the 24-cell one), side 2 -18.830 / -18.504 / -18.242 / -17.789 /
# -16.958 (none); fibrous side 1
# -11.618 / -12.108 / -12.261 / -12.325 / -12.227 (none; a limit point at 24 cells), side 2
# -22.501 / -21.580 / -21.194 / -20.816 / -20.365 (order 0.8, 3.2 %); the fibrous thickness
# along the director there / h, side 1 1.0734 / 1.0803 / 1.0834 / 1.0853 / 1.0848, side 2
# 1.1755 / 1.1846 / 1.1881 / 1.1899 / 1.1877 (no order on 6-12-24, but within 0.41 % and
# 0.26 %). Checked (default and fine): the fibrous thickness, 1 % (it passes as converged);
# the rest is reported. The corner is pushed by one node (an in-plane point load), not lifted,
# and is left so: the gripped patch replaced the lifted node of bai-6.2.1.
ORDER_TOLERANCE = {"fibrous thickness": 0.01}
# Mid-surfaces (validation.paper.profiles.midsurface_gap): the largest distance between the
# same node of the fibrous and the Mindlin run along the sides, 4.59 mm on 8 cells and 5.11
# mm on 12 (6.5 % and 7.2 % of the largest displacement, 71 mm; D_t = K0 h^2 / 12: 5.03 and
# 5.62 mm, 7.1 % and 8.0 %; initial-slope: 9.01 and 10.54 mm). Tolerance 12 % (every
# resolution; kept: the measured values went down; 24 cells not measured: the mid-side gaps
# there, 2.9 and 1.4 mm from the values above, are those of 12 cells, 2.8 and 1.5 mm).
# Directors where the Mindlin slope > 20 deg: fibrous - Mindlin up to 52.2 deg (8 cells),
# 51.6 deg (12 cells) (D_t = K0 h^2 / 12: 52.0, 51.4; initial-slope: 43.5, 41.6): the check
# (> 10 deg) is unchanged.
MIDSURFACE_TOLERANCE = 0.12
COMPARISON_NOTE = (
    "With the same fabric both sheets buckle down the same way and their mid-surfaces lie "
    "within 6.5 to 7 % of the 71 mm corner displacement of each other (the old initial-slope "
    "section: 13 to 15 %); the Mindlin sides stay 1.5 to 3 mm higher at their middle. The "
    "directors differ by about 50 deg where the sides are steepest: the Mindlin directors "
    "follow the normal (within 4 deg), the fibrous ones do not."
)
SPEC = corner_case(
    name=NAME,
    title=TITLE,
    source=SECTION,
    fabric=g1151_laminate(),
    laws_source="Bai Table 2, G1151 (its bending tests: Bai Fig. 7)",
    size=G1151_SIZE,
    displacement=(PUSH, None, None),
    described=f"{PUSH} mm along side 1 (x) to the clamp, y and z free",
    cells={"coarse": 8, "default": 12, "fine": 24},
    order_cells={"default": (6, 12, 24), "fine": (6, 12, 24)},
    order_tolerance={"default": ORDER_TOLERANCE, "fine": ORDER_TOLERANCE},
    increments=20,
    slip_sides=("side_1", "side_2"),
    slip_note=SLIP_NOTE,
    comparison_note=COMPARISON_NOTE,
    midsurface_tolerance=MIDSURFACE_TOLERANCE,
    # The two other meshes' runs, of which the orders read the last equilibrium alone, on 10
    # arc-length increments a phase instead of 20 (benchmarks/paper_refinement.py --turns 3;
    # one thread, CPU, best of 3 alternating turns in one process, load 1.0-1.3): the four
    # runs 3.68 -> 2.95 s (each turn's 4.18 / 3.86 / 3.68 against 2.95 / 3.18 / 3.03; the
    # 24-cell fibrous run 22 -> 15 increments, 116 -> 96 Newton iterations,
    # the limit point passed as before); the compared quantities the same equilibrium within
    # 1.1e-9 relative (the orders' checks are at 1 %). On 5 or 3 the 24-cell runs cut 3-4
    # times and cost as much as on 20.
    order_increments=10,
)
CASE = SPEC.case(source=SOURCE, description=__doc__, order=50)
