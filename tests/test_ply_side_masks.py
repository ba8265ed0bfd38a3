"""The compiled masks of a ply contact's sides and landing points (elements/ply_side_masks.py)
give numpy's flags and rows (elements/ply_sides.py ``behind``, elements/ply_landing.py
``landing_rows`` with ``COMPILED`` False): the same comparisons, on every mix of sides, gaps
about zero and about the depth (exactly at -depth and at zero among them, NaN and -0.0),
touching flags and anchors, on the arrays' types a block hands them (read-only facings,
int8 sides), from no point to hundreds."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from elements import ply_landing, ply_side_masks, ply_sides
from elements.ply_sides import BEHIND, CLEAR, TOUCHING, PlySides

DEPTH = 0.5


def _points(count: int, seed: int):
    """(gap (P,), sides (P,) int8, touching (P,) bool, triangle (P,) int64): read-only, as
    a block's facing and history hold them; gaps about 0 and -DEPTH with the exact edges."""
    rng = np.random.default_rng(seed)
    gap = rng.choice([-1.0, -DEPTH, -0.4, -0.0, 0.0, 1e-12, 0.3, np.nan], count)
    gap = gap + np.where(rng.random(count) < 0.5, rng.normal(0.0, 0.2, count), 0.0)
    sides = rng.choice(np.array([CLEAR, TOUCHING, BEHIND], dtype=np.int8), count)
    touching = rng.random(count) < 0.6
    triangle = np.where(rng.random(count) < 0.4, -1, rng.integers(0, 9, count)).astype(np.int64)
    for array in (gap, sides, touching, triangle):
        array.setflags(write=False)
    return gap, sides, touching, triangle


@pytest.mark.parametrize("count", [0, 1, 7, 384])
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_the_landing_rows_are_numpys(count, seed, monkeypatch):
    _, sides, touching, triangle = _points(count, seed)
    block = SimpleNamespace(friction=0.3)
    history = SimpleNamespace(sides=PlySides(sides, np.zeros((count, 3)), None), triangle=triangle)
    facing = SimpleNamespace(touching=touching)
    compiled = ply_landing.landing_rows(block, history, facing)
    monkeypatch.setattr(ply_side_masks, "COMPILED", False)
    reference = ply_landing.landing_rows(block, history, facing)
    assert compiled.dtype == reference.dtype
    np.testing.assert_array_equal(compiled, reference)


@pytest.mark.parametrize("count", [0, 1, 7, 384])
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_the_points_kept_off_are_numpys(count, seed, monkeypatch):
    """With no point entering (no clear point deeper than the depth) and with some: those
    are then judged by their motion as numpy judges them (the faces the block keeps)."""
    gap, sides, touching, triangle = _points(count, seed)
    rng = np.random.default_rng(seed + 10)
    faces, corners = rng.normal(size=(count, 3)), rng.normal(size=(9, 3, 3))
    moved = (faces + rng.normal(0.0, 0.3, (count, 3)), corners + rng.normal(0.0, 0.1, (9, 3, 3)))
    block = SimpleNamespace(depth=DEPTH, _faces=lambda state: moved)
    weights = rng.dirichlet(np.ones(3), count)
    facing = SimpleNamespace(gap=gap, triangle=np.maximum(triangle, 0), weights=weights)
    last = PlySides(sides, faces, corners)
    cleared = PlySides(np.where(sides == CLEAR, TOUCHING, sides).astype(np.int8), faces, corners)
    for before in (last, cleared):
        compiled = ply_sides.behind(block, None, facing, before)
        with monkeypatch.context() as numpy_masks:
            numpy_masks.setattr(ply_side_masks, "COMPILED", False)
            reference = ply_sides.behind(block, None, facing, before)
        assert compiled.dtype == reference.dtype == np.bool_
        np.testing.assert_array_equal(compiled, reference)
    # the cases hold points kept off by either rule, and entering ones
    if count == 384:
        assert ply_sides.behind(block, None, facing, cleared).any()
        assert ((sides == CLEAR) & (gap < -DEPTH)).any()
