"""The ply contacts' committed history (``PlyContactBlock.update_history``) with its fused
passes and with the chained calls they replace, side by side in one process: the two-ply
hemisphere of the report's hemisphere-plies case (Mindlin [0/90] by default, 8 cells), run to
step ``--start``, then ``--steps`` committed states replayed through both ply contact blocks
(as benchmarks/ply_chain_parts.py), each round from the blocks as they were at ``--start``,
the two ways alternating round by round (the first of each pair in turn), best of
``--rounds``, CPU (``time.process_time``; run it with NUMBA_NUM_THREADS=1: the passes are
serial, the blank small). The ways:

* fused: the new state's directions, faces, ``toward`` and the search lists' moves in one
  compiled call (elements/ply_facing_front.py ``FUSED``), the points leaving the face chosen
  in the friction's history pass (elements/ply_friction_kernels.py ``SELECT_IN_PASS``);
* chained: both off (``offset_normals``, ``face_points``, ``_moves``, ``offset_toward``
  called apart; numpy's masks of ``ply_departure.leaving`` and ``beside_growth``).

The histories committed (every array of each block's history and its sides) are hashed: the
two ways must give the same digest.

    python benchmarks/ply_history_passes.py --rounds 8

Measured (one thread, 2 cores shared with other jobs), us a block-step, chained -> fused:
Mindlin [0/90] steps 8000-8300 301.6 -> 279.8 (x 1.078, load 2.4; 344.5 -> 318.5 at load
4.9), fibrous [0/90] steps 2000-2300 337.2 -> 309.6 (x 1.089, load 2.5); the same digests
(f303b98e44987fda, 7a4e2dea0f3a42a9). Each cut alone (a one-off patch of the flags, not this
script's ways; steps 8000-8300, best of 12, load 2.6): chained 292.9 / 297.8, the fused
facing alone 285.6 / 293.2, the rows chosen in the pass alone 286.4 / 291.2, both 277.1 /
286.6 (two runs; x 1.04-1.06 together, about 2 % each). The whole run beside the code before:
benchmarks/forming_step_overhead.py, its tenth round.
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


def _digest(histories: list) -> str:
    """The bytes of every array of the histories (their sides' too), hashed."""
    digest = hashlib.sha256()
    for history in histories:
        for value in vars(history).values():
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
    from elements import ply_facing_front, ply_friction_kernels

    saved, blocks, states = states_of(args.kinematics, args.layup, args.start, args.steps)

    def replay(fused: bool) -> tuple[float, str]:
        ply_facing_front.FUSED = fused
        ply_friction_kernels.SELECT_IN_PASS = fused
        replayed = pickle.loads(saved)
        spent, histories = 0.0, []
        for state in states:
            for part, b in zip(replayed, blocks):
                began = time.process_time()
                histories.append(part.update_history(state, state.history[b]))
                spent += time.process_time() - began
        return spent / (len(states) * len(blocks)) * 1e6, _digest(histories)

    replay(True), replay(False)  # compiled or read from numba's cache
    best = {True: np.inf, False: np.inf}
    digests = {}
    for round_ in range(args.rounds):
        for fused in (True, False) if round_ % 2 == 0 else (False, True):
            spent, digests[fused] = replay(fused)
            best[fused] = min(best[fused], spent)
    same = digests[False] == digests[True]
    print(f"{args.kinematics} [{args.layup}] steps {args.start}-{args.start + len(states)}, "
          f"the committed history, us a block-step (best of {args.rounds}, CPU, one thread): "
          f"chained {best[False]:.1f}, fused {best[True]:.1f} "
          f"(x {best[False] / best[True]:.3f}); digests {digests[False]} / {digests[True]} "
          f"(the same: {same}); load {os.getloadavg()[0]:.1f}")  # fmt: skip


if __name__ == "__main__":
    main()
