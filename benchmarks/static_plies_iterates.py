"""The record of a Static ply solve, attempt by attempt and iterate by iterate
(benchmarks/static_plies_newton.py ``--detail``, which runs the solves; docs/theory.md §6.5
("Stalled attempts") and §9.3a): ``instrument`` wraps the solver's pieces that the load path
calls, so that ``RECORD["attempts"]`` holds each attempt's residual ratios, the watchdog's
step lengths and its trial force passes and energies, the cut attempts and why they failed,
and what the ply contact's points did between the iterates (on or off the ramp -delta < g < 0
of the smoothed penalty, deeper, in the fade past the outline, the facing triangle switched,
the sign of the gap flipped); ``report`` prints it. ``--detail`` records, per iterate, the
element blocks' and the interactions' internal-force norms and the deepest ply gap as well,
and between iterates the largest change of a point's gap; ``--detail --parts`` adds, per
iterate, the norms on the free unknowns of the plies' membrane, bending and transverse-shear
loads (each group of the Mindlin fabric section's stress resultants alone,
elements/fabric_section.py), the ply contact's and the dead load's. The options below are
benchmarks/static_plies_newton.py's; tests/test_static_plies_record.py checks the record.

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
* sag's first increment (4 plies), 83 iterations: its first 37 alternate a step the update cap
  (0.03 rad) shortens to 0.05-0.57 and a whole step, the element forces 2 N after the first
  (each straight update stretches the plies) and 0.01-0.7 N after the second (which undoes the
  stretch), the ratio ~1 throughout: the increment's sag of 0.57 rad, 0.03 rad a pair. Then 46
  iterations in which the touching points fall from 106 to 12 (2-26 leave at an iterate) with
  the ramp's rate at a double root (the ratio a factor ~4 down an iteration), restarted twice
  (the ratio back to 1.0 and 0.99) by a point carried from g > 0 into the ply below. At the end
  12 of the 120 points touch: equal plies under their own weight sag alike and need almost no
  contact force, the deck's double root (benchmarks/static_plies_tangent_check.py, "The deck's
  linear tail"). The heavy cantilever's first increment (4 plies, 29 iterations) is the same: 10
  iterations at ratio ~1 with the element forces alternating 0.2-2.3 N and 0.002-0.08 N (the cap
  shortened two of its steps), then 60 -> 3 points touching, restarted by gap changes of 0.072
  and 0.037 mm.
* So two causes, neither in the contact's tangent (exact): straight updates of turning plies
  (the plateaus and the zig-zag; what cures them on one ply, the curved step, fails with the
  contact: benchmarks/static_plies_newton.py, "Curved steps") and the smoothed ramp's double
  root at zero-force contact (the tails).
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
  its use would be a softer penalty in the inner solves, and those are bounded by the stacks
  solved with the penalty itself lowered 10 and 100 times
  (benchmarks/static_plies_deck_start.py: the sag's and the heavy cantilever's tangents 20-25 %
  fewer, their first increments 83 -> 55-60 and 29 -> 18-21), before the Uzawa passes' own
  iterations; at zero-force contact (the tails) its multipliers go to 0 and the double root
  stays.
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
  benchmarks/static_plies_tangent_check.py, "The deck's linear tail"). Over the 17 (default;
  coarse 18) converged attempts of the second phase, counted by hand from ``--detail --parts``
  (an iteration the contact's alone once the element parts no longer change in their first two
  digits; the first displacement increment's iterations in the counts), iterations after the
  element parts settled: default 208 of 336, with 740 changes of a point's touching in them;
  coarse 83 of 204 (mostly the quadratic tail), 41 changes. So two costs: the imposed step's
  stretch (3-4 iterations an increment at both resolutions) and, at the default, the contact's
  zero-force points settling one by one (5-17 iterations an increment).
* The tangent at these iterates: benchmarks/static_plies_tangent_check.py, "The second
  phase's increments".
* Not kept: ``predictor=True`` (the last increment extrapolated): coarse 271 -> 399 tangents
  (102-28-39-21-17-15-10-14-30-10, 56 cut), default 403 -> 595 (155-49-35-23-26-16-28-22-27-18,
  130 cut); the ramp's secant W'/g = W''/2 in the tangent of the points whose gap grew since the
  block's last tangent (a leaving point's Newton step halves g on the ramp; the secant takes it
  to 0): coarse 482 tangents (121-38-39-38-42-27-18-21-18-27); on every point on the ramp:
  failed at load factor 1.0002 (10 cuts); the fibre-length projection (solvers/newton_fibres.py)
  on the imposed steps alone: coarse 1037 tangents and 392 cut; the step doubled where the last
  two halve along one line (a double root, Decker, Keller and Kelley,
  benchmarks/static_plies_newton.py, "Curved steps"; the step within 0.4-0.6 of the last and at
  a cosine above 0.99, the ratio below 0.1): taken once on coarse, 3 times on default, 272 and
  401 tangents; ``Static(tol=1e-6)`` instead of 1e-8: coarse 253 tangents, within 2.9e-8 mm,
  default 380, within 1.2e-8 mm: the contact-only iterations run at ratios 1e-3 to 0.3, above
  any tolerance; the ramp wider (``elements.ply_contact.SMOOTHING`` 2e-3 and 5e-3 of the faces'
  half thicknesses instead of 1e-3), default: 353 and 407 tangents
  (96-32-38-25-17-14-18-19-15-17; 127-29-35-25-16-12-17-18-9-17 and 50 cut), but the equilibrium
  moved by 6.8e-3 and 2.4e-2 mm (the plies pressed deeper by the ramp).
* What would cut them (not done): the zero-force points are weakly active (g ~ 0 and W'(g) ~ 0
  at the solution), where the ramp's W'' vanishes and the tangent cannot see a point step on or
  off. A semismooth Newton on the normal contact with a multiplier per point (the augmented
  Lagrangian of Alart and Curnier, CMAME 92 (1991) 353, in its Newton form, the active set set
  by lambda + c g at every iteration, not at convergence as the primal-dual set tried on the
  deck, benchmarks/static_plies_deck_start.py) converges superlinearly without strict
  complementarity (Hintermueller, Ito and Kunisch, SIAM J. Optim. 13 (2002) 865): the 5-17
  contact-only iterations of a default increment would become the 2-3 of a quadratic tail (a
  guess, not derived: the target is the default's 403 tangents; docs/theory.md §9.3a says what
  the method would take; built with the multipliers condensed, it takes more:
  benchmarks/static_plies_active_set.py, "The ply contact's normal law under Static"). The
  imposed step's stretch would need a step that turns the plies without stretching them; the
  curved imposed step (benchmarks/static_plies_newton.py, "Curved steps": 271 -> 628 tangents)
  and its fibre-length projection (1037) do worse.

"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the tree's own packages first

import solvers.line_search as line_search  # noqa: E402
import solvers.newton as newton_module  # noqa: E402
import solvers.penalty_start as penalty_start_module  # noqa: E402
import solvers.static as static_module  # noqa: E402
from benchmarks.static_plies_case import RECORD  # noqa: E402
from elements.ply_block import PlyContactBlock  # noqa: E402


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

    def tangent(self, state, frames, compression_free=False, real=None):
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
        return plain_tangent(self, state, frames, compression_free, real)

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
