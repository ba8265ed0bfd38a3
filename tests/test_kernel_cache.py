"""numba's disk cache of the project's kernels (femcore/kernel_cache.py): a cached build is
stale when a project module the kernel's file imports has changed, not only the kernel's own
file; and the loops that sum a chunk of nodes at a time take the chunk size of the call
(femcore/jit.py ``chunk_size``), never one frozen into their build."""

import importlib
import os
import pkgutil
import shutil
import subprocess
import sys

import numpy as np
import pytest

from femcore import jit, kernel_cache

pytestmark = pytest.mark.skipif(not jit.AVAILABLE, reason="numba is not installed")

# The held angular rates of ``solvers.turning.rates`` (compiled: its kernel calls ``_held``,
# which calls femcore.rotation's ``frame_of``, whose constant FRAME_FALLBACK numba freezes
# into the machine code) against the same rates in numpy from femcore.rotation's
# ``nodal_frames``, which reads FRAME_FALLBACK at each call. Directors near e2: |e2 x V|
# between 0.1 and 0.57, so that FRAME_FALLBACK 0.1 and 0.9 give different frames.
PROBE = """
import numpy as np
import femcore
from femcore.rotation import nodal_frames
from solvers.turning import rates
n = 40
rng = np.random.default_rng(3)
v = np.column_stack([rng.uniform(-0.4, 0.4, n), np.ones(n), rng.uniform(-0.4, 0.4, n)])
v /= np.linalg.norm(v, axis=1)[:, None]
omega, moment = rng.normal(size=(n, 3)), rng.normal(size=(n, 3))
fixed = np.zeros((n, 2), bool)
fixed[:, 0] = True
free, held = rates(omega, moment, np.ones(n), np.ones(n, bool), fixed, v, 1.0, 0.0)
w = free - np.sum(free * v, axis=1)[:, None] * v
_, v2 = nodal_frames(v)
reference = w - np.sum(w * v2, axis=1)[:, None] * v2
print(femcore.__file__)
print(float(np.abs(held - reference).max()), float(np.abs(held).sum()))
"""


def _probe(copy, cache):
    """(femcore's file, largest |compiled - numpy|, sum |held|) of PROBE run in a fresh
    process on the packages of ``copy``, numba's cache in ``cache``."""
    env = {**os.environ, "PYTHONPATH": str(copy), "NUMBA_CACHE_DIR": str(cache)}
    env["NUMBA_NUM_THREADS"] = "1"
    out = subprocess.run(
        [sys.executable, "-c", PROBE], cwd=copy, env=env, capture_output=True, text=True
    )
    assert out.returncode == 0, out.stderr[-2000:]
    where, numbers = out.stdout.split("\n")[:2]
    difference, size = map(float, numbers.split())
    return where, difference, size


@pytest.mark.slow
def test_a_cached_kernel_is_built_again_when_a_constant_it_read_from_another_module_changes(
    tmp_path,
):
    """A copy of the packages with a cache folder of its own (``NUMBA_CACHE_DIR``): a first
    process builds and caches the kernels; FRAME_FALLBACK is then changed in
    femcore/rotation.py (solvers/turning.py, the kernels' file, unchanged), and a second
    process must run kernels built with the new value: its compiled rates are numpy's to
    1e-12 (numpy reads the constant at each call). numba alone served the first build, off
    by 2.3 there. (Two fresh processes: about 3 s of CPU.)"""
    copy = tmp_path / "checkout"
    for package in ("elements", "femcore", "materials", "solvers"):
        shutil.copytree(
            kernel_cache.ROOT / package,
            copy / package,
            ignore=shutil.ignore_patterns("__pycache__", "*.nbi", "*.nbc"),
        )
    cache = tmp_path / "cache"
    where, before, size_before = _probe(copy, cache)
    assert where.startswith(str(copy))  # the copy's packages, not the checkout's
    assert before <= 1e-12 * size_before
    assert any(cache.rglob("*.nbi"))  # the builds were cached in the copy's own folder
    rotation = copy / "femcore" / "rotation.py"
    text = rotation.read_text()
    assert "\nFRAME_FALLBACK = 0.1\n" in text
    rotation.write_text(text.replace("\nFRAME_FALLBACK = 0.1\n", "\nFRAME_FALLBACK = 0.9\n"))
    _, after, size_after = _probe(copy, cache)
    assert size_after != size_before  # the constant changes the held rates
    assert after <= 1e-12 * size_after


def test_the_files_a_kernel_depends_on_follow_its_module_s_imports():
    """The modules whose constants and helpers the kernels read, found through the imports
    of the kernels' files and of the files they import."""
    root = kernel_cache.ROOT

    def names(path):
        return {str(p.relative_to(root)) for p in kernel_cache.dependency_files(root / path)}

    fibrous = names("elements/fibrous/kernels.py")
    for module in ("level_lanes", "packed_laws", "cell_terms", "geometry_kernels", "kernels"):
        assert f"elements/fibrous/{module}.py" in fibrous
    assert {"elements/lane_maths.py", "femcore/jit.py", "femcore/kernel_cache.py"} <= fibrous
    turning = names("solvers/turning.py")
    assert {"solvers/turning.py", "femcore/rotation.py", "femcore/jit.py"} <= turning
    assert "elements/fibrous/kernels.py" not in turning  # only what it imports
    digest = kernel_cache.dependency_digest(root / "solvers/turning.py")
    assert digest == kernel_cache.dependency_digest(root / "solvers" / ".." / "solvers/turning.py")


def test_an_import_s_names_lead_to_their_submodules_or_to_the_module_defining_them(tmp_path):
    """``from a import b`` depends on a/b.py where b is a submodule, else on a/__init__.py
    (b is defined there); relative imports and names in parentheses over several lines
    too."""
    package = tmp_path / "pkg"
    (package / "sub").mkdir(parents=True)
    (package / "__init__.py").write_text("VALUE = 1\n")
    (package / "sub" / "__init__.py").write_text("")
    (package / "sub" / "leaf.py").write_text("LEAF = 2\n")
    (package / "other.py").write_text("from .sub import (\n    leaf,  # a leaf\n)\n")
    kernel = package / "kernel.py"
    kernel.write_text("from . import other\nfrom . import VALUE\n")
    found = {p.relative_to(tmp_path).as_posix() for p in kernel_cache.dependency_files(kernel)}
    assert found == {"pkg/kernel.py", "pkg/other.py", "pkg/__init__.py", "pkg/sub/leaf.py"}


def _library_modules():
    for name in ("elements", "femcore", "materials", "solvers"):
        package = importlib.import_module(name)
        yield package
        for module in pkgutil.walk_packages(package.__path__, name + "."):
            try:
                yield importlib.import_module(module.name)
            except ImportError:  # an optional dependency missing
                continue


def test_every_kernel_of_the_library_is_cached_by_the_project_cache():
    """Every numba build the library's modules make (their kernels and helpers, plain and
    parallel builds) is cached by ``ProjectCache``: none by numba's own cache, which
    would not see the other modules it depends on."""
    from numba.core.dispatcher import Dispatcher

    builds: dict[int, object] = {}
    for module in _library_modules():
        for value in vars(module).values():
            if isinstance(value, jit._Parallel):
                builds[id(value.serial)] = value.serial  # the parted copy made, not compiled
                builds[id(value.parallel)] = value.parallel
            elif isinstance(value, Dispatcher):
                builds[id(value)] = value
    assert len(builds) > 60
    stale = [
        f"{b.py_func.__module__}.{b.py_func.__qualname__}"
        for b in builds.values()
        if not isinstance(b._cache, kernel_cache.ProjectCache)
    ]
    assert stale == []


@pytest.mark.parametrize("size", [2048, 700])
def test_the_node_loops_sum_by_the_chunk_size_of_the_call(monkeypatch, size):
    """update_rates and turn walk chunks of the chunk size the Python side sized its sums
    for (femcore/jit.py ``CHUNK`` read at each call, handed to the kernel): with CHUNK
    changed after the kernels were built, every node is updated and the kinetic energies
    are 1/2 sum m v^2 of the new rates. A kernel that read CHUNK itself kept 1024: with
    2048, 952 of 3000 nodes kept np.empty's values (the reviewer's finding)."""
    from solvers.dynamics import damped_velocity, update_rates
    from solvers.turning import turn

    n = 3000
    rng = np.random.default_rng(1)
    old, applied, internal = (rng.normal(size=(n, 3)) for _ in range(3))
    mass = rng.uniform(0.5, 2.0, n)
    free, constrained = np.ones((n, 3), bool), np.zeros((n, 3), bool)
    update_rates(old, applied, internal, mass, free, constrained, None, (1e-3,) * 3, 0.0, True)
    monkeypatch.setattr(jit, "CHUNK", size)
    new, _, terms = update_rates(
        old, applied, internal, mass, free, constrained, None, (1e-3,) * 3, 0.0, True
    )
    expected = damped_velocity(old, applied - internal, 1.0 / mass[:, None], 1e-3, 0.0)
    np.testing.assert_allclose(new, expected, rtol=1e-13, atol=1e-15)
    kinetic = 0.5 * np.sum(mass[:, None] * expected**2)
    assert abs(terms[3] - kinetic) <= 1e-12 * kinetic

    directors = rng.normal(size=(n, 3))
    directors /= np.linalg.norm(directors, axis=1)[:, None]
    omega = np.cross(directors, rng.normal(size=(n, 3)))
    positions, velocities = rng.normal(size=(n, 3)), rng.normal(size=(n, 3))
    spin, _, _, moved, spin_terms = turn(
        omega, (applied, internal), directors, (positions, velocities), mass,
        np.ones(n, bool), np.zeros((n, 2), bool), (1e-3,) * 3, 0.0, True,
    )  # fmt: skip
    np.testing.assert_array_equal(moved, positions + 1e-3 * velocities)
    spinning = 0.5 * np.sum(mass * np.einsum("ij,ij->i", spin, spin))
    assert abs(spin_terms[3] - spinning) <= 1e-12 * spinning


def test_the_stamp_is_the_one_of_the_modules_as_imported(tmp_path, monkeypatch):
    """A kernel built at its first call, after a module it imports was edited, runs the
    imported code and is cached under the digest taken at its import: saved under the
    edited files' digest, its build would pass for fresh in the next process."""
    for name in ("files", "closures", "digests"):  # this test's own reading of the files
        monkeypatch.setattr(kernel_cache._Read, name, {})
    package = tmp_path / "stamped"
    package.mkdir()
    (package / "__init__.py").write_text("")
    (package / "constants.py").write_text("SCALE = 2.0\n")
    (package / "kernel.py").write_text(
        "from femcore import jit\n\nfrom .constants import SCALE\n\n\n"
        "def scale(out):\n"
        "    for i in jit.prange(out.shape[0]):\n"
        "        out[i] = SCALE * out[i]\n"
    )
    monkeypatch.syspath_prepend(str(tmp_path))
    module = importlib.import_module("stamped.kernel")
    kernel = jit.jit(module.scale)
    imported = kernel_cache.dependency_digest(package / "kernel.py")
    (package / "constants.py").write_text("SCALE = 3.0\n")
    for name in ("files", "closures", "digests"):  # a fresh reading sees the edit
        monkeypatch.setattr(kernel_cache._Read, name, {})
    edited = kernel_cache.dependency_digest(package / "kernel.py")
    assert edited != imported
    out = np.ones(4)
    kernel(out)
    np.testing.assert_array_equal(out, 2.0)  # the imported constant
    assert kernel.serial._cache._cache_file._source_stamp[1] == imported


def test_only_the_project_s_packages_are_followed(tmp_path, monkeypatch):
    """Installed in site-packages the project's packages lie beside numpy and numba: an
    import of those is not followed (the digest read 952 files at import so, against 55,
    and an upgrade of numpy made every build stale)."""
    for name in ("numpy", "elements"):
        (tmp_path / name).mkdir()
        (tmp_path / name / "__init__.py").write_text("")
    (tmp_path / "numpy" / "core.py").write_text("X = 1\n")
    (tmp_path / "elements" / "helper.py").write_text("Y = 2\n")
    kernel = tmp_path / "elements" / "kernel.py"
    kernel.write_text("import numpy as np\nfrom numpy import core\nfrom elements import helper\n")
    monkeypatch.setattr(kernel_cache, "ROOT", tmp_path)
    found = {p.relative_to(tmp_path).as_posix() for p in kernel_cache.dependency_files(kernel)}
    assert found == {"elements/kernel.py", "elements/helper.py"}


def test_the_library_imports_and_runs_with_numba_s_jit_disabled():
    """NUMBA_DISABLE_JIT=1 (a kernel debugged in Python) gives the plain functions, which
    have nothing to cache: the packages import and a rotation kernel runs, and a loop that
    would run on two threads runs whole in Python (part 0 of 1) (femcore/jit.py; an
    AttributeError before, the loop over the parts asking a Python function for its
    numba build)."""
    code = (
        "import numpy as np, femcore, elements, solvers\n"
        "from femcore.rotation import nodal_frames\n"
        "from femcore import jit\n"
        "from elements.node_rows import shifted\n"
        "print(nodal_frames(np.array([[0.0, 0.0, 1.0]]))[0].shape)\n"
        "jit.SMALL_LOOP, jit.FOLLOW_LOAD = 0, False  # every loop on numba's 2 threads\n"
        "print(shifted(np.arange(6.0).reshape(2, 3), np.ones(3)).tolist())\n"
    )
    environment = {**os.environ, "NUMBA_DISABLE_JIT": "1", "NUMBA_NUM_THREADS": "2"}
    done = subprocess.run(
        [sys.executable, "-c", code], env=environment, capture_output=True, text=True, timeout=300
    )
    assert done.returncode == 0, done.stderr[-2000:]
    assert "(1, 3)" in done.stdout
    assert "[[-1.0, 0.0, 1.0], [2.0, 3.0, 4.0]]" in done.stdout
