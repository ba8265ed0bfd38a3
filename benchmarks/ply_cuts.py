"""What the wedge cuts cost the ply contact's facing (elements/ply_wedge.py,
docs/hemisphere_plies.md "The wedge cut"): the two-ply Mindlin [0/90] hemisphere blank of
validation/studies/hemisphere_plies_setup.py at ``--cells`` (its two passes: the upper ply's
points against the lower ply, and the mirrored one), ``--states`` states jittered by 1e-4 mm
about the blank as bound, each block's facing computed afresh per state: with its cuts, and
with none (``WedgeCuts.none``: the reference pass over the same points and candidates),
alternating, best of ``--repeats``, CPU per state (both passes). The machine's load is
printed.

    python benchmarks/ply_cuts.py --cells 10

Measured (one thread, load 0.3-0.7, nothing else running; ms a state, cuts / none):
before `closest_on_cut` took the triangles' gradients from `closest_facing` and the cuts'
overshoot was measured only where a candidate does not hold the projection (main a1c521c)
4.16 / 2.73, 3.86 / 2.71, 3.93 / 2.71, 3.94 / 2.72, 3.93 / 2.72; after (the same facing to
the bit on the wedge tests' paths and six bent states of the 8-cell blank, both passes)
3.83 / 2.71, 3.79 / 2.68, 3.86 / 2.72, 3.89 / 2.69, 3.85 / 2.71: the cuts cost 1.4 x the
facing without them (2 % less than before). The rest of that cost is spread over numpy calls
on small arrays (the cut candidates' planes, the segments' closest points, the search's
closest points on the cut growths), none above 10 % of the facing in a profile.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install

from elements.ply_block import PlyContactBlock  # noqa: E402
from elements.ply_wedge import WedgeCuts  # noqa: E402
from femcore.state import State  # noqa: E402
from validation.studies import hemisphere_plies_setup as setup  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cells", type=int, default=10, help="cells across the blank")
    parser.add_argument("--states", type=int, default=30, help="states timed per round")
    parser.add_argument("--repeats", type=int, default=5, help="rounds (best CPU)")
    args = parser.parse_args()
    _, model = setup.model(args.cells, setup.LAYUPS["0/90"], "mindlin", 20.0)
    compiled = model.compile()
    blocks = [b for b in compiled.interactions if isinstance(b, PlyContactBlock)]
    n = compiled.mesh.n_nodes
    directors = np.tile([0.0, 0.0, 1.0], (n, 1))
    zero = np.zeros((n, 3))
    rng = np.random.default_rng(0)
    x0 = compiled.mesh.points
    states = [
        State(x0 + rng.normal(0.0, 1e-4, x0.shape), directors, zero, zero)
        for _ in range(args.states)
    ]
    cut = [(b.cuts, b.search.cuts) for b in blocks]
    uncut = [(WedgeCuts.none(len(b.cells)), None) for b in blocks]
    print(f"load {os.getloadavg()[0]:.2f}; {args.cells} cells, "
          f"{sum(int(b.cuts.any) for b in blocks)} of {len(blocks)} passes cut")  # fmt: skip
    best = {"cuts": np.inf, "none": np.inf}
    for _ in range(args.repeats):
        for name, sets in (("cuts", cut), ("none", uncut)):
            for block, (cuts, searched) in zip(blocks, sets):
                block.cuts, block.search.cuts = cuts, searched
                block.search._lists = None  # the candidates searched again for these cuts
            start = time.process_time()
            for state in states:
                for block in blocks:
                    block._facing_at = None
                    block.facing(state)
            best[name] = min(best[name], (time.process_time() - start) / len(states) * 1e3)
    ratio = best["cuts"] / best["none"]
    print(f"facing, both passes, ms a state (best of {args.repeats}, CPU): with the cuts "
          f"{best['cuts']:.3f}, without {best['none']:.3f} (x {ratio:.2f})")  # fmt: skip
    print(f"load {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
