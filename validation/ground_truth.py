"""The stack as plies beside the two shells: the ground truth of the fibrous kinematics on a
case file (the report's cases plies-heavy-cantilever and plies-bai-5.1).

One case file run three ways on the same mid-surface mesh, supports, loads and solver
(fibreshell.run.run_case, fibreshell.plies.run_plies): the fibrous shell, the Mindlin shell of
the fabric's own laws (the ``laws`` calibration: the same material, so what differs is the
kinematics) and the stack as N frictionless plies (elements.plies.PlyStack, each ply
MindlinShell(ply_fabric)), whose material lines are the directors a stack of sliding plies
really has. The figure is Bai's Figs. 10 and 12 in form (side elevation with the
through-thickness lines, director angle and thickness along the director along the path), the
checks hold the fibrous shell to the plies, and a paragraph says from the numbers what the
fibrous shell gets right and where it departs.
"""

from __future__ import annotations

import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from fibreshell.calibration import Calibration
from fibreshell.case import Case, case_from_data, read_case_data
from fibreshell.compare import COLOURS, kinematics_record, path_figure
from fibreshell.plies import run_plies
from fibreshell.run import Run, run_case
from validation.checks import check
from validation.records import Figure, Outcome

__all__ = ["GroundTruth", "compute", "discussion", "render"]

ROOT = Path(__file__).resolve().parents[1]
LABELS = {
    "fibrous": "FibrousShell",
    "mindlin": "MindlinShell(fabric) (laws calibration)",
    "plies": "plies (frictionless, their material lines)",
}


@dataclass
class GroundTruth:
    """The three runs of a case file, their profiles along the path, and the case."""

    case: Case
    runs: dict[str, Run]
    path: str
    records: dict[str, dict[str, Any]]
    plies: int


def _case(file: str, cells: int, overrides: dict[str, Any] | None = None) -> Case:
    """The case file ``cases/<file>`` with ``cells`` cells along its rectangle."""
    path = ROOT / "cases" / file
    tables = read_case_data(path)
    tables["mesh"]["rectangle"]["nx"] = int(cells)
    for key, value in (overrides or {}).items():
        node = tables
        *parents, last = key.split(".")
        for part in parents:
            node = node[part]
        node[last] = value
    return case_from_data(tables, path)


def compute(
    file: str,
    cells: int,
    plies: int,
    tolerances: dict[str, float],
    plies_solver: dict[str, Any] | None = None,
) -> Outcome:
    """Run ``cases/<file>`` at ``cells`` cells as fibrous, Mindlin (laws) and ``plies`` plies
    and check the fibrous shell against the plies along the case's first path.

    Parameters
    ----------
    file : str
        A case file of cases/ with one fibrous part, a rectangle mesh and a path.
    cells : int
        Cells along the rectangle.
    plies : int
        N, the plies of the stack.
    tolerances : dict
        "angle_deg": largest |fibrous - plies| director angle along the path but its last 20 %
        (deg: the plies' ends fan out there, which is reported, not checked);
        "angle_mean_deg": mean |fibrous - plies| director angle along the whole path (deg);
        "height_mm": largest |fibrous - plies| mid-surface height (mm);
        "thickness": largest |fibrous - plies| thickness along the director but the last 20 %,
        over h; "mindlin_angle_mean_deg": the band (low, high) of the mean |Mindlin - plies|
        director angle (deg) that shows the Mindlin normals do not follow the plies.
    plies_solver : dict or None
        Tables that replace the case's [solver] for the plies (None: the case's).
    """
    case = _case(file, cells)
    plies_case = _case(file, cells, {"solver": plies_solver} if plies_solver else None)
    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(scratch)
        runs = {
            "fibrous": run_case(case, folder / "fibrous", "fibrous", progress=False),
            "mindlin": run_case(
                case, folder / "mindlin", "mindlin", progress=False, calibration=Calibration()
            ),
            "plies": run_plies(plies_case, folder / "plies", plies, progress=False),
        }
    path = next(iter(case.paths))
    records = {name: kinematics_record(case, run)["paths"][path] for name, run in runs.items()}
    data = GroundTruth(case=case, runs=runs, path=path, records=records, plies=plies)
    h = float(case.parts[0]["element"].fabric.thickness)
    differences = _differences(records, h)
    source = (
        f"a peer model of this project: the stack as {plies} frictionless plies "
        "(elements.plies), their material lines"
    )
    low, high = tolerances["mindlin_angle_mean_deg"]
    checks = [
        check(
            "fibrous - plies: largest director angle difference, path without its last 20 % (deg)",
            0.0,
            differences["fibrous"]["angle_inside"],
            tolerances["angle_deg"],
            relative=False,
            source=source,
        ),
        check(
            "fibrous - plies: mean director angle difference along the whole path (deg)",
            0.0,
            differences["fibrous"]["angle_mean"],
            tolerances["angle_mean_deg"],
            relative=False,
            source=source,
        ),
        check(
            "fibrous - plies: largest mid-surface height difference along the path (mm)",
            0.0,
            differences["fibrous"]["height"],
            tolerances["height_mm"],
            relative=False,
            source=source,
        ),
        check(
            "fibrous - plies: largest thickness-along-director difference, path without its "
            "last 20 % (/ h)",
            0.0,
            differences["fibrous"]["thickness_inside"] / h,
            tolerances["thickness"],
            relative=False,
            source=source,
        ),
        check(
            "Mindlin - plies: mean director angle difference along the path (deg), between "
            f"{low:g} and {high:g}",
            0.5 * (low + high),
            differences["mindlin"]["angle_mean"],
            0.5 * (high - low),
            relative=False,
            source=source + ": the Mindlin normals do not follow the slip",
        ),
    ]
    summary = runs["plies"].summary["plies"]
    plies_info = runs["plies"].result.info
    parameters = {
        "case file": f"cases/{file}",
        "cells": cells,
        "plies": plies,
        "ply thickness (mm)": summary["ply_thickness_mm"],
        "Mindlin calibration": Calibration().label(case.parts[0]["element"].fabric),
        "plies: largest gap / overlap between plies (mm)": (
            f"{summary['largest_gap_mm']:.3g} / {summary['largest_overlap_mm']:.3g}"
        ),
        **{
            f"{name} - plies: largest angle / height / thickness difference": (
                f"{d['angle']:.3g} deg / {d['height']:.3g} mm / {d['thickness']:.3g} mm"
            )
            for name, d in differences.items()
        },
        **{f"{name} wall time (s)": f"{run.wall_time:.1f}" for name, run in runs.items()},
    }
    if "iterations_cut" in plies_info:  # Static's Newton iterations, those of cut attempts apart
        parameters["plies: Newton iterations converged / in cut attempts"] = (
            f"{int(runs['plies'].result.steps)} / {int(plies_info['iterations_cut'])}"
        )
    return Outcome(
        converged=all(run.result.converged for run in runs.values()),
        wall_time_s=sum(run.wall_time for run in runs.values()),
        steps=sum(int(run.result.steps) for run in runs.values()),
        solver="; ".join(
            f"{name}: {run.summary.get('solver')}"
            + (f" (stopped: {run.error})" if run.error else "")
            for name, run in runs.items()
        ),
        parameters=parameters,
        checks=checks,
        discussion=_stopped(runs) + discussion(records, differences, h, plies, summary),
        data=data,
    )


def _stopped(runs: dict[str, Run]) -> str:
    """A first paragraph naming any run that stopped before its goal (its last good state is
    what the figure and the numbers show)."""
    stopped = [
        f"{LABELS[name]} stopped at load factor {run.result.frames[-1].load_factor:.3g} "
        f"({run.error.split('. ')[0]})"
        for name, run in runs.items()
        if run.error
    ]
    if not stopped:
        return ""
    return (
        "Not converged: "
        + "; ".join(stopped)
        + ". The numbers below are those of the last good state.\n\n"
    )


def _differences(records: dict[str, dict[str, Any]], h: float) -> dict[str, dict[str, Any]]:
    """Per shell against the plies, node by node along the path: the largest |difference| of
    the director angle (deg), of the mid-surface height (mm, at the plies' horizontal
    positions), of the thickness along the director (mm), and where (s, mm) each is."""
    base = records["plies"]
    out = {}
    order = np.argsort(base["horizontal"])
    for name in ("fibrous", "mindlin"):
        line = records[name]
        angle = np.abs(np.asarray(line["director_angle_deg"]) - base["director_angle_deg"])
        z = np.interp(
            line["horizontal"], np.asarray(base["horizontal"])[order], np.asarray(base["z"])[order]
        )
        height = np.abs(np.asarray(line["z"]) - z)
        thickness = np.abs(np.asarray(line["thickness"]) - base["thickness"])
        s = np.asarray(line["s"])
        inside = s <= 0.8 * s.max()
        out[name] = {
            "angle_inside": float(angle[inside].max()),
            "thickness_inside": float(thickness[inside].max()),
            "angle": float(angle.max()),
            "angle_at": float(s[np.argmax(angle)]),
            "angle_mean": float(angle.mean()),
            "height": float(height.max()),
            "height_at": float(s[np.argmax(height)]),
            "thickness": float(thickness.max()),
            "thickness_at": float(s[np.argmax(thickness)]),
        }
    return out


def discussion(records, differences, h: float, plies: int, summary: dict) -> str:
    """What the figure shows, from the numbers of the run."""
    f, m = differences["fibrous"], differences["mindlin"]
    p = records["plies"]
    tilt = np.asarray(p["director_tilt_deg"])
    thick = np.asarray(p["thickness"])
    first = (
        f"The {plies} plies slide on each other: their material lines tilt from the stack's "
        f"normal by up to {np.nanmax(tilt):.1f} deg and the stack measured along them reaches "
        f"{thick.max():.2f} mm ({thick.max() / h:.2f} h), the thickness along the normal "
        f"staying h (largest gap between plies {summary['largest_gap_mm']:.2g} mm, overlap "
        f"{summary['largest_overlap_mm']:.2g} mm)."
    )
    second = (
        f"The fibrous shell's directors follow them: the director angle departs from the plies' "
        f"by {f['angle']:.2f} deg at most (at s = {f['angle_at']:.0f} mm; {f['angle_mean']:.2f} "
        f"deg on average), the thickness along the director by {f['thickness']:.2f} mm "
        f"({f['thickness'] / h:.1%} of h, at s = {f['thickness_at']:.0f} mm), and the "
        f"mid-surfaces by {f['height']:.2f} mm (at s = {f['height_at']:.0f} mm). The Mindlin "
        f"shell of the same laws keeps its normals: its director angle departs from the plies' "
        f"by {m['angle']:.1f} deg (at s = {m['angle_at']:.0f} mm) and its thickness along the "
        f"director stays h, {m['thickness']:.2f} mm short of the plies' at s = "
        f"{m['thickness_at']:.0f} mm, although its mid-surface is within {m['height']:.2f} mm: "
        "equal mid-surfaces, different normals, as Bai found with Abaqus S3."
    )
    length = float(np.max(p["s"]))
    gaps = np.asarray(p.get("gap_max_mm", np.zeros(len(tilt))))
    if f["angle_at"] > 0.8 * length:
        where = (
            f"It departs most near the end of the path (s = {f['angle_at']:.0f} of "
            f"{length:.0f} mm), where the plies' ends fan out: nothing there holds them on one "
            f"line, they open (up to {gaps[-3:].max():.2g} mm between plies over the last "
            "nodes) and their material line bends, while the fibrous shell keeps the thickness "
            "along the normal, the closed stack Bai's kinematics assume. Over the first 80 % "
            f"of the path the director angles agree within {f['angle_inside']:.2f} deg and the "
            f"thicknesses within {f['thickness_inside'] / h:.1%} of h."
        )
    else:
        where = (
            f"It departs most inside the strip (s = {f['angle_at']:.0f} of {length:.0f} mm), "
            "where the slip accumulated from the clamp is largest; over the first 80 % of the "
            f"path the director angles agree within {f['angle_inside']:.2f} deg."
        )
    return "\n\n".join([first, second, where])


def render(data: GroundTruth, out_dir: Path, name: str) -> list[Figure]:
    """The comparison figure (fibreshell.compare.path_figure: side elevation with the
    through-thickness lines, director angle, tilt and thickness along the director), named
    after the case, with its caption, and each run's final frame as
    ``<name>-<kinematics>.vtu``."""
    figure = path_figure(
        data.case, data.runs, data.path, out_dir, Calibration().label(
            data.case.parts[0]["element"].fabric
        ) + f"; plies: {data.plies} frictionless plies, their material lines",
    )  # fmt: skip
    target = out_dir / f"{name}-mid-surface-directors-and-thickness-along-{data.path}.png"
    figure.replace(target)
    assert set(data.runs) <= set(COLOURS)
    for kinematics, run in data.runs.items():  # the plies' on their own N-ply mesh
        run.result.write(out_dir / f"{name}-{kinematics}.vtu")
    return [
        Figure(
            target.name,
            f"Along the path '{data.path}': the side elevation with the through-thickness "
            "lines, the director angle, its tilt from the normal (not drawn at the clamped "
            "node, where the director is imposed) and the thickness along it, "
            f"for the fibrous shell, the Mindlin shell and the stack as {data.plies} "
            "frictionless plies (their material lines, the reference). The fibrous curves "
            "should follow the plies; the Mindlin directors stay on the normal.",
        )
    ]
