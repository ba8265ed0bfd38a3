"""The whole facing in two compiled calls (elements/ply_facing_whole.py ``whole_facing``,
taken by ``closest_facing`` with ``ply_projection.WHOLE``) gives the chained passes' Facing to
the bit.

Reference: ``closest_facing`` with ``WHOLE = False``: ``facing_choice``, ``edge_sides`` and
``outline_fade_at`` chained by Python (each held to the bit against its numpy reference in
tests/test_ply_facing_pass.py and tests/test_ply_kernels.py). The two calls run the same
loops (IEEE, no fastmath) and numpy's arctan2 between, so the comparison is exact (no
tolerance): on tests/test_ply_wedge.py's strips cut at both ends (points facing edges, cuts,
turned layers, the fade near the outline, with and without the KD-tree's edges and the
direction toward the points' ply) and on the two-ply hemisphere blank's bent states, both
passes, as the block calls it, on 1 and 2 numba threads.
"""

import numba
import numpy as np
import pytest

from elements import ply_block, ply_fade, ply_projection
from elements.ply_block import PlyContactBlock
from elements.ply_projection import Facing, closest_facing
from elements.ply_topology import FaceTopology
from tests.test_ply_kernels import _bent
from tests.test_ply_wedge import cut_strip


def _bits(value):
    """An array's shape, dtype and bytes (NaN equal to NaN, signed zeros told apart)."""
    if isinstance(value, np.ndarray):
        return value.shape, value.dtype.str, value.tobytes()
    return value


def _differ(got: Facing, want: Facing) -> list[str]:
    """The Facing's fields whose arrays differ in shape, dtype or any bit."""
    return [k for k in vars(want) if _bits(getattr(got, k)) != _bits(getattr(want, k))]


def _both(monkeypatch, call):
    """``call()``'s Facing through the chained passes, then through the two calls."""
    monkeypatch.setattr(ply_projection, "COMPILED", True)
    monkeypatch.setattr(ply_projection, "WHOLE", False)
    want = call()
    monkeypatch.setattr(ply_projection, "WHOLE", True)
    return call(), want


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("pairs", [ply_fade.EVERY_PAIR, 16], ids=["every-pair", "kd-tree"])
@pytest.mark.parametrize("turned", [True, False], ids=["toward", "no-toward"])
def test_the_whole_facing_is_the_chained_passes_on_cut_strips(monkeypatch, seed, pairs, turned):
    """300 points round a cut strip (outline everywhere), every triangle a candidate in a
    shuffled order, padded rows for a fifth, a layer turned away for a third, the outline's
    nearest edges measured every pair or by the KD-tree (``EVERY_PAIR`` 16): the same Facing
    to the bit; the premises, points facing edges and on cuts, faded and turned points, the
    fused call taken (fewer points than SMALL_LOOP, no Hessian)."""
    monkeypatch.setattr(ply_fade, "EVERY_PAIR", pairs)
    from elements import ply_facing_whole

    monkeypatch.setattr(ply_facing_whole, "EVERY_PAIR", pairs)
    rng = np.random.default_rng(seed)
    nodes, y, outline, cuts = cut_strip(rng, 0.3)
    topology = FaceTopology.of(nodes, outline)
    p = rng.uniform([-1.0, -1.2, -0.6], [5.0, 0.9, 0.6], (300, 3))
    near = np.argsort(rng.uniform(size=(len(p), len(y))), axis=1)
    near[::5, 3:] = near[::5, :1]  # padding as the kept lists (elements/ply_search.py)
    toward = np.tile([0.0, 0.0, 1.0], (len(p), 1))
    toward[::3] *= -1.0
    taken = []

    def call():
        return closest_facing(
            p, y, near, 0.0, outline, False, depth=0.4, toward=toward if turned else None,
            fade_distance=0.05, topology=topology, cuts=cuts,
        )  # fmt: skip

    from elements import ply_facing_whole as whole

    original = whole.whole_facing
    monkeypatch.setattr(whole, "whole_facing", lambda *a: taken.append(1) or original(*a))
    got, want = _both(monkeypatch, call)
    assert taken == [1]
    assert _differ(got, want) == []
    assert want.on_edge.any() and (want.fade < 1.0).any() and (want.fade_gradient != 0).any()
    assert want.touching.any() and not want.touching.all()
    held = (want.gap <= 0.0) & (want.fade == 0.0)  # touching but for the fade
    assert held.any() and not want.touching[held].any()


@pytest.mark.parametrize("threads", [1, 2])
@pytest.mark.parametrize("layup", ["0/90", "0/45"])
def test_the_whole_facing_is_the_chained_passes_on_the_bent_two_ply_hemisphere(
    monkeypatch, threads, layup
):
    """The two-ply fibrous hemisphere blank (validation/studies/hemisphere_plies_setup.py,
    8 cells) bent 0-35 mm and jittered, both passes as the block calls them: the same Facing
    to the bit on 1 and 2 numba threads; the premise, points facing edges and faded ones."""
    from validation.studies import hemisphere_plies_setup as setup

    if threads > numba.config.NUMBA_NUM_THREADS:
        pytest.skip("numba has one thread here")
    _, model = setup.model(8, setup.LAYUPS[layup], "fibrous", 20.0)
    compiled_model = model.compile()
    blocks = [b for b in compiled_model.interactions if isinstance(b, PlyContactBlock)]
    assert len(blocks) == 2
    edges = faded = 0
    previous = numba.get_num_threads()
    numba.set_num_threads(threads)
    try:
        for seed, depth in enumerate((0.0, 5.0, 20.0, 35.0)):
            state = _bent(compiled_model, seed, depth)
            for block in blocks:

                def call(block=block, state=state):
                    block._facing_at = None
                    return block.facing(state)

                got, want = _both(monkeypatch, call)
                assert _differ(got, want) == []
                edges += int(want.on_edge.sum())
                faded += int((want.fade < 1.0).sum())
    finally:
        numba.set_num_threads(previous)
    assert edges > 0 and faded > 0
    assert ply_block.closest_facing is closest_facing


def test_the_two_calls_are_built_once_for_read_only_and_writable_faces(monkeypatch):
    """The fan of tests/test_ply_wedge.py faced by its block with its kept (read-only) faces,
    then with fresh writable ones: each of the two compiled calls holds one build (a second
    would be the same machine code compiled again, tests/test_ply_kernel_signatures.py)."""
    from elements import ply_face_points
    from elements import ply_facing_whole as whole
    from femcore import jit
    from femcore.state import State
    from tests.test_ply_wedge import _fan

    if not jit.AVAILABLE:
        pytest.skip("numba is not installed")
    monkeypatch.setattr(ply_projection, "COMPILED", True)
    monkeypatch.setattr(ply_projection, "WHOLE", True)
    block, positions, directors, _ = _fan()
    zero = np.zeros_like(positions[0])
    state = State(positions[100], directors.copy(), zero, zero)
    block.facing(state)
    p, y = block._faces(state)
    assert not (p.flags.writeable or y.flags.writeable)
    state = State(positions[700], directors.copy(), zero, zero)
    x = state.positions
    fresh_p, fresh_y, _ = ply_face_points.face_points(
        x, block.offset_directions(state).copy(), block.above, block.upper_offset,
        block.shape, block.cells, block.corner_offset,
    )  # fmt: skip
    assert fresh_p.flags.writeable and fresh_y.flags.writeable
    block._faces_at = (x.copy(), state.directors.copy(), fresh_p, fresh_y)
    block._facing_at = None
    assert block.facing(state).touching.any()
    built = [
        len(kernel.signatures) for kernel in (whole._choice_compiled, whole._sides_fade_compiled)
    ]
    assert built == [1, 1]


@pytest.mark.parametrize("kept", [1, 16])
def test_each_face_takes_its_own_kept_inputs(monkeypatch, kept):
    """Two cut strips of other shapes faced in turn, A, B, A, B, by the two calls: each call
    gives its strip's chained Facing to the bit, so a face's kept inputs (its topology's,
    outline's and cuts' arrays, converted once, elements/ply_facing_whole.py) serve that face
    alone, both kept or (``_FACES_KEPT`` 1) each dropping the other's; and the faces kept stay
    at most ``_FACES_KEPT``."""
    from elements import ply_facing_whole as whole

    monkeypatch.setattr(whole, "_FACES", {})
    monkeypatch.setattr(whole, "_FACES_KEPT", kept)
    rng = np.random.default_rng(4)
    faces = []
    for share in (0.3, 0.6):
        nodes, y, outline, cuts = cut_strip(rng, share)
        topology = FaceTopology.of(nodes, outline)
        p = rng.uniform([-1.0, -1.2, -0.6], [5.0, 0.9, 0.6], (200, 3))
        near = np.argsort(rng.uniform(size=(len(p), len(y))), axis=1)
        faces.append((p, y, near, outline, topology, cuts))
    assert faces[0][1].shape != faces[1][1].shape or faces[0][4] is not faces[1][4]

    def call(face):
        p, y, near, outline, topology, cuts = face
        return closest_facing(
            p, y, near, 0.0, outline, False, depth=0.4, fade_distance=0.05,
            topology=topology, cuts=cuts,
        )  # fmt: skip

    wants = [_both(monkeypatch, lambda face=face: call(face))[1] for face in faces]
    for face, want in [*zip(faces, wants), *zip(faces, wants)]:
        assert _differ(call(face), want) == []
        assert len(whole._FACES) <= kept
    assert len(whole._FACES) == min(kept, 2)
