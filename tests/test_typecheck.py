"""The four packages type-check cleanly with the [tool.mypy] settings of pyproject.toml."""

from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
pytestmark = pytest.mark.slow  # mypy over the packages: seconds to a minute

PACKAGES = ["femcore", "elements", "materials", "solvers", "fibreshell"]


def test_mypy_reports_no_errors(request, tmp_path_factory, monkeypatch):
    try:
        from mypy import api
    except ImportError:
        pytest.skip("mypy is not importable; install the test extra: pip install -e '.[test]'")
    # Keep mypy's cache out of the work tree: in pytest's cache (kept between runs) if enabled.
    cache = getattr(request.config, "cache", None)  # None with -p no:cacheprovider
    cache_dir = cache.mkdir("mypy") if cache is not None else tmp_path_factory.mktemp("mypy")
    monkeypatch.chdir(ROOT)  # the packages are found relative to the project root
    stdout, stderr, status = api.run(
        [
            "--config-file",
            str(ROOT / "pyproject.toml"),
            "--cache-dir",
            str(cache_dir),
            "--show-error-codes",
            *PACKAGES,
        ]
    )
    report = f"{stdout}{stderr}"
    print(report)
    assert status == 0, f"mypy found errors in {', '.join(PACKAGES)}:\n{report}"
