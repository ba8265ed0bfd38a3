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
20 N (ramped over the first tenth). Ply on ply Coulomb friction 0.2 (elements/ply_contact.py,
both ways: the top ply's Gauss points and the bottom ply's nodes; docs/theory.md §9.3b), the
tools frictionless. Fabric: a G986-like ply (tension 60 N/mm, shear 0.2 N/mm, bending 0.375
N mm, 285 g/m^2); the Mindlin ply its calibration (``ElasticShell.equivalent``). Explicit,
0.1 s, no mass scaling, mass-proportional damping 20/s. The centre lines held in their
symmetry planes.
Checked, per run: the run reaches the end of the stroke; each fibrous ply's rms of shear -
net over its cells in the die (the Mindlin plies' reported, not checked, as in
hemisphere-forming); the plies' order in the die (the top ply's least gap to the bottom ply
along the radius from the die's centre within one ply thickness); the holder's reaction over
the last tenth within 5 % of its force; the largest kinetic energy over the work after the
first tenth within the field's 0.1 (solvers/quasi_static.py), the directors' rotation on the
Mindlin shell's scaled rotary inertia counted at its physical share (docs/theory.md §6.3;
the total, with it, reported beside it).
The report runs the coarsest mesh that shows the physics (``CELLS``: 8 fibre segments across
the blank, 25-mm cells); the finer mesh (10 cells) and the second holder force (40 N, the
holder's sensitivity) are the study's (validation/studies/hemisphere_plies.py), with what they
gave and what led to the settings.
Measured (8 cells, 20 N; one thread):
MEASURED
"""

from __future__ import annotations

from validation.records import Case, Outcome
from validation.studies.hemisphere_plies_run import NAME, SOURCE, TITLE, compute_plan, render
from validation.studies.hemisphere_plies_setup import HOLDER_FORCES, LAYUPS

__all__ = ["CASE", "CELLS", "KINEMATICS", "compute", "plan"]

# fibre segments across the blank per resolution: the study's coarse mesh but at "fine"
# (its runs at 10 cells cost 110-320 s of CPU each)
CELLS = {"coarse": 8, "default": 8, "fine": 10}
# the kinematics run per resolution: the coarse report (the test suite's background run) the
# fibrous plies only, whose checks all pass at 8 cells (the Mindlin runs cost 120-160 s of
# CPU each and fail the quasi-static bound: the module's docstring)
KINEMATICS = {
    "coarse": ("fibrous",),
    "default": ("fibrous", "mindlin"),
    "fine": ("fibrous", "mindlin"),
}


def plan(resolution: str) -> list[tuple[int, str, str, float]]:
    """The case's runs at ``resolution``: both layups, its kinematics (``KINEMATICS``), the
    first holder force, as (cells, layup name, kinematics, holder force in N)."""
    return [
        (CELLS[resolution], name, kinematics, HOLDER_FORCES[0])
        for name in LAYUPS
        for kinematics in KINEMATICS[resolution]
    ]


def compute(resolution: str) -> Outcome:
    """The runs of ``plan(resolution)`` with their checks (hemisphere_plies_run.run)."""
    return compute_plan(plan(resolution))


CASE = Case(
    name=NAME,
    title=TITLE,
    source=SOURCE,
    description=__doc__,
    group="verification",
    order=115,
    compute=compute,
    render=render,
)
