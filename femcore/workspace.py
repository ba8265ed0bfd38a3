"""Work arrays an element block keeps between the calls of its compiled passes.

A pass over the cells writes per-cell and per-node arrays that only the next pass reads (the
fibrous shell's corner forces, director moments and dW/dS_k, (m, 3, 3) each, its normals, areas,
angles, side folds and moments, the nodes' normal sums, frames and pulls; the Mindlin shell's
corner loads, (m, 3, 6), and energies). Made afresh at every call, arrays of tens of MB go back
to the system when freed (glibc maps an allocation above its mmap threshold, at most 32 MB, on
its own pages and trims the top of its heap past twice that), and the kernel hands their pages
over zeroed again at the next step's first touch: at 400k triangles thousands of page faults a
step, a third of the explicit step's time in the system (docs/theory.md §6.1, "Work arrays"). A
``Workspace`` keeps them: ``lease`` gives the arrays of the last call when their shape and type
are the same, new ones otherwise.

The kept arrays hold nothing a caller sees: a pass writes every entry before any is read,
and what a block returns is made afresh. So that two callers never share them:

* one lease at a time: a second ``lease`` while one is held (another thread, or a call
  inside the first) gets fresh arrays, as without a workspace;
* a pickled or deep-copied workspace is an empty one (its arrays are made again at the
  first call: a block sent to a worker or written to a checkpoint does not carry them);
  a shallow copy of its block (fold_branch.py's view of a block) shares it, the same cells.
"""

from __future__ import annotations

import contextlib
import threading
from collections.abc import Iterator

import numpy as np

__all__ = ["Fresh", "Workspace", "workspace_of"]


class Fresh:
    """Arrays made at each request: what a held workspace lends, and, set as a block's
    ``_workspace``, a block that keeps nothing (the reference of benchmarks/step_workspace.py)."""

    @contextlib.contextmanager
    def lease(self) -> Iterator[Fresh]:
        """Itself: every array of the call made afresh."""
        yield self

    @staticmethod
    def empty(name: str, shape: tuple[int, ...], dtype=np.float64) -> np.ndarray:
        """A new uninitialised array of ``shape`` and ``dtype`` (``name`` unused)."""
        return np.empty(shape, dtype=dtype)


class Workspace:
    """Named work arrays kept between calls, lent by ``lease`` to one caller at a time."""

    __slots__ = ("_arrays", "_lock")

    def __init__(self) -> None:
        self._arrays: dict[str, np.ndarray] = {}
        self._lock = threading.Lock()

    def __reduce__(self):
        """Pickled (and copied by ``copy.copy`` of itself) as a new, empty workspace."""
        return (type(self), ())

    def __deepcopy__(self, memo) -> Workspace:
        return type(self)()

    @property
    def nbytes(self) -> int:
        """Bytes held by the kept arrays."""
        return sum(array.nbytes for array in self._arrays.values())

    def clear(self) -> None:
        """Drop the kept arrays (they are made again at the next call)."""
        self._arrays = {}

    def empty(self, name: str, shape: tuple[int, ...], dtype=np.float64) -> np.ndarray:
        """The kept array ``name`` when it has ``shape`` and ``dtype``, else a new one
        (uninitialised, kept in its place). An array of no entries is made and not kept (a
        pass that leaves out a quantity keeps the array of the calls that form it). Only
        within ``lease``."""
        if 0 in shape:
            return np.empty(shape, dtype=dtype)
        array = self._arrays.get(name)
        if array is None or array.shape != tuple(shape) or array.dtype != np.dtype(dtype):
            self._arrays.pop(name, None)  # freed before the new one is made
            array = self._arrays[name] = np.empty(shape, dtype=dtype)
        return array

    @contextlib.contextmanager
    def lease(self) -> Iterator[Workspace | Fresh]:
        """This workspace while no other caller holds it, else ``Fresh``: an object whose
        ``empty(name, shape, dtype)`` gives the work arrays of one call."""
        if not self._lock.acquire(blocking=False):
            yield Fresh()
            return
        try:
            yield self
        finally:
            self._lock.release()


def workspace_of(block) -> Workspace | Fresh:
    """``block``'s workspace (its ``_workspace``), made at the first call on a block that
    has none (one built before, or without its ``__init__``)."""
    workspace = getattr(block, "_workspace", None)
    if workspace is None:
        workspace = block._workspace = Workspace()
    return workspace
