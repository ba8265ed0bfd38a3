"""Run validation cases and write the report folder: results.json, index.html, figures, VTU."""

from __future__ import annotations

import html
import json
import platform
import time
from datetime import UTC, datetime
from pathlib import Path

import numpy as np

from validation.cases import CASES


def run_cases(names: list[str], resolution: str, out_dir: Path, echo=print) -> dict:
    """Run the named cases, write the report into ``out_dir``, return the results dict.

    A case that raises is recorded as failed (with its error) and the others still run.
    """
    out_dir.mkdir(parents=True, exist_ok=True)
    results = {}
    for i, name in enumerate(names, 1):
        module = CASES[name]
        echo(f"[{i}/{len(names)}] {name}: {module.TITLE} ...", end=" ", flush=True)
        started = time.perf_counter()
        try:
            outcome = module.run(resolution, out_dir)
        except Exception as error:  # a broken case is reported, never hidden
            outcome = {
                "converged": False,
                "error": f"{type(error).__name__}: {error}",
                "checks": [],
                "figures": [],
                "parameters": {},
                "steps": 0,
                "solver": "",
            }
        outcome["case_time_s"] = time.perf_counter() - started
        outcome.setdefault("wall_time_s", outcome["case_time_s"])
        outcome.update(
            title=module.TITLE, source=module.SOURCE, description=(module.__doc__ or "").strip()
        )
        passed = sum(c["passed"] for c in outcome["checks"])
        status = (
            "ERROR " + outcome["error"]
            if "error" in outcome
            else (f"{passed}/{len(outcome['checks'])} checks passed")
        )
        echo(f"{outcome['case_time_s']:.1f} s, {status}")
        results[name] = outcome
    report = {
        "generated": datetime.now(UTC).isoformat(timespec="seconds"),
        "resolution": resolution,
        "machine": f"{platform.platform()}, Python {platform.python_version()}, "
        f"numpy {np.__version__}",
        "cases": results,
    }
    (out_dir / "results.json").write_text(json.dumps(report, indent=2, default=_jsonable))
    (out_dir / "index.html").write_text(render_html(report))
    return report


def _jsonable(value):
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, (np.floating, np.integer, np.bool_)):
        return value.item()
    raise TypeError(f"cannot write {type(value).__name__} to JSON")


def _number(value) -> str:
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, (int, np.integer)):
        return str(value)
    if isinstance(value, (float, np.floating)):
        return f"{value:.6g}"
    return html.escape(str(value))


STYLE = """
body { font-family: system-ui, sans-serif; margin: 2em auto; max-width: 1100px; color: #222;
       padding: 0 1em; }
h1 { font-size: 1.6em; } h2 { margin-top: 2em; border-bottom: 1px solid #ccc; }
table { border-collapse: collapse; margin: 1em 0; font-size: 0.92em; }
th, td { border: 1px solid #ccc; padding: 0.3em 0.6em; text-align: left; vertical-align: top; }
th { background: #f2f2f2; }
td.num { text-align: right; font-variant-numeric: tabular-nums; }
.pass { color: #1a7f37; font-weight: 600; } .fail { color: #c62828; font-weight: 600; }
figure { display: inline-block; margin: 0.5em; } img { max-width: 520px; border: 1px solid #eee; }
pre { background: #f7f7f7; padding: 0.8em; white-space: pre-wrap; font-size: 0.88em; }
"""


def render_html(report: dict) -> str:
    """One self-contained page: summary, verification table, then each case in detail."""
    cases = report["cases"]
    rows = []
    for name, case in cases.items():
        checks = case["checks"]
        passed = sum(c["passed"] for c in checks)
        ok = passed == len(checks) and "error" not in case and case["converged"]
        rows.append(
            f"<tr><td><a href='#{name}'>{html.escape(name)}</a></td>"
            f"<td>{html.escape(case['title'])}</td>"
            f"<td>{html.escape(case.get('solver', ''))}</td>"
            f"<td>{_number(bool(case['converged']))}</td>"
            f"<td class='num'>{case['wall_time_s']:.2f}</td><td class='num'>{case['steps']}</td>"
            f"<td class='{'pass' if ok else 'fail'}'>{passed}/{len(checks)}"
            f"{' ERROR' if 'error' in case else ''}</td></tr>"
        )
    check_rows = []
    for name, case in cases.items():
        for c in case["checks"]:
            kind = "relative" if c["relative"] else "absolute"
            check_rows.append(
                f"<tr><td>{html.escape(name)}</td><td>{html.escape(c['name'])}</td>"
                f"<td class='num'>{_number(c['reference'])}</td>"
                f"<td class='num'>{_number(c['value'])}</td>"
                f"<td class='num'>{_number(c['error'])}</td>"
                f"<td class='num'>{_number(c['tolerance'])} ({kind})</td>"
                f"<td class='{'pass' if c['passed'] else 'fail'}'>"
                f"{'pass' if c['passed'] else 'FAIL'}</td>"
                f"<td>{html.escape(c.get('source', ''))}</td></tr>"
            )
    sections = []
    for name, case in cases.items():
        parameters = "".join(
            f"<tr><th>{html.escape(str(k))}</th><td class='num'>{_number(v)}</td></tr>"
            for k, v in case["parameters"].items()
        )
        figures = "".join(
            f"<figure><img src='{html.escape(f)}' alt='{html.escape(f)}'></figure>"
            for f in case["figures"]
        )
        error = (
            f"<p class='fail'>The case failed: {html.escape(case['error'])}</p>"
            if "error" in case
            else ""
        )
        sections.append(
            f"<section id='{name}'><h2>{html.escape(name)}: {html.escape(case['title'])}</h2>"
            f"{error}<pre>{html.escape(case['description'])}</pre>"
            f"<p>Solver: {html.escape(case.get('solver', ''))}; {case['steps']} steps/iterations; "
            f"{case['wall_time_s']:.2f} s.</p>"
            f"<table>{parameters}</table>{figures}</section>"
        )
    n_checks = sum(len(c["checks"]) for c in cases.values())
    n_passed = sum(sum(x["passed"] for x in c["checks"]) for c in cases.values())
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>Validation report</title>
<style>{STYLE}</style></head><body>
<h1>Validation report</h1>
<p>Generated {html.escape(report["generated"])} at resolution
<b>{html.escape(report["resolution"])}</b>
on {html.escape(report["machine"])}. <b>{n_passed} of {n_checks}</b> checks passed.</p>
<h2>Summary</h2>
<table><tr><th>case</th><th>what</th><th>solver</th><th>converged</th><th>time (s)</th>
<th>steps</th><th>checks</th></tr>{"".join(rows)}</table>
<h2>Verification</h2>
<p>Every check compares a computed value with a closed-form or published reference; a failed
check is shown as failed.</p>
<table><tr><th>case</th><th>check</th><th>reference</th><th>value</th><th>error</th>
<th>tolerance</th><th>result</th><th>source</th></tr>{"".join(check_rows)}</table>
{"".join(sections)}
</body></html>
"""
