"""The threads of the compiled kernels (femcore/jit.py): a wait that does not spin, one
thread for small loops, the free cores at most, the same numbers on any thread count."""

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from elements import FibrousShell
from femcore import Mesh, Model, jit
from materials import Fabric

ROOT = Path(__file__).resolve().parents[1]

pytestmark = pytest.mark.skipif(not jit.AVAILABLE, reason="numba is not installed")


def test_a_small_loop_runs_on_one_thread_and_a_large_one_on_at_most_the_free_cores():
    import numba

    before = numba.get_num_threads()
    try:
        numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
        assert jit.threads_for(jit.SMALL_LOOP - 1) == 1
        large = jit.threads_for(jit.SMALL_LOOP)
        assert 1 <= large <= min(jit.free_cores(), numba.config.NUMBA_NUM_THREADS)
        assert 1 <= jit.free_cores() <= len(os.sched_getaffinity(0))
        numba.set_num_threads(1)  # the caller's cap holds
        assert jit.threads_for(10 * jit.SMALL_LOOP) == 1
    finally:
        numba.set_num_threads(before)


@pytest.mark.parametrize(
    "load, own, free",
    [
        (1.0, 1.0, 2),  # this process busy on one thread, nothing else: the second core is free
        (2.0, 1.0, 1),  # and one other busy process: it is not
        (1.0, 0.0, 1),  # another process busy, this one idle since the last look
        (2.0, 2.0, 2),  # this process on both cores, nothing else
        (5.0, 1.0, 1),  # a loaded machine
    ],
)
def test_the_free_cores_count_this_process_out_of_the_load(monkeypatch, load, own, free):
    """free_cores on two cores: the 1-minute load less this process's own CPU share since
    the last look (its CPU seconds over the wall seconds between the looks)."""
    monkeypatch.setattr(jit, "_allowed_cores", lambda: 2)
    monkeypatch.setattr(jit.os, "cpu_count", lambda: 2)
    monkeypatch.setattr(jit.os, "getloadavg", lambda: (load, load, load))
    monkeypatch.setattr(jit.time, "monotonic", lambda: 100.0)
    monkeypatch.setattr(jit.time, "process_time", lambda: 50.0)
    monkeypatch.setattr(jit._Load, "wall", 100.0 - 4.0)  # the last look, 4 s ago
    monkeypatch.setattr(jit._Load, "cpu", 50.0 - 4.0 * own)
    monkeypatch.setattr(jit._Load, "free", 1)
    assert jit.free_cores() == free


def test_a_parallel_loop_leaves_the_callers_thread_setting_as_it_was():
    import numba

    before = numba.get_num_threads()
    try:
        numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
        sheet(4)  # loops of a few cells: run on one thread
        assert numba.get_num_threads() == numba.config.NUMBA_NUM_THREADS
    finally:
        numba.set_num_threads(before)


def sheet(cells: int) -> np.ndarray:
    """The fibrous forces and moments (n, 6) of a jittered, tilted sheet of 2 cells^2
    triangles."""
    mesh = Mesh.rectangle(100.0, 100.0, nx=cells, ny=cells)
    model = Model(mesh)
    model.add(FibrousShell(Fabric(thickness=1.0, areal_density=1e-9, tension=500.0, shear=0.5,
                                  bending=2.0)))  # fmt: skip
    compiled = model.compile()
    state = compiled.initial_state()
    rng = np.random.default_rng(4)
    state.positions = state.positions + rng.normal(scale=0.5, size=state.positions.shape)
    state.directors = state.directors + rng.normal(scale=0.2, size=state.directors.shape)
    state.directors /= np.linalg.norm(state.directors, axis=1)[:, None]
    return np.hstack(compiled.internal_force(state))


def test_the_forces_are_the_same_to_the_last_bit_on_one_thread_and_on_all():
    """The kernels sum in cell order whatever the threads: a loop on one thread and on all
    of numba's threads give the same forces to the last bit, so a run is reproducible
    whatever the load makes free_cores choose."""
    from tests.thread_runs import on_one_thread_and_on_all

    one, every = on_one_thread_and_on_all(lambda: sheet(12))
    np.testing.assert_array_equal(every, one)


@pytest.mark.slow
def test_numbas_threads_wait_passively_on_the_openmp_layer():
    """In a fresh process, after elements is imported and a loop has run on 2 threads: OpenMP
    with OMP_WAIT_POLICY=PASSIVE (its threads sleep between loops instead of spinning); a
    policy given in the environment is kept. Two subprocesses: 5-30 s."""
    script = (
        "import os, numba; import numpy as np; from femcore import jit;"
        "from elements import kernels;"
        "jit.SMALL_LOOP, jit.FOLLOW_LOAD = 0, False;"  # on 2 threads
        "kernels.NodeCorners(np.arange(6).reshape(2, 3), 6).sum(np.ones((2, 3, 3)));"
        "print(numba.threading_layer(), os.environ['OMP_WAIT_POLICY'])"
    )
    env = {
        k: v for k, v in os.environ.items() if k not in ("OMP_WAIT_POLICY", "NUMBA_THREADING_LAYER")
    }
    env["PYTHONPATH"], env["NUMBA_NUM_THREADS"] = str(ROOT), "2"
    out = subprocess.run([sys.executable, "-c", script], env=env, capture_output=True, text=True,
                         check=True, cwd=ROOT)  # fmt: skip
    assert out.stdout.split() == ["omp", "PASSIVE"]
    env["OMP_WAIT_POLICY"] = "ACTIVE"
    out = subprocess.run([sys.executable, "-c", script], env=env, capture_output=True, text=True,
                         check=True, cwd=ROOT)  # fmt: skip
    assert out.stdout.split() == ["omp", "ACTIVE"]
