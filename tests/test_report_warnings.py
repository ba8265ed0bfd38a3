"""A case's runs that warn: the report keeps every Python warning raised while the case ran
(its parts in the workers, the step that combines them, a whole case) in the case's outcome,
its entry of results.json and beside the case on the page, where before they went to stderr
alone and the case read "pass" (hemisphere-forming's Mindlin holder, 0.268 from its force
against the 0.2 limit, was such a warning). The cases are tests/parts_case.py's."""

import json

import parts_case
import pytest

import validation.report as report_module
from validation.cases import CASES

QUIET = {"echo": lambda *args, **kwargs: None}
SAID = f"UserWarning: {parts_case.WARNED}"


@pytest.mark.parametrize("jobs", [1, 2], ids=["one-process", "two-workers"])
def test_the_warnings_a_case_raises_are_in_its_outcome_its_json_and_its_page(
    tmp_path, monkeypatch, jobs
):
    for case in (parts_case.CASE, parts_case.WARNING, parts_case.WARNING_WHOLE):
        monkeypatch.setitem(CASES, case.name, case)
    # a whole case runs in a worker by its name in CASES, which the spawned workers import
    # afresh (without this test's cases): run_case, which a worker calls, runs it in-process
    names = ["cheap-parts", "cheap-parts-warning"] + (["cheap-warning"] if jobs == 1 else [])
    report = report_module.run_cases(names, "coarse", tmp_path, jobs=jobs, **QUIET)
    written = json.loads((tmp_path / "results.json").read_text())["cases"]
    page = (tmp_path / "index.html").read_text()
    assert report.cases["cheap-parts"].outcome.warnings == ()
    assert written["cheap-parts"]["warnings"] == []
    for name in names[1:]:
        assert report.cases[name].outcome.warnings == (SAID,), name
        assert written[name]["warnings"] == [SAID], name
        assert report.cases[name].passed == 1  # the checks pass: the warning is beside them
    # beside the case's section, and counted in the summary's verdict
    assert page.count("pass</span> 1/1, <span class='warned'>1 warning</span>") == len(names) - 1
    assert page.count(parts_case.WARNED) == len(names) - 1
    section = page[page.index("id='cheap-parts-warning'") :]
    assert section.index(parts_case.WARNED) < section.index("</section>")


def test_a_warning_kept_is_still_shown_on_stderr(tmp_path, monkeypatch, capsys):
    monkeypatch.setitem(CASES, "cheap-warning", parts_case.WARNING_WHOLE)
    with pytest.warns(UserWarning, match=parts_case.WARNED):
        report_module.run_cases(["cheap-warning"], "coarse", tmp_path, jobs=1, **QUIET)
