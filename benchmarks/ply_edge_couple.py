"""The stick couple of stuck points facing an edge or a vertex (elements/ply_edge_couple.py,
``ply_friction.edge_couples``; docs/theory.md "Friction between plies"): its cost in the ply
contact's compiled loads, this tree beside a reference tree (``git archive`` of the code
before), each in a process of its own, in turn, CPU (``time.process_time``), one thread.

The model: tests/test_ply_kernels.py's two-ply Mindlin [0/90] hemisphere blank (8 cells,
validation/studies/hemisphere_plies_setup.py) bent 5 then 5.2 mm, both ply contact passes with
friction, the history committed at 5 mm (stuck and sliding anchors at 5.2); ``stick="normal
law"``; its stuck points, and those facing an edge or a vertex. Timed: ``internal_force`` of
both passes with the facing kept (a step's loads), best of 7 x 200 calls.

Measured (one thread, 2 cores shared with other jobs, load 14-16), reference (05b57d7, the tree
before) | this tree, 63 stuck points, none facing an edge or a vertex (what a forming step pays
for the test of its rows), three runs in turn: 0.160 | 0.179, 0.161 | 0.177, 0.162 | 0.183 ms a
call (+0.016 to +0.021 ms for both passes, 10-13 %; about 0.6 % of the coarse hemisphere's
2.5-3 ms step). In one process, per pass: ``ply_loads`` 77-79 -> 87-91 us with friction, 58.3
-> 58.5 us without (the (0, 4, 3) ``turn`` and its test, 2.6 us of which ``np.any(stuck &
on_edge)``; the rest in the compiled pass's friction loop, which now adds the couple's
conditional terms). A first version that always passed a zero (P, 4, 3) array cost the same
(0.166 | 0.187 ms, load 14-16). Where stuck points do face an edge or a vertex: on the pit of
tests/test_ply_edge_couple.py (46 stuck points facing its edges and its vertex, load 14-17)
``edge_couples`` took 216 us a call in numpy with einsums over every row's cuts, 110 us with
the cuts' test on the rows that have one, and takes 15 us compiled
(elements/ply_edge_couple_kernels.py, the same bits). Over the coarse fibrous [0/90]
hemisphere run (6865 steps; 5338 of its 13730 loads calls have such points, 5.7 a call, of
151 stuck), timed round each call: 0.199 ms a step in numpy, 0.028 compiled (load 14-15).
The whole run beside 05b57d7 (``python benchmarks/forming_step_overhead.py --reference``,
fibrous [0/90], 8 cells, best of 2, CPU; the runs differ: 6771 -> 6865 steps): with the couple
in numpy 1.953 -> 2.384 ms a step (load 13-16), compiled 2.124 -> 2.281 ms a step (+7 %, load
14-16; the reference itself moved by 9 % between the two sessions).

Also timed: ``friction_tangent`` of both passes of the blank (best of 5 x 10 calls) and of the
pit's 46 stuck points facing its edges and its vertex (best of 5 x 20). The cuts since (the
same bits: tests/test_ply_edge_couple.py, test_ply_kernels.py, test_ply_stick_potential.py;
the whole run's final positions and steps): ``friction_tangent`` makes the edge features
once a call, where the couple in its forces made them again (``edge_couples``); ``ply_loads``
tests for such points by ``np.count_nonzero`` on the flags it makes for the plane couple's
rows (``stuck ^ edge``), 0.65 us where ``np.any(stuck & on_edge)`` took 2.7 us and the
flags another pass. Beside 16c6b29 (load 6.1, three runs in turn), reference | this tree, ms
a call: loads 0.237 | 0.229, 0.240 | 0.226, 0.231 | 0.220 (-3 to -6 %); the blank's tangent
(no point facing an edge: the cut saves microseconds there, the 3-5 % is noise) 35.9 |
34.0, 35.1 | 33.7, 35.2 | 34.2; the pit's tangent 6.53 |
6.40, 6.40 | 6.29, 6.48 | 6.75 (the features are a few per cent of it: within the noise).
Again at load 1.2-1.3: loads 0.219 | 0.210, 0.214 | 0.212, 0.217 | 0.213 (-1 to -4 %); the
blank's tangent 33.6 | 32.4, 32.1 | 33.9, 34.1 | 33.6; the pit's 5.75 | 5.69, 5.72 | 6.03,
5.79 | 5.80.
The whole run (``forming_step_overhead.py --reference``, fibrous [0/90], 6865 steps, best of
2, the same steps and positions to the bit): 1.935 -> 1.787 ms a step (load 5.7), then
1.701 -> 1.701 (load 2.1): the loads call is about a tenth of a step, its cut within the noise.
What is left of the couple's cost where no point faces an edge lies in the compiled pass:
its kernel alone took 38.1 us a call on the first pass at 05b57d7 and 40.5-42.8 now (one
process each, load 4-6); the pass's ``turned`` terms are not it: a (P, 4, 3) zero ``turn``
in place of the empty one cost 41.0 against 40.5 us, and adding -0.0 (which LLVM may drop)
in place of 0.0 where ``turn`` is empty 40.6 against 40.5 (not kept).

Run: python benchmarks/ply_edge_couple.py --reference /tmp/before
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

if "--measure" not in sys.argv:  # a --measure child: the tree its parent named
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this tree's packages

# the bent blank and the timer of benchmarks/ply_stick_couple.py (this script's directory:
# the same file whichever tree's library the process runs)
from ply_stick_couple import _bent, _best  # noqa: E402

HERE = Path(__file__).resolve().parents[1]


def measure() -> dict:
    """This process's tree: the loads' CPU a call and the premises' counts."""
    from elements import ply_friction
    from elements.ply_block import PlyContactBlock
    from validation.studies import hemisphere_plies_setup as setup

    _, model = setup.model(8, setup.LAYUPS["0/90"], "mindlin", 20.0)
    compiled = model.compile()
    blocks = [b for b in compiled.interactions if isinstance(b, PlyContactBlock)]
    first, second = _bent(compiled, 5.0), _bent(compiled, 5.2)
    histories = [b.update_history(first, b.initial_history()) for b in blocks]
    stuck = edge = 0
    for block, history in zip(blocks, histories):
        block.stick = "normal law"
        block.internal_force(second, history)  # compiled, the facing kept
        facing = block.facing(second)
        sliding = block.friction_state(second, history)
        stuck += int(sliding.stuck.sum())
        edge += int(np.sum(sliding.stuck & facing.on_edge))
    ms = 1e3 * _best(
        lambda: [b.internal_force(second, h) for b, h in zip(blocks, histories)], 7, 200
    )
    tangent = 1e3 * _best(
        lambda: [
            ply_friction.friction_tangent(b, second, h, b.facing(second))
            for b, h in zip(blocks, histories)
        ],
        5,
        10,
    )
    return {"ms": ms, "stuck": stuck, "edge": edge, "tangent": tangent, **_pit()}


def _pit() -> dict:
    """The pit of tests/test_ply_edge_couple.py (on the ramp), its stuck points facing its
    edges and those facing its vertex anchored: ``friction_tangent``'s CPU a call, ms."""
    from elements import ply_friction
    from tests.test_ply_edge_couple import anchored, pit

    block, state = pit(smoothing=0.2)
    history, keep = anchored(block, state, "edge")
    vertex = anchored(block, state, "vertex")[0]
    history = type(history)(
        np.where(keep, history.triangle, vertex.triangle),
        np.where(keep[:, None], history.anchor, vertex.anchor),
        history.slip,
        history.pressing,
        history.dissipated,
    )
    facing = block.facing(state)
    ms = 1e3 * _best(lambda: ply_friction.friction_tangent(block, state, history, facing), 5, 20)
    return {"pit_tangent": ms, "pit_edge": int((history.triangle >= 0).sum())}


def run_in(tree: Path) -> dict:
    """``measure`` in a process of its own on the code of ``tree``."""
    environment = dict(os.environ, PYTHONPATH=str(tree), NUMBA_NUM_THREADS="1")
    done = subprocess.run(
        [sys.executable, __file__, "--measure"],
        cwd=tree,
        env=environment,
        capture_output=True,
        text=True,
        check=True,
    )
    return json.loads(done.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--reference", type=Path, help="the tree before (git archive)")
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--measure", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.measure:
        print(json.dumps(measure()))
        return
    for _ in range(args.runs):
        load = os.getloadavg()[0]
        old = run_in(args.reference) if args.reference else None
        new = run_in(HERE)

        def pair(key, old=old, new=new):
            return (f"{old[key]:.3f} | " if old else "") + f"{new[key]:.3f}"

        print(
            f"load {load:.1f}, ms a call (reference | this tree): loads {pair('ms')}, "
            f"tangent {pair('tangent')} ({new['stuck']} stuck points, {new['edge']} facing "
            f"an edge or a vertex); the pit's tangent {pair('pit_tangent')} "
            f"({new['pit_edge']} facing)",
            flush=True,
        )


if __name__ == "__main__":
    main()
