"""Shared fixtures: small cable models whose answers are known in closed form; numba's kernels
on one thread, except in the tests marked ``parallel``."""

import pytest

from elements import jit, kernels
from femcore import Mesh
from validation import specimens


@pytest.fixture
def box_chain() -> Mesh:
    """40 segments of 3 mm hanging from (0,0,0) and (96,0,0): down 12, across 96, up 12
    (unstretched length 120 mm). Far from the catenary it relaxes to."""
    return specimens.box_chain(40)


@pytest.fixture(scope="session", autouse=True)
def one_numba_thread():
    """The test models have tens of cells: a parallel loop over them costs more in starting
    and joining its threads than it saves, and on a loaded machine each of the thousands of
    steps waits for a second core to come free (an explicit run of 2 s took 80 s). The
    kernels give the same sums in the same order on any number of threads; the tests marked
    ``parallel`` compare them on all of numba's threads against the numpy reference."""
    if not kernels.AVAILABLE:
        yield
        return
    import numba

    before = numba.get_num_threads()
    numba.set_num_threads(1)
    yield
    numba.set_num_threads(before)


@pytest.fixture(autouse=True)
def all_numba_threads_if_parallel(request, one_numba_thread):
    """numba's default thread count for a test marked ``parallel``, on every loop whatever
    its size and the machine's load (elements.jit would run these small models on one)."""
    if not kernels.AVAILABLE or request.node.get_closest_marker("parallel") is None:
        yield
        return
    import numba

    small, follow = jit.SMALL_LOOP, jit.FOLLOW_LOAD
    numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
    jit.SMALL_LOOP, jit.FOLLOW_LOAD = 0, False
    yield
    jit.SMALL_LOOP, jit.FOLLOW_LOAD = small, follow
    numba.set_num_threads(1)
