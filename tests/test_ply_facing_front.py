"""The facing of a new state begun in one compiled call (elements/ply_facing_front.py: the
faces' directions, the points p and lower corners y, the points' direction toward their own ply
and the kept search lists' moves) gives the four chained calls' facing to the bit, and leaves
the block as they leave it.

Reference: the same block's facing with ``ply_facing_front.FUSED = False`` (``offset_normals``,
``face_points``, ``FacingSearch.near``'s own ``_moves`` and ``offset_toward``, each held to
the bit against numpy in tests/test_ply_kernels.py). The pass calls those kernels themselves in
the same order, so the comparison is exact (no tolerance): every array of the Facing, the kept
directions and faces, and the search lists after each state (their candidates, origins, moves
and epoch), on the two-ply hemisphere blank's passes (Mindlin: faces along the nodal normals;
fibrous: along the directors) over a sequence of bent states that keeps the lists, refreshes
them and starts a new epoch.
"""

import pickle

import numpy as np
import pytest

from elements import ply_facing_front, ply_projection, ply_search
from elements.ply_block import PlyContactBlock
from tests.test_ply_kernels import _bent


def _bits(value):
    """An array's shape, dtype and bytes (NaN equal to NaN, signed zeros told apart)."""
    if isinstance(value, np.ndarray):
        return value.shape, value.dtype.str, value.tobytes()
    return value


def _kept(block: PlyContactBlock) -> dict:
    """What of the block the facing leaves for the state's later calls: its kept directions
    (faces along the normals) and faces, and the search's lists."""
    lists = block.search._lists
    kept = {"faces": [_bits(a) for a in block._faces_at[2:]]}
    if block.along_normals:
        kept["directions"] = _bits(block._directions_at[1])
    kept["lists"] = [_bits(getattr(lists, k)) for k in vars(lists)]
    return kept


def _depths():
    """The blank's press, mm, and the upper ply's slide along x, mm, state by state: small
    moves (the lists kept), a slide of one ply over the other (points searched again), then
    a jump (a new epoch)."""
    return [(5.0 + 0.02 * k, 0.0) for k in range(4)] + [(5.1, 1.6), (5.1, 1.7), (20.0, 0.0)]


@pytest.mark.parametrize(
    ("kinematics", "faces"), [("mindlin", "normal"), ("fibrous", "normal"), ("fibrous", "director")]
)
def test_the_begun_facing_is_the_chained_calls_on_the_bent_two_ply_hemisphere(
    monkeypatch, kinematics, faces
):
    """Both passes of the two-ply [0/90] blank (8 cells) over ``_depths``' states, one copy of
    the blocks begun in one call, the other by the chained calls: the same Facing, kept faces,
    directions and lists to the bit at every state; the premises, the pass taken at every
    state, the lists' moves measured by it (kept lists), a refresh and a new epoch seen."""
    from validation.studies import hemisphere_plies_setup as setup

    monkeypatch.setattr(ply_projection, "COMPILED", True)
    _, model = setup.model(8, setup.LAYUPS["0/90"], kinematics, 20.0, faces=faces)
    compiled_model = model.compile()
    blocks = [b for b in compiled_model.interactions if isinstance(b, PlyContactBlock)]
    assert len(blocks) == 2 and all(b.along_normals == (faces == "normal") for b in blocks)
    fused, chained = pickle.loads(pickle.dumps(blocks)), pickle.loads(pickle.dumps(blocks))
    taken, measured = [], []
    original = ply_facing_front._front

    def front(*arguments):
        taken.append(1)
        measured.append(bool(arguments[12]))  # ``listed``: the kept lists' moves measured
        return original(*arguments)

    monkeypatch.setattr(ply_facing_front, "_front", front)
    searches = {"_renew": 0, "_refresh": 0}  # the fused blocks' new epochs and refreshes
    for name in searches:
        method = getattr(ply_search.FacingSearch, name)

        def counted(search, *arguments, name=name, method=method):
            searches[name] += any(search is one.search for one in fused)
            return method(search, *arguments)

        monkeypatch.setattr(ply_search.FacingSearch, name, counted)
    for depth, slide in _depths():
        state = _bent(compiled_model, 3, depth)
        state.positions[blocks[0].upper, 0] += slide
        for one, other in zip(fused, chained):
            monkeypatch.setattr(ply_facing_front, "FUSED", True)
            monkeypatch.setattr(ply_facing_front, "CHOSEN", False)  # (tested below)
            got = one.facing(state)
            monkeypatch.setattr(ply_facing_front, "FUSED", False)
            count = len(taken)
            want = other.facing(state)
            assert len(taken) == count  # (the chained calls alone)
            assert [
                k for k in vars(want) if _bits(getattr(got, k)) != _bits(getattr(want, k))
            ] == []
            assert _kept(one) == _kept(other)
    assert len(taken) == 2 * len(_depths())
    assert sum(measured) >= 2 * (len(_depths()) - 2)  # kept lists after the first state
    assert searches["_renew"] >= 4  # the first state's and the jump's, both passes
    assert searches["_refresh"] > 0  # some points searched again within an epoch


def test_a_state_that_is_not_finite_is_refused_as_before(monkeypatch):
    """A NaN position: the pass's facing raises the chained calls' ValueError (a diverged
    state), naming the cause."""
    from validation.studies import hemisphere_plies_setup as setup

    monkeypatch.setattr(ply_projection, "COMPILED", True)
    monkeypatch.setattr(ply_facing_front, "FUSED", True)
    _, model = setup.model(8, setup.LAYUPS["0/90"], "mindlin", 20.0)
    compiled_model = model.compile()
    block = next(b for b in compiled_model.interactions if isinstance(b, PlyContactBlock))
    state = _bent(compiled_model, 0, 5.0)
    block.facing(state)  # the lists kept
    state.positions[block.above[0, 0], 1] = np.nan
    with pytest.raises(ValueError, match="hold NaN or infinite values"):
        block.facing(state)


def _counted_choices(monkeypatch) -> list[bool]:
    """Each call of the pass that may make the choice (``_front_chosen``): whether it made it."""
    chosen: list[bool] = []
    original = ply_facing_front._front_chosen

    def counted(*arguments):
        answer = original(*arguments)
        chosen.append(bool(answer[2]))
        return answer

    monkeypatch.setattr(ply_facing_front, "_front_chosen", counted)
    return chosen


@pytest.mark.parametrize(
    ("kinematics", "faces"), [("mindlin", "normal"), ("fibrous", "normal"), ("fibrous", "director")]
)
def test_the_facing_chosen_in_the_front_call_is_the_chained_calls_on_the_bent_two_ply_hemisphere(
    monkeypatch, kinematics, faces
):
    """As above, the facing's choice made in the front's call where the kept lists serve
    (``CHOSEN``): the same Facing, kept faces, directions and lists to the bit at every
    state as the chained calls (``FUSED`` False); the choice made at the states whose lists
    the chained search kept as they were, and not at the refreshes and new epochs."""
    from validation.studies import hemisphere_plies_setup as setup

    monkeypatch.setattr(ply_projection, "COMPILED", True)
    _, model = setup.model(8, setup.LAYUPS["0/90"], kinematics, 20.0, faces=faces)
    compiled_model = model.compile()
    blocks = [b for b in compiled_model.interactions if isinstance(b, PlyContactBlock)]
    fused, chained = pickle.loads(pickle.dumps(blocks)), pickle.loads(pickle.dumps(blocks))
    chosen = _counted_choices(monkeypatch)
    searched = [False]  # the chained copy's searches at each state and pass
    for name in ("_renew", "_refresh"):
        method = getattr(ply_search.FacingSearch, name)

        def counted(search, *arguments, method=method):
            searched[-1] |= any(search is one.search for one in chained)
            return method(search, *arguments)

        monkeypatch.setattr(ply_search.FacingSearch, name, counted)
    for depth, slide in _depths():
        state = _bent(compiled_model, 3, depth)
        state.positions[blocks[0].upper, 0] += slide
        for one, other in zip(fused, chained):
            listed = one.search._lists is not None
            monkeypatch.setattr(ply_facing_front, "FUSED", True)
            monkeypatch.setattr(ply_facing_front, "CHOSEN", True)
            count = len(chosen)
            got = one.facing(state)
            assert len(chosen) == count + listed  # the pass tried wherever lists are kept
            monkeypatch.setattr(ply_facing_front, "FUSED", False)
            searched.append(False)
            want = other.facing(state)
            assert len(chosen) == count + listed  # (the chained calls alone)
            assert [
                k for k in vars(want) if _bits(getattr(got, k)) != _bits(getattr(want, k))
            ] == []
            assert _kept(one) == _kept(other)
            if listed:  # chosen exactly where the chained search kept the lists as they were
                assert chosen[-1] == (not searched[-1])
    assert sum(chosen) >= 2 * 3  # the small moves' states
    assert len(chosen) > sum(chosen)  # a refresh or a new epoch among them


def _moves_at(monkeypatch, block, state):
    """(M, drifts (P,)) the kept lists' moves at ``state``, as ``FacingSearch.near`` is handed
    them (the pass without the choice, on a copy of ``block``)."""
    copy = pickle.loads(pickle.dumps(block))
    handed = []
    original = ply_search.FacingSearch.near

    def near(search, p, y, moves=None):
        handed.append(moves)
        return original(search, p, y, moves)

    monkeypatch.setattr(ply_search.FacingSearch, "near", near)
    monkeypatch.setattr(ply_facing_front, "CHOSEN", False)
    copy.facing(state)
    monkeypatch.setattr(ply_search.FacingSearch, "near", original)
    monkeypatch.setattr(ply_facing_front, "CHOSEN", True)
    moved, _, drift = handed[0]
    return moved, drift.copy()


def _skins(moved: float, drift: np.ndarray) -> dict[str, float]:
    """Skins at the search's bounds: M = s EPOCH_SHARE exactly and one ulp of s below; the
    largest drift at 0.5 (1 - ROUNDING) s (the least s reaching it) and one ulp above."""
    epoch = moved / ply_search.EPOCH_SHARE  # (a power of two: exact)
    share = 0.5 * (1.0 - ply_search.ROUNDING)
    largest = float(drift.max())
    skin = largest / share
    while share * skin < largest:
        skin = np.nextafter(skin, np.inf)
    while share * np.nextafter(skin, 0.0) >= largest:
        skin = np.nextafter(skin, 0.0)
    return {
        "epoch": epoch,
        "epoch-below": np.nextafter(epoch, 0.0),
        "drift": skin,
        "drift-above": np.nextafter(skin, np.inf),
        "wide": 10.0 * max(epoch, skin),
    }


@pytest.mark.parametrize(
    ("at", "row"),
    [
        ("epoch", None),
        ("epoch-below", None),
        ("drift", 0),
        ("drift", -1),
        ("drift-above", 0),
        ("drift-above", -1),
        ("wide", None),
    ],
)
def test_the_choice_takes_the_kept_lists_up_to_the_search_s_own_bounds(monkeypatch, at, row):
    """The skin set so that the lists' moves at a state sit on ``FacingSearch.near``'s bounds
    (M <= s EPOCH_SHARE: the lists kept, else a new epoch; every drift < 0.5 (1 - ROUNDING)
    s: kept as they are, else some points searched again), exactly and one ulp off, the
    largest drift the first or the last point's (its list's origin moved 0.05 mm; EPOCH_SHARE
    0.5 there, so that M is within its bound): the pass makes the choice exactly where those
    tests, in numpy, keep the lists as they are, and the same Facing and lists to the bit as
    the chained calls; a point's NaN coordinate refused there as before."""
    from validation.studies import hemisphere_plies_setup as setup

    monkeypatch.setattr(ply_projection, "COMPILED", True)
    _, model = setup.model(8, setup.LAYUPS["0/90"], "mindlin", 20.0)
    compiled_model = model.compile()
    block = next(b for b in compiled_model.interactions if isinstance(b, PlyContactBlock))
    block.facing(_bent(compiled_model, 3, 5.0))  # the lists made
    if row is not None:
        monkeypatch.setattr(ply_search, "EPOCH_SHARE", 0.5)
        block.search._lists.origin[row, 0] += 0.05
    state = _bent(compiled_model, 4, 5.05)
    moved, drift = _moves_at(monkeypatch, block, state)
    assert 0.0 < moved and np.all(drift > 0.0)
    if row is not None:  # the point's drift the largest, alone
        assert np.flatnonzero(drift == drift.max()).tolist() == [len(drift) - 1 if row else 0]
    skin = _skins(moved, drift)[at]
    fused, chained = pickle.loads(pickle.dumps(block)), pickle.loads(pickle.dumps(block))
    fused.search.skin = chained.search.skin = skin
    chosen = _counted_choices(monkeypatch)
    got = fused.facing(state)
    monkeypatch.setattr(ply_facing_front, "FUSED", False)
    want = chained.facing(state)
    kept = moved <= ply_search.EPOCH_SHARE * skin and bool(
        np.all(drift < 0.5 * (1.0 - ply_search.ROUNDING) * skin)
    )
    assert chosen == [kept]
    if at != "epoch":  # (the premises: a new epoch, a refresh, or the lists kept)
        assert kept == (at in ("drift-above", "wide"))
    assert [k for k in vars(want) if _bits(getattr(got, k)) != _bits(getattr(want, k))] == []
    assert _kept(fused) == _kept(chained)
    monkeypatch.setattr(ply_facing_front, "FUSED", True)
    state.positions[block.above[0, 0], 1] = np.nan
    with pytest.raises(ValueError, match="hold NaN or infinite values"):
        fused.facing(state)
    assert chosen == [kept, False]
