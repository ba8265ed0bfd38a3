"""The compiled departure (elements/ply_departure_kernels.py) gives its numpy reference's slips
and records to the last bit (elements/ply_departure.py ``departure``, and the records
elements/ply_friction_kernels.py wrote from it): the same IEEE operations in the same order,
on points leaving tilted, moved and degenerate-free triangles, lifted or not, facing a plane,
an edge or a vertex, beside a growth's edge or not, from 1 row to hundreds (numpy's einsum
could sum in another order on another count), and on the history pass of a pressed, carried
and lifted pair of plies (tests/test_ply_departure.py's model)."""

from __future__ import annotations

import dataclasses
from types import SimpleNamespace

import numpy as np
import pytest

from elements import ply_departure, ply_departure_kernels, ply_friction_kernels
from elements.ply_sides import CLEAR, TOUCHING, PlySides
from tests.ply_pair import random_lower_faces
from tests.test_ply_departure import VX, VZ, lifted_plies

# the upper ply starts PEN0 into the lower one on purpose (the points lift off): the start
# check's overlap warning (elements/ply_start.py) is expected
pytestmark = pytest.mark.filterwarnings("ignore:.*the plies start overlapping")

MU = 0.3


def leaving_points(count: int, seed: int):
    """(block, y, history, facing) stand-ins with ``count`` points over 7 lower triangles:
    every other point anchored and touching at the last accepted state and off the face now
    (a few CLEAR or non-finite: not selected), the triangles tilted and moved between then and
    now, the points then up to 0.3 mm into or above their plane, now up to 0.3 mm above or
    below it (some not lifted: no slip); about a third facing an edge or a vertex (their gaps'
    normals nu random unit vectors), most of those beside a growth's edge (their slip across
    nu), a few of those joined (not beside a growth)."""
    rng = np.random.default_rng(seed)
    m = 7
    before, now, normal_then, normal_now = random_lower_faces(rng, m)
    triangle = rng.integers(0, m, count)
    weights = rng.dirichlet(np.ones(3), count)
    then = np.einsum("pk,pki->pi", weights, before[triangle])
    then += rng.uniform(-0.3, 0.1, count)[:, None] * normal_then[triangle]
    face = np.einsum("pk,pki->pi", weights + rng.normal(0, 0.02, (count, 3)), now[triangle])
    face += rng.uniform(-0.1, 0.3, count)[:, None] * normal_now[triangle]
    anchored = np.arange(count) % 2 == 0
    sides = np.where(rng.random(count) < 0.9, TOUCHING, CLEAR).astype(np.int8)
    on_edge = rng.random(count) < 0.35
    on_growth = on_edge & (rng.random(count) < 0.7)
    joined = on_growth & (rng.random(count) < 0.15)
    normal = rng.normal(0.0, 1.0, (count, 3))
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    face[rng.random(count) < 0.05] = np.nan
    history = SimpleNamespace(
        triangle=np.where(anchored, triangle, -1),
        anchor=weights + rng.normal(0, 0.01, (count, 3)),
        slip=rng.uniform(0.0, 1.0, count),
        pressing=rng.uniform(0.0, 5.0, count),
        sides=PlySides(sides, then, before),
    )
    facing = SimpleNamespace(
        touching=~anchored | (rng.random(count) < 0.1),
        on_edge=on_edge,
        on_growth=on_growth,
        joined=joined,
        normal=normal,
        face=face,
    )
    block = SimpleNamespace(friction=MU)
    return block, now, history, facing


@pytest.mark.parametrize("count", [1, 2, 3, 8, 40, 600])
def test_the_compiled_departure_gives_the_numpy_slips_to_the_bit(count):
    """The same rows (lifted ones: some are not) and the same slips, every bit."""
    block, y, history, facing = leaving_points(count, seed=count)
    rows, slip = ply_departure.departure(block, y, history, facing)
    fast_rows, fast_slip = ply_departure_kernels.departure_slip(block, y, history, facing)
    if count >= 40:  # enough points for every branch
        assert 0 < len(rows) < len(ply_departure.leaving(block, history, facing))
        beside = ply_departure.beside_growth(facing, rows)
        assert 0 < beside.sum() < facing.on_edge[rows].sum()
    np.testing.assert_array_equal(fast_rows, rows)
    assert fast_slip.tobytes() == slip.tobytes()


def test_the_compiled_departure_writes_the_numpy_records_to_the_bit():
    """slipped and dissipation as the history pass wrote them from the numpy slips; the points
    that did not leave untouched."""
    block, y, history, facing = leaving_points(300, seed=7)
    pressing = np.random.default_rng(8).uniform(0.0, 5.0, 300)
    slipped, dissipation = np.full(300, -1.0), np.full(300, -2.0)
    expected_slipped, expected_dissipation = slipped.copy(), dissipation.copy()
    rows, way = ply_departure.departure(block, y, history, facing)
    expected_slipped[rows] = history.slip[rows] + way
    force = MU * 0.5 * (pressing[rows] + history.pressing[rows])
    expected_dissipation[rows] = force * way
    ply_departure_kernels.departed(block, y, history, facing, pressing, slipped, dissipation)
    assert len(rows) > 10
    assert slipped.tobytes() == expected_slipped.tobytes()
    assert dissipation.tobytes() == expected_dissipation.tobytes()


@pytest.mark.parametrize(
    ("fused", "select"), [(True, True), (True, False), (False, False)],
    ids=["fused, rows chosen in the pass", "fused", "apart"],
)  # fmt: skip
def test_the_history_pass_with_the_compiled_departure_keeps_the_numpy_records(
    monkeypatch, fused, select
):
    """The pressed pair carried and lifted in 40 accepted states (its points leave at 0.713
    of the way): every history's slip and dissipation the same bits by the kernel (in the
    fused history pass, elements/ply_friction_pass.py, its rows chosen there or by numpy's
    masks, or called apart) and by the numpy departure."""
    monkeypatch.setattr(ply_friction_kernels, "FUSED", fused)
    monkeypatch.setattr(ply_friction_kernels, "SELECT_IN_PASS", select)
    histories = {}
    for compiled in (True, False):
        monkeypatch.setattr(ply_departure_kernels, "COMPILED", compiled)
        model = lifted_plies().compile()
        block = model.interactions[0]
        state = model.initial_state()
        upper = np.unique(block.above)
        history = block.initial_history()
        records = []
        for step in range(1, 41):
            positions = state.positions.copy()
            positions[upper] += np.array([VX, 0.0, VZ]) * step / 40
            moved = dataclasses.replace(state, positions=positions)
            history = block.update_history(moved, history)
            records.append((history.slip.tobytes(), history.dissipated))
        histories[compiled] = records
    assert histories[True] == histories[False]
    assert histories[True][-1][1] > 0.0
