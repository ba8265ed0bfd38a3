"""Static's cap on the director turn of one Newton update (``Static(update_turn=...)``,
solvers.line_search.step_cap; docs/theory.md §6.5, "Updates of a turning stack")."""

import sys
from pathlib import Path

import numpy as np
import pytest

import solvers.line_search as line_search
from solvers import Static
from validation.cases import plies_deck_of_cards as deck

sys.path.insert(0, str(Path(__file__).parent))
from test_static_stall import _rollup  # noqa: E402


@pytest.mark.parametrize("bad", [0.0, -0.03, float("nan"), "0.03"])
def test_a_cap_that_is_not_a_positive_angle_is_refused(bad):
    with pytest.raises(ValueError, match="update_turn"):
        Static(update_turn=bad)


def _turns(monkeypatch, solver):
    """The solve of the rolled-up strip and the largest director turn of each update the line
    search takes (its scale times the Newton step), rad."""
    turns = []
    plain = line_search.Watchdog._take

    def take(self, state, frames, delta, scale):
        turns.append(scale * float(np.linalg.norm(delta[:, 3:], axis=1).max(initial=0.0)))
        return plain(self, state, frames, delta, scale)

    monkeypatch.setattr(line_search.Watchdog, "_take", take)
    return solver.solve(_rollup()), turns


def test_no_update_turns_a_director_by_more_than_the_cap(monkeypatch):
    # The strip rolled up by the end moment M = (pi / 4) E I / L in one increment: a pure
    # moment bends it to a circular arc whose tip turns by M L / (E I) = pi / 4 (the
    # elastica). The first Newton step is the linear one, turning the tip by pi / 4, which the
    # default cap (0.5 rad) shortens; with a cap of 0.1 rad no update turns more, so it takes
    # at least pi / 4 / 0.1 (7.9) of them, and lands on the same equilibrium within Static's
    # tolerance (1e-8 of the forces: 1e-6 of the size in positions, as
    # tests/test_static_first_turn.py).
    plain, plain_turns = _turns(monkeypatch, Static(increments=1, progress=False))
    capped, capped_turns = _turns(
        monkeypatch, Static(increments=1, update_turn=0.1, progress=False)
    )
    assert max(plain_turns) > 0.1
    assert max(capped_turns) <= 0.1 * (1.0 + 1e-12)
    assert capped.steps >= int(np.ceil(0.25 * np.pi / 0.1))
    scale = np.abs(plain.positions).max()
    assert np.abs(capped.positions - plain.positions).max() <= 1e-6 * scale
    # the directors start along +z: the largest turn is the tip's (10 cells: within 0.02 rad)
    turned = np.arccos(np.clip(capped.directors[:, 2], -1.0, 1.0)).max()
    assert turned == pytest.approx(0.25 * np.pi, abs=0.02)


@pytest.mark.slow
def test_the_heavy_stack_of_four_plies_sags_in_fewer_tangents():
    # plies-deck-of-cards' heavy stack of 4 plies (20 cells, gravity in 6 increments). With
    # the default cap: 98-120-32-33-16-15 Newton iterations and 30 cut, 345 tangents; with
    # 0.03 rad, 104-33-24-18-15-11 and none cut, 205 tangents, the same equilibrium to 4e-12
    # mm (measured, benchmarks/static_plies_newton.py --case sag --update-turn 0.03). Bound:
    # 250, about 20 % over 205 and well below 345; the states within 1e-6 mm (Static's
    # tolerance on a 140 mm strip).
    capped = deck.sag(4).result
    assert deck.SAG_UPDATE_TURN == 0.03
    try:
        deck.SAG_UPDATE_TURN = None
        plain = deck.sag(4).result
    finally:
        deck.SAG_UPDATE_TURN = 0.03
    tangents = {
        "plain": plain.info["evaluations"]["tangent"],
        "capped": capped.info["evaluations"]["tangent"],
    }
    assert tangents["capped"] <= 250 < tangents["plain"], tangents
    assert np.abs(capped.positions - plain.positions).max() <= 1e-6
