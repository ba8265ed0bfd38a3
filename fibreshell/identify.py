"""Identification: the values of some keys of a case file that make its runs match measured
data, by nonlinear least squares (``scipy.optimize.least_squares``) with a forward-difference
Jacobian whose columns are run as parallel Dask tasks.

The measured data is a CSV file (or a dict of columns). Its columns are of two kinds:

- conditions: dotted keys of the case (``mesh.rectangle.lx``) or run options (``kinematics``,
  ``shear_ratio``); the rows with the same conditions are one run. A file without conditions
  is one run.
- responses, names without a dot: either ``x`` and ``z``, a side profile measured along the
  case's path (``--path``; the model's height z at the horizontal position x along the path,
  mm, in the final frame), or columns of ``sweep.csv``'s summary rows
  (``displacement_tip_z``, ``reaction_left_z``, ...) compared with the final frame's.

The residual of a row is model minus measured. The parameters are fitted as the logarithms
of their ratios to the starting values, p = ln(theta / theta_0): keys of any magnitude are
scaled alike, a value keeps its sign (a stiffness stays positive), and a response that goes
as a power of a stiffness (a deflection as 1 / B) is nearly linear in p.
With m residuals and n parameters, the covariance of the fit is
s^2 (J^T J)^-1 with s^2 = |r|^2 / (m - n), and the 95 % confidence interval of each value is
theta +- t(0.975, m - n) sigma (Gauss-Newton's linearisation at the solution).
"""

from __future__ import annotations

import csv
import inspect
import time
from contextlib import nullcontext
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from fibreshell import registry
from fibreshell.case import case_from_data, read_case_data
from fibreshell.cluster import Failure, dask_client, map_tasks
from fibreshell.confidence import below_zero, interval_text
from fibreshell.folder_lock import folder_lock
from fibreshell.identifiability import (
    CORRELATION_BOUND,
    WIDEST,
    combination_text,
    determinacy,
    reduced_combinations,
)
from fibreshell.outputs import IDENTIFY_FILES
from fibreshell.responses import mixed_units_warning, response_residuals
from fibreshell.run import strict_json
from fibreshell.sweep import RUN_KEYS, apply_overrides, read_value, run_variant, summary_row

__all__ = [
    "FitFailed", "Identification", "figure", "format_result", "identify", "read_measurements",
    "start_values",
]  # fmt: skip

CONFIDENCE = 0.95


class FitFailed(RuntimeError):
    """A run of the fit failed (the solver stopped, or its worker died): the message names
    the values it was run with and its error."""


@dataclass
class Identification:
    """The fitted values of ``keys`` (``values``), their standard errors and 95 % confidence
    intervals (``intervals``: (n, 2), NaN where the data cannot tell: as many residuals as
    parameters, or a singular Jacobian), the starting values, the RMS residual (data units;
    in sigmas when ``sigma`` is given), how the optimiser ended, the number of model
    evaluations and of runs (Dask tasks), the wall time (s); ``conditions``, ``measured``,
    ``fitted`` and ``initial`` per data row for figures, and ``profiles`` (fitted, initial):
    per condition group the model's path (horizontal, z) for a profile fit; ``by_response``:
    per response column its RMS residual and its measured values' RMS
    (fibreshell.responses.response_residuals)."""

    keys: list[str]
    start: np.ndarray
    values: np.ndarray
    standard_errors: np.ndarray
    intervals: np.ndarray
    residual_rms: float
    success: bool
    message: str
    evaluations: int
    runs: int
    wall_time_s: float
    responses: list[str]
    conditions: list[dict] = field(default_factory=list)
    measured: np.ndarray = field(default_factory=lambda: np.zeros(0))
    fitted: np.ndarray = field(default_factory=lambda: np.zeros(0))
    initial: np.ndarray = field(default_factory=lambda: np.zeros(0))
    profiles: dict[str, list] = field(default_factory=dict)
    sigma: dict[str, float] = field(default_factory=dict)
    correlation: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    determined: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=bool))
    combinations: list[dict] = field(default_factory=list)
    undetermined: list[str] = field(default_factory=list)
    correlated: list[str] = field(default_factory=list)
    singular_values: np.ndarray = field(default_factory=lambda: np.zeros(0))
    jacobian_error: float = float("nan")
    direction_errors: np.ndarray = field(default_factory=lambda: np.zeros(0))
    by_response: dict[str, dict] = field(default_factory=dict)

    @property
    def all_determined(self) -> bool:
        """Every fitted value determined alone by the data (``determined``; a result built
        without the analysis counts as determined)."""
        return bool(np.all(self.determined))

    def as_dict(self) -> dict:
        return {
            "parameters": {
                key: {
                    "start": self.start[i],
                    "value": self.values[i],
                    "standard_error": self.standard_errors[i],
                    f"confidence_{int(100 * CONFIDENCE)}": self.intervals[i],
                }
                for i, key in enumerate(self.keys)
            },
            "residual_rms": self.residual_rms,
            "residual_rms_by_response": self.by_response,
            "success": self.success,
            "message": self.message,
            "evaluations": self.evaluations,
            "runs": self.runs,
            "wall_time_s": self.wall_time_s,
            "responses": self.responses,
            "sigma": self.sigma,
            "determined": {key: bool(d) for key, d in zip(self.keys, self.determined)},
            "correlation": self.correlation,
            "correlation_bound": CORRELATION_BOUND,
            "singular_values": self.singular_values,
            "jacobian_error": self.jacobian_error,
            "direction_errors": self.direction_errors,
            "undetermined_combinations": self.undetermined,
            "correlated": self.correlated,
            "determined_combinations": self.combinations,
        }


def read_measurements(data: str | Path | dict) -> dict[str, list]:
    """The columns of a measured-data CSV (header row, then values: numbers, or TOML values
    such as ``mindlin``; lines starting with ``#`` are comments, e.g. the data's source), or a
    dict of equal-length columns given in Python.

    Raises
    ------
    ValueError
        A missing, empty or binary file, rows of unequal length, an empty cell, or a response
        column that is not numbers.
    """
    if isinstance(data, dict):
        columns = {str(k): list(v) for k, v in data.items()}
        where = "the data"
    else:
        where = str(data)
        if not Path(data).is_file():
            raise ValueError(f"{where}: no such data file")
        try:
            with open(data, newline="", encoding="utf-8") as handle:
                # Lines starting with # say where the data came from; blank lines are spacing.
                lines = [
                    row for row in csv.reader(handle)
                    if row and any(c.strip() for c in row) and not row[0].lstrip().startswith("#")
                ]  # fmt: skip
        except (UnicodeDecodeError, csv.Error) as error:
            # A binary file (a spreadsheet, an image): say which file, not the codec's words.
            raise ValueError(
                f"{where}: not a text CSV file (header row, then rows of values separated "
                f"by commas): {error}"
            ) from None
        if len(lines) < 2:
            raise ValueError(f"{where}: expected a header row and at least one row of data")
        header = [name.strip() for name in lines[0]]
        for number, row in enumerate(lines[1:], start=2):
            if len(row) != len(header) or any(not cell.strip() for cell in row):
                raise ValueError(
                    f"{where}: row {number} has {len(row)} cells (some empty?); the header has "
                    f"{len(header)}: {', '.join(header)}"
                )
        columns = {name: [read_value(row[i].strip()) for row in lines[1:]]
                   for i, name in enumerate(header)}  # fmt: skip
    lengths = {len(v) for v in columns.values()}
    if len(lengths) != 1 or 0 in lengths:
        raise ValueError(f"{where}: expected columns of one length >= 1, got {lengths}")
    for name, values in columns.items():
        if _is_response(name) and not all(
            isinstance(v, int | float) and not isinstance(v, bool) and np.isfinite(v)
            for v in values
        ):
            raise ValueError(f"{where}: column {name!r} (a response) must hold numbers only")
    return columns


def _is_response(name: str) -> bool:
    return "." not in name and name not in RUN_KEYS


def start_values(data: dict, fit: dict[str, float | None]) -> np.ndarray:
    """The starting value of every fitted key: the one given, else the case's own number at
    that key: a value set in the file, or a preset material's own number
    (``part.0.material.areal_density`` of ``material = "g1151_laminate"``; a law has no single
    number to start from).

    Raises
    ------
    ValueError
        A key not in the case, a value that is not a number, or zero (the fit scales by it).
    """
    start = []
    for key, given in fit.items():
        if given is None:
            node: Any = data
            parts = key.split(".")
            for depth, part in enumerate(parts):
                if isinstance(node, list) and part.isdigit() and int(part) < len(node):
                    node = node[int(part)]
                elif isinstance(node, dict) and part in node:
                    node = node[part]
                elif (
                    depth == len(parts) - 1
                    and parts[depth - 1] == "material"
                    and (number := _preset_number(node, part)) is not None
                ):
                    node = number
                else:
                    raise ValueError(
                        f"{key}: the case has no number there to start from; give one "
                        f"(--fit {key}=VALUE)"
                    )
            given = node
        if isinstance(given, bool) or not isinstance(given, int | float) or not np.isfinite(given):
            raise ValueError(f"{key}: expected a number to start from, got {given!r}")
        if given == 0:
            raise ValueError(f"{key}: the start must not be 0 (the fit scales by it)")
        start.append(float(given))
    return np.array(start)


def _preset_number(material: Any, name: str) -> float | None:
    """The number ``name`` of a preset material (``"g1151_laminate"`` or ``{ preset =
    "g1151_laminate", ... }``) as the preset makes it, or None (not a preset, no such field,
    or not a number: a law)."""
    table = {"preset": material} if isinstance(material, str) else material
    if not isinstance(table, dict) or not isinstance(table.get("preset"), str):
        return None
    try:
        make = registry.material_factory(table["preset"])
        own = inspect.signature(make).parameters
        built = make(**{k: v for k, v in table.items() if k in own})
    except (ValueError, TypeError):
        return None  # the case reader names what is wrong with the preset
    value = getattr(built, name, None)
    if isinstance(value, bool) or not isinstance(value, int | float):
        return None
    return float(value)


def identify(
    case: str | Path | dict,
    data: str | Path | dict,
    fit: dict[str, float | None],
    *,
    path: str | None = None,
    out: str | Path | None = None,
    scheduler: str | None = None,
    workers: int | None = None,
    progress: bool | None = None,
    step: float = 1e-3,
    max_evaluations: int = 34,
    sigma: dict[str, float] | None = None,
    name: str | None = None,
) -> Identification:
    """Fit the values of ``fit``'s keys so that the case's runs match ``data``.

    Parameters
    ----------
    case : str, pathlib.Path or dict
        The case file, or its tables built in Python.
    data : str, pathlib.Path or dict
        The measured data (``read_measurements``; module docstring for its columns).
    fit : dict
        Dotted key -> starting value, or None for the case's own value.
    path : str or None
        For a profile (columns x, z): the case's path it was measured along (default: the
        case's only path).
    out : str, pathlib.Path or None
        Folder for ``identify.json`` and ``fit.png`` (data vs fit); None writes nothing.
    scheduler, workers, progress
        As ``fibreshell.sweep.sweep``.
    step : float
        Forward-difference step of the Jacobian, relative to the values.
    max_evaluations : int
        Model evaluations the fit may make in all (each one run per condition group): the
        optimiser's points, its Jacobians' shifted points, and the 4 n points of the Jacobian
        at the end (central differences with steps h and 2 h), which are kept for it; at
        least 5 n + 1 (a point and a Jacobian for the optimiser). At the cap the fit stops at the
        best point it evaluated and says so (``success`` False).
    sigma : dict or None
        Response column -> its measurement uncertainty (data units; "z" for a profile): each
        residual is divided by it, so responses in different units (a deflection in mm, a
        reaction in N) weigh by their precision. None: 1 for every column.
    name : str or None
        The case's name in messages when ``case`` is a dict.

    Returns
    -------
    Identification

    Raises
    ------
    ValueError
        Bad data, keys or options; fewer data values than fitted keys; ``out`` held by
        another command (fibreshell.folder_lock.FolderInUse, naming it: the fit holds it from
        its first run until it returns).
    FitFailed
        A run that fails during the fit (its values and error are given).
    """
    from scipy import optimize, stats

    started = time.perf_counter()
    if isinstance(case, dict):
        tables, case_path = case, Path(name or str(case.get("title", "case")))
    else:
        case_path = Path(case).resolve()
        tables = read_case_data(case_path)
    if not fit:
        raise ValueError("nothing to fit: give at least one key")
    if not (0.0 < step < 0.1):
        raise ValueError(f"step must be in (0, 0.1) (relative), got {step!r}")
    keys = list(fit)
    fewest = 5 * len(keys) + 1  # a point and its Jacobian, and the Jacobian at the end
    if (
        isinstance(max_evaluations, bool)
        or not isinstance(max_evaluations, int)
        or max_evaluations < fewest
    ):
        raise ValueError(
            f"max_evaluations must be a whole number >= {fewest} for {len(keys)} fitted "
            f"key(s) (a point and its {len(keys)} shifted points for the optimiser, and "
            f"{4 * len(keys)} for the Jacobian at the end), got {max_evaluations!r}"
        )
    columns = read_measurements(data)
    theta0 = start_values(tables, fit)
    conditions = [n for n in columns if not _is_response(n)]
    responses = [n for n in columns if _is_response(n)]
    clash = set(keys) & set(conditions)
    if clash:
        raise ValueError(f"{sorted(clash)}: fitted keys cannot also be data columns")
    profile = set(responses) >= {"x", "z"}
    if profile and set(responses) != {"x", "z"}:
        raise ValueError(
            f"a profile is columns x and z; got also {sorted(set(responses) - {'x', 'z'})}"
        )
    if not responses:
        raise ValueError(
            "the data has no response column (a name without a dot: x and z, or a summary "
            "column such as displacement_tip_z)"
        )
    rows = len(next(iter(columns.values())))
    groups: dict[tuple, list[int]] = {}
    for r in range(rows):
        groups.setdefault(tuple(columns[c][r] for c in conditions), []).append(r)
    settings = [dict(zip(conditions, values)) for values in groups]
    for setting in settings:  # every key resolves, every condition builds, before any run
        trial, _ = apply_overrides(tables, {**setting, **dict(zip(keys, theta0))})
        built = case_from_data(trial, case_path)
    if profile:
        if path is None:
            if len(built.paths) != 1:
                raise ValueError(
                    f"a profile needs the path it was measured along: give path (one of "
                    f"{', '.join(built.paths) or 'none: the case has no [output] paths'})"
                )
            path = next(iter(built.paths))
        elif path not in built.paths:
            raise ValueError(f"no path {path!r} in the case; its paths: {', '.join(built.paths)}")
    elif path is not None:
        raise ValueError(
            f"path {path!r} is for a profile (data columns x and z); the data's responses are "
            f"summary columns ({', '.join(responses)}), which are not along a path: leave the "
            "path out"
        )
    named = ["z"] if profile else responses  # the compared columns, in residual order
    measured = np.array([columns[n][r] for g in groups.values() for r in g for n in named],
                        dtype=float)  # fmt: skip
    if len(measured) < len(keys):
        # Fewer equations than unknowns: a family of values fits the data exactly, and the
        # optimiser would return one of them, found by where it started, as the fit.
        raise ValueError(
            f"{len(measured)} data value(s) ({len(groups)} condition group(s), responses "
            f"{', '.join(named)}) for {len(keys)} fitted keys ({', '.join(keys)}): expected "
            "at least as many data values as fitted keys (more, for an interval)"
        )
    weights = dict(sigma or {})
    for column, value in weights.items():
        if column not in named:
            raise ValueError(f"sigma: {column!r} is not a response column ({', '.join(named)})")
        if isinstance(value, bool) or not isinstance(value, int | float) or not value > 0:
            raise ValueError(f"sigma: {column} must be a positive number, got {value!r}")
    mixed_units_warning(named, weights)  # before the runs: a user may stop and give sigma
    # Each residual over its column's sigma: rows are laid out row by row, columns inside.
    scale = np.tile([float(weights.get(c, 1.0)) for c in named], len(measured) // len(named))
    cache: dict[tuple, tuple[np.ndarray, list[dict]]] = {}
    counts = {"evaluations": 0, "runs": 0}

    def model_values(summaries: list[dict]) -> np.ndarray:
        values = []
        for rows_of_group, summary in zip(groups.values(), summaries):
            if profile:
                track = summary["paths"][path]
                order = np.argsort(track["horizontal"])
                horizontal = np.asarray(track["horizontal"])[order]
                z = np.asarray(track["z"])[order]
                x = np.array([columns["x"][r] for r in rows_of_group], dtype=float)
                values.append(np.interp(x, horizontal, z))  # the end height beyond the ends
            else:
                row = summary_row(summary)
                missing = [n for n in responses if n not in row]
                if missing:
                    raise ValueError(
                        f"the runs have no {missing[0]!r}; their columns: {', '.join(row)} (a "
                        "column without a dot is a response; a condition is a dotted key of "
                        "the case, such as mesh.rectangle.lx)"
                    )
                values.append(np.array([[row[n] for n in responses] for _ in rows_of_group]))
        return np.concatenate([np.ravel(v) for v in values])

    folder = None if out is None else Path(out)
    if folder is not None:  # held from before the first run (fibreshell.folder_lock)
        if folder.exists() and not folder.is_dir():
            raise ValueError(f"out {str(folder)!r} is a file: give a folder")
        folder.mkdir(parents=True, exist_ok=True)
    with folder_lock(folder, f"the fit of {str(case_path)!r}") if folder else nullcontext():
        with dask_client(scheduler, workers) as (client, threads):

            def evaluate(points: list[np.ndarray], limit: int | None = None) -> None:
                """Run every condition group at every new point p (log ratios), in one batch;
                _CapReached instead where it would take the evaluations past ``limit``."""
                new = [p for p in dict.fromkeys(tuple(p) for p in points) if p not in cache]
                if not new:
                    return
                if limit is not None and counts["evaluations"] + len(new) > limit:
                    raise _CapReached
                tasks = [
                    (tables, str(case_path), {**setting, **dict(zip(keys, np.exp(p) * theta0))},
                     None, threads)
                    for p in new for setting in settings
                ]  # fmt: skip
                results = map_tasks(client, run_variant, tasks, f"identify {case_path.stem}",
                                    progress)  # fmt: skip
                counts["evaluations"] += len(new)
                counts["runs"] += len(tasks)
                for k, p in enumerate(new):
                    batch = results[k * len(settings) : (k + 1) * len(settings)]
                    for task, result in zip(tasks[k * len(settings) :], batch):
                        error = result.error if isinstance(result, Failure) else result[0]["error"]
                        if error or result[1] is None or not result[0]["converged"]:
                            values = ", ".join(f"{key} = {_show(v)}" for key, v in task[2].items())
                            raise FitFailed(
                                f"the run with {values} failed: {error or 'not converged'}"
                            )
                    summaries = [result[1] for result in batch]
                    cache[p] = ((model_values(summaries) - measured) / scale, summaries)

            # The optimiser's share of the cap: the rest is the Jacobian at the end.
            budget = max_evaluations - 4 * len(keys)

            def residuals(p: np.ndarray) -> np.ndarray:
                evaluate([p], budget)
                return cache[tuple(p)][0]

            def jacobian(p: np.ndarray, limit: int | None = budget) -> np.ndarray:
                # Forward differences, every column's runs at once (and the base point if new).
                steps = np.full(len(p), step)  # relative steps of theta
                shifted = [p + steps[j] * np.eye(len(p))[j] for j in range(len(p))]
                evaluate([p, *shifted], limit)
                base = cache[tuple(p)][0]
                return np.column_stack(
                    [(cache[tuple(q)][0] - base) / steps[j] for j, q in enumerate(shifted)]
                )

            origin = np.zeros(len(keys))
            try:
                solution = optimize.least_squares(
                    residuals, origin, jac=jacobian, method="trf",
                    x_scale=1.0, max_nfev=max_evaluations, ftol=1e-6, xtol=1e-5, gtol=1e-10,
                )  # fmt: skip
                best, success, message = solution.x, bool(solution.success), solution.message
                capped = None
            except _CapReached:
                # The best point evaluated (the optimiser's or a Jacobian's shifted one).
                best = np.array(min(cache, key=lambda p: float(cache[p][0] @ cache[p][0])))
                success, message, capped = False, "", counts["evaluations"]
            # Central differences at h and 2 h: the first is the Jacobian analysed, their
            # difference its error (fibreshell/identifiability.py).
            shifts = [s * step * e for s in (1.0, -1.0, 2.0, -2.0) for e in np.eye(len(keys))]
            evaluate([best, *(best + shift for shift in shifts)])
            if capped is not None:  # said once the Jacobian's are counted: the counts agree
                message = (
                    f"stopped at the cap of {max_evaluations} model evaluations: "
                    f"{counts['evaluations']} made, {capped} by the optimiser (its share "
                    f"{budget}: its next step would have passed it) and "
                    f"{counts['evaluations'] - capped} for the Jacobian at the end (of its "
                    f"{4 * len(keys)} points, those not evaluated before); the values are the "
                    "best evaluated"
                )
            solution = optimize.OptimizeResult(x=best, success=success, message=message)

            def central(width: float) -> np.ndarray:
                return np.column_stack([
                    (cache[tuple(solution.x + width * e)][0]
                     - cache[tuple(solution.x - width * e)][0]) / (2.0 * width)
                    for e in np.eye(len(keys))
                ])  # fmt: skip

            narrow, wide = central(step), central(2.0 * step)
        m, n = len(measured), len(keys)
        values = np.exp(solution.x) * theta0
        final = cache[tuple(solution.x)][0]
        # In p = ln(theta / theta_0), where the parameters are alike in scale (the singular
        # values then say whether the data tell them apart, not how their units compare);
        # d theta = theta d p carries the covariance over.
        # The round-off of a difference of two model values y (residual units) over 2 h.
        rounding = float(np.finfo(float).eps * np.linalg.norm(np.abs(final) + np.abs(measured
                                                                / scale)) / step)  # fmt: skip
        # With a sigma for every response, the residuals are in units of the data's scatter.
        known = 1.0 if set(weights) == set(named) else None
        found = determinacy(narrow, wide, final, n, rounding, known, CONFIDENCE)
        half_width = stats.t.ppf(0.5 + CONFIDENCE / 2, m - n) if m > n else np.nan
        errors = np.where(
            found.determined, np.abs(values) * np.sqrt(np.diag(found.covariance_p)), np.nan
        )
        intervals = np.column_stack([values - half_width * errors, values + half_width * errors])
        combinations, undetermined, correlated = [], [], []
        if not found.all_determined:
            # The determined combinations as a reduced basis of the determined span (p1 - p2
            # and p3, not the singular vectors' mixes of them), leaving out a single
            # parameter determined alone (its own interval says it); where every direction is
            # determined (a pair correlated alone), the singular vectors themselves.
            tolerance = max(found.share_bound, 1e-9)
            if found.resolved.all():
                spans = found.vectors.T
            else:
                spans = reduced_combinations(found.vectors[:, found.resolved], tolerance)
            for vector in spans:
                present = np.flatnonzero(np.abs(vector) > tolerance)
                if len(present) == 1 and found.determined[present[0]]:
                    continue
                text, exponents = combination_text(keys, vector, tolerance)
                logarithm = float(exponents @ np.log(values))
                spread = half_width * float(np.sqrt(exponents @ found.covariance_p @ exponents))
                combinations.append({
                    "combination": text,
                    "exponents": exponents,
                    "value": float(np.exp(logarithm)),
                    f"confidence_{int(100 * CONFIDENCE)}": np.exp(
                        [logarithm - spread, logarithm + spread]
                    ),
                })  # fmt: skip
            if not found.resolved.all():
                nulls = reduced_combinations(found.vectors[:, ~found.resolved], tolerance)
                undetermined = [combination_text(keys, v, tolerance)[0] for v in nulls]
            correlated = [f"{keys[i]} and {keys[j]}: {c:+.5f}" for i, j, c in found.correlated]
        result = Identification(
            keys=keys,
            start=theta0,
            values=values,
            standard_errors=errors,
            intervals=intervals,
            residual_rms=float(np.sqrt(np.mean(final**2))),  # in units of sigma when given
            by_response=response_residuals(named, final, measured, weights),
            success=bool(solution.success),
            message=str(solution.message),
            evaluations=counts["evaluations"],
            runs=counts["runs"],
            wall_time_s=time.perf_counter() - started,
            responses=named,
            sigma=weights,
            conditions=[dict(s) for s, g in zip(settings, groups.values()) for _ in g],
            measured=measured,
            fitted=final * scale + measured,
            initial=cache[tuple(origin)][0] * scale + measured,
            correlation=found.correlation,
            determined=found.determined,
            combinations=combinations,
            undetermined=undetermined,
            correlated=correlated,
            singular_values=found.singular_values,
            jacobian_error=found.jacobian_error,
            direction_errors=found.direction_errors,
        )
        if profile:
            assert path is not None
            for label, p in (("fitted", solution.x), ("initial", origin)):
                result.profiles[label] = [
                    (np.asarray(s["paths"][path]["horizontal"]), np.asarray(s["paths"][path]["z"]))
                    for s in cache[tuple(p)][1]
                ]
            result.profiles["measured_x"] = [
                np.array([columns["x"][r] for r in g], dtype=float) for g in groups.values()
            ]
        if folder is not None:
            record, drawing = IDENTIFY_FILES
            (folder / record).write_text(strict_json(result.as_dict()))
            figure(result, settings, folder / drawing)
        return result


class _CapReached(Exception):
    """The optimiser asked for evaluations past its share of ``max_evaluations``."""


def _show(value: Any) -> str:
    numeric = isinstance(value, int | float) and not isinstance(value, bool)
    return f"{value:.6g}" if numeric else str(value)


def figure(result: Identification, settings: list[dict], target: Path) -> Path:
    """Data vs fit: for a profile, the measured points and the model's path at the start and
    at the fit, per condition group; for summary responses, each response against the first
    numeric condition (or the row number)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fitted = ", ".join(f"{k} = {v:.4g}" for k, v in zip(result.keys, result.values))
    fig, ax = plt.subplots(figsize=(7, 4.5), constrained_layout=True)
    if result.profiles:
        start = 0
        for g, (x, setting) in enumerate(zip(result.profiles["measured_x"], settings)):
            label = ", ".join(f"{k} = {v}" for k, v in setting.items()) or "measured"
            z = result.measured[start : start + len(x)]
            start += len(x)
            ax.plot(x, z, "o", color=f"C{g}", label=label)
            ax.plot(*result.profiles["fitted"][g], "-", color=f"C{g}")
            ax.plot(*result.profiles["initial"][g], ":", color=f"C{g}")
        ax.set(xlabel="x along the path (mm)", ylabel="z (mm)")
        ax.set_aspect("equal", adjustable="datalim")
    else:
        numeric = [
            k for k in (result.conditions[0] if result.conditions else {})
            if all(isinstance(c[k], int | float) for c in result.conditions)
        ]  # fmt: skip
        count = len(result.responses)
        rows = np.arange(len(result.measured) // count)
        x = (np.array([c[numeric[0]] for c in result.conditions], dtype=float)
             if numeric else rows)  # fmt: skip
        for j, response in enumerate(result.responses):
            ax.plot(x, result.measured[j::count], "o", color=f"C{j}", label=f"{response}: data")
            ax.plot(x, result.fitted[j::count], "-", color=f"C{j}", label="fit")
            ax.plot(x, result.initial[j::count], ":", color=f"C{j}", label="start")
        ylabel = result.responses[0] if count == 1 else "responses"
        ax.set(xlabel=numeric[0] if numeric else "data row", ylabel=ylabel)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize="small")
    ax.set_title(f"data (o) vs fit (-) and start (:): {fitted}", fontsize="small")
    fig.savefig(target, dpi=100)
    plt.close(fig)
    return target


def format_result(result: Identification) -> str:
    """The fitted values with their 95 % intervals, for the terminal."""
    lines = []
    for i, key in enumerate(result.keys):
        low, high = result.intervals[i]
        value = f"{result.values[i]:.6g}"
        if len(result.determined) and not result.determined[i]:
            interval = "NOT DETERMINED by the data alone: no interval (below)"
        elif np.isfinite(low) and np.isfinite(high):
            start, value, end = interval_text(result.values[i], low, high, digits=6)
            interval = f"95 % interval [{start}, {end}]{below_zero((low, high))}"
        else:
            interval = "no interval (as many data values as parameters)"
        lines.append(f"{key} = {value} (start {result.start[i]:.6g}), {interval}")
    correlation = result.correlation
    # Correlations only among the values with a finite variance (identifiability.py leaves
    # NaN for the others: a pseudo-inverse's correlation of an unbounded value is no number).
    finite = (
        np.flatnonzero(np.isfinite(np.diag(correlation)))
        if correlation.shape == (2 * (len(result.keys),))
        else np.zeros(0, dtype=int)
    )
    if len(finite) > 1:  # (none with as many data values as parameters)
        shown = ", ".join(result.keys[i] for i in finite)
        what = "fitted values" if len(finite) == len(result.keys) else f"values {shown}"
        order = "in the order above" if len(finite) == len(result.keys) else "in that order"
        lines.append(f"correlation of the {what} (rows and columns {order}):")
        lines += ["  " + " ".join(f"{correlation[i, j]:+.4f}" for j in finite) for i in finite]
    if not result.all_determined:
        lines.append(
            "NOT DETERMINED: the data do not tell these values apart: "
            + "; ".join(
                [
                    f"{text} is not determined (a singular value of the Jacobian within its "
                    f"own error along it, or a 95 % interval wider than a factor {WIDEST:g} "
                    "either way)"
                    for text in result.undetermined
                ]
                + [
                    f"{text} (|correlation| above {CORRELATION_BOUND})"
                    for text in result.correlated
                ]
            )  # fmt: skip
        )
        if len(result.direction_errors) == len(result.singular_values):
            lines.append(
                "singular values of dr/d(ln value) (their errors): "
                + ", ".join(
                    f"{s:.3g} ({e:.2g})"
                    for s, e in zip(result.singular_values, result.direction_errors)
                )
            )
        for combination in result.combinations:
            low, high = combination[f"confidence_{int(100 * CONFIDENCE)}"]
            bounds = ""
            if np.isfinite(low) and np.isfinite(high):
                start, _, end = interval_text(combination["value"], low, high, digits=6)
                bounds = f", 95 % interval [{start}, {end}]"
            lines.append(
                f"determined: {combination['combination']} = {combination['value']:.6g}{bounds}"
            )
    if len(result.by_response) > 1:  # which response the fit does not follow
        lines.append(
            "RMS residual by response (over its sigma, else in its unit; against its "
            "measured values' RMS): "
            + ", ".join(
                f"{column} {r['rms']:.4g} {r['unit']} (of {r['measured_rms']:.4g})"
                for column, r in result.by_response.items()
            )
        )
    lines.append(
        f"RMS residual {result.residual_rms:.4g}; {result.evaluations} evaluations, "
        f"{result.runs} runs, {result.wall_time_s:.1f} s; "
        + (
            result.message
            if result.success
            else f"NOT CONVERGED: "
            f"{result.message.rstrip('.')}: give the fit more evaluations (--max-evaluations)"
        )
    )
    return "\n".join(lines)
