"""numba's disk cache of the project's kernels made to see the modules a kernel depends on.

numba serves a cached build of a function (``cache=True``) while the function's own file
has the text it had when the build was saved, and the function's bytecode is the same. What
the build took from other modules is not looked at: the value of a constant it reads
(numba freezes a global into the machine code), the code of a helper it calls (numba links
the helper's machine code into its caller's build) or splices (``inline="always"``). A
checkout updated by git, or a cache folder shared through ``NUMBA_CACHE_DIR``, then ran a
kernel built from modules that were no longer the ones imported: the node-update loop of the
explicit step walked chunks of 1024 nodes where the Python side had sized its output for
chunks of 2048, and the fibrous force kept its old tension law after ``level_lanes.py``
changed.

``njit`` here is numba's ``njit`` whose disk cache (``ProjectCache``) takes for the stamp of
a function's file that file's own stamp (numba's: the hash of its text) together with
``dependency_digest``, the hash of the text of every project module that the function's file
imports, followed through their own imports. A change in any of them is a change of stamp:
numba then finds the function's cached builds stale, compiles it again and saves the new
build in place of the old ones (no pile of stale builds beside the fresh one).

The digest is taken when the kernel is made, as numba takes the stamp of its file: when its
module is imported, right after the modules it imports (a kernel of femcore/jit.py, built at
its first call, takes the digest its wrapper took at import). Each file is read once per
process. A file edited while a process runs (a test session lasts minutes) thus leaves the
stamp of what the process imported, and the builds of the old code are not saved under the
new files' stamp, where the next process would take them for fresh.
"""

from __future__ import annotations

import hashlib
import re
from pathlib import Path
from typing import Any

from femcore import compile_lock

__all__ = ["ProjectCache", "dependency_digest", "dependency_files", "njit"]

# The folder that holds the project's packages (femcore, elements, materials, solvers, ...):
# a module whose dotted name names a file under it is the project's.
ROOT = Path(__file__).resolve().parents[1]
# The project's packages (pyproject.toml's packages.find): only their modules are followed,
# so that installed in site-packages, beside numpy and numba, the digest does not walk into
# them (952 files read at import against 55, and every upgrade of numpy a rebuild).
PACKAGES = frozenset({"femcore", "elements", "materials", "solvers", "validation", "fibreshell"})

# ``from a.b import c, d`` (the names possibly in parentheses over several lines) and
# ``import a.b, c as d``; at the start of a line, indented or not (imports inside functions
# count too). A line of a docstring that reads like an import only adds a file to the digest.
_FROM = re.compile(r"^[ \t]*from[ \t]+(\.*[\w.]*)[ \t]+import[ \t]+(\([^)]*\)|[^\n]*)", re.M)
_IMPORT = re.compile(r"^[ \t]*import[ \t]+([\w. \t,]+)", re.M)
_COMMENT = re.compile(r"#[^\n]*")


class _Read:
    """What this process has read of each file: its text's hash and the project files it
    imports (by absolute path)."""

    files: dict[Path, tuple[str, tuple[Path, ...]]] = {}
    closures: dict[Path, tuple[Path, ...]] = {}
    digests: dict[Path, str] = {}


def _module_file(name: str, folder: Path) -> Path | None:
    """The file of module ``name`` (dotted, under ``folder``): a.b -> folder/a/b.py or
    folder/a/b/__init__.py; None where there is neither."""
    if not name or (folder == ROOT and name.split(".")[0] not in PACKAGES):
        return None
    base = folder.joinpath(*name.split("."))
    for candidate in (base.with_name(base.name + ".py"), base / "__init__.py"):
        if candidate.is_file():
            return candidate
    return None


def _imports(path: Path, text: str) -> tuple[Path, ...]:
    """The project files that the module of ``path`` (text ``text``) imports: for ``from
    a.b import c``, the submodule a/b/c.py where there is one, else a/b.py (the name is
    defined there); for ``import a.b``, a/b.py."""
    found: list[Path] = []
    for origin, names in _FROM.findall(text):
        if origin.startswith("."):  # relative: each dot past the first one folder up
            level = len(origin) - len(origin.lstrip("."))
            folder = path.parent
            for _ in range(level - 1):
                folder = folder.parent
            module, base = origin.lstrip("."), folder
        else:
            module, base = origin, ROOT
        listed = _COMMENT.sub("", names).strip("() \t\n")
        own = False
        for entry in listed.split(","):
            name = entry.split(" as ")[0].strip()
            if not name:
                continue
            sub = _module_file(f"{module}.{name}" if module else name, base)
            if sub is not None:
                found.append(sub)
            else:
                own = True
        if own or not listed:
            target = _module_file(module, base) if module else base / "__init__.py"
            if target is not None and target.is_file():
                found.append(target)
    for listed in _IMPORT.findall(text):
        for entry in listed.split(","):
            target = _module_file(entry.split(" as ")[0].strip(), ROOT)
            if target is not None:
                found.append(target)
    return tuple(dict.fromkeys(found))


def _read(path: Path) -> tuple[str, tuple[Path, ...]]:
    """(hash of the text, project files imported) of ``path``, read once per process."""
    known = _Read.files.get(path)
    if known is None:
        try:
            data = path.read_bytes()
        except OSError:  # gone since its import: its absence is part of the digest
            known = ("missing", ())
        else:
            known = (
                hashlib.sha256(data).hexdigest(),
                _imports(path, data.decode("utf-8", "replace")),
            )
        _Read.files[path] = known
    return known


def dependency_files(path: str | Path) -> tuple[Path, ...]:
    """The file ``path`` and every project file it imports, directly or through the
    project files it imports (sorted, absolute paths)."""
    start = Path(path).resolve()
    closure = _Read.closures.get(start)
    if closure is None:
        seen = {start}
        waiting = [start]
        while waiting:
            for imported in _read(waiting.pop())[1]:
                if imported not in seen:
                    seen.add(imported)
                    waiting.append(imported)
        closure = tuple(sorted(seen))
        _Read.closures[start] = closure
    return closure


def dependency_digest(path: str | Path) -> str:
    """The hash (hex) of the texts of ``dependency_files(path)``, each under its path
    relative to the project's folder (a copy of the project elsewhere has the same digest)."""
    start = Path(path).resolve()
    digest = _Read.digests.get(start)
    if digest is None:
        hasher = hashlib.sha256()
        for file in dependency_files(start):
            try:
                name = str(file.relative_to(ROOT))
            except ValueError:  # a kernel outside the project (a user's, a test's)
                name = str(file)
            hasher.update(f"{name}\0{_read(file)[0]}\0".encode())
        digest = hasher.hexdigest()
        _Read.digests[start] = digest
    return digest


try:  # numba is a dependency; without it there is nothing to cache
    import numba
    from numba.core.caching import FunctionCache
    from numba.core.dispatcher import Dispatcher

    class ProjectCache(FunctionCache):
        """numba's disk cache of a function whose builds are stale when the function's file
        or any project module it depends on (``dependency_files``) has changed: the stamp of
        its index, numba's hash of the function's file, joined with ``digest`` (the
        ``dependency_digest`` of the file when the function was made: default, now)."""

        def __init__(self, py_func, digest: str | None = None):
            super().__init__(py_func)
            if digest is None:
                digest = dependency_digest(py_func.__code__.co_filename)
            index = self._cache_file
            index._source_stamp = (index._source_stamp, digest)

    AVAILABLE = True
except ImportError:  # pragma: no cover - numba is a dependency
    numba = None  # type: ignore[assignment]
    ProjectCache = None  # type: ignore[assignment,misc]
    AVAILABLE = False


def njit(function, digest: str | None = None, **options: Any):
    """numba's ``njit(**options)`` of ``function`` cached on disk by ``ProjectCache`` (stale
    when a project module the function's file imports changes) and compiled by one process at
    a time (``compile_lock.locked``: another process asking for it meanwhile waits and loads
    the build), ``digest`` the
    ``dependency_digest`` of the function's file taken when the function was made (default:
    now); ``function`` itself without numba."""
    if not AVAILABLE:
        return function
    dispatcher = numba.njit(cache=False, **options)(function)
    if not isinstance(dispatcher, Dispatcher):
        return dispatcher  # NUMBA_DISABLE_JIT=1: the plain function, nothing to cache
    dispatcher._cache = ProjectCache(dispatcher.py_func, digest)  # type: ignore[attr-defined]
    # compiled by one process at a time, the others loading its build (femcore/compile_lock.py)
    return compile_lock.locked(dispatcher)
