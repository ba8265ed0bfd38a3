"""A module fixture's run made once per run of the suite, whichever of pytest-xdist's workers
asks first: the others wait for it and read its pickled result.

pytest-xdist's ``--dist load`` hands out a module's tests in chunks, so two workers may each
run some tests of one module, and each would set up the module's fixtures: a paired sweep of
tests/test_sweep.py on a LocalCluster of its own ran twice in a whole run of the suite (4.4
and 4.7 s of CPU in its Dask workers, benchmarks/suite_item_cpu.py)."""

import fcntl
import pickle
from collections.abc import Callable
from pathlib import Path
from typing import Any


def run_once(folder: Path, name: str, compute: Callable[[Path], Any]) -> tuple[Path, Any]:
    """``compute(out)``'s result, computed by the first process to ask in ``folder`` (under a
    file lock of ``name``'s) and pickled there, read back by the others: ``(out, result)``,
    ``out`` the folder ``folder / name`` that ``compute`` may write into, the same for every
    process.

    Parameters
    ----------
    folder : Path
        A folder every process of the run sees (tests/conftest.py: the coarse report's, chosen
        by the pytest process and removed at the session's end).
    name : str
        The run's name: its output folder, lock and pickle in ``folder``.
    compute : callable
        ``compute(out) -> result``, the result picklable.
    """
    folder.mkdir(parents=True, exist_ok=True)
    out, saved = folder / name, folder / f"{name}.pickle"
    with open(folder / f"{name}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if saved.exists():
            return out, pickle.loads(saved.read_bytes())
        out.mkdir(exist_ok=True)
        result = compute(out)
        partial = saved.with_suffix(".part")
        partial.write_bytes(pickle.dumps(result))
        partial.replace(saved)  # whole or absent
    return out, result
