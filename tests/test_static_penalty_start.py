"""Static's soft start of an increment with ply contacts (``Static(ply_penalty_start=share)``,
solvers/penalty_start.py; docs/theory.md §6.5, "The deck's last increment")."""

import numpy as np
import pytest
from bent_deck import bent_deck

from elements.ply_block import PlyContactBlock
from solvers import Static
from solvers.penalty_start import softened
from validation.cases import plies_deck_of_cards as deck


@pytest.mark.parametrize("bad", [0.0, 1.0, -0.1, float("nan"), "soft"])
def test_a_share_outside_zero_to_one_is_refused(bad):
    with pytest.raises(ValueError, match="ply_penalty_start"):
        Static(ply_penalty_start=bad)


def test_the_penalties_are_scaled_inside_and_restored_after_even_on_an_error():
    model = bent_deck(2, 4).compile()
    blocks = [part for part in model.interactions if isinstance(part, PlyContactBlock)]
    assert blocks
    for block in blocks:
        block.set_penalty(np.full(len(block.upper), 300.0))
    before = [(block.node_stiffness.copy(), block.stiffness.copy()) for block in blocks]
    with pytest.raises(RuntimeError), softened(model, 0.25) as soft:
        assert soft
        for block, (nodes, points) in zip(blocks, before):
            assert np.allclose(block.node_stiffness, 0.25 * nodes)
            assert np.allclose(block.stiffness, 0.25 * points)
        raise RuntimeError
    for block, (nodes, points) in zip(blocks, before):
        assert np.array_equal(block.node_stiffness, nodes)
        assert np.array_equal(block.stiffness, points)


def _bend(start):
    solver = Static(
        increments=deck.DECK_INCREMENTS,
        seek_stable=False,
        max_iterations=deck.DECK_ITERATIONS,
        curved_with_contact=deck.DECK_CURVED,
        ply_penalty_start=start,
        progress=False,
    )
    return solver.solve(bent_deck(2, 10))


def test_a_soft_start_bends_the_deck_in_fewer_iterations_to_the_same_equilibrium():
    # plies-deck-of-cards' deck of 2 plies on 10 cells in the case's 4 curved increments, the
    # automatic penalty. Measured: plain 9-8-8-43 Newton iterations and 68 more in an attempt
    # cut (137 tangents); started at 1e-3 of the penalty 10-9-8-20 (13 soft and 7 full in
    # the last), none cut (48). Since the Mindlin plies' fibre curvature is the deformed
    # fibre's (docs/theory.md §5.7) the plain bend takes 9-8-8-42 and 86 tangents in all
    # (111 on the code just before), the started one 10-9-6-20 (45). Bound: no cut, at most
    # 25 in any increment, at most 0.6 of the plain bend's tangents. The equilibria:
    # measured within 3.3e-10 mm; bound 1e-6 mm (Static's tolerance 1e-8 of the forces on a
    # 100 mm strip, as tests/test_static_curved_contact.py):
    # the second phase solves the full law, so only the path differs.
    plain, started = _bend(None), _bend(deck.DECK_PENALTY_START)
    assert started.info["iterations_cut"] == 0
    assert started.info["soft_start_iterations"] > 0
    assert max(started.info["iterations_per_increment"]) <= 25
    tangents = plain.info["evaluations"]["tangent"], started.info["evaluations"]["tangent"]
    assert tangents[1] <= 0.6 * tangents[0], tangents
    assert np.abs(started.positions - plain.positions).max() <= 1e-6
    assert np.abs(started.directors - plain.directors).max() <= 1e-8


def test_frictional_ply_contacts_keep_their_penalty():
    # their stick anchors and return mapping hold the penalty's history (module docstring)
    model = bent_deck(2, 4, friction=0.2).compile()
    blocks = [part for part in model.interactions if isinstance(part, PlyContactBlock)]
    assert blocks and all(block.friction > 0.0 for block in blocks)
    before = [block.node_stiffness.copy() for block in blocks]
    with softened(model, 0.25) as soft:
        assert not soft
        for block, nodes in zip(blocks, before):
            assert np.array_equal(block.node_stiffness, nodes)


def test_the_soft_phase_seeks_no_stable_branch_and_the_full_phase_does(monkeypatch):
    # The soft law's equilibrium is a way-point: its stability (an indefinite tangent where
    # the full law's is not) must not start mode searches or pushes, nor mark a kept saddle.
    import solvers.penalty_start as penalty_start

    real, seen = penalty_start.newton, []

    def recording(run, *args, **options):
        blocks = [part for part in run.model.interactions if isinstance(part, PlyContactBlock)]
        seen.append((run.solver.seek_stable, float(blocks[0].node_stiffness.max())))
        return real(run, *args, **options)

    monkeypatch.setattr(penalty_start, "newton", recording)
    solver = Static(increments=1, seek_stable=True, ply_penalty_start=1e-3, progress=False)
    solver.solve(bent_deck(2, 4))
    full = max(stiffness for _, stiffness in seen)
    assert {stiffness < full for _, stiffness in seen} == {True, False}  # both phases ran
    assert all(sought == (stiffness == full) for sought, stiffness in seen), seen
    assert solver.seek_stable is True
