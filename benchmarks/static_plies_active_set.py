"""The ply contact's normal law under Static, the ramp against the active set
(``PlyContact(static_law=...)``, elements/ply_active_set.py; benchmarks/static_plies_newton.py
``--active-set``, or this script alone): the case's solver on its plies (bai or heavy) with
each law, alternately ``--rounds`` times in one process: iterations per increment, tangents,
CPU, the largest change of the material lines between the two equilibria, and for heavy the
change of what plies-heavy-cantilever compares. One thread, CPU; the machine's load.

    python benchmarks/static_plies_active_set.py [--case bai|heavy]
        [--resolution coarse|default] [--rounds 2] [--plies 20] [--unopened]

The options below are benchmarks/static_plies_newton.py's (``--active-set``); this script
takes the same without it.

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
  100 cut), 19.6-20.9 s. With the rule g_{k+1} < 0 alone (femcore.interaction
  ``ACTIVE_SET_HYSTERESIS = False``): coarse 562 tangents. With the rule's c (the gap's
  weight against the multiplier's, k above; one-off runs with the block's freeze patched)
  0.01, 0.1 and 10 k: 607, 574 and 427 tangents; the sag below at 2, 4, 8 plies 31-35-42,
  32-32-75, 22-25-33.
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
  zig-zag of the sag's first increment (benchmarks/static_plies_iterates.py, "Where the
  first increments go"): a step the update cap shortens to 0.1-0.6, the
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

"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install

from benchmarks.static_plies_case import RECORD, command, machine_load, solve_case  # noqa: E402


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


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The comparison's options: the plies and the opening of each phase."""
    parser.add_argument("--plies", type=int, default=None, help="the plies (the case's)")
    parser.add_argument(
        "--unopened",
        action="store_true",
        help="the active set in the first increment of the displacement phase too "
        "(ActiveSetPlyContactBlock.opening_law None)",
    )


def run(args: argparse.Namespace) -> None:
    """The comparison on the case ``args`` name, then the machine's load."""
    opening = None if args.unopened else "ramp"
    active_set(args.case, args.resolution, args.plies, args.rounds, opening)
    print(f"load (1, 5, 15 min): {machine_load()}")


if __name__ == "__main__":
    run(command(__doc__, add_arguments, rounds=True))
