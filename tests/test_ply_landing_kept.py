"""A ply contact's landing points are found once per state and history (elements/
ply_landing_kept.py): the loads, the energy, the tangent and the accepted history at one state
from one history share one landing (``ply_landing.landing``, compiled on the flat faces:
elements/ply_landing_kernels.py), whose answers are those found afresh at each ask; another
history, or the same one edited in place, is answered afresh."""

from __future__ import annotations

import dataclasses

import numpy as np

from elements import ply_landing_kept, ply_landing_kernels
from elements.ply_sides import TOUCHING
from tests.test_ply_landing import landing_plies


def counted(monkeypatch) -> list[int]:
    """The landing the keep asks for (``ply_landing_kernels.landing``: the compiled one on
    the flat faces, numpy's on the curved ones) counted: a list holding the number of its
    calls."""
    calls = [0]
    landing = ply_landing_kernels.landing

    def counting(*args, **kwargs):
        calls[0] += 1
        return landing(*args, **kwargs)

    monkeypatch.setattr(ply_landing_kernels, "landing", counting)
    return calls


def test_the_loads_energy_tangent_and_history_of_a_state_find_its_landing_once(monkeypatch):
    """Each of the four asks found it before; now the first alone, and each answer the same
    bits as with nothing kept."""
    block, state, history = landing_plies(0.05, "normal law")
    fresh = []
    for _ in range(2):  # with nothing kept at each ask: the answers found afresh
        block._landing_at = None
        force = block.internal_force(state, history)
        block._landing_at = None
        energy = block.strain_energy(state, history)
        block._landing_at = None
        blocks = block.tangent(state, history)[-1].blocks
        block._landing_at = None
        fresh.append((force, energy, blocks, block.update_history(state, history)))
    block._landing_at = None
    calls = counted(monkeypatch)
    force = block.internal_force(state, history)
    energy = block.strain_energy(state, history)
    blocks = block.tangent(state, history)[-1].blocks
    accepted = block.update_history(state, history)
    assert calls[0] == 1
    expected = fresh[0]
    for axis in range(2):
        assert force[axis].tobytes() == expected[0][axis].tobytes()
    assert energy == expected[1]
    assert blocks.tobytes() == expected[2].tobytes()
    assert accepted.anchor.tobytes() == expected[3].anchor.tobytes()
    assert accepted.dissipated == expected[3].dissipated


def test_another_history_or_one_edited_in_place_is_answered_afresh(monkeypatch):
    """The keep serves the history it was found from, unedited: a copy of it (another object,
    the same arrays' values) is asked again and answered the same, and so is the same history
    at another facing (another state); the history whose sides are
    made TOUCHING in place after a landing was found has none (its points touched at the
    accepted state: tests/test_ply_landing.py), not the kept one."""
    block, state, history = landing_plies(0.05, "normal law")
    facing = block._held(state, history)
    calls = counted(monkeypatch)
    block.internal_force(state, history)
    assert calls[0] == 1
    kept = block._landing_at
    assert kept[5] is not None
    copy = type(history)(
        history.triangle.copy(),
        history.anchor.copy(),
        history.slip,
        history.pressing,
        history.dissipated,
        history.sides,
    )
    block.internal_force(state, copy)
    assert calls[0] == 2
    assert np.array_equal(block._landing_at[5].rows, kept[5].rows)
    assert np.array_equal(block._landing_at[6].anchor, kept[6].anchor, equal_nan=True)
    again = dataclasses.replace(facing)  # another state's facing (the same values here)
    ply_landing_kept.kept_landing(block, state, copy, again)
    assert calls[0] == 3
    assert history.sides is not None
    history.sides.sides[:] = TOUCHING
    found, landed = ply_landing_kept.kept_landing(block, state, history, facing)
    assert found is None and landed is history
