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
a sliding stack"; ``--increments`` sets the deck's on both sides). ``--detail`` prints, per
iterate, the element blocks' and the interactions' internal-force norms and the deepest ply
gap as well, and between iterates the largest change of a point's gap; ``--tangent-check``
solves the case once and compares, on the last increment's iterates, each part's tangent
with central differences of its forces and the whole residual's directional derivative
with -K v (no timing; "The deck's linear tail" below), with ``--check-load L --every k``
on every k-th iterate of the attempt that converged at load factor L; ``--detail --parts``
adds, per iterate, the norms on the free unknowns of the plies' membrane, bending and
transverse-shear loads (each group of the Mindlin fabric section's stress resultants alone,
elements/fabric_section.py), the ply contact's and the dead load's ("The second phase's
increments" below).

    python benchmarks/static_plies_newton.py [--case bai|heavy|deck|sag]
        [--resolution coarse|default] [--stall 25] [--first-turn 0.1 [--no-stall]]
        [--update-turn 0.03 [--no-stall]] [--curved [--increments 8]] [--rounds 2]
        [--detail [--parts]] [--tangent-check [--check-load 1.8] [--every 1]]
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

The deck's linear tail (``--case deck --tangent-check``; 4 plies, 20 cells, its last
increment, 92 tangents; one thread):

* The tangent is the derivative of the forces there. Each part's own tangent against central
  differences of its forces at the iterates 0, 15, ..., 90: the four Mindlin plies within
  3.5e-10 of the largest entry (step 1e-6 of the median edge, the solver's) and 6.5e-7 (step
  1e-9, round-off); the three ply contacts within 1.7e-6 at the step 1e-9 (5e-9 mm), but
  0.4-0.65 at the step 1e-6 (5e-6 mm): their points sit within a few 1e-7 mm of g = 0, where
  W'' = -k g / delta changes by k / delta = 3e6 N/mm^2 per mm (k = 750 N/mm, delta = 2.5e-4
  mm), so a 5e-6 mm step is not small there. The whole residual (the frames re-evaluated at
  each side, as the iteration does) along a random free direction against -K v: within 3.3e-7
  (step 1e-7; 1.2e-5 at 1e-5) at the same iterates; the moments' components along the directors
  (left out of the 5-DOF equations) at most 2.4e-8 N mm. The deck is frictionless, clamped
  (no support, no tool): nothing else enters its tangent.
* The cause is the root: the exact deck needs no contact force, so its equilibrium puts
  contact points at g = 0, where the ramp's force k g^2 / (2 delta) and stiffness -k g / delta
  both vanish (a double root). There Newton halves g each iteration and quarters the
  residual: runs of ratios 1.7e-2, 4.2e-3, 1.0e-3, 2.6e-4 and 8.2e-3, 2.1e-3, 5.1e-4, 1.3e-4
  (a factor 3.9-4.1 an iteration). Each run is broken when 3-5 points off contact (g > 0, no
  stiffness, so the linear step does not see them) are carried to g = -5e-6 to -1e-5 mm in
  one step: the ratio jumps back to 1e-2 (iterations 29, 34, 36, 38, 40, 45, 50, 56, 61, 67,
  72, 77 of the increment's 92; its first 21 iterates at ratio 0.34-1.0, the 12th with
  points 0.18 mm deep); 19 of each interface's 40 points have |g| < delta, 55 of 120
  touch at the 4th iterate and 9 at the last, each carrying at most 1e-6 N. Not a tangent that
  differs from the derivative, so nothing local mends it: the law's degenerate root at
  zero-force contact (the smoothed penalty, docs/theory.md §9.3a) sets the rate.

The deck's last increment (4 plies, 20 cells, 4 curved increments, the case's solver; one
thread; ``--deck-start`` for the kept change; the trials below by patches of the code, not
kept, their counts the measure):

* Where it goes (``--detail``): 10-8-8-63 iterations. In the three increments before it no
  point touches (the plies 6e-5 to 1.9e-4 mm apart at each equilibrium). The last one's first
  (curved) step carries 54 points to -4.2e-3 mm (17 ramps, delta = 2.5e-4 mm); then 33
  iterations at ratio 0.07-1 in which 10-50 points step on or off at each iterate (the 7th
  0.4 mm deep, 1200 N of contact force), then the halving tail, restarted 5 times by points
  carried from g > 0 to -5e-6 to -1e-5 mm. Its end: 9 points touching, 3.5e-7 N in all, the
  deepest -5.3e-7 mm. The same increment with the plies' contact left out converges in 6
  iterations with the 54 points 3.3e-3 mm through the ply below: the contact is needed, and
  the plies' gap mode, their bending alone, is about 3.5e-7 N / 3.3e-3 mm ~ 1e-4 N/mm
  against the automatic penalty's 3000 N/mm a point. The equilibrium gap g* ~ -sqrt(2 delta
  F / k) is then ~5e-7 mm (as found), and the ramp's tangent is good only within K_s delta
  / k of it: Newton halves its way there from the 3.3e-3 mm the plies would pass.
* Kept: each deck increment started at 1e-3 of the penalty (``Static(ply_penalty_start=
  1e-3)``, solvers/penalty_start.py; validation/cases/plies_deck_of_cards.py
  ``DECK_PENALTY_START``): Newton converges the increment with the soft penalty, then goes on
  from there with the full one. The five decks of the default report (``--deck-start``, load
  5.3-6.5): without 1111 tangents, 17.0-18.8 s (2 plies on 10, 20, 40 cells 9-8-8-43 and 68
  cut, 8-8-6-40, 8-8-8-122; 4 plies 10-8-8-63; 8 plies 16-15-10-139 and 492 cut) -> 390,
  4.2-4.3 s (10-9-8-20, 9-9-9-22, 9-9-9-81, 11-9-9-22, 18-16-12-39 and 48 cut; of the last
  increments' iterations 13, 14, 72, 14, 30 soft), the same equilibria within 3.3e-10 mm.
  3e-4: 384 tangents, 4.9 s (the 8-ply deck's first increment 89). On the other stacks
  (coarse, without -> 1e-3, 1e-2): sag 184 -> 193, 189 tangents, heavy 125 -> 193, 141:
  their contacts carry the weight, and the second phase lifts every ply out of the soft
  penalty's deeper penetration (7-27 iterations an increment); bai coarse (the case's
  solver, load 3.7-4.5) 271 tangents -> failed at load factor 1.072 (1e-3: the stall rule
  cut the first displacement increment 10 times), 441 (1e-1); heavy default 142 -> 180
  (1e-3), 164 (1e-1). Not set there. The report's case (``python
  -m validation --cases plies-deck-of-cards --jobs 1``, the code before from a ``git
  archive``, back to back, warm caches, load 4.9-5.6): 20.5 -> 10.5 s CPU, steps 1014 ->
  796, 12/12 checks both, results.json's numbers within 1.3e-7 relative (the observed
  orders; the tilts within 1.3e-8).
* Not kept: the decks' penalty itself lowered to 3 N/mm a node (1e-3 of the automatic one,
  for the whole solve): 334 tangents, 4.1 s (9-8-8-13, 8-8-6-15, 8-8-8-72, 10-8-8-21,
  16-15-10-22 and 52 cut), but the positions moved by up to 2.5e-5 mm (0.12 delta) and the
  report's checked values by up to 1.5 % (the 2-ply tilt 0.1250 -> 0.1266 deg; the report's
  case 23.8 -> 11.4 s CPU, load 9.5). Other penalties, 4 plies (last increment; positions
  moved): 100 N/mm 31 and 26 cut (1.3e-6 mm); 10, 32 (5.1e-6); 3, 21 (9.8e-6); 1, 15
  (1.7e-5); 0.3, 12 (3e-5); 0.1, 11 (4.9e-5); 8 plies: 10, 21 and 54 cut; 1, 22 and 149
  cut; 0.3, 103-15-11-26.
* Not kept (the 4-ply deck, its last increment 63 iterations, none cut, 89 tangents):
  a contact predictor, a second factorisation of the same iterate where the Newton step
  carries points apart (not touching) past -c delta, with those points held by h k in the
  iteration matrix (the residual unchanged): c = 1, h = 1: 53 and 596 cut (1286 tangents);
  c = 1, up to three passes: 46 and 596 cut (1273); h = 0.01: 72 and 894 cut; h = 1e-3: 86
  and 1065 cut; c = 4, h = 0.01: 102 and 447 cut; c = 0, h = 1: failed at load factor 0.947
  (ratio 2e-5 after 150 iterations, 8 cuts). A held point keeps its gap where the residual
  needs it moved (the iteration's rate h k / (K_s + h k) ~ 1 in that mode).
* Not kept: the contact's acting set frozen within the increment (Newton's contact-set
  protocol, solvers/newton.py: points apart at the increment's start act only after a
  convergence, checked under the full law): 11-8-8-133 (the contact-free solve converges in
  6, its 54 points 3.3e-3 mm deep; from the increment's start with them acting, the chatter
  as before); going on from the converged state instead, with points deeper than 1-20 delta
  joining at once, 212-227 (its 6.7 N of contact force on a 1e-4 N/mm mode: the next steps
  carry points up to 2.8 mm through the plies).
* Not kept: the plain penalty (smoothing 0) with the acting set frozen and held on both sides
  while Newton iterates, updated at convergence (a primal-dual active set): 33-43-106-46 and
  17 cut (27 set updates: the plies laid at g = 0 are tied at the start, and the points of
  almost no force change side at each update), with points joining at a touch 535 cut,
  one-sided 988 cut; the plain penalty alone fails in the first increment (8 cuts). A linear
  onset of the ramp (W'' = k0 + (k - k0) min(1, -g / delta) on contact): k0 = 1e-3 k 135 and
  191 cut, 1e-2 k 53, 0.1 k failed at 0.998. The ramp 10 times wider (2.5e-3 mm): 78.
* Not kept: the automatic penalty lowered for every stack (``PENALTY_SHARE`` 0.01 and 0.001
  instead of 0.1; coarse, load 4-5): sag 184 -> 148, 137 tangents, heavy 125 -> 111, 105
  (their first increments 83 -> 60, 55 and 29 -> 21, 18), but the equilibria moved 2.7e-3,
  1.2e-2 mm and 8.6e-3, 4.4e-2 mm: those stacks carry their weight through the contact, and
  a softer penalty lets them sink into each other by more than the ramp (1.5e-3 mm).

Where the first increments go (``--detail``, coarse; the cases' solvers; one thread, load
3-13; the trials below by patches of the code, not kept, their counts the measure):

* bai's first displacement increment, 82 iterations: the first-turn rule leaves the sub-
  increments 1/16, 1/8, 1/4, 1/4, 5/16 of it (29, 21, 16, 8, 8 iterations). Each opens with a
  plateau at ratio 0.4-1.0 (18, 11, 7, 3, 3 iterations, shorter as the stack leaves its sagged
  start): the imposed step's straight update stretches the turning plies (element forces 1.8
  -> 51 N), 75 points enter the ply below, and the steps that relieve the stretch carry
  points apart (no stiffness between them) through it: 20-75 points step on or off at each
  iterate, points up to 0.093-0.36 mm deep (60-240 ramps) at the 5th-8th iterates, with up
  to 150 N of contact force. Then a quadratic tail from about 1e-2, broken where points step on or
  off. It ends with 50-59 of the 144 points touching, 0.014-0.033 N of contact force against
  0.3 N of the plies' own. Default (8 plies, 30 cells, 123 = 37 + 23 + 26 + 18 + 19
  iterations in the same sub-increments): plateaus of 20, 13, 14, 4, 4 iterations, the
  imposed step taking the touching points from 42 to 536, gap changes up to 0.64 mm; the
  tails, 17-21 iterations in the first three, run while the touching points fall (499 ->
  336 in the first) linearly (the ratio 1.5e-3, 5.1e-4, 1.8e-4, 9.6e-5: 2-3 times down an
  iteration), as the heavy stacks' tails below.
* sag's first increment (4 plies), 83 iterations: its first 37 alternate a step the update
  cap (0.03 rad) shortens to 0.05-0.57 and a whole step, the element forces 2 N after the
  first (each straight update stretches the plies) and 0.01-0.7 N after the second (which
  undoes the stretch), the ratio ~1 throughout: the increment's sag of 0.57 rad, 0.03 rad a
  pair. Then 46 iterations in which the touching points fall from 106 to 12 (2-26 leave at an
  iterate) with the ramp's rate at a double root (the ratio a factor ~4 down an iteration),
  restarted twice (the ratio back to 1.0 and 0.99) by a point carried from g > 0 into the
  ply below. At the end 12 of the 120 points touch: equal plies under their own weight sag
  alike and need almost no contact force, the deck's double root (above). The heavy
  cantilever's first increment (4 plies, 29 iterations) is the same: 10 iterations at ratio
  ~1 with the element forces alternating 0.2-2.3 N and 0.002-0.08 N (the cap shortened two
  of its steps), then 60 -> 3 points touching, restarted by gap changes of 0.072 and 0.037
  mm.
* So two causes, neither in the contact's tangent (exact): straight updates of turning plies
  (the plateaus and the zig-zag; what cures them on one ply, the curved step, fails with the
  contact, above) and the smoothed ramp's double root at zero-force contact (the tails).
* Not kept: a trust region on the gap change, each step (the imposed ones too) shortened so
  that no point ends deeper than max(C delta, its depth before), its gap interpolated
  linearly along the step, the share at least 1/16: C = 10, bai coarse 271 -> 258 tangents
  (82 -> 73 in the first displacement increment; 12 of 253 steps shortened, by 0.49 at the
  median), default 403 -> 392 (123 -> 112; 27.3 -> 24.4 s, load 6-9), sag and heavy coarse
  unchanged (no step shortened); C = 3, bai coarse 277 (62 in the first displacement
  increment, 13-26 in later ones); C = 1, bai coarse failed at load factor 1.74 (at 1.29
  with the share down to 1/100), sag 171 (70 in the first); C = 2, sag 175. The same
  equilibria within 1.7e-10 mm; 3-7 % where it helps at all.
* Not kept: pseudo-transient continuation, each increment first converged with the viscous
  stabilisation (``Static(stabilise=c)``, solvers/stabilisation.py), then without it from
  there: bai coarse c = 1e5 (the damped phases 2-25 iterations, the plain ones from there
  fail as from the start: the first displacement increment failed after 10 cuts at load
  factor 1.028), 1e4 and 1e3 failed at 1.0086 and 1.0074, 1e2 14-27 plain iterations after
  4-28 damped in each sub-increment, 1: the damped phase is the plain one (21, 21, 15, ...)
  and 3-6 plain ones follow. No c lies between dashpots that change nothing and dashpots
  whose equilibrium is as far from the plain one as the increment's start.
* Not kept: a contact predictor on bai coarse, the step solved again with the penalty k
  along the gap gradient of the points it carried from above -delta to below -C delta: C = 1
  887 tangents (447 cut, 676 second solves), 5 402 (196 in the first displacement
  increment), 20 318, against 271.
* Not kept: the ramp's secant W'/g = W''/2 in the tangent of the points that unload (on the
  ramp, the gap grown since the last iterate), the exact W'' elsewhere: sag 184 -> 225
  tangents (77-38-32-26-19-24 and 8 cut); only where the last residual ratio was below 0.1
  or 0.01 (the tails): 229 and 226.
* Not kept (sag, 184 tangents, 83-33-24-18-15-11): a chord K^-1 r with the step's own
  factors after each step the update cap shortened, kept where the residual falls (the
  zig-zag's second step without its tangent): 1201 tangents (235-227-92-100-18-17 and 508
  cut); the curved steps (``curved_with_contact``) with the case's cap 349, without a cap
  425 (99 cut), with 0.1 rad 531; ``first_turn`` 0.03, 0.06, 0.1 rad: 502, 402, 317
  (131-66-46-25-23-11); the fibre-length projection (solvers/newton_fibres.py) let through
  with the contact: 1782 tangents and 906 cut (heavy coarse: failed at load factor 0.49).
* Not tried: an augmented Lagrangian on the ply penalty (elements/augmented_contact.py's way):
  its use would be a softer penalty in the inner solves, and those are bounded by the
  stacks solved with the penalty itself lowered 10 and 100 times (above: the sag's and the
  heavy cantilever's tangents 20-25 % fewer, their first increments 83 -> 55-60 and 29 ->
  18-21), before the Uzawa passes' own iterations; at zero-force contact (the tails) its
  multipliers go to 0 and the double root stays.
* Not kept: the watchdog's allowance (solvers.line_search.WATCHDOG) at 1, 2, 8 instead of 4: bai
  coarse 249, 261, 286 tangents against 271 (82 -> 75, 76, 67 in the first displacement
  increment), but sag 397, 201 and heavy 382, 134 against 184 and 125; bai coarse's
  ``update_turn`` 0.03 and 0.1 rad: 289 (67 in the first displacement increment, 11-28 in
  later ones) and 260 (71).

The second phase's increments (plies-bai-5.1, the case's solver: ``--first-turn 0.1 --detail
--parts``, its second run's figures, and ``--first-turn 0.1 --tangent-check --check-load 1.8``;
``--resolution default`` for the default stack; ``--detail --parts`` alone runs the solver
without the first-turn rule: coarse 975 and 403 tangents; one thread, CPU, load 0.5-2.8; the
trials by patches of the code, not kept, their counts the measure):

* The counts: coarse (4 plies, 12 cells) 21-5-4-4-4-3-3-3-3-3 and 82-19-18-18-18-8-11-10-8-12,
  257 iterations and 8 cut, 271 tangents, 1.4 s; default (8 plies, 30 cells)
  24-7-7-5-4-3-3-3-3-3 and 123-33-34-31-19-19-21-19-15-22, 398 and none cut, 403 tangents, 9.6 s
  (24 ms an iteration). After the first displacement increment every step is whole (scale 1, one
  force pass an iteration), no facing triangle switches and no point enters the fade past the
  outline: the line search and the facing play no part.
* Each increment opens with the imposed step. Coarse, load 1.8 (10 iterations): the straight
  update of the turning plies stretches their fibres, the membrane part of the residual 0.06 ->
  23 N (bending 0.03 and transverse shear 0.06 N unchanged, the ply contact 0.05 -> 1.3 N), 23
  points pushed deeper than the ramp (delta = 1.5e-3 mm), 5 new ones touching; the next iterate
  takes the membrane back to 0.39 N and the 27 points onto the ramp; two more at ratio ~0.5,
  then 1.5e-2 and a quadratic tail, broken once by a point leaving (6.1e-2). Default, load 1.8
  (19 iterations): membrane 0.037 -> 11 N, contact 0.048 -> 1.3 N, 152 points past the ramp and
  27 new ones touching; the membrane, bending and shear parts are at their final values (two
  digits) from the 5th iterate, and the 14 iterations after it are the ply contact's alone: 31
  points cross g = 0 (touching 230 -> 197, most leaving), the ratio restarted to 0.12-0.27 three
  times and falling about 4 times an iteration between (the ramp's rate at zero-force contact,
  "The deck's linear tail" above). Over the 17 (default; coarse 18) converged attempts of the
second phase, counted by hand from ``--detail --parts`` (an iteration the contact's alone once the
element parts no longer change in their first two digits; the first displacement increment's
iterations in the counts),
  iterations after the element parts settled: default 208 of 336, with 740 changes of a point's
  touching in them; coarse 83 of 204 (mostly the quadratic tail), 41 changes. So two costs: the
  imposed step's stretch (3-4 iterations an increment at both resolutions) and, at the default,
  the contact's zero-force points settling one by one (5-17 iterations an increment).
* The tangent is the forces' derivative at every iterate. Coarse, load 1.8, all 10 iterates: the
  Mindlin plies within 3.6e-10 of the largest entry (central differences, 1e-6 of the median
  edge), the three ply contacts within 2.0e-8, the whole residual along a random free direction
  within 5.9e-9 (step 1e-5); default, load 1.8, iterates 0, 3, ..., 18: the plies 3.5e-10, the
  contacts 4.2e-8 but one at the 6th iterate 4.3e-4 (7.9e-7 at the step 1e-9: a point within the
  step of an end of the ramp, where the law's third derivative jumps by k / delta), the whole
  residual 1.3e-8. No term is missing where points step on or off (none changes its facing
  triangle).
* Not kept: ``predictor=True`` (the last increment extrapolated): coarse 271 -> 399 tangents
  (102-28-39-21-17-15-10-14-30-10, 56 cut), default 403 -> 595 (155-49-35-23-26-16-28-22-27-18,
  130 cut); the ramp's secant W'/g = W''/2 in the tangent of the points whose gap grew since the
  block's last tangent (a leaving point's Newton step halves g on the ramp; the secant takes it
  to 0): coarse 482 tangents (121-38-39-38-42-27-18-21-18-27); on every point on the ramp:
  failed at load factor 1.0002 (10 cuts); the fibre-length projection (solvers/newton_fibres.py)
  on the imposed steps alone: coarse 1037 tangents and 392 cut; the step doubled where the last
  two halve along one line (a double root, Decker, Keller and Kelley above; the step within
  0.4-0.6 of the last and at a cosine above 0.99, the ratio below 0.1): taken once on coarse, 3
  times on default, 272 and 401 tangents; ``Static(tol=1e-6)`` instead of 1e-8: coarse 253
  tangents, within 2.9e-8 mm, default 380, within 1.2e-8 mm: the contact-only iterations run at
  ratios 1e-3 to 0.3, above any tolerance; the ramp wider (``elements.ply_contact.SMOOTHING``
  2e-3 and 5e-3 of the faces' half thicknesses instead of 1e-3), default: 353 and 407 tangents
  (96-32-38-25-17-14-18-19-15-17; 127-29-35-25-16-12-17-18-9-17 and 50 cut), but the equilibrium
  moved by 6.8e-3 and 2.4e-2 mm (the plies pressed deeper by the ramp).
* What would cut them (not done): the zero-force points are weakly active (g ~ 0 and W'(g) ~ 0
  at the solution), where the ramp's W'' vanishes and the tangent cannot see a point step on or
  off. A semismooth Newton on the normal contact with a multiplier per point (the augmented
  Lagrangian of Alart and Curnier, CMAME 92 (1991) 353, in its Newton form, the active set set
  by lambda + c g at every iteration, not at convergence as the primal-dual set tried on the
  deck above) converges superlinearly without strict complementarity (Hintermueller, Ito and
  Kunisch, SIAM J. Optim. 13 (2002) 865): the 5-17 contact-only iterations of a default
  increment would become the 2-3 of a quadratic tail (a guess, not derived: the target is the
  default's 403 tangents; docs/theory.md §9.3a says what the method would take; built with
  the multipliers condensed, it takes more: "The ply contact's normal law under Static"). The
  imposed step's stretch would need a step that turns the plies without stretching them; the
  curved imposed step (above, 271 -> 628 tangents) and its fibre-length projection
  (1037) do worse.

The ply contact's normal law under Static (``--active-set``: the case's solver with the ramp
and with ``PlyContact(static_law="active_set")``, the primal-dual active set of a bilateral
penalty frozen within each iteration, elements/ply_active_set.py, its set predicted on each
step's linear model, solvers/contact_sets.py; the two alternately in one process, ``--rounds
2``; docs/theory.md §9.3a, "An active set under Static"):

* bai, coarse (load 2.1-2.4): ramp 271 tangents (21-5-4-4-4-3-3-3-3-3 and
  82-19-18-18-18-8-11-10-8-12, 257 converged and 8 cut iterations), 2.0 and 1.2 s CPU (the
  first pass compiling); active set 245 tangents (14-4-4-4-4-3-3-3-3-3 and
  52-14-14-13-12-8-8-9-8-8, 191 and 50 cut, 2 cuts), 3.1 and 3.1 s. The material lines of the
  two equilibria: tilt within 0.024 deg, thickness within 5.5e-3 mm, mid-point within 2.9e-3 mm
  (nodes 4.9e-3 mm; delta 1.5e-3 mm).
* bai, default (load 2.4-3.0): ramp 403 tangents (24-7-7-5-4-3-3-3-3-3 and
  123-33-34-31-19-19-21-19-15-22, no cut), 10.3 and 9.3 s; active set 345 tangents
  (27-12-4-4-4-3-3-3-3-3 and 64-16-14-13-8-8-9-8-8-9, 223 and 125 cut in 5 stalls of the first
  displacement increment), 24.2 and 24.9 s; tilt within 0.030 deg, thickness 7.7e-3 mm,
  mid-point 4.8e-3 mm (nodes 7.2e-3 mm; delta 7.5e-4 mm). ``contact_sets.MAX_SWITCHED`` and
  ``REFACTOR_AT`` (one-off runs, load 2): 64 and 16, 405 tangents, 19.6 s; 200 and 48 (kept),
  345, 22.7 s; 1000 and 16, 322, 61.9 s. Tried and not kept (one-off runs): the ramp's law
  for the iterations at which more than 0.2 of the points change sets (the plateau's), 345
  tangents and the same stalls (coarse 247); ``stall_iterations=50`` on the coarse stack, its
  two stalls running to 50 (295 tangents).
* Without the prediction (``solvers.contact_sets.PREDICTED = False``, the set chosen between
  iterations alone, and with the unilateral attempt after a failed one; load 1.7-3.8): coarse
  480 tangents (30-4-4-4-4-3-3-3-3-3 and 120-51-18-13-13-13-8-12-8-44, 361 and 112 cut),
  2.9-3.3 s; default 684 (49-30-13-4-4-3-3-3-3-3 and 201-50-39-30-14-18-19-40-39-15, 580 and
  100 cut), 19.6-20.9 s. With the rule g_{k+1} < 0 alone (``ply_active_set.HYSTERESIS =
  False``): coarse 562 tangents. With the rule's c (the gap's weight against the multiplier's,
  k above; one-off runs with the block's freeze patched) 0.01, 0.1 and 10 k: 607, 574 and 427
  tangents; the sag below at 2, 4, 8 plies 31-35-42, 32-32-75, 22-25-33.
* bai at 20 plies (``--plies 20``, 30 cells; one pass each, side by side in two processes,
  load 1-3.4): the ramp converges, 755 tangents (40-7-7-8-4-3-3-3-3-3 and
  187-49-68-29-27-50-34-34-14-52, 625 and 125 cut, 5 cuts), 123 s CPU; the active set without
  the prediction 2010 tangents (65-34-22-4-4-3-3-3-3-3 and 275-66-92-118-42-96-50-26-57-74,
  1040 and 959 cut, 21 cuts), 324 s; with it 527 tangents (66-12-4-4-4-3-3-3-3-3 and
  84-17-16-14-13-10-8-10-12-16, 305 and 225 cut, 9 cuts), 239 s (beside other jobs, load 2-3).
* The prediction made cheaper and each phase opened on the ramp (the columns solved
  together, the rows dense by point, the bilateral loads compiled; ``ActiveSetPlyContactBlock.
  opening_law = "ramp"``; docs/theory.md §9.3a, "The predicted set made cheaper"), the
  default (load 3.7-4.6): ramp 403 tangents, 11.2 and 10.1 s; active set 327 tangents
  (24-13-4-4-4-3-3-3-3-3 and 117-17-14-13-8-8-9-8-8-9, 275 and 50 cut), 10.9 and 10.7 s; the
  same equilibrium as without the opening (nodes within 5e-14 mm), material lines within
  0.030 deg, 7.7e-3 mm and 4.8e-3 mm of the ramp's. The displacement phase alone opened on
  the ramp: 350 tangents, 13.3-13.6 s; neither opened but the prediction cheaper: 345, 15.9 s
  (one-off). Coarse (load 4.4-4.5, 3 rounds): ramp 271 tangents, 1.2-1.4 s (2.6 the first,
  compiling); active set 264 (21-5-4-4-4-3-3-3-3-3 and 86-15-14-13-12-8-8-9-8-8, 234 and 25
  cut), 1.6-1.8 s. ``--unopened``: the active set without the opening.
* The plain penalty without a set (``elements.ply_contact.SMOOTHING = 0``, the ramp's solve
  otherwise), bai coarse: 359 tangents (47-4-4-4-4-3-3-3-3-3 and 91-25-18-13-12-12-9-12-12-19,
  5 cuts), 2.5 s.
* The heavy stack of tests/test_plies.py (``Static(increments=1)``, 10 x 1 cells; its model
  is tests/test_ply_active_set.py's ``_sag_model``, not a case of this script): ramp 23,
  23, 26 Newton iterations at 2, 4, 8 plies; the active set predicted 6, 7, 9 (7, 10, 10
  since no set is predicted on a step turned downhill; without the prediction 27, 29, 34),
  the equilibrium within 5.9e-7, 7.4e-7, 7.9e-7 mm. Without the
  prediction every set change flips 1-7 points whose gaps are 1e-10 to 1e-6 mm off, and their
  force k g restarts the ratio at 0.1-0.5 (docs/theory.md §9.3a).
* heavy (plies-heavy-cantilever's plies, its solver: 5 increments, update_turn 0.03, one gravity
  phase whose first increment opens on the ramp; ``--case heavy --active-set --rounds 3``, which
  prints also the change of what the case compares; load 4.1-5.3): default (8 plies, 20 cells)
  ramp 142 tangents (33-42-30-20-17), best 1.37 s (3.61 the first, compiling); active set 130
  (33-40-24-18-15), best 1.80 s (1.81, 1.80, 1.87); ``--unopened`` 108 (21-30-24-18-15), best
  1.66 s against the ramp's 1.24 in the same run. Coarse (4 plies, 10 cells) ramp 125
  (29-33-29-19-15), best 0.43 s; active set 115 (29-30-24-18-14), 0.50 s; unopened 103
  (17-30-24-18-14), 0.44 s against 0.39. No cut either way. The active set does not win: the
  increments after the first save 2-6 iterations each (the one-increment sags above 13-19), and
  each of its iterations costs more (profiled, default: ``predicted_sets`` 0.54 of 2.37 s, 97
  predictions at ~5.6 ms; the ramp 1.78 s, under the profiler). Where the iterations go
  (``--detail``'s record of the active set's solve, a scratch script): in the last three
  increments the set hardly changes (0-3 points an iterate, 14-26 touching; in the second up to
  91 over 12 of its 40 iterations), and 8-22 of each later increment's 15-40 iterations are the
  zig-zag of the sag's first increment (below): a step the update cap shortens to 0.1-0.6, the
  plies' element forces ~1.3 N after it, then a whole step that undoes the stretch (0.003-0.05
  N), the ratio ~1 throughout; then a quadratic tail of 3-5. The turning stack's straight
  updates set the count, not the contact. The equilibria: nodes within 2.2e-3 mm (default) and
  3.6e-3 mm (coarse); of what the case compares, the plies' director angle along the path within
  0.014 and 0.0043 deg (first 80 %; tolerances 8 and 9.5), its mean within 0.0079 and 0.0026 deg
  (3.7, 5), the mid-surface height within 7.0e-4 and 1.2e-3 mm (0.8, 1), the thickness within
  2.0e-4 and 2.2e-4 h (0.22, 0.25), the tip deflection by -2.0e-5 and +3.4e-5 relative (1.5 %).
  One-off runs of other solvers for the stack (a scratch script, default unless said, load 4-5):
  in 2 increments ramp 185 tangents, 1.83 s, active set 156, 1.79 s; in 1, 335 (149 cut), 3.6 s
  against 417 (298 cut), 20.4 s; coarse without update_turn 277 tangents, 3.9 s against 881 (745
  cut), 5.4 s. The case keeps the ramp.

The linear solves of the bai stack (the ramp, the case's solver; timers around the calls,
one thread, CPU, load 5.9-6.7; docs/theory.md §6.5, "Plans kept over changing contact pairs"):
the linear solver's factorisations 3.9 of 10.7-11.9 s on the default stack, all on band plans
(302 of the 403 at a new pattern, 18 orderings); judged at a measurement of the plies
pressed, the band is kept as they hang apart (6.6 ms a factorisation against a fresh
supernodal one's 1.2 ms) and pressed again (5.5-5.9 against 4.1-5.0 ms). Measuring such
patterns anew (solvers/linear.py ``REORDER_SHRINK`` 0.75, benchmarks/measured_shrink.py, the
two rules alternately in one process, best of 2-3, load 4.6-5.8): default 10.04 -> 9.54 s,
coarse 1.30 -> 1.27 s, the same 403 and 271 tangents, within 5e-14 mm; the heavy stack 1.56 ->
1.62 s and the deck 2.49 -> 3.66 s (its path moved by round-off): not kept.
"""

from __future__ import annotations

import argparse
import functools
import os
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

import solvers.line_search as line_search  # noqa: E402
import solvers.newton as newton_module  # noqa: E402
import solvers.penalty_start as penalty_start_module  # noqa: E402
import solvers.static as static_module  # noqa: E402
from elements.ply_block import PlyContactBlock  # noqa: E402
from solvers import Static  # noqa: E402

RECORD: dict = {}


def _ply_states(run, state):
    """Per ply-contact block: (touching, on the ramp, faded, triangle, gap) at ``state``."""
    out = []
    for block in run.model.interactions:
        if not isinstance(block, PlyContactBlock):
            continue
        facing = block.facing(state)
        gap = np.asarray(facing.gap)
        touching = np.asarray(facing.touching)
        ramp = touching & (gap > -block.smoothing)
        fade = np.ones_like(gap) if facing.fade is None else np.asarray(facing.fade)
        out.append((touching.copy(), ramp, touching & (fade < 1.0), facing.triangle.copy(), gap))
    return out


def _changes(before, after) -> dict:
    """Counts of the points whose contact state changed between two iterates, and the
    largest change of a point's gap (mm, ``gap_change``)."""
    keys = ("in", "out", "ramp_in", "ramp_out", "fade_changed", "triangle", "sign")
    total: dict = dict.fromkeys(keys, 0)
    total["gap_change"] = 0.0
    for (t0, r0, f0, tri0, g0), (t1, r1, f1, tri1, g1) in zip(before, after):
        if g0.shape == g1.shape and g0.size:
            total["gap_change"] = max(total["gap_change"], float(np.abs(g1 - g0).max()))
        total["in"] += int(np.sum(~t0 & t1))
        total["out"] += int(np.sum(t0 & ~t1))
        total["ramp_in"] += int(np.sum(~r0 & r1))
        total["ramp_out"] += int(np.sum(r0 & ~r1))
        total["fade_changed"] += int(np.sum(f0 != f1))
        total["triangle"] += int(np.sum(tri0 != tri1))
        total["sign"] += int(np.sum((np.sign(g0) != np.sign(g1)) & (np.abs(g0 - g1) > 1e-3)))
    return total


def _split(model, state, plies) -> dict:
    """The internal forces' norms at ``state``, N: the element blocks' and the interactions'
    (their sum against the dead load is the residual), and the deepest ply gap, mm."""
    blocks = list(range(len(model.blocks)))
    others = list(range(len(model.blocks), len(model.parts)))
    elements = np.linalg.norm(model.internal_force(state, blocks)[0])
    contacts = np.linalg.norm(model.internal_force(state, others)[0]) if others else 0.0
    deepest = min((float(p[4].min()) for p in plies if len(p[4])), default=0.0)
    return {"elements": float(elements), "contacts": float(contacts), "deepest": deepest}


# The section measures of the Mindlin fabric section (elements/fabric_section.py): membrane
# strains y[0:3], bending strains y[3:6], transverse shear's tying changes y[6:10].
SECTION_PARTS = {"membrane": slice(0, 3), "bending": slice(3, 6), "shear": slice(6, 10)}


def _residual_parts(run, state, frames) -> dict:
    """The residual's parts at ``state`` on the free unknowns (N, the generalised moments over
    the median element edge, as the convergence test counts them): the plies' membrane,
    bending and transverse-shear loads (each the section's stress resultants dW/dy of that
    group alone carried by the element's B), the ply contact's, and the dead load's."""
    from elements.fabric_section import response
    from elements.mindlin_fabric import MindlinFabricBlock
    from elements.mindlin_fabric_loads import fabric_cell_loads
    from elements.mindlin_tables import _TYING_N

    model = run.model
    dofs, size = model.dofs, model.element_size
    out: dict = {}

    def norm(force, moment) -> float:
        r = dofs.generalised(frames, force, moment)
        r = np.where(dofs.free, r, 0.0)
        r[:, 3:] /= size
        return float(np.linalg.norm(r))

    totals = {
        key: [np.zeros((model.n_nodes, 3)), np.zeros((model.n_nodes, 3))] for key in SECTION_PARTS
    }
    for block in model.blocks:
        if not isinstance(block, MindlinFabricBlock):
            continue
        x = state.positions[block.connectivity]
        v = state.directors[block.connectivity]
        gradient = response(block.section, block._measures(x, v), hessian=False).gradient
        for key, part in SECTION_PARTS.items():
            masked = np.zeros_like(gradient)
            masked[:, part] = gradient[:, part]
            force, moment = fabric_cell_loads(
                x, v, block.zeta, block.h, _TYING_N, masked, block._products()[0]
            )
            totals[key][0] += block.scatter.vectors(force)
            totals[key][1] += block.scatter.vectors(moment)
    for key, (force, moment) in totals.items():
        out[key] = norm(force, moment)
    others = list(range(len(model.blocks), len(model.parts)))
    if others:
        out["contact"] = norm(*model.internal_force(state, others))
    force, moment, _ = run.solver.loads(model, state.load_factor)
    out["load"] = norm(force, moment)
    return out


def instrument() -> None:
    """Wrap the solver's pieces to record (module docstring); RECORD holds the attempts."""
    RECORD.update(attempts=[], iterations=[])
    plain_newton = penalty_start_module.newton

    def newton(run, state, load_factor, max_iterations=None, turn_limit=None):
        entry = {"load": load_factor, "iterations": [], "failed": None, "cpu": time.process_time()}
        RECORD["attempts"].append(entry)
        RECORD["current"] = entry
        RECORD["last_ply"] = None
        try:
            out = plain_newton(run, state, load_factor, max_iterations, turn_limit)
        except newton_module.IncrementFailed as failure:
            entry["failed"] = str(failure)
            entry["history"] = failure.history
            entry["cpu"] = time.process_time() - entry["cpu"]
            raise
        entry["history"] = out[3]
        entry["cpu"] = time.process_time() - entry["cpu"]
        return out

    penalty_start_module.newton = newton

    plain_tangent = static_module.StaticRun.tangent

    def tangent(self, state, frames, compression_free=False):
        plies = _ply_states(self, state)
        touching = sum(int(p[0].sum()) for p in plies)
        ramp = sum(int(p[1].sum()) for p in plies)
        faded = sum(int(p[2].sum()) for p in plies)
        row = {"touching": touching, "ramp": ramp, "faded": faded, "scale": None, "trials": 0}
        if RECORD.get("split"):
            row.update(_split(self.model, state, plies))
        if RECORD.get("parts"):
            row["parts"] = _residual_parts(self, state, frames)
        if RECORD.get("last_ply") is not None:
            row.update(_changes(RECORD["last_ply"], plies))
        RECORD["last_ply"] = plies
        RECORD["current"]["iterations"].append(row)
        return plain_tangent(self, state, frames, compression_free)

    static_module.StaticRun.tangent = tangent

    plain_step = line_search.Watchdog.step

    def step(self, *args, **kwargs):
        before = self.run.counts["residual"]
        energies = self.run.counts["energy"]
        out = plain_step(self, *args, **kwargs)
        rows = RECORD["current"]["iterations"]
        if rows:
            rows[-1]["scale"] = out[0]
            rows[-1]["trials"] = self.run.counts["residual"] - before
            rows[-1]["energies"] = self.run.counts["energy"] - energies
        return out

    line_search.Watchdog.step = step


def solve_case(
    name: str,
    resolution: str,
    stall: int | None | str = "case",
    first_turn: float | None | str = "case",
    update_turn: float | None | str = "case",
    curved: bool | None = None,
    increments: int | None = None,
    static_law: str = "ramp",
    plies: int | None = None,
):
    """Solve the Static plies of case ``name`` at ``resolution`` with
    ``Static(stall_iterations=stall, first_turn=first_turn, update_turn=update_turn,
    curved_with_contact=curved)`` (each ``"case"`` by default, and ``curved`` None: the
    case's own, the run the report makes; None for stall, first_turn or update_turn: the rule
    off; bai sets stall 25 and first_turn 0.1, heavy neither, neither sets update_turn, the
    deck curves its steps) and, for the deck, ``increments`` (None: the case's); the
    result."""
    if name in ("bai", "heavy"):
        from fibreshell.plies import plies_solver, ply_stack, stack_model
        from validation.cases import plies_bai_5_1, plies_heavy_cantilever
        from validation.ground_truth import _case

        case_module: Any = plies_bai_5_1 if name == "bai" else plies_heavy_cantilever
        solver = dict(case_module.PLIES_SOLVER)
        if name == "bai":
            solver["increments"] = case_module.PLIES_INCREMENTS[resolution]
        for key, value in (
            ("stall_iterations", stall),
            ("first_turn", first_turn),
            ("update_turn", update_turn),
        ):
            if value != "case":
                solver[key] = value
        if curved is not None:
            solver["curved_with_contact"] = curved
        for key in ("stall_iterations", "first_turn", "update_turn"):
            if solver.get(key, 0) is None:
                del solver[key]
        case = _case(case_module.FILE, case_module.CELLS[resolution], {"solver": solver})
        count = case_module.PLIES[resolution] if plies is None else plies
        stack = ply_stack(case, count, static_law=static_law)
        RECORD["stack"], RECORD["case"] = stack, case  # the material lines of ``--active-set``
        model = stack_model(case, stack).compile()
        return plies_solver(case, progress=False).solve(model)
    from validation.cases import plies_deck_of_cards as deck

    options = {
        key: value
        for key, value in (
            ("stall_iterations", stall),
            ("first_turn", first_turn),
            ("update_turn", update_turn),
        )
        if value != "case"
    }
    deck.Static = functools.partial(Static, **options)  # type: ignore[attr-defined]
    if update_turn != "case":
        deck.SAG_UPDATE_TURN = update_turn  # type: ignore[assignment]
    if curved is not None:
        deck.DECK_CURVED = curved
    if increments is not None:
        deck.DECK_INCREMENTS = increments
    if name == "deck":
        return deck.bend(deck.COUNTS[resolution][-1], deck.MIDDLE).result
    if name == "sag":
        return deck.sag(deck.SAG_COUNTS[resolution][0]).result
    raise ValueError(f"case {name!r}: expected bai, heavy, deck or sag")


def tangent_check(name: str, resolution: str, every: int = 15, load: float | None = None) -> None:
    """The tangent against central differences on the last increment's iterates of case
    ``name`` (or, with ``load``, those of the converged attempt at that load factor; module
    docstring, "The deck's linear tail" and "The second phase's increments"): per part, the
    largest difference between its own tangent and central differences of its forces (the
    solver's step, 1e-6 of the median element edge, and 1e-9), over the largest entry; per
    ply contact, its points with |g| < delta, those touching, its force; and the whole
    residual's directional derivative (the frames re-evaluated at each side, as the Newton
    iteration does) along a random unit direction against -K v."""
    from femcore.assembly import finite_difference_tangent
    from solvers.newton import Residual

    captured: list = []
    plain = static_module.StaticRun.tangent

    def keep(self, state, frames, compression_free=False):
        captured.append((self, state, frames))
        return plain(self, state, frames, compression_free)

    static_module.StaticRun.tangent = keep  # type: ignore[method-assign]
    try:
        solve_case(name, resolution)  # the case's own solver
    finally:
        static_module.StaticRun.tangent = plain  # type: ignore[method-assign]
    if load is None:
        load = captured[-1][1].load_factor
    at = [abs(entry[1].load_factor - load) < 1e-9 for entry in captured]
    if not any(at):
        raise ValueError(f"no increment at load factor {load}: expected one the solve reached")
    end = len(at) - at[::-1].index(True)  # the last attempt at that load: the converged one
    start = end
    while start > 0 and at[start - 1]:  # the trailing run of tangents at that load
        start -= 1
    last = captured[start:end]
    run = last[0][0]
    model, dofs = run.model, run.model.dofs
    free = dofs.free_slots
    equilibrium = Residual(model, *run.solver.loads(model, last[0][1].load_factor))
    direction = np.zeros(dofs.n_slots)  # free slots alone: the fixed ones stay where they are
    direction[free] = np.random.default_rng(0).standard_normal(free.size)
    direction /= np.linalg.norm(direction)
    print(f"last increment: {len(last)} tangents")
    for n in range(0, len(last), every):
        _, state, frames = last[n]
        print(f"iterate {n}")
        for index, part in enumerate(model.parts):
            own = model.stiffness(state, "element", frames, [index])[free][:, free].toarray()
            graph = model.node_graph([index])
            line = f"  {index} {type(part).__name__}:"
            for relative in (1e-6, 1e-9):
                central = finite_difference_tangent(
                    dofs,
                    functools.partial(model.internal_force, parts=[index]),
                    state,
                    graph,
                    step=relative * model.element_size,
                    frames=frames,
                )[free][:, free].toarray()
                scale = max(np.abs(central).max(), 1e-300)
                line += (
                    f" |K - K_cd({relative:g})| / max|K| {np.abs(own - central).max() / scale:.1e}"
                )
            if isinstance(part, PlyContactBlock):
                gap = np.asarray(part.facing(state).gap)
                force = np.linalg.norm(model.internal_force(state, [index])[0])
                line += (
                    f"; |g| < delta {int(np.sum(np.abs(gap) < part.smoothing))}, touching "
                    f"{int(np.sum(gap < 0.0))} of {gap.size}, |F| {force:.1e} N"
                )
            print(line)
        stiffness = model.stiffness(state, "element", frames)[free][:, free]
        step = np.zeros((model.n_nodes, 5))
        for h in (1e-5, 1e-7):
            sides = []
            for sign in (1.0, -1.0):
                step.ravel()[:] = sign * h * direction
                moved = dofs.advance(state, step, frames)
                r = equilibrium.residual(moved, dofs.frames(moved.directors))[0]
                sides.append(r.ravel()[free])
            derivative = (sides[0] - sides[1]) / (2.0 * h)
            predicted = -(stiffness @ direction[free])
            error = np.linalg.norm(derivative - predicted) / np.linalg.norm(predicted)
            print(
                f"  residual along a random direction, step {h:g}: |dR + K v| / |K v| {error:.1e}"
            )


def deck_starts() -> None:
    """The five decks of the default report (validation/cases/plies_deck_of_cards.py,
    ``bend``) without a soft start (the reference pass) and with the case's
    ``Static(ply_penalty_start=DECK_PENALTY_START)``, one deck after the other each way in
    this process: Newton iterations per increment, cut iterations, tangents, CPU, and how far
    the second moved from the first (positions, mm; the tilt and thickness errors the case
    checks)."""
    from validation.cases import plies_deck_of_cards as deck

    kept = deck.DECK_PENALTY_START
    decks = [(2, cells) for cells in deck.MESHES["default"]] + [(4, 20), (8, 20)]
    totals = {}
    for share in (None, kept):
        deck.DECK_PENALTY_START = share  # type: ignore[assignment]
        tangents = cpu = 0.0
        for count, cells in decks:
            start = time.process_time()
            run = deck.bend(count, cells)
            took = time.process_time() - start
            info = run.result.info
            tangents, cpu = tangents + info["evaluations"]["tangent"], cpu + took
            RECORD[(share, count, cells)] = run
            line = f"start {share}: {count} plies, {cells} cells: "
            line += f"{info['iterations_per_increment']}"
            line += f" and {info['iterations_cut']} cut, {info['evaluations']['tangent']} tangents"
            line += f" ({info['soft_start_iterations']} soft), {took:.2f} s"
            if share is not None:
                ref = RECORD[(None, count, cells)]
                moved = np.abs(run.result.positions - ref.result.positions).max()
                errors, before = run.errors(), ref.errors()
                change = {key: abs(errors[key] - before[key]) for key in errors}
                line += f"; within {moved:.2g} mm, errors within " + ", ".join(
                    f"{key} {value:.2g}" for key, value in change.items()
                )
            print(line, flush=True)
        totals[share] = (tangents, cpu)
    deck.DECK_PENALTY_START = kept
    for share, (tangents, cpu) in totals.items():
        print(f"start {share}: {tangents:.0f} tangents, {cpu:.1f} s CPU")


def report(result) -> None:
    """Print the attempts, increment by increment."""
    for entry in RECORD["attempts"]:
        status = "CUT: " + entry["failed"] if entry["failed"] else "converged"
        its = entry["iterations"]
        print(
            f"load {entry['load']:.4f}: {len(entry['history']) - 1:3d} iterations, "
            f"{entry['cpu']:.2f} s, {status}"
        )
        history = entry["history"]
        print("   ratios " + " ".join(f"{r:.1e}" for r in history))
        scales = [row["scale"] for row in its if row["scale"] is not None]
        print("   scales " + " ".join(f"{s:.3g}" for s in scales))
        print("   trials " + " ".join(str(row["trials"]) for row in its))
        print("   touching/ramp/faded " + " ".join(
            f"{row['touching']}/{row['ramp']}/{row['faded']}" for row in its))  # fmt: skip
        if its and "elements" in its[0]:
            print("   |F| elements/contacts N, deepest gap mm " + " ".join(
                f"{row['elements']:.2g}/{row['contacts']:.2g}/{row['deepest']:.2g}"
                for row in its))  # fmt: skip
        if its and "parts" in its[0]:
            print("   |F| free membrane/bending/shear/contact/load N " + " ".join(
                "/".join(f"{row['parts'].get(k, 0.0):.2g}" for k in
                         ("membrane", "bending", "shear", "contact", "load"))
                for row in its))  # fmt: skip
        keys = ("in", "out", "ramp_in", "ramp_out", "triangle", "sign")
        print("   changes (in,out,ramp in,ramp out,triangle,sign) " + " ".join(
            ",".join(str(row.get(k, "-")) for k in keys) for row in its[1:]))  # fmt: skip
        print("   largest gap change mm " + " ".join(
            f"{row['gap_change']:.2g}" for row in its[1:] if "gap_change" in row))  # fmt: skip
    print(f"iterations per increment {result.info['iterations_per_increment']}")
    print(
        f"converged iterations {result.steps}, cut {result.info['iterations_cut']}, cuts "
        f"{result.info['cuts']}; evaluations {result.info['evaluations']}"
    )


def active_set(
    name: str, resolution: str, plies: int | None, rounds: int, opening: str | None = "ramp"
) -> None:
    """The case's solver on its plies with the ply contact's normal law under Static the
    ramp and the active set (``PlyContact(static_law=...)``, elements/ply_active_set.py),
    alternately ``rounds`` times in this process: iterations per increment, tangents, CPU,
    and the largest change of the material lines between the two equilibria (tilt, deg;
    thickness and mid-point, mm; ``PlyStack.material_lines``), and for heavy the change of
    what plies-heavy-cantilever compares (``compared_change``)."""
    if name not in ("bai", "heavy"):
        raise ValueError(f"--active-set: case {name!r}: expected bai or heavy")
    from elements.ply_active_set import ActiveSetPlyContactBlock

    ActiveSetPlyContactBlock.opening_law = opening  # type: ignore[assignment]
    results: dict[str, Any] = {}
    times: dict[str, list[float]] = {"ramp": [], "active_set": []}
    for law in ("ramp", "active_set") * rounds:
        RECORD.update(attempts=[])
        cpu = time.process_time()
        result = solve_case(name, resolution, static_law=law, plies=plies)
        cpu = time.process_time() - cpu
        results[law] = result
        times[law].append(cpu)
        info = result.info
        print(
            f"--- {name} {resolution}, {RECORD['stack'].count} plies, static_law={law}: "
            f"{cpu:.1f} s CPU, converged {result.converged}"
            + (f", opening_law={opening}" if law == "active_set" else "")
        )
        print(f"iterations per increment {info['iterations_per_increment']}")
        print(
            f"converged iterations {result.steps}, cut {info['iterations_cut']}, cuts "
            f"{info['cuts']}, first-turn cuts {len(info['first_turn_cuts'])}; evaluations "
            f"{info['evaluations']}",
            flush=True,
        )
    stack = RECORD["stack"]
    lines = {
        law: stack.material_lines(result.positions, result.directors)
        for law, result in results.items()
    }
    before, after = lines["ramp"], lines["active_set"]
    tilt = np.degrees(np.abs(after.angle - before.angle)).max()
    thickness = np.abs(after.thickness - before.thickness).max()
    middle = np.linalg.norm(after.midpoint - before.midpoint, axis=1).max()
    moved = np.abs(results["active_set"].positions - results["ramp"].positions).max()
    print(
        f"material lines: tilt within {tilt:.3g} deg, thickness within {thickness:.3g} mm, "
        f"mid-point within {middle:.3g} mm; nodes within {moved:.3g} mm (the ramp's delta "
        f"{1e-3 * stack.ply_thickness:.3g} mm)"
    )
    print(
        "CPU best of "
        + ", ".join(
            f"{law} {min(spent):.2f} s ({' '.join(f'{t:.2f}' for t in spent)})"
            for law, spent in times.items()
        )
    )
    if name == "heavy":
        change = compared_change(RECORD["case"], stack, results["ramp"], results["active_set"])
        print_compared_change(change, resolution)


def compared_change(case, stack, before, after) -> dict[str, float]:
    """What plies-heavy-cantilever compares, from the plies' equilibria ``before`` (the ramp)
    and ``after`` (the active set), each with ``positions`` and ``directors`` ((n, 3) of the
    stack's mesh): along the case's path (``fibreshell.plies.plies_profiles``) the largest
    |change| of the director angle (deg; "angle_deg" over its first 80 %, the checks' span,
    "angle_whole_deg" over all of it), its mean ("angle_mean_deg", which bounds the change of
    the mean angle's check), of the mid-surface height ("height_mm") and of the thickness along
    the director over the first 80 % ("thickness", / h); and the tip's mean deflection
    ("tip_before_mm", "tip_after_mm", the drop of the material lines' mid-points at the case's
    set "tip"). A check's value moves by no more than the profile's change (the fibrous and
    Mindlin sides are the same runs either way), but the height's: this one is node by node,
    the check interpolates the plies' heights at the shells' horizontal positions, which adds
    the path's slope times the nodes' horizontal change."""
    from fibreshell.plies import plies_profiles

    lines = [
        next(iter(plies_profiles(case, stack, r.positions, r.directors).values()))
        for r in (before, after)
    ]
    s = np.asarray(lines[0]["s"])
    inside = s <= 0.8 * s.max()
    change = {
        key: np.abs(np.asarray(lines[1][key]) - np.asarray(lines[0][key]))
        for key in ("director_angle_deg", "z", "thickness")
    }
    h = float(case.parts[0]["element"].fabric.thickness)
    tip = case.mesh.nodes("tip")
    drops = [
        -(
            stack.material_lines(r.positions, r.directors).midpoint[tip] - case.mesh.points[tip]
        ).mean(axis=0)[2]
        for r in (before, after)
    ]
    return {
        "angle_deg": float(change["director_angle_deg"][inside].max()),
        "angle_whole_deg": float(change["director_angle_deg"].max()),
        "angle_mean_deg": float(change["director_angle_deg"].mean()),
        "height_mm": float(change["z"].max()),
        "thickness": float(change["thickness"][inside].max() / h),
        "tip_before_mm": float(drops[0]),
        "tip_after_mm": float(drops[1]),
    }


def print_compared_change(change: dict[str, float], resolution: str) -> None:
    """``compared_change``'s figures beside plies-heavy-cantilever's tolerances at
    ``resolution``."""
    from validation.cases import plies_heavy_cantilever as heavy

    tolerance = heavy.TOLERANCES[resolution]
    before, after = change["tip_before_mm"], change["tip_after_mm"]
    print(
        f"the case's compared values ({resolution} tolerances): director angle within "
        f"{change['angle_deg']:.3g} deg on the first 80 % ({change['angle_whole_deg']:.3g} on "
        f"the whole path; tolerance {tolerance['angle_deg']:g}), its mean within "
        f"{change['angle_mean_deg']:.3g} deg (tolerance {tolerance['angle_mean_deg']:g}), "
        f"mid-surface height within {change['height_mm']:.3g} mm (tolerance "
        f"{tolerance['height_mm']:g}), thickness within {change['thickness']:.3g} h (tolerance "
        f"{tolerance['thickness']:g}); tip deflection {before:.5f} -> {after:.5f} mm "
        f"({after / before - 1.0:+.2e}; tolerance {heavy.TIP_TOLERANCE['plies']:g} relative to "
        "the elastica)"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--case", default="bai", help="bai, heavy, deck or sag")
    parser.add_argument("--resolution", default="coarse")
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
        "--tangent-check",
        action="store_true",
        help="the tangent against central differences on the last increment (no timing)",
    )
    parser.add_argument(
        "--check-load",
        type=float,
        default=None,
        help="with --tangent-check: the increment converged at this load factor (default the last)",
    )
    parser.add_argument(
        "--every", type=int, default=15, help="with --tangent-check: every this many iterates"
    )
    parser.add_argument(
        "--parts",
        action="store_true",
        help="with --detail: the residual's membrane, bending, shear and contact parts per iterate",
    )
    parser.add_argument(
        "--rounds", type=int, default=1, help="solve both sides this many times, alternately"
    )
    parser.add_argument(
        "--deck-start",
        action="store_true",
        help="the default report's five decks without and with the case's soft start",
    )
    parser.add_argument(
        "--active-set",
        action="store_true",
        help="the case's solver with the ply contact's ramp and with static_law='active_set'",
    )
    parser.add_argument(
        "--plies", type=int, default=None, help="with --active-set: the plies (the case's)"
    )
    parser.add_argument(
        "--unopened",
        action="store_true",
        help="with --active-set: the active set in the first increment of the displacement "
        "phase too (ActiveSetPlyContactBlock.opening_law None)",
    )
    args = parser.parse_args()
    print(f"load before (1, 5, 15 min): {np.round(os.getloadavg(), 2).tolist()}")
    if args.active_set:
        opening = None if args.unopened else "ramp"
        active_set(args.case, args.resolution, args.plies, args.rounds, opening)
        print(f"load (1, 5, 15 min): {np.round(os.getloadavg(), 2).tolist()}")
        return
    if args.deck_start:
        deck_starts()
        print(f"load (1, 5, 15 min): {np.round(os.getloadavg(), 2).tolist()}")
        return
    if args.tangent_check:
        tangent_check(args.case, args.resolution, args.every, args.check_load)
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
        print(f"load (1, 5, 15 min): {np.round(os.getloadavg(), 2).tolist()}", flush=True)
    before, after = results[:2]
    moved = np.abs(after.positions - before.positions).max()
    turned = np.abs(after.directors - before.directors).max()
    print(f"final positions within {moved:.3g} mm, directors within {turned:.3g}")


if __name__ == "__main__":
    main()
