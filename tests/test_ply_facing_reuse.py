"""The ply contact's facing made once per Newton iteration: the loads' facing carries the
gap's Hessian once a tangent has followed a force pass at its state (elements/ply_block.py
``PlyContactBlock.facing``), with the same forces and tangent to the bit."""

from dataclasses import replace

import numpy as np
import pytest

from elements import ply_block, ply_facing_front
from validation.studies.ply_overhang_setup import two_plies


def _states(count: int):
    """The overhanging upper ply (past the lower ply's outline edge: points facing its
    edges, where the gap has a Hessian of its own) pressed into the lower one and jittered,
    ``count`` states; the compiled model."""
    model, first, _ = two_plies(-4.0)
    compiled = model.compile()
    start = compiled.initial_state()
    rng = np.random.default_rng(3)
    states = []
    for _ in range(count):
        positions = start.positions.copy()
        positions[first:, 2] -= 0.05
        positions[first:] += rng.normal(scale=0.02, size=positions[first:].shape)
        states.append(replace(start, positions=positions))
    return compiled, states


def _iterates(count: int, facings: list[bool]):
    """``_states(count)``, with the facings made until then forgotten (the initial state's
    history holds each point's side at the reference: elements/ply_sides.py)."""
    compiled, states = _states(count)
    facings.clear()
    return compiled, states


@pytest.fixture
def facings(monkeypatch):
    """The ``second`` of each facing the ply contact makes."""
    made: list[bool] = []
    original = ply_block.closest_facing

    def counted(*args, **kwargs):
        made.append(bool(args[5]))
        return original(*args, **kwargs)

    monkeypatch.setattr(ply_block, "closest_facing", counted)
    # the facings without the Hessian whose choice the front's call made
    # (elements/ply_facing_front.py ``CHOSEN``), which closest_facing does not see
    finished = ply_facing_front.finished_facing

    def chosen(*args, **kwargs):
        made.append(False)
        return finished(*args, **kwargs)

    monkeypatch.setattr(ply_facing_front, "finished_facing", chosen)
    return made


def test_a_newton_iteration_makes_one_facing(facings):
    compiled, states = _iterates(4, facings)
    block = compiled.interactions[0]
    for state in states:  # each iteration: the trial's loads, then the tangent there
        block.internal_force(state)
        block.tangent(state)
    # the first tangent made the facing again; then the loads' facing served each tangent
    assert facings == [False, True, True, True, True]


def test_loads_without_tangents_drop_the_hessian(facings):
    compiled, states = _iterates(4, facings)
    block = compiled.interactions[0]
    block.internal_force(states[0])
    block.tangent(states[0])
    for state in states[1:]:  # explicit steps: loads alone
        block.internal_force(state)
    assert facings == [False, True, True, False, False]


def test_the_same_forces_and_tangent_to_the_bit(monkeypatch):
    results = {}
    for reuse in (False, True):
        monkeypatch.setattr(ply_block, "HESSIAN_WITH_LOADS", reuse)
        compiled, states = _states(3)
        block = compiled.interactions[0]
        out = []
        for state in states:
            out.append(block.internal_force(state))
            out.append([(part.nodes, part.blocks) for part in block.tangent(state)])
            out.append(block.strain_energy(state))
        results[reuse] = out
    for old, new in zip(results[False], results[True]):
        if isinstance(old, float):
            assert old == new
        elif isinstance(old, tuple):
            assert all(np.array_equal(a, b) for a, b in zip(old, new))
        else:
            assert len(old) == len(new)
            for (nodes_a, blocks_a), (nodes_b, blocks_b) in zip(old, new):
                assert np.array_equal(nodes_a, nodes_b) and np.array_equal(blocks_a, blocks_b)
    # the states touch and face the outline's edges: the Hessian is not all zero
    assert any(np.abs(part[1]).max() > 0 for part in results[True][1])


def test_the_loads_facing_gives_the_tangent_where_points_face_a_vertex(facings):
    """Faces round an outline vertex of a folded fan (tests/test_ply_fade_hessian.py), where
    touching points face the vertex and the gap's Hessian is the search's: the tangent from
    the loads' facing is the tangent from a facing made for it, to the bit."""
    from test_ply_fade_hessian import _fan, _placed, _round_the_vertex

    from femcore.state import State

    block, x, directors, low = _fan("folded")
    zero = np.zeros_like(x)
    faced = 0
    for face in _round_the_vertex(block, low, 0.05):
        state = State(_placed(x, face), directors, zero, zero)
        block.internal_force(state)
        reused = block.tangent(state)
        block._facing_at = None  # a facing made afresh for the tangent
        fresh = block.tangent(state)
        for a, b in zip(reused, fresh):
            assert np.array_equal(a.nodes, b.nodes) and np.array_equal(a.blocks, b.blocks)
        facing = block.facing(state, second=True)
        faced += int(np.any(facing.hessian[facing.touching] != 0.0))
    assert faced >= 1
    # each face but the first: one facing for the loads and the reused tangent, one made
    # afresh (the first face's tangent made its own too, unless the cached fan's block had
    # learnt it in an earlier test)
    faces = len(_round_the_vertex(block, low, 0.05))
    assert len(facings) in (2 * faces, 2 * faces + 1)


def test_the_facing_before_the_last_is_taken_back(facings):
    """The watchdog's pattern: the loads at a trial, the energy at its best iterate, the trial
    again: the best's facing was kept, then the trial's, each made once and the same object
    (the energy the same number); a facing asked afresh (``_facing_at`` None) is made again."""
    compiled, states = _iterates(3, facings)
    block = compiled.interactions[0]
    best, trial, other = states
    first = block.facing(best)
    energy = block.strain_energy(best)
    second = block.facing(trial)
    assert block.facing(best) is first and block.strain_energy(best) == energy
    assert block.facing(trial) is second
    assert len(facings) == 2
    block.facing(other)  # the third state: the first falls out
    block.facing(best)
    assert len(facings) == 4
    block._facing_at = None
    block.facing(best)
    assert len(facings) == 5


def test_the_facing_before_the_last_is_not_taken_back_for_other_directors(facings):
    """The facing before the last is taken back only at the same positions and directors: a
    state with the best iterate's positions and other directors (a rotation's update) is faced
    afresh."""
    compiled, states = _iterates(2, facings)
    block = compiled.interactions[0]
    best, trial = states
    tilted = best.directors + np.random.default_rng(5).normal(scale=1e-3, size=best.directors.shape)
    turned = replace(best, directors=tilted / np.linalg.norm(tilted, axis=1, keepdims=True))
    block.facing(best)
    block.facing(trial)
    assert len(facings) == 2
    block.facing(turned)
    assert len(facings) == 3


def test_closest_facing_refuses_candidates_not_one_row_a_point():
    """The compiled passes size their loops by the candidates' rows and their outputs by the
    points: a mismatch is a ValueError at the call, not a write past the arrays."""
    from elements.ply_projection import closest_facing

    y = np.array([[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]])
    p = np.array([[0.2, 0.2, 0.1], [0.3, 0.1, 0.1]])
    for near in (np.zeros((3, 1), dtype=np.intp), np.zeros((1, 1), dtype=np.intp),
                 np.zeros(2, dtype=np.intp), np.zeros((2, 0), dtype=np.intp)):  # fmt: skip
        with pytest.raises(ValueError, match="near must hold K >= 1 candidates"):
            closest_facing(p, y, near, 0.0)
