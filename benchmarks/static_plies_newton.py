"""Where the Static ply cases' Newton iterations go, increment by increment: each attempt's
residual ratios, the watchdog's step lengths and its trial force passes and energies, the cut
attempts and why they failed, and what the ply contact's points did between the iterates (on
or off the ramp -delta < g < 0 of the smoothed penalty, deeper, in the fade past the outline,
the facing triangle switched, the sign of the gap flipped), docs/theory.md §6.5 ("Stalled
attempts") and §9.3a; the case's plies solved without ``Static(stall_iterations=...)`` (the
reference pass, as before) and with it (``--stall``, 25 by default), side by side in this
process, the final positions and directors compared; with ``--first-turn theta`` the two
sides are the case's solver (``--stall``, or none with ``--no-stall``) without and with
``Static(first_turn=theta)`` (docs/theory.md §6.5, "Increments sized by the first step"), and
with ``--update-turn theta`` the case's solver without and with ``Static(update_turn=theta)``
(docs/theory.md §6.5, "Updates of a turning stack"), and with ``--curved`` the case's solver
without and with ``Static(curved_with_contact=True)`` (docs/theory.md §6.5, "Curved steps of
a sliding stack"; ``--increments`` sets the deck's on both sides).
``--detail`` prints, per iterate, the element blocks' and the interactions' internal-force
norms and the deepest ply gap as well, and between iterates the largest change of a point's
gap; ``--detail --parts`` adds, per iterate, the norms on the free unknowns of the plies'
membrane, bending and transverse-shear loads, the ply contact's and the dead load's (the
record and what it showed: benchmarks/static_plies_iterates.py). ``--tangent-check`` solves
the case once and compares, on the last increment's iterates, each part's tangent with
central differences of its forces and the whole residual's directional derivative with -K v
(no timing), with ``--check-load L --every k`` on every k-th iterate of the attempt that
converged at load factor L (benchmarks/static_plies_tangent_check.py); ``--deck-start``
solves the default report's five decks without and with the case's soft start
(benchmarks/static_plies_deck_start.py); ``--active-set`` the case's plies with the ply
contact's ramp and with its active set (benchmarks/static_plies_active_set.py). Each of
those scripts runs alone as well and holds the figures it measured; the cases are set up in
benchmarks/static_plies_case.py (``solve_case``).

    python benchmarks/static_plies_newton.py [--case bai|heavy|deck|sag]
        [--resolution coarse|default] [--stall 25] [--first-turn 0.1 [--no-stall]]
        [--update-turn 0.03 [--no-stall]] [--curved [--increments 8]] [--rounds 2]
        [--detail [--parts]] [--tangent-check [--check-load 1.8] [--every 1]] [--deck-start]
        [--active-set [--plies 20] [--unopened]]  (--active-set: bai or heavy)

bai: plies-bai-5.1's stack (validation/cases/plies_bai_5_1.py); heavy: plies-heavy-cantilever's;
deck and sag: plies-deck-of-cards' deck at its largest N on 20 cells and its heavy stack of the
fewest plies. One thread, CPU time (``time.process_time``); the machine's load is printed.

Measured (one thread, CPU, 2 cores shared with other jobs):

* bai, coarse (12 cells, 4 plies, 10 increments a phase; load 2-4.5): 21-5-4-4-4-3-3-3-3-3
  in the gravity phase (the first from the plies laid at g = 0: all 144 points on the ramp,
  8-28 stepping on or off it at each iterate while the ratio crawls from 1e-4 to 1e-6; each
  later increment 3-5, a quadratic tail from 1e-3). The displacement phase: at its start 12
  of the 144 points touch; the imposed step, taken whole with the free unknowns moved by
  K_ff^-1 K_fp (no stiffness between plies apart), carries 120 points through the ply below
  (the gaps change sign by more than 1e-3 mm); from there 20-80 points step on or off at every
  iterate (no facing triangle switches, no point in the fade), the watchdog's steps are
  0.004-1 with 1-6 trial force passes, and the ratio stays at 0.6-1.0: 105, 149, 52, 149
  iterations in the attempts at the whole, half, quarter and eighth step (two failed on the
  line search, two at max_iterations 150) before 1/16 converges in 29 (ratio ~1 for 16,
  then a quadratic tail). Then 116, 26, 14, 18, 8-12 iterations per increment, each a plateau
  of ratio ~1 and a tail. In all 358 converged and 470 cut iterations (1065 force passes,
  664 energies, 834 tangents; the accepted trial's forces are already the next iteration's
  residual: one force pass an iteration, more only where the watchdog backtracks). With
  stall_iterations=25 (load 9-11): 261 and 140 (the second increment 116 -> 19 after a cut;
  507 force passes, 218 energies, 403 tangents), 15: 238 and 120, 20 with the ratio's
  halving as the rule: 261 and 119.
* bai, default (30 cells, 8 plies, 20 increments a phase; load 9-16): without the rule 57.0 s,
  465 converged iterations (22-6-5-4-4-4-4-3 ... and 92, 33, 21, 12-19 in the displacement
  phase) and 420 in three cut attempts of its first displacement increment (149, 149 and 122
  iterations at ratio 0.6-1.0); with 25: 31.1 s, the same 465 and 75 cut (25 each), the final
  positions and directors the same to the bit (the attempts cut fail either way: the path is
  the same). The report's case side by side (``python -m validation --cases plies-bai-5.1
  --jobs 1``, main's code from a ``git archive``): default 124.9 -> 82.9 s CPU (load 10-15),
  results.json the same in every number; coarse 17.2 -> 9.9 s (load 13-15), its numbers
  within 4e-14 relative (5.2905, 3.2354, 3.3894, 0.2146, 27.031), Newton iterations of the
  three runs 824 -> 727.
* sag, coarse (the heavy stack of 4 plies, 20 cells, gravity in 6 increments; load 9-11):
  98-120-32-33-16-15 and 30 cut without the rule (its first increment converges after a
  plateau of 58 iterations at ratio ~1); with 25: 289 and 188, with 30: 289 and 97: more in
  all, so the deck-of-cards case does not set it; its 8-ply stack (default): 142-103-33-22-17-15
  and 73 cut in 4 attempts (14-23 iterations each, all on the line search), 11.2 s; with 25:
  218 and 200 in 10, 12.1 s, the same equilibrium to 1e-13 mm. The deck (4 plies, 20 cells,
  8 increments): 12-12-12-12-12-14-36-92 and 17 cut, the same with 25 (its last increments
  converge linearly in the band 1e-5 to 1e-2, below the rule's 0.1).
* heavy, default (plies-heavy-cantilever's 8 plies on 20 cells, 10 increments; load 11-16):
  18-32-21-33-34-14-44-13-13-11, no cut, 7.2 s; with 25 the seventh increment is cut once
  (25 iterations, then 20), 209 and 25, 6.0 s, the same equilibrium to 1e-13 mm: nothing
  saved, and the case does not set it.
* Not kept (coarse bai, in this script's way): the ply contact's tangent with the full
  penalty k on the ramp while the ratio is above 1e-2 (472 and 544) or 1e-4 (1996 and 1831);
  ``predictor=True`` (405 and 596; the heavy stack 348 and 440); the fibre-length
  projection, the curved steps and the chords let through with the ply contact (fibres alone
  816 and 1881; with the chords 751 and 1847; all three 425 and 988; on the heavy stack 186
  and 172 against 314 and 30); the first tangent of each increment (the one of the imposed
  step) holding the points near contact, touching or up to a gap b apart, with the full
  penalty k (b = 0.003 mm: 303 and 399; 0.01: 312 and 403; 0.1: 368 and 424), or every
  tangent so with b = 0.01 (the first increment fails after 10 cuts, stuck at a ratio of
  3e-5: the tangent no longer the force's derivative near equilibrium): 15 % fewer
  iterations at best, from the first tangents alone.

The imposed step (``--first-turn``; one thread, CPU, the reference pass first in the same
process, so its CPU holds the loading of the compiled kernels: the counts are the measure):

* What the first step of each attempt asks for (coarse bai, stall 25): the gravity phase's
  first steps turn a director by at most 0.052 rad; the displacement phase's first step 1.45
  rad and 59 mm of free translation for an imposed (-3, 0, -5) mm: pushed along its axis, the
  sagged strip has to buckle, and the linear step at the sagged state carries 120 of the 144
  ply points up to 0.49 mm through the ply below (ramp 1.5e-3 mm). Attempts whose first step
  turned a director by 1.45, 0.73, 0.36, 0.18, 0.134, 0.177 rad were cut (25 iterations each
  at ratio ~1, or 7 on the line search), and one of 0.090 (8, on the line search); the others,
  0.044-0.127 rad, converged in 8-29 iterations.
* Kept, first_turn = 0.1 (the attempt cut to the largest 1/2^k whose first step turns none
  by more, before any iteration): bai coarse (load 8-9) 261 converged and 140 cut iterations,
  7 cuts, 403 tangents, 507 force passes, 218 energies, 7.7 s -> 257 and 8, 1 cut, 5
  first-turn cuts, 271 tangents, 336 force passes, 89 energies, 3.9 s; the same
  sub-increments (1/16 of the first displacement increment first, as the cuts reached),
  final positions within 2.5e-14 mm. Per increment 21-5-4-4-4-3-3-3-3-3 and
  82-19-26-14-18-8-11-10-8-12 -> the same gravity phase and 82-19-18-18-18-8-11-10-8-12
  (1.3 and 1.4 now each in two halves of 8-10 iterations, where whole they took 26 and 14).
  bai default (load 12-13) 465 and 75, 540 tangents, 38.7 s -> 462 and 0, 464 tangents,
  28.4 s, within 7.1e-14 mm; per increment 22-6-5-4-4-4-4-3 (x13) and 92-33-21-12-15-19-
  17-14-13-14-18-16-14-11-13-12-10-11-12-10 -> the same but 33 -> 30. The report's case
  (``python -m validation --cases plies-bai-5.1 --jobs 1``, the code before from a
  ``git archive`` beside it, warm caches, load 11-14): coarse 9.8 -> 7.4 s CPU (the plies
  29.0 -> 19.5 s wall), results.json's numbers within 6e-15 relative, steps 727 -> 723.
* Other limits on bai coarse: 0.05, 339 and 0 (360 tangents; the smaller sub-increments
  take 14-31 iterations each); 0.2, 261 and 65 (329 tangents).
* The other stacks, not set there: heavy default (no stall rule, load 12) 233 -> 205
  tangents (18-32-21-33-34-14-44-13-13-11 -> 18-32-34-22-23-19-20-13-13-11), within 1.1e-13
  mm; heavy coarse 188 -> 192 tangents (17-30-36-11-30-11-14-20-9-10 ->
  17-30-19-19-22-21-20-20-9-10), within 5.3e-14 mm; sag coarse (no stall rule, load 9) 314
  and 30 (345 tangents; 98-120-32-33-16-15) -> 327 and 0 (342; 150-64-50-25-23-15: its first
  increment's step turns 0.57 rad, and the plies laid at g = 0 are its plateau's cause, not
  the step), within 1.2e-13 mm; with 0.05, 460 and 6 (500 tangents); the deck coarse (no
  stall rule) 202 and 17 (220 tangents; 12-12-12-12-12-14-36-92) -> 205 and 89 (303;
  14-14-14-14-14-14-14-107: each of the 8 increments cut once by the rule, two sub-increments
  taking 14 where the whole took 12, and the last one's attempt still cut after 89), within
  3.6e-11 mm.
* Not kept: the imposed step truncated at the first contact event (the whole step scaled so
  that no point's gap, interpolated linearly between the iterate and the step's end, passes
  below -delta where it was above): the scales kept were about 0.01 and each iterate imposed
  the remainder again, 546 converged and 758 cut (1304 tangents); floored at 1/4, 293 and 75
  (368 tangents); the imposed step with the free unknowns held (the prescribed nodes moved
  alone): the first displacement increment failed after 10 cuts at load factor 1.036. The
  update cap (solvers.line_search.MAX_ROTATION) at 0.1 rad instead of 0.5, with first_turn=0.1:
  bai coarse 271 -> 260 tangents (its first displacement increment 82 -> 71 iterations), at
  0.05 313; sag coarse without first_turn 345 -> 455 (0.1) and 366 (0.05) tangents.

The first increment of the heavy stack (sag, coarse, 4 plies; ``--detail``, load 15-17):

* The plies laid at g = 0 (W'' = 0 there): the first Newton step is each ply's own linear sag,
  the same shape for every ply, turning the strip 0.57 rad (0.5 after the update cap). Its
  straight update leaves the offset (h/N) n0 between the plies unturned: after it the gaps
  are -0.157 mm at the deepest and -0.125 at the median (114 of 120 points past the ramp,
  delta = 1.5e-3 mm), correlated 0.999 with -(h/N)(1 - cos theta) of each point's turn (ratio
  0.86-1.0 away from the clamp), and each ply's chord is stretched by theta^2 / 2: element
  forces 440 N, contact forces 133 N, against the increment's weight 0.013 N. The next
  iterates: 102 / 1.1, 7.6 / 20, 66 / 115 N (deepest -0.44 mm), then back near the start
  (0.54 / 0.008 N) and the same again: the plateau of 58 iterations at ratio ~1.
* Tried and not kept (tangents in all, 345 before): the contact's tangent with W'' floored at
  0.01 k (361) and at k (the first increment failed in 8 cuts); each update corrected so that
  every ply's normal offset from its column's centroid (the nodes that started on one normal)
  keeps its first order along the column's turned director (the pressing removed: gaps
  -0.002 to +0.017 mm after the first update; the chord's stretch left: 419 tangents); with
  the curved steps let through as well (363; element forces 69 N after the first update, the
  contact's 153 N: the two corrections do not compose).
* Kept, plies-deck-of-cards' heavy stacks, ``Static(update_turn=0.03)`` (``--update-turn 0.03
  --no-stall``; the side by side in one process, one thread, CPU, load 15-17): 4 plies
  98-120-32-33-16-15 and 30 cut, 345 tangents, 5.0 s -> 104-33-24-18-15-11, none cut, 205,
  2.8 s, final positions within 3.7e-12 mm; 8 plies (default) 142-103-33-22-17-15 and 73
  cut, 409 tangents, 11.1 s -> 98-34-22-17-13-11, none cut, 195, 4.9 s, within 1.8e-9 mm.
  Other caps, 4 plies: 0.01, 0.02, 0.025, 0.04 rad: 339, 275, 213 (11 cut), 254 (51 cut)
  tangents (0.05 and 0.1 above: 366, 455). The deck (4 plies, 20 cells) at 0.03: 1514
  tangents and 904 cut (86-58-58-58-58-58-74-122) against 220: not set there.
* Kept, plies-heavy-cantilever's plies, the same cap (``--case heavy --update-turn 0.03
  --no-stall``, load 9-12): default (8 plies, 20 cells) 18-32-21-33-34-14-44-13-13-11, 233
  tangents, 7.0 s -> 18-36-23-18-20-14-13-12-11-12, 177, 4.6 s, within 1.3e-12 mm; coarse
  (4 plies, 10 cells) 17-30-36-11-30-11-14-20-9-10, 188, 2.9 s -> 17-30-18-18-18-18-13-12-
  10-10, 164, 1.7 s, within 1.1e-10 mm.
* The report's cases (``python -m validation --cases plies-heavy-cantilever,
  plies-deck-of-cards --jobs 1``, default, the code before from a ``git archive`` of fd53ee8
  beside it, warm caches, load 5-17): case_cpu_s 7.8 -> 6.2 s and 32.1 -> 25.2 s, steps 280
  -> 224 and 1977 -> 1731, 8/8 and 12/12 checks, results.json's numbers within 5e-9
  relative (the 8-ply sag's angles; the 4-ply sag's within 5e-12).

Curved steps (``--curved``; one thread, CPU, 2 cores shared; the counts are the measure):

* The deck's increments (4 plies, 20 cells, 8 increments; ``--detail``): each starts with 7
  iterations at ratio ~1: the first step turns each ply by the increment's 11 deg on its
  own (no contact stiffness at g = 0), its straight update stretches every ply (element
  forces 330 N against end moments of 0.02 N mm) and presses the plies 0.0024 mm (10 ramps)
  into each other, and the penetrations then halve at each iterate. Curved (solvers.
  newton_curvature), 12-12-12-12-12-14-36-92 and 17 cut -> 9-5-5-5-5-5-4-74, none cut
  (220 -> 112 tangents; the same counts and bits with the curved deck solved first, alone,
  or after the straight one in this process: tests/test_static_reproducible.py). An earlier
  figure here, 6-5-5-5-5-5-5-67 and 98 cut (202 tangents), was not what the code that
  introduced the curved steps gives: neither it nor the code since reproduces it in any
  order of solves.
* Kept, the decks in 4 curved increments (validation/cases/plies_deck_of_cards.py; its five
  decks, the case's ``bend`` in one process each way, load 4-6): 8 straight increments 1549
  tangents, 14.8 s; 4 straight 1711, 26.0 s (4 plies 24-24-26-128 and 184 cut); 8 curved
  956, 15.6 s; 4 curved 634, 8.5 s (4 plies 10-8-8-52, 8 plies 16-15-11-104 and 35 cut);
  within 4.9e-10 mm and 3.1e-11 of the 8 straight increments' positions and directors. The
  report's case (``python -m validation --cases plies-deck-of-cards --jobs 1``, the code
  before from a ``git archive``, back to back, warm caches, load 5.3-5.9): default 23.0 ->
  16.4 s CPU (48.4 -> 39.6 s wall), steps 1731 -> 1011 (the heavy stacks' unchanged), 12/12
  checks both, results.json's numbers within 2.1e-7 relative (the observed orders; the
  tilts within 3.1e-8); coarse 6.3 -> 5.3 s CPU, 8/8 checks both.
* Not kept: the curved steps on the other stacks (``--curved``, coarse, no stall rule, load
  6-7): bai 834 -> 1512 tangents (21-5-4-4-4-3-3-3-3-3 and 82-116-26-14-18-8-11-10-8-12 ->
  23-4-4-3-3-3-3-3-3-3 and 193-138-87-38-30-18-17-15-9-28, 470 -> 877 cut), heavy 164 ->
  318 (17-30-18-18-18-18-13-12-10-10 -> 18-27-69-97-23-23-16-16-15-14); the chords with the
  curved steps on the deck (8 increments: 276 tangents and 805 energies against 202 and
  279); the watchdog's allowance of full steps without a decrease (solvers.line_search.WATCHDOG)
  at 1 or 2 instead of 4, with the curved decks in 4 increments: 2 failed (2 plies, 20
  cells: 4-th increment after 8 cuts), 2: 960 tangents against 634. Newton at a double
  root converges linearly by halving (Decker, Keller and Kelley, SIAM J. Numer. Anal. 20
  (1983) 296): a step twice the Newton step where it was within 0.4-0.6 of the last plain
  one and within a cosine of 0.99 of its direction was taken 2 times in the deck's 220
  tangents (233 with it): its steps alternate in direction and size (points carried into
  contact and out again), they do not halve along one line.
* Not kept either (the five decks in 4 curved increments, 634 tangents; coarse bai 834 and
  heavy 164 without the curved steps): the curved steps' second derivative taken from the
  element blocks' forces alone (the contact's ramp, k / delta = 3e6 N/mm^2 per mm, left out
  of the probe at 1e-2 of the step): bai 1134 tangents, heavy 320, no better than with it;
  the heavy stack's cap with the curved steps (update_turn None, 0.1, 0.06 rad: 200, 328,
  328 tangents; 0.1 straight 229); the ply contact's tangent with the ramp's W'' times 0.5
  (the ramp's secant at a double root: one Newton step to g = 0; the 2-ply deck's last
  increment failed after 8 cuts at ratio 1e-5, the linear rate (W'' - s) / (K + s) of the
  points on the ramp that carry force) or 0.75 (82 and 216 tangents for the 4- and 8-ply
  decks against 78 and 182); a line search to the root of dPi/ds (Illinois regula falsi, 4
  probes) where a full step overshoots (dPi/ds < 0 at its start, > 0 at its end, the
  residual risen), to land the points carried into contact on the ramp: 704 and 509
  tangents for the same two decks (their first increments 111 and 113 iterations); the
  watchdog going back at once where a full step raised the residual by more than 100 or
  1000 times the best iterate's (the deck's last increment climbs out of contact 13 ramps
  deep by them): 100 failed, 1000 4964 tangents for the five decks. The watchdog's full
  steps through a residual that rises are what carry the plies past their pressing.
* Not kept: the curved steps on the imposed steps alone (the first of each displacement
  increment, whose straight form stretches the plies: ratio 0.99, element forces 30 N), coarse
  bai with the case's solver: 271 -> 628 tangents (82-19-18-18-18-8-11-10-8-12 -> 142-50-21-
  19-33-18-17-16-9-29, 8 -> 212 cut).

Increments (the cases' solvers, plies-bai-5.1's with stall 25 and first_turn 0.1; one
thread, CPU, one process each way):

* Kept, the default's plies in 10 increments a phase instead of 20 (validation/cases/
  plies_bai_5_1.py, ``PLIES_INCREMENTS``; the 20 were chosen before the first-turn rule, when
  the 10's first displacement increments took 130 and 101 iterations and 4 cuts): 464 ->
  403 tangents (gravity 22-6-5-4-4-4-4-3 x13 -> 24-7-7-5-4-3-3-3-3-3; displacement 92-30-21-
  12-19 ... -> 123-33-34-31-19-19-21-19-15-22, 2 -> 5 first-turn cuts, none else), 29.8 ->
  27.6 s (load 6-7), within 1.8e-11 mm and 2.4e-12 in the directors. The report's case
  (``python -m validation --cases plies-bai-5.1 --jobs 1``, the code before from a ``git
  archive``, back to back, load 6.2-6.5): 36.7 -> 32.9 s CPU, steps 991 -> 927, 5/5 checks
  both, results.json's numbers within 7.1e-13 relative. Not kept: 6 increments (381
  tangents, 26.9 s: its first displacement increment 152 iterations), coarse in 5 (277
  tangents against 271).
* Kept, plies-heavy-cantilever's plies in 5 increments instead of 10 (its own solver, no
  stall rule, no first turn; load 6): default 18-36-23-18-20-14-13-12-11-12, 177 tangents,
  4.3 s -> 33-42-30-20-17, 142, 3.9 s; coarse 164 -> 125, 1.5 -> 0.9 s; within 1.5e-12 mm.
  The report's case (default, back to back, three rounds, load 4.8-5.4): 5.3-5.6 -> 4.6-4.8
  s CPU, steps 224 -> 189, 8/8 checks both, results.json within 3.7e-12 relative. Not kept:
  4 increments (224 tangents), 3 (258), first_turn=0.1 with 10 (249) or 5 (232).
* Not kept: plies-deck-of-cards' heavy stacks in fewer than their 6 increments (update_turn
  0.03; load 4-5): 4 plies 205 tangents in 6, 219 in 3 (28 cut), 198 in 4 (20 cut, 2.7 ->
  2.2 s); 8 plies 195 in 6, 335 in 3, 243 in 4.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install

from benchmarks import (  # noqa: E402
    static_plies_active_set,
    static_plies_deck_start,
    static_plies_tangent_check,
)
from benchmarks.static_plies_case import (  # noqa: E402
    RECORD,
    command,
    machine_load,
    solve_case,
)
from benchmarks.static_plies_iterates import instrument, report  # noqa: E402


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The two sides' rules, the record's detail and the other scripts' switches."""
    parser.add_argument("--stall", type=int, default=25, help="stall_iterations of the new run")
    parser.add_argument(
        "--first-turn",
        type=float,
        default=None,
        help="Static(first_turn=...) of the new run, rad; the reference then keeps --stall",
    )
    parser.add_argument(
        "--update-turn",
        type=float,
        default=None,
        help="Static(update_turn=...) of the new run, rad; the reference then takes none",
    )
    parser.add_argument(
        "--no-stall", action="store_true", help="with --first-turn or --update-turn: no stall rule"
    )
    parser.add_argument(
        "--curved",
        action="store_true",
        help="the two sides without and with Static(curved_with_contact=True)",
    )
    parser.add_argument(
        "--increments", type=int, default=None, help="the deck's increments (both sides)"
    )
    parser.add_argument("--detail", action="store_true", help="every attempt, before and after")
    parser.add_argument(
        "--parts",
        action="store_true",
        help="with --detail: the residual's membrane, bending, shear and contact parts per iterate",
    )
    parser.add_argument(
        "--tangent-check",
        action="store_true",
        help="the tangent against central differences on the last increment (no timing; "
        "benchmarks/static_plies_tangent_check.py)",
    )
    parser.add_argument(
        "--deck-start",
        action="store_true",
        help="the default report's five decks without and with the case's soft start "
        "(benchmarks/static_plies_deck_start.py)",
    )
    parser.add_argument(
        "--active-set",
        action="store_true",
        help="the case's solver with the ply contact's ramp and with static_law='active_set' "
        "(benchmarks/static_plies_active_set.py)",
    )


def main() -> None:
    args = command(
        __doc__,
        add_arguments,
        static_plies_tangent_check.add_arguments,
        static_plies_active_set.add_arguments,
        rounds=True,
    )
    if args.active_set:
        static_plies_active_set.run(args)
        return
    if args.deck_start:
        static_plies_deck_start.run(args)
        return
    if args.tangent_check:
        static_plies_tangent_check.run(args)
        return
    instrument()
    RECORD["split"] = args.detail  # two more force passes an iterate, outside the counts
    RECORD["parts"] = args.detail and args.parts
    stall = None if args.no_stall else args.stall
    runs: list[tuple[int | None | str, float | None | str, float | None | str]]
    curved: list[bool | None] = [None, None]
    if args.curved:
        runs = [("case", "case", "case")] * 2  # the case's solver, straight and curved
        curved = [False, True]
    elif args.update_turn is not None:
        runs = [(stall, args.first_turn, None), (stall, args.first_turn, args.update_turn)]
    elif args.first_turn is None:
        runs = [(None, None, "case"), (args.stall, None, "case")]
    else:
        runs = [(stall, None, "case"), (stall, args.first_turn, "case")]
    results = []
    for (stall, first_turn, update_turn), bent in zip(runs * args.rounds, curved * args.rounds):
        RECORD.update(attempts=[])
        cpu = time.process_time()
        result = solve_case(
            args.case, args.resolution, stall, first_turn, update_turn, bent, args.increments
        )
        cpu = time.process_time() - cpu
        results.append(result)
        print(
            f"--- {args.case} {args.resolution}, stall_iterations={stall}, "
            f"first_turn={first_turn}, update_turn={update_turn}, curved_with_contact={bent}: "
            f"{cpu:.1f} s CPU"
        )
        if args.detail:
            report(result)
        else:
            print(f"iterations per increment {result.info['iterations_per_increment']}")
            print(
                f"converged iterations {result.steps}, cut {result.info['iterations_cut']}, "
                f"cuts {result.info['cuts']}, first-turn cuts "
                f"{len(result.info['first_turn_cuts'])}; evaluations {result.info['evaluations']}"
            )
        print(f"load (1, 5, 15 min): {machine_load()}", flush=True)
    before, after = results[:2]
    moved = np.abs(after.positions - before.positions).max()
    turned = np.abs(after.directors - before.directors).max()
    print(f"final positions within {moved:.3g} mm, directors within {turned:.3g}")


if __name__ == "__main__":
    main()
