"""Two-ply layups [0/90] and [0/45] formed on the hemisphere under a blank holder, fibrous and
Mindlin plies, each ply's shear angles against the pin-jointed net of its own orientation.

Source: the pin-jointed net of Mack and Taylor (J. Textile Inst. 47 (1956) T477) draped on
each ply's mid-surface sphere over the punch from its pole, its generators along that ply's
own fibres (validation/references/drape.py): where a ply lies in the die, its fibres, nearly
inextensible and free to shear, must form the net of its own orientation whatever the other
ply does, the two plies sliding on each other with friction.
Geometry and process (validation/studies/hemisphere_plies_setup.py): a 200 x 200 mm blank of
two 0.3-mm plies, the bottom one at 0 deg, the top one at 90 or 45 deg, centred on a rigid
punch (sphere of radius 50 mm) that moves 50.6 mm down (smooth amplitude) into a meshed
hemispherical die (radius 50.9 mm: the punch, the plies and a clearance of one ply; entry
radius 5 mm); a ring-shaped blank holder of 10 g on the flange, free to rise, pressed by
20 N (ramped over the first tenth), in contact with both plies' nodes (a rigid plate presses
whichever ply is under it). Ply on ply Coulomb friction 0.2 (elements/ply_contact.py,
both ways: the top ply's Gauss points and the bottom ply's nodes; docs/theory.md §9.3b), the
tools frictionless. Fabric: a G986-like ply (tension 60 N/mm, shear 0.2 N/mm, bending 0.375
N mm, 285 g/m^2); the Mindlin ply its equivalent elastic section (``ElasticShell.equivalent``,
the laws' initial slopes: ``Layup`` kinematics "mindlin-elastic", not the fabric's own laws
of "mindlin"; the tolerances below were measured on it) on B2's
closed-form rotary inertia (docs/theory.md §6.2; setup's ROTARY_SCALING lists no layup for the
element rule: on [0/90] it reached the quasi-static answer slowed x8 where the closed form
does slowed x2, docs/hemisphere_forming.md "The penalty at the closed j's step, the element
rule, and the two plies' pace").
Explicit, 0.1 s, no mass scaling, mass-proportional damping 20/s.
The Mindlin runs' pace: the Mindlin [0/90] stroke in 0.4 s (setup's STROKE_SLOWING, x4; x2
before, see below). At 0.1 s its largest inter-ply slip was 2.47 mm where the runs slowed x4
and x8 agree on 0.59 mm (rms 0.48 against 0.29 mm), its corners 4-8 mm more drawn in, and the
case's KE / W rule passed it (above 0.1 over 5.2 % of the run); slowed x2 single runs agreed
with x8, but over perturbed runs x2 snaps late in the stroke and its end measures are chance
(below); tests/test_hemisphere_plies_pace.py (slow) checks the run against one at half its
pace. The
Mindlin [0/45] runs do not converge with the pace up to x16 (their flange's wrinkles pick a
shape) and keep the 0.1-s stroke.
Measured so, the code before (the 0.1-s stroke) beside it in brackets (``python -m validation
--cases hemisphere-plies,hemisphere-forming --jobs 1``, one thread, back to back, the kernels
compiled by a run before, load 1.4-1.8): 24 of 24 checks, 34349 steps (26376), 48.2 s of CPU
for the case (40.3); Mindlin [0/90]: 16402 steps (8429), 18.9 s (11.0), largest slip 0.59 mm
(2.47), draw-in of the edge middle 30.2 / 30.3 mm (31.3 / 31.4), of the corners 12.8 / 12.9
mm (17.0 / 21.5), end force 137.6 N (115.9), ply 2's cells in the die 10 (13); every other
run's results the same bits. With the ply contact's landing points anchored where their way
crossed the lower face (docs/theory.md §9.3a, "A point's landing step"; their landing steps
were frictionless before): Mindlin [0/90] largest slip 0.687 mm (0.593 before), rms 0.297
(0.292), edge middles 29.8 / 29.9 mm (30.2 / 30.3), corners 11.3 / 12.1 mm (12.8 / 12.9), end
force 137.1 N (137.6): within the run's scatter under a change of mu by 1e-6 (the corners move
1-2 mm, tests/test_hemisphere_plies_pace.py); the fibrous runs by at most 0.5 %; Mindlin
[0/45] the 45-deg ply's edge draw-in 14.4 -> 9.5 mm (that run picks its wrinkles' shape: mu x
(1 + 1e-6) moves it 3.9 mm with the rule, to 13.40, its 0-deg ply's edge 5.7 mm without).
With the edge-gap points landing and leaving too (docs/theory.md §9.3a), the Mindlin [0/90]
run's checks pass at mu and at mu x (1 + d), d from -1e-5 to 1e-5 (seven runs): the share above
KE / W 0.1 0.011-0.045, the least gap in the die -0.145 to -0.149 mm, the holder 19.997-20.002
N; its reported measures move (largest slip 0.60-8.48 mm, corners 11.0-13.1 mm, end force
136.0-141.2 N: the run snaps late at that pace; slowed x4 the largest slip 0.56-0.60 mm,
the corners 13.0-13.2 mm over six such runs, x8 within them, tests/test_hemisphere_plies_pace.py;
validation/studies/hemisphere_plies_pace_scatter.py): the run is slowed x4 since, its reported
measures the quasi-static answer's, not one of chance, at twice the x2 run's CPU. These runs
are the landing rule's with its step fallback near T's plane; with the continuous one (docs/
theory.md §9.3a, ``ply_landing.TILT``) the x4 run at mu ends at 0.563 mm, rms 0.275 mm (0.568,
0.274 before; the history re-expressed by the same rule), its corners and edges within 0.1 mm,
and the pace test passes.
Not time-scaled: the fibrous [0/90]
stroke in 0.067 s (x1.5) put KE / W above 0.1 over 13.7 % of the judged run (peak 0.28) and
fails the quasi-static check, though its compared numbers hardly moved
(docs/hemisphere_plies.md, "Time scaling"). The centre lines held in their
symmetry planes.
The plies' automatic contact penalty against its limit (validation/studies/
hemisphere_plies_penalty.py; docs/hemisphere_plies.md, "The plies' penalty"): the fibrous
[0/90] results within 0.03 deg and 0.13 mm of eight times it, the Mindlin runs' within their
own scatter, the [0/45] stacks (crossing meshes) without a limit on the flat faces at 8 cells
(in shear and draw-in the faceting's error, not the penalty's; the punch's force not at
its limit).
Checked, per run: the run reaches the end of the stroke; each fibrous ply's rms of shear -
net over its cells in the die (the Mindlin plies' reported, not checked, as in
hemisphere-forming); the plies' order in the die (the top ply's least gap to the bottom ply
along the radius from the die's centre within one ply thickness); the holder's reaction over
the last tenth within 5 % of its force; quasi-static: the share of the run after its first
tenth with a kinetic energy above the field's 0.1 of the work at most a tenth, the rule of
hemisphere-forming (solvers/quasi_static.py ``KINETIC_SHARE``: a small KE / W throughout the
majority of the process), the largest KE / W reported beside it; the directors' rotation on
the Mindlin shell's scaled rotary inertia counted whole (docs/theory.md §6.3 says why; its
part and the translations' reported beside it).
The report runs the coarsest mesh that shows the physics (``CELLS``: 8 fibre segments across
the blank, 25-mm cells; at 6 cells the Mindlin [0/90] run stops at 70 % of the stroke, KE / W
0.31, and the fibrous [0/90] one reaches KE / W 0.18), both layups of both kinematics
(``RUNS``), the coarse report the fibrous layups (the test suite's background run, whose runs
tests/test_hemisphere_plies.py reads: 116 s of CPU for the case, the runs 59 and 48 s, 12 of 12
checks passing, load 3.2-4.7; the [0/45] run alone 89.6 s before); the finer mesh (10 cells,
the fine report: its four runs below) and the second holder force (40 N, the holder's
sensitivity) are the study's (validation/studies/hemisphere_plies.py), with what they gave
and what led to the settings. The runs are the case's independent parts (``parts``, gathered
by ``combine``): with several jobs the report runs each as a task of its own
(validation/report.py), with the same results as one after another.
Measured now (8 cells, 20 N, the holder on both plies, the fade's SIDEWAYS = 1; ``python -m
validation --cases hemisphere-plies --jobs 1``, one thread, load 3.8-5.6, compiling afresh:
the first run's CPU holds the kernels' compilation; per ply, ply 1 / ply 2, the rms of shear -
net over its cells in the die and their number; the holder's reaction over the last tenth and
its travel; KE / W at most after the first tenth, its rotational part in brackets; each ply's
face at most this far through the holder's over the run), 24 of 24 checks, 26376 steps, 102.1
s of CPU for the case:
- fibrous [0/90]: rms 3.46 / 3.51 deg (26 / 26 cells), draw-in of the edge middle 24.9 / 25.1
  mm, no crests, holder 20.01 N (0.06 mm down), KE / W 0.086, the plies' order -0.13 mm,
  through the holder -0.25 / 0.04 mm; 4131 steps, 47.9 s.
- fibrous [0/45]: rms 2.28 / 4.65 deg (14 / 36), draw-in 29.0 / 10.8 mm, crests up to 10.9 /
  10.7 mm, holder 19.62 N (10.6 mm up), KE / W 0.075, order +0.01 mm, through the holder 0.24
  / 0.17 mm; 4825 steps, 9.8 s.
- Mindlin [0/90]: rms 3.14 / 3.18 deg (20 / 13), draw-in 31.3 / 31.4 mm, crests up to 13.9 /
  13.6 mm, holder 20.45 N (13.5 mm up), KE / W 0.115 (0.057), above 0.1 over 5.2 % of the
  judged time, order -0.13 mm, through the holder 0.09 / 0.12 mm; 8429 steps, 16.6 s.
- Mindlin [0/45]: rms 3.02 / 4.77 deg (20 / 32), draw-in 30.1 / 14.4 mm, crests up to 13.0 /
  12.8 mm, holder 19.79 N (12.7 mm up), KE / W 0.088 (0.044), order +0.33 mm, through the
  holder 0.04 / 0.17 mm; 8991 steps, 15.7 s.
Measured before (the code of its time, with the fade's SIDEWAYS = 0.5 where it had the fade;
8 cells, 20 N, the holder on both plies; one thread, one run at a time, the run's CPU, load
2.8-8.2; the same figures):
- fibrous [0/90]: rms 3.46 / 3.51 deg (26 / 26 cells), draw-in of the edge middle 24.9 / 25.1
  mm, no crests, holder 20.00 N (0.1 mm down), KE / W 0.086, the plies' order -0.13 mm,
  through the holder -0.24 / 0.03 mm; 5280 steps, 65 s. Every check passes.
- fibrous [0/45]: rms 2.20 / 4.64 deg (14 / 36), draw-in 26.3 / 10.3 mm, crests up to 10.6 /
  10.4 mm (24.7 / 10.7 with the holder on the top ply alone: the study's docstring, "The
  holder on every ply"), holder 19.78 N (10.3 mm up), KE / W 0.075, order +0.01 mm, through
  the holder 0.11 / 0.21 mm; 5240 steps, 123 s. Every check passes.
- Mindlin [0/90]: rms 3.12 / 3.13 deg (20 / 13), draw-in 30.3 / 30.4 mm, crests up to 13.3 /
  13.0 mm, holder 20.21 N (12.9 mm up), KE / W 0.115 (0.051) at t = 0.044 s, order -0.14 mm,
  through the holder 0.07 / 0.15 mm; 9990 steps, 102 s; above 0.1 over 6.4 % of the judged
  time: every check passes. With a gap to an edge of the other ply's face signed by the
  edge's pseudonormal (one thread, load 0.3-2.2): rms 3.14 / 3.19 deg, draw-in 30.7 / 30.9 mm,
  crests up to 13.7 / 13.4 mm, holder 19.32 N (13.4 mm up), KE / W 0.115 (0.051), order
  -0.12 mm, through the holder 0.09 / 0.18 mm; 9993 steps, 76 s: every check passes.
- Mindlin [0/45]: rms 3.48 / 4.71 deg (26 / 34), draw-in 25.2 / 14.3 mm, crests up to 16.1 /
  16.0 mm, holder 19.85 N (16.0 mm up), KE / W 0.108 (0.065) at t = 0.060 s, order +0.25 mm,
  through the holder -0.01 / 0.13 mm; 9785 steps, 102 s; above 0.1 over 0.53 % of the judged
  time: every check passes.
With the holder on the top ply alone the whole case at this resolution passed its 24 checks
in 473 s of CPU (one job, load 1.2-3.8). The Mindlin flange snaps at 60-62 % of the stroke
(the bursts above 0.1 in the case's figure of KE / W against time); the check counts the
directors' kinetic energy on the Mindlin shell's scaled rotary inertia (docs/theory.md §6.3
says why, with the run that decides it: with that inertia's scaled part divided by 4, KE / W
0.104).
At 10 cells (the fine resolution; 20-mm cells; the ply contact faded by the distance to the
outline, elements/ply_fade.py) the four runs pass all their 24 checks (one thread, one or two
runs at a time, the run's CPU, load 5-11; per ply, ply 1 / ply 2, rms of shear - net over its
cells in the die and their number, draw-in of the edge middle, the holder's mean reaction
over the last tenth):
- fibrous [0/90]: rms 3.17 / 3.19 deg (52 / 52), draw-in 27.4 / 27.5 mm, holder 19.96 N,
  KE / W 0.090, order -0.075 mm; 7344 steps, 63 s.
- fibrous [0/45]: rms 3.57 / 4.38 deg (34 / 52), draw-in 23.4 / 7.4 mm, holder 19.85 N,
  KE / W 0.071, order -0.12 mm; 7387 steps, 70 s.
- Mindlin [0/90]: rms 3.40 / 3.37 deg (52 / 45), draw-in 27.0 / 28.0 mm, holder 19.41 N,
  KE / W 0.195, above 0.1 over 9.2 % of the judged time (10 % allowed), order -0.091 mm;
  17058 steps, 185 s (with the jump study's recorder).
- Mindlin [0/45]: rms 3.52 / 4.45 deg (46 / 56), draw-in 27.3 / 9.7 mm, holder 19.49 N,
  KE / W 0.131, above 0.1 over 2.0 %, order -0.094 mm; 15298 steps, 144 s.
The same code at 8 cells (per ply rms and draw-in of the edge middle): fibrous [0/90] 3.46 /
3.51 deg, 24.9 / 25.1 mm; fibrous [0/45] 2.27 / 4.65 deg, 28.4 / 9.7 mm (the coarse report, 12
of 12 checks, 100 s of CPU for the case); Mindlin [0/90] 3.14 / 2.86 deg, 31.5 / 31.7 mm (every
check); Mindlin [0/45] 3.34 / 4.73 deg, 28.1 / 10.2 mm (every check; 97 s). From 8 to 10 cells
the rms of shear - net moves by 0.2-1.3 deg (the most, fibrous [0/45]'s 0-deg ply: 2.27 -> 3.57
deg, 14 -> 34 cells in the die) and the draw-in by 2.3-5.0 mm (fibrous), 0.5-4.5 mm (Mindlin):
two resolutions, not yet an order of convergence. The holder's mean reaction over the last
tenth is its force plus its momentum change over the tenth, m dv / T
(``holder_inertia_last_tenth``), -0.61 N for Mindlin [0/90] here, -1.23 N (18.78 N) on the
barycentric fade of before, -1.59 N (18.43 N) at 8 cells with the wedge cuts: its check takes
m dv / T off, both reported beside it (docs/hemisphere_plies.md, "The holder at 10 cells").
The fine resolution again after the fade's clamp was made flat and the tangent's outline ends
trimmed (`python -m validation --cases hemisphere-plies --resolution fine`, one thread, quiet):
24 of 24 checks, 399.6 s of CPU; rms fibrous [0/90] 3.17 / 3.19 deg, holder 19.96 N; Mindlin
[0/90] 3.36 / 3.41 deg, holder 19.85 N, above KE / W 0.1 over 9.0 % (peak 0.131); fibrous
[0/45] 3.57 / 4.38 deg, holder 19.92 N; Mindlin [0/45] 3.34 / 4.42 deg, holder 20.34 N.
The step counts and times above are those of the code they were measured on; at 8 cells the
runs now take 4131 (fibrous [0/90]), 4825 (fibrous [0/45]), 8429 (Mindlin [0/90]) and 8991
(Mindlin [0/45]) steps with the fade's wedge full only along the normal (SIDEWAYS = 1, its
springs' factor 3 beside an outline vertex: elements/ply_fade.py, benchmarks/ply_step_bound.py;
5530, 5949, 11032 and 10814 at SIDEWAYS = 0.5, the factor 12) with the ply springs' nodes
weighed by their masses (docs/theory.md §6.2, "The penalty springs"; 5612, 6636, 11261 and
12573 before it, one thread; 6865, 6053, 13939 and 11868 with the couple of stuck points
facing an edge or a vertex, docs/hemisphere_plies.md) at 1.7-3.0 ms a step, one thread
(benchmarks/forming_step_overhead.py).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from validation.records import Case, Outcome, compute_parts
from validation.studies.hemisphere_plies_run import (
    NAME,
    SOURCE,
    TITLE,
    combine_plan,
    plan_parts,
    render,
)
from validation.studies.hemisphere_plies_setup import HOLDER_FORCES, LAYUPS

__all__ = ["CASE", "CELLS", "EVERY", "RUNS", "combine", "compute", "parts", "plan"]

# fibre segments across the blank per resolution: the study's coarse mesh but at "fine"
# (its runs at 10 cells cost 63-185 s of CPU each, every check passing: the docstring)
CELLS = {"coarse": 8, "default": 8, "fine": 10}
# the layups and kinematics run per resolution: the coarse report (the test suite's
# background run, whose two fibrous runs tests/test_hemisphere_plies.py reads: the suite runs
# each once) the fibrous layups, [0/90] with matching meshes and [0/45] whose plies' meshes
# do not match; the Mindlin runs cost 102 and 102 s more (the module's docstring)
EVERY = tuple((name, kinematics) for name in LAYUPS for kinematics in ("fibrous", "mindlin"))
RUNS = {"coarse": tuple((name, "fibrous") for name in LAYUPS), "default": EVERY, "fine": EVERY}


def plan(resolution: str) -> list[tuple[int, str, str, float]]:
    """The case's runs at ``resolution`` (``RUNS``) at the first holder force, as (cells,
    layup name, kinematics, holder force in N)."""
    return [
        (CELLS[resolution], name, kinematics, HOLDER_FORCES[0])
        for name, kinematics in RUNS[resolution]
    ]


def parts(resolution: str) -> dict[str, Callable[[], tuple]]:
    """The runs of ``plan(resolution)``, each an independent part of the case (the report
    runs them at once with several jobs): hemisphere_plies_run.plan_parts."""
    return plan_parts(plan(resolution))


def combine(resolution: str, made: dict[str, Any]) -> Outcome:
    """The runs of ``plan(resolution)``, ``made`` by ``parts``, with their checks
    (hemisphere_plies_run.combine_plan)."""
    return combine_plan(plan(resolution), made)


def compute(resolution: str) -> Outcome:
    """The runs of ``plan(resolution)`` one after another, with their checks."""
    return compute_parts(parts, combine, resolution)


CASE = Case(
    name=NAME,
    title=TITLE,
    source=SOURCE,
    description=__doc__,
    group="verification",
    order=115,
    compute=compute,
    render=render,
    parts=parts,
    combine=combine,
)
