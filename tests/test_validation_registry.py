"""The case registry of `python -m validation` (validation/cases/__init__.py) and its records."""

import ast
import importlib
import sys
import textwrap
from pathlib import Path

import pytest

import validation.cases
from validation.cases import (
    CASES,
    PAPER_CASES,
    SENSITIVITY_CASES,
    VERIFICATION_CASES,
    RegistryError,
    discover,
)
from validation.records import Case, CaseResult, Figure, Outcome
from validation.report import run_case

CASE_DIR = Path(validation.cases.__file__).parent

# The report order: the paper's tests, the sensitivity study, then the verification cases.
REPORT_ORDER = [
    "bai-5.1",
    "bai-6.1.1",
    "bai-6.1.2",
    "bai-6.2.1",
    "bai-6.2.2",
    "bai-6.1.1-sensitivity",
    "cable-catenary",
    "cable-elastic-catenary",
    "bar-wave",
    "fibrous-curvature",
    "fibrous-deck-of-cards",
    "fibrous-heavy-cantilever",
    "plies-deck-of-cards",
    "heavy-cantilever-nonlinear",
    "plies-heavy-cantilever",
    "plies-bai-5.1",
    "mindlin-elastica",
    "mindlin-rollup",
    "mindlin-plate",
    "mindlin-scordelis-lo",
    "mindlin-pinched-cylinder",
    "hemisphere-forming",
    "hemisphere-plies",
]


def case_modules() -> list[str]:
    return sorted(p.stem for p in CASE_DIR.glob("*.py") if p.name != "__init__.py")


def test_every_module_of_the_case_package_is_registered():
    modules = case_modules()
    assert len(modules) == len(CASES)
    for name in modules:
        module = importlib.import_module(f"validation.cases.{name}")
        assert isinstance(module.CASE, Case)
        assert CASES[module.CASE.name] is module.CASE


def test_the_report_order_is_paper_then_sensitivity_then_verification():
    assert list(CASES) == REPORT_ORDER
    assert [c.group for c in PAPER_CASES] == ["paper"] * 5
    assert [c.name for c in SENSITIVITY_CASES] == ["bai-6.1.1-sensitivity"]
    assert (*PAPER_CASES, *SENSITIVITY_CASES, *VERIFICATION_CASES) == tuple(CASES.values())


def test_every_case_states_its_source_and_description():
    for case in CASES.values():
        assert case.title and case.source and case.description.strip(), case.name
        assert callable(case.compute) and callable(case.render)


def test_cases_do_not_import_each_other():
    for path in CASE_DIR.glob("*.py"):
        if path.name == "__init__.py":
            continue
        tree = ast.parse(path.read_text())
        imported = [node.module for node in ast.walk(tree) if isinstance(node, ast.ImportFrom)] + [
            alias.name
            for node in ast.walk(tree)
            if isinstance(node, ast.Import)
            for alias in node.names
        ]
        assert not [m for m in imported if m and m.startswith("validation.cases")], path.name


CASE_SOURCE = """
from validation.records import Case, Outcome


def compute(resolution):
    return Outcome(True, 0.0, 0, "", {{}}, [])


CASE = Case(
    name={name!r}, title="t", source="s", description="d", group="verification", order=1,
    compute=compute, render=lambda data, out_dir: [],
)
"""


@pytest.fixture
def make_package(tmp_path, monkeypatch):
    """Write a package of case modules under tmp_path; remove it from sys.modules after."""
    monkeypatch.syspath_prepend(str(tmp_path))
    made = []

    def make(package: str, modules: dict[str, str], init: str = "") -> str:
        folder = tmp_path / package
        folder.mkdir()
        (folder / "__init__.py").write_text(textwrap.dedent(init))
        for name, source in modules.items():
            (folder / f"{name}.py").write_text(source)
        made.append(package)
        importlib.invalidate_caches()
        return package

    yield make
    for name in list(sys.modules):
        if any(name == p or name.startswith(p + ".") for p in made):
            del sys.modules[name]


def test_discover_collects_the_case_of_every_module(make_package):
    package = make_package(
        "cases_good",
        {"first": CASE_SOURCE.format(name="one"), "second": CASE_SOURCE.format(name="two")},
    )
    assert list(discover(package)) == ["one", "two"]


def test_a_module_without_a_case_record_is_an_error(make_package):
    package = make_package(
        "cases_missing",
        {"good": CASE_SOURCE.format(name="one"), "helper": "def shared():\n    return 1\n"},
    )
    with pytest.raises(RegistryError, match=r"cases_missing\.helper .*declares no CASE record"):
        discover(package)


def test_a_package_with_a_module_without_case_fails_at_import(make_package):
    package = make_package(
        "cases_at_import",
        {"good": CASE_SOURCE.format(name="one"), "forgotten": "NAME = 'forgotten'\n"},
        init="""
        from validation.cases import discover

        CASES = discover(__name__)
        """,
    )
    with pytest.raises(RegistryError, match=r"cases_at_import\.forgotten"):
        importlib.import_module(package)


def test_duplicate_case_names_are_an_error(make_package):
    package = make_package(
        "cases_duplicate",
        {"a": CASE_SOURCE.format(name="same"), "b": CASE_SOURCE.format(name="same")},
    )
    with pytest.raises(RegistryError, match="duplicate case name 'same'"):
        discover(package)


def test_a_case_record_of_the_wrong_type_is_an_error(make_package):
    package = make_package("cases_wrong_type", {"old": "CASE = {'name': 'old'}\n"})
    with pytest.raises(RegistryError, match="not a validation.records.Case"):
        discover(package)


def test_an_unknown_group_is_refused():
    with pytest.raises(ValueError, match="group must be one of"):
        Case("x", "t", "s", "d", "other", 1, compute=print, render=print)


def test_a_case_that_raises_is_reported_with_the_keys_of_results_json(monkeypatch, tmp_path):
    def broken(resolution):
        raise RuntimeError("boom")

    case = Case("broken", "t", "s", " d ", "verification", 1, compute=broken, render=print)
    monkeypatch.setitem(CASES, "broken", case)
    result = run_case("broken", "coarse", tmp_path)
    assert isinstance(result, CaseResult) and result.outcome.error == "RuntimeError: boom"
    record = result.to_json()
    assert list(record) == [
        "converged",
        "error",
        "checks",
        "figures",
        "parameters",
        "steps",
        "solver",
        "case_time_s",
        "wall_time_s",
        "case_cpu_s",
        "warnings",
        "title",
        "source",
        "description",
    ]
    assert record["description"] == "d" and record["wall_time_s"] == record["case_time_s"]
    assert record["case_cpu_s"] >= 0.0


def test_an_outcome_serialises_with_the_keys_of_results_json():
    from validation.checks import check

    figure = Figure("f.png", "The strip's centre line on the closed-form curve, both shells.")
    outcome = Outcome(True, 1.0, 2, "solver", {"p": 1}, [check("c", 1.0, 1.0, 0.1)], [figure])
    case = Case("ok", "t", "s", "d", "verification", 1, compute=print, render=print)
    record = CaseResult(case, outcome, 1.5).to_json()
    assert list(record) == [
        "converged",
        "wall_time_s",
        "steps",
        "solver",
        "parameters",
        "checks",
        "figures",
        "case_time_s",
        "warnings",
        "title",
        "source",
        "description",
    ]
    # the CPU time where the report measured it, after the wall time
    timed = CaseResult(case, outcome, 1.5, 1.25).to_json()
    assert list(timed) == [*list(record)[:8], "case_cpu_s", *list(record)[8:]]
    assert timed["case_cpu_s"] == 1.25
    assert list(record["checks"][0]) == [
        "name",
        "reference",
        "value",
        "error",
        "tolerance",
        "relative",
        "passed",
        "source",
        "comparison",
    ]
