"""The ply contact's own share of an explicit step, replayed on a run's states, beside a
reference tree: the two-ply hemisphere of the report's hemisphere-plies case (validation/
studies/hemisphere_plies_setup.py, fibrous [0/90] by default, 8 cells, two 128-triangle
plies), run to step ``--start``, then ``--steps`` consecutive committed states replayed
through both ply contact blocks as a step asks for them: the committed history
(``update_history``: the facing of the new state, the friction's return mapping) and the
next step's loads (``internal_force``), CPU (``time.process_time``), one thread, best of
``--repeats`` rounds, each round from the blocks as they were at ``--start`` (their kept
search lists included). The replay's results (the histories' arrays, the forces and
moments) are hashed: a tree giving the same bits gives the same digest.

    python benchmarks/ply_contact_replay.py --reference /tmp/main

Each tree runs in a process of its own (``PYTHONPATH``), this one and the reference in
turn, twice.

Measured (main ff71a95 as the reference, ``git archive``; fibrous [0/90], steps 2000-2600;
one numba thread; 2 cores shared with other jobs, load 11-13), us a block-step, the
committed history then the loads:

* the choice's pass (elements/ply_choice.py ``_choose``) with its scratch rows indexed in
  place: 384 points 41.1 -> 12.7 us a call, 81 points 15.0 -> 8.8 (best of 40 rounds of
  the kernel alone on a state of the run);
* the fade's pass (elements/ply_fade_kernels.py) with ``fade_at`` reading and writing by
  index: 90 points 27.7 -> 21.3 us, 34 points 12.3 -> 10.0;
* the loads' pass (elements/ply_load_kernels.py) with its scatter helpers spliced: 75-84 ->
  44-45 us a call;
* numpy's cube of the touching gaps only where the smoothed law's ramp reads it
  (elements/ply_penalty.py ``ramp_cubes``): ``ply_loads`` lost ~42 us a call on the upper
  pass's 245 touching points (numpy's power of a negative base, ~170 ns a point).

The replay, this tree (the four cuts) beside main ff71a95, load 12-13, best of 3: the
committed history 351.3 -> 327.5 us a block-step, the loads 116.6 -> 92.9 us, the same
digest (6a012d171735b7ef: the same histories, forces and moments to the bit). The kernels'
own work is now a small part of the rest: the committed history's compiled passes take
about 75 us of its ~300 (the choice, the planes, the fade, the sides, the chosen rows, the
face points, the friction's two mappings), the rest is the Python round them (some forty
arrays made a call, the kernels' ~30-argument calls, the kept states' comparisons); a
facing is made once a block and step (``closest_facing`` 2.00 calls a step, the other
2.42 ``facing`` calls of a step find the state kept), so the next cut is that glue in one
compiled pass per block and state.

The whole run and the case, beside main ff71a95 (``git archive``, one numba thread, each
tree's cache warm):

* ``python benchmarks/forming_step_overhead.py --reference`` (fibrous [0/90], 5612 steps,
  best of 2, load 12.8-13.2): 1.822 -> 1.715 ms a step, the same steps and final positions
  to the bit;
* ``python -m validation --cases hemisphere-plies --jobs 1`` (both trees at once, load
  11-12): case_cpu_s 73.3 -> 70.2 s; fibrous [0/90] 10.96 -> 10.37 s, fibrous [0/45] 14.88
  -> 14.13, Mindlin [0/90] 18.77 -> 17.93, Mindlin [0/45] 22.49 -> 21.67; results.json the
  same in every one of its 324 numbers but the 11 times (24 of 24 checks).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(HERE))  # this tree's case_settings (run from anywhere, no install)

REPLAY = """
import hashlib, json, pickle, sys, time
import numpy as np
import femcore.compiled as compiled_model
from elements.ply_block import PlyContactBlock
from solvers import CentralDifference
from validation.studies import hemisphere_plies_setup as setup
kinematics, layup, start, steps, repeats = sys.argv[1], sys.argv[2], *map(int, sys.argv[3:6])
settings = json.loads(sys.argv[6])  # this tree's case_settings (the tree run may not have it)
_, model = setup.model(8, setup.LAYUPS[layup], kinematics, 20.0)
compiled = model.compile()
blocks = [i for i, part in enumerate(compiled.parts) if isinstance(part, PlyContactBlock)]
saved, states, count = [None], [], [0]
commit = compiled_model.CompiledModel.commit
class Done(Exception):
    pass
def capture(self, state):
    count[0] += 1
    if count[0] == start:
        saved[0] = pickle.dumps([self.parts[b] for b in blocks])
    if count[0] >= start:
        states.append(state)
    if len(states) == steps:
        raise Done
    return commit(self, state)
compiled_model.CompiledModel.commit = capture
solver = CentralDifference(**settings)
try:
    solver.solve(compiled)
except Done:
    pass
compiled_model.CompiledModel.commit = commit
def replay(digest=None):
    parts = pickle.loads(saved[0])
    spent = [0.0, 0.0]
    for state in states:
        for part, b in zip(parts, blocks):
            history = state.history[b]
            began = time.process_time()
            kept = part.update_history(state, history)
            middle = time.process_time()
            force, moment = part.internal_force(state, history)
            spent[0] += middle - began
            spent[1] += time.process_time() - middle
            if digest is not None:
                for value in (*vars(kept).values(), force, moment):
                    if isinstance(value, np.ndarray):
                        digest.update(np.ascontiguousarray(value).tobytes())
    return spent
digest = hashlib.sha256()
replay(digest)
best = [float("inf")] * 2
for _ in range(repeats):
    spent = replay()
    best = [min(b, s) for b, s in zip(best, spent)]
calls = len(states) * len(blocks)
print(json.dumps({"history_us": best[0] / calls * 1e6, "loads_us": best[1] / calls * 1e6,
                  "digest": digest.hexdigest()[:16], "states": len(states)}))
"""


def replay_in(tree: Path, args: argparse.Namespace) -> dict:
    """The replay in a process of its own on ``tree``'s code, one numba thread."""
    from validation.studies.hemisphere_plies_run import case_settings

    environment = {**os.environ, "PYTHONPATH": str(tree), "NUMBA_NUM_THREADS": "1"}
    settings = json.dumps(case_settings(args.layup, args.kinematics, output_interval=None))
    done = subprocess.run(
        [sys.executable, "-c", REPLAY, args.kinematics, args.layup, str(args.start),
         str(args.steps), str(args.repeats), settings],
        cwd=tree, env=environment, capture_output=True, text=True, check=True,
    )  # fmt: skip
    return json.loads(done.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--kinematics", default="fibrous", choices=("fibrous", "mindlin"))
    parser.add_argument("--layup", default="0/90", choices=("0/90", "0/45"))
    parser.add_argument("--start", type=int, default=2000, help="the first replayed step")
    parser.add_argument("--steps", type=int, default=600, help="consecutive steps replayed")
    parser.add_argument("--repeats", type=int, default=3, help="rounds (best CPU)")
    parser.add_argument("--reference", type=Path, help="a tree of the code before")
    args = parser.parse_args()
    trees = {"this": HERE}
    if args.reference is not None:
        trees = {"reference": args.reference.resolve(), "this": HERE}
    for _ in range(2 if args.reference is not None else 1):
        for name, tree in trees.items():
            ran = replay_in(tree, args)
            print(f"{name:9s} {args.kinematics} [{args.layup}] steps {args.start}-"
                  f"{args.start + ran['states']}: committed history {ran['history_us']:6.1f} "
                  f"us, loads {ran['loads_us']:6.1f} us a block-step (best of "
                  f"{args.repeats}), digest {ran['digest']} (load "
                  f"{os.getloadavg()[0]:.1f})", flush=True)  # fmt: skip


if __name__ == "__main__":
    main()
