"""Parameter sweeps: one case file run over a product (or a pairing) of values of some of its
keys, every variant a Dask task, one row per variant in ``sweep.csv``.

A key is a dotted path into the case file's tables: ``mesh.rectangle.lx``,
``part.0.material.bending`` (``[[part]]`` tables by index from 0), ``solver.increments``.
A material given as a preset name is opened into ``{ preset = name }`` so that one of its
values can be set (``part.0.material.bending`` on ``material = "paper_stack"``). Two keys are
not in the file but choose how the case runs, as ``fibreshell compare`` does: ``kinematics``
("fibrous" or "mindlin": every fibrous part as the calibrated Mindlin shell), ``calibration``
("laws" or "initial-slope", fibreshell/calibration.py) and that calibration's numbers:
``bending_scale``, ``transverse_shear`` (N/mm) and ``twisting`` (N mm) of "laws",
``shear_ratio`` (G13 / E) of "initial-slope" (alone, it implies that rule).
"""

from __future__ import annotations

import copy
import csv
import itertools
import json
import math
import re
import signal
import tempfile
import threading
import time
import tomllib
from collections.abc import Iterator
from contextlib import contextmanager, nullcontext
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from fibreshell.case import CaseError, case_from_data, read_case_data
from fibreshell.cluster import Failure, dask_client, map_tasks, set_threads
from fibreshell.folder_lock import folder_lock
from fibreshell.outputs import VARIANT_FILE, remove_run_folder

__all__ = [
    "MAX_VARIANTS", "RUN_KEYS", "SweepTable", "apply_overrides", "parse_vary", "read_value",
    "remove_variants", "run_variant", "split_values", "summary_row", "sweep", "variants",
]  # fmt: skip

# Keys that are options of the run, not of the case file: run_case's keywords (those of
# fibreshell compare), with the values they take (None: a positive number).
RUN_KEYS = {
    "kinematics": ("fibrous", "mindlin"),
    "calibration": ("laws", "initial-slope"),
    "shear_ratio": None,
    "bending_scale": None,
    "transverse_shear": None,
    "twisting": None,
}
_SPACES: dict[str, Any] = {"linspace": np.linspace, "geomspace": np.geomspace}
#: The most variants a sweep runs unless told otherwise (``max_variants``, ``--max-variants``):
#: more is almost always a typo (a count of 1e9 in a linspace), refused before anything runs.
MAX_VARIANTS = 10_000
# A variant's folder in the sweep's: variant-000, variant-001, ... (variant-1000 past 999).
VARIANT_FOLDER = re.compile(r"variant-[0-9]{3,}")
# The error of a variant a stopped sweep (Ctrl-C, SIGTERM: exit 130) did not finish.
INTERRUPTED = "interrupted: the sweep was stopped before this variant ended"


# ------------------------------------------------------------------ the variants
def parse_vary(text: str, max_variants: int = MAX_VARIANTS) -> tuple[str, list]:
    """``KEY=V1,V2,...`` as (key, values). Each value is read as a TOML value (``2``, ``2.5``,
    ``true``, ``"text"``, ``[0.0, 0.0, 1.0]``), a bare word as a string; ``linspace(a, b, n)``
    and ``geomspace(a, b, n)`` give n values from a to b, evenly or geometrically spaced.

    Raises
    ------
    ValueError
        No ``=``, an empty key or no value; a count that is not a whole number, or more than
        ``max_variants`` values.
    """
    key, sep, rest = text.partition("=")
    key = key.strip()
    if not sep or not key or not rest.strip():
        raise ValueError(f"--vary {text!r}: expected KEY=V1,V2,... (e.g. solver.increments=2,4)")
    spaced = re.fullmatch(r"\s*(linspace|geomspace)\((.*)\)\s*", rest)
    if spaced:
        numbers = [read_value(v) for v in split_values(spaced.group(2))]
        if (
            len(numbers) != 3
            or not all(isinstance(v, int | float) and not isinstance(v, bool) for v in numbers)
            or not isinstance(numbers[2], int)
            or numbers[2] < 1
        ):
            raise ValueError(
                f"--vary {text!r}: expected {spaced.group(1)}(start, stop, count) with numbers "
                "and a whole count >= 1"
            )
        if numbers[2] > max_variants:
            raise ValueError(
                f"--vary {text!r}: {numbers[2]} values, more than the {max_variants} variants "
                "a sweep may run (--max-variants)"
            )
        if spaced.group(1) == "geomspace" and numbers[0] * numbers[1] <= 0:
            raise ValueError(f"--vary {text!r}: geomspace needs start and stop of one sign")
        return key, [float(v) for v in _SPACES[spaced.group(1)](*numbers)]
    texts = split_values(rest)
    if len(texts) > max_variants:
        raise ValueError(
            f"--vary {key}=...: {len(texts)} values, more than the {max_variants} variants a "
            "sweep may run (--max-variants)"
        )
    values = [read_value(v) for v in texts]
    if any(v == "" for v in values):
        raise ValueError(f"--vary {text!r}: an empty value (two commas in a row?)")
    return key, values


def split_values(text: str) -> list[str]:
    """``text`` split at the commas outside brackets, braces and quotes."""
    parts, depth, quote, start = [], 0, "", 0
    for i, char in enumerate(text):
        if quote:
            quote = "" if char == quote else quote
        elif char in "\"'":
            quote = char
        elif char in "[{(":
            depth += 1
        elif char in "]})":
            depth -= 1
        elif char == "," and depth == 0:
            parts.append(text[start:i])
            start = i + 1
    parts.append(text[start:])
    return [p.strip() for p in parts]


def read_value(text: str) -> Any:
    """A value as the command line gives it: a TOML value, else the bare word as a string."""
    try:
        return tomllib.loads(f"value = {text}")["value"]
    except tomllib.TOMLDecodeError:
        return text  # a bare word: fibrous, g986_ply


def variants(
    vary: dict[str, list], paired: bool = False, max_variants: int = MAX_VARIANTS
) -> list[dict[str, Any]]:
    """The overrides of every variant: the full product of the values of ``vary`` (the first
    key's values outermost), or with ``paired`` the i-th value of every key together.

    Raises
    ------
    ValueError
        A key without values, paired lists of different lengths, or more than
        ``max_variants`` variants (counted before any is built).
    """
    if isinstance(max_variants, bool) or not isinstance(max_variants, int) or max_variants < 1:
        raise ValueError(f"max_variants must be an integer >= 1, got {max_variants!r}")
    if not vary:
        raise ValueError("nothing to vary: give at least one KEY=V1,V2,...")
    for key, values in vary.items():
        if not isinstance(values, list | tuple) or len(values) == 0:
            raise ValueError(f"{key}: expected a list of values, got {values!r}")
    keys = list(vary)
    counts = [len(values) for values in vary.values()]
    count = counts[0] if paired else math.prod(counts)
    if count > max_variants:
        sizes = " x ".join(map(str, counts))
        raise ValueError(
            f"the sweep has {count} variants ({sizes} values), more than max_variants = "
            f"{max_variants} (--max-variants): vary fewer values, or raise the cap"
        )
    if paired:
        lengths = {key: len(values) for key, values in vary.items()}
        if len(set(lengths.values())) != 1:
            raise ValueError(f"paired (--zip) keys need as many values each, got {lengths}")
        combos = list(zip(*vary.values()))
    else:
        combos = list(itertools.product(*vary.values()))
    return [dict(zip(keys, combo)) for combo in combos]


def apply_overrides(data: dict, overrides: dict[str, Any]) -> tuple[dict, dict]:
    """A copy of the case tables ``data`` with ``overrides`` (dotted key -> value) set, and
    the run options among them (``RUN_KEYS``).

    Raises
    ------
    ValueError
        A key whose path is not in the tables (the last part may be a new key of a table),
        a list index out of range, or a run option with a value it does not take.
    """
    data = copy.deepcopy(data)
    options: dict[str, Any] = {}
    for key, value in overrides.items():
        if key in RUN_KEYS:
            allowed = RUN_KEYS[key]
            if allowed is not None and value not in allowed:
                raise ValueError(f"{key}: expected one of {', '.join(allowed)}, got {value!r}")
            if allowed is None and (
                isinstance(value, bool) or not isinstance(value, int | float) or value <= 0
            ):
                raise ValueError(f"{key}: expected a positive number, got {value!r}")
            options[key] = value
            continue
        _set(data, key, value)
    return data, options


def _set(data: dict, key: str, value: Any) -> None:
    """``data`` at the dotted ``key`` set to ``value`` (in place); ValueError naming the part
    of the key that is not there."""
    parts = key.split(".")
    if not all(parts):
        raise ValueError(f"{key!r}: expected a dotted path such as part.0.material.bending")
    node: Any = data
    for depth, part in enumerate(parts):
        last = depth == len(parts) - 1
        here = ".".join(parts[: depth + 1])
        if isinstance(node, list):
            if not part.isdigit() or int(part) >= len(node):
                raise ValueError(
                    f"{key!r}: {'.'.join(parts[:depth]) or 'the case'} is a list of "
                    f"{len(node)} tables; expected an index 0 to {len(node) - 1}, got {part!r}"
                )
            index: Any = int(part)
        elif isinstance(node, dict):
            if part.isdigit() and part not in node and not last:
                raise ValueError(f"{key!r}: {here[: -len(part) - 1]} is a single table, not a list")
            if part not in node and not last:
                raise ValueError(
                    f"{key!r}: the case has no {here!r}"
                    + (f" (its keys: {', '.join(map(str, node))})" if node else "")
                )
            index = part
        else:
            raise ValueError(f"{key!r}: {'.'.join(parts[:depth])} is a value, not a table")
        if last:
            node[index] = value
        else:
            child = node[index]
            if isinstance(child, str) and part == "material":  # a preset, opened to change it
                child = node[index] = {"preset": child}
            elif (
                isinstance(child, dict)
                and parts[0] in ("part", "fix", "displace", "force", "moment", "contact")
                and depth == 0
            ):
                child = node[index] = [child]  # [part] written once: its index is 0
            node = child


# ------------------------------------------------------------------ one variant (a Dask task)
def summary_row(summary: dict) -> dict[str, Any]:
    """The numbers of a run's summary (``fibreshell.run.summarise``) as one flat row: how it
    ended, then per history set the reaction sum (N) and mean displacement (mm), the force
    on each tool (N), the largest fibre strain, the director tilt range (deg) and the
    director-angle range along each path (deg); names as in history.csv."""
    row: dict[str, Any] = {
        "converged": summary["converged"],
        "error": summary.get("stopped") or "",
        "wall_time_s": summary["wall_time_s"],
        "steps": summary["steps"],
        "final_load_factor": summary["final_load_factor"],
    }
    for group, prefix in (("reactions", "reaction"), ("mean_displacements", "displacement")):
        for name, vector in summary.get(group, {}).items():
            row.update({f"{prefix}_{name}_{a}": float(v) for a, v in zip("xyz", vector)})
    for name, vector in summary.get("tool_forces", {}).items():
        row.update({f"{name}_force_{a}": float(v) for a, v in zip("xyz", vector)})
        moved = summary.get("tool_displacements", {}).get(name, ())
        row.update({f"{name}_displacement_{a}": float(v) for a, v in zip("xyz", moved)})
    if "max_fibre_strain" in summary:
        row["max_fibre_strain"] = summary["max_fibre_strain"]
    if "director_tilt_deg" in summary:
        row["director_tilt_min_deg"] = summary["director_tilt_deg"]["min"]
        row["director_tilt_max_deg"] = summary["director_tilt_deg"]["max"]
        # the nodes past the thickness guard's tilt or at its cap (fibreshell/tilt_flag.py)
        row["tilted_directors"] = summary.get("tilted_directors", {}).get("nodes", 0)
    for name, profile in summary.get("paths", {}).items():
        angle = np.asarray(profile["director_angle_deg"], dtype=float)
        row[f"path_{name}_director_angle_min_deg"] = float(np.nanmin(angle))
        row[f"path_{name}_director_angle_max_deg"] = float(np.nanmax(angle))
    return row


def remove_variants(folder: Path) -> None:
    """Remove from a sweep's ``folder`` the variants an earlier sweep wrote there: each
    ``variant-<k>`` folder holding a ``variant.json``, emptied of the run's files and that
    record and then removed (a user's own file in it stays, and the folder with it), so that
    the folder holds only the new sweep's variants and not, beyond them or where a variant
    fails to build, those of another sweep."""
    for child in folder.iterdir():
        if VARIANT_FOLDER.fullmatch(child.name) and (child / VARIANT_FILE).is_file():
            remove_run_folder(child, extra=(VARIANT_FILE,))


def run_variant(
    data: dict, path: str, overrides: dict, folder: str | None, threads: int | None = None
) -> tuple[dict, dict | None]:
    """Build and run one variant (a Dask task): the case tables ``data`` of the case file
    ``path`` with ``overrides`` set, its outputs written into ``folder`` (None: a temporary
    folder, removed, and no frame series written there: ``run_case(write_frames=False)``).
    Returns its row (``summary_row``, or the error that stopped it before the solver ran) and
    its summary (None when it did not run)."""
    from fibreshell.run import run_case

    set_threads(threads)
    started = time.perf_counter()
    try:
        tables, options = apply_overrides(data, overrides)  # options: run_case's keywords
        case = case_from_data(tables, path)
        if folder is None:
            with tempfile.TemporaryDirectory() as scratch:
                run = run_case(case, Path(scratch), progress=False, write_frames=False, **options)
        else:
            Path(folder).mkdir(parents=True, exist_ok=True)
            (Path(folder) / VARIANT_FILE).write_text(
                json.dumps({"case": path, "overrides": overrides}, indent=1) + "\n"
            )
            run = run_case(case, Path(folder), progress=False, **options)
    except Exception as error:  # this variant's failure, not the sweep's
        row = {"converged": False, "error": f"{type(error).__name__}: {error}",
               "wall_time_s": time.perf_counter() - started}  # fmt: skip
        return row, None
    return summary_row(run.summary), run.summary


# ------------------------------------------------------------------ the sweep
@dataclass
class SweepTable:
    """A sweep's results: one row per variant (in variant order) with ``variant``,
    ``folder``, the varied keys, then ``summary_row``'s columns; ``summaries`` the full
    summary of each variant (None for one that did not run).

    ``column(name)`` is one column as a numpy array (NaN where a row has no value)."""

    keys: list[str]
    rows: list[dict[str, Any]]
    summaries: list[dict | None] = field(default_factory=list)

    @property
    def columns(self) -> list[str]:
        names = ["variant", "folder", *self.keys, "converged", "error", "wall_time_s"]
        for row in self.rows:
            names += [name for name in row if name not in names]
        return names

    def column(self, name: str) -> np.ndarray:
        if name not in self.columns:
            raise ValueError(f"no column {name!r}; columns: {', '.join(self.columns)}")
        values = [row.get(name, math.nan) for row in self.rows]
        try:
            return np.array(values, dtype=float)
        except (TypeError, ValueError):
            return np.array(values, dtype=object)

    @property
    def failed(self) -> list[int]:
        """Variants that did not converge or did not run."""
        return [row["variant"] for row in self.rows if not row.get("converged")]

    def text(self, most: int = 6) -> str:
        """The table for a terminal: variant, the varied values, converged, wall time, then
        up to ``most`` numbers of the runs (the z components of the history sets' reactions
        and displacements and of the tool forces, then the largest fibre strain, always
        shown), a line each; a
        failed variant shows its whole error instead (never cut short: the terminal wraps a
        long one, and the lines of a message of several are indented under its first)."""
        wanted = [
            name for name in self.columns
            if name.endswith("_z") and (name.startswith(("reaction_", "displacement_"))
                                        or (name.startswith("tool") and "_force_" in name))
        ]  # fmt: skip
        # the largest fibre strain always shown, the tool's own prescribed travel never (the
        # same in every variant: a driven tool's displacement is in sweep.csv)
        strain = ["max_fibre_strain"] if "max_fibre_strain" in self.columns else []
        shown = wanted[: most - len(strain)] + strain
        columns = ["variant", *self.keys, "converged", "wall_time_s", *shown]

        def cell(row: dict, name: str) -> str:
            value = row.get(name, "")
            if isinstance(value, float) and not isinstance(value, bool):
                return f"{value:.4g}"
            return str(_cell(value))

        cells = [[cell(row, name) for name in columns] for row in self.rows]
        widths = [max([len(name)] + [len(r[i]) for r in cells]) for i, name in enumerate(columns)]
        lines = ["  ".join(name.rjust(w) for name, w in zip(columns, widths))]
        for row, texts in zip(self.rows, cells):
            line = "  ".join(t.rjust(w) for t, w in zip(texts, widths))
            if row.get("error"):
                line = "  ".join(t.rjust(w) for t, w in zip(texts[: len(self.keys) + 2], widths))
                indent = "\n" + " " * (len(line) + 2)
                line += "  " + indent.join(str(row["error"]).splitlines())
            lines.append(line)
        return "\n".join(lines)

    def write_csv(self, path: Path) -> None:
        columns = self.columns
        with open(path, "w", newline="") as handle:
            writer = csv.DictWriter(handle, fieldnames=columns, restval="")
            writer.writeheader()
            for row in self.rows:
                writer.writerow({k: _cell(v) for k, v in row.items()})


def _cell(value: Any) -> Any:
    if isinstance(value, list | tuple | dict):
        return json.dumps(value)
    return value


def sweep(
    case: str | Path | dict,
    vary: dict[str, list],
    *,
    paired: bool = False,
    out: str | Path | None = None,
    scheduler: str | None = None,
    workers: int | None = None,
    progress: bool | None = None,
    name: str | None = None,
    max_variants: int = MAX_VARIANTS,
    in_process: bool = False,
) -> SweepTable:
    """Run a case over the values of some of its keys, every variant a Dask task (or, with
    ``in_process``, one after another in this process).

    Parameters
    ----------
    case : str, pathlib.Path or dict
        A case file, or its tables (as ``tomllib`` reads them) built in Python.
    vary : dict
        Dotted key -> list of values (module docstring; ``parse_vary`` reads the command
        line's form).
    paired : bool
        Pair the i-th values of every key (``--zip``) instead of the full product.
    out : str, pathlib.Path or None
        Folder of ``sweep.csv``, ``sweep.json`` (the sweep's definition) and one folder per
        variant (``variant-000``, ... with the run's files and ``variant.json``; the variant
        folders of an earlier sweep there are removed first, ``remove_variants``); None writes
        nothing (the table is returned). On a remote cluster the workers write the variant
        folders: give a folder they share with this machine.
    scheduler : str or None
        Address of a Dask scheduler; None: a LocalCluster of ``workers`` processes here.
    workers : int or None
        LocalCluster workers (default: one per core).
    progress : bool or None
        Progress bar over the tasks (None: on unless FIBRESHELL_PROGRESS=0 or under pytest).
    name : str or None
        The case's name in messages when ``case`` is a dict (default: its title).
    max_variants : int
        The most variants the sweep may have (default MAX_VARIANTS = 10000); more is refused
        before anything runs, naming the count.
    in_process : bool
        Run the variants one after another in this process, with its numba threads, and no
        Dask cluster (neither ``scheduler`` nor ``workers`` may be given): for a caller with
        one core to give, to which a LocalCluster of one worker adds only its cost (its
        scheduler, its worker process's imports and numba kernels loaded again: 2.8 s of
        CPU beside the 6.6 s of the eight 12-cell runs of the report's
        bai-6.1.1-sensitivity, benchmarks/report.py). The same rows and summaries as on a
        cluster; no progress bar.

    Returns
    -------
    SweepTable
        Rows in variant order; a variant that failed is a row with ``converged`` false and
        its ``error``, the others run on. ``sweep.csv`` is rewritten as each variant ends,
        and once more when the sweep is stopped (KeyboardInterrupt, raised on): the variants
        that did not end then have ``converged`` false and ``error`` INTERRUPTED.

    Raises
    ------
    ValueError
        A case file that cannot be read, a key that is not in it, no values, paired lists of
        different lengths, a bad ``workers`` or a scheduler that does not answer; or every
        variant failing to build (then the sweep itself is wrong: the first error is given);
        more than ``max_variants`` variants; ``in_process`` with ``scheduler`` or ``workers``.
        ``out`` held by another command (fibreshell.folder_lock.FolderInUse, naming it): the
        sweep holds it until it returns, and each variant its own folder while it runs.
    """
    from fibreshell.run import check_kinematics, check_run_options

    if not isinstance(in_process, (bool, np.bool_)):
        raise ValueError(f"in_process must be True or False, got {in_process!r}")
    if in_process and (scheduler is not None or workers is not None):
        raise ValueError(
            "in_process runs the variants here, without a cluster: give neither scheduler "
            f"nor workers (got scheduler={scheduler!r}, workers={workers!r})"
        )
    if isinstance(case, dict):
        data, path = case, Path(name or str(case.get("title", "case")))
    else:
        path = Path(case).resolve()
        data = read_case_data(path)
    combos = variants(vary, paired, max_variants)
    rows: list[dict[str, Any]] = []
    tasks, where = [], []
    folder = Path(out).resolve() if out is not None else None
    if folder is not None:
        if folder.exists() and not folder.is_dir():
            raise ValueError(f"out {str(folder)!r} is a file: give a folder")
        folder.mkdir(parents=True, exist_ok=True)
    held = folder_lock(folder, f"the sweep of {str(path)!r}") if folder else nullcontext()
    with held:
        if folder is not None:
            remove_variants(folder)
            definition = {"case": str(path), "vary": vary, "paired": paired,
                          "scheduler": scheduler}  # fmt: skip
            (folder / "sweep.json").write_text(json.dumps(definition, indent=1) + "\n")
        errors = []
        for i, overrides in enumerate(combos):
            label = f"variant-{i:03d}"
            row: dict[str, Any] = {"variant": i, "folder": label if folder else "", **overrides}
            rows.append(row)
            tables, options = apply_overrides(data, overrides)  # a wrong key: the sweep's error
            try:
                built = case_from_data(tables, path)  # a value the case refuses: its row
                check_run_options(**options)  # a calibration its kinematics would ignore
                check_kinematics(built, options.get("kinematics"))  # no part of that shell
            except (CaseError, ValueError) as error:
                # refused before it ran: no folder of its own to name
                row.update(folder="", converged=False, error=f"{type(error).__name__}: {error}")
                errors.append(str(error))
                continue
            tasks.append((data, str(path), overrides, str(folder / label) if folder else None))
            where.append(i)
        if not tasks:
            raise ValueError(f"no variant of the sweep could be built: {errors[0]}")
        table = SweepTable(keys=list(vary), rows=rows, summaries=[None] * len(rows))

        ended: set[int] = set()  # the tasks that ended (their rows filled)

        def done(task: int, result: Any) -> None:
            ended.add(task)
            i = where[task]
            if isinstance(result, Failure):
                rows[i].update(converged=False, error=result.error)
            else:
                rows[i].update(result[0])
                table.summaries[i] = result[1]
            if folder is not None and not (folder / rows[i]["folder"]).is_dir():
                rows[i]["folder"] = ""  # it failed before its folder was made
            if folder is not None:
                table.write_csv(folder / "sweep.csv")

        try:
            with _terminated_as_interrupt():
                if in_process:
                    for task, arguments in enumerate(tasks):
                        result: Any
                        # as map_tasks on a cluster: an error escaping the variant is its row's
                        try:
                            result = run_variant(*arguments)
                        except Exception as error:
                            result = Failure(f"{type(error).__name__}: {error}")
                        done(task, result)
                else:
                    with dask_client(scheduler, workers) as (client, threads):
                        map_tasks(
                            client,
                            run_variant,
                            [(*task, threads) for task in tasks],
                            f"sweep {path.stem}",
                            progress,
                            done,
                        )
        except KeyboardInterrupt:  # SIGINT or SIGTERM: the variants that did not end say so
            for task, i in enumerate(where):
                if task not in ended:
                    rows[i].update(converged=False, error=INTERRUPTED)
            if folder is not None:
                table.write_csv(folder / "sweep.csv")
            raise
        if folder is not None:
            table.write_csv(folder / "sweep.csv")
        return table


@contextmanager
def _terminated_as_interrupt() -> Iterator[None]:
    """SIGINT and SIGTERM raised as KeyboardInterrupt while the sweep runs (in the main
    thread; elsewhere signals cannot be set and nothing changes), so that a terminated sweep,
    as one stopped by Ctrl-C, writes sweep.csv with its unfinished variants marked; the
    previous handlers are restored on exit. SIGINT's is set too, not left to Python's default:
    a shell starts a background job of a non-interactive script with SIGINT ignored, which
    Python keeps, and such a sweep ignored Ctrl-C and ``kill -INT`` (``fibreshell run`` sets
    its own handler, solvers.interruptible, and stops with 130)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def interrupt(number: int, frame: Any) -> None:
        raise KeyboardInterrupt

    previous = {number: signal.signal(number, interrupt)
                for number in (signal.SIGINT, signal.SIGTERM)}  # fmt: skip
    try:
        yield
    finally:
        for number, old in previous.items():  # None: a handler not set from Python
            signal.signal(number, signal.SIG_DFL if old is None else old)
