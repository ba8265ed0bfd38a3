"""Modules of another revision of this repository imported beside this tree's: a benchmark
that holds a rewritten kernel to the numbers and the time of the code before it
(benchmarks/kernel_pairs.py, mindlin_kernel_pairs.py, curved_friction_pairs.py)."""

from __future__ import annotations

import importlib
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def revision_modules(ref: str, folder: Path, modules: dict[str, str]) -> tuple[str, str]:
    """The files ``modules`` (path in the repository: dotted name) of revision ``ref`` (those
    it has), written into a package ``other_<hash>`` in ``folder`` with their imports of one
    another pointed there, ``folder`` put on the import path: the package's name and the
    revision's short hash. Raises subprocess.CalledProcessError where git does not know
    ``ref`` (a checkout without that history)."""
    commit = subprocess.run(
        ["git", "-C", str(ROOT), "rev-parse", "--short", f"{ref}^{{commit}}"],
        check=True, capture_output=True, text=True,
    ).stdout.strip()  # fmt: skip
    package = f"other_{commit}"
    (folder / package).mkdir(exist_ok=True)
    _write(folder / package / "__init__.py", "")
    for path, name in modules.items():
        shown = subprocess.run(
            ["git", "-C", str(ROOT), "show", f"{ref}:{path}"], capture_output=True, text=True
        )
        if shown.returncode != 0:  # a module the revision does not have
            continue
        text = shown.stdout
        for other in modules.values():
            parent, module = other.rsplit(".", 1)
            text = text.replace(f"from {other} import", f"from {package}.{module} import")
            text = text.replace(
                f"from {parent} import {module} as", f"from {package} import {module} as"
            )
        _write(folder / package / f"{name.rsplit('.', 1)[1]}.py", text)
    if str(folder) not in sys.path:
        sys.path.insert(0, str(folder))
    importlib.invalidate_caches()
    return package, commit


def _write(path: Path, text: str) -> None:
    """``text`` into ``path`` unless it holds it already (a file kept from an earlier run: its
    numba builds beside it stay fresh), whole or not at all: another test process (pytest-xdist)
    may import the file meanwhile."""
    if path.exists() and path.read_text() == text:
        return
    partial = path.with_name(f"{path.name}.{os.getpid()}.partial")
    partial.write_text(text)
    os.replace(partial, path)
