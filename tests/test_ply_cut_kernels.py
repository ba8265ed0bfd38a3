"""The closest point of the cut growths compiled (elements/ply_cut_kernels.py) gives numpy's
``ply_wedge.closest_on_cut_numpy`` to the last bit: the closest points, the flags on a cut,
the segments' ends and the parameters, on tests/test_ply_wedge.py's strips cut at both ends
and on the two-ply hemisphere's lower faces (both passes, both layups), points and growths'
closest points scattered round the triangles, degenerate segments and NaN among them; on one
thread and on all of numba's."""

import numpy as np
import pytest
from test_ply_wedge import cut_strip
from thread_runs import on_one_thread_and_on_all

from elements import ply_cut_kernels, ply_projection, ply_wedge
from elements.ply_projection import triangle_frames


def _bits(a: np.ndarray) -> np.ndarray:
    a = np.asarray(a)
    return a if a.dtype == bool else a.view(np.uint8)


def _check(p, corners, q, lines, ends) -> int:
    """Both answers the same to the bit (one thread and all); the rows on a cut."""
    gradients = triangle_frames(corners)[2]
    want = ply_wedge.closest_on_cut_numpy(p, corners, q, lines, ends, gradients)
    one, every = on_one_thread_and_on_all(
        lambda: ply_cut_kernels.closest_on_cut(
            p, corners, q, lines, ends, gradients, ply_wedge.KEEP
        )
    )
    through = ply_wedge.closest_on_cut(p, corners, q, lines, ends, gradients)
    for got in (one, every, through):
        for a, b in zip(got, want):
            assert np.asarray(a).shape == np.asarray(b).shape
            np.testing.assert_array_equal(_bits(a), _bits(b))
    return int(want[1].sum())


def _scattered(rng, y, rows, spread=1.0):
    corners = y[rows] + rng.normal(0.0, 0.02 * spread, (len(rows), 3, 3))
    centre = corners.mean(axis=1)
    size = float(np.linalg.norm(y[:, 1] - y[:, 0], axis=1).mean())
    p = centre + rng.normal(0.0, size * spread, (len(rows), 3))
    q = centre + rng.normal(0.0, 0.7 * size * spread, (len(rows), 3))
    return p, corners, q


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_the_strips_cut_growths_give_numpy_s_bits(seed):
    rng = np.random.default_rng(seed)
    _, y, _, cuts = cut_strip(rng, 0.3)
    rows = np.repeat(np.arange(len(y)), 300)
    p, corners, q = _scattered(rng, y, rows)
    # degenerate: a point on a cut's start, a NaN point, a closest point on its corner
    p[0], p[1], q[2] = corners[0, 0], np.nan, corners[2, 1]
    assert _check(p, corners, q, cuts.lines[rows], cuts.ends[rows]) > 0  # premise: some cut


def test_the_hemisphere_faces_cut_growths_give_numpy_s_bits():
    from elements.ply_block import PlyContactBlock
    from validation.studies import hemisphere_plies_setup as setup

    rng = np.random.default_rng(5)
    on_cut = 0
    for layup in ("0/90", "0/45"):
        _, model = setup.model(8, setup.LAYUPS[layup], "fibrous", 20.0)
        compiled = model.compile()
        for block in compiled.interactions:
            if not isinstance(block, PlyContactBlock) or block.cuts is None:
                continue
            _, y = block._faces(compiled.initial_state())
            lined = np.flatnonzero(np.any(block.cuts.lines != 0.0, axis=(1, 2)))
            rows = np.concatenate([rng.choice(lined, 1500), rng.integers(0, len(y), 300)])
            p, corners, q = _scattered(rng, y, rows, spread=20.0)
            on_cut += _check(p, corners, q, block.cuts.lines[rows], block.cuts.ends[rows])
    assert on_cut > 100


def test_without_gradients_or_compiled_numpy_answers(monkeypatch):
    """``closest_on_cut`` takes the compiled pass only with the gradients given and
    ``ply_projection.COMPILED``."""
    calls = []
    monkeypatch.setattr(ply_cut_kernels, "closest_on_cut", lambda *a: calls.append(a))
    rng = np.random.default_rng(9)
    _, y, _, cuts = cut_strip(rng, 0.3)
    rows = np.arange(len(y))
    p, corners, q = _scattered(rng, y, rows)
    ply_wedge.closest_on_cut(p, corners, q, cuts.lines[rows], cuts.ends[rows])
    monkeypatch.setattr(ply_projection, "COMPILED", False)
    gradients = triangle_frames(corners)[2]
    ply_wedge.closest_on_cut(p, corners, q, cuts.lines[rows], cuts.ends[rows], gradients)
    assert not calls
    monkeypatch.setattr(ply_projection, "COMPILED", True)
    ply_wedge.closest_on_cut(p, corners, q, cuts.lines[rows], cuts.ends[rows], gradients)
    assert len(calls) == 1
