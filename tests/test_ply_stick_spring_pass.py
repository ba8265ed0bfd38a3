"""The compiled return mapping's stick spring (elements/ply_friction_kernels.py) is numpy's to
the last bit, signed zeros included.

Reference: ``ply_friction.friction_state`` with ``ply_projection.COMPILED = False``: the stick
spring k_t = w W''(g) and its slope W'''(g) from ``ply_friction.stick_spring`` (numpy's
``penalty_law``) on the touching points' rows. The compiled pass computes them in its own
loop from numpy's min(g, 0), so the comparison is of the bytes (no tolerance): every field of
``Sliding`` (the spring, the normal force, the stuck and sliding flags, the forces, and the
stuck points' ``lift`` = w W''' |s|^2 / 2 and ``stored`` = W'' |s|^2 / 2), on gaps past the
ramp, on it, at its ends (-delta, -0.0, +0.0) and apart, with and without the ramp, for both
stick laws, on one thread and on all of numba's.
"""

from types import SimpleNamespace

import numpy as np
import pytest

from elements import ply_friction, ply_friction_kernels, ply_projection
from elements.ply_friction import PlyFrictionHistory
from tests.thread_runs import on_one_thread_and_on_all

DELTA = 0.05  # mm, the ramp


def _contact(smoothing: float, stick: str, seed: int):
    """A block, a facing, a state and a history of 600 points over 4 flat triangles (z = 0),
    anchored with tangential offsets about the friction limit, so that some points stick and
    some slide on the ramp and past it."""
    rng = np.random.default_rng(seed)
    count = 600
    corners = np.array([[0.0, 0.0, 0.0], [10.0, 0.0, 0.0], [0.0, 10.0, 0.0]])
    y = corners[None] + np.arange(4)[:, None, None] * np.array([0.0, 0.0, 0.0])
    y = y + rng.normal(scale=[0.5, 0.5, 0.0], size=(4, 3, 3))
    ramp = DELTA if smoothing > 0.0 else 0.1
    gap = rng.uniform(-3.0 * ramp, 0.5 * ramp, count)
    gap[:6] = [-ramp, -0.0, 0.0, -0.0, 0.0, -ramp]  # the ramp's ends, both zeros
    touching = rng.random(count) < 0.9
    touching[:6] = True
    stiffness = rng.uniform(10.0, 40.0, count)
    fade = np.where(rng.random(count) < 0.5, 1.0, rng.uniform(0.1, 1.0, count))
    triangle = np.where(rng.random(count) < 0.8, rng.integers(0, 4, count), -1)
    weights = rng.dirichlet(np.ones(3), count)
    anchor = np.einsum("pk,pki->pi", weights, y[np.maximum(triangle, 0)])
    # offsets either side of the friction limit's length mu N / k_t, N = -w W'(g) and k_t =
    # w W''(g) (k_p, no w, for "penalty")
    law = ply_projection.penalty_law(gap, stiffness, smoothing)
    spring = stiffness / fade if stick == "penalty" else law[2]
    limit = 0.3 * -law[1] / np.where(spring > 0.0, spring, 1.0)
    angle = rng.uniform(0.0, 2.0 * np.pi, count)
    length = rng.uniform(0.0, 2.0, count) * limit
    offset = length[:, None] * np.column_stack([np.cos(angle), np.sin(angle), np.zeros(count)])
    face = anchor + offset + np.column_stack([np.zeros((count, 2)), gap])
    normal = np.tile([0.0, 0.0, 1.0], (count, 1))
    facing = SimpleNamespace(touching=touching, gap=gap, fade=fade, face=face, normal=normal)
    block = SimpleNamespace(
        above=np.zeros((count, 3), dtype=np.int64),
        stiffness=stiffness,
        smoothing=smoothing,
        stick=stick,
        friction=0.3,
        curved=False,
        _faces=lambda state: (face, y),
    )
    block.normal_law = lambda g, k: ply_projection.penalty_law(g, k, smoothing)
    history = PlyFrictionHistory(
        triangle, np.where((triangle >= 0)[:, None], weights, np.nan), np.zeros(count),
        np.zeros(count), 0.0,
    )  # fmt: skip
    return block, facing, history


def _differ(compiled, reference) -> list[str]:
    """The names of the fields whose bytes differ."""
    return [
        name
        for name, value in vars(reference).items()
        if getattr(compiled, name).dtype != value.dtype
        or getattr(compiled, name).tobytes() != value.tobytes()
    ]


@pytest.mark.parametrize("smoothing", [DELTA, 0.0])
@pytest.mark.parametrize("stick", ["normal law", "penalty"])
@pytest.mark.parametrize("seed", [0, 1])
def test_the_compiled_stick_spring_is_numpy_s_to_the_bit(monkeypatch, smoothing, stick, seed):
    block, facing, history = _contact(smoothing, stick, seed)
    monkeypatch.setattr(ply_projection, "COMPILED", False)
    reference = ply_friction.friction_state(block, None, history, facing)
    monkeypatch.setattr(ply_projection, "COMPILED", True)

    def compiled():
        return ply_friction_kernels.friction_state(block, None, history, facing)

    one, every = on_one_thread_and_on_all(compiled)
    assert _differ(one, reference) == []
    assert _differ(every, reference) == []
    # the premises: stuck and sliding points, on the ramp and past it, lifted by the potential
    on = facing.touching
    ramp = on & (facing.gap < 0.0) & (facing.gap > -DELTA)
    assert reference.stuck.sum() > 20 and reference.sliding.sum() > 20
    assert (reference.stuck & ramp).sum() > 5 and (reference.stuck & ~ramp & on).sum() > 5
    if stick == "normal law" and smoothing > 0.0:
        assert np.count_nonzero(reference.lift) > 5
        # a touching point at g = +-0 has the ramp's W'' = -0.0 (numpy's min(g, 0) is +0.0)
        assert np.signbit(reference.spring[1:5]).all()
