"""The compiled landing (elements/ply_landing_kernels.py) gives its numpy reference's landing
to the last bit (elements/ply_landing.py ``landing``): the same IEEE operations in the same
order, on points landing on tilted and moved triangles, from above their plane then or
already through it, penetrating now or touching at zero gap, facing a plane, an edge or a
vertex, with the gap's zero normal to nu or on T's plane (beside a growth's edge, not
joined), non-finite points among them, from 1 row to hundreds (numpy's einsum could sum in
another order on another count); and on the accepted histories of a ply carried onto a flat
face and onto a fold's edge (tests/test_ply_landing.py's and tests/test_ply_edge_crossing.py's
models), whose anchors and records are the same bits by either."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from elements import ply_landing, ply_landing_kernels
from elements.ply_sides import CLEAR, TOUCHING, PlySides
from tests.ply_pair import random_lower_faces, stepped_history
from tests.test_ply_edge_crossing import VALLEY as FOLD
from tests.test_ply_edge_crossing import VY_LANDING, VZ, landing_run
from tests.test_ply_landing import VX, carried_plies
from tests.test_ply_landing import VZ as CARRIED_VZ

MU = 0.3
FIELDS = ("rows", "rate", "theta", "dtheta", "weights", "gradients", "normal", "height")


def landing_points(count: int, seed: int, edges: bool = True, growth: bool = True):
    """(block, state, history, facing) stand-ins with ``count`` points over 7 lower
    triangles: most without an anchor and not touching at the last accepted state and
    touching now (the landing rows; the others anchored, touching then or not touching
    now), the triangles tilted and moved between then and now, the points then up to 0.1 mm
    through or 0.3 mm above their plane, now up to 0.3 mm into it (some at a zero gap); with
    ``edges`` about a third facing an edge or a vertex (their gaps' normals nu random unit
    vectors, a few nearly in T's plane), with ``growth`` most of those beside a growth's
    edge, a few of those joined; a few points non-finite now."""
    rng = np.random.default_rng(seed)
    m = 7
    before, now, normal_then, normal_now = random_lower_faces(rng, m)
    triangle = rng.integers(0, m, count)
    weights = rng.dirichlet(np.ones(3), count)
    then = np.einsum("pk,pki->pi", weights, before[triangle])
    then += rng.uniform(-0.1, 0.3, count)[:, None] * normal_then[triangle]
    moved = weights + rng.normal(0, 0.02, (count, 3))
    face = np.einsum("pk,pki->pi", moved, now[triangle])
    face += rng.uniform(-0.3, 0.05, count)[:, None] * normal_now[triangle]
    gap = np.minimum(rng.uniform(-0.3, 0.1, count), 0.0)
    gap[rng.random(count) < 0.1] = 0.0
    face[rng.random(count) < 0.05] = np.nan
    anchored = rng.random(count) < 0.2
    sides = np.where(rng.random(count) < 0.85, CLEAR, TOUCHING).astype(np.int8)
    normal = rng.normal(0.0, 1.0, (count, 3))
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    flat = rng.random(count) < 0.1  # nu within TILT of T's plane: the blend's rows
    plane = normal_now[triangle[flat]]
    normal[flat] -= np.sum(normal[flat] * plane, axis=1)[:, None] * plane
    normal[flat] /= np.linalg.norm(normal[flat], axis=1)[:, None]
    rise = rng.uniform(-0.1, 0.1, int(flat.sum()))  # nu . n
    normal[flat] = np.sqrt(1.0 - rise**2)[:, None] * normal[flat] + rise[:, None] * plane
    on_edge = rng.random(count) < 0.35
    on_growth = on_edge & (rng.random(count) < 0.7)
    joined = on_growth & (rng.random(count) < 0.15)
    history = SimpleNamespace(
        triangle=np.where(anchored, triangle, -1),
        anchor=np.where(anchored[:, None], weights, np.nan),
        sides=PlySides(sides, then, before),
    )
    facing = SimpleNamespace(
        touching=rng.random(count) < 0.9,
        triangle=triangle,
        face=face,
        gap=gap,
        weights=moved,
        normal=normal,
        on_edge=on_edge if edges else None,
        on_growth=on_growth if growth else None,
        joined=joined if growth else None,
    )
    block = SimpleNamespace(friction=MU, curved=False, _faces=lambda state: (face, now))
    return block, None, history, facing


def same_bits(found, expected) -> None:
    """Every array of the two landings the same bits (NaN's too), the same Nones."""
    assert found is not None and expected is not None
    for name in (*FIELDS, "edge", "place"):
        a, b = getattr(found, name), getattr(expected, name)
        assert (a is None) == (b is None), name
        if a is not None:
            assert a.dtype == b.dtype and a.shape == b.shape, name
            assert a.tobytes() == b.tobytes(), name
    # what the tangent moves an edge row's anchor by (ply_edge_landing.crossing_motion)
    assert (found.crossing is None) == (expected.crossing is None), "crossing"
    if found.crossing is not None:
        for name in ("before", "now", "then", "point", "feature", "normal", "plane"):
            a, b = getattr(found.crossing, name), getattr(expected.crossing, name)
            assert a.dtype == b.dtype and a.shape == b.shape, name
            assert a.tobytes() == b.tobytes(), f"crossing.{name}"


@pytest.mark.parametrize("count", [1, 2, 3, 8, 40, 600])
def test_the_compiled_landing_gives_the_numpy_landing_to_the_bit(count):
    """The same rows, rates, thetas, frames, heights, edge flags and places, every bit."""
    points = landing_points(count, seed=count)
    expected = ply_landing.landing(*points)
    if expected is None:  # too few points to land: none either way
        assert ply_landing_kernels.landing(*points) is None
        return
    same_bits(ply_landing_kernels.landing(*points), expected)
    if count >= 40:  # enough points for every branch
        assert expected.edge is not None and 0 < expected.edge.sum() < len(expected.rows)
        assert 0 < np.sum(expected.dtheta > 0.0) < len(expected.rows)
        assert np.any(expected.theta == 1.0)
    if count >= 600:
        assert np.any(np.isnan(expected.rate))
        # both sides of the anchor's rule met: the blend (|nu . n| <= TILT) and nu below T
        tilt = np.sum(points[3].normal[expected.rows] * expected.normal, axis=1)
        edge = expected.edge
        assert np.any(edge & (np.abs(tilt) <= ply_landing.TILT) & (tilt != 0.0))
        assert np.any(edge & (tilt < -ply_landing.TILT))


@pytest.mark.parametrize("edges, growth", [(False, False), (True, False)])
def test_the_compiled_landing_without_edge_or_growth_flags_is_the_numpy_landing(edges, growth):
    """A facing that marks no edge gaps (None: no edge rows, no places) or no growths (every
    edge row's zero normal to nu)."""
    points = landing_points(200, seed=11, edges=edges, growth=growth)
    found, expected = ply_landing_kernels.landing(*points), ply_landing.landing(*points)
    same_bits(found, expected)
    assert (expected.edge is None) == (not edges)


@pytest.mark.parametrize(
    "model, way",
    [
        (carried_plies, np.array([VX, 0.0, -CARRIED_VZ])),
        (lambda: landing_run(FOLD), np.array([0.0, VY_LANDING, -VZ])),
    ],
    ids=["face", "edge"],
)
@pytest.mark.parametrize("steps", [40, 3])
def test_the_accepted_histories_by_the_compiled_landing_are_the_numpy_ones(
    monkeypatch, model, way, steps
):
    """The upper ply carried down onto the lower face (its points landing on a plane) and
    onto a fold's valley (its point landing on the edge) in 40 and in 3 accepted states:
    the last history's anchors, slips and dissipation the same bits by either landing, and
    points landed."""
    histories = {}
    for compiled in (True, False):
        monkeypatch.setattr(ply_landing_kernels, "COMPILED", compiled)
        _, history = stepped_history(model(), way, steps)
        histories[compiled] = history
    fast, reference = histories[True], histories[False]
    assert np.any(reference.triangle >= 0) and reference.dissipated > 0.0
    for name in ("triangle", "anchor", "slip", "pressing"):
        assert getattr(fast, name).tobytes() == getattr(reference, name).tobytes(), name
    assert fast.dissipated == reference.dissipated


def test_the_curved_faces_landing_is_numpys():
    """On the curved faces (the places along the Phong patch's normal) the kernel is not
    asked: the numpy reference's answer, the same object's fields."""
    block, state, history, facing = landing_points(60, seed=5)
    curved = SimpleNamespace(**{**vars(block), "curved": True})
    called = []

    def reference(*args):
        called.append(args)
        return "numpy"

    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(ply_landing, "landing", reference)
        assert ply_landing_kernels.landing(curved, state, history, facing) == "numpy"
    assert len(called) == 1
