"""Where Static's Newton iterations go, increment by increment (docs/theory.md §6.5).

Lines (every model of the validation cases or benchmarks that run it, one thread):

1. the elastica (validation case mindlin-elastica: 100 x 5 x 1 mm, 20 cells, P L^2 / EI = 3
   in 5 increments);
2. the roll-up (mindlin-rollup: 100 x 10 x 1 mm, 20 cells, a quarter circle in 4 increments);
3. the 2560-triangle Mindlin cantilever of benchmarks/kratos_cantilever.py and
   benchmarks/static_solver.py line 2 (80 x 16 cells, P L^2 / EI = 3, 5 increments);
4. Peirce's cantilever (G986 stack, 20 x 1 cells, 3 increments; static_solver.py line 6),
   fibrous and MindlinShell(fabric);
6. (printed after 5) Peirce's fibrous strip in 3 and 12 increments with the convergence
   test's round-off floor (solvers.round_off, the default) beside the strict test
   (``solvers.round_off.FLOOR_FACTOR = 0``, the solver before it).
5. Peirce's fibrous strip with its bilinear bending law (7.5 N mm to the knee at 1e-3 1/mm,
   0.5 N mm beyond) replaced by a linear one of 7.5 or 0.5 N mm, and with its fibre tension
   (1200 N/mm) times 0.01 and 10: what the iterations follow.
7. (printed after 6) the fibrous strips without the level-strain projection
   (``Static(level_projection=...)``, solvers.newton_levels), with it by the coloured
   differences of before (the reference pass; ``--no-coloured`` leaves it out), with it by
   the exact gradient's numpy form (level_jacobian.py ``level_strain_gradient(...,
   compiled=False)``, the reference pass of the compiled loop) and by its compiled cell loop
   (elements/fibrous/level_kernels.py, the default): Peirce's in
   3 and 12 increments, the heavy fibrous cantilever of validation/cases at 10, 20 and 40
   cells, the bias specimen of tests/test_bias_extension.py pulled by a force of 20 N; for
   Peirce's in 3 increments the residual ratio of every iteration, the cells past the bending
   law's knee at each tangent and the cells that switched branch between tangents.

Each solve prints its Newton iterations per increment, the residual ratio after the first
update of each increment (the first iterate starts from the last converged state with the
whole load step), the orders log(r_k+1) / log(r_k) of the last iterations (the decreasing
steps from r_k at most 0.1 with r_k+1 above 3e-8, i.e. clear of the round-off floor; 2 for a
quadratic iteration with a unit constant, 1.5 and below for a linear one from 1e-2), the
tangents, the CPU time (best of ``--repeat``) and the tip. Lines 1-4 run the default beside
``predictor=True`` (the previous increment extrapolated, as Abaqus's and Kratos's predictors
do), in the same run.

Measured on this 2-core machine (one thread, CPU time best of 3, load 3.4-4.2), default /
predictor=True, the tips the same to 1e-6 mm, with the strict convergence test (before the
round-off floor of line 6; with it, the default now, Peirce fibrous 9-9-10, 28 tangents /
9-13-15 and a cut; the linear 7.5 N mm law 3-4-4; fibres x 10 13-10-9; the rest unchanged):

- elastica 4-6-5-4-4, 23 tangents, 0.06 s / 4-5-6-7-4, 26; roll-up 5-4-5-4, 18, 0.06 s /
  5-8-6-9, 28; the 2560-triangle cantilever 4-5-5-5-4, 23 tangents, 0.94 s / 4-6-6-7-4, 27,
  1.03 s (the issue's 9-9-9-8-8 were the straight steps before solvers.newton_curvature);
  Peirce fibrous 10-9-10, 29, 0.12 s / 10-13-15 and a cut, 88, 0.42 s; Peirce
  MindlinShell(fabric) 4-5-5, 14, 0.09 s / 4-12-6 and a cut, 72, 0.48 s.
- The first update of every increment leaves the residual ratio at 1.0 (from 1e-2 to 5e-2 on
  the Mindlin strips): a step of 1-16 elements turning the directors by 0.1-0.4 rad, whose
  third-order remainder stretches the membrane, whose stiffness per element is 75-300 times
  the bending's (12 (L_e / t)^2); the next step is 1-5 % of it and the rest is Newton's
  quadratic tail: orders 1.6-3.4 on the Mindlin strips (tests/test_newton_orders.py; with
  the tangent scaled by 1.1 or 0.9, 6-13 iterations per increment and orders down to 1.0).
  The tangent is consistent (the Mindlin tangent matches central differences to 1e-8, the
  fibrous one to their own noise, docs/theory.md §6.5) and the steps are taken whole: the
  first iterate is what a predictor would have to save, and the extrapolated ones cost
  iterations instead: linear (the ``predictor=True`` line) and quadratic (the last three
  converged states, translations and rotation vectors; measured with a script not kept:
  elastica 4-6-5-5-5, roll-up 5-4-6-6, cantilever 20 x 2 cells 5-6-10-9-8, Peirce 10-9-28)
  both land off the equilibrium path by the chord's stretch.
- Peirce's fibrous strip: with a linear bending law of 7.5 N mm 4-4-4 (12 tangents, tail
  orders 2.33 and 2.54; 3-4-4 with fibres of 12 or 120 N/mm), with 0.5 N mm 9-11-9, with its
  bilinear law 10-9-10; fibres of 12, 120, 1200, 12000 N/mm under the bilinear law: 9-9-9,
  6-9-8, 10-9-10, 14-11-10. The count follows the soft branch of the bending law (past the
  knee the strip deflects 15 x more per increment), not the fibres' stiffness alone: with
  any tension above ~100 times the bending (T L_e^2 / B; 2400 with 12 N/mm and 0.5 N mm), a
  step's remainder stretches the fibres enough to rule the residual (ratio ~1 for 5-6
  iterations, the plateau of docs/theory.md §6.5). On the soft strip even the tail is not
  quadratic from 1e-3 (linear 0.5 N mm law: orders 1.39, 3.19, 1.27; with the bilinear law
  1.28, 1.01, 1.40, 2.16): a step from a ratio of 1e-3 raises it, the next takes it to 1e-7
  to 1e-9, with plain Newton and the exact tangent as well (``compression_free=0,
  curved=False, chords=0, seek_stable=False``: 49-27-15): the region where Newton is
  quadratic is that small, as §6.5 says. Also measured and not kept: the Mindlin tangent with
  each level's compressed edge strains raised to zero in its stress terms far from
  equilibrium (as the fibrous compression-free tangent; ratio 1e-2 / 1e-1): elastica
  4-26-17-8-5 / 4-16-7-6-5, cantilever 20 x 2 cells 5-16-47-24-11 / 4-32-24-6-7.
- The convergence test and round-off: the fibrous residual's round-off, measured as the change
  of the internal forces under a rigid translation of Peirce's converged strip (exact physics:
  the forces do not change), is 1.3e-11 to 2.2e-11 N against F_ref 0.018 N, 1e-9 of it (the
  fibres' 1200 N/mm times the rounding of coordinates of order 40 mm); tol 1e-8 is 5-10 times
  above it, and one iteration in Peirce's 29 is spent at that floor (1.1e-8 -> 7.4e-9), which
  solvers.newton's ``at_round_off_floor`` then accepts. On the Mindlin strips the same probe
  gives 4e-12 to 5e-11 of F_ref (the elastica, 1377 and 5313 nodes): tol 1e-8 is far above
  the floor, and their last ratios of 3e-10 to 8e-9 are Newton's, not round-off.

Line 6, strict -> floor (same run, one thread, best of 3, load 3.7-4.1): 3 increments
10-9-10 -> 9-9-10 iterations, 29 -> 28 tangents, 0.16 -> 0.13 s; 12 increments
4-6-6-7-7-6-7-7-7-6-5-6 -> 3-4-5-7-6-6-7-7-7-6-5-6, 74 -> 69 tangents, 0.32 -> 0.30 s; the
positions equal to 6e-14 mm. The heavy fibrous cantilever (10, 20, 40 cells), the elastica,
the roll-up, the 2560-triangle cantilever and Peirce's MindlinShell(fabric) strip: the same
iterations and positions (their rounding is below tol / 10).

Line 7, off / coloured differences / exact gradient (same run, one thread, CPU best of 3,
load 1.8-2.0; the figures of lines 1-6 above are those of the solver's default, off; the
Mindlin strips have no block that gives level strains; "coloured" is the projection with the
gradient of before, on today's solve, rule of held measures and stopping test):
Peirce 3 increments 9-9-10 / 6-5-6 / 6-5-6 iterations, 28 / 17 / 17 tangents, 23 sweeps,
0.09 / 0.17 / 0.11 s; 12 increments 69 / 51 / 52 tangents, 47 sweeps, 0.20 / 0.36 / 0.27 s;
heavy cantilever 10 cells 26-9-7 / 6-6-4 / 6-6-4, 0.10 / 0.13 / 0.08 s; 20 cells 25-9-8 /
5-5-4 / 5-5-4, 0.14 / 0.16 / 0.11 s; 40 cells 49-11-9 / 6-7-5 / 6-7-5, 0.33 / 0.26 / 0.19 s;
the bias specimen pulled by 20 N 4-4-4-4 / 12-5-4-4 / 6-4-4-4, 0.19 / 0.89 / 0.31 s;
positions (exact against off) equal to 4.5e-9 mm. The exact gradient costs 0.56 ms a sweep
on Peirce's strip against 2.3-2.7 by coloured differences. Before the rule holding only the
measures a step changes by at most 1e-3 (solvers.newton_levels CHANGE), the pulled bias took
6-5-13-19 with the exact gradient and 28-29-27-34 with the coloured one. The projection stays
an option: on Peirce's strip (1.2-1.35 x) and the pulled bias (1.6 x) its sweeps (about 1.5
a projected step at 2-5 ms each: a gradient, J^T J, a band LDL^T, a strain evaluation) cost
more than the tangents they save; it saves CPU on the heavy cantilever (0.58-0.8 x). With
the sweeps' stopping test at 1e-12 (before the last change; load 2.6-2.8): Peirce 0.09 /
0.22 / 0.14 and 0.20 / 0.51 / 0.36 s, heavy 0.10 / 0.15 / 0.09, 0.14 / 0.18 / 0.12, 0.35 /
0.28 / 0.19 s, the pulled bias 0.20 / 1.20 / 0.43 s (36, 88, 32, 32, 32, 40 sweeps).
Before the exact gradient (load 5.1-5.4, SuperLU for the sweeps' solve): Peirce 3
increments 0.10 -> 0.24 s, 12 increments 0.21 -> 0.60 s; heavy cantilever 0.10 -> 0.17,
0.14 -> 0.20, 0.34 -> 0.31 s. The CPU went to the projection's gradient (8 colours x 5
unknowns of one-sided strain differences at each of up to 4 sweeps, 36 sweeps on Peirce)
(measured and not kept: the gradient of every other sweep with 6 sweeps, the same
iterations and CPU; of the first sweep alone with 8 sweeps, Peirce 7-6-7 in 0.14 s but
fibres x 10 9-22-9 and the heavy cantilever 8-11-7 at 40 cells; 2 or 3 sweeps, Peirce
11-13-7 or 7-5-5 and the heavy cantilever 25-11-8 or 8-6-5 at 20 cells; steps projected from
0.1 or 0.3 element instead of 0.01, Peirce 7-6-6 or 15-7-7). Before the projection,
the first increment of Peirce's strip (ratios 0.99, 1.0, 1.0, 0.65, 1.0, 0.31, 0.66, 2.4e-4,
2.2e-5, 1.1e-8): the first update leaves the levels stretched, and each later step that
corrects the bending by 0.01-0.03 rad stretches them again by 1e-4 to 1e-3 of strain (a
strain of 1e-6 across the strip is a ratio of 1); the cells past the knee settle after two
iterations (15 at the first update, then 2, 0, 2, 0, ... switches: no chatter), so the
tangent's branch at the iterate (a semi-smooth Newton, as it is) is not what costs. With the
projection the ratios are 0.99, 1.1, 0.20, 0.78, 1.1e-2, 3.5e-5, 8.1e-9.

Line 7 after the projection's sums were compiled (solvers.level_system: K + rho J^T J on a
pattern kept over the solve, J^T J by cell blocks; solvers.level_gather: J's entries), off /
on, e5843a3 beside this code in turns, two rounds each (one thread, CPU best of 5, load
2.0-3.5): Peirce 3 increments 0.089-0.091 / 0.110-0.111 s (1.21-1.23 x) -> 0.088-0.089 /
0.091-0.092 s (1.035-1.04 x); 12 increments 0.192-0.193 / 0.260-0.264 (1.34-1.38 x) -> 0.190-
0.193 / 0.220 (1.14-1.16 x; 5 iterations in one increment where 4, 52 tangents against 51);
heavy cantilever 10 cells 0.100-0.103 / 0.085-0.087 -> 0.101-0.104 / 0.070-0.071 (0.67-0.70
x), 20 cells 0.140-0.143 / 0.109-0.112 -> 0.139-0.145 / 0.087-0.089 (0.61-0.63 x), 40 cells
0.325-0.330 / 0.190-0.201 (7-7-5) -> 0.323-0.342 / 0.147-0.156 (6-7-5; 0.45-0.46 x); the
force-pulled bias 0.201-0.202 / 0.299-0.302 -> 0.196-0.213 / 0.306-0.323 (1.52-1.56 x).
Profile of Peirce's 3 increments with the projection (cProfile by tottime and timers around
each part, one thread): 23 sweeps in 8 projected steps; before, 49-65 ms a solve in the
projection against 0.10-0.12 s for the solve: the gradient 21 ms (level_strain_gradient's
numpy 0.35-0.38 ms a sweep, its sums into J 0.25), scipy's diag(held) J, J^T J, K + rho N
15 ms and their placement on the kept pattern 7, the factorisation and solve of the sweeps
10, the strains at each sweep's end 4.5, the targets' central differences 2.3; after, 37 ms:
the gradient 16, the system 6 (0.6 of it its pattern, once a solve), the factorisations and
solves 9, strains and steps 6. The projection saves 11 tangents and their factorisations
(28 -> 17), about 35 ms: it stayed an option (``level_projection=False`` the default) until
the gradient's numpy (about 8 ms a solve here) is compiled as well. Not kept: J^T J by one
product per pair of a row's entries (245 000 on Peirce's strip, 0.4-0.5 ms a sweep) and by
a block updated row by row (1.6 ms a sweep on the bias against scipy's 0.8: the updates went
through memory); the places of the products by np.unique / searchsorted over all keys
(19 ms once a solve on the bias, 6 by bisection within each column).

Line 7 after the gradient's pieces were compiled (elements/fibrous/level_kernels.py, one cell
at a time; level_jacobian.py's numpy its reference pass), off / numpy gradient / compiled in
the same run, three rounds (one thread, CPU best of 5, load 7.9-9.6; a fourth round run beside
a profile not counted): Peirce 3 increments 0.096 / 0.099 / 0.093, 0.103 / 0.104 / 0.098,
0.090 / 0.097 / 0.086 s (on over off 1.01-1.08 -> 0.95-0.97 x); 12 increments 0.216 / 0.253 /
0.230, 0.223 / 0.238 / 0.228, 0.191 / 0.218 / 0.202 s (1.07-1.17 -> 1.02-1.065 x; 52
tangents, 47 sweeps); heavy cantilever 10 cells 0.101-0.116 / 0.070-0.079 / 0.063-0.069 s
(0.68-0.70 -> 0.59-0.64 x), 20 cells 0.140-0.156 / 0.088-0.098 / 0.078-0.092 (0.63-0.64 ->
0.55-0.59 x), 40 cells 0.322-0.346 / 0.147-0.151 (6-7-5) / 0.136-0.142 s (7-7-5: the pieces'
rounding, 3e-13 mm in the positions, moves one iteration; 0.44-0.46 -> 0.40-0.42 x); the
force-pulled bias 0.203-0.209 / 0.311-0.336 / 0.298-0.312 s (1.52-1.66 -> 1.44-1.54 x). The
positions of the compiled and numpy gradients' solves equal to 3.2e-13 mm. A sweep's gradient
on Peirce's strip (solvers.newton_levels ``gradient``, 40 cells, load 9): 0.51 -> 0.24 ms, its
pieces 0.34 -> 0.07 (the normal sums 0.009, the shares 0.015 of it), the step's end (``advance``)
0.055, the compiled sums into J 0.035, scipy's CSR 0.02. The projection now saves CPU on
Peirce's strip in 3 increments but not in 12 (1.02-1.065 x): the default stayed off. What is
left a sweep (about 1 ms: the gradient 0.24, K + rho J^T J 0.3, its factorisation and solve
0.4, the strains 0.1) is spread over pieces of 0.02-0.4 ms.

The projection made the default on fibrous models (solvers.newton_levels CHANGE 1e-3 ->
1e-4). Profile of the force-pulled bias with and without it (cProfile by tottime, one thread,
load 0.3-2): without, 4-4-4-5 iterations, 17 tangents, the first update of every increment
leaving the ratio at 1.0 (0.46-0.15 before it); with it (CHANGE 1e-3) 6-4-4-4, 18 tangents:
no iteration saved, and 24 sweeps in 10 projected steps (2.4 a step) at about 4 ms each: the
J^T J sums (level_system ``_normal``, 2.4 ms a sweep: 30-60 columns a cell), the gradient
(1.4 ms), the system's factorisation (its pattern new whenever K's zeros move: 18 symbolic
analyses a solve against 7), and once a solve J's pattern (np.unique over 282 000 keys,
20-25 ms) and the system's maps (10-15 ms). The projected steps that did not pay: the first
increment's third step (0.06 element) held the fibres near the clamps, whose first-order
change was 7e-4 to 9e-4, to targets off by about its square (5e-7 at 120000 N/mm) and left a
ratio of 7.7e-2 where plain Newton reached 2.5e-4; each later increment's second step (0.02-
0.04 element, held error 1.4e-5 to 2.6e-5) took the ratio from 3e-2 to 3e-2 / 4e-3 / 1e-3 only.
Measured and not kept (one thread, best of 3, load 5-6.6): a gate on the held error before
the first sweep (skip the projection below 1e-5 / 3e-5 / 1e-4): the bias 6-4-4-4 / 6-3-3-3 /
6-3-3-3 but Peirce 10-6-6 (its first step's held error is 3.4e-6, and that one sweep saves
4 iterations) and the heavy cantilevers up to 6-6-7; steps projected from 0.05 or 0.1
element (LEVEL_GATE): the bias 7-3-4-3, Peirce 6-6-6 and in 12 increments one of 11
iterations (58 tangents against 52). CHANGE 3e-5 / 1e-4 / 3e-4: the bias 5-4-4-3 / 5-4-3-3 /
5-4-4-3, Peirce and the heavy cantilevers the same iterations from 3e-5 to 1e-3: 1e-4 kept.
J's pattern by scipy's sums of duplicates and a bisection in each row (the same bits): the
bias 0.342 -> 0.305 s with CHANGE 1e-3.

Line 7 off / on (CHANGE 1e-4) / on with CHANGE 1e-3 (its reference pass), same run, two
rounds (one thread, CPU best of 5, load 12.4-13.0): Peirce 3 increments 0.096 / 0.092 / 0.086,
0.096 / 0.089 / 0.087 s (6-5-6, 17 tangents against 9-9-10, 28); 12 increments 0.214 / 0.231 /
0.231, 0.206 / 0.224 / 0.213 s (52 tangents against 69); heavy cantilever 10 cells 0.113-0.116
/ 0.070 / 0.070-0.071, 20 cells 0.156-0.160 / 0.084-0.094 / 0.091-0.095, 40 cells 0.358-0.359 /
0.147-0.154 / 0.151-0.156 s; the force-pulled bias 0.222 / 0.244 / 0.306, 0.218 / 0.249 /
0.311 s (5-4-3-3, 15 tangents, 17 sweeps / 6-4-4-4, 18, 24; off 4-4-4-5, 17): on over off
Peirce 0.93-0.96 and 1.08-1.09 x, heavy 0.60-0.62 / 0.54-0.59 / 0.41-0.43 x, bias 1.10-1.14 x
(1.38-1.43 with CHANGE 1e-3); the six solves in sum 1.154-1.159 -> 0.874-0.876 s (0.76 x).
Again after the band LDL^T took the envelope and these patterns (solvers/linear.py: the bias's
526 unknowns go to the band, whose factors differ from QDLDL's in the last bits), off / on
(one thread, CPU best of 5, load 7.3-9.0): Peirce 3 increments 0.117 / 0.108 s (the same
9-9-10 / 6-5-6), 12 increments 0.253 / 0.257, heavy cantilever 0.133 / 0.082, 0.187 / 0.105,
0.417 / 0.168, the bias 0.222 / 0.285 s (4-4-4-4, 16 tangents / 6-4-4-3, 17, 17 sweeps): on
over off 0.92, 1.02, 0.62 / 0.56 / 0.40 and 1.28 x; the six in sum 1.329 -> 1.005 s (0.76 x).
Every fibrous Static solve of the tests (tests/test_static*, test_fibrous*, test_newton*,
test_bias*, test_plies, test_hemisphere_static, test_capstan, test_level_projection,
test_round_off_floor, test_nonlinear_bending, test_compression_free_tangent,
test_picture_frame, test_case_files and others: 105 solves) and of the coarse validation cases
that run one (fibrous- and plies-heavy-cantilever, fibrous- and plies-deck-of-cards,
bai-6.1.1-sensitivity, bai-6.1.2: 28 solves) run with the projection off and on: the same tests
pass (but those of test_level_projection that ask for the projection); 24 test solves and 3
case solves projected, the rest have prescribed motions (the fibrous deck of cards, the paper
cases on the arc-length path: the projection off there) or interactions (the plies), and are
the same to the bit; the cases' checks all pass both ways, the compared values equal to 1e-9 of
each (the heavy cantilever's tip 117.5210592 mm both, tolerance 1 %), their iterations 2606 ->
2535 (heavy cantilever 26-9-7 -> 6-6-4, the plies' heavy fibrous strip 6-12-8-7-7 -> 5-6-5-4-5,
the plies' deck's fibrous sag 12-12-14-9-6-5 -> 5-6-5-4-4-4), their solves' CPU 31.7 -> 31.6 s
(load 9-12). Lines 1-2 now (one thread, best of 3, load 9-10): elastica 4-6-5-4-4, 23 tangents,
0.06 s; roll-up 5-4-5-4, 18, 0.05 s (Mindlin: no level strains, the same with either setting).
Lines 4-6's fibrous Peirce figures above were taken with the projection off; with the default
now, 6-5-6. Left as it is: the projection's set-up once a solve, 25-30 ms on the 169-node plate
of tests/test_fibrous_supports.py (J's pattern 7-11 ms, the system's maps 11-16 of which the
products' places 3.4, the first factorisation's analysis 3.6; 1.5, 1.4 and 0.8 ms on Peirce's
42 nodes): its one-increment solves 0.058 -> 0.093 s with the same 3 iterations. Measured and
not kept: the sweeps after the first with the first sweep's factorisation (J new in the
right-hand side only): Peirce stopped at load factor 0.58 after 8 cuts.

Issue 30's 3-6 Newton iterations an increment, measured on 432e668 (one thread, best of 1, load
4.5-11): elastica 4-6-5-4-4, roll-up 5-4-5-4, the 2560-triangle cantilever 4-5-5-5-4, Peirce
fibrous 6-5-6 (the level projection, the default on fibrous models), Peirce
MindlinShell(fabric) 4-5-5: every one within 3-6, the tips as above; the Mindlin strips' tail
orders 1.6-3.4 (quadratic), Peirce fibrous's 1.06-2.96. What is left of each increment's first
update (ratio 1.0: the residual is the membrane's, F_ref's ||F_int|| with it) was followed on
the cantilever of 20 x 2 cells: the curved step's second-order correction w overshoots on the
first update of every increment (the residual after delta + a w, increments 1-5: least at a =
0.6-0.7, 2-7 times below that at a = 1; at a = 1 the iterate has 1-12 negative pivots, none at
a <= 0.7), and on the 2560-triangle cantilever the 8-14 negative pivots of that iterate cost a
mode search, the shifted factorisation that tells them from neutral ones and the jump check at
the end of the increment (0.37 of 1.15 s CPU). Measured and not kept: w scaled by 0.8 / 0.65 /
0.5 (no indefinite iterate at 0.65 and 0.5): the cantilever 5-5-4-6-4 / 6-6-5-5-4 / 7-7-6-5-6
(19 -> 20 / 22 / 27 tangents), the elastica 5-5-5-4-4 / 6-5-5-4-5 / 6-6-5-5-5, the roll-up
5-4-4-5 / 4-4-4-4 / 5-6-6-5, the 20 x 2 cells 5-6-5-9-4 / 6-6-6-5-4 / 7-7-7-5-5: fewer negative
pivots, not fewer iterations. The curvature probe h (0.01 the default) at 0.1, 0.3, 0.5, 1:
within one iteration an increment of the default's, 1.0 worse. The kept tangent
(solvers/kept_tangent.py): the Mindlin lines' Newton tangents elastica 23 -> 19, roll-up 18 ->
15, cantilever 23 -> 19, Peirce MindlinShell(fabric) 14 -> 12, the same iterations and
positions to the bit; the fibrous lines unchanged (their folds are history a commit renews).
Since, the default (``Static(correction="fitted")``; the line ``correction="whole"`` is the
solver before, solvers/newton_curvature.py ``correction_scale``): the share of w fitted at
each curved step, the least of the parabola through ||r||^2 at a = 0, 1/2, 1 within
[0.25, 1]: elastica 4-4-4-4-4 (16 tangents, 107 forces, no mode search; whole 4-6-5-4-4, 19,
66, 5 mode searches), roll-up 5-4-4-4 (14, 91, none; whole 5-4-5-4, 15, 48, 4), cantilever
5-4-4-4-4 (17 tangents, no mode search), MindlinShell(fabric) 5-5-4 (12 tangents, 62 forces;
whole 4-5-5, 12, 39); not on fibrous models, nor with interactions (docs/theory.md §6.5,
"Curved steps"). CPU, best of 5 alternated in one process (load 10): elastica 0.035 against
0.061 s, roll-up 0.031 against 0.048 s; MindlinShell(fabric) 0.045 against 0.044 s (best of
4). The first variant of each line here carries the line's first-call costs at --repeat 1.
The closing orders (the last step of each increment from a ratio >= 1e-6, as
tests/test_newton_orders.py reads them): elastica 1.72-3.67 (whole 1.83-5.04), roll-up
1.67-1.77 (1.72-2.65); the tail orders of the elastica with the share, 1.04-1.61, are those of
the step after the second iterate (module docstring of tests/test_newton_orders.py).

Run: python benchmarks/newton_iterations.py [--repeat 3] [--skip-large] [--levels-only]
[--no-coloured]
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import os
import platform
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np  # noqa: E402

from materials import BendingLaw  # noqa: E402
from materials.presets import g986_stack  # noqa: E402
from solvers import Static, round_off  # noqa: E402
from validation import specimens  # noqa: E402
from validation.references.elastica import peirce_overhang  # noqa: E402

VARIANTS = (
    ("default", {}),
    ('correction="whole" (the solver before the fitted share)', {"correction": "whole"}),
    ("predictor=True", {"predictor": True}),
)


def tail_orders(history: list[float]) -> list[float]:
    """log(r_k+1) / log(r_k) of the decreasing steps of a residual-ratio history from
    r_k <= 0.1 whose r_k+1 is above 3e-8, clear of the round-off floor (the measure
    tests/test_newton_orders.py took before the fitted share of the curved correction; it
    now reads the last step of each increment from r_k >= 1e-6, ``closing_order``)."""
    return [
        math.log(after) / math.log(before)
        for before, after in zip(history[:-1], history[1:])
        if before <= 0.1 and 3e-8 < after < before
    ]


def closing_order(history: list[float]) -> float | None:
    """log(r_k+1) / log(r_k) of the last decreasing step of a residual-ratio history from
    1e-6 <= r_k <= 0.1 (as tests/test_newton_orders.py measures it); None where none."""
    orders = [
        math.log(after) / math.log(before)
        for before, after in zip(history[:-1], history[1:])
        if 1e-6 <= before <= 0.1 and after < before
    ]
    return orders[-1] if orders else None


def _tip_loaded(length, width, young, cells, across, amplitude):
    """A strip 1 mm thick under the tip load P L^2 / EI = 3 (the elastica case's as it is,
    kratos_cantilever.py's ramped linearly)."""
    mesh, model = specimens.mindlin_strip(length, width, 1.0, young, cells, across)
    bending = young * width / 12
    tip = mesh.nodes("right")
    load = (0.0, 0.0, -3.0 * bending / length**2 / len(tip))
    model.force(tip, load, **({"amplitude": amplitude} if amplitude else {}))
    return mesh, model


def _rollup():
    length, width, young = 100.0, 10.0, 1e5
    mesh, model = specimens.mindlin_strip(length, width, 1.0, young, cells=20)
    bending = young * width / 12
    tip = mesh.nodes("right")
    moment = 0.5 * math.pi * bending / length
    model.moment(tip, (0.0, -moment / len(tip), 0.0), amplitude="linear")
    return mesh, model


def _peirce(kind: str, bending: float | None = None, tension_scale: float = 1.0):
    fabric = g986_stack()
    overhang = peirce_overhang(fabric.areal_density * specimens.GRAVITY, fabric.bending)
    if bending is not None:
        fabric = dataclasses.replace(fabric, bending=BendingLaw.linear(bending))
    fabric = dataclasses.replace(fabric, tension=tension_scale * 1200.0)  # N/mm (g986_stack)
    build = specimens.fibrous_strip if kind == "fibrous" else specimens.mindlin_fabric_strip
    return build(overhang["overhang"], 10.0, fabric, 20)


def lines(skip_large: bool):
    """(name, mesh, model, increments, variants) of each line."""
    yield "1. elastica, 20 cells", *_tip_loaded(100.0, 5.0, 1e5, 20, 1, None), 5, VARIANTS
    yield "2. roll-up, 20 cells", *_rollup(), 4, VARIANTS
    if not skip_large:
        strip = _tip_loaded(200.0, 20.0, 70e3, 80, 16, "linear")
        yield "3. cantilever, 2560 triangles", *strip, 5, VARIANTS
    yield "4. Peirce, fibrous", *_peirce("fibrous"), 3, VARIANTS
    yield "4. Peirce, MindlinShell(fabric)", *_peirce("mindlin"), 3, VARIANTS
    default = VARIANTS[:1]
    for bending in (7.5, 0.5):
        name = f"5. Peirce, fibrous, linear bending {bending} N mm"
        yield name, *_peirce("fibrous", bending), 3, default
    for scale in (0.01, 10.0):
        name = f"5. Peirce, fibrous, fibres x {scale:g}"
        yield name, *_peirce("fibrous", tension_scale=scale), 3, default


def floor_lines(repeat: int) -> None:
    """Line 6: Peirce's fibrous strip, the strict convergence test beside the round-off
    floor's, in the same run."""
    mesh, model = _peirce("fibrous")
    compiled = model.compile()
    print("6. Peirce, fibrous, the round-off floor of the convergence test:")
    default = round_off.FLOOR_FACTOR
    for increments in (3, 12):
        positions = {}
        for variant, factor in (("strict", 0.0), ("floor", default)):
            round_off.FLOOR_FACTOR = factor
            best, result = math.inf, None
            for _ in range(repeat):
                started = time.process_time()
                result = Static(increments=increments, progress=False).solve(compiled)
                best = min(best, time.process_time() - started)
            assert result is not None
            info = result.info
            positions[variant] = result.positions
            print(
                f"  {increments} increments, {variant}: iterations "
                f"{info['iterations_per_increment']}, {info['evaluations']['tangent']} "
                f"tangents, {info['round_off_converged']} at the floor, {best:.2f} s CPU, load "
                f"{os.getloadavg()[0]:.1f}"
            )
        round_off.FLOOR_FACTOR = default
        moved = np.abs(positions["floor"] - positions["strict"]).max()
        print(f"  {increments} increments: positions differ by {moved:.1e} mm")


def _heavy(cells: int):
    from validation.cases.fibrous_heavy_cantilever import strip

    return strip(cells)


def branch_switches(compiled, options: dict) -> tuple[list[int], list[int]]:
    """(cells past the bending law's knee at each tangent of the solve, cells that switched
    branch between consecutive tangents) on Peirce's fibrous strip: the tangent takes each
    cell's branch at the iterate, and a chattering active set would show here."""
    from elements.fibrous import bending
    from elements.fibrous.block import FibrousShellBlock
    from solvers import static

    block = next(p for p in compiled.parts if isinstance(p, FibrousShellBlock))
    knee = 1e-3  # 1/mm, g986_stack's bilinear law
    active: list[np.ndarray] = []
    original = static.StaticRun.tangent

    def tangent(run, state, frames, compression_free=False, real=None):
        chi, _ = bending.curvatures(block, bending.geometry(block, state.positions))
        active.append(np.abs(chi) > knee)
        return original(run, state, frames, compression_free, real)

    static.StaticRun.tangent = tangent  # type: ignore[method-assign]
    try:
        Static(increments=3, progress=False, **options).solve(compiled)
    finally:
        static.StaticRun.tangent = original  # type: ignore[method-assign]
    switched = [int((b != a).sum()) for a, b in zip(active[:-1], active[1:])]
    return [int(a.sum()) for a in active], switched


def _coloured_gradient(levels, state, frames, delta):
    """The projection's J by the coloured one-sided differences it took before the exact
    gradient (solvers.newton_levels ``_jacobian``): the reference pass of line 7."""
    k = levels.strains(state).size
    return levels._jacobian(state, frames, delta, levels.model.element_size, k)


def _pulled_bias():
    """The bias specimen of tests/test_bias_extension.py (its linear fabric) pulled by 20 N
    on its free end (tests/test_static_vanished_normal.py): its shear is the load's own."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
    from test_bias_extension import LINEAR, bias_specimen

    mesh, model = bias_specimen(LINEAR, pull=None)
    right = np.asarray(mesh.node_sets["right"])
    model.force("right", (20.0 / len(right), 0.0, 0.0))
    return mesh, model


def _numpy_gradient(function):
    """``level_jacobian.level_strain_gradient`` by its numpy form (the reference pass of the
    compiled cell loop, elements/fibrous/level_kernels.py)."""

    def numpy_form(block, positions, directors, compiled=None):
        return function(block, positions, directors, compiled=False)

    return numpy_form


def level_lines(repeat: int, coloured: bool = True) -> None:
    """Line 7: the fibrous strips without the level-strain projection, with it by the
    coloured differences of before (unless ``coloured`` is false), with it by the exact
    gradient's numpy form and by its compiled loop (solvers.newton_levels), in the same run;
    the residual ratio of every iteration and the bending law's branch switches of Peirce's
    strip."""
    from elements.fibrous import level_jacobian
    from solvers.newton_levels import LevelStrains

    print("7. the level-strain projection (off / coloured / numpy gradient / compiled):")
    strips = [("Peirce, fibrous, 3 increments", _peirce("fibrous"), 3)]
    strips.append(("Peirce, fibrous, 12 increments", _peirce("fibrous"), 12))
    strips += [(f"heavy fibrous cantilever, {n} cells", _heavy(n), 3) for n in (10, 20, 40)]
    strips.append(("bias specimen pulled by 20 N", _pulled_bias(), 4))
    exact = LevelStrains.gradient
    compiled_form = level_jacobian.level_strain_gradient
    variants = [
        ("off", False, exact, compiled_form),
        ("coloured", True, _coloured_gradient, compiled_form),
        ("numpy", True, exact, _numpy_gradient(compiled_form)),
        ("exact", True, exact, compiled_form),
    ]
    if not coloured:
        del variants[1]
    for name, (_mesh, model), increments in strips:
        compiled = model.compile()
        positions = {}
        for variant, flag, gradient, pieces in variants:
            LevelStrains.gradient = gradient  # type: ignore[method-assign]
            level_jacobian.level_strain_gradient = pieces
            best, result = math.inf, None
            try:
                for _ in range(repeat):
                    started = time.process_time()
                    solver = Static(increments=increments, progress=False, level_projection=flag)
                    result = solver.solve(compiled)
                    best = min(best, time.process_time() - started)
            finally:
                LevelStrains.gradient = exact  # type: ignore[method-assign]
                level_jacobian.level_strain_gradient = compiled_form
            assert result is not None
            info = result.info
            positions[variant] = result.positions
            print(
                f"  {name}, {variant}: iterations {info['iterations_per_increment']}, "
                f"{info['evaluations']['tangent']} tangents, {info['evaluations']['residual']} "
                f"forces, {info['level_projection_sweeps']} sweeps, {best:.3f} s CPU, load "
                f"{os.getloadavg()[0]:.1f}"
            )
            if increments == 3 and name.startswith("Peirce") and variant in ("off", "exact"):
                for history in info["residual_history"]:
                    print("    ratios " + " ".join(f"{r:.1e}" for r in history))
                past, switched = branch_switches(compiled, {"level_projection": flag})
                print(f"    cells past the knee per tangent {past}")
                print(f"    cells that switched branch {switched}")
        moved = np.abs(positions["exact"] - positions["off"]).max()
        same = np.abs(positions["exact"] - positions["numpy"]).max()
        print(f"  {name}: positions differ by {moved:.1e} mm (compiled against numpy {same:.1e})")


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3, help="solves per line (best CPU)")
    parser.add_argument("--skip-large", action="store_true", help="without line 3")
    parser.add_argument("--levels-only", action="store_true", help="line 7 alone")
    parser.add_argument(
        "--no-coloured", action="store_true", help="line 7 without the coloured differences"
    )
    args = parser.parse_args(argv)
    print(f"python {platform.python_version()} on {platform.machine()} ({platform.system()})")
    if args.levels_only:
        level_lines(args.repeat, not args.no_coloured)
        return
    for name, mesh, model, increments, variants in lines(args.skip_large):
        compiled = model.compile()
        print(f"{name}:")
        for variant, options in variants:
            best, result = math.inf, None
            for _ in range(args.repeat):
                started = time.process_time()
                result = Static(increments=increments, progress=False, **options).solve(compiled)
                best = min(best, time.process_time() - started)
            assert result is not None
            info = result.info
            histories = info["residual_history"]
            first = [f"{history[1]:.1g}" for history in histories if len(history) > 1]
            orders = [f"{order:.2f}" for history in histories for order in tail_orders(history)]
            closing = [closing_order(history) for history in histories]
            last = ", ".join("-" if order is None else f"{order:.2f}" for order in closing)
            tip = result.positions[mesh.nodes("right")].mean(axis=0)
            print(
                f"  {variant}: iterations {info['iterations_per_increment']}, cuts "
                f"{info['cuts']}, first-iterate ratios [{', '.join(first)}], tail orders "
                f"[{', '.join(orders)}], closing orders [{last}], "
                f"{info['evaluations']['tangent']} tangents, {info['evaluations']['residual']} "
                f"forces, {info['mode_searches']} mode searches, "
                f"{best:.2f} s CPU, tip x {tip[0]:.6f} z {tip[2]:.6f} mm, load "
                f"{os.getloadavg()[0]:.1f}"
            )
    floor_lines(args.repeat)
    level_lines(args.repeat, not args.no_coloured)


if __name__ == "__main__":
    main()
