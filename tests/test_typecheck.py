"""The five packages type-check cleanly with the [tool.mypy] settings of pyproject.toml."""

import ast
import fnmatch
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
# mypy over the packages: seconds to a minute, and no compiled kernel (run first)
pytestmark = [pytest.mark.slow, pytest.mark.no_kernels]

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


def test_no_package_imports_a_module_mypy_does_not_follow():
    """pyproject.toml's ``follow_imports = "skip"`` list names packages mypy met only through
    dask, distributed and matplotlib: skipped, their types are Any, so a module of the five
    that imported one would go unchecked where it uses it. No module of the five imports
    any of them."""
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())
    skipped = [
        pattern
        for override in config["tool"]["mypy"]["overrides"]
        if override.get("follow_imports") == "skip"
        for pattern in override["module"]
    ]
    assert skipped, "no follow_imports = 'skip' override found in pyproject.toml"
    found = []
    for package in PACKAGES:
        for path in sorted((ROOT / package).rglob("*.py")):
            for node in ast.walk(ast.parse(path.read_text(), str(path))):
                if isinstance(node, ast.Import):
                    names = [alias.name for alias in node.names]
                elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
                    names = [node.module] + [f"{node.module}.{a.name}" for a in node.names]
                else:
                    continue
                for name in names:
                    for pattern in skipped:
                        root = pattern.removesuffix(".*")
                        if name == root or fnmatch.fnmatch(name, pattern):
                            found.append(f"{path.relative_to(ROOT)}:{node.lineno} {name}")
    assert not found, "imports of modules mypy skips:\n" + "\n".join(found)
