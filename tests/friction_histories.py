"""Ply friction histories made for the tests of the ply contact's friction
(tests/test_interaction_conformance.py, test_ply_curved_friction.py,
test_ply_stick_potential.py)."""

import numpy as np

from elements.ply_friction import PlyFrictionHistory


def shifted_anchors(facing, small: float, large: float) -> PlyFrictionHistory:
    """Each touching point anchored on its facing triangle off its projection by a random
    shift of the barycentric coordinates (seed 7, summing to 0) whose largest component is
    ``small`` at even points and ``large`` at odd ones (some stuck, some sliding); slip 0,
    pressing 0.5 N, 1 N mm dissipated."""
    count = len(facing.gap)
    shift = np.random.default_rng(7).normal(size=(count, 3))
    shift -= shift.mean(axis=1)[:, None]  # the coordinates still sum to 1
    size = np.where(np.arange(count) % 2, large, small) / np.abs(shift).max(axis=1)
    on = facing.touching
    return PlyFrictionHistory(
        np.where(on, facing.triangle, -1),
        np.where(on[:, None], facing.weights + size[:, None] * shift, np.nan),
        np.zeros(count),
        np.full(count, 0.5),
        1.0,
    )


def kept_anchors(history: PlyFrictionHistory, kept: np.ndarray) -> PlyFrictionHistory:
    """``history`` with the anchors of the points not ``kept`` (P,) bool dropped."""
    return PlyFrictionHistory(
        np.where(kept, history.triangle, -1),
        np.where(kept[:, None], history.anchor, np.nan),
        history.slip,
        history.pressing,
        history.dissipated,
    )
