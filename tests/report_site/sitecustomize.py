"""Run by Python at the start of each of the coarse report's processes (its own and the
workers it spawns, which inherit its PYTHONPATH; tests/coarse_report.py puts this folder
first): numba's kernels compiled by one of the session's processes at a time, the report's
and the tests' alike (tests/compile_once.py), so that the report can start with the session
in a fresh checkout without compiling a kernel that a test is compiling beside it. Then the
interpreter's own sitecustomize, if it has one (this one hides it)."""

import importlib.util
import sys
from pathlib import Path

_here = Path(__file__).resolve().parent
_spec = importlib.util.spec_from_file_location("compile_once", _here.parent / "compile_once.py")
assert _spec is not None and _spec.loader is not None
compile_once = importlib.util.module_from_spec(_spec)
sys.modules["compile_once"] = compile_once
_spec.loader.exec_module(compile_once)
compile_once.install()

# The next sitecustomize on the path (Debian's, for one), as Python would have run it. Where
# there is none this module stays registered under the name: Python's import of it takes it
# back out of sys.modules once it has run ("Error in sitecustomize ... KeyError" otherwise,
# printed at the start of each of the report's processes).
_self = sys.modules.pop("sitecustomize")
_path = sys.path
try:
    sys.path = [p for p in _path if Path(p or ".").resolve() != _here]
    importlib.import_module("sitecustomize")
except ImportError:
    sys.modules["sitecustomize"] = _self
finally:
    sys.path = _path
