"""The friction's history pass in one compiled call (elements/ply_friction_pass.py, taken by
``ply_friction_kernels.updated_history`` with ``FUSED``) gives the three calls' history and
mappings to the bit.

Reference: ``updated_history`` with ``FUSED = False``: the return mapping's kernel, ``_moved``
and the mapping's kernel again, chained by Python (each held to the bit against numpy's
``ply_friction`` in tests/test_ply_kernels.py). The one call runs the same loops (IEEE, no
fastmath) and numpy sums the dissipation either way, so the comparison is exact (no
tolerance, signed zeros told apart): the two-ply Mindlin [0/90] hemisphere blank bent 5,
5.2 and 5.4 mm, both passes, both stick laws, a fresh mapping and a kept one served, the
reference's kernels on one thread and on all of numba's.
"""

import numpy as np
import pytest

from elements import ply_friction_kernels, ply_projection
from elements.ply_block import PlyContactBlock
from tests.test_ply_kernels import _bent
from tests.thread_runs import on_one_thread_and_on_all


def _bits(record) -> list:
    """Every field of a history or a Sliding as bytes (arrays: shape, dtype and bytes;
    floats: their repr; the history's sides: their own fields)."""
    out = []
    for name, value in vars(record).items():
        if hasattr(value, "__dataclass_fields__"):
            out += [(name, *item) for item in _bits(value)]
        elif isinstance(value, np.ndarray):
            out.append((name, value.shape, value.dtype.str, value.tobytes()))
        else:
            out.append((name, repr(value)))
    return out


@pytest.mark.parametrize("stick", ["penalty", "normal law"])
def test_the_fused_history_is_the_three_calls_to_the_bit(monkeypatch, stick):
    """Three committed states a block, the last committed twice from the same history (its
    kept mapping served, not made): each history and the mapping kept for the next loads the
    same to the bit through the one call as through the three (those on one thread and on
    all); the premises, stuck and sliding points, a kept mapping served."""
    from validation.studies import hemisphere_plies_setup as setup

    _, model = setup.model(8, setup.LAYUPS["0/90"], "mindlin", 20.0)
    compiled_model = model.compile()
    blocks = [b for b in compiled_model.interactions if isinstance(b, PlyContactBlock)]
    states = [_bent(compiled_model, 3, depth) for depth in (5.0, 5.2, 5.4)]
    monkeypatch.setattr(ply_projection, "COMPILED", True)
    seen = {"stuck": 0, "sliding": 0, "served": 0}

    def run(fused: bool) -> list:
        monkeypatch.setattr(ply_friction_kernels, "FUSED", fused)
        records = []
        for block in blocks:
            monkeypatch.setattr(block, "stick", stick)
            block._next_sliding = None
            history = block.initial_history()
            for state in (*states, states[-1]):
                kept = block._next_sliding
                served = kept is not None and kept[0] is history
                history = block.update_history(state, history)
                following = block._next_sliding[3]
                records.append(_bits(history) + _bits(following))
                if fused:
                    seen["stuck"] += int(following.stuck.sum())
                    seen["sliding"] += int(following.sliding.sum())
                    seen["served"] += int(served)
        return records

    want_one, want_all = on_one_thread_and_on_all(lambda: run(False))
    got = run(True)
    assert want_one == want_all
    assert got == want_one
    assert min(seen.values()) > 0, seen


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_the_pass_chooses_the_leaving_rows_and_their_flags_as_numpy(seed):
    """``_leaving`` (the rows the pass's departure takes with ``select``) against
    ``ply_departure.leaving`` and ``beside_growth`` on 500 random points: anchored or not,
    touching then by each side (clear, touching, behind), touching now or not, points now
    finite or not in each coordinate, and every combination of the three edge flags; the same
    rows in the same order and the same flags, with the flags and without (none aside)."""
    from types import SimpleNamespace

    from elements import ply_departure
    from elements.ply_friction_pass import _leaving

    rng = np.random.default_rng(seed)
    count = 500
    triangle = rng.integers(-1, 5, count)
    sides = rng.integers(0, 3, count).astype(np.int8)
    touching = rng.uniform(size=count) < 0.3
    face = rng.normal(size=(count, 3))
    face[rng.uniform(size=(count, 3)) < 0.05] = np.nan
    face[rng.uniform(size=(count, 3)) < 0.02] = np.inf
    on_edge, on_growth, joined = (rng.uniform(size=(3, count)) < 0.5).astype(bool)
    facing = SimpleNamespace(
        touching=touching, face=face, on_edge=on_edge, on_growth=on_growth, joined=joined
    )
    history = SimpleNamespace(triangle=triangle, sides=SimpleNamespace(sides=sides))
    rows = ply_departure.leaving(SimpleNamespace(friction=0.3), history, facing)
    aside = ply_departure.beside_growth(facing, rows)
    assert 20 < len(rows) < count and 0 < aside.sum() < len(rows)
    for flagged in (True, False):
        got, got_aside, way = _leaving(
            triangle, touching, sides, face, flagged, on_edge, on_growth, joined
        )
        assert got.tolist() == rows.tolist()
        assert got_aside.tolist() == (aside if flagged else np.zeros(len(rows), bool)).tolist()
        assert way.shape == (len(rows),)
