"""The ply contacts' per-step work with the side and landing masks compiled
(elements/ply_side_masks.py) and with numpy's, side by side in one process: the two-ply
hemisphere of the report's hemisphere-plies case (Mindlin [0/90] by default, 8 cells), run to
step ``--start``, then ``--steps`` committed states replayed through both ply contact blocks
as a step meets them (the committed history, ``update_history``, then the next step's loads
from it at the same state, ``internal_force``), each round from the blocks as they were at
``--start``, the two ways alternating round by round (the first of each pair in turn), best
of ``--rounds``, CPU (``time.process_time``; run it with NUMBA_NUM_THREADS=1). The histories
committed and the loads are hashed: the two ways must give the same digest.

    NUMBA_NUM_THREADS=1 python benchmarks/ply_side_masks.py --rounds 8

Measured (one thread, 2 cores shared with other jobs), us a block-step, numpy's masks ->
compiled: see benchmarks/forming_step_overhead.py, its eleventh round.
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
sys.path.insert(0, str(HERE))  # run from anywhere, no install

from benchmarks.ply_chain_parts import states_of  # noqa: E402


def _digest(outputs: list) -> str:
    """The bytes of every array of the histories (their sides' too) and loads, hashed."""
    digest = hashlib.sha256()
    for output in outputs:
        if isinstance(output, tuple):
            for item in output:
                digest.update(np.asarray(item).tobytes())
            continue
        for value in vars(output).values():
            values = vars(value).values() if hasattr(value, "__dataclass_fields__") else [value]
            for item in values:
                digest.update(np.asarray(item).tobytes())
    return digest.hexdigest()[:16]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--kinematics", default="mindlin", choices=("fibrous", "mindlin"))
    parser.add_argument("--layup", default="0/90", choices=("0/90", "0/45"))
    parser.add_argument("--start", type=int, default=8000, help="the first replayed step")
    parser.add_argument("--steps", type=int, default=300, help="consecutive steps replayed")
    parser.add_argument("--rounds", type=int, default=8, help="rounds of each way (best CPU)")
    args = parser.parse_args()
    from elements import ply_side_masks

    saved, blocks, states = states_of(args.kinematics, args.layup, args.start, args.steps)

    def replay(compiled: bool) -> tuple[float, str]:
        ply_side_masks.COMPILED = compiled
        replayed = pickle.loads(saved)
        spent, outputs = 0.0, []
        for state in states:
            for part, b in zip(replayed, blocks):
                began = time.process_time()
                history = part.update_history(state, state.history[b])
                loads = part.internal_force(state, history)
                spent += time.process_time() - began
                outputs += [history, loads]
        return spent / (len(states) * len(blocks)) * 1e6, _digest(outputs)

    replay(True), replay(False)  # compiled or read from numba's cache
    best = {True: np.inf, False: np.inf}
    digests = {}
    for round_ in range(args.rounds):
        for compiled in (True, False) if round_ % 2 == 0 else (False, True):
            spent, digests[compiled] = replay(compiled)
            best[compiled] = min(best[compiled], spent)
    same = digests[False] == digests[True]
    print(f"{args.kinematics} [{args.layup}] steps {args.start}-{args.start + len(states)}, "
          f"the committed history and the next loads, us a block-step (best of {args.rounds}, "
          f"CPU, one thread): numpy's masks {best[False]:.1f}, compiled {best[True]:.1f} "
          f"(x {best[False] / best[True]:.3f}); digests {digests[False]} / {digests[True]} "
          f"(the same: {same}); load {os.getloadavg()[0]:.1f}")  # fmt: skip


if __name__ == "__main__":
    main()
