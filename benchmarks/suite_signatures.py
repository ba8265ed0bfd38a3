"""The kernels numba's cache holds more than one build of, with the signatures that differ:
each build is a compilation of its own in a fresh checkout, and a helper built once per
constant its callers give it (numba's Literal[int] or Literal[bool] of a constant argument),
or once for a loop's uint64 index beside an int64 one, compiles again for nothing.

Reads the cache's index files (``*.nbi``: numba's pickled version, then (stamp, overloads))
of a folder: the NUMBA_CACHE_DIR a run of the suite used, or a checkout (its ``__pycache__``
folders). Nothing is compiled or imported but numba's types to unpickle the signatures.

Measured on the cache of a whole run of the suite (main 9864ff6, a fresh clone, a fresh
NUMBA_CACHE_DIR, ``python -m pytest`` with the coarse report): 107 builds, 11 of them a
kernel's second or later: the table law helpers ``_table_energy`` and ``_table_integral`` 4
each (Literal[int] 2, 3, 4 and int64: one build each since the index is given as int64,
elements/fibrous/packed_laws.py); fibrous ``cell_terms.corner_thickness`` 3 (its node index
int64 or uint64, ``nodal`` Literal[bool] True or False), ``cell_terms.wall_fold`` 2 (int64
or uint64), ``hessian_kernels._tension_level`` 2 (``edge`` Literal[int] 0 or 1); Mindlin
``kernels._base_vectors`` 2 (a writable and a read-only array).

After those helpers were given one set of argument types (``corner_thickness``'s ``nodal``
and ``_tension_level``'s edge passed as variables, not constants; the parallel loops' index
no longer reaching the helpers, elements/jit.py ``_Parallel``; the Mindlin tables and fields
given read-only positions and directors alike), the cache of one process running
tests/test_fibrous.py, test_mindlin.py, test_fibrous_hessian_kernels.py,
test_fibrous_tangent_kernels.py, test_threads.py and test_bias_extension.py
(``-m "not slow"``, numba on 2 threads, fresh NUMBA_CACHE_DIR): 73 builds, none a kernel's
second.

Run: python benchmarks/suite_signatures.py [FOLDER]
"""

from __future__ import annotations

import pickle
import sys
from pathlib import Path

import numba  # noqa: F401 - the signatures' types, to unpickle them


def builds(index: Path) -> list[tuple]:
    """The signatures of the builds in one index file."""
    with open(index, "rb") as handle:
        pickle.load(handle)  # numba's version
        _, overloads = pickle.loads(handle.read())
    return [key[0] for key in overloads]


def main() -> None:
    folder = Path(sys.argv[1] if len(sys.argv) > 1 else Path(__file__).resolve().parents[1])
    total = repeated = 0
    for index in sorted(folder.glob("**/*.nbi")):
        if ".venv" in index.parts:
            continue
        signatures = builds(index)
        total += len(signatures)
        if len(signatures) < 2:
            continue
        repeated += len(signatures) - 1
        name = index.name.split(".py")[0]
        print(f"{len(signatures)} builds  {name}")
        for position in range(len(signatures[0])):
            kinds = {str(signature[position]) for signature in signatures}
            if len(kinds) > 1:
                print(f"    argument {position}: {', '.join(sorted(kinds))}")
    print(f"{total} builds in all, {repeated} of them a kernel's second or later")


if __name__ == "__main__":
    main()
