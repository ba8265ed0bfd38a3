"""The test suite's own setup (tests/conftest.py, tests/coarse_report.py): OpenBLAS on one
thread, and the background report's start once numba's cache holds the kernels it needs."""

import ctypes

import numpy as np
import pytest
from coarse_report import REPORT_KERNELS, report_kernels_cached


def openblas_threads() -> list[int]:
    """The thread count of each OpenBLAS library loaded in this process (numpy's, scipy's)."""
    with open("/proc/self/maps") as maps:
        libraries = {line.split()[-1] for line in maps if "openblas" in line and ".so" in line}
    counts = []
    for path in sorted(libraries):
        library = ctypes.CDLL(path)
        for symbol in ("scipy_openblas_get_num_threads64_", "scipy_openblas_get_num_threads",
                       "openblas_get_num_threads64_", "openblas_get_num_threads"):  # fmt: skip
            function = getattr(library, symbol, None)
            if function is not None:
                counts.append(function())
                break
    return counts


def test_the_tests_run_openblas_on_one_thread():
    np.linalg.eigh(np.eye(3))  # numpy's OpenBLAS loaded
    counts = openblas_threads()
    if not counts:
        pytest.skip("no OpenBLAS found in this process (another BLAS)")
    assert counts == [1] * len(counts)


def test_the_report_waits_for_every_one_of_its_kernels_in_numbas_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path))
    assert not report_kernels_cached()  # a fresh checkout
    folder = tmp_path / "elements_0123"
    folder.mkdir()
    for kernel in REPORT_KERNELS[:-1]:
        (folder / f"{kernel}-42.py311.nbi").touch()
    assert not report_kernels_cached()
    (folder / f"{REPORT_KERNELS[-1]}-7.py311.nbi").touch()
    assert report_kernels_cached()
