"""The decks of plies-deck-of-cards' default report without and with the case's soft start
of the ply penalty (``Static(ply_penalty_start=DECK_PENALTY_START)``, solvers/penalty_start.py;
benchmarks/static_plies_newton.py ``--deck-start``, or this script alone), one deck after the
other each way in one process: Newton iterations per increment, cut iterations, tangents,
CPU, and how far the second moved from the first. One thread, CPU; the machine's load.

    python benchmarks/static_plies_deck_start.py

The options below are benchmarks/static_plies_newton.py's.

The deck's last increment (4 plies, 20 cells, 4 curved increments, the case's solver; one
thread; ``--deck-start`` for the kept change; the trials below by patches of the code, not
kept, their counts the measure):

* Where it goes (``--detail``): 10-8-8-63 iterations. In the three increments before it no
  point touches (the plies 6e-5 to 1.9e-4 mm apart at each equilibrium). The last one's first
  (curved) step carries 54 points to -4.2e-3 mm (17 ramps, delta = 2.5e-4 mm); then 33
  iterations at ratio 0.07-1 in which 10-50 points step on or off at each iterate (the 7th
  0.4 mm deep, 1200 N of contact force), then the halving tail, restarted 5 times by points
  carried from g > 0 to -5e-6 to -1e-5 mm. Its end: 9 points touching, 3.5e-7 N in all, the
  deepest -5.3e-7 mm. The same increment with the plies' contact left out converges in 6
  iterations with the 54 points 3.3e-3 mm through the ply below: the contact is needed, and
  the plies' gap mode, their bending alone, is about 3.5e-7 N / 3.3e-3 mm ~ 1e-4 N/mm
  against the automatic penalty's 3000 N/mm a point. The equilibrium gap g* ~ -sqrt(2 delta
  F / k) is then ~5e-7 mm (as found), and the ramp's tangent is good only within K_s delta
  / k of it: Newton halves its way there from the 3.3e-3 mm the plies would pass.
* Kept: each deck increment started at 1e-3 of the penalty (``Static(ply_penalty_start=
  1e-3)``, solvers/penalty_start.py; validation/cases/plies_deck_of_cards.py
  ``DECK_PENALTY_START``): Newton converges the increment with the soft penalty, then goes on
  from there with the full one. The five decks of the default report (``--deck-start``, load
  5.3-6.5): without 1111 tangents, 17.0-18.8 s (2 plies on 10, 20, 40 cells 9-8-8-43 and 68
  cut, 8-8-6-40, 8-8-8-122; 4 plies 10-8-8-63; 8 plies 16-15-10-139 and 492 cut) -> 390,
  4.2-4.3 s (10-9-8-20, 9-9-9-22, 9-9-9-81, 11-9-9-22, 18-16-12-39 and 48 cut; of the last
  increments' iterations 13, 14, 72, 14, 30 soft), the same equilibria within 3.3e-10 mm.
  3e-4: 384 tangents, 4.9 s (the 8-ply deck's first increment 89). On the other stacks
  (coarse, without -> 1e-3, 1e-2): sag 184 -> 193, 189 tangents, heavy 125 -> 193, 141:
  their contacts carry the weight, and the second phase lifts every ply out of the soft
  penalty's deeper penetration (7-27 iterations an increment); bai coarse (the case's
  solver, load 3.7-4.5) 271 tangents -> failed at load factor 1.072 (1e-3: the stall rule
  cut the first displacement increment 10 times), 441 (1e-1); heavy default 142 -> 180
  (1e-3), 164 (1e-1). Not set there. The report's case (``python
  -m validation --cases plies-deck-of-cards --jobs 1``, the code before from a ``git
  archive``, back to back, warm caches, load 4.9-5.6): 20.5 -> 10.5 s CPU, steps 1014 ->
  796, 12/12 checks both, results.json's numbers within 1.3e-7 relative (the observed
  orders; the tilts within 1.3e-8).
* Not kept: the decks' penalty itself lowered to 3 N/mm a node (1e-3 of the automatic one,
  for the whole solve): 334 tangents, 4.1 s (9-8-8-13, 8-8-6-15, 8-8-8-72, 10-8-8-21,
  16-15-10-22 and 52 cut), but the positions moved by up to 2.5e-5 mm (0.12 delta) and the
  report's checked values by up to 1.5 % (the 2-ply tilt 0.1250 -> 0.1266 deg; the report's
  case 23.8 -> 11.4 s CPU, load 9.5). Other penalties, 4 plies (last increment; positions
  moved): 100 N/mm 31 and 26 cut (1.3e-6 mm); 10, 32 (5.1e-6); 3, 21 (9.8e-6); 1, 15
  (1.7e-5); 0.3, 12 (3e-5); 0.1, 11 (4.9e-5); 8 plies: 10, 21 and 54 cut; 1, 22 and 149
  cut; 0.3, 103-15-11-26.
* Not kept (the 4-ply deck, its last increment 63 iterations, none cut, 89 tangents):
  a contact predictor, a second factorisation of the same iterate where the Newton step
  carries points apart (not touching) past -c delta, with those points held by h k in the
  iteration matrix (the residual unchanged): c = 1, h = 1: 53 and 596 cut (1286 tangents);
  c = 1, up to three passes: 46 and 596 cut (1273); h = 0.01: 72 and 894 cut; h = 1e-3: 86
  and 1065 cut; c = 4, h = 0.01: 102 and 447 cut; c = 0, h = 1: failed at load factor 0.947
  (ratio 2e-5 after 150 iterations, 8 cuts). A held point keeps its gap where the residual
  needs it moved (the iteration's rate h k / (K_s + h k) ~ 1 in that mode).
* Not kept: the contact's acting set frozen within the increment (Newton's contact-set
  protocol, solvers/newton.py: points apart at the increment's start act only after a
  convergence, checked under the full law): 11-8-8-133 (the contact-free solve converges in
  6, its 54 points 3.3e-3 mm deep; from the increment's start with them acting, the chatter
  as before); going on from the converged state instead, with points deeper than 1-20 delta
  joining at once, 212-227 (its 6.7 N of contact force on a 1e-4 N/mm mode: the next steps
  carry points up to 2.8 mm through the plies).
* Not kept: the plain penalty (smoothing 0) with the acting set frozen and held on both sides
  while Newton iterates, updated at convergence (a primal-dual active set): 33-43-106-46 and
  17 cut (27 set updates: the plies laid at g = 0 are tied at the start, and the points of
  almost no force change side at each update), with points joining at a touch 535 cut,
  one-sided 988 cut; the plain penalty alone fails in the first increment (8 cuts). A linear
  onset of the ramp (W'' = k0 + (k - k0) min(1, -g / delta) on contact): k0 = 1e-3 k 135 and
  191 cut, 1e-2 k 53, 0.1 k failed at 0.998. The ramp 10 times wider (2.5e-3 mm): 78.
* Not kept: the automatic penalty lowered for every stack (``PENALTY_SHARE`` 0.01 and 0.001
  instead of 0.1; coarse, load 4-5): sag 184 -> 148, 137 tangents, heavy 125 -> 111, 105
  (their first increments 83 -> 60, 55 and 29 -> 21, 18), but the equilibria moved 2.7e-3,
  1.2e-2 mm and 8.6e-3, 4.4e-2 mm: those stacks carry their weight through the contact, and
  a softer penalty lets them sink into each other by more than the ramp (1.5e-3 mm).

"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install

from benchmarks.static_plies_case import command, machine_load  # noqa: E402


def deck_starts() -> None:
    """The five decks of the default report (validation/cases/plies_deck_of_cards.py,
    ``bend``) without a soft start (the reference pass) and with the case's
    ``Static(ply_penalty_start=DECK_PENALTY_START)``, one deck after the other each way in
    this process: Newton iterations per increment, cut iterations, tangents, CPU, and how far
    the second moved from the first (positions, mm; the tilt and thickness errors the case
    checks)."""
    from validation.cases import plies_deck_of_cards as deck

    kept = deck.DECK_PENALTY_START
    decks = [(2, cells) for cells in deck.MESHES["default"]] + [(4, 20), (8, 20)]
    totals = {}
    runs: dict = {}  # (start, plies, cells): the run
    for share in (None, kept):
        deck.DECK_PENALTY_START = share  # type: ignore[assignment]
        tangents = cpu = 0.0
        for count, cells in decks:
            start = time.process_time()
            run = deck.bend(count, cells)
            took = time.process_time() - start
            info = run.result.info
            tangents, cpu = tangents + info["evaluations"]["tangent"], cpu + took
            runs[(share, count, cells)] = run
            line = f"start {share}: {count} plies, {cells} cells: "
            line += f"{info['iterations_per_increment']}"
            line += f" and {info['iterations_cut']} cut, {info['evaluations']['tangent']} tangents"
            line += f" ({info['soft_start_iterations']} soft), {took:.2f} s"
            if share is not None:
                ref = runs[(None, count, cells)]
                moved = np.abs(run.result.positions - ref.result.positions).max()
                errors, before = run.errors(), ref.errors()
                change = {key: abs(errors[key] - before[key]) for key in errors}
                line += f"; within {moved:.2g} mm, errors within " + ", ".join(
                    f"{key} {value:.2g}" for key, value in change.items()
                )
            print(line, flush=True)
        totals[share] = (tangents, cpu)
    deck.DECK_PENALTY_START = kept
    for share, (tangents, cpu) in totals.items():
        print(f"start {share}: {tangents:.0f} tangents, {cpu:.1f} s CPU")


def run(args: argparse.Namespace) -> None:
    """The decks each way, then the machine's load."""
    deck_starts()
    print(f"load (1, 5, 15 min): {machine_load()}")


if __name__ == "__main__":
    run(command(__doc__, case=False))
