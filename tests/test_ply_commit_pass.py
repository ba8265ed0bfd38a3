"""The next step's ply loads made in the committed history's compiled pass
(elements/ply_commit_pass.py, ``LOADS_IN_PASS``) and served by ``PlyContactBlock.
internal_force`` are the numpy reference's loads.

Reference: the numpy path (``ply_projection.COMPILED = False``: ``ply_friction.
updated_history``, ``_pair_loads``, ``_end_loads``, ``ply_friction.friction_loads`` and their
``np.bincount`` sums), which no compiled code runs, stepped over the same states from its own
block. The pass runs the loads' and stick couples' own kernels on the same inputs, so the
loads agree to round-off of the sums' order at most: asserted within 1e-12 of the largest
force (moment) component (the compiled loads sum each node's terms in numpy's order, so they
are equal in practice; the tolerance is the brief's bound for a reduction reordered, not a
fit). The histories (anchors, slips, dissipation) are held to the numpy reference's bits by
tests/test_ply_kernels.py and test_ply_friction_pass.py; here they are compared too.

The models: the ply pair of tests/ply_pair.py (mu 0.3, the plain penalty), the upper ply
carried along x while it comes down onto the lower one's face, lands and slides, then goes
back up and leaves it (points landing, sliding, sticking at the turn, departing); and its
folded pair, a point carried along a valley's edge line (stuck there, then sliding: the stick
couple of a point facing an edge, which the pass makes too).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from elements import ply_commit_pass, ply_projection
from elements.ply_block import PlyContactBlock
from tests.ply_pair import folded_plies, moved_plies

GAP = 0.0213  # mm between the faces at the start
DOWN, ALONG = 0.1, 1.0  # mm: the way down (and back up), along x over the run
STEPS = 24


def _path(compiled) -> list:
    """The states of the carried ply: down DOWN over the first half of the steps, back up
    over the second, ALONG x over all of them but steps 9-14 (held along x there, pressed
    deeper: its points stick), the lower ply held."""
    state = compiled.initial_state()
    upper = np.unique(compiled.interactions[0].above)
    states = []
    for step in range(1, STEPS + 1):
        down = DOWN * min(step, STEPS - step) / (STEPS / 2)
        along = ALONG * (min(step, 8) + max(step - 14, 0)) / (STEPS - 6)
        positions = state.positions.copy()
        positions[upper] += [along, 0.0, -down]
        states.append(dataclasses.replace(state, positions=positions))
    return states


def _stepped(model, states_of, compiled: bool, monkeypatch) -> list:
    """(history, force, moment) of each ply block at each state, each committed from the
    last, then the loads from it (an explicit step's order), by the passes ``compiled``
    selects; with the compiled ones, the loads are asserted to be the kept ones."""
    monkeypatch.setattr(ply_projection, "COMPILED", compiled)
    compiled_model = model.compile()
    blocks = [b for b in compiled_model.interactions if isinstance(b, PlyContactBlock)]
    histories = [block.initial_history() for block in blocks]
    records = []
    for state in states_of(compiled_model):
        for i, block in enumerate(blocks):
            histories[i] = block.update_history(state, histories[i])
            if compiled:  # the premise: the loads served are the pass's
                assert (
                    ply_commit_pass.kept_loads(
                        block, histories[i], block._held(state, histories[i])
                    )
                    is not None
                )
            force, moment = block.internal_force(state, histories[i])
            records.append((histories[i], force, moment))
    return records


def _compare(fast: list, reference: list) -> None:
    for (history, force, moment), (history_ref, force_ref, moment_ref) in zip(fast, reference):
        for ours, theirs in ((force, force_ref), (moment, moment_ref)):
            scale = max(float(np.max(np.abs(theirs))), 1e-300)
            np.testing.assert_allclose(ours, theirs, rtol=0.0, atol=1e-12 * scale)
        np.testing.assert_array_equal(history.triangle, history_ref.triangle)
        np.testing.assert_array_equal(history.anchor, history_ref.anchor)
        np.testing.assert_array_equal(history.slip, history_ref.slip)
        assert history.dissipated == history_ref.dissipated


def test_a_ply_landing_sliding_and_leaving_gets_the_numpy_loads(monkeypatch):
    """The carried ply's 24 states: the pass's kept loads against numpy's (module
    docstring); the premises: points land (no anchor, then anchored), slide, stick and leave
    (anchored, then none), and the loads are not zero."""
    monkeypatch.setattr(ply_commit_pass, "LOADS_IN_PASS", True)
    model = moved_plies(GAP, 0.0, 0.0)
    fast = _stepped(model, _path, True, monkeypatch)
    reference = _stepped(model, _path, False, monkeypatch)
    _compare(fast, reference)
    anchored = np.array([record[0].triangle >= 0 for record in fast])
    assert np.any(~anchored[:-1] & anchored[1:]), "no point landed"
    assert np.any(anchored[:-1] & ~anchored[1:]), "no point left"
    slips = np.array([record[0].slip for record in fast])
    assert np.any(np.diff(slips, axis=0) > 0.0), "no point slid"
    assert np.any(anchored[1:] & anchored[:-1] & (np.diff(slips, axis=0) == 0.0)), "none stuck"
    assert max(float(np.max(np.abs(record[1]))) for record in fast) > 0.0


def _along_the_fold(compiled) -> list:
    """Six states of the folded pair's upper ply: carried 2 um along the valley's edge line
    and 1 um down a step (its point on the edge sticks, then slides)."""
    state = compiled.initial_state()
    upper = np.unique(compiled.interactions[0].above)
    states = []
    for step in range(1, 7):
        positions = state.positions.copy()
        positions[upper] += [0.0, 2e-3 * step, -1e-3 * step]
        states.append(dataclasses.replace(state, positions=positions))
    return states


@pytest.mark.filterwarnings("ignore:.*the plies start overlapping")
def test_a_point_stuck_on_an_edge_gets_its_couple_in_the_pass(monkeypatch):
    """The folded pair of tests/ply_pair.py (a valley 0.5 mm deep, the upper ply's point 0.02
    mm into the faces under its edge line, carried along it): the pass's kept loads, with
    the stick couple of the point facing the edge, against numpy's; the premise: the point
    faces the edge stuck, then sliding."""
    monkeypatch.setattr(ply_commit_pass, "LOADS_IN_PASS", True)

    def model():
        return folded_plies(-0.02, 0.0, 0.0, 0.5, unknown=False)

    fast = _stepped(model(), _along_the_fold, True, monkeypatch)
    reference = _stepped(model(), _along_the_fold, False, monkeypatch)
    _compare(fast, reference)
    compiled_model = model().compile()
    block = compiled_model.interactions[0]
    history = block.initial_history()
    seen = {"stuck": 0, "sliding": 0}
    for state in _along_the_fold(compiled_model):
        history = block.update_history(state, history)
        facing = block._held(state, history)
        sliding = block.friction_state(state, history, facing)
        seen["stuck"] += int(np.count_nonzero(sliding.stuck & facing.on_edge))
        seen["sliding"] += int(np.count_nonzero(sliding.sliding & facing.on_edge))
    assert seen["stuck"] > 0 and seen["sliding"] > 0, seen


def test_loads_kept_for_other_penalties_are_not_served(monkeypatch):
    """The penalties changed after the commit (``set_penalty``): the loads are made again at
    the new penalties (numpy's), not the kept ones."""
    monkeypatch.setattr(ply_commit_pass, "LOADS_IN_PASS", True)
    results = []
    for compiled in (True, False):
        monkeypatch.setattr(ply_projection, "COMPILED", compiled)
        compiled_model = moved_plies(GAP, 0.0, 0.0).compile()  # its own penalties
        block = compiled_model.interactions[0]
        history = block.initial_history()
        for state in _path(compiled_model)[:8]:
            history = block.update_history(state, history)
        block.set_penalty(2.0 * block.node_stiffness)
        if compiled:
            assert ply_commit_pass.kept_loads(block, history, block._held(state, history)) is None
        results.append(block.internal_force(state, history))
    for ours, theirs in zip(*results):
        assert np.max(np.abs(theirs)) > 0.0
        np.testing.assert_allclose(ours, theirs, rtol=0.0, atol=1e-12 * np.max(np.abs(theirs)))


@pytest.mark.parametrize("loads_in_pass", [True, False])
def test_the_kept_loads_are_fresh_arrays(monkeypatch, loads_in_pass):
    """Two asks at one state give equal loads, neither the other's array (a caller may add
    into what it is given), with the pass's loads or the loads' own call."""
    monkeypatch.setattr(ply_commit_pass, "LOADS_IN_PASS", loads_in_pass)
    monkeypatch.setattr(ply_projection, "COMPILED", True)
    compiled_model = moved_plies(GAP, 0.0, 0.0).compile()
    block = compiled_model.interactions[0]
    history = block.initial_history()
    for state in _path(compiled_model)[:8]:
        history = block.update_history(state, history)
    first, second = block.internal_force(state, history), block.internal_force(state, history)
    for a, b in zip(first, second):
        assert a is not b
        np.testing.assert_array_equal(a, b)
        a += 1.0
    np.testing.assert_array_equal(block.internal_force(state, history)[0], second[0])
