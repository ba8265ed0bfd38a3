"""The stick couple of stuck ply contact points whose closest point lies on an edge or at a
vertex of the facing triangle (elements/ply_edge_couple.py; docs/theory.md §9.3a, "Friction
between plies"): the loads are the gradient of the energy the block reports,
E = w W''(g) |s|^2 / 2 with s measured across n = (p - q) / g, and the tangent their
derivative.

The model: a lower ply of 2 x 2 cells, 4 mm square, whose centre node is pushed down by 0.6 mm
(a pit: six faces sloping at 0.3 towards it, its edges from the centre valleys), and an upper
ply of 6 x 6 cells, 3 mm square, laid on it 0.1 mm into it (each node at the lower ply's height
under it, jittered by 0.003 mm; directors tilted by ~0.02 rad), with its points at its
vertices: every node on the valleys' lines faces an edge (40 points) and the centre node the
pit's vertex (its 6 points). Only the chosen points are anchored, 0.002 in barycentric units
off their projections, so every frictional point is stuck and its energy a potential.

The reference is central differences of ``strain_energy`` at every node, translations and
director turns (femcore/interaction_checks.py ``check_force_is_energy_gradient``: step 1e-6 of
the model's size or 1e-6 rad, truncation O(h^2), held to 1e-6 of the largest force or moment
component). Measured: without the couple at edges and vertices the loads were off by 1.4e-3
(edges and vertex, deeper) and 2.9e-3 to 3.1e-3 (on the ramp) of the largest force, 1.6e-2 to
3.5e-2 of the largest moment (the normal penalty's sets the scale; the couple is of the point's
own |F|: at the vertex all of it); with it within 2.1e-10 and 1.7e-9. Compiled and numpy.
"""

import numpy as np
import pytest

from elements import ply_projection
from elements.ply_contact import PlyContact
from elements.ply_edge_couple import edge_features, turning
from elements.ply_friction import PlyFrictionHistory, edge_couples
from femcore import Body, Mesh
from femcore.interaction_checks import check_force_is_energy_gradient, check_tangent
from femcore.state import State

PIT = 0.6  # mm the lower ply's centre node is pushed down
PRESS = 0.1  # mm the upper ply's faces sink into the lower's
HALF = 0.5  # mm the plies' faces' offsets add up to, (h_u + h_l) / 2 with h = 0.5 mm


def _heights(points: np.ndarray, corners: np.ndarray) -> np.ndarray:
    """z (n,) of the piecewise linear surface of triangles ``corners`` (m, 3, 3) under the
    points (n, 2) (each inside one triangle's footprint)."""
    z = np.full(len(points), np.nan)
    a = corners[:, 0, :2]
    frame = np.stack([corners[:, 1, :2] - a, corners[:, 2, :2] - a], axis=2)  # (m, 2, 2)
    for i, xy in enumerate(points):
        local = np.linalg.solve(frame, (xy - a)[:, :, None])[:, :, 0]  # (m, 2)
        inside = (local.min(axis=1) >= -1e-12) & (local.sum(axis=1) <= 1.0 + 1e-12)
        t = np.flatnonzero(inside)[0]
        c = corners[t, :, 2]
        z[i] = c[0] + local[t, 0] * (c[1] - c[0]) + local[t, 1] * (c[2] - c[0])
    return z


def pit(smoothing=None, stick="normal law"):
    """(block, state) of the module docstring's plies (``smoothing``: the penalty's ramp)."""
    rng = np.random.default_rng(3)
    lower = Mesh.rectangle(4.0, 4.0, nx=2, ny=2)
    low = lower.points - [2.0, 2.0, 0.0]
    low[np.argmin(np.linalg.norm(low[:, :2], axis=1)), 2] -= PIT
    upper = Mesh.rectangle(3.0, 3.0, nx=6, ny=6)
    up = upper.points - [1.5, 1.5, 0.0]
    up[:, 2] = _heights(up[:, :2], low[lower.triangles]) + HALF - PRESS
    up += rng.normal(scale=0.003, size=up.shape)
    coordinates = np.vstack([low, up])
    n = len(coordinates)
    mesh = Mesh(
        coordinates,
        triangles=np.vstack([lower.triangles, upper.triangles + len(low)]),
        node_sets={"upper": np.arange(len(low), n)},
        element_sets={"lower": np.arange(len(lower.triangles))},
    )
    directors = [0.0, 0.0, 1.0] + rng.normal(scale=0.02, size=(n, 3))
    directors = directors / np.linalg.norm(directors, axis=1)[:, None]
    active = np.zeros((n, 6), dtype=bool)
    active[:, :5] = True
    contact = PlyContact(
        "upper",
        "lower",
        0.25,
        0.25,
        penalty=100.0,
        rule="vertices",
        smoothing=smoothing,
        friction=0.4,
        stick=stick,
    )
    block = contact.bind(Body(mesh, (), directors, active))
    zero = np.zeros((n, 3))
    return block, State(mesh.points.copy(), directors.copy(), zero, zero.copy())


def _features(block, state, rows):
    _, y = block._faces(state)
    return edge_features(block.facing(state), y, block.cuts, rows)


def anchored(block, state, where: str):
    """The history with only the touching points facing an edge (``where="edge"``) or the
    vertex (``"vertex"``) anchored, 0.002 in barycentric units off their projections."""
    facing = block.facing(state)
    count = len(facing.gap)
    rows = np.flatnonzero(facing.touching & facing.on_edge)
    slide = _features(block, state, rows).slide
    keep = np.zeros(count, dtype=bool)
    keep[rows[slide if where == "edge" else ~slide]] = True
    move = np.random.default_rng(7).normal(size=(count, 3))
    move -= move.mean(axis=1)[:, None]
    return PlyFrictionHistory(
        np.where(keep, facing.triangle, -1),
        np.where(keep[:, None], facing.weights + 0.002 * move, np.nan),
        np.zeros(count),
        np.full(count, 0.5),
        0.0,
    ), keep


def edge_and_vertex(block, state):
    """The history with the touching points facing an edge and those facing the vertex
    anchored (``anchored``'s two histories in one)."""
    history, keep = anchored(block, state, "edge")
    vertex = anchored(block, state, "vertex")[0]
    return type(history)(
        np.where(keep, history.triangle, vertex.triangle),
        np.where(keep[:, None], history.anchor, vertex.anchor),
        history.slip,
        history.pressing,
        history.dissipated,
    )


CASES = {"deeper": None, "on the ramp": 0.2}  # smoothing: |g| = 0.1 past it, or on it


def test_the_pits_points_face_its_edges_and_vertex_as_the_search_says():
    """The premises: 40 touching points face an edge and 6 the vertex; and the features'
    dn/dz (``turning``) is the row of p of the search's gap Hessian (elements/ply_edge_gap.py
    ``edge_hessian``) to round-off, so the loads and the tangent turn n as the gap does."""
    block, state = pit()
    facing = block.facing(state, second=True)
    rows = np.flatnonzero(facing.touching & facing.on_edge)
    features = _features(block, state, rows)
    assert features.slide.sum() == 40 and (~features.slide).sum() == 6
    assert np.all(np.abs(facing.gap[rows] + PRESS) < 0.02)
    turn = turning(features, facing.gap[rows], facing.normal[rows])
    hessian = np.swapaxes(facing.hessian[rows][:, 0], 1, 2)
    assert np.abs(turn - hessian).max() <= 1e-12 * np.abs(hessian).max()


@pytest.mark.parametrize("compiled", [True, False], ids=["compiled", "numpy"])
@pytest.mark.parametrize("where", ["edge", "vertex"])
@pytest.mark.parametrize("case", list(CASES))
def test_a_stuck_point_facing_an_edge_or_a_vertex_loads_the_gradient_of_its_energy(
    monkeypatch, case, where, compiled
):
    monkeypatch.setattr(ply_projection, "COMPILED", compiled)
    block, state = pit(smoothing=CASES[case])
    history, keep = anchored(block, state, where)
    sliding = block.friction_state(state, history)
    assert keep.sum() >= 6 and np.array_equal(sliding.stuck, keep)
    check_force_is_energy_gradient(block, state, history)  # every node, u and psi
    # the couple acts on the point itself too (n turns with p): at the vertex it takes nearly
    # all of F off p (n . r ~ g), at an edge F's part across the edge
    couple = edge_couples(block, state, sliding, block.facing(state), np.flatnonzero(keep))
    share = np.linalg.norm(couple[:, 0], axis=1) / np.linalg.norm(sliding.force[keep], axis=1)
    if where == "vertex":
        assert np.all(np.abs(share - 1.0) < 0.1)
    else:
        assert np.median(share) > 0.3


@pytest.mark.parametrize("stick", ["normal law", "penalty"])
@pytest.mark.parametrize("where", ["edge", "vertex"])
def test_the_tangent_of_a_stuck_point_facing_an_edge_or_a_vertex(where, stick):
    """The block's tangent against central differences of its forces and moments at every
    node (``check_tangent``, 1e-6 of the largest entry), on the ramp (k_t = W'' moves with
    g); with ``stick="penalty"`` the loads are the gradient too."""
    block, state = pit(smoothing=0.2, stick=stick)
    history, _ = anchored(block, state, where)
    if stick == "penalty":
        check_force_is_energy_gradient(block, state, history)
    assert check_tangent(block, state, history)


def _cut_strip_facing(seed: int, hessian: bool):
    """400 random points faced on tests/test_ply_wedge.py's cut strip (its rng's ``seed``;
    the gap's Hessian with ``hessian``): (the rng after them, y, cuts, the facing)."""
    from elements.ply_projection import closest_facing
    from elements.ply_topology import FaceTopology
    from tests.test_ply_wedge import cut_strip

    rng = np.random.default_rng(seed)
    nodes, y, outline, cuts = cut_strip(rng, 0.3)
    p = rng.uniform([-1.0, -1.2, -0.6], [5.0, 0.9, 0.6], (400, 3))
    near = np.tile(np.arange(len(nodes)), (len(p), 1))
    toward = np.tile([0.0, 0.0, 1.0], (len(p), 1))
    topology = FaceTopology.of(nodes, outline)
    facing = closest_facing(
        p, y, near, 0.0, outline, hessian, depth=0.2, toward=toward, topology=topology, cuts=cuts
    )
    return rng, y, cuts, facing


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_the_features_turn_n_as_the_search_s_hessian_round_cut_strips(seed):
    """tests/test_ply_wedge.py's strips (grown past their outline, cut at both ends) and 400
    points round them: at every point facing an edge, a vertex or a cut (``on_edge``) the
    features' dn/dz is the row of p of the search's gap Hessian (``edge_hessian``, which sees
    the cut's segment the facing does not keep) to round-off (measured: 3.6e-16 of its
    largest entry); the premise, points whose closest point lies inside a cut (no coordinate
    at its bound)."""
    rng, y, cuts, facing = _cut_strip_facing(seed, hessian=True)
    rows = np.flatnonzero(facing.on_edge)
    features = edge_features(facing, y, cuts, rows)
    turn = turning(features, facing.gap[rows], facing.normal[rows])
    hessian = np.swapaxes(facing.hessian[rows][:, 0], 1, 2)
    assert np.abs(turn - hessian).max() <= 1e-12 * np.abs(hessian).max()
    inside_cut = (facing.weights[rows] > -facing.reach[rows] + 1e-9).all(axis=1)
    assert inside_cut.any() and features.slide.any() and (~features.slide).any()


def test_the_compiled_loads_with_the_edge_couple_are_numpy_s_to_the_bit(monkeypatch):
    """The pit's stuck points facing its edges and its vertex (on the ramp): the compiled
    loads (elements/ply_load_kernels.py) give numpy's forces and moments to the bit, on one
    thread and on all of numba's."""
    from tests.thread_runs import on_one_thread_and_on_all

    block, state = pit(smoothing=0.2)
    history = edge_and_vertex(block, state)
    both = history.triangle

    def loads():
        answers = []
        for compiled in (True, False):
            monkeypatch.setattr(ply_projection, "COMPILED", compiled)
            for kept in ("_facing_at", "_faces_at", "_directions_at"):
                setattr(block, kept, None)
            answers.append(block.internal_force(state, history))
        return answers

    for compiled, reference in on_one_thread_and_on_all(loads):
        for got, want in zip(compiled, reference):
            assert got.dtype == want.dtype and np.array_equal(got, want)
    assert (both >= 0).sum() == 46


def test_at_a_passage_from_a_plane_to_an_edge_the_loads_are_the_energy_s_one_sided_gradients():
    """One stuck point of the pit (on the ramp) on the valley along +y, the upper ply moved
    along x until the point's closest point passes from the edge onto a face's plane (found by
    bisection to 1e-17 mm): 3e-6 mm either side, the upper ply's loads along x are the
    central differences of the reported energy along that motion (step 1e-6 mm) to 1e-4 of
    the point's |F| (measured: 3e-9 and 8e-9). The gap's Hessian jumps there (dn/dp = 0 on
    the plane, (I - n n^T - e^ e^T) / g on the edge), and so does E's gradient: by 0.18 |F|
    along the motion and by 0.15 |F| at a node (measured), the loads with it; without the
    couple at the edge they were off E's gradient on the edge's side by 0.15 |F| (and jumped
    by 0.05 |F| at a node)."""
    block, state = pit(smoothing=0.2)
    facing = block.facing(state)
    p = facing.face
    on_valley = facing.touching & facing.on_edge & (np.abs(p[:, 0]) < 0.02)
    point = np.flatnonzero(on_valley & (p[:, 1] > 0.4) & (p[:, 1] < 0.6))[0]
    history, keep = anchored(block, state, "edge")
    keep = np.arange(len(keep)) == point
    history = type(history)(
        np.where(keep, history.triangle, -1),
        np.where(keep[:, None], history.anchor, np.nan),
        history.slip,
        history.pressing,
        history.dissipated,
    )
    upper = np.unique(block.above)

    def moved(dx):
        x = state.positions.copy()
        x[upper, 0] += dx
        return State(x, state.directors, state.velocities, state.angular_velocities)

    def on_edge(dx):
        return bool(block.facing(moved(dx)).on_edge[point])

    low, high = 0.0, 0.1
    assert on_edge(low) and not on_edge(high)
    for _ in range(60):
        middle = 0.5 * (low + high)
        low, high = (middle, high) if on_edge(middle) else (low, middle)
    step = 1e-6
    force = {}
    for side, at in (("edge", low - 3e-6), ("plane", high + 3e-6)):
        plus = block.strain_energy(moved(at + step), history)
        minus = block.strain_energy(moved(at - step), history)
        loads = block.internal_force(moved(at), history)[0]
        sliding = block.friction_state(moved(at), history)
        assert sliding.stuck[point]
        size = np.linalg.norm(sliding.force[point])
        assert abs(loads[upper, 0].sum() - (plus - minus) / (2 * step)) < 1e-4 * size
        force[side] = loads
    # the premise: E's gradient, and the loads, jump there by a share of |F|
    assert np.abs(force["edge"] - force["plane"]).max() > 0.05 * size


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_the_compiled_edge_couples_are_numpy_s_to_the_bit_round_cut_strips(seed):
    """The strips above, every point facing an edge, a vertex or a cut given a random offset r
    and force F: the compiled couple (elements/ply_edge_couple_kernels.py) is numpy's
    ``edge_couple(edge_features(...))`` to the bit, on one thread and on all of numba's."""
    from elements import ply_edge_couple_kernels
    from elements.ply_edge_couple import edge_couple
    from tests.thread_runs import on_one_thread_and_on_all

    rng, y, cuts, facing = _cut_strip_facing(seed, hessian=False)
    rows = np.flatnonzero(facing.on_edge)
    count = len(facing.gap)
    offset, force = rng.normal(size=(count, 3)), rng.normal(size=(count, 3))
    features = edge_features(facing, y, cuts, rows)
    want = edge_couple(features, facing.gap[rows], facing.normal[rows], offset[rows], force[rows])
    for got in on_one_thread_and_on_all(
        lambda: ply_edge_couple_kernels.edge_couples(facing, y, cuts, rows, offset, force)
    ):
        assert got.dtype == want.dtype and np.array_equal(got, want)
    assert features.slide.any() and (~features.slide).any() and np.any(want != 0.0)


def test_the_tangent_makes_the_edge_features_once_and_gives_the_same_bits(monkeypatch):
    """``friction_tangent`` on the pit's 46 stuck points facing its edges and its vertex
    makes their edge features once a call (for the couple's derivative and for the couple in
    its forces), where it made them twice (again in ``edge_couples``, numpy's
    ``edge_features`` or the compiled pass): the same blocks to the bit with the compiled
    kernels on and off, and the couple in them the ``edge_couples`` the loads use."""
    from elements import ply_edge_couple_kernels, ply_friction

    block, state = pit(smoothing=0.2)
    history = edge_and_vertex(block, state)
    made = []
    features, compiled = ply_friction.edge_features, ply_edge_couple_kernels.edge_couples
    monkeypatch.setattr(
        ply_friction, "edge_features", lambda *a: made.append("numpy") or features(*a)
    )
    monkeypatch.setattr(
        ply_edge_couple_kernels, "edge_couples", lambda *a: made.append("compiled") or compiled(*a)
    )
    blocks = []
    for on in (True, False):
        monkeypatch.setattr(ply_projection, "COMPILED", on)
        made.clear()
        facing = block.facing(state)
        blocks.append(ply_friction.friction_tangent(block, state, history, facing).blocks)
        assert made == ["numpy"]
    assert np.array_equal(blocks[0], blocks[1])
    # the couple's rows: the forces' geometric part reads it (a turn of the directors)
    sliding = ply_friction.friction_state(block, state, history, facing)
    rows = np.flatnonzero(sliding.stuck | sliding.sliding)
    assert np.count_nonzero(edge_couples(block, state, sliding, facing, rows)) > 0
    assert (history.triangle >= 0).sum() == 46
