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
Again, each tree's own script run from a ``git archive`` of it with its packages first
(PYTHONPATH; the scripts of then did not put their tree first, so a script run from an archive
imported the installed checkout's packages), the two trees alternately three times (one
thread, 200 repeats, load 5.0-5.7): the distance fade (0b9ea4b) 2.70-2.73 ms against 2.21-2.23
for the reference pass, the barycentric fade (10ffb2c) 2.41-2.47 against 1.89-1.96: the fade
about 0.5 ms a step's searches in either, the distance fade's searches 11-14 % dearer.

The outline's nearest edge (``ply_fade.nearest_segments``) by a KD-tree over the edges'
midpoints (``tree_segments``) against every edge against every point (the reference pass,
the search as it was; the same answers, tests/test_ply_outline_nearest.py), alternately in
the same process: on a wavy closed outline of E edges with c points spread 5 mm about it
(``--outline``), and in the hemisphere step's searches above (c points near the outline
against its E edges).
Measured (one thread, CPU, load 6.9-8.3; the outline's best of 5, the hemisphere's mean of
200): E 400, c 2000: tree 4.3-4.7 ms against 35.2-36.2 ms every edge; E 1200, c 5000: 19.7-20.2
against 220-230 ms; E 4000, c 10000: 87-90 against 1104-1134 ms. The hemisphere at 10 cells
(searches of 114 and 36 points against 40 edges): the tree 4.87 ms a step's searches against
4.31 ms every edge (its build and queries cost more than 4560 pairs): below ``EVERY_PAIR`` =
8192 pairs ``nearest_segments`` measures every pair, 4.30 ms; at 32 cells (378 and 122 points
against 128 edges, 7233 points in all) 18.5-19.0 ms with the tree against 19.8-20.0 ms every
edge.

Run: python benchmarks/ply_fade.py [--outline | --cells N (the hemisphere's, 10)]
"""

from __future__ import annotations

import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this tree's packages

from elements import ply_fade, ply_projection
from elements.ply_block import PlyContactBlock
from femcore.state import State
from validation.studies import hemisphere_plies_setup as setup

REPEATS = 200


def _unfaded(p, corners, reach, beside, ends, length, *cuts_and_joins):
    """outline_fade's signature (its optional joins and cuts ignored), no fade: w = 1."""
    return np.ones(len(p)), np.zeros((len(p), 6, 3))


# the nearest segment by measuring every segment against every point: the search as it was
# for every size (ply_fade keeps it for few pairs)
every_segment = ply_fade.every_segment


def _alternated(blocks, state, attribute: str, variants: dict) -> dict:
    """CPU of the blocks' facing searches at ``state`` with ply_fade's ``attribute`` replaced by
    each of ``variants`` (name -> function) in turn, REPEATS rounds, summed per name (s); the
    module's own function put back after."""
    own = getattr(ply_fade, attribute)
    totals = dict.fromkeys(variants, 0.0)
    for _ in range(REPEATS):
        for name, function in variants.items():
            setattr(ply_fade, attribute, function)
            start = time.process_time()
            for block in blocks:
                block._facing_at = None
                block.facing(state)
            totals[name] += time.process_time() - start
    setattr(ply_fade, attribute, own)
    return totals


def outline(repeats: int = 5) -> None:
    """CPU of the nearest edge on a wavy outline of E edges, c points about it: the tree and
    every edge, alternately, the best of ``repeats``."""
    rng = np.random.default_rng(0)
    for edges, count in [(400, 2000), (1200, 5000), (4000, 10000)]:
        angle = np.linspace(0.0, 2.0 * np.pi, edges + 1)
        radius = 100.0 * (1.0 + 0.2 * np.sin(5.0 * angle))
        loop = np.column_stack([radius * np.cos(angle), radius * np.sin(angle), 0 * angle])
        starts, ends = loop[:-1], loop[1:]
        p = rng.normal(size=(count, 3)) * 5.0 + starts[rng.integers(0, edges, count)]
        best = {"tree": np.inf, "every edge": np.inf}
        for _ in range(repeats):
            for name, search in (
                ("tree", ply_fade.nearest_segments),
                ("every edge", every_segment),
            ):
                start = time.process_time()
                found = search(p, starts, ends)
                best[name] = min(best[name], time.process_time() - start)
                if name == "tree":
                    tree = found
            assert np.array_equal(tree, every_segment(p, starts, ends))
        print(
            f"E {edges}, c {count}: tree {1e3 * best['tree']:.2f} ms, "
            f"every edge {1e3 * best['every edge']:.2f} ms"
        )
    print("load", os.getloadavg())


def main(cells: int = 10) -> None:
    _, model = setup.model(cells, setup.LAYUPS["0/90"], "mindlin", 20.0)
    compiled = model.compile()
    blocks = [b for b in compiled.interactions if isinstance(b, PlyContactBlock)]
    n = compiled.mesh.n_nodes
    rng = np.random.default_rng(0)
    # the plies pressed into each other by up to 0.05 mm: points touching all over
    x = compiled.mesh.points.copy()
    x[:, 2] += rng.uniform(-0.05, 0.05, n)
    directors = np.tile([0.0, 0.0, 1.0], (n, 1))
    state = State(x, directors, np.zeros((n, 3)), np.zeros((n, 3)))
    fades = {"fade": ply_fade.outline_fade, "reference (w = 1)": _unfaded}
    totals = _alternated(blocks, state, "outline_fade", fades)
    points = sum(len(b.above) for b in blocks)
    for name, total in totals.items():
        print(f"{name}: {1e3 * total / REPEATS:.3f} ms per step's searches ({points} points)")
    # the nearest edge by the tree and by every edge, the same searches, on the numpy path
    # (with ply_projection.COMPILED few pairs are measured in the fade's pass,
    # ply_fade_kernels.outline_fade_at, not through nearest_segments)
    ply_projection.COMPILED = False
    tree = ply_fade.nearest_segments
    sizes = []

    def counted(p, starts, ends, kept=None):
        sizes.append((len(p), len(starts)))
        return tree(p, starts, ends, kept)

    ply_fade.nearest_segments = counted
    for block in blocks:
        block._facing_at = None
        block.facing(state)
    ply_fade.nearest_segments = tree
    searches = {
        "nearest_segments": tree,
        "tree_segments": ply_fade.tree_segments,
        "every edge (as it was)": lambda p, starts, ends, kept=None: every_segment(p, starts, ends),
    }
    totals = _alternated(blocks, state, "nearest_segments", searches)
    ply_projection.COMPILED = True
    print("nearest edge, (points, edges) per search:", sizes)
    for name, total in totals.items():
        print(f"nearest edge by {name}: {1e3 * total / REPEATS:.3f} ms a step's searches")
    print("load", os.getloadavg())


if __name__ == "__main__":
    if "--outline" in sys.argv:
        outline()
    else:
        main(int(sys.argv[sys.argv.index("--cells") + 1]) if "--cells" in sys.argv else 10)
