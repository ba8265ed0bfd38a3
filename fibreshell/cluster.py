"""Independent runs as Dask distributed tasks: a client (a LocalCluster of worker processes on
this machine, or a remote scheduler) and a map over tasks with a progress bar that keeps every
task's failure as its own result instead of losing the others.

A task is a plain module-level function of picklable arguments; the workers import the
package (on a remote cluster it must be installed there, README "Sweeps on a cluster")."""

from __future__ import annotations

import logging
import os
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Any

from solvers.common import ProgressLine, resolve_progress

__all__ = ["Failure", "IDLE_CONFIG", "check_workers", "dask_client", "map_tasks", "set_threads"]

# Dask's defaults poll for an interactive dashboard's sake: the event loop's health every 20 ms,
# each worker's memory every 100 ms, work stealing every 100 ms, and each worker samples its
# threads for the profiler every 10 ms. An idle 2-worker LocalCluster then takes 4.5-5.3 s of
# CPU a minute (about 9 % of a core, felt on a laptop between a sweep's tasks); with these,
# 1.0 s (benchmarks/cluster_idle.py). A sweep's tasks last seconds to hours, so a second's
# latency in stealing or in the memory monitor changes nothing, and no dashboard reads the
# profiles. The nannies pass the config to their workers.
IDLE_CONFIG: dict[str, Any] = {
    "distributed.admin.tick.interval": "500ms",
    "distributed.worker.memory.monitor-interval": "1s",
    "distributed.scheduler.work-stealing-interval": "1s",
    "distributed.worker.profile.enabled": False,
}


@dataclass(frozen=True)
class Failure:
    """A task that raised (or whose worker died): the exception's type and message."""

    error: str


def check_workers(workers: int | None) -> None:
    """ValueError unless ``workers`` is None or a whole number >= 1."""
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int)
                                or workers < 1):  # fmt: skip
        raise ValueError(f"workers must be a whole number >= 1, got {workers!r}")


@contextmanager
def dask_client(
    scheduler: str | None = None, workers: int | None = None, timeout: float = 10.0
) -> Iterator[tuple[Any, int | None]]:
    """A Dask ``Client`` and the numba threads each task may use.

    Parameters
    ----------
    scheduler : str or None
        Address of a running scheduler (``tcp://host:8786``); None starts a LocalCluster here.
    workers : int or None
        Worker processes of the LocalCluster, one thread each (default: one per core); the
        cores are shared out, so each task's numba kernels get cores // workers threads. With
        a scheduler the workers are the cluster's and their threads its own (None).
    timeout : float
        Seconds to wait for the scheduler to answer.

    Raises
    ------
    ValueError
        ``workers`` not a whole number >= 1, both arguments given, or no scheduler answering
        at ``scheduler``.
    """
    import dask
    from distributed import Client, LocalCluster

    check_workers(workers)
    if scheduler is not None:
        if workers is not None:
            raise ValueError("give workers (a LocalCluster here) or a scheduler address, not both")
        try:
            client = Client(scheduler, timeout=f"{timeout}s")
        except (OSError, TimeoutError, ValueError) as error:
            raise ValueError(f"no Dask scheduler answers at {scheduler!r}: {error}") from None
        try:
            yield client, None
        finally:
            client.close()
        return
    cores = os.cpu_count() or 1
    count = workers or cores
    # Worker processes (not threads): the solvers hold the GIL between numba kernels, and
    # numba's thread pool must not be entered by two threads of one process at once.
    # Dask's nannies start their workers with MALLOC_TRIM_THRESHOLD_=65536, which also fixes
    # glibc's mmap threshold: every large numpy temporary is then mapped and unmapped, and
    # a solver runs 25-40 % slower than in this process (measured, benchmarks/sweep.py).
    # Without a dashboard the scheduler still serves HTTP (its health and metrics routes), by
    # default on port 8787, and warns when a second cluster finds it taken: bound here to a
    # free port on this machine only.
    config = IDLE_CONFIG | {"distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": None}
    with dask.config.set(config):
        try:
            cluster = LocalCluster(
                n_workers=count,
                threads_per_worker=1,
                processes=True,
                dashboard_address=None,
                scheduler_kwargs={"dashboard_address": "127.0.0.1:0"},
                silence_logs=logging.ERROR,
            )
        except RuntimeError as error:
            raise RuntimeError(
                f"the local Dask workers did not start ({error}). In a script, run the sweep "
                'under if __name__ == "__main__": (each worker is a new process that imports '
                "the script)"
            ) from error
    with cluster, Client(cluster) as client:
        yield client, max(1, cores // count)


def set_threads(threads: int | None) -> None:
    """In a task: at most ``threads`` numba threads (None: leave the worker's setting)."""
    if threads:
        import numba

        numba.set_num_threads(min(threads, numba.config.NUMBA_NUM_THREADS))  # type: ignore[attr-defined]


def map_tasks(
    client: Any,
    function: Callable[..., Any],
    arguments: Sequence[tuple],
    label: str,
    progress: bool | None = None,
    done: Callable[[int, Any], None] | None = None,
) -> list[Any]:
    """``function(*arguments[i])`` for every i as Dask tasks; their results in order, a task
    that raised (or whose worker died) as a ``Failure``.

    Parameters
    ----------
    client : distributed.Client
    function : callable
        Module-level (the workers import it).
    arguments : sequence of tuple
    label : str
        Progress line label.
    progress : bool or None
        The progress bar on stderr (None: ``solvers.common.resolve_progress``).
    done : callable(index, result) or None
        Called here as each task finishes (a result or a Failure), e.g. to write it at once.
    """
    from distributed import as_completed

    if not arguments:
        return []
    futures = [client.submit(function, *args, pure=False) for args in arguments]
    index = {future.key: i for i, future in enumerate(futures)}
    results: list[Any] = [None] * len(futures)
    failed = 0
    with ProgressLine(resolve_progress(progress), label) as line:
        for count, future in enumerate(as_completed(futures), 1):
            i = index[future.key]
            try:
                results[i] = future.result()
            except Exception as error:  # the task's own error, or the worker's death
                results[i] = Failure(f"{type(error).__name__}: {error}")
            failed += isinstance(results[i], Failure)
            if done is not None:
                done(i, results[i])
            line(f"{count}/{len(futures)} tasks, {failed} failed", fraction=count / len(futures))
    return results
