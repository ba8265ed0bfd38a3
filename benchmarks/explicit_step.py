"""The explicit step taken apart: where its time goes, what the model costs to build and hold.

On the pinned square sheet of ``shell_sheet.py`` (5 mm cells, gravity from rest) of the
Mindlin shell (aluminium, h = 1 mm) or the fibrous shell (G986 stack), for each size:

* build: seconds (wall and CPU) for ``Model.compile``, the resident memory it added and the
  process's peak, kB per triangle;
* the steady step: ``CentralDifference`` over ``--steps`` (at least ``--work`` element-steps)
  and over twice as many, the difference of the two times per added element-step (what a
  long run costs a step: the run's start, its first and last frames left out), wall and CPU,
  against the reference pass; and the shorter run's whole time per element-step as
  ``shell_sheet.py`` reports it;
* per-phase CPU times at the sheet's state after the run (best of ``--repeats``, µs per
  element): the internal force, the force with the strain energy
  (``internal_force_and_energy``: what a step that checks the energy balance asks), the
  strain energy alone, the rest of a step (``explicit_step`` less its force), a checked step,
  the commit of a step (the blocks' history: the fibrous fold branch) after a first one;
* the numpy reference pass of ``shell_sheet.reference_pass`` (wall, best of 20) and the same
  in CPU time.

On one thread the CPU time is what the step costs whatever the other processes of a shared
machine take (their caches and memory traffic still count); the wall time is what a user
waits.

Measured on the project's 2-core machine shared with other busy processes (load average 5-6:
wall times about 2.5 x the CPU times), Mindlin shell, one thread, before this renovation
(main 3698780) and after it, µs per element-step of CPU (wall in brackets):

    size   steady step                  x ref.      force+energy  rest of step  build, s
    10k    0.27 (0.81) -> 0.11 (0.24)   3.5 -> 1.6  0.20 -> 0.07  0.08 -> 0.02  0.31 -> 0.03
    100k   0.26 (0.77) -> 0.11 (0.31)   3.4 -> 1.4  0.19 -> 0.08  0.07 -> 0.02  3.2 -> 0.26
    400k   0.37 (issue) -> 0.12 (0.42)  1.2                                     ~15 -> 1.6

Memory (kB per triangle, the model's resident memory after the build; the process's peak at
400k, the interpreter's 176 MB included): 3.7 -> 0.96 resident; peak 7.4 (issue) -> 1.9 with
a given dt and 2.7 with the solver's own (its assembled stable step holds the node pairs'
5 x 5 sums, 0.7 kB a triangle). The assembled stable step at 100k: 6.2 -> 0.7-1.8 s of CPU;
the cells' calibration 6.6 s -> 0.2 s (cells of one shape share one eigenvalue problem). Two
threads gave the one-thread figures at that load (the threads follow the free cores). The
fibrous shell with its force kernel as on main, 100k: steady step 1.10 -> 0.77 µs of CPU, the
rest of a step 0.070 -> 0.034, build 0.77 -> 0.47 s (its energy still a pass of its own here:
the block's ``internal_force_and_energy`` is the fibrous kernel's to fuse).

The solver's own stable step at 400k (``--memory --sizes 400000 --steps 10``: a fresh process
per case, one thread, the peak over the whole process, interpreter included), on a 2-core Intel
Xeon (AVX-512) at a load of 7-10, before (main 549fe00, a second checkout) and after the
Gershgorin bound sums a node's row as soon as the tangent's pieces have left it
(femcore/gershgorin.py) and the Mindlin pieces gather their own corners only: Mindlin peak
1071-1107 MB (2.74-2.84 kB a triangle) -> 763 MB (1.96; with a given dt 738 MB, 1.89), the
bound the same to the last bit (3.7145469669250825e-07 s at 100k, 3.7143016430062914e-07 at
30k), its CPU time at 100k 1.20-1.22 -> 1.27-1.45 s (best of 3, old and new in turns: the
pairs of each piece merged with those held); build 2.6-2.8 s CPU (6-7 s wall at that load).
The fibrous shell there: peak 12785 MB (32.8 kB a triangle) before and after, all of it the
tangent that the assembled bound asks for (elements/fibrous/tangent.py forms the membrane's
and the bending's blocks of all cells at once; ``tangent_pieces`` gives them in one piece);
with a given dt 729 MB (1.87 kB a triangle, the build's own peak); build 4.4-4.8 s CPU
(10-11 s wall) in a fresh process, the cached loops loaded in it.

The fibrous tangent a slice of cells at a time (elements/fibrous/tangent_pieces.py: per 4096
cells the membrane's J^T H_C J on the slice's halo and its bending patches, summed into the
node pairs' rows and dropped), same machine, load 3.5-7, one thread: the 400k sheet with the
solver's own step peaks at 777 MB (1.99 kB a triangle; 12785 MB, 32.8, before), build 3.5-4.2
s CPU (5.7-7.2 s wall). The assembled bound alone at 100k (``assembled_stable_dt`` at the
initial state in a fresh process, old (main b2c069b, a second checkout) and new in turns, load
2.2-3.0): peak 3336 MB -> 442-448 MB (the interpreter's 127 MB included), CPU 10.0-11.2 s ->
6.0-6.2 s, the bound 1.0861103818624533e-05 s both times, to the last bit (the pieces add a
node pair's blocks slice by slice: equal to round-off in general).

The fibrous build (``--build``: ``Model.compile`` of the sheet alone in a fresh process, one
thread, the loops compiled on a small sheet first), on the 2-core AMD EPYC machine, CPU time,
before (main 40ae4af, a second checkout) and after, the same construction timed in turns in
fresh processes, three rounds at a load of 2.7-2.9: 400k triangles 3.78-3.91 s -> 2.47-2.53 s
(an earlier pair at a load of 5-6, without the reference geometry's change below: 2.96 ->
1.56 s); ``--build`` itself after: 0.62 s at 100k, 2.40 s at 400k (3.66 s wall, load 5).
What went: the fibre frame of each cell by one
compiled loop (elements/fibrous/fibre_kernels.py; the numpy order forms some thirty (m, 3)
temporaries) 0.47-0.62 -> 0.03 s, and the shear signs 0.15 -> 0.004 s; the triangle checks
on points and cells validated once (not once per check), repeated nodes and edge keys found
without sorting rows, 0.69-0.71 -> 0.46-0.52 s; the wall nodes from the block's own node
mask instead of ``np.unique`` of the connectivity, apply_supports 0.39-0.41 -> 0.16 s; the
norms and dot products of the reference geometry without numpy's reductions over an axis of
3 (the same numbers to the last bit), fibre lengths 0.26-0.29 -> 0.14-0.19 s. The built
model's arrays (every array of the compiled model and of the block, compiled and numpy
kernels, nodal and element normals, a clamped edge) are the same to the last bit as before
at 20k. Where the 400k build's 2.5 s go now: the reference geometry 0.52-0.60 s, the
triangle checks 0.46-0.52 (the duplicate-node search by a k-d tree a third of it), the
block's topology 0.17, apply_supports 0.16, the median edge 0.14, the fibre lengths
0.14-0.19.

The fibrous force with its folds once per side and its corner terms once per node
(elements/fibrous/kernels.py), Intel Xeon, one thread, ``--element fibrous --sizes 100000
--repeats 3`` on main 78b2577 (a second checkout) and after, one after the other, load
5.8-6.1, µs of CPU: force 0.589 -> 0.498, force+energy 0.752 -> 0.574, energy 0.440 -> 0.350,
steady step 1.039 -> 0.743 (4.8 -> 3.9 x the reference pass, 0.217 / 0.192), whole run of
100 steps 0.677 -> 0.704 (the steady step is noisy at that load; paired in one process the
step is 0.933 of before, median of 20 rounds, benchmarks/fibrous_shell.py).

The fibrous 400k peak after the side pass (``--memory --sizes 400000 --steps 10``, one
thread, each revision in a checkout of its own with a numba cache of its own, run twice and
the second, warm, run kept; the first compiles the loops inside the process and peaks higher:
1044 MB on main 78b2577, 939 MB on main 2c4bff8, and so does the first run after a checkout
or merge that touches a kernels' module, whose cached loops numba then drops, its cache
being keyed on the source file's time stamp and size), 2-core machine at a load of 3-7: main
78b2577 760 MB (1.947 kB a triangle), main 2c4bff8 787 MB (2.018), after 758-761 MB
(1.942-1.951). What it was: the side table of the fold angles once per side (supports.py
``shared_sides``), held by the block, six int64 columns and a float sign per side, 27 + 4.6
MB at 400k (598533 sides), of which the cell across, its side and the side's two nodes are
in the block's own tables (``across_cell``, ``across_side``, the connectivity); it now holds
each side's cell and side (int32) and an int8 sign, 4.6 + 0.6 MB, the forces the same to
the last bit. The run's peak is reached in the build (``Model.compile`` of the 400k sheet
alone in a fresh process, after: 771 MB peak, 538 MB kept at its end, load 6), so whatever
the block holds from its side tables on counts in it.
The Mindlin shell on the same code and machine (load 6-7), not regressed: peak 709 MB
(1.816 kB a triangle; 741 MB, 1.899, on the run that compiled its loops), build 2.64 s CPU
in that run; ``--build --sizes 400000`` 2.14-2.18 s CPU (7.5-7.8 s wall), +356 MB resident.

With the subnormal numbers flushed to zero while the runs stepped (tried, not kept:
benchmarks/hemisphere_forming.py), the fibrous force kernel itself unchanged. ``--element
fibrous --sizes 10000,100000 --repeats 3``, one thread, main 9864ff6 (a second checkout) and
after, one after the other, µs of CPU an element-step: steady step at 10k 1.133 (load 8.2) ->
1.007 (load 6.9) and 1.200 (load 9.4, a test run beside it), at 100k 1.112 (load 6.6) -> 1.089
(load 9.2); the force alone at 10k 1.032 -> 0.770 / 0.909, at 100k 0.938 -> 0.891: the same
within this machine's noise at these loads (the sheet falls under gravity from rest, every node
at once: no wave front of tiny rates, unlike the forming blank pressed at its centre,
benchmarks/hemisphere_forming.py).
The force's 0.498 µs at 100k above was measured at load 6 on the Intel machine; 0.35 was not
reached.

The energy check (elements/fibrous/packed_laws.py: a table law's energy, the G986 bending
laws', from the integrals at the knots tabled by ``pack_laws``, spliced into the loops instead
of a compiled call that summed the trapezoids twice), the AMD EPYC machine (znver4, AVX-512,
numba without SVML), one thread, CPU, main c108a2a against after. Paired in one process (the
kernels.py, cell_terms.py and packed_laws.py of c108a2a imported beside, in turns, 16-24
rounds, 100k, load 3.9-5.4): force and energy 0.72-0.75 of before (best 0.50-0.52 -> 0.36-0.38
µs per element), the energy alone 0.61-0.65 (0.36-0.37 -> 0.22-0.24), the force the same, the
forces and energies the same to the last bit; at 10k (30 rounds, load 10-12) 0.75 and 0.68.
This script, before then after (load 5.0-5.5):
10k force+energy 0.834 -> 0.478, energy 0.509 -> 0.293, checked step 0.901 -> 0.491, steady
step 0.592 -> 0.520; 100k force+energy 0.560 -> 0.490, energy 0.435 -> 0.278, checked step
0.588 -> 0.483, steady step 0.548 -> 0.505 (the force 0.39-0.53 in these runs: the load's
noise). A checked step now costs what a step does, give or take the noise.

Where the fibrous force's 0.32-0.34 µs per element go at 100k (the same process): the cells'
pass about 0.2, the other passes 0.14 (normals 0.024, sides' folds 0.03, normal sums and
frames 0.025, pulls 0.036, nodal sums 0.02). A perf profile of the cells' pass (its machine
code mapped to the samples): about 10 % in libm's log and asin, the rest the scalar arithmetic
of the corner terms, the three levels and the bending, some thousand double operations a
cell, one lane at a time, the roots and divisions of 1 / (|g1| |g2|), of the shear's 1 / sin
and of the strains' shared reciprocal on the longest chains. Measured and not kept (force,
paired, median new / old):

* numba's numpy error model (no zero test before each division): 0.98;
* fastmath {"contract"} (multiply-adds fused): 0.96; besides, a serial and a parallel build
  might fuse differently, and the bits must not depend on the thread count;
* the log of the strains' ratio and the shear's arcsine by their series near 1 and 0 (no
  call into libm in the level loop, exact to double precision within |u| <= 0.1, |x| <=
  0.125): 1.04, slower (a division and eight multiply-adds against the library's log);
* the levels' log and arcsine replaced by plain arithmetic (wrong, timed only: what the nine
  calls a cell and the registers saved around them can cost at most): 0.93;
* the cells' helpers that read arrays (cell_terms.py ``cell_cross``, ``corner_frame``,
  ``corner_thickness``, ``wall_fold``) spliced by numba rather than inlined by LLVM: 0.92 /
  0.96, and with one node pass that sums S_k and forms the frames (no (n, 3) sums between
  two passes): 0.98 / 0.96; the same bits;
* the bending tables' segment found by counting the knots at or below the curvature (no
  branch on its sign, which changes from cell to cell) instead of a binary search: 0.99.

What is left is the arithmetic itself: SIMD across cells (structure-of-arrays loops that LLVM
turns into 8-wide AVX-512 code) needs the transcendental functions out of those loops (numba
here has no SVML, and its scalar log, asin and atan2 keep a loop scalar): not done. The Mindlin
shell on the same tree (100k, load 5.1): steady step 0.124 µs CPU, 1.2 x the reference pass
(0.100), force 0.089, force+energy 0.105, the rest of a step 0.032.

The fibrous force toward 0.35 µs a step, tried after main 544e521 and not kept (nothing paid
5 %); the AMD EPYC machine (znver4, AVX-512), one thread, CPU. Main itself, ``--element
fibrous --sizes 100000`` at a load of 5.9: steady step 0.453 (4.7 x the reference pass,
0.096), force 0.374, force+energy 0.419, energy 0.278, the rest of a step 0.027 (0.439, 0.369,
0.413, 0.274, 0.021 on a quiet machine, load 0.5-1.3); the 20k hemisphere
(benchmarks/hemisphere_forming.py ``--fraction 0.003``) 14.82 ms CPU a step (the element force
6.29 ms), load 6.4-7.0. Where the force goes (benchmarks/fibrous_shell.py's passes, load 3):
the cells' pass 0.246 µs a cell of 0.43, of which the three fibre levels are 0.16 (the levels
skipped: 0.585 of the force) and the bending 0.04 (0.899); the normals 0.036 and the sides'
folds 0.042, their arctan2 calls 0.05 (0.880 with them replaced by arithmetic); the pulls 0.044;
the nodal sums 0.03. The force costs the same per cell at 2k, 10k and 100k triangles (0.41,
0.40, 0.40 at a load of 4): the cells' data stay in the caches that matter; the pass is the
processor's scalar arithmetic.

* Intel's vectorised functions (SVML) cannot be had here: llvmlite's PyPI wheel is built
  without numba's SVML patch of LLVM (``numba -s``: "llvmlite Using SVML Patched LLVM: False";
  benchmarks/vector_maths.py prints it), so installing icc-rt or intel-cmplr-lib-rt switches
  nothing on; numba's conda build of llvmlite has the patch, which pip cannot install.
  LLVM 22 does vectorise a loop of ``np.log`` and ``np.arcsin`` 8 lanes wide
  (``llvm.log.v8f64``) and its code generator then calls the scalar library function lane by
  lane; glibc's vector functions (libmvec, asked for by ``-vector-library=LIBMVEC-X86``
  through llvmlite before numba loads) were not called either.
* The library's functions in a compiled loop (benchmarks/vector_maths.py, load 6.8), ns a
  value: log 3.4, arcsin 4.0, arctan2 11.7, arctan 7.9, 1 / sqrt 3.7 (0.9 with numba's numpy
  error model, which lets LLVM vectorise it), a multiply-add 0.2.
* Paired in one process against main's kernels (benchmarks/kernel_pairs.py; its docstring has
  the table): numba's numpy error model 1.025, fastmath {"contract"} 0.984, the corner and fold
  angles by Cephes' arctangent in plain arithmetic (two divisions, 2 units in the last place
  of numpy's) 1.003 with branches and 1.024 with selects, the cells' index unsigned 1.021: all
  within the noise of loads 2.6-6.5. The laws of the levels cost nothing measurable (1.003 with
  them replaced by c x).
* A structure-of-arrays probe of the level strains (64 cells a chunk in a scratch array,
  vectorised by LLVM as its IR showed) ran at 0.103 µs a cell for the three levels with the
  library's log and arcsin and 0.034 without them, the same as the scalar loop: not pursued.

The fibre levels, the corner angles and the sides' folds as loops across chunks of 32 cells
(elements/fibrous/level_lanes.py; their log, arcsine and arctangent branch-free,
elements/lane_maths.py; what each step gave: benchmarks/vector_maths.py), the same machine,
one thread, CPU, main 9d2b4be and this tree in turns, two runs each of ``--element fibrous
--sizes 100000`` at a load of 7.9-9.1, µs per element-step (main -> this tree): steady step
0.448 / 0.547 -> 0.366 / 0.388 (3.7-3.9 x the reference pass, 0.10), force 0.380 -> 0.319 /
0.321, force+energy 0.424 / 0.426 -> 0.341 / 0.346, energy 0.275 / 0.279 -> 0.196 / 0.198,
checked step 0.451 / 0.536 -> 0.366 / 0.371; the forces within 7.3e-15 of main's (of the
largest), the energies 4.7e-19. Paired in one process against main (benchmarks/kernel_pairs.py,
12 rounds, load 11.6-12.2): the force 0.791 (quartiles 0.759-0.821; best 0.406 -> 0.314),
force+energy 0.769 (0.764-0.775), energy 0.686 (0.677-0.695). Not reached: the issue's 0.35
µs a step on one core (main's 0.439 on a quiet machine would be about 0.36 by these ratios);
what is left of the force is the scalar work around the lanes (the corner frames, director
moments and forces, the bending with its tables, the sides' gathers), which vectorises only
with its gathers and scatters done apart (the pulls' pass so done gave 0.981: not kept).
Quiet (load 0.83-0.98, nothing else running), the merged tree (7fd0cbe: the lanes, the
threaded updates) and main before them (fdcebfd) in turns, two runs each, ``--element
fibrous --sizes 100000``, one thread, µs of CPU an element-step: steady step 0.430 / 0.442 ->
0.346 / 0.371 (3.5-3.7 x the reference pass, 0.095-0.100), force 0.374 / 0.386 -> 0.321 /
0.311, force+energy 0.420 / 0.424 -> 0.337 / 0.339, energy 0.272 / 0.273 -> 0.201 / 0.193,
step less force 0.024 / 0.040 -> 0.012 / 0.025: at the issue's 0.35 in one run of two, 0.371
in the other.

The director moments, dW/dS_k and corner forces of the cells' pass as one more loop across
the chunk (level_lanes.py ``moment_lanes``; before, cell by cell after the levels, each
corner's frame read a second time: 0.18 of the force's time, by the pass timed without
them), the AMD EPYC machine, one thread, CPU, the forces and energies the same to the last
bit. Paired in one process against main d004b4e (benchmarks/kernel_pairs.py, 10 rounds, load
11.4-11.6): the force 0.845 (quartiles 0.834-0.852; best 0.340 -> 0.287 µs a cell),
force+energy 0.856 (0.854-0.861). This script, main d004b4e and this tree each exported to a
folder of its own and run in turns, five rounds of ``--element fibrous --sizes 100000``
(load 7.3-12.6, other runs beside them), µs per element-step (main -> this tree): steady
step 0.377 / 0.385 / 0.387 / 0.387 / 0.401 -> 0.327 / 0.337 / 0.353 / 0.329 / 0.343 (3.3-3.4
x the reference pass, 0.10), force 0.331 / 0.332 / 0.339 / 0.333 / 0.337 -> 0.282 / 0.277 /
0.284 / 0.285 / 0.288, force+energy 0.353-0.371 -> 0.308-0.325, energy 0.221-0.229 ->
0.212-0.217, checked step 0.382-0.397 -> 0.337-0.342; main's 0.346 / 0.371 on a quiet machine
(above) would be about 0.30 / 0.32 by these ratios. The force's passes after it
(benchmarks/fibrous_shell.py ``force_phases``, load 10.6; at load 4 before): the cells' pass
0.203 -> 0.155 µs a cell, the sides' folds 0.034, the pulls 0.044, the normals 0.015, the
nodal sums 0.010 + 0.003 (normals, frames), 0.007 (dW/dS), 0.012 (forces, moments).
Tried on top of it and not kept (force paired against it, median new / old, load 5-10, the same bits
each time): the bending of the cells' pass as loops across the chunk (the sides' folds,
scales and flags gathered, the coefficients and curvatures in one loop, the laws by
``law_row``) 1.056 with a loop over the sides, 1.022 written out; the pulls' pass so
(sides, normals, moments, angles and T_k gathered, ``fold_gradient`` and ``angle_pull`` in one
loop) 1.069; the normal sums and the nodes' frames in one node pass 0.989 (quartiles
0.983-1.017); a linear law's value and energy in one loop across the chunk instead of four
(``law_row``) 0.991, force+energy 0.976; the two together, 16 rounds, 1.000 (0.991-1.006),
force+energy 0.990: within the noise, or slower.
Measured after, main 34bcb6a (the moments' lanes merged), nearly quiet (load 1.1-1.2: one
other single-thread run beside it), ``--element fibrous --sizes 100000 --repeats 3``, three
fresh processes, one thread: steady step 0.314 / 0.316 / 0.313 µs an element-step (3.2-3.4 x
the reference pass, 0.094-0.098), force 0.275, force+energy 0.306, checked step 0.332, step
less force 0.024; build 0.38 s, the process's peak 397 MB (4.05 kB a triangle: this script's
runs and reference pass in one process, not the model's own, below); ``--element mindlin``
0.121 (1.3 x its reference pass), force 0.087, step less force 0.030. ``--build --sizes
400000`` on the same code (load 7.8-8.0, the test suite beside it): fibrous 2.03 s CPU (10.2
s wall), +338 MB resident; Mindlin 1.56 s CPU (4.7 s wall), +355 MB.

Re-measured on main 8a6e6f5 (the fold branch kept per side, elements/fibrous/fold_branch.py)
with the model built on small pages (femcore/memory.py; the step itself unchanged), the AMD
EPYC machine shared with other busy runs (load 8.1-9.4), ``--sizes 100000 --repeats 3``, one
thread, µs of CPU an element-step: fibrous steady step 0.474 (3.0 x the reference pass, 0.158
at that load against 0.094-0.098 quiet), force 0.388, force+energy 0.417, energy 0.290, step
less force 0.034, checked step 0.460, commit (the fold branch) 0.096; Mindlin 0.182 (1.3 x its
reference pass, 0.140), force 0.137, step less force 0.042. Two more runs each (load 6.2-9.9):
fibrous 0.480 / 0.533 (3.4 / 3.5 x the reference pass, 0.141 / 0.152), force 0.370 / 0.442;
Mindlin 0.197 / 0.169 (1.4 / 1.2 x, 0.139 / 0.139). Not measured quiet this time; by
the reference pass's own slowdown at that load (1.6-1.7 x and 1.4-1.5 x) about 0.29 and 0.125
quiet, against the issue's 0.35 and 0.15 (an estimate, not a measurement). The build in this
script's process (the loops already loaded): fibrous 0.40 s CPU, Mindlin 0.28 s at 100k;
benchmarks/model_memory.py has the build and the peaks stage by stage in fresh processes.
Re-measured on main 9a25df8 (the blocks' work arrays kept, femcore/workspace.py; the Mindlin
cells' step following their stretch), the machine nearly quiet (load 1.5-1.8), ``--sizes
100000 --repeats 3``, one thread: fibrous steady step 0.462 µs an element-step (3.5 x the
reference pass, 0.133 in this run against 0.094-0.098 in the quiet runs above), force 0.373,
force+energy 0.402, energy 0.288, step less force 0.034, checked step 0.438, commit 0.083;
Mindlin 0.189 (1.5 x its reference pass, 0.125), force 0.135, step less force 0.039.

Reference counting out of the fibrous force's hot loops (the Intel Xeon, AVX-512, one
thread). perf put 40 % of the cells' pass in numba's NRT_incref / NRT_decref (lock-prefixed
adds), and gdb's count of their callers, 15 a cell: 12 from ``corner_frame`` (given the frame
and director arrays, it branches on ``nodal``, so the increfs and decrefs of its arguments
were not pruned), the rest from the array arguments of the level lanes, 26 a level of a chunk
of 32 cells. The corners' frames now read in the pass itself (cell_terms.py
``element_corner`` for the element normal, scalars only) and the lanes compiled without
reference counting (femcore/jit.py ``lane_rows``): 7 a chunk are left. Paired in one process
(benchmarks/kernel_pairs.py, 100k, 8 rounds, the same bits each time): the frames, force
0.798 of main cfaff59's (best 0.311 -> 0.247 µs a cell, load 4.0), force+energy 0.821; the
lanes on top, force 0.962, force+energy 0.972, energy 0.939 (load 5.5). Outside the force,
the fold branch's commit after each step (elements/fibrous/fold_branch.py) measured the motion
since its last full pass by numpy's three (k, 3) temporaries (0.57 ms alone, 2.4 ms of self
time a step in a run under cProfile) and asked the (m, 3) turns ``any()`` at every force
call (0.9 ms): one compiled pass (0.11 ms) and the answer kept with the turns array. Main
cfaff59 (exported to a folder of its own) and this tree in turns, two runs each,
``--element fibrous --sizes 100000``, one thread, load 5.7-6.1 (other jobs on the machine),
µs of CPU an element-step (main -> this tree): steady step 0.375 / 0.410 -> 0.303 / 0.291
(3.0 / 3.3 -> 2.6 / 2.7 x the reference pass, 0.108-0.124 at that load), force 0.352 /
0.342 -> 0.256 / 0.249, force+energy 0.378 / 0.366 -> 0.284 / 0.273, energy 0.257 / 0.261 ->
0.176 / 0.176, checked step 0.408 / 0.398 -> 0.316 / 0.306, step less force 0.024 / 0.027 ->
0.026 / 0.027; two more runs each at a load of 3.7-6.6: steady step 0.376 / 0.413 -> 0.306 /
0.318 (3.2 / 3.5 -> 2.5 / 2.8 x the reference pass), force 0.321 / 0.329 -> 0.257 / 0.260.
Both changes paired against cfaff59 in one process (8 rounds, load 7.5): force 0.776
(quartiles 0.767-0.787; best 0.327 -> 0.253 µs a cell), force+energy 0.805, energy 0.714,
the same bits. (The "commit" phase, 0.06-0.07 in those runs, timed a state whose history
had no positions yet, a full pass over the sides each call; it now times the commit after
a first one, as a run's step commits.) What the
step spends outside the compiled loops, about 0.03 µs an element-step (cProfile, 200 steps
of the 100k sheet): the external load's fresh (n, 3) arrays and sums
(femcore/compiled.py ``external_load``, about 2 ms a step), the rotational kinetic energy's
einsum (solvers/dynamics.py, about 1-2 ms), numpy's reductions and allocations, the Python
around some forty compiled calls; the rotation update (solvers/turning.py) is 0.02 µs of
compiled work.

Where the fibrous force's time goes, and what LLVM made of its loops, on main 186b5d5 (the
2-core Intel Xeon, AVX-512, one thread, CPU, other jobs on the machine). This script, ``--sizes
10000,100000 --repeats 3`` at a load of 4.5: steady step 0.405 at 10k, 0.462 at 100k (3.6 and
3.1 x the reference pass, 0.113 and 0.148 at that load against 0.094-0.098 quiet), force 0.333
/ 0.376, force+energy 0.349 / 0.424, energy 0.230 / 0.273, step less force 0.038; two threads
(``--threads 2``, load 4.2-5.1, the other core busy) 0.994 / 0.940 µs wall, 0.595 / 0.457 CPU:
slower than one. The force's passes (benchmarks/fibrous_shell.py ``force_phases``, 100k, load
3.4; force 0.331): normals 0.020, normal sums 0.014, frames 0.007, sides' folds 0.040, the
cells' pass 0.161, dW/dS sums 0.013, pulls 0.050, nodal sums 0.019. Inside the cells' pass
(0.151 with the linear laws' loop below, load 3.5; a copy of the pass with one part left out at
a time): the lanes (levels, laws, loads, moments) 0.070, the bending 0.026, the copies of the
lanes' results into the (m, 3, 3) outputs 0.01-0.02, the gathers into the scratch rows about
0.03. The lanes run alone (a compiled loop calling them chunk after chunk on one chunk's rows,
100k cells' worth, main): the three levels' strains 0.046, their laws 0.030, loads 0.011,
moments 0.009. What LLVM did (benchmarks/vector_width.py: numba's ``inspect_asm``, and perf
with a map of numba's builds): the lanes run 4 doubles wide in ymm registers, not 8: LLVM names
this host rocketlake, whose tuning prefers 256-bit vectors; with the preference lifted
(``NUMBA_CPU_FEATURES``, ``-prefer-256-bit``) they run in zmm and the force is 1-12 % slower.
The pulls' pass and the sides' folds are scalar code. Of the cells' pass's perf samples, 33 %
fall on packed ymm instructions, 38 % on scalar double arithmetic, the rest on integer work,
moves and branches (its hottest scalar stretch, a loop over three sides, stores to the stack).

Three linear laws in one loop across the chunk (level_lanes.py ``linear_lanes``: the presets'
tension and shear; the laws' eleven loops and their rows' loads and stores were the lanes'
0.030, the one loop is 0.005 run alone). Paired against main 186b5d5 (benchmarks/
kernel_pairs.py, 100k, 10 rounds, load 3.8-4.3): force 0.982 (quartiles 0.974-0.986; best 0.321
-> 0.315 µs a cell), force+energy 0.971 (0.964-0.974), energy 0.958 (0.952-0.961), the same
bits (on a forming state the force is unchanged as well: the hemisphere's ply,
validation/cases/hemisphere_forming.py, has a K5 shear polynomial, whose laws take ``law_row``
as before). This script, main (exported) and this tree in turns, two rounds each, one thread,
load 2.8-3.8, µs of CPU an element-step (main -> this tree): 100k steady step 0.401 / 0.410 ->
0.394 / 0.377 (2.9-3.1 -> 2.7-2.9 x the reference pass, 0.13-0.14 at that load), force 0.345 /
0.322 -> 0.324 / 0.338; 10k steady step 0.377 / 0.390 -> 0.359 / 0.369, force 0.274 / 0.331 ->
0.316 / 0.303: the runs' noise is larger than the change, the paired ratio is its measure. Two
threads after (load 2.5-3.0): 10k 1.112 µs wall (0.517 CPU), 100k 0.287 wall (0.381 CPU). The
issue's 0.35 µs a step on one core is not reached in these runs (0.38-0.41 CPU at a load of 3,
where the reference pass ran 1.4 x its quiet time; scaled by that, about 0.28 quiet: an
estimate, not a measurement; main 34bcb6a measured 0.313 nearly quiet, above). What is left, by
the split above: the scalar work around the lanes in the cells' pass (the gathers, the bending,
the copies: about half of its 0.15), the scalar pulls (0.05) and folds (0.04), and the nodal
sums (0.05 over three node passes); the lanes' 0.07 for three levels is what 4-wide vectors
give with the branch-free log and arcsine. The bending and the pulls as lanes were tried before
and were slower (above); their gathers and the sides' indirection are what such loops would
have to pay for.

Threads: ``--threads 1`` (default) or any count numba may use; the machine's load average is
printed with the figures. On several threads every loop runs on all of them whatever the load
(``femcore.jit.FOLLOW_LOAD`` off), the loops first called on a sheet above ``SMALL_LOOP``
(before, the shorter timed run paid the parallel builds' first call, and the steady step came
out negative: -2.9 µs at 100k on two threads).
With the parallel builds as parts of the plain build (femcore/jit.py), 100k triangles, one
process per line, one and two threads in turns, one other run beside them (load 2.0-2.8), µs an
element-step (steady wall; whole run of 100 steps wall): fibrous one thread 0.518, 0.473,
0.480, 0.568 (0.45-0.49); two threads 0.231 (0.297), 1.171 (0.691), 1.093 (0.911), -0.204
(0.933): twice as fast as one thread when the second core was free (2.2 x), slower when the
other run held it. Mindlin one thread 0.113, 0.156 (0.167, 0.174), two threads 0.266, 0.315.
A fair two-thread figure needs the machine quiet (benchmarks/threads.py has the quiet one).

The velocity and rotation updates on the threads, their energy terms summed by chunks of
nodes (solvers/dynamics.py, turning.py; benchmarks/threads.py): the one-thread step as
before, main fdcebfd and after in turns, 100k, ``--repeats 3``, µs of CPU an element-step
(steady; the step less its force): Mindlin 0.124 / 0.129 -> 0.130 / 0.128 (0.031 -> 0.032 /
0.033), load 6.1-6.7; fibrous 0.442 -> 0.441 (0.022 -> 0.022), load 8.0-8.9.

The Mindlin force on one thread in one pass that adds each cell's loads to its nodes
(elements/mindlin_cell_loads.py; its energy sums left out on the steps that do not check the
balance), this script on 432e668 and after, 100k, ``--repeats 3``, one thread, µs of CPU an
element-step: Mindlin steady step 0.171 (1.4 x the reference pass, 0.119; load 4.2) -> 0.158
(1.2 x, 0.131; load 18.5), force 0.123 -> 0.107, force+energy 0.122 -> 0.112, the step less
its force 0.037 -> 0.036, checked step 0.162 -> 0.151. Where the step went before, CPU
profile of 300 steps of CentralDifference at 100k (load 10-11, ms a step): the cells' pass
10.3, the nodes' sums of its (m, 3, 6) buffer 1.95, the rotations' pass 1.7, the velocities'
0.64, the copies of the force's and moment's (n, 3) halves of one (n, 6) array 0.2-0.5, the
external load 0.56, the records' rotational kinetic energy 0.36; after, the one pass 10.9
(cells and nodes), rotations 1.9, velocities 0.7 (load 13-15). Paired in one process, the
old force kernels beside these (benchmarks/explicit_step_pairs.py, load 12-18): 0.163-0.171
-> 0.142-0.145, median 0.854-0.875 of before, the same bits. The fibrous shell's step is not
changed (its 300-step run the same to the bit): 0.322 (2.6 x, 0.123; load 9.4) and 0.346
(2.2 x, 0.155; load 18.6) in the two runs. Tried and not kept: the Mindlin levels as loops
across chunks of 32 cells (structure of arrays, as the fibrous levels; LLVM ran them 4 wide):
1.09-1.4 x the cell-by-cell pass, the stiffness (m, Z, 28) and references (m, Z, 7) copied
into the chunk's rows, or read from a chunked copy (nchunks, Z, 28, 32) in place; without
the tables' 560 bytes a cell the lanes took 0.052 µs a cell against 0.073 cell by cell, so
the tables' traffic, not the arithmetic, bounds the pass. Nor the same one-thread pass for the
fibrous shell's pulls (each cell's corner forces, its pulls added, and moments to its nodes as
it goes, the pull's arithmetic a helper shared with the threads' pass): the same bits, but
the force 1.13 x and the whole step 1.13 x those of 432e668 paired in one process
(benchmarks/kernel_pairs.py, explicit_step_pairs.py --element fibrous; load 13-18).

Run from the project root:

    python benchmarks/explicit_step.py
    python benchmarks/explicit_step.py --element fibrous --sizes 10000,100000 --threads 2
    python benchmarks/explicit_step.py --element fibrous --build --sizes 400000
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import os
import platform
import resource
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install

from fresh_process import fresh_output  # noqa: E402
from shell_sheet import GRAVITY, reference_pass  # noqa: E402

from femcore import Mesh, Model  # noqa: E402
from solvers import CentralDifference  # noqa: E402
from solvers.step import LumpedMasses, explicit_step  # noqa: E402

ALUMINIUM = dict(E=70e3, nu=0.3, thickness=1.0, density=2.7e-9)  # MPa, mm, t/mm^3


def element(name: str, kernel: str):
    """A fresh element of the benchmark's kind."""
    if name == "mindlin":
        from elements import MindlinShell
        from materials import ElasticShell

        return MindlinShell(ElasticShell(**ALUMINIUM), kernel=kernel)
    from elements import FibrousShell
    from materials import presets

    return FibrousShell(presets.g986_stack(), kernel=kernel)


def resident_mb() -> float:
    """The process's resident memory now, MB (Linux /proc)."""
    with open("/proc/self/statm") as statm:
        pages = int(statm.read().split()[1])
    return pages * os.sysconf("SC_PAGE_SIZE") / 2**20


def peak_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def sheet(name: str, kernel: str, triangles: int):
    """The pinned sheet's model, compiled, with the build's seconds and memory."""
    n = max(2, round(math.sqrt(triangles / 2)))
    before = resident_mb()
    mesh = Mesh.rectangle(5.0 * n, 5.0 * n, nx=n, ny=n)
    model = Model(mesh)
    model.add(element(name, kernel))
    for edge in ("left", "right", "bottom", "top"):
        model.fix(edge, ["ux", "uy", "uz"])
    model.gravity(GRAVITY)
    started, cpu = time.perf_counter(), time.process_time()
    compiled = model.compile()
    build = (time.perf_counter() - started, time.process_time() - cpu)
    return compiled, build, resident_mb() - before


def run(compiled, steps: int) -> tuple[tuple[float, float], object]:
    """(wall, CPU) seconds of ``CentralDifference`` over ``steps`` steps at 0.9 x the stable
    step, frames at the start and the end only."""
    dt = 0.9 * compiled.stable_dt(compiled.initial_state())
    solver = CentralDifference(
        duration=steps * dt, dt=dt, output_interval=steps * dt, progress=False
    )
    started, cpu = time.perf_counter(), time.process_time()
    result = solver.solve(compiled)
    return (time.perf_counter() - started, time.process_time() - cpu), result


def best(call, repeats: int) -> float:
    """The shortest CPU time of ``repeats`` calls, s (on one thread the CPU time is what the
    call costs whatever the other processes of a shared machine take)."""
    shortest = math.inf
    for _ in range(repeats):
        started = time.process_time()
        call()
        shortest = min(shortest, time.process_time() - started)
    return shortest


def cpu_reference(triangles: int, repeats: int = 20) -> float:
    """``shell_sheet.reference_pass`` timed in CPU time: µs per element, the best of
    ``repeats``."""
    return reference_pass(triangles, repeats, clock=time.process_time)


def phases(compiled, state, repeats: int) -> dict:
    """Per-phase seconds at ``state`` (best of ``repeats``)."""
    masses = LumpedMasses.of(compiled, state)
    dt = 0.9 * compiled.stable_dt(state)
    force = best(lambda: compiled.internal_force(state), repeats)
    fused = best(lambda: compiled.internal_force_and_energy(state), repeats)
    energy = best(lambda: compiled.strain_energy(state), repeats)
    step = best(lambda: explicit_step(compiled, state, dt, masses, duration=1.0), repeats)
    checked = best(
        lambda: explicit_step(compiled, state, dt, masses, duration=1.0, checking=True), repeats
    )
    # the commit of a run's step: its history already has the positions of a full pass
    committed = compiled.commit(state)
    commit = best(lambda: compiled.commit(committed), repeats)
    return {
        "force": force,
        "force+energy": fused,
        "energy": energy,
        "step less force": step - force,
        "checked step": checked,
        "commit": commit,
    }


def fresh_peak(name: str, triangles: int, steps: int) -> str:
    """The process's peak resident memory of a ``CentralDifference`` run of ``steps`` steps with
    the solver's own stable step (the cells' bound and the assembled Gershgorin bound), the
    sheet built in a fresh process (one thread): its line of figures."""
    out = fresh_output("explicit_step", f"_peak_child({name!r}, {triangles}, {steps})")
    return out.strip().splitlines()[-1]


def _peak_child(name: str, triangles: int, steps: int) -> None:
    """``fresh_peak`` inside its fresh process: prints the build's seconds and the peak."""
    compiled, build, _ = sheet(name, "compiled", triangles)
    elements = sum(len(block.connectivity) for block in compiled.blocks)
    dt = compiled.stable_dt(compiled.initial_state())
    started = time.process_time()
    CentralDifference(duration=steps * 0.9 * dt, output_interval=steps * dt, progress=False).solve(
        compiled
    )
    print(
        f"{name} {elements:>8d} triangles: build {build[0]:.2f} s wall, {build[1]:.2f} s CPU "
        f"(the loops loaded from the cache); {steps} steps with the solver's own step "
        f"{time.process_time() - started:.1f} s CPU; peak {peak_mb():.0f} MB "
        f"({peak_mb() * 1024 / elements:.3f} kB per triangle); load {os.getloadavg()[0]:.2f}"
    )


def fresh_build(name: str, triangles: int) -> str:
    """The CPU and wall seconds of ``Model.compile`` of the sheet in a fresh process (one
    thread), the loops compiled or loaded on a small sheet first: its line of figures."""
    out = fresh_output("explicit_step", f"_build_child({name!r}, {triangles})")
    return out.strip().splitlines()[-1]


def _build_child(name: str, triangles: int) -> None:
    """``fresh_build`` inside its fresh process: prints the build's seconds."""
    sheet(name, "compiled", 200)  # the loops compiled or loaded from the cache
    compiled, build, memory = sheet(name, "compiled", triangles)
    elements = sum(len(block.connectivity) for block in compiled.blocks)
    print(
        f"{name} {elements:>8d} triangles: build {build[0]:.2f} s wall, {build[1]:.2f} s CPU, "
        f"+{memory:.0f} MB resident; load {os.getloadavg()[0]:.2f}"
    )


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--element", choices=("mindlin", "fibrous"), default="mindlin")
    parser.add_argument("--kernel", choices=("compiled", "numpy"), default="compiled")
    parser.add_argument("--sizes", default="10000,100000")
    parser.add_argument("--steps", type=int, default=100, help="at least this many steps")
    parser.add_argument(
        "--work", type=float, default=1e7, help="element-steps a run makes at least"
    )
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument(
        "--memory",
        action="store_true",
        help="only the peak memory and build of a run with the solver's own step, a fresh "
        "process per size",
    )
    parser.add_argument(
        "--build", action="store_true", help="only the build, a fresh process per size"
    )
    args = parser.parse_args(argv)
    if args.build:
        for size in [int(s) for s in args.sizes.split(",")]:
            print(fresh_build(args.element, size), flush=True)
        return
    if args.memory:
        for size in [int(s) for s in args.sizes.split(",")]:
            print(fresh_peak(args.element, size, args.steps), flush=True)
        return
    import numba

    numba.set_num_threads(min(args.threads, numba.config.NUMBA_NUM_THREADS))
    print(
        f"python {platform.python_version()} on {platform.machine()}, {args.element} "
        f"({args.kernel}), {numba.get_num_threads()} thread(s), load average "
        f"{os.getloadavg()[0]:.2f}"
    )
    from femcore import jit

    # On several threads every loop runs on all of them whatever the load (the free-core
    # count would pick one on a busy machine), and the loops are first called on a sheet
    # large enough for their parallel builds: otherwise the shorter timed run pays for those
    # builds' first call and the steady step comes out negative.
    jit.FOLLOW_LOAD = numba.get_num_threads() == 1
    warm = 200 if numba.get_num_threads() == 1 else 4 * jit.SMALL_LOOP
    compiled, _, _ = sheet(args.element, args.kernel, warm)  # compile the loops first
    run(compiled, 3)
    for size in [int(s) for s in args.sizes.split(",")]:
        compiled, build, memory = sheet(args.element, args.kernel, size)
        elements = sum(len(block.connectivity) for block in compiled.blocks)
        steps = max(args.steps, round(args.work / elements))
        short, _ = run(compiled, steps)
        long, result = run(compiled, 2 * steps)
        per = 1e6 / (elements * steps)
        steady = [(b - a) * per for a, b in zip(short, long)]
        whole = [a * per for a in short]
        reference = reference_pass(size)
        reference_cpu = cpu_reference(size)
        state = result.frames[-1]
        at = dataclasses.replace(
            compiled.initial_state(),
            positions=state.positions,
            directors=state.directors,
            velocities=state.velocities,
        )
        timed = phases(compiled, at, args.repeats)
        print(
            f"{elements:>8d} triangles: build {build[0]:6.2f} s wall, {build[1]:6.2f} s CPU, "
            f"+{memory:6.0f} MB resident ({memory * 1024 / elements:.2f} kB per triangle), "
            f"peak {peak_mb():6.0f} MB ({peak_mb() * 1024 / elements:.2f} kB per triangle); "
            f"load {os.getloadavg()[0]:.2f}"
        )
        print(
            f"{'':>10} steady step {steady[0]:.3f} us/element-step wall, {steady[1]:.3f} CPU "
            f"({steady[1] / reference_cpu:.1f} x the reference pass, {reference:.3f} wall, "
            f"{reference_cpu:.3f} CPU); "
            f"whole run of {steps} steps {whole[0]:.3f} wall, {whole[1]:.3f} CPU"
        )
        print(
            f"{'':>10} per element, us of CPU: "
            + ", ".join(f"{name} {value / elements * 1e6:.3f}" for name, value in timed.items()),
            flush=True,
        )


if __name__ == "__main__":
    main()
