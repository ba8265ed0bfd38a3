"""numba's compilations of a kernel shared by the processes that ask for it at once
(femcore/compile_lock.py): one process compiles, the others wait and load its build; never a
deadlock (a timeout, a crashed holder's lock released, a kernel's own lock taken again within
its compilation); no lock for a kernel that numba does not cache on disk."""

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numba

from elements import kernels
from femcore import compile_lock

ROOT = Path(__file__).resolve().parents[1]

KERNEL = (
    "from femcore.kernel_cache import njit\n\n\n"
    "def twice(x):\n    return 2.0 * x\n\n\n"
    "twice = njit(twice)\n"
)
# A process that makes the kernel, says where its lock is, waits for the word, asks for the
# kernel and prints (compiled, loaded from the cache).
ASK = (
    "import sys; sys.path[:0] = sys.argv[1:3]\n"
    "import kernel\n"
    "from femcore import compile_lock\n"
    "print(compile_lock.path(kernel.twice), flush=True); sys.stdin.readline()\n"
    "assert kernel.twice(1.5) == 3.0\n"
    "print(sum(kernel.twice._cache_misses.values()), sum(kernel.twice._cache_hits.values()))\n"
)


def test_two_processes_asking_for_a_kernel_at_once_build_it_once(tmp_path, monkeypatch):
    # Both processes ask for the uncached kernel at the same moment, while its lock is held
    # (as while a third process compiles it): one compiles it, the other loads that build
    # from numba's cache. Without the lock each of them compiles it (the report's two jobs
    # compiled 18 kernels twice so, benchmarks/suite_signatures.py).
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path / "cache"))
    (tmp_path / "kernel.py").write_text(KERNEL)
    command = [sys.executable, "-c", ASK, str(tmp_path), str(ROOT)]
    asking = [
        subprocess.Popen(command, stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
        for _ in range(2)
    ]
    locks = {Path(process.stdout.readline().strip()) for process in asking}
    assert len(locks) == 1 and tmp_path / "cache" in next(iter(locks)).parents
    with compile_lock.holding(next(iter(locks))) as taken:
        assert taken
        for process in asking:
            process.stdin.write("go\n")
            process.stdin.flush()
        time.sleep(0.5)  # both at the lock
    counts = sorted(tuple(map(int, p.communicate(timeout=120)[0].split())) for p in asking)
    assert [p.returncode for p in asking] == [0, 0]
    assert counts == [(0, 1), (1, 0)]  # (compiled, loaded from the cache) in each process


def test_the_projects_kernels_compile_under_their_locks():
    # Every kernel of the project is made by femcore.kernel_cache.njit: a helper, the plain
    # and the parallel build of a loop (femcore/jit.py), in any process (the report's
    # workers too), beside its cache index.
    loop = kernels._node_sums
    for dispatcher in (kernels._base_vectors, loop.serial, loop.parallel):
        assert compile_lock.is_locked(dispatcher)
        lock = compile_lock.path(dispatcher)
        assert lock is not None and lock.name.startswith("kernels.")
        assert lock.with_suffix(".nbi") == Path(dispatcher._cache._cache_file._index_path)


def test_a_process_waits_at_most_wait_s_then_compiles_itself(tmp_path, monkeypatch):
    # A holder that never lets go (stopped, or a file system that never grants the lock):
    # the kernel is compiled all the same after WAIT_S.
    monkeypatch.syspath_prepend(str(tmp_path))
    (tmp_path / "waited.py").write_text(KERNEL)
    import waited

    monkeypatch.setattr(compile_lock, "WAIT_S", 0.4)
    lock = compile_lock.path(waited.twice)
    assert lock is not None
    holder = subprocess.Popen(
        [sys.executable, "-c", HOLD, str(lock), str(ROOT)], stdout=subprocess.PIPE, text=True
    )
    try:
        assert holder.stdout.readline() == "held\n"
        started = time.monotonic()
        assert waited.twice(2.0) == 4.0
        assert time.monotonic() - started >= 0.4
    finally:
        holder.kill()
        holder.wait()


# A process that takes a lock, says so and sleeps (until it is killed).
HOLD = (
    "import sys, time; sys.path.insert(0, sys.argv[2]); from pathlib import Path\n"
    "from femcore import compile_lock\n"
    "with compile_lock.holding(Path(sys.argv[1])) as taken:\n"
    "    print('held' if taken else 'not held', flush=True); time.sleep(600)\n"
)


def test_a_killed_holders_lock_is_free_at_once(tmp_path):
    lock = tmp_path / "kernel.lock"
    holder = subprocess.Popen(
        [sys.executable, "-c", HOLD, str(lock), str(ROOT)], stdout=subprocess.PIPE, text=True
    )
    assert holder.stdout.readline() == "held\n"
    with compile_lock.holding(lock, wait_s=0.0) as taken:
        assert not taken  # held by the other process
    os.kill(holder.pid, signal.SIGKILL)
    holder.wait()
    started = time.monotonic()
    with compile_lock.holding(lock, wait_s=30.0) as taken:
        assert taken
    assert time.monotonic() - started < 5.0


def test_a_lock_taken_again_within_its_holder_is_not_waited_for(tmp_path):
    # (a recursive kernel: its compilation asks for itself)
    lock = tmp_path / "kernel.lock"
    with compile_lock.holding(lock, wait_s=0.0) as outer:
        with compile_lock.holding(lock, wait_s=0.0) as inner:
            assert outer and inner
    with compile_lock.holding(lock, wait_s=0.0) as again:
        assert again  # released by the outer block


def test_a_kernel_without_a_disk_cache_takes_no_lock(monkeypatch):
    def tripled(x):
        return 3.0 * x

    dispatcher = compile_lock.locked(numba.njit(cache=False)(tripled))
    assert compile_lock.path(dispatcher) is None

    def refused(*args, **kwargs):
        raise AssertionError("a lock taken for a kernel numba does not cache")

    monkeypatch.setattr(compile_lock, "holding", refused)
    assert dispatcher(2.0) == 6.0


def test_a_kernel_built_in_this_process_takes_no_lock_again(tmp_path, monkeypatch):
    # numba asks ``compile`` again for a signature it has (a caller typed with its helper):
    # answered from the process's own builds, no file opened.
    monkeypatch.syspath_prepend(str(tmp_path))
    (tmp_path / "built.py").write_text(KERNEL)
    import built

    assert built.twice(1.0) == 2.0

    def refused(*args, **kwargs):
        raise AssertionError("a lock taken for a kernel built in this process")

    monkeypatch.setattr(compile_lock, "holding", refused)
    built.twice.compile((numba.float64,))
    assert built.twice(2.0) == 4.0


def test_the_lock_is_off_where_locking_is_false(tmp_path, monkeypatch):
    monkeypatch.syspath_prepend(str(tmp_path))
    (tmp_path / "unlocked.py").write_text(KERNEL)
    import unlocked

    def refused(*args, **kwargs):
        raise AssertionError("a lock taken with LOCKING False")

    monkeypatch.setattr(compile_lock, "holding", refused)
    monkeypatch.setattr(compile_lock, "LOCKING", False)
    assert unlocked.twice(1.0) == 2.0
