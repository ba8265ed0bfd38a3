"""The test suite's own setup (tests/conftest.py, tests/coarse_report.py): OpenBLAS on one
thread, and the background report: started once for all the session's processes, compiling
numba's kernels under the tests' locks, its failure reported, stopped with the session."""

import ctypes
import os
import signal
import subprocess
import sys
import time
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from coarse_report import CoarseReport


def openblas_threads() -> list[int]:
    """The thread count of each OpenBLAS library loaded in this process (numpy's, scipy's)."""
    with open("/proc/self/maps") as maps:
        libraries = {line.split()[-1] for line in maps if "openblas" in line and ".so" in line}
    counts = []
    for path in sorted(libraries):
        library = ctypes.CDLL(path)
        for symbol in ("scipy_openblas_get_num_threads64_", "scipy_openblas_get_num_threads",
                       "openblas_get_num_threads64_", "openblas_get_num_threads"):  # fmt: skip
            function = getattr(library, symbol, None)
            if function is not None:
                counts.append(function())
                break
    return counts


def test_the_tests_run_openblas_on_one_thread():
    np.linalg.eigh(np.eye(3))  # numpy's OpenBLAS loaded
    counts = openblas_threads()
    if not counts:
        pytest.skip("no OpenBLAS found in this process (another BLAS)")
    assert counts == [1] * len(counts)


# A stand-in for the report's command: writes results.json into the folder it is given last,
# after a pause that outlasts the test's second start (or fails, or never ends).
def stand_in(body: str) -> list[str]:
    code = (
        "import json, pathlib, sys, time\n"
        "out = pathlib.Path(sys.argv[-1])\n"
        "out.mkdir(parents=True)\n" + body
    )
    return [sys.executable, "-c", code]


WRITES = stand_in("time.sleep(0.5)\n(out / 'results.json').write_text(json.dumps({'runs': 1}))\n")


# Whether a kernel of the project compiles under its lock in a process, and that lock's file
# (femcore/compile_lock.py): in the report's process and in a worker it spawns.
LOCKED = (
    "[__import__('femcore.compile_lock', fromlist=['is_locked']).is_locked("
    "__import__('elements.kernels', fromlist=['_base_vectors'])._base_vectors),"
    " str(__import__('femcore.compile_lock', fromlist=['path']).path("
    "__import__('elements.kernels', fromlist=['_base_vectors'])._base_vectors))]"
)


def test_the_reports_processes_compile_under_the_tests_locks(tmp_path):
    # The report starts with the session, beside the tests compiling the kernels of a fresh
    # checkout: its processes, and the workers they spawn, must take the same per-kernel
    # locks (the same files) or each would compile a kernel that a test is compiling.
    body = (
        "import multiprocessing\n"
        f"main = eval({LOCKED!r})\n"
        "with multiprocessing.get_context('spawn').Pool(1) as pool:\n"
        f"    worker = pool.apply(eval, ({LOCKED!r},))\n"
        "(out / 'results.json').write_text(json.dumps([main, worker]))\n"
    )
    report = CoarseReport.start_once(tmp_path / "locks", stand_in(body))
    try:
        locked = eval(LOCKED)
        assert locked[0] is True
        assert report.result()[1] == [locked, locked]
    finally:
        report.stop()


def test_the_shared_cluster_stops_after_the_last_test_that_uses_it(monkeypatch):
    # tests/conftest.py's dask_scheduler: its LocalCluster idles at about 5.7 s of CPU a
    # minute, and its tests run among the first of a whole run (marked slow): kept to the
    # session's end it took minutes of CPU from the others. Stopped after the last test in
    # the session's order that uses it (each xdist worker runs its share in that order).
    import conftest

    closed: list[int] = []
    uses = [["dask_scheduler", "tmp_path"], [], ["overhangs", "dask_scheduler"], ["tmp_path"]]
    items = [SimpleNamespace(nodeid=f"t{i}", fixturenames=names) for i, names in enumerate(uses)]
    session = SimpleNamespace(items=items)
    for item in items:
        item.session = session
    monkeypatch.setattr(
        conftest, "_cluster", {"stack": SimpleNamespace(close=lambda: closed.append(1))}
    )
    for item, stopped in zip(items, [[], [], [1], [1]], strict=True):
        conftest.pytest_runtest_teardown(item, None)
        assert closed == stopped, item.nodeid
    assert conftest._cluster["stack"] is None


def test_a_test_that_asks_for_the_cluster_after_it_stopped_gets_a_running_one(monkeypatch):
    # A worker need not run its share in the session's order (xdist's worksteal hands it the
    # tail of another's queue; a rerun repeats a test): a test that asks for the shared
    # cluster after the teardown hook stopped it must not get the stopped one's address.
    from contextlib import contextmanager

    import conftest

    import fibreshell.cluster

    started: list[str] = []
    closed: list[str] = []

    @contextmanager
    def one_cluster(workers=None):
        # one worker process: the cores are the xdist workers' and the report's already
        assert workers == conftest.CLUSTER_WORKERS == 1
        address = f"tcp://127.0.0.1:{8800 + len(started)}"
        started.append(address)
        try:
            yield SimpleNamespace(scheduler=SimpleNamespace(address=address)), None
        finally:
            closed.append(address)

    monkeypatch.setattr(fibreshell.cluster, "dask_client", one_cluster)
    monkeypatch.setattr(conftest, "_cluster", {"stack": None, "address": None})
    first = conftest.start_the_cluster()
    assert conftest.start_the_cluster() == first and started == [first]  # shared while up
    conftest.stop_the_cluster()
    assert closed == [first]
    second = conftest.start_the_cluster()
    assert second != first and started == [first, second] and closed == [first]
    conftest.stop_the_cluster()
    assert closed == [first, second]


def test_the_report_starts_once_for_all_the_sessions_processes(tmp_path):
    # xdist: each worker asks for the report; the first starts it, the others read that run.
    folder = tmp_path / "report"
    first = CoarseReport.start_once(folder, WRITES)
    # another process (a second xdist worker) asking for it while it runs
    ask = (
        "import sys; sys.path.insert(0, sys.argv[1]); from coarse_report import CoarseReport\n"
        "fails = [sys.executable, '-c', 'raise SystemExit(3)']\n"
        "report = CoarseReport.start_once(sys.argv[2], fails)\n"
        "print(report.process is None, report.result()[1])\n"
    )
    other = subprocess.run([sys.executable, "-c", ask, str(Path(__file__).parent), str(folder)],
                           capture_output=True, text=True, check=True)  # fmt: skip
    assert other.stdout.split(maxsplit=1) == ["True", "{'runs': 1}\n"]
    assert first.process is not None
    again = CoarseReport.start_once(folder, stand_in("raise SystemExit(3)\n"))
    assert again.process is None and again.result() == first.result() == (first.out, {"runs": 1})
    first.stop()
    assert not folder.exists()


def test_a_run_shared_by_the_workers_is_computed_once_and_read_back_by_the_others(tmp_path):
    # tests/run_once.py: the first process to ask computes and pickles; the others (another
    # xdist worker) read the pickle and never compute, in the same output folder.
    from run_once import run_once

    calls = []

    def compute(out):
        calls.append(out)
        (out / "written").write_text("once")
        return {"rows": [1.0, 2.0]}

    out, first = run_once(tmp_path, "sweep", compute)
    assert calls == [out] and out == tmp_path / "sweep" and (out / "written").is_file()
    assert run_once(tmp_path, "sweep", compute) == (out, first) and len(calls) == 1
    ask = (
        "import sys; sys.path.insert(0, sys.argv[1]); from pathlib import Path\n"
        "from run_once import run_once\n"
        "def compute(out): raise SystemExit('computed twice')\n"
        "print(run_once(Path(sys.argv[2]), 'sweep', compute))\n"
    )
    other = subprocess.run([sys.executable, "-c", ask, str(Path(__file__).parent), str(tmp_path)],
                           capture_output=True, text=True, check=True)  # fmt: skip
    assert other.stdout == f"{(out, first)}\n"


def test_a_failed_or_killed_report_fails_its_tests_with_its_log(tmp_path):
    failed = CoarseReport.start_once(tmp_path / "a", stand_in("print('no mesh'); sys.exit(2)\n"))
    with pytest.raises(AssertionError, match="no mesh"):
        failed.result()
    killed = CoarseReport.start_once(tmp_path / "b", stand_in("time.sleep(60)\n"))
    os.killpg(killed.process.pid, signal.SIGKILL)
    with pytest.raises(AssertionError, match="stopped without its status"):
        killed.result()


def test_the_session_stops_a_report_still_running(tmp_path):
    report = CoarseReport.start_once(tmp_path / "c", stand_in("time.sleep(60)\n"))
    started = time.monotonic()
    report.stop()  # SIGTERM to its process group
    assert time.monotonic() - started < 10.0
    assert report.process.poll() is not None and not report.folder.exists()
    with pytest.raises(ProcessLookupError):
        os.killpg(report.process.pid, 0)


def test_the_slow_tests_run_first_and_those_that_read_the_report_last():
    # A test waiting for the report holds up only the tests after it in its process; a long
    # test collected late would leave the other xdist worker idle at the end. Before the other
    # slow tests: one that calls no kernel (mypy, while the first kernels compile), then those
    # that wait for processes they start (beside the report's jobs, which take the idle core).
    from conftest import pytest_collection_modifyitems

    def item(name, *fixtures, marks=()):
        def marker(mark):
            return SimpleNamespace(name=mark) if mark in marks else None

        return SimpleNamespace(name=name, fixturenames=fixtures, get_closest_marker=marker)

    items = [item("a", "coarse_report"), item("b"), item("c", "tmp_path", "coarse_report"),
             item("d", "tmp_path"), item("e", marks=["slow"]),
             item("f", "coarse_report", marks=["slow"]), item("g", marks=["slow"]),
             item("h", marks=["slow", "waits"]), item("i", "dask_scheduler", marks=["slow"]),
             item("j", marks=["waits"]), item("k", marks=["slow", "no_kernels"]),
             item("l", "coarse_report", marks=["waits"])]  # fmt: skip
    pytest_collection_modifyitems(None, None, items)
    assert [i.name for i in items] == ["k", "h", "i", "j", "e", "g", "b", "d", "l", "f", "a", "c"]


def test_the_configured_scheduler_ends_both_workers_together_after_a_long_first_run():
    """The session's order puts the slow tests first (above: the suite's 85, minutes of
    wall, the two-ply pace test's 108 s among them). xdist's ``load`` hands the first worker
    a run of a quarter of its share at the start (514 of 4118 tests, every slow one in it) and
    never takes back what it sent: the other worker, done with the rest, waited at the end.
    pyproject.toml's ``--dist``, replayed with xdist's own scheduler (tests/xdist_replay.py)
    on a session of that shape, 10 tests of 10 s first (100 s of 140), ends the two workers
    within the longest test of each other: no schedule can do better once that test has
    started last. (``load`` ends them 104.1 and 35.9 s in: the test fails there.)"""
    import tomllib

    from xdist_replay import ends, replay

    options = tomllib.loads((Path(__file__).parents[1] / "pyproject.toml").read_text())
    addopts = options["tool"]["pytest"]["ini_options"]["addopts"].split()
    dist = addopts[addopts.index("--dist") + 1] if "--dist" in addopts else "load"
    for durations in ([10.0] * 10 + [0.1] * 400, [0.1] * 400 + [10.0] * 10):
        end = ends(replay(dist, durations))
        assert sum(durations) / 2 <= max(end.values()) <= sum(durations) / 2 + max(durations)
        assert abs(end["gw0"] - end["gw1"]) <= max(durations), (dist, end)


def test_two_workers_asking_at_once_compute_the_run_once_and_both_read_it(tmp_path):
    # tests/run_once.py under a race: two processes ask at the same moment, the compute slow
    # enough (0.5 s) for the second to ask while the first computes; the lock makes the
    # second wait and read the pickle (without it both would compute: two lines in the log).
    ask = (
        "import sys, time; sys.path.insert(0, sys.argv[1]); from pathlib import Path\n"
        "from run_once import run_once\n"
        "def compute(out):\n"
        "    with open(Path(sys.argv[2]) / 'computes.log', 'a') as log: log.write('x\\n')\n"
        "    time.sleep(0.5)\n"
        "    return {'rows': [1.0, 2.0]}\n"
        "print(run_once(Path(sys.argv[2]) / 'shared', 'sweep', compute)[1])\n"
    )
    args = [sys.executable, "-c", ask, str(Path(__file__).parent), str(tmp_path)]
    both = [subprocess.Popen(args, stdout=subprocess.PIPE, text=True) for _ in range(2)]
    outputs = [process.communicate(timeout=60)[0] for process in both]
    assert [process.returncode for process in both] == [0, 0]
    assert outputs == ["{'rows': [1.0, 2.0]}\n"] * 2
    assert (tmp_path / "computes.log").read_text() == "x\n"


def test_the_sessions_processes_write_the_bytecode_of_what_they_import(tmp_path):
    """Python's bytecode written by the processes the session starts, whatever
    PYTHONDONTWRITEBYTECODE said (tests/conftest.py): a module a subprocess imports leaves
    its .pyc, which the next process reads instead of compiling the source again. (Fails on
    the conftest before where the environment sets it, as this machine's does.)"""
    assert "PYTHONDONTWRITEBYTECODE" not in os.environ
    (tmp_path / "probe_module.py").write_text("VALUE = 1\n")
    subprocess.run(
        [sys.executable, "-c", "import probe_module"], cwd=tmp_path, check=True, timeout=60
    )  # fmt: skip
    assert list((tmp_path / "__pycache__").glob("probe_module.*.pyc"))
