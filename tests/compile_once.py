"""numba's compilations shared by the session's processes: a kernel cached on disk
(femcore/kernel_cache.py) missing from numba's cache is compiled by one process at a time,
under a file lock of its own, so that a process asking for it while another compiles it
waits and then loads the other's build from the cache instead of compiling it a second time.

In a fresh checkout the cache is empty, and pytest-xdist's workers run the tests of a module
side by side: both asked for the same kernels at the same time and compiled each of them, tens
of seconds of CPU per kernel (benchmarks/suite_compile.py prints the figures).

The lock is taken around numba's ``Dispatcher.compile`` (which looks in the disk cache before
compiling). A kernel compiled inside another's compilation (a callee typed with its caller)
takes its own lock inside its caller's: a process holds the locks of a chain of callers, and
waits only for a callee, so two processes cannot wait for each other (the calls form no cycle).
"""

import fcntl
import os
import tempfile
import threading
from contextlib import contextmanager
from pathlib import Path

_held: set[str] = set()  # the kernels whose locks this process holds (a recursive compile)
_guard = threading.RLock()


def lock_folder() -> Path:
    """The folder of the locks: beside numba's cache (``NUMBA_CACHE_DIR``), or in the
    system's temporary folder for the ``__pycache__`` of this checkout."""
    root = os.environ.get("NUMBA_CACHE_DIR") or tempfile.gettempdir()
    checkout = str(Path(__file__).resolve().parents[1]).strip("/").replace("/", "+")
    folder = Path(root) / f"numba-compile-locks-{checkout}"
    folder.mkdir(parents=True, exist_ok=True)
    return folder


@contextmanager
def compiling(key: str):
    """Hold the lock of kernel ``key`` (reentrant within this process)."""
    with _guard:
        if key in _held:
            yield
            return
        with open(lock_folder() / f"{key}.lock", "w") as lock:
            fcntl.flock(lock, fcntl.LOCK_EX)
            _held.add(key)
            try:
                yield
            finally:
                _held.discard(key)
                fcntl.flock(lock, fcntl.LOCK_UN)


def install() -> None:
    """Wrap numba's ``Dispatcher.compile`` (once per process) so that a kernel cached on disk
    is compiled by one process at a time."""
    try:
        from numba.core import dispatcher
        from numba.core.caching import NullCache
    except ImportError:  # no numba: the numpy kernels, nothing compiled
        return

    original = dispatcher.Dispatcher.compile
    if getattr(original, "compile_once", False):
        return

    def compile(self, sig):
        if isinstance(self._cache, NullCache):  # not cached on disk: nothing to share
            return original(self, sig)
        function = self.py_func
        with compiling(f"{function.__module__}.{function.__qualname__}"):
            return original(self, sig)

    compile.compile_once = True  # type: ignore[attr-defined]
    dispatcher.Dispatcher.compile = compile
