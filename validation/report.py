"""Run validation cases and write the report folder: results.json, index.html, figures, VTU."""

from __future__ import annotations

import html
import json
import multiprocessing
import os
import platform
import time
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import replace
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import numpy as np

from validation.cases import CASES
from validation.records import CaseResult, Outcome, Report

__all__ = ["INTRODUCTION", "STYLE", "render_html", "run_case", "run_cases"]


def run_case(name: str, resolution: str, out_dir: Path) -> CaseResult:
    """Compute the named case at ``resolution``, then draw its figures and write its files
    into ``out_dir``.

    A case that raises (in its computation or its figures) is recorded as failed, with its
    error, and not raised.
    """
    case = CASES[name]
    started = time.perf_counter()
    try:
        outcome = case.compute(resolution)
        outcome = replace(outcome, figures=list(case.render(outcome.data, out_dir)))
    except Exception as error:  # a broken case is reported, never hidden
        outcome = Outcome.failed(error)
    return CaseResult(case=case, outcome=outcome, case_time_s=time.perf_counter() - started)


def _run_in_worker(name: str, resolution: str, out_dir: Path, threads: int):
    """``run_case`` in a worker process: (outcome without its figure data, which stays with
    the worker that drew it, and the case time)."""
    import numba

    numba.set_num_threads(threads)  # the cores are shared between the workers
    result = run_case(name, resolution, out_dir)
    return replace(result.outcome, data=None), result.case_time_s


def run_cases(
    names: list[str],
    resolution: str,
    out_dir: Path,
    echo: Callable[..., Any] = print,
    jobs: int = 1,
) -> Report:
    """Run the named cases, write the report into ``out_dir``, return it.

    Parameters
    ----------
    names : list of str
        Case names (keys of ``validation.cases.CASES``), in report order.
    resolution : str
        "coarse", "default" or "fine".
    out_dir : Path
        The report folder: results.json, index.html, the figures and the VTU/XDMF files.
    echo : callable, optional
        Progress printer (``print`` signature).
    jobs : int, optional
        Cases run at once, each in its own process (1: one after another, here).

    Returns
    -------
    Report
        Every case's outcome; a case that raised is recorded as failed and the others run.
    """
    out_dir.mkdir(parents=True, exist_ok=True)
    # One line per case here: the solvers' own progress lines stay off (workers inherit it).
    before = os.environ.get("FIBRESHELL_PROGRESS")
    os.environ["FIBRESHELL_PROGRESS"] = "0"
    try:
        results = _run_all(names, resolution, out_dir, echo, jobs)
    finally:
        if before is None:
            del os.environ["FIBRESHELL_PROGRESS"]
        else:
            os.environ["FIBRESHELL_PROGRESS"] = before
    report = Report(
        generated=datetime.now(UTC).isoformat(timespec="seconds"),
        resolution=resolution,
        machine=f"{platform.platform()}, Python {platform.python_version()}, "
        f"numpy {np.__version__}",
        cases=results,
    )
    content = _strict(report.to_json())
    (out_dir / "results.json").write_text(json.dumps(content, indent=2, allow_nan=False))
    (out_dir / "index.html").write_text(render_html(content))
    return report


def _run_all(
    names: list[str], resolution: str, out_dir: Path, echo: Callable[..., Any], jobs: int
) -> dict[str, CaseResult]:
    """The cases of ``run_cases``, one after another or in ``jobs`` worker processes."""
    results: dict[str, CaseResult] = {}

    def done(result: CaseResult, before: str = "") -> None:
        checks = result.outcome.checks
        status = (
            "ERROR " + result.outcome.error
            if result.outcome.error is not None
            else f"{result.passed}/{len(checks)} checks passed"
        )
        echo(f"{before}{result.case_time_s:.1f} s, {status}")

    if jobs <= 1:
        for i, name in enumerate(names, 1):
            echo(f"[{i}/{len(names)}] {name}: {CASES[name].title} ...", end=" ", flush=True)
            results[name] = run_case(name, resolution, out_dir)
            done(results[name])
    else:
        # Spawned workers: numba's thread pool must not be forked.
        context = multiprocessing.get_context("spawn")
        threads = max(1, (os.cpu_count() or 1) // jobs)
        with ProcessPoolExecutor(jobs, mp_context=context) as pool:
            futures = {
                pool.submit(_run_in_worker, name, resolution, out_dir, threads): name
                for name in names
            }
            for count, future in enumerate(as_completed(futures), 1):
                name = futures[future]
                outcome, seconds = future.result()
                results[name] = CaseResult(case=CASES[name], outcome=outcome, case_time_s=seconds)
                done(results[name], f"[{count}/{len(names)}] {name}: {CASES[name].title}: ")
        results = {name: results[name] for name in names}  # report order
    return results


def _strict(value: Any) -> Any:
    """``value`` with arrays as lists, numpy scalars as Python ones and the non-finite floats
    (the unbounded tolerance of a one-sided check) as None, so that results.json is strict
    JSON (null, not Infinity)."""
    if isinstance(value, dict):
        return {key: _strict(item) for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return [_strict(item) for item in value]
    if isinstance(value, np.ndarray):
        return _strict(value.tolist())
    if isinstance(value, (np.floating, np.integer, np.bool_)):
        return _strict(value.item())
    if isinstance(value, float) and not np.isfinite(value):
        return None
    if value is None or isinstance(value, (str, int, float, bool)):
        return value
    raise TypeError(f"cannot write {type(value).__name__} to JSON")


def _number(value) -> str:
    if value is None:  # a non-finite number in results.json (an unbounded tolerance)
        return "none"
    if isinstance(value, (list, tuple)):  # e.g. an imposed (ux, uy, uz), None = free
        return ", ".join("free" if v is None else _number(v) for v in value)
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
figure { display: inline-block; margin: 0.5em; max-width: 100%; }
img { max-width: 100%; height: auto; border: 1px solid #eee; }
figcaption { font-size: 0.88em; color: #555; max-width: 60em; }
table { display: block; overflow-x: auto; max-width: 100%; }
details { margin: 1em 0; } summary { cursor: pointer; font-weight: 600; }
nav ol { columns: 2; font-size: 0.95em; } @media (max-width: 900px) { nav ol { columns: 1; } }
pre { background: #f7f7f7; padding: 0.8em; white-space: pre-wrap; font-size: 0.88em; }
td.small { font-size: 0.85em; max-width: 28em; }
p.discussion { max-width: 60em; }
"""


def _key_numbers(case: dict, kinematics: str) -> str:
    """Short text of the numbers an engineer looks at first, per element of a paper case."""
    record = case["elements"][kinematics]
    parts = []
    if "max_fibre_strain" in record:
        parts.append(f"max fibre strain {100 * record['max_fibre_strain']:.3f} %")
    for side in ("side_1", "side_2"):
        numbers = case.get("key_numbers", {}).get(f"{kinematics} {side}")
        if numbers:
            parts.append(
                f"{side.replace('_', ' ')}: slope up to {numbers['max_midsurface_slope_deg']:.0f}"
                f" deg, director {numbers['director_angle_min_deg']:.0f}-"
                f"{numbers['director_angle_max_deg']:.0f} deg, tilt from the normal up to "
                f"{numbers['side_tilt_max_deg']:.0f} deg, thickness up to "
                f"{numbers['thickness_max_over_h']:.2f} h"
            )
    return html.escape("; ".join(parts))


def _summary_rows(name: str, case: dict) -> list[str]:
    checks = case["checks"]
    passed = sum(c["passed"] for c in checks)
    ok = passed == len(checks) and "error" not in case and case["converged"]
    verdict = (
        f"<td class='{'pass' if ok else 'fail'}'>{passed}/{len(checks)}"
        f"{' ERROR' if 'error' in case else ''}</td>"
    )
    link = f"<a href='#{name}'>{html.escape(name)}</a>"
    elements = case.get("elements")
    if not elements:
        return [
            f"<tr><td>{link}</td><td>{html.escape(case['title'])}</td><td>-</td>"
            f"<td>{html.escape(case.get('solver', ''))}</td>"
            f"<td>{_number(bool(case['converged']))}</td>"
            f"<td class='num'>{case['wall_time_s']:.2f}</td><td class='num'>{case['steps']}</td>"
            f"<td></td>{verdict}</tr>"
        ]
    rows = []
    for i, (kinematics, record) in enumerate(elements.items()):
        head = (
            f"<td rowspan='{len(elements)}'>{link}</td>"
            f"<td rowspan='{len(elements)}'>{html.escape(case['title'])}</td>"
            if i == 0
            else ""
        )
        tail = verdict.replace("<td", f"<td rowspan='{len(elements)}'", 1) if i == 0 else ""
        rows.append(
            f"<tr>{head}<td>{html.escape(record.get('label', kinematics))}</td>"
            f"<td>{html.escape(record['solver'])}</td>"
            f"<td>{_number(bool(record['converged']))}</td>"
            f"<td class='num'>{record['wall_time_s']:.2f}</td>"
            f"<td class='num'>{record['steps']}</td>"
            f"<td class='small'>{_key_numbers(case, kinematics)}</td>{tail}</tr>"
        )
    return rows


def _caption(case: str, figure: str) -> str:
    """A figure's caption from its file name: "<case>-side-profiles.png" -> "side profiles"."""
    stem = Path(figure).stem
    if stem.startswith(case):
        stem = stem[len(case) :]
    words = stem.strip("-_ ").replace("_", " ").replace("-", " ")
    return f"{case}: {words}" if words else case


def _checks_table(case: dict) -> str:
    """The case's checks with the rule of each, in a <details> block, open if one failed."""
    rows = []
    for c in case["checks"]:
        if c["relative"]:
            rule = "pass if |value - reference| / |reference| <= tolerance"
        else:
            rule = "pass if |value - reference| <= tolerance"
        if c["tolerance"] is None:
            rule = "reported, no bound (not a pass/fail check)"
        rows.append(
            f"<tr><td>{html.escape(c['name'])}</td>"
            f"<td class='num'>{_number(c['reference'])}</td>"
            f"<td class='num'>{_number(c['value'])}</td>"
            f"<td class='num'>{_number(c['error'])}</td>"
            f"<td class='num'>{_number(c['tolerance'])}</td>"
            f"<td class='small'>{html.escape(rule)}</td>"
            f"<td class='{'pass' if c['passed'] else 'fail'}'>"
            f"{'pass' if c['passed'] else 'FAIL'}</td>"
            f"<td class='small'>{html.escape(c.get('source', ''))}</td></tr>"
        )
    passed = sum(c["passed"] for c in case["checks"])
    failed = passed < len(case["checks"])
    return (
        f"<details{' open' if failed else ''}><summary>Checks: {passed} of "
        f"{len(case['checks'])} passed</summary><table><tr><th>check</th><th>reference</th>"
        "<th>value</th><th>error</th><th>tolerance</th><th>rule</th><th>result</th>"
        f"<th>source</th></tr>{''.join(rows)}</table></details>"
    )


def _orders_table(case: dict) -> str:
    """The paper case's observed orders on three meshes (Richardson): per kinematics and
    quantity, the values, the order and the extrapolated value; empty for other cases."""
    orders = case.get("observed_orders")
    if not orders:
        return ""
    labels = {k: e.get("label", k) for k, e in case.get("elements", {}).items()}
    rows = []
    for record in orders:
        order = record["order"]  # None in results.json: no order (oscillating, or none found)
        gap = (
            abs(record["extrapolated"] - record["values"][-1]) / abs(record["values"][-1])
            if order is not None and record["extrapolated"] is not None and record["values"][-1]
            else None
        )
        rows.append(
            f"<tr><td>{html.escape(labels.get(record['kinematics'], record['kinematics']))}</td>"
            f"<td>{html.escape(record['quantity'])}</td>"
            + "".join(f"<td class='num'>{value:.5g}</td>" for value in record["values"])
            + f"<td class='num'>{'-' if order is None else f'{order:.2f}'}</td>"
            f"<td class='num'>{'-' if gap is None else _number(record['extrapolated'])}</td>"
            f"<td class='num'>{'-' if gap is None else f'{100 * gap:.2f} %'}</td>"
            f"<td>{'' if record['converged'] else 'NOT converged'}</td></tr>"
        )
    first = orders[0]
    meshes = "".join(
        f"<th>n = {n}<br>h = {size:.3g} mm</th>" for n, size in zip(first["cells"], first["sizes"])
    )
    return (
        "<p>Observed order of convergence on three meshes (Richardson, for any refinement "
        "ratio: f(h) = f0 + C h^p through the three values; h the largest node spacing "
        "along side 1). A dash: the differences change sign, no order. Checked where the case "
        "states a tolerance (see its checks).</p>"
        f"<table><tr><th>kinematics</th><th>quantity</th>{meshes}<th>order p</th>"
        "<th>extrapolated f0</th><th>|f0 - finest| / |finest|</th><th></th></tr>"
        f"{''.join(rows)}</table>"
    )


def render_html(report: dict[str, Any]) -> str:
    """One self-contained page: contents, summary, then each case in detail: its description,
    parameters, figures with captions, discussion, files and (collapsed) checks with their
    rules.

    ``report`` is the content of results.json (``Report.to_json``), so that the page can be
    rendered again from that file alone."""
    cases = report["cases"]
    rows = [row for name, case in cases.items() for row in _summary_rows(name, case)]
    sections = []
    for name, case in cases.items():
        parameters = "".join(
            f"<tr><th>{html.escape(str(k))}</th><td class='num'>{_number(v)}</td></tr>"
            for k, v in case["parameters"].items()
        )
        figures = "".join(
            f"<figure><img src='{html.escape(f)}' alt='{html.escape(_caption(name, f))}'>"
            f"<figcaption>Figure {i}. {html.escape(_caption(name, f))}</figcaption></figure>"
            for i, f in enumerate(case["figures"], 1)
        )
        error = (
            f"<p class='fail'>The case failed: {html.escape(case['error'])}</p>"
            if "error" in case
            else ""
        )
        discussion = "".join(
            f"<p class='discussion'>{html.escape(paragraph)}</p>"
            for paragraph in case.get("discussion", "").split("\n\n")
            if paragraph.strip()
        )
        files = ""
        if case.get("elements"):
            files = (
                "<p>ParaView files: "
                + ", ".join(
                    f"<a href='{name}-{k}.{ext}'>{name}-{k}.{ext}</a>"
                    for k in case["elements"]
                    for ext in ("vtu", "xdmf")
                )
                + ".</p>"
            )
        sections.append(
            f"<section id='{name}'><h2>{html.escape(name)}: {html.escape(case['title'])}</h2>"
            f"{error}<pre>{html.escape(case['description'])}</pre>"
            f"<p>Solver: {html.escape(case.get('solver', ''))}; {case['steps']} steps/iterations; "
            f"{case['wall_time_s']:.2f} s.</p>"
            f"<table>{parameters}</table>{figures}{discussion}{_orders_table(case)}{files}"
            f"{_checks_table(case)}</section>"
        )
    contents = "".join(
        f"<li><a href='#{html.escape(name)}'>{html.escape(name)}</a>: "
        f"{html.escape(case['title'])}</li>"
        for name, case in cases.items()
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
{INTRODUCTION}
<nav><h2>Contents</h2><ol>{contents}</ol></nav>
<h2>Summary</h2>
<table><tr><th>case</th><th>what</th><th>element</th><th>solver</th><th>converged</th>
<th>time (s)</th><th>steps</th><th>key numbers</th><th>checks</th></tr>{"".join(rows)}</table>
<p>Every check compares a computed value with a closed-form or published reference, or states
an invariant of the formulation; each case lists its checks, with the rule that decides them,
below its figures (collapsed unless one failed).</p>
{"".join(sections)}
</body></html>
"""


INTRODUCTION = """<p>The cases named <code>bai-*</code> rerun the simulations of Bai, Colmars,
Naouar and Boisse, <i>Composites Part A</i> 139 (2020) 106135, with three kinematics on the same
mesh, boundary conditions and loads: the fibrous shell of the paper, whose material directors
are free to leave the normal and whose thickness along them follows from Eq. 10, in two variants
(<b>fibrous</b>, the default: the thickness along the director from the area-weighted nodal
normal, so that the directors of a bent stack tilt as its plies slip; <b>fibrous_element</b>:
Bai's Eq. 15 as published, each element's own normal, so that parallel directors are strain-free
and keep their orientation), and a reference Mindlin shell (<b>mindlin</b>, MITC3, the role
Abaqus S3 plays in the paper) made of the same fabric: <code>MindlinShell(fabric)</code>, whose
section is the fabric's own tension, in-plane shear and bending laws (non-linear ones as given),
with a stated transverse shear S = 5 B0 / h<sup>2</sup> and twisting stiffness D_t = B0 / 2
(calibration "laws", fibreshell.calibration), so that a difference between
the runs is one of kinematics, not of material. (Earlier versions used the paper's
calibration, E = 12 B / h<sup>3</sup>: a membrane hundreds of times softer than the fibres and,
past the knee of a non-linear law, a bending far too stiff.) Each case states the calibration
and its numbers. Gravity acts in every case. Sizes, imposed displacements and the material
data the paper does not give are stated in each case. The other cases verify the elements
against closed-form or published solutions.</p>"""
