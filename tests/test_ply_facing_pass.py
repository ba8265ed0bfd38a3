"""The facing's planes, choice and chosen arrays in one compiled call
(elements/ply_facing_pass.py ``facing_choice``) give the three kernels' arrays to the bit.

Reference: ``ply_kernels.candidates_at``, ``ply_choice.choose_facing`` and
``ply_chosen.chosen`` called in turn (each held to the bit against its numpy reference in
tests/test_ply_kernels.py). The fused call runs the same loops (IEEE, no fastmath), so the
comparison is exact (no tolerance): on tests/test_ply_wedge.py's strips cut at both ends
(with and without their cuts, candidates shuffled and padded, a layer turned away for a
third of the points) and on the two-ply hemisphere blank's bent states, both passes, as
``closest_facing`` calls it.
"""

import numpy as np
import pytest

from elements import (
    ply_block,
    ply_choice,
    ply_chosen,
    ply_facing_front,
    ply_kernels,
    ply_projection,
)
from elements.ply_block import PlyContactBlock
from elements.ply_facing_pass import facing_choice
from elements.ply_projection import INSIDE, MARGIN
from tests.test_ply_kernels import _bent
from tests.test_ply_wedge import cut_strip


def _stages(p, y, near, outline, cuts, toward):
    """The three kernels in turn: (choice, picked) as ``facing_choice`` returns them."""
    planes = ply_kernels.candidates_at(p, y, near, outline, MARGIN, INSIDE)
    n, gradients, gap, weights, reach, inside, past = planes
    choice = ply_choice.choose_facing(p, y, near, *planes, cuts)
    picked = ply_chosen.chosen(choice[0], near, n, gap, weights, gradients, reach, toward)
    return choice, picked


def _differ(got, want) -> list[int]:
    """The positions in the flattened (choice, picked) where the arrays differ in shape,
    dtype or any bit (NaN equal to NaN, signed zeros told apart); None where both are."""
    flat_got = [*got[0], *got[1]]
    flat_want = [*want[0], *want[1]]
    assert len(flat_got) == len(flat_want) == 15
    wrong = []
    for position, (a, b) in enumerate(zip(flat_got, flat_want, strict=True)):
        if a is None or b is None:
            if not (a is None and b is None):
                wrong.append(position)
            continue
        same = a.shape == b.shape and a.dtype == b.dtype
        if same and a.dtype == float:
            same = np.array_equal(a.view(np.int64), b.view(np.int64))  # every bit
        elif same:
            same = np.array_equal(a, b)
        if not same:
            wrong.append(position)
    return wrong


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("with_cuts", [True, False], ids=["cut", "uncut"])
def test_the_fused_choice_is_the_three_kernels_on_cut_strips(seed, with_cuts):
    """400 points round a cut strip, every triangle a candidate in a shuffled order, padded
    rows for a fifth of them (the first candidate repeated), a layer turned away for a third:
    the same 15 arrays to the bit; the premises, points facing edges, cuts (where cut) and
    turned layers."""
    rng = np.random.default_rng(seed)
    _, y, outline, cuts = cut_strip(rng, 0.3)
    assert cuts.any
    p = rng.uniform([-1.0, -1.2, -0.6], [5.0, 0.9, 0.6], (400, 3))
    near = np.argsort(rng.uniform(size=(len(p), len(y))), axis=1)
    near[::5, 3:] = near[::5, :1]  # padding as the kept lists (elements/ply_search.py)
    toward = np.tile([0.0, 0.0, 1.0], (len(p), 1))
    toward[::3] *= -1.0
    given = cuts if with_cuts else None
    want = _stages(p, y, near, outline, given, toward)
    assert _differ(facing_choice(p, y, near, outline, MARGIN, INSIDE, given, toward), want) == []
    assert want[0][1].any() and want[1][8].any()
    assert (want[0][3].any() and want[0][5] is not None) if with_cuts else want[0][5] is None


def test_the_fused_choice_without_outline_or_toward_is_the_three_kernels():
    """No outline (no reach) and no direction toward the ply (nothing turned): the same bits."""
    rng = np.random.default_rng(5)
    _, y, _, _ = cut_strip(rng, 0.3)
    p = rng.uniform([-1.0, -1.2, -0.6], [5.0, 0.9, 0.6], (97, 3))
    near = rng.integers(0, len(y), (len(p), 4))
    want = _stages(p, y, near, None, None, None)
    assert _differ(facing_choice(p, y, near, None, MARGIN, INSIDE, None, None), want) == []
    assert not want[1][8].any() and not want[1][5].any()


def test_the_fused_choice_is_the_three_kernels_on_the_bent_two_ply_hemisphere(monkeypatch):
    """The two-ply fibrous [0/90] hemisphere blank (validation/studies/
    hemisphere_plies_setup.py, 8 cells) bent 0-20 mm and jittered, both passes: each call of
    ``closest_facing``'s arguments through the fused call and the three kernels, the same
    bits; the premise, the fused call taken (fewer points than SMALL_LOOP) and some points
    facing edges."""
    from validation.studies import hemisphere_plies_setup as setup

    _, model = setup.model(8, setup.LAYUPS["0/90"], "fibrous", 20.0)
    compiled_model = model.compile()
    blocks = [b for b in compiled_model.interactions if isinstance(b, PlyContactBlock)]
    assert len(blocks) == 2
    seen = []
    closest_facing = ply_block.closest_facing

    def recorded(p, y, near, tolerance, outline, second, **keywords):
        seen.append((p, y, near, outline, keywords["cuts"], keywords["toward"]))
        return closest_facing(p, y, near, tolerance, outline, second, **keywords)

    monkeypatch.setattr(ply_block, "closest_facing", recorded)
    monkeypatch.setattr(ply_projection, "COMPILED", True)
    # every facing through closest_facing (the choice not made in the front's call,
    # tests/test_ply_facing_front.py)
    monkeypatch.setattr(ply_facing_front, "CHOSEN", False)
    for seed, depth in enumerate((0.0, 5.0, 20.0)):
        state = _bent(compiled_model, seed, depth)
        for block in blocks:
            block._facing_at = None
            block.facing(state)
    assert len(seen) == 6
    edges = 0
    for p, y, near, outline, cuts, toward in seen:
        assert len(p) < ply_projection.SMALL_LOOP
        want = _stages(p, y, near, outline, cuts, toward)
        got = facing_choice(p, y, near, outline, MARGIN, INSIDE, cuts, toward)
        assert _differ(got, want) == []
        edges += int(want[0][1].sum())
    assert edges > 0
