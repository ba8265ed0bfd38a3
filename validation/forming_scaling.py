"""The time scaling of the hemisphere-forming case's strokes (validation/cases/
hemisphere_forming.py): how much faster than its process duration each kinematics' run takes
the punch's stroke at each resolution, the margin on the kinetic energy a scaled run must
keep, and how the report states both.

Measured beside the unscaled runs (benchmarks/hemisphere_scaling.py, "The report's scaling";
one thread, CPU, load 9-17): the fibrous stroke x2 at 12 / 20 cells keeps every check and
moves rms shear - net by -0.004 / -0.006 deg (tolerance 3.7 / 2.8; 12 -> 20 cells: -0.57),
the edges' mean draw-in by -0.01 / -0.01 mm (12 -> 20: +1.75), the corners' by -0.05 / -0.06
mm (+2.8), the edge middle's by +0.02 / -0.09 mm (its range 21.87-29.68 / 23.44-29.68), the
late punch force by +0.03 / +0.33 N (+7.6), the punch force at the end by +2.1 / -1.1 N
(-21.1; it rings), no wrinkles either way, the holder down, KE / W at most 0.033 / 0.026
(0.009 / 0.007 unscaled; bound 0.1, none of the stroke above it), in half the steps. x3 moved
nothing more but put KE / W at 0.073 / 0.067: not kept. The Mindlin run is not scaled:
unscaled it already rings near the bound at 12 cells (KE / W at most 0.169, 6.8 % of the
stroke above 0.1, the holder lifted 1.2 mm by its flange's wrinkles), and x2 put 15.3 % of the
stroke above the bound (the case allows 10 %) and moved its corners' draw-in by +10 %; at 20
cells x2 moved its late punch force by as much as 12 -> 20 cells does. The fine resolution
(the orders over 12 / 20 / 32 cells) stays unscaled: at 40 cells x2 turned the fibrous edge
middle from cornered to taut (-13 % of its draw-in), and 32 cells was not measured scaled.
"""

from __future__ import annotations

from solvers.quasi_static import KINETIC_BOUND, KINETIC_SHARE
from validation.checks import check

__all__ = [
    "DAMPING_NOTED",
    "KINETIC_MARGIN",
    "TIME_SCALING",
    "kinetic_margin_check",
    "quasi_static_words",
    "stroke_words",
]

# The stroke run this many times faster, per kinematics and resolution (in the process
# duration / s; the punch's amplitude and the holder's closing follow it, the damping c
# unchanged).
TIME_SCALING = {
    "fibrous": {"coarse": 2.0, "default": 2.0, "fine": 1.0},
    "mindlin": {"coarse": 1.0, "default": 1.0, "fine": 1.0},
}
# A run's largest KE / W after the first tenth is checked within this share of the bound: the
# margin a time scaling must keep (x2 gave at most 0.033, x3 0.073; the unscaled fine meshes
# 0.016).
KINETIC_MARGIN = 0.5
# A damper's share of the work above which a run's forces carry its drag, as the figures' text
# says: the bound's tenth (measured: fibrous 0.25-2.2 % at 12-32 cells, Mindlin 4.6 % at 20
# cells, 18.5 % at 12, where its flange rings; docs/hemisphere_forming.md, "The coarse Mindlin
# run's pace").
DAMPING_NOTED = 0.1


def stroke_words(duration: float, speed: dict[str, float], runs: dict[str, dict]) -> str:
    """How each kinematics' run took the stroke of ``duration`` (s), in words: time-scaled by
    its ``speed`` or not, and the largest KE / W after the first tenth its ``runs`` record
    gave (``largest_kinetic_over_work``)."""
    words = []
    for kinematics, record in runs.items():
        factor = speed[kinematics]
        scaled = "not time-scaled" if factor == 1.0 else (
            f"time-scaled x{factor:g} (run in {duration / factor:g} s)"
        )  # fmt: skip
        words.append(
            f"{kinematics} {scaled}, largest KE / W after the first tenth "
            f"{record['largest_kinetic_over_work']:.3f}"
        )
    return f"the {duration:g}-s stroke: " + "; ".join(words)


def kinetic_margin_check(kinematics: str, speed: float, record: dict):
    """The check that a run of ``kinematics`` whose stroke was time-scaled by ``speed`` kept
    its largest KE / W after the first tenth (its ``record``'s ``largest_kinetic_over_work``)
    within KINETIC_MARGIN of the quasi-static bound (solvers/quasi_static.py)."""
    return check(
        f"{kinematics}: the largest KE / W after the first tenth, at most {KINETIC_MARGIN:g} "
        f"of the bound {KINETIC_BOUND:g} (the margin the stroke's time scaling x{speed:g} "
        "keeps)",
        0.0,
        record["largest_kinetic_over_work"],
        KINETIC_MARGIN * KINETIC_BOUND,
        relative=False,
        source="validation/forming_scaling.py: KE / W 0.026-0.033 at x2, 0.067-0.073 at x3",
    )


def quasi_static_words(results: dict) -> str:
    """How quasi-static each run of ``results`` (kinematics -> solver result, with
    ``info["quasi_static"]`` and the ``energies`` record) was, in words for a figure's
    caption: its largest KE / W after the first tenth, the share of the judged stroke above
    KINETIC_BOUND and the damper's share of the work; and, for a run outside the case's rule
    (at most KINETIC_SHARE of the stroke above the bound), above the bound at its peak, or
    whose damper took more than DAMPING_NOTED of the work, what that does to its forces."""
    words, flagged = [], []
    for kinematics, result in results.items():
        quasi = result.info["quasi_static"]
        largest, share = quasi["kinetic_over_work_largest"], quasi["exceeded_share"]
        energies = result.energies
        damped = float(energies["damping"][-1] / energies["external_work"][-1])
        above = "none" if not share else f"{share:.1%}"
        words.append(
            f"{kinematics} largest KE / W {largest:.3f}, {above} of the stroke above "
            f"{KINETIC_BOUND:g}, damping {damped:.1%} of the work"
        )
        if share is None or share > KINETIC_SHARE:
            flagged.append(f"the {kinematics} run is not quasi-static by the case's rule")
        elif largest > KINETIC_BOUND or damped > DAMPING_NOTED:
            flagged.append(
                f"the {kinematics} run passes the rule but rises to KE / W {largest:.2f} and "
                f"its damper took {damped:.0%} of the work: its force carries inertia and "
                "drag, not the quasi-static answer's level alone"
            )
    rule = (
        f"How quasi-static the runs were (the case's rule: at most {KINETIC_SHARE:.0%} of the "
        f"stroke after its first tenth with KE / W above {KINETIC_BOUND:g}): "
    )
    verdict = "; ".join(flagged) + "." if flagged else "both are quasi-static."
    return rule + "; ".join(words) + ". " + verdict[0].upper() + verdict[1:]
