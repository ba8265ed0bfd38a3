"""Speed of an explicit forming run: the hemisphere forming case of the validation report
(validation/cases/hemisphere_forming.py) with a blank of about 20k triangles.

The blank (200 x 200 mm, fibrous shell, ``--cells`` squares along a side, two triangles each)
is pressed by the rigid spherical punch into the meshed die (elements.RigidSurface) over
``--duration`` s of simulated time. Printed: the pieces of one step on the starting state (the
element's force, the contact blocks' forces, a reference pass over the same nodes: one norm
per node), then per run (``--mass-scaling-dt``, a list: "none" for the model's own masses) the
wall and CPU time, the machine's load before and after (/proc/loadavg: the machine may be
shared), the threads (femcore/jit.py), the steps, ms per step and its ratio to the
reference pass, the step size, the mass scaling asked and the mass it added, and the kinetic
energy at the end over the work done (a quasi-static run keeps it small). ``--fraction`` stops
each run at that fraction of the stroke's time (its figures: those of the steps done).

``--phases`` times the pieces of the steps (CPU and wall per step): the element force
passes, the contacts (the meshed die's closest-facet search inside), the cells' and the
assembled stable step, the lumped masses (the rotary inertia refresh every 10 steps), and the
rest taken apart: the external loads, the nodal update (velocities, positions, rotations and
their energy terms), the history commit and the other bookkeeping (the parts' forces summed,
the energy account, the output); it lists each evaluation of the assembled bound with its
ratio to the cells' bound of the model's own masses, and each run prints its mean step and the
whole stroke projected at that pace. Beside each phase's CPU, the main thread's
(``time.thread_time``): a phase split evenly over two threads shows half its CPU there, a
serial one all of it, a measure the machine's load does not blur as it blurs the wall time.
``--threads`` forces a thread count (numba's setting, femcore/jit.py's FOLLOW_LOAD off;
default: the free cores, which at the loads below chose one).

Subnormal numbers, measured at 20k triangles on the first 0.3 % of the stroke (402 steps of
2.24e-6 s), one thread, CPU, main 9864ff6 twice (load 5.9 -> 6.9, 6.9 -> 7.3): 36.82 / 36.83
ms a step: element force 21.06 / 21.84, die 3.51 / 3.58, punch and holder 3.33 / 3.41, the
cells' bound 0.58 / 0.59, the assembled bound 3.84 / 2.92 (its one evaluation), the rotary
inertia 0.36 / 0.37, the rest 4.14 / 4.11 (a profile, load 7.5: the rotations' pass 1.84,
the velocities' 0.63, the external loads 0.25; the energy account, the bookkeeping and the
output next to nothing). A run from rest spreads its disturbance one ring of cells a step;
ahead of the wave the velocities, moments and the directors' in-plane components are tiny,
and their products fall below 2.2e-308 (subnormal numbers), where each operation costs the
processor some hundred cycles. The nodal update's arguments at step 250 held 819 subnormal
velocity components, 1046 in the internal forces, 648 in the moments (of 30606 each): the
update took 2.5-2.7 ms CPU on them against 0.7-0.8 on random data of the same size (load 8).
With the processor's flush-to-zero modes on (FTZ and DAZ, tried), a step took 27.17 against
27.65 ms (load 5.5 / 5.8), the element force 14.9 against 16.5, the nodal update 0.99 against
2.24; the same run to the last bit. The gain is the start's alone: at step 2700 (2 % of the
stroke; 69.0 s of CPU for those steps, load 4-5) no subnormal was left and the element force
took 11.4-11.9 ms with the modes and 11.2-12.7 without (load 4.1): some 20 s of CPU of the
stroke's hour. Not kept: the modes are each thread's processor state, to be set and restored
on every worker of numba's pool, which a work-stealing threading layer (TBB) does not let one
reach for certain, and a thread left flushed would change every later result. What the
measurement leaves: the first fraction of a stroke from rest runs slower than the rest of it,
so a projection from the first 1 % overstates the stroke (the 74-76 min below).

One compiled pass for the whole nodal update (velocities, positions, the directors' turn; the
same numbers to the last bit) was tried and measured no faster than the solver's two passes:
on the captured arguments of step 250, 2.53-3.28 against 2.46-2.97 ms (best of 100, load 8),
in whole runs 2.77 / 2.60 against 2.37 ms (load 9.0 -> 8.5): the update is arithmetic (the
Rodrigues turn, a sine and a cosine a node), not memory traffic, at 10201 nodes. Not kept.

With a table law's energy spliced into the force pass (elements/fibrous/packed_laws.py; the
energy check every 10 steps meets the G986 bending tables twice a cell), ``--fraction 0.003``,
one thread, main c108a2a then after, the die's new lists: 19.97 -> 16.90 ms CPU a step (8.0 ->
6.8 s for the 402 steps, load 6.4 -> 12.7: the machine's noise is most of that difference; the
force is the same to the last bit, and what the checks save is about 1.5 % of these steps'
CPU: 40 checks of 20k cells at some 0.15 µs a cell).

Where the element force goes (a profile of 268 steps at 20k, main, load 7.5, CPU per step):
the cells' pass (tension, shear, bending of each cell, elements/fibrous/kernels.py
``_cells_pass``) 15.7 ms, the pulls' pass 1.8, the sides' folds 1.6, the normals 1.3 (with
the cells' bound's), the normal sums 0.6, the nodal sums of the loads 0.5, of dW/dS_k 0.3,
the nodes' frames 0.16. The cells' pass is three fibre levels of two logarithms, an arcsine
and two roots each, plus the corner terms and the bending: not changed here.

Measured at 20k triangles on the first 1 % of the stroke, one thread, this machine's 2 cores
shared with other work (load 5-12: CPU times, which the load inflates too; the same code ran
17-22 ms CPU per step on a quiet, faster machine), the two side by side in this session:

* before (main 799cc6c; load 5.2 -> 9.1): 3099 steps of 9.68e-7 s on average, 46.4 ms CPU per
  step: element force 16.9 ms (36 %), contacts 14.1 (30 %), the assembled stable step 10.2
  (22 %: evaluated again at every 1 % move of the cells' bound, 4.9 s of CPU each), the rest
  4.4 + 0.8; the stroke at that pace 310k steps, 240 min CPU.
* after (load 11.2 -> 11.6): 1339 steps of 2.24e-6 s, 34.1 ms CPU per step: element force
  15.9 ms (47 %), contacts 11.8 (35 %), the assembled bound 3.6 (one evaluation, 4.8 s), the
  cells' bound 0.47, the rotary inertia 0.32, the rest 2.0; the stroke at that pace 134k
  steps, 76 min CPU (the assembled bound, evaluated at least every 4000 steps, then costs
  about 1.2 ms a step, not 3.6: about 71 min). Again with the die's signed distance compiled
  (below; load 14.3 -> 12.5): the same 1339 steps, 40.1 ms CPU per step, the element force
  19.5 ms (its code unchanged: the load moves these figures by 20 %), the contacts 12.9: the
  whole-run figures do not resolve that last gain.

What changed, each at its cause:

* The step was 2.3 times too short. The assembled Gershgorin bound summed the contacts'
  tangents as well as the elements' while the contact springs were added again apart
  (penalty_frequency_squared), and the holder's springs were bounded by Gershgorin's row sum at
  its node, sum k (1 + sqrt(m_t / m)) / m_t with m_t / m ~ 1e5: 3.6 times the elements'
  omega^2. On the starting blank: the cells' bound 2.85e-6 s, the exact 2 / omega_max of the
  elements 4.10e-6 s (scipy eigsh), their Gershgorin bound 3.99e-6 s (0.97 of it) but 1.54e-6
  s with the contacts summed in; with the springs the solver took 1.33e-6 s x 0.9. Now the
  Gershgorin bound is the elements' (the cells' bound governs, 1.40 times below it) and the
  holder's springs are bounded by max k / m + sum k / m_t (elements/contact.py ``springs``,
  docs/theory.md §9.5): the step 2.24e-6 s on average over the first 1 %.
* The assembled bound (3.3-4.9 s of CPU, the fibrous membrane tangent in numpy most of it)
  was evaluated again whenever the cells' bound moved 1 %; with the cells' bound 1.40 times
  below it, it now waits for a move of half that room (20 %) or 4000 steps.
* The punch's and the holder's contacts run in one compiled pass (elements/tool_contact.py):
  the same forces to the last bit on this case (tests/test_forming_shortcuts_change_nothing.py),
  0.46-0.69 ms CPU a call against about 2 ms each before (all three contacts 11.8 ms against
  14.1 per step). The meshed die is the rest of the contacts' time: its distance query cost
  6-8 ms CPU at this load, the compiled closest-facet search about half of it and the signed
  distance and normal (numpy passes) about a quarter; those now run in one compiled pass
  (elements/facet_search.py ``signed_from_closest``, the same numbers to the last bit): in a
  profile of 60 queries their time fell from 0.52 to 0.17 of the closest-facet search's.

Mass scaling (``--mass-scaling-dt``, selective: only the cells whose step is below the target
get mass), measured at 20 cells on the case's own run (benchmarks/hemisphere_scaling.py), the
unscaled run beside it: 2.4e-5 s (the unscaled step ended at 1.03e-5 s) added 2.5 times the
blank's mass (every cell of this uniform blank raised alike, x3.5; the solver's figure read
0.25 then, of the model's mass with the 100-g holder, nine blanks' mass: it is the elements'
mass since) and took 16289 steps instead
of 27783 (0.59); the rms shear error against the net 2.12 deg instead of 2.01 (the case's
tolerance 2.8), the draw-in 29.44 mm instead of 29.30, the largest KE / W after the first tenth
0.139 instead of 0.128 (above the 0.1 bound over 6.6 % of the stroke instead of 5.8; the case
allows 10 %), the damping's share of the work 22.9 % instead of 21.2 %, the holder's largest
lift 0.28 mm instead of 0.46, the punch force at the end 81 N instead of 61 (that force rings:
61-88 N between runs of the same mesh). At 20k triangles (first 1 %, load 11.6 -> 12.5): 5.5e-6
s adds 3.6 times the blank's mass (its density x4.6; 0.37 of the model's with the holder) and
takes 714 steps of 4.2e-6 s on average instead of 1339 (0.53), 37.0 ms CPU each; the stroke
at that pace 71k steps, 44 min CPU (about 38 with the assembled bound's evaluations spread
over the stroke). Its effect on the compared results at 20k was not run (the full stroke); at
20 cells a like share of added mass stayed within the case's tolerances.

The die's candidate lists (``--die-lists old,new``, each run on a fresh model; ``--rim``,
default the case's DIE_RIM = 10 mm entry radius, which the figures above predate: they ran on
the sharp die). Two changes, each giving the same run to the last bit
(tests/test_forming_shortcuts_change_nothing.py): the lists are searched again in batches
(a node past the margin brings every node past half of it, REBUILD_SHARE) instead of a few
nodes at every step, and between scans a node keeps its nearest facet alone while it lies
within half the gap to the next candidate (KEEP_NEAREST, docs/theory.md §9.3). Measured, one
thread, CPU:

* on the first 0.5 % of the stroke (670 steps of 2.24e-6 s, the 10-mm die, old then new in
  one process; load 8.1 -> 6.4): the die's contact 9.83 -> 6.09 ms CPU a step, the whole step
  42.2 -> 38.2 ms (element force 20.2 both, the others' contacts 3.6, the assembled bound 4.0
  and 3.8 in its one evaluation, the cells' bound 0.6, the rotary inertia 0.4, the rest 3.5);
  no node moved past the margin yet (the punch's smooth start);
* at the stroke's peak pace (``--die-calls 600``: the blank laid on the die sliding 7e-4 mm a
  call, 10089 of its 10201 nodes within the search distance; load 13-15): the die's distance
  13.0 / 13.6 -> 8.4 / 7.8 ms CPU a call (two passes each, alternated), the lists searched
  398 times (14028 nodes) -> 59 times (33648 nodes) in 600 calls. The compiled pass alone,
  same load: 0.9 ms where every node keeps its facet, 7.0 for the scan of every list (the
  nodes' rooms: median 0.026 mm, a quarter below 0.006: many still scan every few steps); the
  rest of the 7.8 ms, not timed apart: the batched searches (56 nodes a call on average) and
  the numpy passes of ``distance``. In a step the die's contact added its formulas in numpy
  (``ContactBlock``); it now takes one compiled pass (below).

The die's contact compiled (elements/tool_contact.py ``surface_forces``): the closest-facet
loop (elements/facet_search.py, as it was), then one pass for each node's signed distance, the
open-edge and far-node answers and k p n; the lists' drift question at every call compiled
(``largest_drift``); the same forces to the last bit (tests/test_tool_contact.py, and a
12-cell forming run bit for bit, tests/test_forming_shortcuts_change_nothing.py); the
closest-facet record kept only once a contact is frozen (Static's stop diagnosis), not on the
explicit path. Measured, one thread, CPU, 300 calls of the die's contact on the 20k blank
laid in the die (``--die-calls``' blank), the reference pass beside, before (7e3a340) and
now, each in a process of its own, one after the other:

* at the stroke's peak pace (7e-4 mm a call; load 5.3 -> 5.6): before 7.3 ms a call, now
  5.9 (the numpy formulas in the same process 6.9);
* the blank all but still (1e-7 mm a call; load 5.7 -> 5.9): before 5.7 (4.3 in an earlier
  pass at load 5.6), now 2.7 (the numpy formulas 3.6).

Where the die's time went nearly still before the drift question was compiled (3.1 ms a
call, a profile): the closest-facet loop 37 % (0.45-0.65 ms on the starting blank where the
nodes keep their facets, more where a node's room is small), numpy reductions (the drift
question, the memory of the last answer) 24 %, the force pass 10 %, the node gather and the
scatter 10 %. At the peak pace the batched searches of the candidate lists (numpy and the
k-d tree) added about 2 ms a call at load 13-15, 0.71-0.88 at load 7-9; their closest points
are now compiled (the section on two threads below). A try that made the two loops one (the
closest-facet loop's body an inlined helper of the pass) made the kept facets' loop 2.4 times
slower (2.2-2.6 against 0.9-1.1 ms on the 10201 nodes, load 6.4): not kept.

Before the drift question was compiled, on the first 0.3 % of the stroke side by side (402
steps each, one thread, before then now; load 8.4 -> 7.7, 7.6 -> 7.4): 37.2 against 36.3
ms CPU a step; element force 20.1 / 18.5, die 5.6 / 6.9 (that try's slower loop), the punch
and holder 3.2 / 3.0, the cells' bound 0.57 / 0.51, the assembled bound 3.5 / 3.3 (one
evaluation, 1.4 s of CPU), the rotary inertia 0.35 / 0.32, the rest 4.0 / 3.8. (7e3a340 as
first run in a fresh worktree, 670 steps, load 6.4 -> 5.9: element 21.9, die 6.2, others
3.6, the assembled bound 74.7 ms a step: its one evaluation compiled the tangent kernels, 50
s of CPU; warm, an evaluation takes 1.35 s of CPU at load 8.2.)

Threads: at the loads of these measurements (4-9 on 2 cores) the default threads chose one (free
cores: femcore/jit.py). Two forced on the element force at 20k (the starting state, 30 calls
a round, one thread then two, three rounds, load 7.8-7.9, the quietest load seen):
median wall 34.8 / 33.6 / 34.3 ms on one thread against 29.2 / 29.6 / 33.0 on two (1.04-1.19
times as fast); again at load 4.8: 26.0 / 25.0 / 26.4 against 24.0 / 21.8 / 22.9 (1.08-1.15;
the best single call 11.2 ms on one thread, 18.5 on two), while the free cores' count said
one: right at that load, where a second thread takes a core another process is using for a
gain of a tenth. The count takes this
process's own CPU share out of the load (tests/test_threads.py: alone and busy on one thread
of two cores, it gives two), so on a machine whose second core is free the element force
runs on both: measured quiet at 1fdf3ac (below, 1.44 x one thread on the whole step), and
phase by phase on the main thread's CPU in the section on two threads below.

The punch's and holder's forces added into the model's sums in place, their node gathers
and totals compiled (elements/node_rows.py), the velocity and rotation updates on the threads
(solvers/dynamics.py, turning.py; benchmarks/threads.py): ``--fraction 0.005 --phases``, one
thread (the default chose one at these loads), main fdcebfd and after in turns, twice, CPU
ms a step (load 6.1-6.6, 7.1-7.6, 9.0-9.8, 10.4-10.9): the step 12.93 / 13.27 -> 12.18 /
12.99; the punch and holder 0.96 / 1.04 -> 0.51 / 0.56; the die 1.66 / 1.71 -> 1.51 / 1.64;
the nodal update 0.64 / 0.65 -> 0.69 / 0.73 (before its index was unsigned: femcore/jit.py
``unsigned``); the element force 7.88 / 8.01 -> 7.74 / 8.20 (unchanged code). On two threads
forced the main thread's share was not measured at 20k; at 100k see benchmarks/threads.py.

The stroke in fewer steps (benchmarks/hemisphere_scaling.py, 20 cells, every setting beside
the unscaled run): time scaling x4 (the stroke in 0.075 s) keeps every check of the case in
0.25 of the steps (rms 2.087 against 2.140 deg, draw-in 28.50 against 28.57 mm, KE / W at most
0.082 against the bound 0.1); mass scaling to 2.4e-5 s with time x2 keeps them in 0.29; with
x4 it does not (KE / W above the bound over 0.28 of the stroke).

Projected at the stroke's pace past its start (the first 2700 steps averaged 25.5 ms CPU a
step, load 4-5; with the subnormals flushed the first 0.3 % ran 28.5-29.9 ms a step at load
6.7-8.3, 25.3-26.7 with the assembled bound's one 1.4-s evaluation spread over its 4000 steps;
the whole x4 stroke measured below averaged 31.6 ms a step at load 2-4 on older code), one
thread: unscaled, 133.8k steps, 56-60 min CPU; at time scaling x2 (the stroke in 0.15 s, 66.9k
steps) 28-30 min; at x4 (33.5k steps) 14-15 min. The 74-76 min that the first 0.3 % gave (36.8
ms a step) was the start's subnormals' figure, not the stroke's. 3 minutes on the 2 cores is 6
min of CPU at most: the x2 stroke is 5 times away, the x4 one 2.5 times. What would close the
rest: the element force is 55 % of a step (15.8-16.8 ms at load 7-8, 11.4-11.9 at load 4, 0.57
us a triangle), so a quieter machine takes 4-5 ms off a step from the element force alone (the
x2 stroke near 24 min of CPU, less as the other pieces shrink too); two threads on the element
force where the second core is free (not measured quiet); the cells' pass itself
(``_cells_pass``, 15.7 of the force's 22 ms in a profile: transcendental functions per fibre
level, not vectorised across cells); the punch's and holder's 2.9-3.1 ms, most of it outside
their compiled passes (the contact blocks' node gathers, 0.34 ms each in a profile, the scatter
by bincount, the copies of the answer kept from memory: elements/contact.py); the die's
2.9-3.2; the external loads (0.2 ms: two (n, 3) arrays of zeros a step, femcore/compiled.py)
and the parts' forces summed into fresh arrays.

Fewer steps than x4 did not keep the case's checks at 20 cells (mass scaling on top of x4).

Measured, the whole 20k-triangle stroke at time scaling x4 (benchmarks/hemisphere_scaling.py
--cells 100 --time-scaling 4: the case's run, one thread, the code before the drift question
was compiled and with the slower kept-facet loop of the try above, about 1.5 ms a step more
in the die than now; load 4.2 -> 2.1): 34884 steps (the step 2.03e-6 s at the end), 1102 s
of CPU (18.4 min), 2021 s wall (33.7 min: the machine shared), 600 MB resident; it reaches
the end; KE / W at most 0.087 after the first tenth (none of the stroke above the bound
0.1), 0.0097 at the end; the damping 1.1 % of the work; the holder did not rise; draw-in of
the edge middle 28.93 mm (the inextensible centre-line range at 100 cells 24.10-29.68); punch
force at the end 88.7 N (20 cells: 56.9-64.4 across the settings); rms shear error against
the net 4.98 deg, against 2.09-2.17 at 20 cells (x4 and the others) and 2.07 unscaled at 32
cells: the fine blank departs from the net more than the coarse ones, and whether the x4
stroke does that (its KE / W 0.087 against 0.082 at 20 cells) or the mesh does (wrinkles the
coarse cells cannot form) would take the unscaled 20k stroke (about 74 min of CPU), not run.
At 40 cells x4 moves the rms from 1.771 to 2.303 deg and the draw-in from 28.58 to 24.75 mm
against the unscaled run (benchmarks/hemisphere_scaling.py), KE / W below the bound throughout
(x2: rms 1.698 deg, draw-in 24.89 mm): x4 is not a safe setting on fine meshes, so the x4
stroke's figures cannot be taken as the 20k mesh's, nor its time as that of a trustworthy
stroke; x2 (or mass scaling alone) would have to be measured beyond 40 cells before it is used.
At 18.4 min of CPU, the stroke is 3 times the 6 min of CPU that 3 minutes on the 2 cores allow,
and 11 times the 3 minutes of wall on one thread.
Quiet (load 0.5-1.0, nothing else running; main 1fdf3ac: the threaded updates, the fibrous
lanes), ``--fraction 0.005 --phases``, unscaled, 670 steps: one thread 11.70 ms a step wall
(11.69 CPU; the element force 7.07, the die 1.59, the other contacts 0.53, the assembled bound
1.07, the nodal update 0.66, the rest 0.33): the stroke at that pace 133.8k steps, 26.1 min;
``NUMBA_NUM_THREADS=2`` 8.11 ms a step wall (11.73 CPU; the element force 3.87 wall, the die
1.22, the assembled bound 1.03, the nodal update 0.51): 1.44 x one thread, the stroke 18.1 min
wall (a first two-thread run, 11.33 ms, paid the parallel builds' compilation in its timed
steps). The issue's 3 minutes on 2 cores is 6 times away unscaled.

What the 0.5 % figures put on a step that the stroke does not: the assembled bound's 1.03-1.07
ms a step is its one evaluation at the start (0.75 s of CPU on one thread, three evaluations
on the starting state, load 10; 0.67 s of it the fibrous tangent's pieces, 0.08 s the
Gershgorin sums of femcore/gershgorin.py) spread over the 670 steps. Over the stroke it is
evaluated again when the cells' bound has moved by half the room it had below it (20 % at
the start, 7 % at 0.9 of the stroke on the 20-cell blank) or after 4000 steps
(solvers/explicit_step_size.py ASSEMBLED_DT_MAX): some 35-40 evaluations in 133.8k steps, 0.2 ms a
step. Those quiet figures so corrected, the stroke would take about 24 min on one thread and
16 min on two (10.8 and 7.3 ms a step); threading the Gershgorin sums would take at most 0.08
s of CPU off each evaluation (1 % of the assembled bound's share), not done.

What sets the step (benchmarks/hemisphere_step_bounds.py, 20k blank at 0.01 of the stroke): the
solver's 2.242e-6 s is 0.546 of the exact 2 / omega_max of the blank (4.103e-6 s, scipy eigsh
on its tangent and lumped masses): the safety 0.9, the cells' bound 0.695 of the exact (the
assembled Gershgorin bound 0.974; at mid-stroke, t = 0.15 s, the step, the cells' bound and
Gershgorin 0.547, 0.691 and 0.939 of the exact 3.979e-6 s), and the tools' springs, counted as
sum over the tools of max k / m (0.644 of the exact omega^2), which lower the cells' critical
step to 0.873 of it, while pressing every node along z by all three tools lowers the exact one
by nothing at the start, by 10.6 % at mid-stroke (20k) and by 8-14 % at 0.5-0.9 of the stroke
(20 cells). A softer automatic penalty does not pay (benchmarks/hemisphere_scaling.py, 20
cells): a quarter of it (PENALTY_SHARE 0.025) took 0.91 of the steps and let the ply 0.41 mm
into the die (0.11 at the default), the corners' draw-in moved 15 %; a tenth, 0.89 of the
steps, the ply 0.82 mm into the die and the edge middle's draw-in out of the case's range. The
assembled bound alone (not the library's rule: the smaller of the two is taken, docs/theory.md
§6.2) would give the step 0.691 of the exact here (2.83e-6 s, 0.79 of the steps; 0.682 at
mid-stroke), 0.834-0.841 of the steps over the whole stroke at 20, 32 and 40 cells with the
compared results within 2 %; at 20k it would have to be evaluated often (every 500 steps: 1.5
ms a step on one thread) for the carried ratio to stay safe, which eats most of the gain.

Two threads, phase by phase (``--threads 1`` and ``--threads 2``, ``--fraction 0.005 --phases``:
670 steps of 2.24e-6 s; main 5523c00 before, then after the three changes below, alternated in
fresh processes, two rounds, load 5.4-6.5; CPU ms a step, "main" the main thread's):

* one thread: the step 10.96 / 10.86 before, 9.90 / 10.83 after (the load's noise as large
  as the gain);
* two threads: the step 11.69 / 12.08 CPU, 7.50 / 7.64 main before; 10.14 / 10.73 CPU, 6.31 /
  6.71 main after. Phase by phase, main / CPU, before -> after: the element force 3.08-3.29 /
  5.93-6.28 -> 2.79-2.99 / 5.35-5.73 (split evenly: some 0.25 ms serial); the die 1.06-1.19 /
  1.86-2.06 -> 0.90-0.98 / 1.59-1.72 (its two compiled loops split; some 0.2 serial: the
  node gathers, the drift question, its answer kept); the punch and the holder 0.53-0.60 /
  0.65-0.73 -> 0.50-0.51 / 0.63 (some 0.4 serial: their passes are a tenth of a ms each, the
  rest the positions' copies, the forces kept for the tools' work asked again, the holder's
  reaction summed in order); the cells' bound 0.255-0.258 (numpy, serial) -> 0.022-0.023 /
  0.041-0.043; the nodal update 0.47-0.49 / 0.78-0.83 -> 0.45-0.47 / 0.77-0.78 (some 0.15
  serial); serial still: the bookkeeping 0.33-0.38, the external loads 0.08-0.10, the rotary
  inertia 0.10-0.11, the assembled bound's one evaluation 1.13-1.55 (0.2 a step over the
  stroke). Serial in all, some 1.5 ms of the 9.9-10.8 ms one-thread step: at most about 1.7 x
  on two free cores. Wall at that load: two threads 15.3 / 19.0 ms before, 13.1 / 16.1 after,
  one thread 14.4 / 18.9 and 10.2 / 20.7: the second core was other processes' (no gain from
  a second thread there, which is why the default takes one);
* at the stroke's peak pace (``--die-calls 400 --threads 1`` / ``2``, three rounds, load
  7.0-9.6): the die's distance on one thread 3.54-4.43 ms CPU a call before (its batched
  searches 0.71-0.88), 2.95-3.57 after (0.47-0.53); on two threads the main thread's
  2.29-2.59 -> 1.68-2.15 ms a call.

The changes, each the same numbers to the last bit on one thread and on two: the cells'
critical steps in one compiled pass over the cells (elements/fibrous/stable_steps.py, numpy's
formulas kept: tests/test_fibrous_stable_steps.py); the batched searches' closest points on the
k-d tree's nearest facets compiled, the tree's queries on the threads (RigidSurface._closest:
numpy's closest_on_triangles and argmin to the last bit, tests/test_facet_search.py; the
candidate lists themselves still from the tree's ball query, whose order decides between equal
distances: a compiled search of another order would not give the same lists); whether a tool
is asked about its last points again, a loop that stops at the first difference
(node_rows.same_rows, 0.14 ms a call of the die before on the main thread).

The stroke on two threads, projected: with its second core free a two-thread step takes at
least its main thread's CPU, 6.31-6.71 ms at the start after (load 5.5), 5.4-5.7 with the
assembled bound's evaluations spread over the stroke (before: 6.1-6.6); a step from the
blank at 0.25 and 0.5 of the unscaled stroke (100 steps of explicit_step from a kept state,
not a mode of this script; load 6.7-9.2) took 5.00-5.92 ms main and 9.1-10.6 CPU after
(5.30-6.04 and 9.2-10.4 before); the quiet wall at 1fdf3ac (8.11 ms, 7.3 with the bound spread)
bounds it from above. Unscaled (133.8k steps) 12-13 min to 16 min; at time scaling x3 (44.6k
steps) 4.0-4.2 to 5.4 min; at x4 (33.5k) 3.0-3.2 to 4.1 min. The issue's 3 minutes on the 2
cores: x4 at the main thread's pace alone, and x4 moved the shear and the draw-in at 40 cells
(above): unscaled, 4 to 5 times away; x2 (66.9k steps, the setting measured safe to 40
cells) 6-8 min. What is left serial is the next share to take: the punch's and holder's numpy
around their passes (0.4 ms), the bookkeeping and the external loads (0.45: fresh (n, 3)
arrays, the parts' sums), the die's 0.2; then the element force itself (5.4-5.9 ms CPU of the
step at these loads, 2.8-3.0 on the main thread).

What sets the step, and what a scaling can take off it (benchmarks/hemisphere_step_parts.py,
main c0b0822): at 20k the cells' bound is the fibres' tension 0.707 of its omega^2, the shear
0.287 (the locking law's largest slope, 61 times its slope where the blank starts), the
bending 0.006; the tools' springs add 0.311 of it. Uniform mass scaling is time scaling by
another name, and the library's ``mass_scaling_dt`` is uniform on this blank (above). A
selective scaling that keeps the translations' inertia (Olovsson, Simonsson, Unosson 2005)
is capped by the springs: a blank pressed between tools moves as a whole against them, which
such a scaling leaves as it is; in the solver's rule at most 2.05 times the step (1.76 at beta
8: the stroke at least 7 min on two threads, 3.5 min with time scaling x2 on top, a linear
solve of the mass a step besides; not written). The shear's slope at each cell's current angle
would give 1.08-1.13 times the step (not done: the automatic penalty is calibrated on the same
bound, so the springs would soften with it).
Run from the project root:

    python benchmarks/hemisphere_forming.py                       # 100 x 100 x 2 = 20k
    python benchmarks/hemisphere_forming.py --mass-scaling-dt none,3.5e-6
    python benchmarks/hemisphere_forming.py --cells 40 --duration 0.05
    python benchmarks/hemisphere_forming.py --fraction 0.2        # the first fifth of it
    python benchmarks/hemisphere_forming.py --fraction 0.01 --phases  # where a step goes
    python benchmarks/hemisphere_forming.py --fraction 0.005 --phases --die-lists old,new
    python benchmarks/hemisphere_forming.py --die-calls 600 --die-lists old,new,old,new
    python benchmarks/hemisphere_forming.py --fraction 0.005 --phases --die-lists new --threads 2
"""

from __future__ import annotations

import argparse
import itertools
import os
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install
os.environ.setdefault("FIBRESHELL_PROGRESS", "0")

from contact_search import best  # noqa: E402

from elements import RigidSurface  # noqa: E402
from elements import rigid_surface as tools  # noqa: E402
from femcore import jit  # noqa: E402
from solvers import CentralDifference  # noqa: E402
from solvers import step as step_module  # noqa: E402
from validation.cases import hemisphere_forming as case  # noqa: E402
from validation.specimens import hemisphere_die  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cells", type=int, default=100)
    parser.add_argument("--duration", type=float, default=case.DURATION)
    parser.add_argument(
        "--mass-scaling-dt", default="none", help='target steps, s, a list ("none": no scaling)'
    )
    parser.add_argument("--safety", type=float, default=0.9, help="the solver's default 0.9")
    parser.add_argument(
        "--fraction", type=float, default=1.0, help="stop at this fraction of the stroke's time"
    )
    parser.add_argument(
        "--phases", action="store_true", help="time the pieces of each step (CPU and wall)"
    )
    parser.add_argument(
        "--die-lists",
        default="old,new",
        help='the die\'s candidate lists, a list: "old" searches again only the nodes past '
        'the margin and scans every candidate at every step, "new" searches in batches '
        "(elements.rigid_surface.REBUILD_SHARE) and keeps a nearest facet while it cannot change "
        "(KEEP_NEAREST); each run is made once per value",
    )
    parser.add_argument("--rim", type=float, default=case.DIE_RIM, help="the die's entry radius")
    parser.add_argument(
        "--die-calls",
        type=int,
        default=0,
        help="only time the die's distance over this many calls on a blank sliding into it",
    )
    parser.add_argument(
        "--threads",
        type=int,
        default=0,
        help="the threads forced (numba's setting, femcore/jit.py's FOLLOW_LOAD off); 0: "
        "femcore/jit.py's choice (the free cores)",
    )
    args = parser.parse_args()
    if args.threads:
        import numba

        numba.set_num_threads(args.threads)
        jit.FOLLOW_LOAD = False
    if args.die_calls:
        die_pace(args.cells, args.rim, args.die_calls, args.die_lists.split(","))
        return
    mesh, model = case.model(args.cells, "fibrous", rim=args.rim)
    compiled = model.compile()
    print(f"blank: {mesh.n_triangles} triangles, {mesh.n_nodes} nodes; punch travel "
          f"{case.PUNCH + case.THICKNESS} mm in {args.duration} s")  # fmt: skip

    # The pieces of one step, timed on the reference state: the element, the contacts, a
    # reference pass.
    state = compiled.initial_state()
    shell = list(range(len(compiled.blocks)))  # compiled.parts: the blocks, then the contacts
    contact_blocks = list(range(len(compiled.blocks), len(compiled.parts)))

    compiled.internal_force(state)  # compiles the kernels and fills the tools' caches
    element = best(lambda: compiled.internal_force(state, shell), 20)
    # Two states in turn: the meshed tool answers the same points asked again from memory.
    nudged = replace(state, positions=state.positions + 1e-6)
    turns = itertools.cycle([state, nudged])
    contact = best(lambda: compiled.internal_force(next(turns), contact_blocks), 20)
    reference = best(lambda: np.linalg.norm(state.positions, axis=1), 20)
    n = mesh.n_nodes
    print(f"per step: element force {element * 1e3:.2f} ms ({element / mesh.n_triangles * 1e6:.3f} "
          f"us/triangle), contact forces of {len(contact_blocks)} tools {contact * 1e3:.2f} ms "
          f"({contact / n / len(contact_blocks) * 1e6:.3f} us per node and tool), reference pass "
          f"{reference * 1e3:.3f} ms")  # fmt: skip

    threads = jit.threads_for(mesh.n_triangles)
    # The steps, counted where the solver accepts each (a run stopped early has no result).
    steps = [0]
    reached = [0.0]  # the time of the last step accepted, s

    def counting(commit):
        def counted(new_state):
            steps[0] += 1
            reached[0] = new_state.time
            return commit(new_state)

        return counted

    def stop_early(frame) -> dict:
        if frame.time >= args.fraction * args.duration * (1.0 - 1e-9):
            raise _Enough
        return {}

    runs = itertools.product(args.mass_scaling_dt.split(","), args.die_lists.split(","))
    for target, lists in runs:
        scaling = None if target.strip().lower() == "none" else float(target)
        die_lists(lists)
        # A fresh model per run: the die's candidate lists start empty in each.
        compiled = case.model(args.cells, "fibrous", rim=args.rim)[1].compile()
        compiled.commit = counting(compiled.commit)  # type: ignore[method-assign]
        solver = CentralDifference(
            duration=args.duration,
            safety=args.safety,
            damping=case.DAMPING,
            mass_scaling_dt=scaling,
            progress=False,
            # --fraction is looked at on each frame: a frame at least every 1 % and at it.
            output_interval=args.duration * min(0.01, args.fraction)
            if args.fraction < 1.0
            else None,
            frame_summary=stop_early if args.fraction < 1.0 else None,
        )
        load_before = load()
        steps[0] = 0
        phases = Phases(compiled) if args.phases else None
        start, cpu, own = time.perf_counter(), time.process_time(), time.thread_time()
        try:
            result = solver.solve(compiled)
        except _Enough:
            result = None
        wall, cpu = time.perf_counter() - start, time.process_time() - cpu
        own = time.thread_time() - own
        per_step = wall / steps[0]
        print(f"run, mass scaling {scaling}, the die's lists {lists}, {args.fraction:g} "
              f"of the stroke: {wall:.1f} s wall, "
              f"{cpu:.1f} s CPU on {threads} threads (load {load_before} -> {load()}), "
              f"{steps[0]} steps, {per_step * 1e3:.2f} ms per step ({cpu / steps[0] * 1e3:.2f} "
              f"ms CPU; {per_step / reference:.0f} x the reference pass)", flush=True)  # fmt: skip
        stroke = args.duration / (reached[0] / steps[0])  # steps at the mean step so far
        print(f"  mean step {reached[0] / steps[0]:.3g} s: the stroke at this pace {stroke:.0f} "
              f"steps, {stroke * cpu / steps[0] / 60:.1f} min CPU, {stroke * per_step / 60:.1f} "
              "min wall", flush=True)  # fmt: skip
        if phases is not None:
            print(phases.report(wall, cpu, own, steps[0]), flush=True)
            phases.undo()
        if result is not None:
            energies = {key: values[-1] for key, values in result.energies.items()}
            ratio = energies["kinetic"] / max(abs(energies["external_work"]), 1e-300)
            quasi = result.info["quasi_static"]
            print(f"  dt {result.info['dt']:.3g} s at the end, added mass "
                  f"{result.info['added_mass_ratio']:.3g} x the blank's, kinetic / work at the "
                  f"end {ratio:.3f}, largest after the first tenth "
                  f"{quasi['kinetic_over_work_largest']:.3f} (above the bound over "
                  f"{quasi['exceeded_share']:.3f} of the stroke), punch force "
                  f"{result.tool_forces[-1, 1, 2]:.3g} N, converged {result.converged}",
                  flush=True)  # fmt: skip


NEW_LISTS = (tools.REBUILD_SHARE, tools.KEEP_NEAREST)


def die_lists(which: str) -> None:
    """The die's candidate lists as they were ("old") or are ("new")."""
    if which.strip() not in ("old", "new"):
        raise ValueError(f'--die-lists takes "old" and "new", got {which!r}')
    old = which.strip() == "old"
    tools.REBUILD_SHARE, tools.KEEP_NEAREST = (1.0, False) if old else NEW_LISTS


def die_pace(cells: int, rim: float, calls: int, kinds: list[str]) -> None:
    """The die's distance (RigidSurface.distance, its candidate lists) at the stroke's peak
    pace, for each of ``kinds`` ("old", "new": ``die_lists``): the blank's nodes laid on the
    die (on the bowl half a ply inside it, on the flange half a ply above it) slide towards
    the axis by SLIDE mm a call, each call a step (the punch at its peak speed, 0.31 m/s,
    moves 7e-4 mm in a step of 2.24e-6 s), from a slide of 5 mm. Printed for each: CPU per
    call, the searches and the nodes searched, and a reference pass; one process, the same
    calls."""
    mesh = case.model(cells, "fibrous", rim=rim)[0]
    radius = case.DIE - 0.5 * case.THICKNESS  # the bowl's surface less half a ply, mm
    r0 = np.linalg.norm(mesh.points[:, :2], axis=1)
    angle = np.arctan2(mesh.points[:, 1], mesh.points[:, 0])

    def laid(slide: float) -> np.ndarray:
        r = np.maximum(r0 - slide, 0.0)
        z = np.where(r < radius, -np.sqrt(np.maximum(radius**2 - r**2, 0.0)), 0.5 * case.THICKNESS)
        return np.column_stack([r * np.cos(angle), r * np.sin(angle), z])

    reference = best(lambda: np.linalg.norm(mesh.points, axis=1), 20)
    for kind in kinds:
        die_lists(kind)
        die = RigidSurface(hemisphere_die(case.DIE, 1.7 * case.HALF, rings=48, rim=rim))
        die.distance(laid(5.0))  # the lists built
        searches = [0, 0]
        search = die._searched

        spent = [0.0]  # CPU in the searches, s

        def counted(local, rows, cache, search=search, searches=searches, spent=spent):
            searches[0] += 1
            searches[1] += int(np.count_nonzero(rows))
            cpu = time.process_time()
            try:
                return search(local, rows, cache)
            finally:
                spent[0] += time.process_time() - cpu

        die._searched = counted  # type: ignore[method-assign]
        positions = [laid(5.0 + SLIDE * (call + 1)) for call in range(calls)]
        before = load()
        wall, cpu, own = time.perf_counter(), time.process_time(), time.thread_time()
        for x in positions:
            die.distance(x)
        wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
        own = time.thread_time() - own
        near = int(np.count_nonzero(~die._cache.far))
        print(f"die, {kind} lists: {cpu / calls * 1e3:.3f} ms CPU a call ({own / calls * 1e3:.3f} "
              f"on the main thread, {wall / calls * 1e3:.3f} wall; the searches "
              f"{spent[0] / calls * 1e3:.3f} CPU) over {calls} calls on "
              f"{jit.threads_for(mesh.n_nodes)} threads ({mesh.n_nodes} nodes, {near} within "
              f"the search distance; load {before} "
              f"-> {load()}), {searches[1]} nodes searched in {searches[0]} searches; the "
              f"reference pass {reference * 1e3:.3f} ms", flush=True)  # fmt: skip


# mm a call of die_pace: the punch's peak speed times the step, 0.31 m/s x 2.24e-6 s
SLIDE = 7e-4


class _Enough(Exception):
    """Raised to stop a run at ``--fraction`` of its stroke."""


class Phases:
    """CPU and wall time spent in the pieces of the steps, by wrapping (on the instances)
    the element blocks' force passes, the contact blocks' (the closest-facet search inside),
    the cells' and the assembled stable step and the lumped masses (the rotary inertia
    refresh); the rest of a step is the solver's own update and bookkeeping."""

    def __init__(self, compiled) -> None:
        self.spent: dict[str, list[float]] = {}
        self.inside: dict[str, list[int]] = {}
        self.wrapped: list[tuple[object, str]] = []
        self.restored: list[tuple[object, str, object]] = []
        # Each evaluation of the assembled bound: (time, the bound, the cells' bound), s.
        self.assembled: list[tuple[float, float, float]] = []
        evaluate, cells = compiled.assembled_stable_dt, compiled.cell_stable_dt

        def logged(state, mass, inertia):
            value = evaluate(state, mass, inertia)
            cell = min(float(dt.min()) for dt in cells(state))
            self.assembled.append((state.time, value, cell))
            return value

        object.__setattr__(compiled, "assembled_stable_dt", logged)  # timed below, undone once
        for block in compiled.blocks:
            for name in ("internal_force", "internal_force_and_energy"):
                self._wrap(block, name, "element force")
        # Inside the die's contact: its candidate lists' searches (counted apart from the rest).
        self.nested = {"  of which the die's searches"}
        self.searched = [0, 0]  # the die's searches and the points searched in them
        for interaction in compiled.interactions:
            tool = getattr(interaction, "tool", None)
            meshed = isinstance(tool, RigidSurface)
            # (add_internal_force: how the model sums a contact's forces; the protocol's
            # default calls internal_force, timed once: ``_wrap``)
            for name in ("internal_force", "add_internal_force", "strain_energy", "tool_work"):
                self._wrap(interaction, name, "contact (die)" if meshed else "contact (others)")
            if meshed:
                self._wrap(tool, "_searched", "  of which the die's searches", self._count)
        self._wrap(compiled, "cell_stable_dt", "stable step (cells)")
        self._wrap(compiled, "assembled_stable_dt", "stable step (assembled)")
        self._wrap(compiled, "lumped_mass", "rotary inertia refresh")
        # The rest taken apart: the external loads, the parts' forces summed, the nodal update
        # (velocities, positions, rotations and their energy terms), the history commit.
        self._wrap(compiled, "external_load", "rest: external load")
        self._wrap(compiled, "commit", "rest: commit")
        for name in ("update_rates", "turn"):
            self._wrap(step_module, name, "rest: nodal update", module=True)

    def _count(self, local, rows, cache) -> None:
        self.searched[0] += 1
        self.searched[1] += int(np.count_nonzero(rows))

    def _wrap(self, owner, name: str, phase: str, count=None, module: bool = False) -> None:
        method = getattr(owner, name, None)
        if method is None:
            return
        totals = self.spent.setdefault(phase, [0.0, 0.0, 0.0])
        inside = self.inside.setdefault(phase, [0])  # a timed call of the phase under way

        def timed(*args, **kwargs):
            if count is not None:
                count(*args, **kwargs)
            if inside[0]:  # called from another of the phase's timed calls: counted there
                return method(*args, **kwargs)
            inside[0] += 1
            wall, cpu, own = time.perf_counter(), time.process_time(), time.thread_time()
            try:
                return method(*args, **kwargs)
            finally:
                inside[0] -= 1
                totals[0] += time.perf_counter() - wall
                totals[1] += time.process_time() - cpu
                totals[2] += time.thread_time() - own

        if module:  # a module's function: put back as it was by ``undo``
            setattr(owner, name, timed)
            self.restored.append((owner, name, method))
            return
        object.__setattr__(owner, name, timed)
        self.wrapped.append((owner, name))

    def undo(self) -> None:
        for owner, name in self.wrapped:
            object.__delattr__(owner, name)
        for owner, name, method in self.restored:
            setattr(owner, name, method)

    def report(self, wall: float, cpu: float, own: float, steps: int) -> str:
        """The phases' figures per step; ``own``: the main thread's CPU (s) over the run."""
        outer = [value for phase, value in self.spent.items() if phase not in self.nested]
        rest = [
            wall - sum(w for w, _, _ in outer),
            cpu - sum(c for _, c, _ in outer),
            own - sum(o for _, _, o in outer),
        ]
        rows = [*self.spent.items(), ("rest: the other bookkeeping", rest)]
        # The main thread's CPU beside the process's: a phase that runs on two threads
        # evenly shows about half on the main thread, a serial one all of it (a measure the
        # machine's load does not blur, as it does the wall time).
        lines = [
            f"  {phase:28s} {w / steps * 1e3:7.3f} ms wall {c / steps * 1e3:7.3f} ms CPU "
            f"({o / steps * 1e3:7.3f} on the main thread) per step ({c / max(cpu, 1e-300):5.1%} "
            "of the CPU)"
            for phase, (w, c, o) in rows
        ]
        lines.append(
            f"  the die searched again {self.searched[1]} nodes in {self.searched[0]} batches "
            f"({self.searched[1] / steps:.1f} nodes a step)"
        )
        ratios = ", ".join(f"{t:.3g} s: {a / c:.3f}" for t, a, c in self.assembled)
        lines.append(
            f"  the assembled bound evaluated {len(self.assembled)} times; its ratio to the "
            f"cells' bound then: {ratios}"
        )
        return "\n".join(lines)


def load() -> str:
    """The 1-minute load average (/proc/loadavg), '?' where there is none."""
    try:
        return Path("/proc/loadavg").read_text().split(" ")[0]
    except OSError:
        return "?"


if __name__ == "__main__":
    main()
