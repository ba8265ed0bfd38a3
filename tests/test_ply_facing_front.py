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
