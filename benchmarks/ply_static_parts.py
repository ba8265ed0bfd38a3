"""The Static ply stacks' Newton iterations at a lower cost each: the ply contact's tangent of
its touching points in one compiled pass (elements/ply_point_tangent.py, the carry to the
nodes elements/ply_carry.py) against numpy's (their reference), the facing before the last
kept (elements/ply_block.py ``KEEP_FACING_BEFORE``) against the last alone, and the facing
search over every pair compiled (elements/ply_search_pairs.py) against numpy's. Each solve of the
report's Static plies at a resolution (benchmarks/static_plies_case.py ``solve_case``:
plies-bai-5.1's plies, plies-heavy-cantilever's, plies-deck-of-cards' 4-ply sag) once with
the reference (numpy's tangent, the last facing alone: main before these) and once with both,
in turns in this process, best of ``--repeat``: CPU (``time.process_time``, one thread), the
tangents, the facings made, and the sha256 of every frame's positions, directors and
reactions (the same bits asked); the machine's load printed with them.

    python benchmarks/ply_static_parts.py [--cases bai,heavy,sag] [--resolution coarse]
        [--repeat 3]

Where the time went (cProfile of the default plies-bai-5.1, one thread, main debd499, load
3-4): of the plies' 18.5 s, the contact's tangent 3.7 s (its two einsums carrying the points'
Hessians to the nodes 1.6 s, the plane's Hessian 0.4 s, the forces again 0.6 s), the facings
2.6 s (3941 made for 7791 asked). The carry's map is sparse: each node's columns reach one z
and, of its three coordinates, one (du) or two (dpsi) are not zero; einsum multiplies the
zeros. The compiled pass takes the products that are not zero in einsum's order (each entry
has at most two, so any order of the sum is the same), the same blocks to the bit.

Measured (one thread, CPU, 2 cores shared, load 3.1-3.3; each best of 2 in turns):

* coarse: bai 6.54 -> 4.93 s (0.754 x), heavy 0.50 -> 0.35 s (0.688 x), sag 1.09 -> 0.75 s
  (0.693 x); tangents 975, 125, 184 both ways; facings made 4920 -> 3690, 723 -> 381,
  963 -> 558; the frames the same bits (and the same as main debd499's, a ``git archive``).
* the report's three cases at the default resolution, ``python -m validation --cases
  plies-bai-5.1,plies-deck-of-cards,plies-heavy-cantilever --jobs 1`` beside debd499, back to
  back in both orders (load 2.8-3.9), case CPU s: 16.5 / 16.9 -> 13.9 / 14.2, 7.1 / 7.5 ->
  5.5 / 5.8, 2.4 / 2.4 -> 1.8 / 1.9; in all 26.0 / 26.8 -> 21.2 / 21.9 (0.82 x); results.json
  the same in every number but the times, the .vtu files byte for byte.

Tried and not kept: the loads' facings with the gap's Hessian until two or three in a row went
unused by a tangent (one today): coarse bai 3690 -> 3558 / 3495 facings, within the run's
spread in CPU. Measured and not pursued: a cache of the linear solver's plans by pattern (the
coarse bai's 975 tangents had 834 patterns, 20 of them seen again within the last 16;
docs/theory.md §6.5, "The cost of a stack's Newton iteration"); since, the band plans and
K_ff's structure are kept over the patterns instead (benchmarks/ply_band_plans.py).
"""

from __future__ import annotations

import argparse
import hashlib
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

from benchmarks.static_plies_case import solve_case  # noqa: E402
from elements import ply_block, ply_carry, ply_point_tangent, ply_search  # noqa: E402

COMPILED_BLOCKS = ply_point_tangent.point_blocks
COMPILED_CARRY = ply_carry.carried_blocks
EVERY_PAIR = ply_search.FacingSearch._every_pair


def numpy_pairs(search, here, y, corners):
    """The search over every pair left to numpy (``FacingSearch._every_pair``'s None)."""
    return None


def configure(new: bool) -> None:
    """The compiled tangent, the facing before the last and the compiled search over every
    pair (``new``), or numpy's tangent and search and the last facing alone."""
    ply_point_tangent.point_blocks = (
        COMPILED_BLOCKS if new else ply_point_tangent.point_blocks_reference
    )
    ply_carry.carried_blocks = COMPILED_CARRY if new else ply_carry.carry_reference
    ply_block.KEEP_FACING_BEFORE = new
    ply_search.FacingSearch._every_pair = EVERY_PAIR if new else numpy_pairs  # type: ignore[method-assign]


def digest(result) -> str:
    """sha256 of every frame's positions, directors and reactions."""
    h = hashlib.sha256()
    for frame in result.frames:
        for array in (frame.positions, frame.directors, frame.reactions):
            h.update(np.ascontiguousarray(array).tobytes())
    return h.hexdigest()[:16]


def solve(name: str, resolution: str) -> tuple[float, int, int, str]:
    """(CPU s, tangents, facings made, digest) of one solve."""
    made = [0]
    original = ply_block.closest_facing

    def counted(*args, **kwargs):
        made[0] += 1
        return original(*args, **kwargs)

    ply_block.closest_facing = counted
    try:
        start = time.process_time()
        result = solve_case(name, resolution, None, None)  # no stall, no first-turn rule
        cpu = time.process_time() - start
    finally:
        ply_block.closest_facing = original
    return cpu, int(result.info["evaluations"]["tangent"]), made[0], digest(result)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", default="bai,heavy,sag")
    parser.add_argument("--resolution", default="coarse")
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    load = subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()
    print(f"load before: {load}")
    for name in args.cases.split(","):
        configure(True)
        solve(name, args.resolution)  # the kernels loaded
        rows: dict[bool, list] = {False: [], True: []}
        for _ in range(args.repeat):
            for new in (False, True):
                configure(new)
                rows[new].append(solve(name, args.resolution))
        configure(True)
        old, new = min(rows[False]), min(rows[True])
        same = {row[3] for row in rows[False] + rows[True]}
        print(
            f"{name} ({args.resolution}): CPU {old[0]:.2f} -> {new[0]:.2f} s "
            f"({new[0] / old[0]:.3f} x), tangents {old[1]} -> {new[1]}, facings made "
            f"{old[2]} -> {new[2]}, frames {'the same bits' if len(same) == 1 else 'DIFFER'}"
        )
    load = subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()
    print(f"load after: {load}")


if __name__ == "__main__":
    main()
