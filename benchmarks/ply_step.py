"""The two-ply explicit step's own cost: CPU per step over a window of the hemisphere-plies
case's [0/90] run (fibrous plies, or Mindlin ones with ``--kinematics``; 8 cells, holder 20
N: validation/studies/hemisphere_plies_run.py's model and solver, its history file written
as the case writes it), this tree beside a
reference tree (``--reference PATH``, e.g. a ``git archive`` of main), each round a fresh
process per tree, alternating, best of ``--repeats``, one thread; the machine's load printed.
The run goes from the start; the steps ``--start`` to ``--stop`` are timed (the tools move
with t / duration, so a window of the stroke is taken by its steps, not by a shorter run),
and the state at ``--stop`` is compared bit for bit between the trees (positions,
directors, velocities).

    NUMBA_NUM_THREADS=1 nice -n 5 python benchmarks/ply_step.py --reference /tmp/main
    NUMBA_NUM_THREADS=1 nice -n 5 python benchmarks/ply_step.py --parts --kinematics mindlin
    NUMBA_NUM_THREADS=1 nice -n 5 python benchmarks/ply_step.py --kinematics mindlin \
        --toggle elements.ply_facing_front.CHOSEN --start 1000 --stop 9000

``--toggle`` compares a flag that keeps the bits with itself in one process: False and True by
turns every ``--every`` steps of the window, each setting's CPU a step (the load's drift, which
two processes one after the other each meet alone, falls on both settings alike).

Where a step's time goes (``--parts``: each function's CPU summed with a timer round it, so a
little over the step's own; this tree, one thread, load 3.6-5.9), fibrous [0/90] steps
1700-2500 (2.04 ms a step so timed) / Mindlin [0/90] steps 3400-5000 (1.75 ms): the commit
0.84 / 0.84 ms (the new state's facing, both passes, 0.64 / 0.64: ``closest_facing`` 0.45 /
0.45, of which the choice 0.11, the outline's fade 0.11, the edges' sides 0.07, the
candidates' planes 0.05, the chosen arrays 0.02-0.03, its numpy glue about 0.09; the kept
lists and the faces 0.13-0.14; the friction's accepted history with its two return mappings
0.15); the step 0.64 / 0.52 (the forces 0.45 / 0.36: the ply loads 0.27 / 0.19 with the
return mapping the commit kept for them, the fibrous plies 0.16, the tools from their
cache); the tools' forces for the history rows 0.22 / 0.13 (the next step's forces take them
from a cache); the stable step, every 10 steps, 0.16 a step; the rest the march's own
bookkeeping. Each state's facing is made once (at the commit) and served from the block's
cache to the next step's loads, energy and springs: what a step pays for is the facing
itself, about twenty compiled calls a pass and their numpy glue, none of them dominant.

Where it goes since the facing's choice is made in the front's call (``--parts``, one
thread, load 1.4-1.8, each kernel's own line its compiled call alone), Mindlin [0/90] steps
3400-5000 (1.091 ms a step so timed) / fibrous [0/90] steps 1700-2500 (1.607 ms): the commit
0.513 / 0.624 ms, of it the facing 0.324 / 0.378 (the front's call 0.286 / 0.329, its kernel
0.110 / 0.118; the second call 0.116 / 0.119, its kernel 0.069 / 0.073) and the friction's
history 0.132 / 0.145 (its kernel 0.039 / 0.048); the ply loads 0.143 / 0.177 (their kernel
0.049 / 0.050); the fibrous plies 0.150; the tools' forces for the history rows 0.018 /
0.248; the stable step 0.06. The ply contact's four compiled calls a block take 0.27 / 0.29
ms of a step, its Python round them 0.39 / 0.51: the allocations of the facing's fresh
arrays and their copies kept for the state's later calls (about 10 us a block for the
first call's 21 outputs), the kept-state checks, the masks of the sides, the landing and
the loads, and the calls' own conversion of 33-58 arguments (about 5 us each, measured
with an empty kernel of 52 arguments: 4.6 us). No item above about 10 us a block: the
whole ply glue, were it all gone, is about a third of the Mindlin step, not a half.

"The tools' forces for the history rows" (0.248 ms of the fibrous step, 0.018 of the
Mindlin's) are the step's own tools' forces, evaluated once a step in both runs: the
fibrous run keeps a history row at every step (thin 1: its ~4100 steps), the row asks the
three tools' forces at the new state and the next step takes them from the contacts' kept
forces (counted over fibrous steps 1700-2500: 800 computed calls a tool, all in the rows,
none in the steps; the Mindlin run keeps a row every 7 steps and computes the rest in its
steps). Each evaluation costs about twice the Mindlin's (0.30 against 0.15 ms) because the
fibrous stroke is 4 times as fast at a step 1.8 times as long: the die's candidate lists
searched again 53 times in those 800 steps (Mindlin steps 3400-5000: twice), 80 us a step,
and whole candidate lists scanned 21 times a step (the holder's nodes over its vertices,
where a short list of four held too few facets: up to eight since, where that doubles the
list's room, benchmarks/tool_short_lists.py: the whole-list scans 15933 -> 6635, the tools'
calls replayed 0.97 of their time, the same bits).

Measured (this script, best of 2-4, one thread, nice 5):

* the next step's ply loads made in the committed history's pass (elements/ply_commit_pass.py
  ``LOADS_IN_PASS``, the same bits): ``--toggle`` (every 50 steps, one thread, 2 cores shared
  with a dozen other jobs) Mindlin [0/90] steps 2000-6000 1.1607 -> 1.1137 ms a step (0.959,
  load 11-12), 12000-20000 1.5341 -> 1.5062 (0.982, load 12-14), fibrous [0/90] steps
  500-4000 1.7384 -> 1.6828 (0.968, load 10-11): 28-56 us a step. The case's results.json
  (``python -m validation --cases hemisphere-plies --jobs 1`` from this tree and from
  432e668b, side by side from empty numba caches, load 12-22) the same in its 491 entries but
  the 19 times and the stamp;

* the facing's choice made in the front's call (elements/ply_facing_front.py ``CHOSEN``;
  98 % of the fibrous run's new facings, all but 4 of 10000 of the Mindlin run's first 5000
  steps, the rest refreshes and new epochs): ``--toggle`` (every 50 steps, load 4.5-5.9)
  Mindlin [0/90] steps 1000-9000 1.0992 -> 1.0648 ms a step (0.969), 12000-20000 1.3131 ->
  1.2956 (0.987), 22000-30000 1.3957 -> 1.3743 (0.985), fibrous [0/90] steps 500-4000
  1.7344 -> 1.7147 (0.989): 20-34 us a step. Against main 15bf388 in two processes (best of
  4-6, load 1.7-2.8) Mindlin steps 3400-5000 0.959 / 0.966 against 0.992 / 0.994 ms,
  fibrous steps 1700-2500 1.485 / 1.517 against 1.485 / 1.513 (within the noise), the states
  at steps 5000 and 2500 identical to the bit; the whole case (``python -m validation --cases
  hemisphere-plies --jobs 1`` from each tree) the same 333 numbers of results.json but the
  times and the same three PNGs byte for byte. Tried, not kept: the next step's ply loads
  made in the history's pass of the commit and kept for them (one compiled call a block
  and step less, the same bits at every state of a 1600-step window): on a bent state the
  pass 46 -> 77 us a block, the loads' call 35 -> 2.6 us served kept (one-off timeit, load
  1.5), no gain together; Mindlin steps 3400-5000 with both cuts 0.950 against 0.972 ms
  (0.978), as with the choice's alone (0.967-0.978): the loads' cost is their kernel (25 us
  a block in the run, ``--parts``), not the Python round it;

* the sides accepted at a commit from the flags its held facing was made with, the held
  facing kept for the new sides (elements/ply_sides.py ``accepted_sides``), and the
  per-state caches tested by their arrays' bits (elements/kept_bits.py) against main
  81b7828, load 2.8-5.7: 1.844 against 1.981 ms a step (0.931), again at load 4.6-6.4
  1.913 against 1.996 (0.958), the state at step 2500 identical to the bit (positions,
  directors, velocities); the sides alone 2.109 against 2.154 (0.979, one round, load
  4.5-6.1); the window of steps 3400-5000 asked for Mindlin [0/90], load 3.1-5.7: 2.028
  against 2.098 (0.967), the state at step 5000 identical to the bit (the window's child
  then ran the fibrous plies whatever --kinematics said: it is given them since);
* the whole case (``python -m validation --cases hemisphere-plies --jobs 1`` from each tree,
  one after the other, both warm, load 6-7): 80.4 s of CPU (main) against 81.3 s, its four
  runs 11.88 / 21.16 / 14.95 / 25.70 against 11.58 / 21.86 / 15.59 / 25.47 s: the 4-7 %
  of the step lie within the case's own spread at that load; every number of its
  results.json but the times identical.
"""

from __future__ import annotations

import argparse
import importlib
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

if "--window" not in sys.argv:  # a --window child: the tree its parent named
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this tree's packages


ROOT = Path(__file__).resolve().parents[1]


#: (module, owner, attribute) of the functions ``--parts`` times, with their labels
PARTS = (
    ("femcore.compiled", "CompiledModel", "commit", "commit (the new state's history)"),
    ("elements.ply_block", "PlyContactBlock", "facing", "  the facing, both passes"),
    ("elements.ply_facing_front", None, "begun", "    the front's call (faces, lists, choice)"),
    ("elements.ply_facing_front", None, "_front_chosen", "      its kernel"),
    ("elements.ply_facing_front", None, "finished_facing", "      the facing's second call"),
    ("elements.ply_facing_whole", None, "_sides_fade_compiled", "        its kernel"),
    ("elements.ply_block", None, "closest_facing", "    closest_facing (no choice made before)"),
    ("elements.ply_choice", None, "choose_facing", "      the choice"),
    ("elements.ply_fade_kernels", None, "outline_fade_at", "      the outline's fade"),
    ("elements.ply_edge_kernels", None, "edge_sides", "      the edges' sides"),
    ("elements.ply_kernels", None, "candidates_at", "      the candidates' planes"),
    ("elements.ply_chosen", None, "chosen", "      the chosen arrays"),
    ("elements.ply_block", "PlyContactBlock", "_candidates", "    the kept lists, faces"),
    ("elements.ply_friction_kernels", None, "updated_history", "  the friction's history"),
    ("elements.ply_friction_pass", None, "_history_compiled", "    its kernel"),
    ("solvers.explicit", None, "explicit_step", "the step (forces, update)"),
    ("femcore.compiled", "CompiledModel", "internal_force", "  the forces"),
    ("elements.ply_block", "PlyContactBlock", "internal_force", "    the ply loads"),
    ("elements.ply_load_kernels", None, "_loads", "      their kernel"),
    ("elements.fibrous.block", "FibrousShellBlock", "internal_force", "    the fibrous plies"),
    ("femcore.compiled", "CompiledModel", "tool_forces", "the tools' forces (history rows)"),
    ("solvers.explicit", "CentralDifference", "_step_size", "the stable step"),
)


def _timed_parts() -> dict[str, float]:
    """Each of ``PARTS`` wrapped with a CPU timer (nested calls counted in each): the CPU (s)
    summed per label, filled as the run goes."""
    import functools
    import importlib

    spent: dict[str, float] = {}
    for module_name, owner_name, name, label in PARTS:
        module = importlib.import_module(module_name)
        owner = module if owner_name is None else getattr(module, owner_name)
        function = getattr(owner, name)

        def timed(*args, _function=function, _label=label, **kwargs):
            began = time.process_time()
            try:
                return _function(*args, **kwargs)
            finally:
                spent[_label] = spent.get(_label, 0.0) + time.process_time() - began

        setattr(owner, name, functools.wraps(function)(timed))
    return spent


def window(
    start: int,
    stop: int,
    out: str,
    kinematics: str = "fibrous",
    parts: bool = False,
    settings: dict | None = None,
    toggle: str | None = None,
    every: int = 50,
):
    """Run the case's ``kinematics`` [0/90] run to step ``stop``, print the CPU per step (ms)
    of the steps ``start`` .. ``stop`` and save the state there to ``out`` (.npz); with
    ``parts``, each of ``PARTS``' CPU a step in the window too (timed, so a little slower);
    with ``toggle`` ("module.FLAG", a flag that keeps the bits), the flag set False and True
    by turns every ``every`` steps of the window, each setting's CPU a step printed (one
    process, the same states: the load's drift falls on both alike).
    ``settings``: the solver's (validation/studies/hemisphere_plies_run.py ``case_settings``,
    handed over by this tree to a tree of the code before, which may not have it; None: this
    tree's)."""
    from femcore.state import State
    from solvers import CentralDifference
    from solvers.common import SolverError
    from solvers.interrupts import STOP, interruptible
    from validation.studies import hemisphere_plies_setup as setup

    if settings is None:
        from validation.studies.hemisphere_plies_run import case_settings

        settings = case_settings("0/90", kinematics)
    spent = _timed_parts() if parts else {}
    _, model = setup.model(8, setup.LAYUPS["0/90"], kinematics, 20.0)
    compiled = model.compile()
    commit = type(compiled).commit
    marks: dict[str, float] = {}
    count = [0]

    flag_module, flag = (None, "") if toggle is None else toggle.rsplit(".", 1)
    owner = None if flag_module is None else importlib.import_module(flag_module)
    by_setting = {False: [0.0, 0], True: [0.0, 0]}

    def counted(state: State) -> State:
        count[0] += 1
        now = time.process_time()
        if count[0] == start:
            marks["start"] = now
            spent.clear()
        if owner is not None and start <= count[0] <= stop:
            if count[0] > start:  # the step that ends here ran with the setting of before
                setting = bool(getattr(owner, flag))
                by_setting[setting][0] += now - marks["last"]
                by_setting[setting][1] += 1
            setattr(owner, flag, (count[0] - start) // every % 2 == 1)
            marks["last"] = time.process_time()
        accepted = commit(compiled, state)
        if count[0] == stop:
            marks["stop"] = time.process_time()
            np.savez(
                out,
                positions=state.positions,
                directors=state.directors,
                velocities=state.velocities,
                time=state.time,
            )
            STOP.signal = "SIGINT"  # stops the run at this step's end
        return accepted

    compiled.commit = counted  # type: ignore[method-assign]
    with tempfile.TemporaryDirectory() as folder, interruptible():
        solver = CentralDifference(**settings, history=Path(folder) / "history.csv")
        try:
            solver.solve(compiled)
        except SolverError:
            pass
    for setting, (cpu, steps) in by_setting.items() if owner is not None else ():
        print(f"{toggle} {setting}: {cpu / max(steps, 1) * 1e3:.4f} ms a step ({steps} steps)")
    for *_, label in PARTS if parts else ():
        print(f"{label:40s} {spent.get(label, 0.0) / (stop - start) * 1e3:7.3f} ms a step")
    print(f"{(marks['stop'] - marks['start']) / (stop - start) * 1e3:.4f}")


def timed(tree: Path, start: int, stop: int, out: Path, kinematics: str) -> float:
    """CPU ms a step of the window in a fresh process run from ``tree``'s root."""
    # the tree's packages first on the path (before an installed copy), this script's code
    from validation.studies.hemisphere_plies_run import case_settings

    environment = dict(os.environ, NUMBA_NUM_THREADS="1", PYTHONPATH=str(tree))
    done = subprocess.run(
        [
            sys.executable,
            str(Path(__file__).resolve()),
            "--window",
            str(start),
            str(stop),
            str(out),
            "--kinematics",
            kinematics,
            "--settings",
            json.dumps(case_settings("0/90", kinematics)),
        ],
        cwd=tree,
        env=environment,
        capture_output=True,
        text=True,
        check=True,
    )
    return float(done.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--reference", type=Path, help="the tree to compare with")
    parser.add_argument("--start", type=int, default=1700, help="first step timed")
    parser.add_argument("--stop", type=int, default=2500, help="last step timed")
    parser.add_argument("--repeats", type=int, default=3, help="rounds (best CPU)")
    parser.add_argument("--kinematics", default="fibrous", help="fibrous or mindlin plies")
    parser.add_argument("--parts", action="store_true", help="this tree's parts of a step")
    parser.add_argument("--toggle", help="module.FLAG set False / True by turns in the window")
    parser.add_argument("--every", type=int, default=50, help="steps between the turns")
    parser.add_argument("--window", nargs=3, help=argparse.SUPPRESS)
    parser.add_argument("--settings", help=argparse.SUPPRESS)  # a --window child's solver
    args = parser.parse_args()
    if args.window:
        settings = json.loads(args.settings) if args.settings else None
        window(int(args.window[0]), int(args.window[1]), args.window[2], args.kinematics,
               settings=settings)  # fmt: skip
        return
    if args.parts or args.toggle:
        print(f"load {os.getloadavg()}")
        with tempfile.TemporaryDirectory() as folder:
            out = str(Path(folder) / "state.npz")
            window(args.start, args.stop, out, args.kinematics, args.parts, None, args.toggle,
                   args.every)  # fmt: skip
        print(f"load {os.getloadavg()}")
        return
    trees = {"this": ROOT} | ({"reference": args.reference.resolve()} if args.reference else {})
    best = {name: np.inf for name in trees}
    print(f"load {os.getloadavg()}")
    with tempfile.TemporaryDirectory() as folder:
        for _ in range(args.repeats):
            for name, tree in trees.items():
                best[name] = min(
                    best[name],
                    timed(
                        tree, args.start, args.stop, Path(folder) / f"{name}.npz", args.kinematics
                    ),
                )
        states = {name: np.load(Path(folder) / f"{name}.npz") for name in trees}
    for name in trees:
        print(f"{name}: {best[name]:.3f} ms a step, steps {args.start}-{args.stop} (best CPU)")
    if "reference" in trees:
        same = all(
            np.array_equal(states["this"][key], states["reference"][key])
            for key in ("positions", "directors", "velocities", "time")
        )
        print(f"ratio this / reference {best['this'] / best['reference']:.3f}; state at step "
              f"{args.stop} {'identical' if same else 'DIFFERENT'} to the bit")  # fmt: skip
    print(f"load {os.getloadavg()}")


if __name__ == "__main__":
    main()
