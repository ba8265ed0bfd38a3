"""The cost of the ply contact's fade past the outline (elements/ply_fade.py) in its search:
CPU time of ``PlyContactBlock.facing`` on the two-ply hemisphere's contacts (validation/
studies/hemisphere_plies.py, Mindlin [0/90], 10 cells: the top ply's Gauss points and the
mirrored pass at the bottom ply's nodes), with the fade and with it replaced by w = 1 (the
reference pass, the search as before), alternately in the same process, the facing's cache
cleared before each call; prints the mean per call over the repeats and the machine's load.

Measured (one thread, 200 repeats, load 5.4): 6.35 ms a step's searches with the fade
against 5.48 ms for the reference pass, 721 points (the fade computed at every point: 7.56
against 5.89 ms, load 5.3; now only at the points facing an outline triangle). The two ply
contacts' facing and force on the code before the fade and with it, each in its own process,
alternately three times (load 9.8-12.4): 6.48 / 7.04 / 6.13 ms before, 7.70 / 7.38 / 6.86
ms with the fade.
The fade by the distance to the outline (its nearest edge searched over every outline edge
at the points facing an outline triangle, in the reference pass too): 3.67 ms with the fade
against 3.00 ms for the reference pass; the barycentric fade of before, run after it from an
export of its commit, 3.41 against 2.76 ms (one thread, 200 repeats, load 5.4-5.6).

Run: python benchmarks/ply_fade.py
"""

from __future__ import annotations

import os
import time

import numpy as np

from elements import ply_fade
from elements.ply_block import PlyContactBlock
from femcore.state import State
from validation.studies import hemisphere_plies_setup as setup

REPEATS = 200


def _unfaded(p, corners, reach, beside, ends, length):
    return np.ones(len(p)), np.zeros((len(p), 6, 3))


def main() -> None:
    _, model = setup.model(10, setup.LAYUPS["0/90"], "mindlin", 20.0)
    compiled = model.compile()
    blocks = [b for b in compiled.interactions if isinstance(b, PlyContactBlock)]
    n = compiled.mesh.n_nodes
    rng = np.random.default_rng(0)
    # the plies pressed into each other by up to 0.05 mm: points touching all over
    x = compiled.mesh.points.copy()
    x[:, 2] += rng.uniform(-0.05, 0.05, n)
    directors = np.tile([0.0, 0.0, 1.0], (n, 1))
    state = State(x, directors, np.zeros((n, 3)), np.zeros((n, 3)))
    faded = ply_fade.outline_fade
    totals = {"fade": 0.0, "reference (w = 1)": 0.0}
    for _ in range(REPEATS):
        for name, function in (("fade", faded), ("reference (w = 1)", _unfaded)):
            ply_fade.outline_fade = function
            start = time.process_time()
            for block in blocks:
                block._facing_at = None
                block.facing(state)
            totals[name] += time.process_time() - start
    ply_fade.outline_fade = faded
    points = sum(len(b.above) for b in blocks)
    for name, total in totals.items():
        print(f"{name}: {1e3 * total / REPEATS:.3f} ms per step's searches ({points} points)")
    print("load", os.getloadavg())


if __name__ == "__main__":
    main()
