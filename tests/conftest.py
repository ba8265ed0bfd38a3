"""Shared fixtures: small cable models whose answers are known in closed form; numba's kernels
on one thread, except in the tests marked ``parallel``; OpenBLAS on one thread; the coarse
validation report, run in the background beside the other tests from the session's start.
(numba's kernels are compiled once for all the session's processes, the report's included:
a process asking for a kernel that another compiles waits and loads its build,
femcore/compile_lock.py.)"""

import os
import sys
import tempfile
import uuid
from pathlib import Path

# Before numpy loads OpenBLAS (here, and in every subprocess the tests start, which inherit
# the environment): one BLAS thread. The test models' dense matrices are small (the static
# solvers' eigenvalue check takes a dense eigh up to 200 unknowns), and OpenBLAS's idle
# threads spin: with other processes busy on 2 cores an eigh of 200 unknowns took 700 ms on
# its default threads against 8.5 ms on one, and it runs once per increment of every static
# solve.
os.environ["OPENBLAS_NUM_THREADS"] = "1"

# Python's bytecode of the project's modules (and pytest's rewritten test modules) written
# beside them, in __pycache__ where numba's cache already lives, where the environment says
# not to (PYTHONDONTWRITEBYTECODE): else each of a run's processes (the xdist workers, the
# coarse report's jobs, the Dask workers, the tests' subprocesses: dozens) compiles the same
# sources again, 0.3-0.5 s of CPU each, and a worker's collection 8.7 against 4.0 s
# (benchmarks/suite_bytecode.py). Before the project's imports below; the subprocesses
# inherit it.
if os.environ.pop("PYTHONDONTWRITEBYTECODE", None) is not None:
    sys.dont_write_bytecode = False

import pytest  # noqa: E402
from coarse_report import CoarseReport  # noqa: E402
from run_once import run_once  # noqa: E402

from elements import kernels  # noqa: E402
from femcore import Mesh, jit  # noqa: E402
from validation import specimens  # noqa: E402

# The coarse report's folder, shared by the session's processes: chosen by the pytest process
# that the command started, handed to each pytest-xdist worker (pytest_configure_node).
_folder: dict[str, Path] = {}
_reports: list[CoarseReport] = []


def pytest_configure(config):
    worker = getattr(config, "workerinput", None)
    if worker is None:
        name = f"fibreshell-coarse-report-{uuid.uuid4().hex}"
        _folder["path"] = Path(tempfile.gettempdir()) / name
    else:
        # (an xdist run whose main process did not load this file: one folder per run)
        name = f"fibreshell-coarse-report-{worker['testrunuid']}"
        _folder["path"] = Path(
            worker.get("coarse_report_folder", Path(tempfile.gettempdir()) / name)
        )


@pytest.hookimpl(optionalhook=True)
def pytest_configure_node(node):
    """pytest-xdist, before it starts a worker: the folder of the session's one report."""
    node.workerinput["coarse_report_folder"] = str(_folder["path"])


def start_report() -> None:
    if not _reports:
        _reports.append(CoarseReport.start_once(_folder["path"]))


def uses_the_report(item) -> bool:
    return "coarse_report" in getattr(item, "fixturenames", ())


def waits(item) -> bool:
    """Whether ``item`` spends most of its time waiting for processes it started (marked
    ``waits``, or on the session's shared Dask cluster: a fit's rounds, a subprocess's start),
    leaving a core idle unless another process takes it."""
    return item.get_closest_marker("waits") is not None or uses_the_cluster(item)


def pytest_collection_modifyitems(session, config, items):
    """The order of a run: the tests that call no compiled kernel (marked ``no_kernels``:
    mypy) first, then those that wait for processes they start (``waits``), then the other
    tests marked ``slow``, and the tests that read the coarse report last (in the order
    collected otherwise, the same in every xdist worker; xdist's ``worksteal``, the
    ``--dist`` of pyproject.toml, hands each worker half of the tests in this order: the
    first worker takes these groups first, the other the fast tests of the second half and
    the report's readers, and a worker that runs out takes half of what the other has not
    started). At the start of a fresh checkout the report's jobs and the workers ask for the
    same kernels, and the processes waiting for one being compiled left a core idle; mypy
    needs none. A waiting test leaves its core to the report's jobs while they run (the
    README's Dask fit left one idle after the report had ended, benchmarks/suite_idle.py).
    A test waiting for the report holds up only the tests after it, and the two workers end
    together on short tests rather than one of them idle while the other runs a long one
    collected late (mypy's 29 s, the last test of a whole run, started when the other worker
    had 1 s of tests left)."""
    items.sort(
        key=lambda item: (
            uses_the_report(item),
            item.get_closest_marker("no_kernels") is None,
            not waits(item),
            item.get_closest_marker("slow") is None,
        )
    )


def pytest_collection_finish(session):
    """A session that checks the coarse report starts it at once, beside its other tests: its
    cases, minutes of CPU, take the cores those leave idle (a test waiting for a subprocess,
    a Dask cluster or another process's compilation) and its longest case starts first. Its
    processes and the tests' compile numba's kernels under the same locks
    (femcore/compile_lock.py), so a fresh checkout compiles each kernel once, in whichever
    process asks first. Under
    pytest-xdist each worker collects every test and runs its share: the first to ask starts
    the report, the others read the same run."""
    wanted = any(uses_the_report(item) for item in session.items)
    if wanted and not session.config.option.collectonly:
        start_report()


def pytest_sessionfinish(session):
    """Each process stops its shared cluster if one is left; the pytest process the command
    started (not an xdist worker, which may end while another still waits for the report)
    stops the report and removes its folder."""
    stop_the_cluster()
    if getattr(session.config, "workerinput", None) is None and "path" in _folder:
        (_reports[0] if _reports else CoarseReport(_folder["path"])).stop()


@pytest.fixture(scope="session")
def coarse_report() -> tuple[Path, dict]:
    """One coarse run of every case (the paper cases included), two cases at a time in two
    worker processes (--jobs 2), shared by the tests of tests/test_validation_cli.py,
    tests/test_hemisphere_forming.py, tests/test_hemisphere_plies.py and
    tests/test_static_stall.py (and by the xdist workers): the report folder and its
    results.json."""
    start_report()
    return _reports[0].result()


@pytest.fixture(scope="session")
def once_per_run():
    """``once_per_run(name, compute)``: ``compute(out)`` run by the first of the session's
    processes to ask and read back by the others, ``(out, result)`` (tests/run_once.py), in
    the folder the session's processes share (removed at its end): a module fixture that
    pytest-xdist's two workers would each set up when both run tests of its module."""
    return lambda name, compute: run_once(_folder["path"] / "once", name, compute)


@pytest.fixture
def box_chain() -> Mesh:
    """40 segments of 3 mm hanging from (0,0,0) and (96,0,0): down 12, across 96, up 12
    (unstretched length 120 mm). Far from the catenary it relaxes to."""
    return specimens.box_chain(40)


# The session's shared LocalCluster (``dask_scheduler``), stopped once this process has run
# the last test that asks for it in the session's order, found at the first teardown. A
# worker need not run its share in that order (xdist's worksteal hands a worker the tail of
# another's queue; a rerun repeats a test): a test that asks for the cluster after it stopped
# starts it again, and the session's end stops whatever is left.
_cluster: dict = {"stack": None, "address": None}


def uses_the_cluster(item) -> bool:
    return "dask_scheduler" in getattr(item, "fixturenames", ())


def stop_the_cluster() -> None:
    stack, _cluster["stack"], _cluster["address"] = _cluster["stack"], None, None
    if stack is not None:
        stack.close()


#: The shared cluster's worker processes: one. The pytest-xdist workers and the coarse report
#: already keep the cores busy, so a second Dask worker ran no task sooner; it cost its start
#: (importing the package, loading numba's kernels) and its idle ticks
#: (benchmarks/suite_processes.py prints the figures).
CLUSTER_WORKERS = 1


def start_the_cluster() -> str:
    """The shared LocalCluster's scheduler address, the cluster started if it is not
    running (fibreshell.cluster.dask_client, ``CLUSTER_WORKERS`` worker processes)."""
    if _cluster["stack"] is None:
        from contextlib import ExitStack

        from fibreshell.cluster import dask_client

        with ExitStack() as stack:
            client, _ = stack.enter_context(dask_client(workers=CLUSTER_WORKERS))
            _cluster["stack"] = stack.pop_all()
        _cluster["address"] = client.scheduler.address
    return _cluster["address"]


def pytest_runtest_teardown(item, nextitem):
    """The shared cluster stopped after the last test that uses it (``dask_scheduler``)."""
    if _cluster["stack"] is None:
        return
    if "last" not in _cluster:
        order = {test.nodeid: i for i, test in enumerate(item.session.items)}
        users = [order[test.nodeid] for test in item.session.items if uses_the_cluster(test)]
        _cluster["order"], _cluster["last"] = order, max(users, default=-1)
    if _cluster["order"].get(item.nodeid, -1) >= _cluster["last"]:
        stop_the_cluster()


@pytest.fixture
def dask_scheduler() -> str:
    """The address of one LocalCluster (fibreshell.cluster.dask_client, ``CLUSTER_WORKERS``
    worker processes) shared by the tests of what runs on a cluster, fits and sweeps, rather
    than how a cluster starts (tests/test_sweep.py starts its own): a LocalCluster of their
    own costs each fit 7 s of starting and warming its workers (a fit of 54 runs took 17 s on
    its own cluster, 9.5 s on this one, with the machine's load at 2).

    Stopped once the last test that uses it has run (``pytest_runtest_teardown``), not kept
    to the session's end: an idle LocalCluster of 2 workers takes about 5.7 s of CPU a minute
    (its event loops' ticks, heartbeats and memory monitors: 3.3 s in its workers, 2.5 s in
    the threads of the process that started it), minutes of an idle cluster in a whole run
    whose tests that use it run among the first (marked slow). benchmarks/suite_item_cpu.py
    prints the figures. Started again by a test that asks for it after that (a test another
    worker's queue handed on, a rerun); the session's end stops it."""
    return start_the_cluster()


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
    its size and the machine's load (femcore.jit would run these small models on one): these
    tests run each kernel's parallel build (its parts on threads of their own), the others its
    plain build (femcore/jit.py ``_Parallel``)."""
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
