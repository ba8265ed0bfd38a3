"""The CPU a run's processes spend compiling the project's Python sources where the
environment sets PYTHONDONTWRITEBYTECODE (each process compiles every module it imports)
against bytecode written once and read by the later processes (tests/conftest.py).

A fresh export of ``--ref`` (no __pycache__, as a clean checkout); the processes the suite
starts, each ``--rounds`` times in turns: the coarse report's command line (``python -m
validation --help``: its cases' modules), the fibreshell command (``--help``), a Dask
worker's imports (the package's runners and distributed), and an xdist worker's collection
(``pytest --collect-only -n 0``: the test modules rewritten by pytest). Each process's CPU is
its user + system time (resource, its children); the first process of the "written" side
writes the bytecode and is not counted (the session's first import). The machine's load is
printed: other jobs share the 2 cores.

Measured (HEAD with tests/conftest.py writing the bytecode, two rounds, load 10.6-11.6: 2
cores shared with other jobs): the report's command 2.30-2.41 -> 1.85-1.97 s, the fibreshell
command 1.22-1.23 -> 0.96 s, a Dask worker's imports 1.70-1.71 -> 1.43 s, a collection
9.04-9.11 -> 3.94-4.34 s. In a clean checkout the two xdist workers collect at the same time
(each compiles most of the test modules); the report's processes, the Dask workers and the
tests' subprocesses, which start later, read what the first process wrote.

The tests that start subprocesses (``-m "not slow"`` of test_checkpoint_fingerprint,
test_compile_lock, test_interrupts, test_kernel_cache, test_readme_examples, test_registry,
test_supernodal and test_threads: 110 tests, ``-n 0``, PYTHONDONTWRITEBYTECODE=1, one numba
thread), fresh exports of the conftest before (14e312d) and after, each on its own numba cache
filled by a first pass, then two passes in turns (user + system of pytest and its children,
load 4.6 -> 1.9): before 31.1 and 33.3 s, after 28.1 and 27.2 s.

Run: python benchmarks/suite_bytecode.py [--ref HEAD] [--rounds 3]
"""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

PROCESSES = {
    "report command": ["-m", "validation", "--help"],
    "fibreshell command": ["-m", "fibreshell", "--help"],
    "Dask worker imports": ["-c", "import fibreshell.run, fibreshell.sweep, distributed"],
    "collection": ["-m", "pytest", "--collect-only", "-q", "-n", "0", "-p", "no:cacheprovider"],
}


def cpu_of(arguments: list[str], tree: Path, write: bool) -> float:
    """User + system CPU (s) of ``python ARGUMENTS`` in ``tree``: bytecode written and read,
    or none there (the tree's .pyc files removed first: a process that may not write finds
    none, as in a clean checkout)."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    if not write:
        env["PYTHONDONTWRITEBYTECODE"] = "1"
        for path in tree.rglob("*.pyc"):
            path.unlink()
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run(
        [sys.executable, *arguments], cwd=tree, env=env, check=True, capture_output=True
    )  # fmt: skip
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--ref", default="HEAD")
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args()
    print(f"load before: {os.getloadavg()}")
    with tempfile.TemporaryDirectory() as scratch:
        archive = subprocess.run(
            ["git", "archive", args.ref], cwd=ROOT, capture_output=True, check=True
        )  # fmt: skip
        bare, written = Path(scratch) / "bare", Path(scratch) / "written"
        for tree in (bare, written):
            tree.mkdir()
            subprocess.run(["tar", "-x", "-C", str(tree)], input=archive.stdout, check=True)
        for name, arguments in PROCESSES.items():
            cpu_of(arguments, written, write=True)  # the first process: writes the bytecode
            compiled, read = [], []
            for _ in range(args.rounds):
                compiled.append(cpu_of(arguments, bare, write=False))
                read.append(cpu_of(arguments, written, write=True))
            print(
                f"{name:22s} each process compiling: {min(compiled):.2f}-{max(compiled):.2f} s"
                f", bytecode read: {min(read):.2f}-{max(read):.2f} s"
            )
    print(f"load after: {os.getloadavg()}")


if __name__ == "__main__":
    main()
