"""Each vertex's fan made once a call (elements/ply_edge_kernels.py ``_parts_once``, which the
whole facing's first call takes, elements/ply_facing_whole.py ``_choice``) gives ``_parts``'
arrays to the bit.

Reference: ``_parts``, which makes a fan's rise |u x v| and run u . v again at every point at
its vertex (``ply_feature_normals.fan_parts``). Both do the same IEEE operations on the same
corners (no fastmath), so the comparison is exact, no tolerance. The inputs are the ones the
chained facing (``ply_projection.WHOLE = False``) hands ``_parts`` on tests/test_ply_wedge.py's
strips cut at both ends, 300 points round them, then the same points slid along the strip by
a quarter and a half of a cell (so that points leave their vertex and others reach one).
Premises: points at a vertex outnumber the vertices they lie at (the kept fans are served
again), and some points lie on an edge off a vertex and some off every edge (the other two
branches). The whole facing against the chained one, with this pass in it, is
tests/test_ply_facing_whole.py's.
"""

import numpy as np
import pytest

from elements import ply_edge_kernels, ply_projection
from elements.ply_projection import closest_facing
from elements.ply_topology import FaceTopology
from tests.test_ply_wedge import cut_strip


def _inputs_of_parts(monkeypatch, call) -> list[tuple]:
    """The arguments ``edge_sides`` hands ``_parts`` in ``call()``'s chained facing."""
    seen: list[tuple] = []
    kernel = ply_edge_kernels._parts_compiled

    def recorded(*args):
        seen.append(tuple(np.array(a) if isinstance(a, np.ndarray) else a for a in args))
        return kernel(*args)

    monkeypatch.setattr(ply_edge_kernels, "_parts_compiled", recorded)
    monkeypatch.setattr(ply_projection, "COMPILED", True)
    monkeypatch.setattr(ply_projection, "WHOLE", False)
    call()
    monkeypatch.setattr(ply_edge_kernels, "_parts_compiled", kernel)
    return seen


@pytest.mark.parametrize("seed", [0, 1])
def test_the_fans_made_once_are_the_fans_made_at_each_point_on_sliding_points(monkeypatch, seed):
    rng = np.random.default_rng(seed)
    nodes, y, outline, cuts = cut_strip(rng, 0.3)
    topology = FaceTopology.of(nodes, outline)
    start = rng.uniform([-1.0, -1.2, -0.6], [5.0, 0.9, 0.6], (300, 3))
    near = np.argsort(rng.uniform(size=(len(start), len(y))), axis=1)
    at_vertex = vertices = on_edge_only = off_edges = 0
    for slide in (0.0, 0.25, 0.5):  # mm along the strip, whose cells are 1 mm long
        p = start + [slide, 0.0, 0.0]
        calls = _inputs_of_parts(
            monkeypatch,
            lambda p=p: closest_facing(
                p, y, near, 0.0, outline, False, depth=0.4, fade_distance=0.05,
                topology=topology, cuts=cuts,
            ),
        )  # fmt: skip
        assert len(calls) == 1
        given = calls[0][:9]
        on_edge, fans = given[0], given[4]
        count, width = len(on_edge), fans.shape[1]
        want = [np.full((count, 3), np.nan), *np.full((2, count, width), np.nan)]
        got = [np.full_like(a, np.nan) for a in want]
        ply_edge_kernels._parts_compiled(*given, *want)
        ply_edge_kernels._parts_once(*given, *got)
        for a, b in zip(got, want):
            assert a.tobytes() == b.tobytes()
        rows = np.any(want[1] != 0.0, axis=1)
        at_vertex += int(rows.sum())
        vertices += len({r.tobytes() for r in want[1][rows]})
        on_edge_only += int((on_edge & ~rows).sum())
        off_edges += int((~on_edge).sum())
    assert at_vertex > vertices > 0
    assert on_edge_only > 0 and off_edges > 0
