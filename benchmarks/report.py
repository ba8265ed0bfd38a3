"""The validation report's cost, case by case: wall and CPU time of each case's computation and
of its figures at one resolution, each case in a fresh process of its own (as a worker of
``python -m validation --jobs N`` meets it: its imports and numba's cached kernels loaded
once), one case at a time; then the report's fixed costs (the imports of the cases, numba's
kernels loaded from a warm cache, the HTML page) and the whole report run as a user runs it.

The cases run on one numba thread unless NUMBA_NUM_THREADS says otherwise (the report's
workers share the cores). CPU time is the process's user + system time, its children's
included. The machine's load (os.getloadavg) is printed before and after, as other jobs may
share the cores: a figure measured beside a busy process is the wall time of a shared core.

Measured (one thread, 2 cores shared with other jobs, load 4-10; CPU of computation + figures):
coarse, 22 cases, 556 s (the first case compiling a cold cache): hemisphere-forming 131,
plies-bai-5.1 77, plies-deck-of-cards 52, bai-5.1 38 (warm), bai-6.1.1-sensitivity 29, the
four other paper cases 16-21, the 14 others 1-11. Default, 17 cases in 275 s: bai-6.2.1 67,
bai-6.1.1 66, bai-6.1.2 49, bai-6.2.2 46, bai-6.1.1-sensitivity 40, plies-heavy-cantilever 28,
heavy-cantilever-nonlinear 19, the 10 others 1-6 (bai-5.1, plies-bai-5.1, plies-deck-of-cards
and hemisphere-forming measured apart: validation/report.py EXPECTED_CPU_S). A paper case's
figures and VTU/XDMF files take 6-8 s of it (matplotlib's layout and text, the XDMF series);
each process's imports 2.6-3.3 s; numba's cached kernels load at their first call (1.8 s
for mindlin-elastica's 8, 1.2 s of it numba's setup of its registries, once per process).

Since then (load 9-11 on 2 cores, other jobs running; CPU best of 2 side by side with the
code before, fresh processes, one thread): the fabric section response of MindlinShell(fabric)
compiled (elements/fabric_section_kernels.py): 1015 -> 27 us per call with the Hessian at 20
cells (the Mindlin ply's force 1.47 -> 0.77 ms, its tangent 2.57 -> 1.63 ms); the 4-ply deck of
plies-deck-of-cards on 20 cells 13.8 / 15.2 -> 10.5 / 9.4 s CPU, 258 -> 220 Newton iterations
(the free end within 3e-13 mm: the round-off of the new sums moves the linear convergence near
separation, so part of the gain is the path's, not the kernel's; about 56 -> 45 ms per
iteration). bai-6.1.1-sensitivity's Dask cluster takes one worker per numba thread of its
report worker (one at --jobs 2 on 2 cores, two before). The default resolution is still far
from 60 s: hemisphere-forming alone took 168 s, the ply contact's facing search and the
Mindlin tangent remain numpy. The coarse report with these changes (python -m validation
--resolution coarse --jobs 2, load 10.6-14 with other jobs, another coarse report among them):
22 cases, every check passed, 529 s CPU (user 519, system 9; its workers and their Dask
workers included), 1739 s wall (the shared cores' wall, not a figure of the report).

The plies' increments cut once (one thread, CPU, the same process measuring each run; load
7-9 on 2 cores with other jobs, 2.8 at the end): an increment of a model whose only
interactions are the plies' contact, which keeps no contact set, was tried a second time under
the unilateral law, the same iterations again, before it was cut; and a new pattern of K_ff
(the plies' contact changes it at almost every iteration) takes the band on the last QDLDL
measurement. plies-bai-5.1's plies run (30 cells, 8 plies, default): 320.2 -> 217.6 s CPU, the
same 476 converged Newton iterations in the same 20 increments and 4 cuts, the cut attempts
1126 -> 596 iterations, 1610 -> 1076 tangents (989 new patterns), its material lines the
same to 3e-13 deg and 5e-14 mm; in a profiled run of the code before (wall, load 7-9) the
solve spent 44 % in the tangents, 26 % in the factorisations (18 % choosing the band, a QDLDL
factor per new pattern), 19 % in the plies' facing search and 17 % rebuilding the assembly's
map per new pattern (8 % compiling a cold numba cache). plies-deck-of-cards' heavy stacks (20
cells): N = 8 45.4 -> 36.2 s CPU (4 cuts, 146 -> 73 iterations cut), N = 4 15.3 -> 15.0 s, the
same equilibria to 1e-6 deg and mm printed. The band reuse alone is neutral there (the heavy
stack's patterns choose QDLDL: 281 of 306 new patterns factorised by it anyway; factorise 2.3
of 16.4 s CPU).

A new pattern's analysis made cheaper, the same bits (one thread, CPU; old and new side by side
in fresh processes, load 5-9): the assembler's map counted per node pair and the upper plan's
mirrors by a transpose (benchmarks/tangent_pattern.py). plies-bai-5.1's plies run alone
(30 cells, 8 plies, default): 100.2 -> 80.9 s CPU, the map's 755 rebuilds 33.4 -> 15.2 s, the
754 plans 4.8 -> 1.7 s, the same 465 Newton iterations and 3 cuts, the final positions and
directors equal to the bit (coarse, 4 plies: 22.1 -> 19.8 s, 358 iterations, 6 cuts, the same
bits); with the places gathered by one flat index (benchmarks/tangent_pattern.py), again side
by side (load 5-7): 113.4 -> 77.8 s, the rebuilds 33.0 -> 12.1 s, the plans 4.8 -> 1.7 s, the
same iterations, cuts and bits. The two cases as the report runs them (python -m validation --cases
plies-bai-5.1,plies-deck-of-cards --resolution default --jobs 1, old and new at once, load
14 -> 5): plies-bai-5.1 130.2 / 131.6 s CPU (the cut lost in the noise of the shared cores:
its fibrous and Mindlin runs' wall times moved 130 / 312 and 55 / 10 s between the two),
plies-deck-of-cards 55.7 / 50.4 s; their results.json the same in every value but the times.
The profile of the plies run before (cProfile, wall 604 s for 136 s CPU at load 14-16) put
the rest in the plies' facing search (25 %), the Mindlin plies' tangents (15 %, 8-9 ms for
the 960 triangles, numpy: one block instead of 8 measured 1-3 ms less) and the contact's
tangent (16 %), the band's numeric factorisations (6 %) and its orderings (2 %).

Measured again (one thread, 2 cores shared with other jobs, load 5.6-10.6, CPU of
computation + figures): default bai-5.1 45.4 + 7.2 s (1800 Newton iterations in its 7 runs),
bai-6.1.1 52.8 + 7.6 s. The coarse plies-bai-5.1's plies run (12 cells, 4 plies; load 12-13,
one process after the other): in 10 increments per phase 50.3 s CPU (358 converged Newton
iterations, 6 cuts, 370 iterations cut, 734 tangents), in 20 increments 47.5 s (340, 3 cuts,
447 cut, 790 tangents), the same equilibrium (the material line within 1.9e-9 deg and 6e-11
mm): more tangents, a CPU difference within what the load moves, so the coarse run keeps 10.
The default report of the 19 cases other than plies-bai-5.1, plies-deck-of-cards and
hemisphere-forming (python -m validation --resolution default --jobs 2, load 14 -> 3.9): every
check passed, 14.0 min wall, 330.5 s CPU (user 325.3, system 5.2), the cases' CPU: bai-6.1.1
59.0, bai-6.2.1 58.2, bai-5.1 53.6, bai-6.1.2 39.0, bai-6.2.2 30.2, plies-heavy-cantilever
22.3, bar-wave 12.0, heavy-cantilever-nonlinear 8.7, the 11 others 0.3-4.1 each (the
sensitivity's Dask workers not in its 4.1). With plies-bai-5.1 (201 s), plies-deck-of-cards
(99 s) and hemisphere-forming (205 s) the whole default report is about 835 s of CPU: at
least 420 s wall on 2 free cores, far from 60 s.
Coarse, the three longest (python -m validation --resolution coarse --jobs 2, load 2.2-2.9):
hemisphere-forming 86.3 s CPU, plies-bai-5.1 43.3, plies-deck-of-cards 27.6; 166 s CPU in all,
2.8 min wall.
Each report now records each case's CPU time (results.json ``case_cpu_s``, the worker
process's) beside its wall time, and prints it on the case's line.

Where the default resolution's CPU goes, looked for waste that is not physics (one numba
thread, CPU time, 2 cores shared with other jobs at a load of 5-15; cProfile figures are of
profiled runs, their shares the point):
- bai-6.1.1 (7 arc-length Static runs: three kinematics on 20 cells, fibrous and Mindlin on
  10 and 40 for the orders; 515 increments): computation 25.3-27.1 s CPU on a warm numba cache,
  107 s on a cold one (140 s of a profiled run compiling); figures and files 6.5 s in a fresh
  process, 4.0 s with matplotlib warm (the side panels 1.0, the side elevation 1.0, the 3D view
  0.8, the laws 0.5, the XDMF series of the three runs 0.65, the VTU 0.07). In the profiled
  computation the factorisations take 40 % (QDLDL's numeric updates 28 %: 71 ms each on the
  40-cell fibrous corner, 4025 unknowns, 833k entries in L after AMD; the band LDL^T of
  solvers/band.py on the same four matrices 78-107 ms against QDLDL's 82-100 ms, its RCM band
  6.1 times QDLDL's operations: no gain in choosing it there), the element tangents 31 % (the
  fibrous membrane Hessian and loads), the assembly 11 % (of it the node blocks' stacked
  numpy products, 3.4 s of 57 s profiled), the residuals and the path the rest.
  Tried and taken out: the SparseTangent's node blocks added by a compiled pass with T's
  shape (66 products a block where the stacked products take 330, straight into K_ff's data
  at the positions found once, as the cell parts' pass): a whole assembly of the fibrous
  corner 0.49 -> 0.23 ms on 10 cells (1584 node blocks), 2.16 -> 0.80 on 20 (6849), 11.31 ->
  7.70 on 40 (28479), K_ff the same to 5e-18 of its largest entry (best of 20, load 10); the
  whole case with the numpy pass and the compiled one in one process, both orders (load
  10-15): bai-6.1.1 27.1 / 22.7 s and 22.7 / 25.9 s CPU (numpy / compiled; the first
  computation in a process 3-4 s dearer), bai-6.2.2 old, new, old, new 14.1, 12.6, 12.4, 12.6
  s: no gain beyond the noise, while every check value moved by up to 5.6e-12 relative (the
  sums in another order; the same increments and Newton iterations), so the numpy pass stays.
- hemisphere-plies, Mindlin [0/90] on 8 cells, the first 0.01 s of the stroke (999 steps;
  and 0.002 s on a warm cache): the march is the contacts' searches, the plies' facing search
  (ply_projection.closest_facing, once per step and direction: the friction's history at the
  committed state reuses the loads' search) about half, the die's facets (rigid_surface
  _closest) about a fifth, the shells' forces a small part; the 100 frames and the history
  rows do not show. On a cold cache the run's start compiled 85 s (the Gershgorin bound's
  kernels 52 s).
- numba: the report's workers are spawned processes that load the kernels from the on-disk
  cache (0.002 s run above: 3.2 s of cache loads profiled, nothing compiled); a fresh checkout
  or a changed kernel file makes the first report compile (each worker the kernels its cases
  meet first, both workers the same kernel when they meet it at once).
- per worker process: the imports of validation.cases 1.5-1.8 s CPU; the references: the
  plies' nets 1.9 s (once per case), hemisphere-forming's net 0.85 s; bai-6.1.1-sensitivity's
  LocalCluster of one worker, started, one task and closed, 2.5 s CPU with its processes.
- the plies cases (validation/ground_truth.py) run fibreshell's run_case and run_plies into a
  scratch folder, whose frames (VTU series, history, summary) no check or figure reads: on
  plies-heavy-cantilever coarse (5.4 s of computation) 0.4 s of 11.3 s profiled (4 %); left,
  as run_case has no run without its files.
- No model is solved twice: the paper cases' orders reuse the resolution's own mesh,
  plies-deck-of-cards its N = 2 deck at the middle mesh, the sensitivity runs 12 cells where
  bai-6.1.1 runs 20; the plies cases' fibrous and Mindlin runs (the case files' solver) are
  not the paper cases' arc-length runs.
So at the default resolution the CPU is the solves (the Static factorisations and tangents,
the explicit contact searches): the figures and files are 4-8 s a paper case, the imports
and the cache loads a few seconds a worker. The whole default report was not run again here
(about 1300 s of CPU, at least 650 s wall on two free cores; hours at the load these figures
were measured at); nothing here changed its CPU, which EXPECTED_CPU_S (validation/report.py)
states.

The coarse report's waste cut (python -m validation --resolution coarse --jobs 1, one numba
thread; the code before, main 544e521, and the code after run at the same time side by side,
each on one of the 2 cores shared with other jobs, load 3.1-5.5; case CPU = results.json
``case_cpu_s``, before / after, s): hemisphere-plies 102.5 / 101.2, hemisphere-forming 28.7 /
25.2, plies-bai-5.1 22.3 / 22.7, plies-deck-of-cards 15.5 / 14.9, bai-5.1 13.9 / 13.2, the
four other paper cases 29.5 / 29.8, the 14 others 13.6 / 12.4; the cases 226.0 / 219.4 s, the
whole process 235.5 / 227.7 s (user + system), every check passed in both. Every check
value and parameter of results.json the same in both (only the times differ). The same
report before, alone on a quieter machine (load 1.5-2.9): 213.5 s of the cases, 221.5 s in
all. What was cut: the kernels' parting check walked each loop again for every name it
stores (benchmarks/kernel_parting.py: 1.4-1.8 -> 0.24 s a process, once in each report
worker and each test process that runs a kernel); the pin-jointed nets marched crossing by
crossing (benchmarks/drape_net.py: 0.59 -> 0.023 s a net, three in the coarse report); a
rigid tool's offset and ``moves`` evaluated some ten times a step (benchmarks/tool_offsets.py:
hemisphere-forming coarse -11 %). Tried and taken out: the assembler's map of K_ff rebuilt
from the sorted keys of the leading parts that kept their structure (the plies' elements
while their contact changes): the same map, the builds of plies-deck-of-cards coarse 2.18 ->
1.88 s of its 15 s (450 builds), plies-bai-5.1 coarse 24.1 / 27.4 -> 24.9 / 25.6 s (no gain
beyond the noise): not worth its code. Where the rest goes (cProfile of each case coarse,
shares of the profiled run): hemisphere-plies about 60 % in the ply contact's facing search
and friction (elements/ply_projection.py, ply_friction.py: the search once per state and
block, the friction's return mapping twice a step, at the commit and in the next force), the
die's facet search and the assembled stable step 3-6 % each; hemisphere-forming the die's
facet search (about 20 %), the element and contact forces, the assembled Gershgorin step (6
%); plies-bai-5.1 and plies-deck-of-cards the ply search in the tangents (about 25 %), the
K_ff map per new pattern (10-15 %, of it np.unique's sort 8-10 %), the band choice and the
factorisations (10 %); the plies cases' scratch frames 1.5 % (0.4 s), a paper case's figures
and files 3-4 s (matplotlib's constrained layout a third of it, its XDMF series 0.5-1 s).
The default report was not run again (about 1300 s of CPU, hours at this load): the same
cuts apply there (the parting and the nets per process and case, the tools' offsets in the
explicit forming runs), a few per cent of it; its CPU is still the solves above.

The paper cases at the default resolution, where their CPU goes and what was cut (one numba
thread, CPU time, 2 cores shared with other jobs at a load of 5-13). bai-6.2.1 in a fresh
process: imports 1.5 s, computation 19.6-21.0 s, figures and files 4.3 s (2.8 s with matplotlib
warm: the side panels 0.7, the side elevation 0.7, the 3D view 0.5, the laws 0.3, the XDMF
series of the three runs 0.45, the VTU 0.01-0.05). The computation is its seven Static solves
(no other part above 0.1 s): the fibrous run on 40 cells (4025 unknowns, 74 Newton iterations)
10.2-10.6 s, of it 5.9 s in 76 QDLDL factorisations (75 ms each); the fibrous Eq. 15 run on 20
cells 2.8-2.9 s (its membrane tangent by central differences of the numpy loads, 31 ms a
tangent, 75 tangents), the default fibrous run 2.1-2.5 s, the Mindlin run on 40 cells 2.7 s,
the four others 0.2-0.7 s each. bai-6.1.1 alike: computation 20.8 s, its 40-cell fibrous run
11.1 s with 6.2 s in 75 QDLDL factorisations, the 20-cell runs 2.2 / 2.9 / 0.7 s, the 40-cell
Mindlin 3.2 s, the 10-cell ones 0.45 / 0.25 s. No waste found in the path: 19-21 increments and
3.5 Newton iterations per increment on the corners, no cut, one tangent and one factorisation
per iteration, the assembly's map built once per model, every figure and file written once.
Cut: the band LDL^T eliminates within the envelope of the ordered matrix (the same factors to
the bit: benchmarks/band_envelope.py) and is chosen by the envelope's operations, so the
fibrous corners leave QDLDL (40 cells: 75 -> 53 ms a factorisation; the run's 76 factorisations
5.91 -> 4.44 s). Tried and taken out: the side elevation's lines through the thickness as one
LineCollection (0.59-0.66 -> 0.55-0.59 s, within the noise); the Eq. 15 membrane tangent's 36
perturbed states stacked along the cell axis into one call of the numpy loads (the same bits;
29.6-30.1 -> 33.8-35.4 ms a tangent on 20 cells: the loads' arithmetic, not numpy's overhead
per call, is its cost). The six paper cases, code before (main 036d613) and after run at the
same time side by side (python -m validation --cases
bai-6.2.1,bai-6.1.1,bai-6.1.2,bai-6.2.2,bai-5.1,bai-6.1.1-sensitivity --resolution default
--jobs 1, one per core, load 11.9 -> 5.0; case CPU = results.json ``case_cpu_s``, before /
after, s): bai-6.2.1 23.9 / 21.5, bai-6.1.1 22.1 / 19.9, bai-6.1.2 13.9 / 13.1, bai-6.2.2 13.0
/ 12.3, bai-5.1 19.0 / 19.0, bai-6.1.1-sensitivity 1.2 / 1.3 (its Dask worker's CPU not
counted); 93.1 / 87.1 s, the whole process (user + system) 102.3 / 96.4 s, 7.4 / 7.2 min wall.
Every check passed in both; the same increments, Newton iterations and cuts in every run; every
number of results.json the same but for round-off (among the values above 1e-9 in size the
largest relative difference 1.7e-6: a shear angle of 1.8e-9 deg), the printed digits of the
report the same but for the runs' times and four check values that are zero to round-off (three
Eq. 15 director tilts of 1.4e-14 to 4.3e-14 deg, tolerance 1 deg; a thinnest thickness 1 -
1.1e-16 -> 1). These figures are far below the 30-59 s measured earlier at loads of 4-14
(validation/report.py EXPECTED_CPU_S, now the figures after): a case's CPU time on a shared
core grows with the load.

The default report's cases profiled again for what does not serve the result (one numba
thread, CPU; 2 cores shared with other jobs at a load of 9-15, so the figures are ratios of
runs side by side, the code before, main 14e312d, and this tree's at once, one per core):
- bai-6.1.1 (cProfile, wall shares of a profiled run): the seven Static solves 68 % (the
  40-cell order runs 43 %: factorisations 20 s of 176 profiled, the fibrous membrane Hessian
  13.5, the linear solves 11, the assembly 12), figures and files 20 % (constrained layout
  7 %, the XDMF series 3 %: an HDF5 dataset per field and frame), imports 12 %. The
  arc-length runs converge in 3.6-3.9 Newton iterations an increment, quadratically: a
  looser tolerance (1e-6 for 1e-8) saved 3-8 of 98-108 iterations on bai-6.1.2's runs, CPU
  9.3 -> 8.4 s at load 12 (within its noise), every checked number moved: not kept.
- bai-6.1.1-sensitivity: its eight 12-cell runs 6.6 s of CPU in one process, the case's
  process tree (python -m validation --cases bai-6.1.1-sensitivity --jobs 1, user + system)
  12.86 s with its one Dask worker, 10.10 s with the runs in the report's process (the
  sweep's ``in_process``, taken when the report worker has one numba thread), side by side,
  load 11; results.json's 35 numbers the same.
- hemisphere-plies: outside its four explicit runs (96 s of CPU) 8.6 s: the plies' nets, the
  model builds (a 48-ring die zipped ring by ring, 0.2 s a run), the least gaps to the
  bottom ply's face over the run's frames (twice a run, the flat facets' over the frames
  discarded). With the die's arrays made once and the flat facets measured at the end
  alone: 8.62 -> 7.38 s, the case 103.7 -> 102.5 s CPU (side by side, load 9-14), the same
  313 numbers in results.json.
- the explicit balance check (every 10 steps) asked each frictionless tool for its
  distances again for its strain energy, which the step's forces give (elements/contact.py
  ``strain_energy``): a force + energy pass of hemisphere-forming's Mindlin blank
  mid-stroke 422-558 -> 370-383 us (load 15); hemisphere-forming 54.5 -> 54.3 s CPU side by
  side (load 11-12: within the noise, 1-3 % expected).
The report's CPU remains its solves: the explicit forming runs (hemisphere-plies,
hemisphere-forming: their steps, the step's bound and the ply contact's facing) and the
Static ply and paper runs (tangents and factorisations); no run solved twice was found
beyond those listed above, no output written each step.

Run: python benchmarks/report.py [--resolution default] [--cases a,b] [--report JOBS]
(``--report JOBS``: also time ``python -m validation`` on all the cases with --jobs JOBS);
python benchmarks/report.py --reference PATH [--repeats N] [--cases a,b]: each case's CPU
with the code of the checkout at PATH (the code before, ``git worktree`` or ``git archive``)
and with this one's, in fresh processes, alternating, the least of N each and their ratio.
Each child runs with its tree first on PYTHONPATH (before, a child imported the installed
copy of the package, which need not be this tree's).
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

if "--child" not in sys.argv:  # a --child: the tree its parent named (PYTHONPATH)
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this tree's packages


ROOT = Path(__file__).resolve().parents[1]


def _cpu() -> float:
    """User + system CPU time of this process and its waited-for children (s)."""
    own = resource.getrusage(resource.RUSAGE_SELF)
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def _one(name: str, resolution: str, out: Path) -> dict:
    """Compute and render one case here (the child's side): the times of each part."""
    wall, cpu = time.perf_counter(), _cpu()
    from validation.cases import CASES

    imports = (time.perf_counter() - wall, _cpu() - cpu)
    case = CASES[name]
    wall, cpu = time.perf_counter(), _cpu()
    outcome = case.compute(resolution)
    compute = (time.perf_counter() - wall, _cpu() - cpu)
    wall, cpu = time.perf_counter(), _cpu()
    figures = case.render(outcome.data, out)
    render = (time.perf_counter() - wall, _cpu() - cpu)
    return {
        "imports": imports,
        "compute": compute,
        "render": render,
        "passed": sum(c.passed for c in outcome.checks),
        "checks": len(outcome.checks),
        "steps": outcome.steps,
        "solver": outcome.solver,
        "figures": len(figures),
    }


def _child(name: str, resolution: str, tree: Path = ROOT) -> dict:
    """One case in a fresh process with the code of the checkout ``tree`` (this one by
    default: its folder first on the child's path, before an installed copy); its times."""
    environment = {**os.environ, "PYTHONPATH": str(tree)}
    with tempfile.TemporaryDirectory() as out:
        command = [sys.executable, __file__, "--child", name, "--resolution", resolution,
                   "--out", out]  # fmt: skip
        done = subprocess.run(
            command, cwd=tree, env=environment, capture_output=True, text=True, check=False
        )
    if done.returncode != 0:
        raise RuntimeError(f"{name}: {done.stderr[-2000:]}")
    return json.loads(done.stdout.strip().splitlines()[-1])


def _side_by_side(names: list[str], resolution: str, reference: Path, repeats: int) -> None:
    """Each case's CPU (computation + figures, its process's children included: a sweep's
    Dask workers) with the code of ``reference`` and with this tree's, each in fresh
    processes, alternating, ``repeats`` times; the least of each, their ratio and the checks
    passed, with the machine's load."""
    print(f"resolution {resolution}, NUMBA_NUM_THREADS={os.environ['NUMBA_NUM_THREADS']}, "
          f"reference {reference}, best of {repeats}; load before: {_load()}")  # fmt: skip
    print(f"{'case':28s} {'reference CPU':>13s} {'this CPU':>9s} {'ratio':>6s}  checks")
    totals = [0.0, 0.0]
    for name in names:
        best: list[float] = [float("inf"), float("inf")]
        passed = ["", ""]
        for _ in range(repeats):
            for k, tree in enumerate((reference, ROOT)):
                t = _child(name, resolution, tree)
                best[k] = min(best[k], t["compute"][1] + t["render"][1])
                passed[k] = f"{t['passed']}/{t['checks']}"
        totals = [totals[0] + best[0], totals[1] + best[1]]
        print(f"{name:28s} {best[0]:13.1f} {best[1]:9.1f} {best[1] / best[0]:6.3f}  "
              f"{passed[0]} / {passed[1]}  (load {_load()})", flush=True)  # fmt: skip
    print(f"{'all':28s} {totals[0]:13.1f} {totals[1]:9.1f} {totals[1] / totals[0]:6.3f}")
    print(f"load after: {_load()}")


def _load() -> str:
    return ", ".join(f"{x:.2f}" for x in os.getloadavg())


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--resolution", default="default")
    parser.add_argument("--cases", default=None)
    parser.add_argument("--report", type=int, default=0)
    parser.add_argument("--child", default=None)
    parser.add_argument("--out", default=None)
    parser.add_argument("--reference", default=None)
    parser.add_argument("--repeats", type=int, default=2)
    args = parser.parse_args()
    os.environ.setdefault("NUMBA_NUM_THREADS", "1")
    os.environ["FIBRESHELL_PROGRESS"] = "0"
    if args.child:
        print(json.dumps(_one(args.child, args.resolution, Path(args.out))))
        return
    from validation.cases import CASES
    from validation.report import expected_cost

    names = args.cases.split(",") if args.cases else list(CASES)
    if args.reference:
        _side_by_side(names, args.resolution, Path(args.reference), args.repeats)
        return
    print(f"resolution {args.resolution}, NUMBA_NUM_THREADS={os.environ['NUMBA_NUM_THREADS']}, "
          f"{os.cpu_count()} cores; load (1, 5, 15 min) before: {_load()}")  # fmt: skip
    header = (f"{'case':28s} {'compute CPU':>11s} {'wall':>7s} {'figures CPU':>11s} {'wall':>6s}"
              f" {'expected':>8s}  checks  steps  solver")  # fmt: skip
    print(header)
    total_cpu = total_wall = 0.0
    fixed = []
    for name in names:
        t = _child(name, args.resolution)
        fixed.append(t["imports"])
        total_cpu += t["compute"][1] + t["render"][1]
        total_wall += t["compute"][0] + t["render"][0]
        print(f"{name:28s} {t['compute'][1]:11.1f} {t['compute'][0]:7.1f} {t['render'][1]:11.1f}"
              f" {t['render'][0]:6.1f} {expected_cost(name, args.resolution):8.0f}  "
              f"{t['passed']:2d}/{t['checks']:<3d} {t['steps']:6d}  {t['solver'][:70]}",
              flush=True)  # fmt: skip
    print(f"{'all cases':28s} CPU {total_cpu:.1f} s, wall {total_wall:.1f} s (one at a time)")
    imports = min(fixed, key=lambda f: f[1])
    print(
        f"per process, best of {len(fixed)}: imports {imports[1]:.2f} s CPU / {imports[0]:.2f}"
        " s wall (numba's cached kernels load at their first call, inside the case's time)"
    )
    if args.report:
        with tempfile.TemporaryDirectory() as out:
            command = [sys.executable, "-m", "validation", "--resolution", args.resolution,
                       "--jobs", str(args.report), "--out", out]  # fmt: skip
            if args.cases:
                command += ["--cases", args.cases]
            wall, cpu = time.perf_counter(), _cpu()
            done = subprocess.run(command, cwd=ROOT, capture_output=True, text=True)
            wall, cpu = time.perf_counter() - wall, _cpu() - cpu
            results = Path(out) / "results.json"
            content = json.loads(results.read_text()) if results.exists() else {"cases": {}}
        print(done.stdout[-3000:])
        print(
            f"python -m validation --jobs {args.report}: wall {wall:.1f} s, CPU {cpu:.1f} s, "
            f"exit {done.returncode}, {len(content['cases'])} cases"
        )
        from validation.report import render_html

        wall, cpu = time.perf_counter(), _cpu()
        render_html(content)
        wall, cpu = time.perf_counter() - wall, _cpu() - cpu
        print(f"its HTML page alone: {cpu:.2f} s CPU / {wall:.2f} s wall")
    print(f"load after: {_load()}")


if __name__ == "__main__":
    main()
