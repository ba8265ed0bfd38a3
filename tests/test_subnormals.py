"""Subnormal numbers flushed to zero while an explicit run steps (elements/subnormals.py): on
inside the block and off after it, and a forming run from rest the same run with them
flushed."""

import numpy as np
import pytest

from elements import subnormals
from solvers import CentralDifference
from validation.cases import hemisphere_forming as case

pytestmark = pytest.mark.skipif(not subnormals.SUPPORTED, reason="no MXCSR on this processor")

TINY = 1e-310  # a subnormal double: below 2.2250738585072014e-308


def test_subnormals_are_flushed_inside_the_block_and_kept_after_it():
    with subnormals.flushed():
        inside = np.array([TINY]) * 1.0
        assert np.array([1e-300])[0] * 1e-300 == 0.0  # a product that would be subnormal
    after = np.array([TINY]) * 1.0
    assert inside[0] == 0.0
    assert after[0] == TINY


def test_a_block_inside_another_leaves_the_modes_on():
    with subnormals.flushed():
        with subnormals.flushed():
            pass
        assert (np.array([TINY]) * 1.0)[0] == 0.0
    assert (np.array([TINY]) * 1.0)[0] == TINY


def formed(flush: bool, monkeypatch):
    """The hemisphere case at 6 cells, the punch's stroke in 0.01 s: the last positions,
    directors and velocities, with subnormals flushed or not."""
    monkeypatch.setattr(subnormals, "ENABLED", flush)
    _, model = case.model(6, "fibrous")
    result = CentralDifference(duration=0.01, damping=case.DAMPING, progress=False).solve(model)
    frame = result.frames[-1]
    return frame.positions, frame.directors, result.tool_forces


def test_a_forming_run_with_subnormals_flushed_is_the_run_without(monkeypatch):
    """Flushing changes only the numbers below 2.2e-308 and those made of them alone: the
    run from rest ends with the same positions, directors and punch forces to 1e-12 of the
    largest (to the last bit on this coarse run, whose wave crosses the blank in a few
    steps; the 20k blank's first steps meet thousands of subnormal rates,
    benchmarks/hemisphere_forming.py)."""
    with_flush = formed(True, monkeypatch)
    without = formed(False, monkeypatch)
    for mine, reference in zip(with_flush, without):
        assert np.abs(mine - reference).max() <= 1e-12 * np.abs(reference).max()
    assert np.abs(without[2]).max() > 1.0  # the punch pressed the blank


@pytest.mark.parallel
def test_numbas_worker_threads_flush_inside_the_block_and_not_after_it():
    """A parallel loop's iterations, on every thread of numba's pool, read the FTZ and DAZ
    modes on inside the block and off after it."""
    import numba

    if numba.config.NUMBA_NUM_THREADS < 2:
        pytest.skip("numba's pool has one thread")

    @numba.njit(parallel=True)
    def modes(out):
        for i in numba.prange(out.shape[0]):
            out[i] = subnormals._read_register() & subnormals.FLAGS

    seen = np.zeros(64 * numba.config.NUMBA_NUM_THREADS, dtype=np.int64)
    with subnormals.flushed():
        modes(seen)
        assert (seen == subnormals.FLAGS).all()
    modes(seen)
    assert (seen == 0).all()
