"""Modules of another revision of this repository imported beside this tree's: a test or a
benchmark that holds a rewritten kernel to the numbers of the code before it
(tests/test_mindlin_cell_terms.py, benchmarks/kernel_pairs.py,
benchmarks/mindlin_kernel_pairs.py)."""

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


def revision_for_tests(request, ref: str, modules: dict[str, str]) -> dict:
    """For a test fixture (``request`` pytest's): the modules ``modules`` of revision ``ref`` by
    their file names (without .py), kept in pytest's cache folder so that numba's builds of
    them are kept beside them from run to run (the session's temporary folder without the
    cache); the test skipped where this checkout has no git history holding ``ref``."""
    import pytest

    cache = getattr(request.config, "cache", None)
    name = f"revision-{ref}"
    if cache is not None:
        folder = cache.mkdir(name)
    else:  # one folder a session: its package is imported once, whichever test asks first
        folder = request.getfixturevalue("tmp_path_factory").getbasetemp() / name
        folder.mkdir(exist_ok=True)
    try:
        package, _ = revision_modules(ref, Path(folder), modules)
    except (subprocess.CalledProcessError, FileNotFoundError):
        pytest.skip(f"this checkout has no git history holding {ref}")
    names = [dotted.rsplit(".", 1)[1] for dotted in modules.values()]
    return {name: importlib.import_module(f"{package}.{name}") for name in names}
