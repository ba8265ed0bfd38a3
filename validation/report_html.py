"""The report's page, index.html, from the content of results.json.

A reader sees first a summary, one line per case (what it is, its verdict, the number to look
at), then the cases with their figures, numbered through the whole page, each with the caption
its case wrote; the statement, the parameters, the runs and the checks of each case are folded
below its figures. The page is self-contained (one style sheet inline), fits a phone's width
(viewport meta tag, tables that wrap) and links every thumbnail to its full-size image.
"""

from __future__ import annotations

import html
from typing import Any

import numpy as np

__all__ = ["INTRODUCTION", "STYLE", "render_html"]


def _number(value) -> str:
    if value is None:  # a non-finite number in results.json (an unbounded tolerance)
        return "none"
    if isinstance(value, (list, tuple)):  # e.g. an imposed (ux, uy, uz), None = free
        return ", ".join("free" if v is None else _number(v) for v in value)
    if isinstance(value, dict):  # e.g. a run's scaling: {time_scaling: 2, mass_scaling_dt_s: None}
        return ", ".join(f"{html.escape(str(key))} = {_number(v)}" for key, v in value.items())
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, (int, np.integer)):
        return str(value)
    if isinstance(value, (float, np.floating)):
        return f"{value:.6g}"
    return html.escape(str(value))


def _short(value) -> str:
    """A number in the summary: four significant digits."""
    if isinstance(value, (float, np.floating)):
        return f"{value:.4g}"
    return _number(value)


def _numeric(value) -> str:
    """The class of a number's cell (right-aligned, kept on one line); none for text."""
    is_number = isinstance(value, (int, float, np.integer, np.floating))
    return " class='num'" if is_number and not isinstance(value, bool) else ""


STYLE = """
body { font-family: system-ui, sans-serif; margin: 1.5em auto; max-width: 1100px; color: #222;
       padding: 0 1em; line-height: 1.4; }
h1 { font-size: 1.6em; margin-bottom: 0.2em; }
h2 { margin-top: 2em; border-bottom: 1px solid #ccc; font-size: 1.3em; }
table { border-collapse: collapse; margin: 0.8em 0; font-size: 0.92em; max-width: 100%; }
th, td { border: 1px solid #ccc; padding: 0.25em 0.5em; text-align: left; vertical-align: top;
         overflow-wrap: break-word; }
th { background: #f2f2f2; }
td.num { text-align: right; font-variant-numeric: tabular-nums; overflow-wrap: normal;
         white-space: nowrap; }
.pass { color: #1a7f37; font-weight: 600; } .fail { color: #c62828; font-weight: 600; }
.warned { color: #9a5b00; font-weight: 600; }
table.summary { width: 100%; }
table.summary td.what { min-width: 12em; }
table.summary td.key { font-size: 0.9em; }
table.summary td.name { overflow-wrap: normal; }
table.summary td.verdict { white-space: nowrap; }
.figures { display: flex; flex-wrap: wrap; gap: 0 1.5em; align-items: flex-start; }
figure { margin: 1em 0; flex: 1 1 100%; min-width: 0; }
figure.half { flex: 1 1 460px; }
figure img { display: block; max-width: 100%; height: auto; border: 1px solid #eee; }
figcaption { font-size: 0.92em; color: #333; max-width: 62em; margin-top: 0.3em; }
figcaption b { color: #000; }
details { margin: 0.8em 0; } summary { cursor: pointer; font-weight: 600; }
pre { background: #f7f7f7; padding: 0.8em; white-space: pre-wrap; font-size: 0.85em;
      overflow-wrap: anywhere; }
td.small, .small { font-size: 0.85em; } span.small { color: #555; }
td.small, td.key { overflow-wrap: anywhere; }
p.discussion, p.verdict { max-width: 62em; }
p.verdict { font-size: 1.02em; }
@media (max-width: 900px) {
  body { padding: 0 0.5em; }
  table { font-size: 0.85em; }
  th, td { padding: 0.2em 0.3em; }
  td.num { white-space: normal; }
}
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


def _comparison(check: dict) -> str:
    """How a check compares its value with its reference (``Check.comparison``; "within" in a
    results.json written before it was recorded)."""
    return check.get("comparison", "within")


def _counted(checks: list[dict]) -> list[dict]:
    """The checks with a verdict: the reported values left out."""
    return [c for c in checks if _comparison(c) != "reported"]


def _ok(case: dict) -> bool:
    """Whether the case passed: every check, no error, converged."""
    return (
        "error" not in case
        and bool(case["converged"])
        and all(c["passed"] for c in _counted(case["checks"]))
    )


def _word(case: dict) -> str:
    """The verdict in a word: pass, FAIL, NOT CONVERGED or ERROR, coloured."""
    if "error" in case:
        return "<span class='fail'>ERROR</span>"
    if not case["converged"]:
        return "<span class='fail'>NOT CONVERGED</span>"
    return "<span class='pass'>pass</span>" if _ok(case) else "<span class='fail'>FAIL</span>"


def _verdict(case: dict) -> str:
    """The verdict and the checks passed: "pass 12/12", "FAIL 3/4", "ERROR 0/0" (the
    reported values, which have no verdict, left out), and how many warnings its runs raised
    where they raised any ("pass 5/5, 1 warning")."""
    checks = _counted(case["checks"])
    count = len(case.get("warnings", []))
    warned = (
        f", <span class='warned'>{count} warning{'s' if count > 1 else ''}</span>" if count else ""
    )
    return f"{_word(case)} {sum(c['passed'] for c in checks)}/{len(checks)}{warned}"


def _warnings(case: dict) -> str:
    """The warnings the case's runs raised (results.json's "warnings"), each in full, or
    nothing where they raised none: a run that warned is doubtful though its checks pass."""
    warned = case.get("warnings", [])
    if not warned:
        return ""
    items = "".join(f"<li>{html.escape(text)}</li>" for text in warned)
    return (
        f"<div class='warned'><p>The case's runs warned ({len(warned)}; the checks do not "
        f"judge what a warning says):</p><ul>{items}</ul></div>"
    )


def _margin(check: dict) -> float:
    """How much of its tolerance a check uses (error / tolerance; 0 for a reported value)."""
    tolerance, error = check["tolerance"], check["error"]
    if tolerance is None or error is None or _comparison(check) == "reported":
        return 0.0
    if _comparison(check) != "within":  # a bound: used up only when crossed
        return 0.0 if check["passed"] else float("inf")
    if tolerance == 0:  # an exact check (e.g. "converged"): used up only when missed
        return 0.0 if error == 0 else float("inf")
    return abs(error) / tolerance


def _largest(numbers: dict, kinematics: str, name: str) -> float | None:
    """The largest ``name`` of ``kinematics`` over a paper case's sides (``key_numbers``:
    "fibrous side_1", "fibrous side_2", ...), or None where it has none."""
    values = [v[name] for k, v in numbers.items() if k.split(" ")[0] == kinematics]
    return max(values) if values else None


def _self_check(check: dict) -> bool:
    """Whether a check verifies a reference's own numbers (its name ends "(self-check)": a
    series summed to the printed digits), not the code: never a case's key number."""
    return check["name"].rstrip().endswith("(self-check)")


def _key_number(case: dict) -> str:
    """The number a reader of the summary looks at, as short text (HTML escaped).

    A case that raised: the start of its error. A case with a failed check: the first one,
    as value and reference. A paper case: how far the default fibrous directors leave the
    nodal normal (in three dimensions, away from the clamped node: ``SideSummary``) and how
    thick the stack grows along them, the largest over its sides (the paper's point), beside
    the Mindlin tilt. Another case: the check that uses most of its tolerance, a reference's
    self-check left out (``_self_check``); a check whose name states its window ("within [a,
    b]") with its value alone, not the window's midpoint as a reference.
    """
    if "error" in case:
        error = case["error"]
        return html.escape(error if len(error) <= 90 else error[:87] + "...")
    checks = _counted(case["checks"])
    failed = [c for c in checks if not c["passed"]]
    numbers = case.get("key_numbers") or {}
    tilt = _largest(numbers, "fibrous", "normal_tilt_max_deg")
    thickness = _largest(numbers, "fibrous", "thickness_max_over_h")
    tilt_mindlin = _largest(numbers, "mindlin", "normal_tilt_max_deg")
    if tilt is not None and thickness is not None and tilt_mindlin is not None and not failed:
        return (
            f"fibrous directors up to {tilt:.0f} deg from the normal (Mindlin "
            f"{tilt_mindlin:.0f}), thickness up to {thickness:.2f} h"
        )
    if not checks:
        return "no checks"
    of_the_code = [c for c in checks if not _self_check(c)] or checks
    check = failed[0] if failed else max(of_the_code, key=_margin)
    if check["reference"] is None or check["tolerance"] is None or " within [" in check["name"]:
        return f"{html.escape(check['name'])}: {_short(check['value'])}"
    return (
        f"{html.escape(check['name'])}: {_short(check['value'])} "
        f"(reference {_short(check['reference'])})"
    )


def _summary_table(cases: dict[str, dict]) -> str:
    """One line per case: number and link, what, verdict, key number."""
    rows = "".join(
        f"<tr><td class='num'>{i}</td><td class='name'><a href='#{html.escape(name)}'>"
        f"{html.escape(name)}</a></td><td class='what'>{html.escape(case['title'])}</td>"
        f"<td class='verdict'>{_verdict(case)}</td>"
        f"<td class='key'>{_key_number(case)}</td></tr>"
        for i, (name, case) in enumerate(cases.items(), 1)
    )
    return (
        "<table class='summary'><tr><th>#</th><th>case</th><th>what</th><th>checks passed</th>"
        f"<th>key number</th></tr>{rows}</table>"
    )


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
                f"{numbers['normal_tilt_max_deg']:.0f} deg ({numbers['side_tilt_max_deg']:.0f} "
                f"seen facing the side), thickness up to "
                f"{numbers['thickness_max_over_h']:.2f} h"
            )
    return html.escape("; ".join(parts))


def _runs_table(case: dict) -> str:
    """A paper case's runs, one row per kinematics: solver, convergence, time, steps and the
    numbers of its sides; folded. Empty for the other cases."""
    elements = case.get("elements")
    if not elements:
        return ""
    rows = "".join(
        f"<tr><td>{html.escape(record.get('label', kinematics))}</td>"
        f"<td>{html.escape(record['solver'])}</td>"
        f"<td>{_number(bool(record['converged']))}</td>"
        f"<td class='num'>{record['wall_time_s']:.2f}</td>"
        f"<td class='num'>{record['steps']}</td>"
        f"<td class='small'>{_key_numbers(case, kinematics)}</td></tr>"
        for kinematics, record in elements.items()
    )
    return (
        "<details class='runs'><summary>Runs: one per kinematics, with the numbers of each "
        "side</summary><table><tr><th>kinematics</th><th>solver</th><th>converged</th>"
        f"<th>time (s)</th><th>steps</th><th>numbers</th></tr>{rows}</table></details>"
    )


RULES = (
    "Rule: a two-sided check passes if |value - reference| / |reference| &lt;= tolerance for a "
    "relative check (rel), |value - reference| &lt;= tolerance for an absolute one (abs); a "
    "one-sided check (tolerance &quot;value &gt;= reference&quot; or &quot;value &lt;= "
    "reference&quot;) passes if the value lies on that side of the reference, its error how far "
    "it lies past it; a reported value has no verdict and is not counted among the checks "
    "passed. A tolerance of none: the check's name states its bound."
)

# The tolerance column of a one-sided check: the comparison in place of a tolerance.
ONE_SIDED = {"at least": "value &gt;= reference", "at most": "value &lt;= reference"}


def _result(check: dict) -> str:
    """The result cell: pass, FAIL, or "reported" (no verdict, not coloured)."""
    if _comparison(check) == "reported":
        return "<td class='small'>reported</td>"
    word = "pass" if check["passed"] else "FAIL"
    return f"<td class='{word.lower()}'>{word}</td>"


def _tolerance(check: dict) -> str:
    """The tolerance cell's text: the tolerance and its kind (rel, abs), the comparison of a
    one-sided check, a dash for a reported value."""
    comparison = _comparison(check)
    if comparison == "reported":
        return "-"
    if comparison in ONE_SIDED:
        return ONE_SIDED[comparison]
    kind = "" if check["tolerance"] is None else (" rel" if check["relative"] else " abs")
    return f"{_number(check['tolerance'])}{kind}"


def _checks_table(case: dict) -> str:
    """The case's checks in a <details> block, open if one failed: the rule stated once above
    the table, each check's source under its name, so that the table fits a narrow page; the
    count of checks passed leaves out the reported values."""
    rows = []
    for c in case["checks"]:
        source = (
            f"<br><span class='small'>{html.escape(c['source'])}</span>" if c.get("source") else ""
        )
        rows.append(
            f"<tr><td>{html.escape(c['name'])}{source}</td>"
            f"<td class='num'>{_number(c['reference'])}</td>"
            f"<td class='num'>{_number(c['value'])}</td>"
            f"<td class='num'>{_number(c['error'])}</td>"
            f"<td class='num'>{_tolerance(c)}</td>"
            f"{_result(c)}</tr>"
        )
    counted = _counted(case["checks"])
    passed = sum(c["passed"] for c in counted)
    failed = passed < len(counted)
    if not rows:
        return "<details class='checks'><summary>Checks: none</summary></details>"
    reported = len(case["checks"]) - len(counted)
    beside = f", {reported} reported" if reported else ""
    return (
        f"<details class='checks'{' open' if failed else ''}><summary>Checks: {passed} of "
        f"{len(counted)} passed{beside}</summary><p class='small'>{RULES}</p>"
        "<table class='checks'><tr><th>check (source)</th><th>reference</th><th>value</th>"
        f"<th>error</th><th>tolerance</th><th>result</th></tr>{''.join(rows)}</table></details>"
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
        "<details class='orders'><summary>Observed order of convergence on three meshes"
        "</summary><p>Richardson, for any refinement ratio: f(h) = f0 + C h^p through the three "
        "values; h the largest node spacing along side 1. A dash: the differences change sign, "
        "no order. Checked where the case states a tolerance (see its checks).</p>"
        f"<table><tr><th>kinematics</th><th>quantity</th>{meshes}<th>order p</th>"
        "<th>extrapolated f0</th><th>|f0 - finest| / |finest|</th><th></th></tr>"
        f"{''.join(rows)}</table></details>"
    )


# Figures at most this wide (pixels) sit two to a row on a wide page.
NARROW_FIGURE = 800


def _figure(number: int, figure: dict) -> str:
    """A numbered figure: the thumbnail links to the full-size image; its case's caption.
    With its size known, the image's place is reserved and a narrow figure is classed
    "half" (two to a row where the page is wide enough)."""
    file, caption = html.escape(figure["file"]), html.escape(figure["caption"])
    width, height = figure.get("width"), figure.get("height")
    size = f" width='{width}' height='{height}'" if width and height else ""
    half = " class='half'" if width and width <= NARROW_FIGURE else ""
    return (
        f"<figure id='figure-{number}'{half}><a href='{file}'><img src='{file}'{size} "
        f"alt='{caption}'></a><figcaption><b>Figure {number}.</b> {caption}</figcaption>"
        "</figure>"
    )


def _section(number: int, name: str, case: dict, first_figure: int) -> str:
    """A case: its verdict line, its figures numbered from ``first_figure``, its discussion,
    then folded: the runs, the orders, the statement with the parameters, the checks."""
    for figure in case["figures"]:
        if not isinstance(figure, dict) or not figure.get("caption"):
            raise ValueError(
                f"case {name!r}: figure {figure!r} has no caption: each figure of results.json "
                'is a record {"file": ..., "caption": ...} (validation.records.Figure)'
            )
    figures = "".join(_figure(first_figure + i, f) for i, f in enumerate(case["figures"]))
    figures = f"<div class='figures'>{figures}</div>" if figures else ""
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
    parameters = "".join(
        f"<tr><th>{html.escape(str(k))}</th><td{_numeric(v)}>{_number(v)}</td></tr>"
        for k, v in case["parameters"].items()
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
    statement = (
        "<details class='statement'><summary>The case: source, geometry, parameters, solver"
        f"</summary><pre>{html.escape(case['description'])}</pre>"
        f"<p>Solver: {html.escape(case.get('solver', ''))}; {case['steps']} steps or "
        f"iterations, {case['wall_time_s']:.2f} s.</p><table>{parameters}</table></details>"
    )
    counted = _counted(case["checks"])
    passed = sum(c["passed"] for c in counted)
    verdict = (
        f"<p class='verdict'>{_word(case)}: {passed} of "
        f"{len(counted)} checks passed. Key number: {_key_number(case)}. Source: "
        f"{html.escape(case['source'])}; {case['wall_time_s']:.1f} s of solving. "
        "<a href='#summary'>Back to the summary</a>.</p>"
    )
    return (
        f"<section id='{html.escape(name)}'><h2>{number}. {html.escape(name)}: "
        f"{html.escape(case['title'])}</h2>{error}{verdict}{_warnings(case)}{figures}{discussion}"
        f"{_runs_table(case)}{_orders_table(case)}{statement}{files}{_checks_table(case)}"
        "</section>"
    )


def render_html(report: dict[str, Any]) -> str:
    """One self-contained page: the summary (one line per case), then each case: its verdict,
    its figures with their captions (numbered through the page), its discussion, and folded
    below them its runs, orders, statement, parameters and checks with their rules.

    Parameters
    ----------
    report : dict
        The content of results.json (``Report.to_json``), so that the page can be rendered
        again from that file alone; each case's ``figures`` are {"file", "caption"} records.

    Returns
    -------
    str
        The HTML of index.html.
    """
    cases = report["cases"]
    sections, first = [], 1
    for number, (name, case) in enumerate(cases.items(), 1):
        sections.append(_section(number, name, case, first))
        first += len(case["figures"])
    n_checks = sum(len(_counted(c["checks"])) for c in cases.values())
    n_passed = sum(sum(x["passed"] for x in _counted(c["checks"])) for c in cases.values())
    n_ok = sum(_ok(c) for c in cases.values())
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>Validation report</title>
<style>{STYLE}</style></head><body>
<h1>Validation report</h1>
<p><b>{n_ok} of {len(cases)}</b> cases pass, <b>{n_passed} of {n_checks}</b> checks. Generated
{html.escape(report["generated"])} at resolution <b>{html.escape(report["resolution"])}</b> on
{html.escape(report["machine"])}.</p>
<nav id="summary"><h2>Summary</h2>
<p>One line per case (its name links to its figures): what it is, whether every check passed,
and the number to look at. Each check names its reference under it: a closed form, a
published value, the same model on other meshes or another of its settings, the other
kinematics made of the same fabric, or an invariant of the formulation. The paper cases (bai-*)
reproduce the set-ups of Bai et al.'s figures; their checks are the formulation's invariants, the
runs' convergence and the fibrous runs against the Mindlin one, not the paper's numbers: set
their figures beside the paper's. Their Mindlin shell is made of the fabric's own laws, so that
the runs differ in kinematics alone; hemisphere-forming's Mindlin blank is not: a linear section
at the fabric's initial shear slope (ElasticShell.equivalent), 1.9-4.0 x softer in shear at the
30-40 deg its blank reaches, so that there the material differs as well.</p>
{_summary_table(cases)}</nav>
<details class="introduction"><summary>The kinematics compared: fibrous, fibrous_element,
mindlin</summary>{INTRODUCTION}</details>
{"".join(sections)}
</body></html>
"""
