"""The ply contact's step (the committed history, then the next step's loads from it, as an
explicit step asks them) with the loads made in the history's pass (elements/
ply_commit_pass.py ``LOADS_IN_PASS``) and with the loads' own call at the next step (the
chain before), side by side in one process, and the numpy reference (``ply_projection.
COMPILED = False``) over the same states: the two-ply hemisphere of the report's
hemisphere-plies case (Mindlin [0/90] by default, 8 cells), run to step ``--start``, then
``--steps`` committed states replayed through both ply contact blocks (as
benchmarks/ply_chain_parts.py), each round from the blocks as they were at ``--start``, the
two compiled ways alternating round by round (the first of each pair in turn), best of
``--rounds``, CPU (``time.process_time``; run it with NUMBA_NUM_THREADS=1: the passes are
serial, the blank small); the numpy reference once, over the first ``--numpy-steps``.

The histories and the loads (forces and moments) of every replayed state are hashed: the two
compiled ways must give the same digest; the numpy reference's loads are compared with the
compiled ones (the largest difference relative to the largest force).

    NUMBA_NUM_THREADS=1 python benchmarks/ply_commit_pass.py --rounds 6

Measured (one thread, 2 cores shared with a dozen other jobs, load 13), Mindlin [0/90] steps
8000-8300, us a block-step, history + loads: chained 273.9 + 74.0 = 347.9, loads in the pass
309.7 + 17.3 = 327.0 (x 1.064), the numpy reference 2244.7 + 869.2 = 3113.9 (its first 30
steps); again at load 12: 296.3 + 77.5 = 373.9 against 325.2 + 16.6 = 341.8 (x 1.094), the
numpy reference 2935.5; the same digest 51091b0b620e5d25 each time, the numpy reference's
loads equal to the compiled ones (0 difference). At one state of that window (step 8050's
upper pass, 182 of 384 points touching; best of 80 x 10 calls, load 15): the history's pass
29.3 us alone, 56.4 with the loads (their inputs 7.9 of it: the touching rows, numpy's ramp
cubes, the arrays' checks); the loads' own call 33.2 (their kernel about 19, the rest its
masks, conversions and arguments), ``internal_force`` served the kept loads 6.1 (the held
facing, the landing's masks, the kept mapping's test and two copies). The loads' kernel moves
to the commit; what is saved is their call's Python round it, less the inputs the pass now
takes: about 4-10 us a block-step, 20 at that load.
"""

from __future__ import annotations

import argparse
import hashlib
import os
import pickle
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(HERE))  # this tree's packages first, run from anywhere

from benchmarks.ply_chain_parts import states_of  # noqa: E402


def _digest(records: list) -> str:
    """The bytes of every array of the histories (their sides' too) and loads, hashed."""
    digest = hashlib.sha256()
    for record in records:
        values = record if isinstance(record, tuple) else vars(record).values()
        for value in values:
            items = vars(value).values() if hasattr(value, "__dataclass_fields__") else [value]
            for item in items:
                digest.update(np.asarray(item).tobytes())
    return digest.hexdigest()[:16]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--kinematics", default="mindlin", choices=("fibrous", "mindlin"))
    parser.add_argument("--layup", default="0/90", choices=("0/90", "0/45"))
    parser.add_argument("--start", type=int, default=8000, help="the first replayed step")
    parser.add_argument("--steps", type=int, default=300, help="consecutive steps replayed")
    parser.add_argument("--rounds", type=int, default=6, help="rounds of each way (best CPU)")
    parser.add_argument("--numpy-steps", type=int, default=30, help="steps of the reference")
    args = parser.parse_args()
    from elements import ply_commit_pass, ply_projection

    saved, blocks, states = states_of(args.kinematics, args.layup, args.start, args.steps)

    def replay(fused: bool, compiled: bool = True, count: int = len(states)):
        ply_commit_pass.LOADS_IN_PASS = fused
        ply_projection.COMPILED = compiled
        replayed = pickle.loads(saved)
        histories = [states[0].history[b] for b in blocks]
        spent = [0.0, 0.0]
        records: list = []
        for state in states[:count]:
            for i, part in enumerate(replayed):
                began = time.process_time()
                histories[i] = part.update_history(state, histories[i])
                middle = time.process_time()
                loads = part.internal_force(state, histories[i])
                spent[0] += middle - began
                spent[1] += time.process_time() - middle
                records += [histories[i], loads]
        ply_projection.COMPILED = True
        scale = 1e6 / (count * len(blocks))
        return spent[0] * scale, spent[1] * scale, records

    replay(True), replay(False)  # compiled or read from numba's cache
    best = {True: (np.inf, np.inf), False: (np.inf, np.inf)}
    digests = {}
    for round_ in range(args.rounds):
        for fused in (True, False) if round_ % 2 == 0 else (False, True):
            history, loads, records = replay(fused)
            digests[fused] = _digest(records)
            if history + loads < sum(best[fused]):
                best[fused] = (history, loads)
    numpy_history, numpy_loads, numpy_records = replay(False, False, args.numpy_steps)
    compiled_records = replay(True, True, args.numpy_steps)[2]
    worst = 0.0
    for ours, theirs in zip(compiled_records[1::2], numpy_records[1::2]):
        for a, b in zip(ours, theirs):
            worst = max(worst, float(np.max(np.abs(a - b)) / max(np.max(np.abs(b)), 1e-300)))
    print(
        f"{args.kinematics} [{args.layup}] steps {args.start}-{args.start + len(states)}, "
        f"us a block-step (best of {args.rounds}, CPU, one thread), history + loads:"
    )
    for name, fused in (("chained (loads' own call)", False), ("loads in the pass", True)):
        history, loads = best[fused]
        print(f"  {name:28s} {history:7.1f} + {loads:6.1f} = {history + loads:7.1f}")
    print(
        f"  {'numpy reference':28s} {numpy_history:7.1f} + {numpy_loads:6.1f} = "
        f"{numpy_history + numpy_loads:7.1f} (first {args.numpy_steps} steps)"
    )
    print(f"ratio chained / in the pass {sum(best[False]) / sum(best[True]):.3f}; digests "
          f"{digests[False]} / {digests[True]} (the same: {digests[False] == digests[True]}); "
          f"numpy reference's loads against the compiled: {worst:.2e} of the largest; "
          f"load {os.getloadavg()[0]:.1f}")  # fmt: skip


if __name__ == "__main__":
    main()
