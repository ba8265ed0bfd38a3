"""The CPU of chosen test items, compiling and running apart: the items run by pytest in one
process (``-n 0``) on a fresh empty numba cache (NUMBA_CACHE_DIR: every kernel an item calls
first is compiled there), then again in a second process on the cache the first one left
(the run alone). Each item's CPU is ``time.process_time`` over its setup, call and teardown
(a plugin of this script records it); compile = cold - warm. An item that compiles kernels
later items also call takes their compile in a cold pass, so the figures depend on the
items' order (pytest's, as given). One numba and BLAS thread; the machine's 1-minute load is
printed before and after each pass (2 cores shared with other jobs).

Measured (2 cores shared with other jobs at a load of 5-8: a cold pass of the slow items
did not finish in the time there was; the warm figures are of one process on a cache that
already held their kernels, ``-n 0``, load 8.0 -> 3.2): CPU s of the item, then its wall
time in a whole run of the suite on main 9864ff6 (a fresh clone, fresh cache, two xdist
workers beside the coarse report, load 5-8, 47 min 46 s wall in all, 1044 s of CPU of pytest
and its workers):

    tests/test_hemisphere_static.py  ..._at_the_case_coarse_mesh          63.3   401.6 s
    tests/test_stable_step.py        ..._coarse_hemisphere_forming_blank  29.0   114.8 s
    tests/test_compare.py            ..._same_laws_leave_only_the_kinem.  28.7    88.7 s
    tests/test_compare.py            ..._fit_calibration_recovers_...      2.8    87.8 s
    tests/test_capstan.py            ..._dynamic_relaxation_...[0.0]       5.6     (< 47 s)
    tests/test_capstan.py            ..._dynamic_relaxation_...[0.2]       8.9    64.3 s

The fit's CPU is in the Dask workers of the LocalCluster it starts (``fit_calibration``
takes no scheduler: not the session's shared one); the others are their runs (their
kernels compiled by earlier items). Items whose whole-suite time is numba's compiling, the
first of their worker to ask for a family of kernels: test_bias_extension.py's setup
358.5 s, test_fibrous.py's first compiled pieces 345.0 s, test_conformance.py's first
Mindlin-fabric motion 105.0 s, test_mindlin.py's parallel kernel [2] 81.2 s,
test_augmented_contact.py's pressed plate 67.6 s (earlier warm figures: 0.01-0.04 s,
benchmarks/suite_items.py).

The coarse report the suite runs beside its tests (tests/conftest.py), in that same run of
main: 23 cases in 851 s wall on its two jobs, 327.9 s of the cases' CPU (``case_cpu_s``; a
Dask worker's CPU not in it): hemisphere-plies 90.1, hemisphere-forming 67.4, plies-bai-5.1
44.3, bai-5.1 28.3, plies-deck-of-cards 27.8, bai-6.1.1 15.5, bai-6.2.1 11.9, bai-6.1.2 11.0,
bai-6.2.2 10.2, plies-heavy-cantilever 5.0, bai-6.1.1-sensitivity 4.2 (and its Dask workers),
heavy-cantilever-nonlinear 3.7, the other 11 cases 8.5 s together.

A whole run of the suite after the parallel builds became loops over parts of the plain
builds (femcore/jit.py ``_Parallel``; commit 2a218a7, a fresh clone, fresh cache, ``python -m
pytest``: two xdist workers beside the coarse report, the slow tests included), on the 2
cores shared with other jobs at a load of 5 rising to 15: 1899 passed, 7 skipped, 24 min
0 s wall, 582.6 s of CPU of pytest, its workers and the report (user 552.5 + system 30.1).
The wall times of its slowest items at that load: the 12-cell Static drape 195.2 s, the
bias extension's setup (the fibrous tangent's kernels compiling) 118.5 s, the first compiled
fibrous test 87.6 s (its parallel builds now a loop over parts: 36.6 -> 23.5 s of CPU alone
at a load of 1-3, benchmarks/suite_kernels.py), the report workers' kill test 86.4 s, the
README's identify command 84.4 s, mypy 84.1 s, the stable-step forming blank 73.4 s, the
Mindlin Static drape 61.1 s, the same-laws comparison 36.9 s, the Mindlin kernel test [2]
26.3 s. No run of main beside it: at that load a second 24-minute run would have measured
the other jobs more than the suite.

Each item's figures are its own process's CPU and, apart ("children"), the CPU of the
processes it reaped during the item: a subprocess, a Dask LocalCluster's workers stopped in
it. A cluster the session shares (tests/conftest.py ``dask_scheduler``) is reaped in the item
after which it stops, with the CPU of every task it ran and of its idle time.

Measured, the Dask clusters of the tests (one pytest process, ``-n 0``, warm cache, the
2-core machine shared with other jobs, load 4-10; CPU the user + system time of pytest and
its reaped processes, ``/usr/bin/time``, old and new in turns):

* an idle LocalCluster of 2 workers (fibreshell.cluster.dask_client, nothing submitted for
  60 s after one task): 3.25 s of CPU in its workers and 2.47 s in the process that started
  it (its scheduler's and nannies' event loops: ticks, heartbeats, memory monitors), about
  5.7 s a minute; starting it took 0.83 s in its workers, 4.0 s wall (load 8). The suite's
  shared cluster was kept to the session's end, though the tests that use it are marked slow
  and run among the first of a whole run (tests/test_identify.py): minutes of that.
* the fit calibration (tests/test_compare.py, a LocalCluster of its own before, the shared one
  after), then tests/test_identify.py, test_static.py, test_nonlinear_bending.py and
  test_relaxation.py (84 tests): before (the shared cluster kept to the end) 51.4 and 56.9 s
  of CPU (load 3.8-4.9, 7.7-10.0), after (the fit on the shared cluster, stopped after the
  last test that uses it) 46.5 and 46.7 s (load 4.9-7.7, 10.0-9.6).
* the fit calibration, the sweep on a scheduler's address (tests/test_sweep.py) and one
  identify test, the first two on clusters of their own against both on the shared one: 15.3
  and 14.8 s of CPU, 28 and 27 s wall, against 9.4 and 9.1 s, 18 and 17 s wall (load 7-8).
  The sweep's test runs late in a whole run (not slow): on the shared cluster it would keep
  that cluster up to there, so it keeps a cluster of its own.

A whole run each (a fresh clone, ``python -m pytest``, two xdist workers beside the coarse
report, each item's CPU and reaped children's CPU logged), before (d004b4e, load 1.2 -> 12.4)
and after (c57c400, load 8.9 -> 13 -> 4.6), one after the other on the 2-core machine shared
with other jobs: 1991 / 1993 passed in 895.6 / 981.4 s wall; the workers' own CPU 344.0 /
342.6 s; the report's cases 255 / 249 s (``case_cpu_s``). The shared cluster started with
the fit calibration (247 s into the run) and was stopped after the last identify test (610.6
s, 32.6 s of CPU of its workers reaped there, the fits' runs included); before, it ran from
the first identify test (about 400 s) to the session's end (868 s): at 5.7 s of CPU a
minute, about 30 s of CPU that the other processes now have. At those loads the wall times
measure the other jobs, not the suite: the figures to compare are the CPU's.

Items taken out because another item or the coarse report makes the same claim (each item's
CPU as above, warm cache, one process, ``-n 0``, two passes; the 2-core machine shared with
other jobs, load 8-9):

* tests/test_hemisphere_static.py's 12-cell drape (the case's coarse mesh): 24.0 and 24.6 s
  (19.4 s in a third pass); the 8-cell drape it duplicates 1.7 and 2.4 s. With the inertia
  correction taken out (solvers/inertia.py ``convexified_step`` returning None, the defect the
  12-cell docstring measured: 7 cuts there) the 8-cell test fails (1 cut, none allowed).
  benchmarks/hemisphere_static.py still draws the 12-cell mesh.
* tests/test_plies.py's heavy stack of four plies on 10 cells: 8.7 and 8.5 s. The coarse
  report's plies-deck-of-cards sags the same stack and its fibrous twin on 20 cells and checks
  them to 0.3 mm and 0.65 deg (the test held 0.9 mm and 1.5 deg on 10 cells);
  tests/test_validation_cli.py holds every check of the report.

* tests/test_forming_shortcuts_change_nothing.py: the three comparisons (a run with each
  shortcut off against the shared run with all on: 4 runs of the 12-cell case over 0.02 s)
  made one (every shortcut off against all on: 2 runs): 8.1 and 8.7 s of CPU before, 4.0 s
  after (a pass whose first item compiled: 14.5 s); load 8-9. The pair still fails on a
  compiled tool pass one ulp off (``np.nextafter`` on its forces: arrays not equal) and on a
  memory that answers whatever the positions (the run diverges at step 10).

Measured and not changed: tests/test_stable_step.py's coarse forming blank (about 15 s of CPU
warm): with the explicit solver's rotary inertia refreshed without its two safeguards (it
only grows, the angular velocities scaled to keep the rotational energy) it diverges at step
13560 (12.4 s of CPU), where the fast tests of test_explicit.py, test_stable_step.py and
test_step.py all pass; the lever of a tilted director (``rotary_lever`` without the 1 /
cos(tilt)) fails test_stable_step.py's fast tilted-directors test already, and a refresh
taken out its README-strip test. tests/test_identify.py's command test on the session's shared
cluster (``--scheduler``) instead of a LocalCluster of its own (``--workers 1``): 1.0-1.4 s of
CPU less a run (the pytest process and its reaped children, two rounds, load 7-9), not worth
the ``--workers`` option's only end-to-end test. tests/test_bias_extension.py's arc length
(32 s in a quiet CI run) and its fixture (19 s) are numba compiling the fibrous tangent's
kernels (0.26 and 0.12 s warm); test_capstan.py's Static strips 0.16-0.36 s warm: cutting them
would move the compilation to the next test that needs those kernels.

The slow tests after these cuts, warm (``-m slow`` in one process, ``-n 0``, on a cache that
held every kernel but 1.2 s of compiling; the tests reading the coarse report and mypy left
out; load 2.9-6.9): 43 items, 109.9 s of CPU with their reaped children. The largest: the
shared cluster's workers reaped after its last test (12.4 s: the fits of test_identify.py and
test_compare.py, their start and idle ticks), the README's identify command 11.4 s (10.8 in
its own cluster's two workers), the coarse forming blank 8.5 s, the README's Python sweep 6.4 s
(a subprocess and its two workers), the same-laws comparison 5.4 s, the README's sweep
command 5.0 s, the Mindlin Static drape 4.8 s, identify's command test 4.3 s, the smoothed
drape 4.0 s, Static against dynamic relaxation on the sagging cable 3.5 s; every other under
3.5 s. Beside the coarse report's cases (a whole run of 5523c00 at a load of 8-10: hemisphere-plies
156.3 s of CPU, the other 22 cases 143.2 s together) and numba's compilations (81 s in the workers,
benchmarks/suite_processes.py), what is left in the tests' own runs is small.

A whole run of main 97cc118 (benchmarks/suite_processes.py, a fresh export, the 2-core machine
shared with other jobs, load 2.0 -> 13.3, 20 min 20 s wall; the CPU is the run's): the coarse
report's processes 212 s (its two jobs 121.5 and 76.6 s, bai-6.1.1-sensitivity's Dask worker
14.0 s, 7.6 s of it compiling), the xdist workers about 360 s (one of them 205.4 s, 65.4 s
of it compiling; the other's exit record was lost, its items 146.6 s and their reaped
children 67.4 s), the tests' Dask workers 46.7 s in 15 processes (the shared cluster's
one 14.8 s, the others 1.2-5.5 s each: a start, the package imported, kernels loaded),
pytest 3.5 s; 2133 passed, 1 failed (the one test that script's timed compile fails, as it
says). Its items (setup, call, teardown) 343 s of the workers' own CPU; the largest mypy
24.7 s, the bias extension's arc length 23.3 s, the shared cluster reaped after its last
test 15.3 s, the README's identify command 12.4 s (11.2 s in its own cluster's two
workers). Found there and cut (CPU of the items with their reaped children, the checkout
before, main 97cc118, and after run side by side, warm numba caches, one numba thread,
load 8.9-10.2):

* tests/test_sweep.py's paired sweep (a module fixture on a LocalCluster of 2 workers) ran
  twice: pytest-xdist handed the module's tests to both workers and each swept on a cluster
  of its own (4.65 and 4.36 s of reaped Dask CPU in the two). Swept once per run now, the
  other worker reading its pickled table (tests/run_once.py, tests/conftest.py
  ``once_per_run``). ``pytest -n 2 tests/test_sweep.py`` (user + system of pytest and every
  process it reaped): before 23.0 and 22.7 s, after 18.4, 18.4 and 17.9 s.
* tests/test_identify.py's overhangs fixture fitted Peirce's B and rho_A to three overhangs
  of 16 cells (on the shared cluster) where the README's identify example fits the same
  strip, data and starts (cases/strip.toml, cases/overhangs.csv): its claims moved to the
  README test's check (B and the bending length within 1 %, rho_A to 1e-4, both intervals,
  runs = 3 x evaluations, identify.json, fit.png), the fixture gone. tests/test_identify.py
  and the README's four commands (this script, ``-n 0``, load 9.3 -> 5.3), warm: the items
  4.7 and 4.7 s, their reaped children 31.9 -> 27.4 s (the shared cluster's worker, reaped
  after the last test that uses it, 10.7 -> 6.0 s), 36.6 -> 32.1 s in all; cold (every
  kernel compiled in a fresh cache) 98.2 -> 91.4 s.

A whole run after these cuts (5c5be05, a fresh clone, ``python -m pytest``): 2133 passed, 7
skipped in 10 min 47 s wall, 422 s of user + system CPU of pytest and the processes it
reaped; started at a load of 2.4, another checkout's whole CI run beside it from its fourth
minute (load 5-6): the wall measures that run too, not the change.
* mypy (tests/test_typecheck.py) no longer analyses the packages the five reach only through
  dask, distributed and matplotlib, nor dask's array, bag and dataframe collections
  (pyproject.toml, ``follow_imports = "skip"``); the calls into numpy, numba, dask,
  distributed, matplotlib and rich checked as before. From an empty cache (``python -m mypy``
  over the five, user CPU, old and new in turns): 21.21 -> 18.47 s (load 9.3), 23.52 ->
  21.22 and 23.68 -> 22.42 s (load 9-15). Its ``--timing-stats``: elements/ 55 % of the
  per-module time (ply_friction.py 3.4 s, ply_block.py 1.7 s of 40.7 s wall), femcore 13 %,
  the installed packages 17 % before.

Measured and not changed:

* tests/test_bias_extension.py's arc-length test: 47.5 s of CPU in a cold pass, 0.8 s warm
  (load 10-11): numba compiling the fibrous tangent's kernels, which the next fibrous Static
  test would compile; a shorter path or a smaller mesh would not cut it.
* the ply contact's kernels are built twice in a fresh checkout, once for read-only and once
  for writable arrays (benchmarks/suite_signatures.py on the whole run's cache: 17 second
  builds of 187, ply_choice ``_choose_part`` 2.2 + 2.3 s, ply_load_kernels ``_loads`` 1.7 +
  1.4 s, ply_feature_normals, ply_chosen, ply_face_points, ply_search ``_moves``; about 7 s
  of compiling, half in a report job, half in a worker). Giving tests/test_ply_kernels.py's
  direct calls read-only points and corners (as elements/ply_block.py hands them) left 14
  second builds of 119 in a cache of that module, test_ply_search.py and a ply test run
  through the model: the writable builds come from the library's own paths (elements/).
  Unified since (the wrappers hand those inputs read-only, elements/kernel_inputs.py):
  benchmarks/suite_signatures.py.

Where a whole run's CPU goes (main 8a6e6f5: in a quiet CI run, 2504 tests, 5:04 of pytest on
2 cores, user + system 607 s with the install). Each item warm, one process (``-n 0``), on
the numba cache a whole run of the same checkout had left (a fresh clone, load 8-12; the
per-item CPU at load 5-11, so a little above a quiet machine's):

* the 2449 fast tests 209.4 s with their reaped children: 2030 items under 0.05 s (13.8 s
  together), 2327 under 0.5 s (68.4 s), none above 4.7 s (the supernodal factors' build for
  a generic CPU, a subprocess on an empty cache). By module: test_ply_edge_couple.py 10.2 s,
  test_sweep.py 9.2, test_ply_springs.py 8.7, test_ply_search.py 7.4, test_contact.py 6.9,
  test_ply_curved_friction.py 6.9, every other module under 6.9 s: the tests' own runs,
  spread over a few hundred items of 0.2-2 s;
* the 52 slow tests that neither read the coarse report nor run mypy 149.9 s: the study's run
  at four times the ply penalty 22.8, the README's identify command 12.2 (11.3 in its own
  cluster's two workers), the coarse plies-bai-5.1 solves of test_static_stall.py and
  test_static_first_turn.py 9.6 and 6.2 (three runs, the rules on and off: the report's run
  has both rules on and keeps neither the plies' positions nor the first-turn cuts), the
  coarse forming blank 9.1, the identify tests' shared cluster reaped 6.4, the README's
  Python sweep 5.8 and sweep command 5.4; every other under 5.6 s;
* mypy from an empty cache 25.7-26.9 s of user CPU (load 8-12); with ``--cache-dir
  /dev/null`` (no cache written) 25.7-26.0 against 26.4-26.9, with numba and llvmlite not
  followed 26.2 (and six unused ``type: ignore`` errors): neither kept. A worker's collection
  3.1 s;
* the coarse report beside the tests, in that run: 106.4 s of its cases' CPU
  (``case_cpu_s``; hemisphere-plies 41.4, hemisphere-forming 17.3, bai-5.1 7.8, bai-6.1.1
  5.2, plies-bai-5.1 4.9, bai-6.2.1 4.9, bai-6.1.2 4.5, bai-6.1.1-sensitivity 4.5, bai-6.2.2
  4.2, the other 14 cases 10.9), 306.9 s of its wall at that load;
* numba's builds: 203 in the run's cache, one a kernel's second (the curved friction's
  ``_local_loads_part`` for complex128 beside float64: the complex-step test's, on purpose;
  benchmarks/suite_signatures.py). What is left of the 607 s after the above, about 60-70 s,
  is the builds' compiling, shared by the report's processes and the tests' under the
  compile locks.

So no single item or duplicate is left that would take the 90 s a run of 4:30 needs: the
tests' own runs are about 360 s spread thin. Cut from it (CPU of the items with their reaped
children, old and new in turns, warm cache, one numba thread):

* the report's kill test (tests/test_report_workers_end_with_it.py) kills the report 0.5 s
  of a worker's CPU past its imports, not 2 s: 3 s of CPU less (two workers, 1.5 s each),
  by construction (the killed workers are not reaped by pytest); its wall 21.5 and 15.7 ->
  9.6 and 6.2 s (load 6). With the workers' initializer taken out (validation/report.py
  ``_end_with`` returning at once) it still fails: "workers [...] outlived the killed
  report";
* the paired sweep's own LocalCluster (tests/test_sweep.py ``paired_sweep``) of one worker,
  not two: its six tests 12.3 and 9.5 -> 7.2 and 6.8 s (load 5; the README's sweep command
  still runs its variants on two workers);
* the curved face's history test (tests/test_ply_search.py, two seeds) searches each of its
  67 states afresh on a copy of a block never asked (0.1 ms) instead of a model compiled
  again (12 ms): the same answers to the bit on all 120 states of both seeds, 6.6 -> 4.6 s
  (pytest's start included; load 10-13); with ``FacingSearch.fresh`` handing out the kept
  lists it still fails.

Tried and not kept: tests/test_cluster_idle.py's two clusters made one (the port and the
idle intervals asserted on the same cluster): 3.2 and 3.3 -> 2.7 and 2.9 s, too little for
two claims reported as one. The sweep against a scheduler's address (tests/test_sweep.py) on
the session's shared cluster instead of a LocalCluster of its own: with an identify test on
that cluster beside it 8.7, 8.7 and 9.0 -> 6.5, 6.6 and 6.8 s (load 5-6), but in a whole
run it would be the shared cluster's last user (not slow, it sorts after the slow tests that
wait, tests/conftest.py) and keep that cluster idling through them, at about 4 s of CPU a
minute for its one worker: about what it saved.

Where a whole run's CPU goes again (main 1620fbc, 3123 tests: CI140 452 s of pytest, 857 s
of user CPU, the wall following the CPU on its 2 cores). A fresh clone, a fresh numba cache,
``python benchmarks/suite_signatures.py --run -- python -m pytest --durations=0`` (load 0.2
rising to 6 as other jobs started: 13 min 2 s wall, 837 s of user + system CPU):

* numba compiling 161.5 s (19 %): 477 compilations in 6 processes, 150.6 s of them the project's
  kernels in 270 compilations, spread thin (the largest the curved friction's local loads, real
  and complex, 5.9 + 7.5 s; the fibrous Hessian's cells 7.6 s; the fabric section's response 5.9
  s; every other under 3.7 s); the parallel builds 30.2 s, all in the worker that ran the tests
  marked ``parallel`` (their only callers: they compare those builds' bits). Three second builds
  (``law_row`` three times, kept: elements/fibrous/level_lanes.py; the complex local loads, the
  complex-step test's) and six builds again in another process (3.1 s: the supernodal factors
  compiled for a generic CPU in a subprocess of their own, on purpose);
* the pace test (tests/test_hemisphere_plies_pace.py, the Mindlin [0/90] run at x4 and x8)
  about 165 s of one worker's CPU (170 s of wall in CI140, 163 s alone and quiet): a fifth
  of the run; the only test of its claim, and no other test or the coarse report runs it;
* mypy from an empty cache 25.5 s of user CPU (load 2.5-3.2). Its ``--timing-stats``: the
  five packages 28.3 of 31.3 s of per-module time (elements/ 20.9 s, mindlin_fabric.py the
  largest at 1.3 s), the installed packages and the standard library about 2.5 s (numba 0.7,
  distributed 0.7, numpy 0.3, matplotlib 0.2, rich 0.2, dask 0.1): not following them would
  save at most that and leave the calls into them unchecked. mypy 2.4's native parser is
  already its default; its worker processes (``-n 2``, from an empty cache, once each, one
  after the other, load 5.3-5.8) 26.7 s of user + system CPU against 26.6 with ``-n 0``
  (40.9 against 40.2 s of wall): nothing to cut in the configuration;
* the coarse report alone on a warm cache (``--jobs 2``, load 4-5.8): 68.5 s of CPU, 64.2 s
  of it its cases' (hemisphere-plies 23.3, hemisphere-forming 14.5, every other under 3.1),
  its 49 figures and files about 4 s;
* the 44 slowest items that read no report, run no cluster and are neither the pace test
  nor mypy (one process, ``-n 0``, the order pytest gives; load 4-5): 214.0 s of CPU cold
  (a fresh cache), 86.4 s warm: 128 s of compiling, paid by whichever item asks first (the
  ply penalty's run 53.7 cold against 14.8 warm, the identify test 38.8 / 2.9, the ply
  margin 19.8 / 3.3); the largest warm the ply penalty's run 14.8, the forming blank at
  the default safety 8.4, the rotary-scaling cantilever 6.6 s.

Without the pace test a run is about 670-690 s of CPU, some 5.9-6.1 minutes on 2 cores at
CI140's use of them (857 s of CPU in 452 s of wall: 95 %): under 5 minutes (about 570 s of
CPU) needs the pace test out of the README's command (or its two runs a lot faster) and
about 110 s more from the rest, which is spread over thousands of items and the kernels'
first builds. Run so (21f50c6, a fresh clone and cache, ``python -m pytest --deselect`` the
pace test; load 2.3 rising to 10.4 with other jobs, then 2.7): 3122 passed in 17 min 15 s of
wall, 754.8 s of user + system CPU; at that load the CPU of the same work rises too (the
clusters' and the report's idle ticks over a longer wall, two cores shared by a dozen
processes), so the 82 s below the run above understate the pace test's 165 s.

Run: python benchmarks/suite_item_cpu.py tests/test_x.py::test_y ... [--against CHECKOUT]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

PLUGIN = """
import json, os, resource, time
import pytest

_cpu = {}

def _children():
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime

@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_protocol(item, nextitem):
    started, children = time.process_time(), _children()
    yield
    _cpu[item.nodeid] = (time.process_time() - started, _children() - children)

def pytest_sessionfinish(session):
    with open(os.environ["SUITE_ITEM_CPU"], "w") as f:
        json.dump(_cpu, f)
"""


def one_pass(
    checkout: Path, items: list[str], cache: str, plugin_dir: str
) -> dict[str, tuple[float, float]]:
    """CPU s per item of one pytest process on ``cache``: its own, and that of the processes
    it reaped during the item (a subprocess, a Dask cluster's workers)."""
    out = Path(plugin_dir) / "cpu.json"
    one = {"NUMBA_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1"}
    env = {**os.environ, **one, "NUMBA_CACHE_DIR": cache, "SUITE_ITEM_CPU": str(out),
           "PYTHONPATH": os.pathsep.join([plugin_dir, str(checkout)])}  # fmt: skip
    load = os.getloadavg()[0]
    command = [sys.executable, "-m", "pytest", "-q", "-n", "0", "-p", "no:cacheprovider",
               "-p", "suite_item_cpu_plugin", *items]  # fmt: skip
    done = subprocess.run(command, env=env, cwd=checkout, capture_output=True, text=True)
    last = done.stdout.strip().splitlines()[-1] if done.stdout.strip() else done.stderr[-500:]
    print(f"  pass in {checkout.name}: load {load:.1f} -> {os.getloadavg()[0]:.1f}, {last}")
    return {item: tuple(cpu) for item, cpu in json.loads(out.read_text()).items()}


def measure(checkout: Path, items: list[str]) -> None:
    with tempfile.TemporaryDirectory() as cache, tempfile.TemporaryDirectory() as plugin_dir:
        Path(plugin_dir, "suite_item_cpu_plugin.py").write_text(PLUGIN)
        print(f"{checkout}:")
        cold = one_pass(checkout, items, cache, plugin_dir)
        warm = one_pass(checkout, items, cache, plugin_dir)
    nan = (float("nan"), float("nan"))
    print(f"  {'cold s':>8} {'warm s':>8} {'compile':>8} {'children':>17}  item")
    for item in cold:
        (c, c_children), (w, w_children) = cold[item], warm.get(item, nan)
        print(f"  {c:8.1f} {w:8.1f} {c - w:8.1f} {c_children:8.1f} {w_children:8.1f}  {item}")
    c, c_children = (sum(cpu[k] for cpu in cold.values()) for k in (0, 1))
    w, w_children = (sum(cpu[k] for cpu in warm.values()) for k in (0, 1))
    print(f"  {c:8.1f} {w:8.1f} {c - w:8.1f} {c_children:8.1f} {w_children:8.1f}  all")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("items", nargs="+", help="pytest node ids or files")
    parser.add_argument("--against", type=Path, help="another checkout, measured first")
    args = parser.parse_args()
    for checkout in ([args.against.resolve()] if args.against else []) + [ROOT]:
        measure(checkout, args.items)


if __name__ == "__main__":
    main()
