"""``fibreshell compare``: one case in several kinematics on the same mesh, supports, loads and
solver, side by side: the fibrous shell, the Mindlin shell of a stated calibration
(fibreshell/calibration.py: the fabric's own laws by default) and the stack as plies.

``comparison.json`` has one schema (README "comparison.json"):

    {"case": title, "calibration": {"name", "rule", "numbers"},
     "kinematics": {NAME: {"converged", "stopped", "final_load_factor", "wall_time_s",
                           "paths": {PATH: {"s", "x", "y", "z", "horizontal",
                                            "director_angle_deg", "director_tilt_deg",
                                            "thickness"}},
                           "sets": {SET: {"displacement": [x, y, z]}},
                           "reactions": {SET: [x, y, z]}}},
     "differences": {NAME: {"paths": {PATH: {"z_max_mm", "director_angle_max_deg",
                                             "thickness_max_mm"}}}},  (NAME against fibrous)
                    or {NAME: {"stopped": "mindlin stopped at load factor 0", "paths": {}}}
                    where either run stopped (its state is not a result to compare)
     "figures": [...]}
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from fibreshell.calibration import CALIBRATIONS, Calibration
from fibreshell.case import Case
from fibreshell.confidence import below_zero, interval_text
from fibreshell.folder_lock import folder_lock
from fibreshell.outputs import IDENTIFY_FILES, MATERIAL_LINES, remove_run_folder
from fibreshell.run import (
    Run,
    case_held_directors,
    profile,
    run_case,
    section_thickness,
    strict_json,
)

__all__ = [
    "COLOURS", "DEFAULT_KINEMATICS", "KINEMATICS", "calibration_lines", "compare_case",
    "fit_calibration", "kinematics_record", "path_figure", "remove_comparison", "stopped_text",
    "summary_lines", "view_3d",
]  # fmt: skip

KINEMATICS = ("fibrous", "mindlin", "plies")
#: How a comparison is given the Mindlin section's numbers a fabric's bending laws with a toe
#: have no default for (Calibration.check_section).
COMPARE_ROUTE = (
    "give them to the comparison: fibreshell compare --transverse-shear S --twisting D "
    "(compare_case(..., transverse_shear=S, twisting=D) in Python)"
)
DEFAULT_KINEMATICS = ("fibrous", "mindlin")
COLOURS = {"fibrous": "tab:blue", "mindlin": "tab:orange", "plies": "tab:green"}
# Sized for a report page: 9 in at 110 dpi is 990 px, shown at about 780 px on an 800-px
# screen, where the smallest text (10 pt) still reads as 9 pt.
PATH_FIGURE_SIZE = (9.0, 7.6)
PATH_FIGURE_DPI = 110
# The characters of 11-pt text across the figure and across one panel of it.
TITLE_WIDTH, PANEL_TITLE_WIDTH = 100, 46


def _fabric(case: Case):
    for part in case.parts:
        fabric = getattr(part["element"], "fabric", None)
        if fabric is not None:
            return fabric
    return None


def _kinematics(names: Sequence[str] | str) -> tuple[str, ...]:
    if isinstance(names, str):
        names = [n.strip() for n in names.split(",") if n.strip()]
    chosen = tuple(dict.fromkeys(names))
    unknown = [n for n in chosen if n not in KINEMATICS]
    if unknown or not chosen:
        raise ValueError(
            f"kinematics: expected a subset of {', '.join(KINEMATICS)}, got {list(names)!r}"
        )
    return chosen


def compare_case(
    case: Case,
    out: Path,
    progress: bool | None = None,
    calibration: Calibration | str = "laws",
    kinematics: Sequence[str] | str = DEFAULT_KINEMATICS,
    plies: int | None = None,
    shear_ratio: float | None = None,
    transverse_shear: float | None = None,
    twisting: float | None = None,
    fit_path: str | None = None,
    fit_evaluations: int = 34,
    scheduler: str | None = None,
    workers: int | None = None,
) -> dict[str, Run]:
    """Run ``case`` in each of ``kinematics`` into ``out/<name>`` and write
    ``out/comparison.json`` (module docstring), ``out/view-3d.png`` (the deformed shells at
    true scale, the directors drawn across the thickness along the paths) and one figure per
    path (``out/path-<name>.png``: side elevation with the through-thickness lines, director
    angle, director tilt from the normal, thickness along the director). Every figure and the
    JSON state the Mindlin calibration and the numbers it chose. What an earlier comparison
    wrote in ``out`` is removed first (``remove_comparison``): the folder holds this one's.
    ``out`` is held from then on (fibreshell.folder_lock): another command writing there is
    refused, and this one is refused where another holds it.

    Parameters
    ----------
    case : Case
    out : pathlib.Path
    progress : bool or None
        The solvers' progress lines.
    calibration : Calibration or str
        "laws" (default), "fit" or "initial-slope" (fibreshell/calibration.py).
    kinematics : sequence of str or a comma-separated str
        Any of "fibrous", "mindlin", "plies" (default fibrous and mindlin).
    plies : int or None
        Plies of the "plies" kinematics (default: the fabric's ply count where it has one).
    shear_ratio : float or None
        G13 / E of the "initial-slope" calibration (default 0.5).
    transverse_shear, twisting : float or None
        S (N/mm) and D_t (N mm) of the "laws" and "fit" sections (default 5 B0 / h^2 and
        B0 / 2, B0 the initial bending slope; a fabric whose bending laws have a toe, B0 = 0,
        needs both). The fit starts from S and keeps D_t.
    fit_path : str or None
        The path whose mid-surface the "fit" calibration matches (default: the first).
    fit_evaluations : int
        Model evaluations the "fit" may make in all, its Jacobians' included
        (fibreshell.identify.identify's ``max_evaluations``; at least 11 for its two values).
    scheduler, workers
        Where the "fit" runs its evaluations: a Dask scheduler's address, or the worker
        processes of a LocalCluster started here (``fibreshell.cluster.dask_client``).

    Raises
    ------
    ValueError
        A case without a fibrous part (nothing to calibrate on or to split into plies), an
        unknown kinematics or calibration, a calibration number it refuses (a negative
        ``shear_ratio``), a bad ply count or fit path: all before the first run; ``out`` or
        a kinematics' folder in it held by another command (fibreshell.folder_lock.FolderInUse).
    """
    chosen = _kinematics(kinematics)
    if isinstance(calibration, str) and calibration not in CALIBRATIONS:
        raise ValueError(
            f"calibration must be one of {', '.join(CALIBRATIONS)}, got {calibration!r}"
        )
    fabric = _fabric(case)
    if not case.has_fibrous or fabric is None:
        raise ValueError(
            f'{case.path}: compare needs a fibrous part (element = "fibrous"): the Mindlin '
            "shell is calibrated on its fabric and the plies split it"
        )
    fitting = calibration == "fit" or (
        isinstance(calibration, Calibration)
        and calibration.name == "fit"
        and not calibration.fitted
    )
    # Every option is checked before the first run: a mistake in the last one must not cost
    # the fibrous run first.
    if isinstance(calibration, Calibration):
        rule = calibration
    else:
        rule = Calibration.from_options(calibration, shear_ratio)
    if transverse_shear is not None or twisting is not None:
        rule = Calibration.from_options(rule, None, None, transverse_shear, twisting)
    if "mindlin" in chosen:
        rule.check_section(fabric, COMPARE_ROUTE)
    if fitting and "mindlin" in chosen:
        _check_fit(case, fit_path, fit_evaluations)
        _check_cluster(scheduler, workers)
    elif scheduler is not None or workers is not None:
        raise ValueError(
            "scheduler and workers are where the fit calibration runs (calibration 'fit' with "
            f"the mindlin kinematics); got scheduler={scheduler!r}, workers={workers!r} "
            "without it"
        )
    if "plies" in chosen:
        from fibreshell.plies import ply_stack

        ply_stack(case, plies)  # the count and the case's fitness for plies, now
    out.mkdir(parents=True, exist_ok=True)
    with folder_lock(out, f"the comparison of {str(case.path)!r}"):
        remove_comparison(out)
        runs: dict[str, Run] = {}
        if "fibrous" in chosen or (fitting and "mindlin" in chosen):
            runs["fibrous"] = run_case(case, out / "fibrous", "fibrous", progress)
        if fitting and "mindlin" in chosen:
            rule = fit_calibration(
                case, runs["fibrous"], out / "fit", fit_path, fit_evaluations, start=rule,
                scheduler=scheduler, workers=workers,
            )  # fmt: skip
        if "mindlin" in chosen:
            runs["mindlin"] = run_case(case, out / "mindlin", "mindlin", progress, calibration=rule)
        if "plies" in chosen:
            from fibreshell.plies import run_plies

            runs["plies"] = run_plies(case, out / "plies", plies, progress)
        records = {name: kinematics_record(case, run) for name, run in runs.items()}
        comparison: dict[str, Any] = {
            "case": case.title,
            "calibration": (
                {"kinematics": "mindlin", **rule.describe(fabric)}
                if "mindlin" in runs
                else {
                    "kinematics": "mindlin",
                    "name": None,
                    "rule": "no Mindlin run",
                    "numbers": {},
                }
            ),
            "kinematics": records,
            "differences": _differences(records),
            "figures": [],
        }
        if "plies" in runs:
            comparison["plies"] = runs["plies"].summary.get("plies", {})
        label = rule.label(fabric) if "mindlin" in runs else ""
        comparison["figures"].append(view_3d(case, runs, out, label).name)
        for name in case.paths:
            comparison["figures"].append(path_figure(case, runs, name, out, label).name)
        (out / "comparison.json").write_text(strict_json(comparison))
        return runs


def remove_comparison(out: Path) -> None:
    """Remove from ``out`` what an earlier comparison wrote there, so that it holds only the
    new one's results (an old ``mindlin/`` beside a new fibrous-only comparison would be read
    as this one's): the folders of each kinematics and of the fit, emptied of the files a run
    (or the fit) writes and then removed unless a user's own file is left in them, and the
    figures the earlier comparison.json lists, with it."""
    for name in KINEMATICS:
        remove_run_folder(out / name, extra=(MATERIAL_LINES,) if name == "plies" else ())
    remove_run_folder(out / "fit", extra=IDENTIFY_FILES)
    try:
        earlier = json.loads((out / "comparison.json").read_text()).get("figures", [])
    except (OSError, ValueError, AttributeError):
        return
    for figure in earlier if isinstance(earlier, list) else []:
        # only a figure's plain name, as compare_case writes it (never a path elsewhere)
        if isinstance(figure, str) and Path(figure).name == figure and figure.endswith(".png"):
            (out / figure).unlink(missing_ok=True)
    (out / "comparison.json").unlink()


# The fit's two values (bending_scale, transverse_shear): 5 n + 1 evaluations at the least
# (fibreshell.identify.identify).
FIT_FEWEST_EVALUATIONS = 11


def _check_fit(case: Case, path: str | None, max_evaluations: int) -> str:
    """The path the fit matches (``path``, or the case's first), or ValueError: no path, an
    unknown one, a case not read from a file, a count of evaluations that is not one."""
    if not case.paths:
        raise ValueError(
            f"{case.path}: the fit calibration matches the mid-surface along a path; the case "
            "has no [output] paths"
        )
    path = path or next(iter(case.paths))
    if path not in case.paths:
        raise ValueError(f"no path {path!r} in the case; its paths: {', '.join(case.paths)}")
    if not Path(case.path).is_file():
        raise ValueError(f"the fit calibration reruns the case file; {case.path} is not a file")
    if (
        isinstance(max_evaluations, bool)
        or not isinstance(max_evaluations, int | np.integer)
        or max_evaluations < FIT_FEWEST_EVALUATIONS
    ):
        raise ValueError(
            f"fit evaluations must be an integer >= {FIT_FEWEST_EVALUATIONS} (a point and its "
            f"2 shifted points, and 8 for the Jacobian at the end), got {max_evaluations!r}"
        )
    return path


# Seconds a scheduler given for the fit has to answer before the fibrous run.
SCHEDULER_TIMEOUT_S = 10.0


def _check_cluster(scheduler: str | None, workers: int | None) -> None:
    """ValueError for a ``workers`` that is not a count, both given, or a scheduler that
    does not answer: before the fibrous run the fit starts from, not after it."""
    from fibreshell.cluster import check_workers, dask_client

    check_workers(workers)
    if scheduler is not None:
        # Connects, or names the address it could not reach.
        with dask_client(scheduler, workers, timeout=SCHEDULER_TIMEOUT_S):
            pass


def fit_calibration(
    case: Case,
    fibrous: Run,
    out: Path | None = None,
    path: str | None = None,
    max_evaluations: int = 34,
    start: Calibration | None = None,
    scheduler: str | None = None,
    workers: int | None = None,
) -> Calibration:
    """Bai's calibration: the "laws" section's bending scale and transverse shear stiffness
    fitted by least squares (``fibreshell.identify``, each run a Dask task) so that the
    Mindlin mid-surface height matches the fibrous one's along ``path`` at the fibrous
    nodes' horizontal positions, from ``start``'s numbers (default: the laws as given, the
    default transverse shear). The evaluations run on the Dask scheduler at ``scheduler``, or
    on a LocalCluster of ``workers`` processes started here (``fibreshell.cluster.dask_client``).

    Returns
    -------
    Calibration
        name "fit", the fitted numbers, and in ``fitted`` the values with their 95 %
        confidence intervals, the RMS height residual (mm), the path, the evaluations.

    Raises
    ------
    ValueError
        No path to fit along, or a case not read from a file.
    """
    from elements.mindlin_fabric import default_transverse_shear
    from fibreshell.identify import identify

    path = _check_fit(case, path, max_evaluations)
    line = fibrous.summary["paths"][path]
    n = len(line["horizontal"])
    data = {
        "x": [float(v) for v in line["horizontal"]],
        "z": [float(v) for v in line["z"]],
        "kinematics": ["mindlin"] * n,
        "calibration": ["laws"] * n,
    }
    if start is not None and start.twisting is not None:  # kept, not fitted (a toe's D_t)
        data["twisting"] = [start.twisting] * n
    fabric = _fabric(case)
    first = start or Calibration(name="fit")
    values0: dict[str, float | None] = {
        "bending_scale": first.bending_scale,
        "transverse_shear": first.transverse_shear or default_transverse_shear(fabric),
    }
    found = identify(
        case.path, data, values0, path=path, out=out, max_evaluations=max_evaluations,
        progress=False, scheduler=scheduler, workers=workers,
    )  # fmt: skip
    values = dict(zip(found.keys, (float(v) for v in found.values)))
    fitted = {
        "path": path,
        "target": "the fibrous shell's mid-surface height z at its nodes' horizontal positions",
        "values": values,
        "confidence_95": {
            k: [float(a), float(b)] for k, (a, b) in zip(found.keys, found.intervals)
        },
        "start": dict(zip(found.keys, (float(v) for v in found.start))),
        "residual_rms_mm": float(found.residual_rms),
        "success": bool(found.success),
        "message": found.message,
        "evaluations": int(found.evaluations),
        "runs": int(found.runs),
        "wall_time_s": float(found.wall_time_s),
    }
    return Calibration(
        name="fit",
        bending_scale=values["bending_scale"],
        transverse_shear=values["transverse_shear"],
        twisting=first.twisting,
        fitted=fitted,
    )


def kinematics_record(case: Case, run: Run) -> dict[str, Any]:
    """One kinematics' entry of comparison.json: how it ended, the profiles along the case's
    paths (with the director's tilt from the surface normal, deg), the mean displacement of
    each history set and the reaction sums."""
    summary = run.summary
    h = section_thickness(case)
    paths = run.profiles if run.profiles is not None else {
        name: _path_record(case, run, name, h) for name in case.paths
    }  # fmt: skip
    return {
        "converged": summary.get("converged"),
        "stopped": summary.get("stopped"),
        "final_load_factor": summary.get("final_load_factor"),
        "wall_time_s": run.wall_time,
        "paths": paths,
        "sets": {
            name: {"displacement": value}
            for name, value in summary.get("mean_displacements", {}).items()
        },
        "reactions": summary.get("reactions", {}),
    }


def _path_record(case: Case, run: Run, name: str, h: float) -> dict[str, Any]:
    line = profile(case, run.result, name, h)
    record = {k: v for k, v in line.items() if k not in ("directors", "director_horizontal")}
    nodes = case.paths[name]
    try:
        tilt = np.array(run.result.field("director_tilt_deg")[nodes], dtype=float)
    except (KeyError, ValueError):
        tilt = np.full(len(nodes), np.nan)
    # a clamped node's director is imposed: its tilt is the clamp's one-sided facets' (a
    # Mindlin strip's 27.7 deg at the clamp of bai-5.1), left out as the summary leaves it
    tilt[np.isin(nodes, case_held_directors(case))] = np.nan
    record["director_tilt_deg"] = tilt
    return record


def stopped_text(name: str, record: dict[str, Any]) -> str | None:
    """ "mindlin stopped at load factor 0.25" for a kinematics whose run stopped before its end
    (``record``: its entry of comparison.json, ``kinematics_record``), else None: its last
    state is where the solver gave up, not the case's answer."""
    if not record.get("stopped"):  # the solver's error, None for a run that reached its end
        return None
    factor = record.get("final_load_factor")
    at = f" at load factor {factor:.4g}" if isinstance(factor, int | float) else ""
    return f"{name} stopped{at}"


def _differences(records: dict[str, dict[str, Any]]) -> dict[str, Any]:
    """Per kinematics other than fibrous, per path (``records``: kinematics -> its entry of
    comparison.json, ``kinematics_record``): the largest |difference| from the fibrous shell
    of the mid-surface height (mm, of the same material points: at the fibrous nodes'
    reference arc length s, over the s both paths cover, never held past an end), of the
    director angle (deg) and of the thickness along the director (mm), node by node. Where
    either run stopped, no numbers: {"stopped": "... stopped at load factor x", "paths": {}}
    (a stopped run's state compared with a finished one's read as a result; two stopped ones
    at load factor 0 as agreement)."""
    if "fibrous" not in records:
        return {}
    out: dict[str, Any] = {}
    for name in records:
        if name == "fibrous":
            continue
        out[name] = {"paths": {}}
        stopped = [
            text for text in (stopped_text(k, records[k]) for k in ("fibrous", name)) if text
        ]
        if stopped:
            out[name]["stopped"] = " and ".join(stopped)
            continue
        for path, line in records[name]["paths"].items():
            base = records["fibrous"]["paths"][path]
            # The heights of the same material points: at the fibrous nodes' reference arc
            # length s, over the s both paths cover. At the same horizontal position the
            # shorter reach of the profile that sags more was held at its last height past
            # its end (np.interp), and a steep profile's chords between nodes read its
            # curvature (0.3 mm and 0.8 mm on the G1151 strip, 0.61 at the same s).
            order = np.argsort(line["s"])
            along = np.asarray(line["s"], dtype=float)[order]
            at = np.asarray(base["s"], dtype=float)
            common = (at >= along[0] - 1e-9 * along[-1]) & (at <= along[-1] * (1 + 1e-9))
            z = np.interp(at[common], along, np.asarray(line["z"])[order])
            out[name]["paths"][path] = {
                "z_max_mm": float(np.max(np.abs(z - np.asarray(base["z"])[common]))),
                "director_angle_max_deg": float(
                    np.max(
                        np.abs(np.asarray(line["director_angle_deg"]) - base["director_angle_deg"])
                    )
                ),
                "thickness_max_mm": float(
                    np.max(np.abs(np.asarray(line["thickness"]) - base["thickness"]))
                ),
            }
    return out


def calibration_lines(
    case: Case,
    calibration: str = "laws",
    shear_ratio: float | None = None,
    kinematics: Sequence[str] | str = DEFAULT_KINEMATICS,
    transverse_shear: float | None = None,
    twisting: float | None = None,
) -> list[str]:
    """What ``fibreshell compare`` prints before its runs: the Mindlin calibration it will
    use, its rule and the numbers it gives the section (the bending laws, S, ...); for "fit"
    the rule alone, its values being known after the fibrous run (``summary_lines``). Nothing
    without a Mindlin run or a fabric to calibrate on (``compare_case`` then says why).

    Raises
    ------
    ValueError
        An unknown kinematics or calibration, a calibration number it refuses, a section it
        cannot make (bending laws with a toe without S and D_t: COMPARE_ROUTE)."""
    if "mindlin" not in _kinematics(kinematics) or _fabric(case) is None:
        return []
    rule = Calibration.from_options(calibration, shear_ratio, None, transverse_shear, twisting)
    rule.check_section(_fabric(case), COMPARE_ROUTE)
    if rule.name == "fit":
        return [
            f"calibration: fit: {rule.describe(None)['rule']}",
            "  its values: once fitted, after the fibrous run",
        ]
    return _calibration_lines(rule.describe(_fabric(case)))


def _calibration_lines(calibration: dict[str, Any]) -> list[str]:
    """The calibration of comparison.json (``Calibration.describe``) as printed lines."""
    if calibration["name"] is None:
        return ["calibration: none (no Mindlin run)"]
    lines = [f"calibration: {calibration['name']}: {calibration['rule']}"]
    for key, value in calibration["numbers"].items():
        if key == "fit":
            lines.append(
                f"  fitted along path {value['path']!r}: RMS height residual "
                f"{value['residual_rms_mm']:.3g} mm in {value['evaluations']} evaluations"
            )
            if not value.get("success", True):
                # identify's message says which values these are (the best evaluated)
                said = str(value.get("message", "")).rstrip(".")
                lines.append(
                    f"  NOT CONVERGED: {said}: give the fit more evaluations "
                    "(fibreshell compare --fit-evaluations)"
                )
            for name, ends in value["confidence_95"].items():
                found = value["values"][name]
                if ends is None or not all(e is not None and np.isfinite(e) for e in ends):
                    lines.append(f"    {name} = {found:.4g} (no interval: the data cannot tell)")
                    continue
                low, shown, high = interval_text(found, *ends)
                lines.append(f"    {name} = {shown} (95 %: {low} to {high}){below_zero(ends)}")
        else:
            lines.append(f"  {key} = {value if isinstance(value, str) else f'{value:.4g}'}")
    return lines


def summary_lines(comparison: dict[str, Any], calibration: bool = True) -> list[str]:
    """What ``fibreshell compare`` prints after its runs: the calibration and its numbers
    (unless ``calibration`` is false: printed before the runs, ``calibration_lines``), then
    per path the largest differences from the fibrous shell."""
    lines = _calibration_lines(comparison["calibration"]) if calibration else []
    for name, record in comparison["differences"].items():
        if record.get("stopped"):
            lines.append(f"{name} - fibrous: not compared: {record['stopped']}")
        for path, d in record["paths"].items():
            lines.append(
                f"{name} - fibrous along {path}: height {d['z_max_mm']:.3g} mm, director angle "
                f"{d['director_angle_max_deg']:.3g} deg, thickness {d['thickness_max_mm']:.3g} mm"
                " (largest)"
            )
    return lines


def path_figure(case: Case, runs: dict[str, Run], name: str, out: Path, label: str = "") -> Path:
    """The figure of path ``name``, four panels in two rows: (a) side elevation, the
    mid-surface of each kinematics and its through-thickness lines (the directors drawn
    across the thickness along them, at true scale); (b) director angle to the horizontal;
    (c) director tilt from the surface normal; (d) thickness along the director.
    ``label``: the calibration, in the title. Written as ``path-<name>.png`` in ``out``,
    990 px wide (PATH_FIGURE_SIZE at PATH_FIGURE_DPI)."""
    import textwrap

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, grid = plt.subplots(2, 2, figsize=PATH_FIGURE_SIZE, layout="constrained")
    axes = grid.ravel()
    for kinematics, run in runs.items():
        record = kinematics_record(case, run)
        line = record["paths"][name]
        colour = COLOURS[kinematics]
        stopped = stopped_text(kinematics, record)  # its state is not a result: said
        legend = f"{stopped} (not a result)" if stopped else kinematics
        horizontal = np.asarray(line["horizontal"])
        z = np.asarray(line["z"])
        angle = np.radians(np.asarray(line["director_angle_deg"]))
        thickness = np.asarray(line["thickness"])
        style = "--" if stopped else "-"
        axes[0].plot(horizontal, z, style, color=colour, label=legend)
        half = 0.5 * thickness[:, None] * np.column_stack([np.cos(angle), np.sin(angle)])
        ends_u = np.column_stack([horizontal - half[:, 0], horizontal + half[:, 0]])
        ends_z = np.column_stack([z - half[:, 1], z + half[:, 1]])
        axes[0].plot(ends_u.T, ends_z.T, color=colour, linewidth=0.8)
        axes[1].plot(line["s"], line["director_angle_deg"], style, color=colour, label=legend)
        axes[2].plot(line["s"], line["director_tilt_deg"], style, color=colour, label=legend)
        axes[3].plot(line["s"], thickness, style, color=colour, label=legend)
    axes[0].set_aspect("equal", adjustable="datalim")
    titles = (
        f"(a) side elevation of path '{name}', true scale",
        "(b) director angle to the horizontal",
        "(c) director tilt from the surface normal (clamped nodes left out)",
        "(d) thickness along the director",
    )
    labels = (
        ("horizontal distance along the path (mm)", "z (mm)"),
        ("s, reference arc length (mm)", "degrees"),
        ("s, reference arc length (mm)", "degrees"),
        ("s, reference arc length (mm)", "mm"),
    )
    for axis, title, (xlabel, ylabel) in zip(axes, titles, labels):
        axis.set_title(textwrap.fill(title, PANEL_TITLE_WIDTH), fontsize=11)
        axis.set(xlabel=xlabel, ylabel=ylabel)
        axis.grid(True, alpha=0.3)
        axis.legend(fontsize=10)
    lines = [f"{case.title}: {', '.join(runs)}", *([label] if label else [])]
    figure.suptitle("\n".join(textwrap.fill(text, TITLE_WIDTH) for text in lines), fontsize=11)
    path = out / f"path-{name}.png"
    figure.savefig(path, dpi=PATH_FIGURE_DPI)
    plt.close(figure)
    return path


def view_3d(case: Case, runs: dict[str, Run], out: Path, label: str = "") -> Path:
    """The deformed shells side by side at true scale (equal axes), the directors drawn
    across the thickness at the nodes of the paths."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import MaxNLocator

    h = section_thickness(case)
    figure = plt.figure(figsize=(7 * len(runs), 5.5), constrained_layout=True)
    everything = np.vstack([run.result.positions for run in runs.values()])
    low, high = everything.min(axis=0) - h, everything.max(axis=0) + h
    for i, (kinematics, run) in enumerate(runs.items()):
        axis = figure.add_subplot(1, len(runs), i + 1, projection="3d")
        x = run.result.positions
        triangles = run.result.mesh.triangles  # the plies' own mesh for the plies
        if len(triangles):
            axis.plot_trisurf(
                x[:, 0], x[:, 1], x[:, 2], triangles=triangles, alpha=0.35,
                color=COLOURS[kinematics], linewidth=0.1, edgecolor="0.4",
            )  # fmt: skip
        if run.profiles is None:
            thickness = run.result.thickness
            for nodes in case.paths.values():
                t = thickness[nodes] if thickness is not None else np.full(len(nodes), h)
                d = run.result.directors[nodes]
                for a, b in zip(x[nodes] - 0.5 * t[:, None] * d, x[nodes] + 0.5 * t[:, None] * d):
                    axis.plot(*np.column_stack([a, b]), color="k", linewidth=1.2)
        for setter, a, b in zip((axis.set_xlim, axis.set_ylim, axis.set_zlim), low, high):
            setter(a, b)
        axis.set_box_aspect(np.maximum(high - low, 1e-9))
        axis.view_init(elev=22, azim=-130)
        for ticks in (axis.xaxis, axis.yaxis, axis.zaxis):  # readable ticks at true scale
            ticks.set_major_locator(MaxNLocator(nbins=4))
        axis.set(xlabel="x (mm)", ylabel="y (mm)", zlabel="z (mm)")
        stopped = stopped_text(kinematics, run.summary)
        axis.set_title(
            f"{stopped}: its last state, not a result" if stopped
            else f"{kinematics}: deformed, true scale"
        )  # fmt: skip
    if label:
        figure.suptitle(label)
    path = out / "view-3d.png"
    figure.savefig(path, dpi=100)
    plt.close(figure)
    return path
