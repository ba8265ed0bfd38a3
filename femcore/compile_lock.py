"""numba's compilations of a kernel shared by the processes that ask for it at once: a kernel
missing from numba's disk cache is compiled by one process at a time, under a file lock beside
its cache index, so that a process asking for it while another compiles it waits, then loads
the other's build from the cache instead of compiling it a second time.

Two processes started together on an empty cache ask for the same kernels at about the same
moment: the validation report's worker processes (``python -m validation --jobs 2``), a test
session's pytest-xdist workers, a user's two runs. Each used to compile every kernel it did
not find saved yet: the default report's first run compiled 18 kernels in both its jobs, 18.5
of its 100.7 s of compiling; the coarse report's 10 kernels, 32.5 of 124.9 s, and none with
the lock, 92.1 s of compiling, its results the same (benchmarks/suite_signatures.py).

The lock (``locked``, applied by femcore/kernel_cache.py ``njit`` to every kernel of the
project) is taken around numba's ``Dispatcher.compile``, which looks in the disk cache before
compiling and saves the build after: whoever holds it either finds the build saved by the
previous holder or compiles and saves it. It is one lock per kernel (its cache index file,
``path``), over all of its signatures: numba's index of a function is one file that each save
reads, extends and writes back, so two processes saving two signatures of one kernel at once
could each write the index without the other's entry.

Never a deadlock:

* a kernel compiled inside another's compilation (a helper typed with its caller) takes its
  own lock inside its caller's: a process holds the locks of a chain of callers and waits only
  for a callee, so two processes cannot wait for each other (that would need a cycle of calls);
  a kernel's own lock taken again inside its compilation (a recursive kernel) is not waited for;
* a process holds a lock only while it compiles, and the system releases a file lock when its
  holder ends, crashed or killed;
* a process waits ``WAIT_S`` seconds at most, then compiles without the lock (a holder stopped,
  a lock on a file system that never grants it): the lock only saves work, the builds are the
  same either way.

numba's own lock of the process (``global_compiler_lock``, which its ``compile`` takes) is
taken first, then the file lock: in that order in every thread, so that a thread compiling a
function of its own whose callee is a kernel here and a thread asking for a kernel here cannot
each hold the lock the other waits for. A kernel without a disk cache (numba's ``NullCache``)
or already built in this process is compiled, or returned, without any lock. Where the system
has no ``fcntl`` (Windows) or the lock file cannot be opened, numba compiles as it would alone.
"""

from __future__ import annotations

import os
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

try:
    import fcntl
except ImportError:  # pragma: no cover - Windows: numba compiles as it would alone
    fcntl = None  # type: ignore[assignment]

__all__ = ["LOCKING", "WAIT_S", "holding", "is_locked", "locked", "path"]

#: Whether the kernels' compilations take their locks (False: each process compiles what it
#: misses, as numba alone does; read at each compilation).
LOCKING = True
#: Seconds a process waits for another's compilation of a kernel before it compiles the
#: kernel itself. The longest compilation of one kernel, the fibrous force pass's, took 25.6 s
#: of CPU (load 6-11): on two cores shared by nine busy processes about two minutes.
WAIT_S = 300.0
# Seconds between two tries of a lock held by another process (doubling from the first).
_FIRST_TRY_S, _LAST_TRY_S = 0.005, 0.1

_held: set[str] = set()  # the lock files this process holds (a compilation within its own)


def path(dispatcher) -> Path | None:
    """The lock file of ``dispatcher``'s kernel (numba's dispatcher): its cache index's path
    with ``.lock`` for ``.nbi``, beside it, so that the processes sharing a cache share its
    locks; None where the kernel has no disk cache."""
    from numba.core.caching import NullCache

    cache = getattr(dispatcher, "_cache", None)
    if cache is None or isinstance(cache, NullCache):
        return None
    index = Path(cache._cache_file._index_path)
    return index.with_suffix(".lock")


@contextmanager
def holding(lock: Path, wait_s: float | None = None) -> Iterator[bool]:
    """Hold the file lock ``lock`` (created if missing) for the ``with`` block: whether it was
    taken (False: not within ``wait_s`` seconds, default ``WAIT_S``, or the file could not be
    opened or locked; the block runs all the same). Reentrant within this process."""
    key = str(lock)
    if key in _held or fcntl is None:
        yield key in _held
        return
    try:
        # Read-only: flock needs no write access, and a lock file another user made in a
        # shared cache (mode 0644) opens read-only where "a" would be refused.
        descriptor = os.open(lock, os.O_RDONLY | os.O_CREAT, 0o666)
    except OSError:
        yield False
        return
    with os.fdopen(descriptor, "rb") as handle:
        taken = _take(handle, WAIT_S if wait_s is None else wait_s)
        if taken:
            _held.add(key)
        try:
            yield taken
        finally:
            if taken:
                _held.discard(key)
                fcntl.flock(handle, fcntl.LOCK_UN)


def _take(handle, wait_s: float) -> bool:
    """Whether the exclusive lock of the open file ``handle`` was taken within ``wait_s``
    seconds (tried without blocking, at growing intervals: a blocking ``flock`` cannot be
    given a timeout)."""
    deadline = time.monotonic() + wait_s
    pause = _FIRST_TRY_S
    while True:
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
            return True
        except BlockingIOError:
            pass
        except OSError:  # a file system without locks
            return False
        left = deadline - time.monotonic()
        if left <= 0:
            return False
        time.sleep(min(pause, left))
        pause = min(2 * pause, _LAST_TRY_S)


def locked(dispatcher):
    """``dispatcher`` (numba's, cached on disk) whose ``compile`` takes the kernel's lock
    (``path``) around numba's: the same dispatcher, returned for chaining."""
    from numba.core import sigutils
    from numba.core.compiler_lock import global_compiler_lock

    original = dispatcher.compile

    def compile(sig) -> Any:
        with global_compiler_lock:
            if LOCKING:
                args, _ = sigutils.normalize_signature(sig)
                lock = None if tuple(args) in dispatcher.overloads else path(dispatcher)
                if lock is not None:
                    with holding(lock):
                        return original(sig)
            return original(sig)

    compile.locked = True  # type: ignore[attr-defined]
    # numba calls ``self.compile`` (at a call with new argument types, when a caller is typed
    # with it, and ``compile`` itself): the instance's attribute before the class's method
    dispatcher.compile = compile
    return dispatcher


def is_locked(dispatcher) -> bool:
    """Whether ``dispatcher``'s compilations take the kernel's lock (``locked``)."""
    return getattr(getattr(dispatcher, "compile", None), "locked", False)
