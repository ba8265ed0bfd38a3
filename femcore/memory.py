"""Up-front memory estimates: refuse a mesh or a model that cannot fit before allocating it.

A mesh of 1e9 triangles, or a model of 1e7, ends in a MemoryError after minutes of work (or
in the machine swapping); comparing a cheap estimate with the memory the machine has left
turns that into an immediate ValueError that gives the numbers.

The figures are peaks measured on fibre-aligned rectangles (temporaries included) and
rounded to the safe side of what was measured, so a mesh or a model that is refused would
certainly not have fitted with the work it is built for (a model: its explicit steps; its
build alone peaks lower, 0.8-0.95 kB per triangle at 400k):

- a mesh: about 200 bytes per triangle at generation (the grid, the split into triangles,
  the sets, the checks; ``tracemalloc`` at 800 to 7200 triangles);
- a model: about 1.4-2.0 kB per triangle above the interpreter's own memory, the process's
  peak through the build and a few explicit steps (resident memory, 100k and 400k
  triangles, benchmarks/model_memory.py: MindlinShell 1.37-1.50, FibrousShell 1.43-1.54,
  1.47 and 1.93-1.95 at 400k with the blocks' kept work arrays, benchmarks/
  step_workspace.py;
  small models carry more per cell, 7.7-8.5 kB by ``tracemalloc`` at 800-7200 triangles,
  but are never near the machine's limit);
- a static solve (the model, the sparse tangent and its factorisation; peak resident memory
  of one Static increment on 3200 to 20000 triangles): 39 kB per triangle for MindlinShell,
  128 kB for FibrousShell (its bending couples each node to its neighbours' neighbours).

``small_pages`` holds back numpy's advice of huge pages while a model is built: a build
touches each of its large arrays (tables and temporaries) once or twice, and the kernel
first gives each huge page zeroed, compacting memory for it when free memory is fragmented,
which cost a 400k-triangle Mindlin build 1.4-2.4 s of system time against 0.27-0.29 s with
ordinary pages (its own work 0.96-1.0 s; benchmarks/model_memory.py).
"""

from __future__ import annotations

import contextlib
import importlib
import os
import threading
from collections.abc import Iterator
from pathlib import Path
from typing import Any

__all__ = [
    "MESH_BYTES_PER_CELL",
    "MODEL_BYTES_PER_CELL",
    "STATIC_BYTES_PER_CELL",
    "available_memory",
    "check_memory",
    "check_mesh_memory",
    "check_model_memory",
    "small_pages",
]

MESH_BYTES_PER_CELL = 150
"""Bytes per cell of a mesh being built (measured about 200 per triangle; the lower figure
keeps the refusal certain)."""

MODEL_BYTES_PER_CELL = 1_200
"""Bytes per cell of a compiled model and its explicit steps (measured 1.37-1.95 kB per
triangle at 100k and 400k triangles; the lower figure keeps the refusal certain: the 6 kB
once used refused a 400k-triangle model on a machine with 2 GB free, which it fits in)."""

STATIC_BYTES_PER_CELL = 30_000
"""Bytes per cell of a static solve (measured 39-128 kB per triangle; the lower figure keeps
the refusal certain)."""

_GB = 1024.0**3


# Memory limit and usage of this process's control group (cgroup v2, then v1): a container
# may be allowed far less than the machine has.
CGROUP_FILES = (
    (Path("/sys/fs/cgroup/memory.max"), Path("/sys/fs/cgroup/memory.current")),
    (
        Path("/sys/fs/cgroup/memory/memory.limit_in_bytes"),
        Path("/sys/fs/cgroup/memory/memory.usage_in_bytes"),
    ),
)
MEMINFO = Path("/proc/meminfo")


def available_memory() -> int:
    """Memory the machine can still give this process, in bytes.

    ``MemAvailable`` of /proc/meminfo (free memory plus what the kernel can reclaim) where
    the system has it, else the physical memory (``SC_PHYS_PAGES * SC_PAGE_SIZE``), and no
    more than the control group's limit less its usage where a limit is set (a container);
    0 if nothing can be read (then no check refuses anything).

    Returns
    -------
    int
        Bytes.
    """
    machine = _meminfo_available()
    if machine is None:
        try:
            machine = int(os.sysconf("SC_PHYS_PAGES")) * int(os.sysconf("SC_PAGE_SIZE"))
        except (OSError, ValueError, AttributeError):
            machine = 0
    group = _cgroup_available()
    if group is not None and (machine == 0 or group < machine):
        return group
    return machine


def _meminfo_available() -> int | None:
    try:
        for line in MEMINFO.read_text().splitlines():
            if line.startswith("MemAvailable:"):
                return int(line.split()[1]) * 1024  # the file counts kB
    except (OSError, ValueError, IndexError):
        pass
    return None


def _cgroup_available() -> int | None:
    """The control group's limit less its usage (bytes), None without a limit."""
    for limit_file, usage_file in CGROUP_FILES:
        try:
            limit_text = limit_file.read_text().strip()
            usage = int(usage_file.read_text().strip())
        except (OSError, ValueError):
            continue
        # "max" (v2) or a huge number (v1, 2^63 rounded to pages) means no limit.
        if limit_text == "max" or not limit_text.isdigit() or int(limit_text) >= 2**60:
            return None
        return max(int(limit_text) - usage, 0)
    return None


def check_memory(n_bytes: float, what: str) -> None:
    """Refuse an allocation that cannot fit in the memory available.

    Parameters
    ----------
    n_bytes : float
        Estimated peak bytes of the allocation.
    what : str
        What would need them, for the message, e.g. "a mesh with 1800000000 triangles".

    Raises
    ------
    ValueError
        ``n_bytes`` exceeds :func:`available_memory`, giving both in GB.
    """
    available = available_memory()
    if available and n_bytes > available:
        raise ValueError(
            f"{what} would need about {n_bytes / _GB:.3g} GB; this machine has "
            f"{available / _GB:.3g} GB available: use fewer cells (or a machine with more "
            "memory)"
        )


def check_mesh_memory(
    n_cells: int, n_nodes: int = 0, what: str = "the mesh", noun: str = "cells"
) -> None:
    """Refuse a mesh of ``n_cells`` cells that could not be built in the memory available.

    Parameters
    ----------
    n_cells : int
        Number of cells (triangles and lines) the mesh would have.
    n_nodes : int
        Number of nodes (24 bytes each for the coordinates, counted on top).
    what : str
        How the message names the mesh, e.g. "Mesh.rectangle(1.0, 1.0, 30000, 30000)".
    noun : str
        What the cells are, e.g. "triangles".

    Raises
    ------
    ValueError
        The estimate (MESH_BYTES_PER_CELL per cell) exceeds the memory available.
    """
    estimate = float(n_cells) * MESH_BYTES_PER_CELL + 24.0 * float(n_nodes)
    check_memory(estimate, f"{what} with {n_cells} {noun}")


def check_model_memory(
    n_cells: int, per_cell: int = MODEL_BYTES_PER_CELL, what: str = "a model"
) -> None:
    """Refuse a model (or a run of it) of ``n_cells`` element cells that could not fit in
    memory.

    Parameters
    ----------
    n_cells : int
        Number of cells carrying an element, over all element blocks.
    per_cell : int
        Bytes per cell: MODEL_BYTES_PER_CELL for the compiled model, STATIC_BYTES_PER_CELL
        for a static solve.
    what : str
        What would need them, e.g. "a static solve".

    Raises
    ------
    ValueError
        The estimate (``per_cell`` per cell) exceeds the memory available.
    """
    check_memory(
        float(n_cells) * per_cell,
        f"{what} of {n_cells} element cells (about {per_cell} bytes each)",
    )


def _hugepage_switch():
    """numpy's setter of its huge-page advice (``numpy._core.multiarray`` from numpy 2, and
    1.26's shim; ``numpy.core.multiarray`` in 1.24-1.25), or None without one."""
    for module in ("numpy._core.multiarray", "numpy.core.multiarray"):
        try:
            return importlib.import_module(module)._set_madvise_hugepage
        except (ImportError, AttributeError):
            continue
    return None


# The advice is one setting of the whole process: the threads that build models at once (a
# Dask worker's) share one hold, and the last to leave gives the advice back.
_hold_lock = threading.Lock()
_hold: dict[str, Any] = {"depth": 0, "before": None}


@contextlib.contextmanager
def small_pages() -> Iterator[None]:
    """Within it, numpy does not advise the kernel to back its new large arrays (4 MB and
    more) by huge pages; numpy's setting before the first of the holds open at once (nested
    or in other threads) is restored when the last of them is left, on an error inside too
    (numpy's setter itself does not fail on a bool).

    Meant for one-off work that touches much fresh memory a few times (a model's build, a
    stable-step bound): there the first touch of a huge page, zeroed and often compacted for,
    costs more than the fewer address translations save. The values computed are the same
    to the bit (only where the memory lies changes). Without numpy's switch it does nothing.
    """
    switch = _hugepage_switch()
    if switch is None:  # nothing to hold back
        yield
        return
    with _hold_lock:
        if _hold["depth"] == 0:
            _hold["before"] = switch(False)
        _hold["depth"] += 1
    try:
        yield
    finally:
        with _hold_lock:
            _hold["depth"] -= 1
            if _hold["depth"] == 0:
                switch(_hold["before"])
