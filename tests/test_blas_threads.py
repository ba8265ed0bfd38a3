"""A solve holds BLAS to one thread (its dense matrices are small and OpenBLAS's idle threads
spin on a busy machine) and gives the caller's threads back afterwards, also when it raises."""

import pytest
from threadpoolctl import ThreadpoolController, threadpool_info

from solvers import CentralDifference, DynamicRelaxation, Static
from solvers.blas_threads import one_blas_thread


def blas_threads() -> list[int]:
    return [lib["num_threads"] for lib in threadpool_info() if lib["user_api"] == "blas"]


@pytest.fixture
def two_blas_threads():
    """The caller's BLAS on two threads (whatever the machine or the test run set)."""
    controller = ThreadpoolController()
    if not controller.select(user_api="blas").lib_controllers:
        pytest.skip("no BLAS library loaded")
    with controller.limit(limits=2, user_api="blas"):
        yield


def test_inside_a_decorated_method_blas_has_one_thread_and_after_it_the_callers(two_blas_threads):
    seen = one_blas_thread(blas_threads)()
    assert seen and set(seen) == {1}
    assert set(blas_threads()) == {2}


def test_the_callers_threads_come_back_when_the_method_raises(two_blas_threads):
    @one_blas_thread
    def fails():
        raise RuntimeError("diverged")

    with pytest.raises(RuntimeError, match="diverged"):
        fails()
    assert set(blas_threads()) == {2}


class Seen(Exception):
    """Stops a solve where it builds its model, with the BLAS threads it saw."""


@pytest.mark.parametrize(
    "module, solver",
    [
        ("static", Static()),
        ("relaxation", DynamicRelaxation()),
        ("explicit", CentralDifference(duration=1.0)),
    ],
)
def test_every_solver_solves_on_one_blas_thread(module, solver, two_blas_threads, monkeypatch):
    def seen(*args):
        raise Seen(blas_threads())

    monkeypatch.setattr(f"solvers.{module}.compiled_model", seen)
    with pytest.raises(Seen) as stopped:
        solver.solve(object())
    assert set(stopped.value.args[0]) == {1}
    assert set(blas_threads()) == {2}
