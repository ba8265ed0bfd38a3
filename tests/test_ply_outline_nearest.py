"""The outline's edge nearest a contact point (elements/ply_fade.py ``nearest_segments``, which
the fade past the outline measures its distance to) is that of measuring every edge.

Reference: the brute force the KD-tree's search (``tree_segments``) replaced where the pairs
are many, kept here as it was: every point against every segment, ties to the lowest index
(``_every_segment``). Held exactly (the same index,
so the fade has the same bits): on random outlines with the points spread about them, massed
at their vertices (where two edges meet at the same closest point and the distances differ
only by round-off), on exact ties (a segment given twice, segments of zero length) and on
segments of very different lengths; and on the two-ply hemisphere's contacts
(validation/studies/hemisphere_plies.py, Mindlin [0/90], 10 cells), whose whole facing
(gaps, fades, their gradients) is compared bit for bit with the search over every edge.
"""

import numpy as np
import pytest

from elements import ply_fade, ply_kernels


def _every_segment(
    p: np.ndarray, starts: np.ndarray, ends: np.ndarray, kept: object = None
) -> np.ndarray:
    """The brute force (c E work), as ``nearest_segments`` was (``kept``, a caller's kept
    tree, unused)."""
    chosen = np.zeros(len(p), dtype=np.int64)
    if len(p) == 0:
        return chosen
    e = ends - starts
    squared = np.maximum(np.einsum("ei,ei->e", e, e), np.finfo(float).tiny)
    block = max(1, 2**20 // max(len(starts), 1))
    for first in range(0, len(p), block):
        rel = p[first : first + block, None, :] - starts[None]
        t = np.clip(np.einsum("cei,ei->ce", rel, e) / squared, 0.0, 1.0)
        r = rel - t[..., None] * e
        chosen[first : first + block] = np.argmin(np.einsum("cei,cei->ce", r, r), axis=1)
    return chosen


def _outline(rng, edges: int) -> np.ndarray:
    """(edges + 1, 3): a closed wavy loop about 100 mm across, lifted out of plane."""
    angle = np.sort(rng.uniform(0.0, 2.0 * np.pi, edges))
    radius = 100.0 * (1.0 + 0.2 * np.sin(5.0 * angle))
    loop = np.column_stack([radius * np.cos(angle), radius * np.sin(angle), rng.normal(size=edges)])
    return np.vstack([loop, loop[:1]])


@pytest.mark.parametrize("seed", range(6))
def test_the_nearest_segment_is_that_of_every_segment(seed):
    rng = np.random.default_rng(seed)
    edges = int(rng.integers(3, 1500))
    loop = _outline(rng, edges)
    starts, ends = loop[:-1].copy(), loop[1:].copy()
    if seed % 2:  # exact ties: a segment given twice, a segment of zero length, a long one
        starts = np.vstack([starts, starts[3 % edges], starts[5 % edges], [-300.0, 0.0, 0.0]])
        ends = np.vstack([ends, ends[3 % edges], starts[5 % edges], [300.0, 10.0, 0.0]])
    count = 3000
    around = starts[rng.integers(0, len(starts), count)]
    p = np.vstack(
        [
            around + rng.normal(scale=5.0, size=(count, 3)),  # near the outline
            around + rng.normal(scale=1e-6, size=(count, 3)),  # at its vertices
            rng.uniform(-150.0, 150.0, size=(count, 3)),  # anywhere
            starts[: min(count, len(starts))],  # on the vertices themselves
        ]
    )
    every = _every_segment(p, starts, ends)
    np.testing.assert_array_equal(ply_fade.tree_segments(p, starts, ends), every)
    np.testing.assert_array_equal(ply_fade.nearest_segments(p, starts, ends), every)
    few = slice(0, max(1, ply_fade.EVERY_PAIR // len(starts)))  # measured pair by pair
    np.testing.assert_array_equal(ply_fade.nearest_segments(p[few], starts, ends), every[few])
    # the compiled pass point by point (the ply springs' nearest edges, ply_kernels.py)
    np.testing.assert_array_equal(ply_kernels.nearest_segments_at(p, starts, ends), every)


@pytest.mark.parametrize(
    "search", ["tree_segments", "every_segment", "nearest_segments", "nearest_segments_at"]
)
def test_one_segment_and_no_point(search):
    rng = np.random.default_rng(0)
    starts, ends = rng.normal(size=(1, 3)), rng.normal(size=(1, 3))
    nearest = getattr(ply_kernels if search == "nearest_segments_at" else ply_fade, search)
    assert nearest(rng.normal(size=(5, 3)), starts, ends).tolist() == [0] * 5
    assert nearest(np.zeros((0, 3)), starts, ends).shape == (0,)


def test_the_hemisphere_plies_facing_is_that_of_every_segment(monkeypatch):
    from elements.ply_block import PlyContactBlock
    from femcore.state import State
    from validation.studies import hemisphere_plies_setup as setup

    _, model = setup.model(10, setup.LAYUPS["0/90"], "mindlin", 20.0)
    compiled = model.compile()
    blocks = [b for b in compiled.interactions if isinstance(b, PlyContactBlock)]
    n = compiled.mesh.n_nodes
    rng = np.random.default_rng(3)
    # the plies pressed into each other and shifted in plane: points near and past the outline
    x = compiled.mesh.points.copy()
    x[:, 2] += rng.uniform(-0.05, 0.05, n)
    x[:, :2] += rng.uniform(-0.5, 0.5, (n, 2))
    state = State(x, np.tile([0.0, 0.0, 1.0], (n, 1)), np.zeros((n, 3)), np.zeros((n, 3)))
    found = []
    # the tree's search forced (the hemisphere's few pairs are measured pair by pair)
    for search in (ply_fade.tree_segments, _every_segment):
        monkeypatch.setattr(ply_fade, "nearest_segments", search)
        facings = []
        for block in blocks:
            block._facing_at = None
            facings.append(block.facing(state, second=True))
        found.append(facings)
    compared = 0
    for tree, every in zip(*found):
        assert np.count_nonzero(every.fade_edge >= 0) > 0
        compared += int(np.count_nonzero(every.fade_edge >= 0))
        for name, value in vars(every).items():
            if isinstance(value, np.ndarray):
                np.testing.assert_array_equal(getattr(tree, name), value, err_msg=name)
    assert compared > 50


def test_a_blown_up_state_is_measured_as_before_not_refused():
    """Above EVERY_PAIR a non-finite vertex or point (a trial state that blew up) is answered
    by every pair, as before the tree (which refuses non-finite coordinates): the caller's
    own finiteness check, not a ValueError from deep inside the search, decides about it."""
    rng = np.random.default_rng(7)
    starts = rng.uniform(-100.0, 100.0, (200, 3))
    ends = starts + rng.uniform(-5.0, 5.0, (200, 3))
    p = rng.uniform(-100.0, 100.0, (100, 3))
    assert len(p) * len(starts) > ply_fade.EVERY_PAIR
    broken = starts.copy()
    broken[3] = np.nan
    far = p.copy()
    far[1] = np.inf
    for points, first in ((p, broken), (far, starts)):
        chosen = ply_fade.nearest_segments(points, first, ends)
        assert np.array_equal(chosen, _every_segment(points, first, ends))
        # the compiled pass takes the first NaN distance as numpy's argmin does
        compiled = ply_kernels.nearest_segments_at(points, first, ends)
        assert np.array_equal(compiled, _every_segment(points, first, ends))
