"""Run validation cases and write the report folder: results.json, index.html, figures, VTU.

With ``jobs`` of 1 the cases run one after another in this process. With more, a pool of
``jobs`` spawned worker processes runs tasks, the longest first (``schedule_tasks``: the last
report's times in the same folder, else ``EXPECTED_CPU_S``): a task is a whole case, or one
part of a case made of independent runs (``Case.parts``: hemisphere-plies' runs, one per
layup and kinematics, and hemisphere-forming's, one per kinematics and mesh). A part's data
comes back pickled; once a case's last part is in, this process combines them
(``Case.combine``) and draws the figures while the workers go on, so that the report's wall
time follows the cases' CPU time over ``jobs`` rather than its longest case. A case's
results are the same split or not; its results.json entry then holds each part's time
(``parts``), its ``case_time_s`` and ``case_cpu_s`` the sums of the parts' and the combining
step's: the case's cost as if it ran in one process (which orders the next report), not its
span in this one. benchmarks/report_wall.py measures the wall against CPU / jobs. A worker
that dies (killed, out of memory) fails the cases not done, and the report is written;
interrupted (Ctrl-C), the report ends its workers at once.
"""

from __future__ import annotations

import ctypes
import gc
import json
import multiprocessing
import os
import pickle
import platform
import signal
import threading
import time
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor, as_completed
from concurrent.futures.process import BrokenProcessPool
from dataclasses import replace
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import numba
import numpy as np

from femcore.jit import free_cores
from fibreshell.folder_lock import folder_lock
from validation.case_warnings import kept_warnings
from validation.cases import CASES
from validation.records import Case, CaseResult, Figure, Outcome, Report
from validation.report_html import INTRODUCTION, STYLE, render_html

__all__ = [
    "EXPECTED_CPU_S",
    "EXPECTED_PART_WEIGHTS",
    "INTRODUCTION",
    "STYLE",
    "default_jobs",
    "expected_cost",
    "measured_costs",
    "measured_part_costs",
    "part_weight",
    "render_html",
    "run_case",
    "run_cases",
    "schedule",
    "schedule_tasks",
]

# The CPU time of each case, its computation and its figures (s, one numba thread), at the
# coarse and the default resolution, measured with benchmarks/report.py (2 cores shared, load
# 4-10), the order of a first report (a report folder that already holds a report of the same
# cases at the same resolution orders them by its measured case times, ``measured_costs``):
# with several jobs the workers take the cases in decreasing order of it, so that the
# longest starts first and the last to start is short (in report order hemisphere-forming, the
# longest, started last and ran alone on one core at the end). An order, not a promise: the
# coarse paper cases but bai-5.1 ran first after a cold cache (some compilation included).
# Refreshed at the default resolution (CPU time, 2 cores shared with other jobs): 17 cases
# from the case_cpu_s of one report of the 19 cases below (--jobs 2, load 3.9-14; 330.5 s CPU
# in all, 14 min wall); bai-6.1.1-sensitivity keeps its earlier figure (its Dask workers' CPU
# is not in its worker's case_cpu_s: 4.1 s there, 75 s wall) and bar-wave too (12.0 s there,
# 1.6 before: not measured again); plies-bai-5.1 (plies in 20 increments) and
# plies-deck-of-cards each the whole process of ``python -m validation --cases NAME --jobs 1``
# (user + system, load 1.4-2.5); hemisphere-forming the case_cpu_s of ``--cases
# hemisphere-forming --jobs 1`` with its fibrous stroke time-scaled x2 (its TIME_SCALING),
# coarse 18.2 s and default 37.2 s (load 7-10; 22.4 and 58.6 s unscaled, run beside them).
# Coarse: plies-bai-5.1 and plies-deck-of-cards from one report of those two and
# hemisphere-forming (--jobs 2, load 2.2-2.9; 166 s CPU, 2.8 min wall), the others as before.
# hemisphere-plies: with the rest of the ply contact's facing, its loads and its friction
# compiled (benchmarks/ply_facing.py), its case_cpu_s of ``--cases hemisphere-plies --jobs 1``
# at the default resolution: 148.7 s (24 of 24 checks), main c0b0822 run beside it 288.1 s,
# load 11-16; coarse (both fibrous layups, ``--resolution coarse``): 55.5 s (59.0 s without
# the faces' kernel), main beside it 102.2 s, load 9-16; the same results.json numbers to
# the bit as main's at both resolutions. Before, with the candidates' planes alone compiled
# (elements/ply_kernels.py): 289.5 s default (24 of 24 checks, load 7-9; 366.7 s for the code
# before beside it; not time-scaled: docs/hemisphere_plies.md, "Time scaling"), 99.2 s coarse
# (load 5-7).
# The five paper cases at the default resolution: their case_cpu_s in one report of the six
# paper cases (--jobs 1, one numba thread, load 5-13 with other jobs; the band LDL^T within
# its envelope, benchmarks/report.py), bai-6.1.1-sensitivity as before. plies-bai-5.1 and
# plies-deck-of-cards at the default resolution: their case_cpu_s in one report of the two
# (--jobs 1, load 14 -> 5, the code before running beside it: 130.2 and 55.7 s), after a new
# pattern's analysis was made cheaper (benchmarks/report.py). plies-bai-5.1 again, both
# resolutions, after its small facing searches were made cheaper (benchmarks/ply_relist.py):
# case_cpu_s of ``--cases plies-bai-5.1 --jobs 1``, the code before run beside it, coarse 18.1
# s (18.0-18.8 in three runs; before 18.8-20.6), default 72.1 s (before 74.5), load 3.3-4.3.
# The Static ply cases once more (benchmarks/static_plies.py; one thread, --jobs 1, the code
# before, main c0b0822, run beside it, load 7-17): plies-bai-5.1 default, with the ply
# contact's facing made once per Newton iteration, 80.4 -> 75.7 s, the same results to the
# bit; its figure here is the quiet machine's 72.1 s times that ratio (an estimate); likewise
# plies-deck-of-cards default 45.7 -> 43.9 s, 50.4 s times that ratio. bai-5.1
# coarse 13.0 s (warm cache, load 9-10; the 37.7 s before had compiled a cold cache),
# plies-deck-of-cards coarse 13.2 s (the code before, load 10-12). plies-bai-5.1 with its
# stalled attempts cut at 25 iterations (``Static(stall_iterations=25)``,
# benchmarks/static_plies_newton.py): case_cpu_s of ``--cases plies-bai-5.1 --jobs 1``, the
# code before run beside it, default 124.9 -> 82.9 s (load 10-15), coarse 17.2 -> 9.9 s
# (load 13-15); its figures here are those before times these ratios (estimates).
# Default, after the figures were drawn with one layout pass and fewer artists
# (benchmarks/report_overhead.py: the 23 cases' figures and files 17.7 -> 14.8 s CPU): the
# case_cpu_s of ``--cases bai-6.2.2,bai-6.1.2,fibrous-deck-of-cards,fibrous-heavy-cantilever,
# mindlin-plate --jobs 1`` (one thread, a warm numba cache, load 10-14): 13.8, 14.3, 1.1, 0.3
# and 0.4 s; its results.json the same as the code before's in every number.
# hemisphere-plies once more, with the history written at the frame rate and the ply
# penalty law and the cut growths' closest points compiled (benchmarks/
# forming_step_overhead.py): case_cpu_s of ``--cases hemisphere-plies --jobs 1``, main
# 97cc118 run beside it (load 9-14), coarse 50.0 -> 45.4 s, default 134.0 -> 117.7 s, the same
# results.json numbers to the bit; hemisphere-forming default 38.8 s beside main's 38.3 s
# (those cuts do not touch it). hemisphere-plies with the friction's stick spring and the
# facing's ``toward`` in compiled passes (benchmarks/forming_step_overhead.py): main db6c2b7
# run beside it (load 3-9), coarse 47.2 -> 42.5 s, default 116.5 -> 109.0 s, the same
# results.json numbers to the bit. plies-bai-5.1 with its increments sized by their first
# Newton step (``Static(first_turn=0.1)``, benchmarks/static_plies_newton.py): case_cpu_s of
# ``--cases plies-bai-5.1 --jobs 1``, the code before (05b57d7) run beside it, warm caches,
# load 11-15, coarse 9.8 -> 7.4 s, default 42.1 -> 33.8 s, results.json's numbers within
# 1.1e-13 relative; its figures here are those before times these ratios (estimates).
# The five paper cases, default, with the element-normal (Eq. 15) membrane tangent's central
# differences through the compiled passes (benchmarks/paper_cases.py): case_cpu_s of
# ``--cases NAME --jobs 1`` (one thread, a warm numba cache), main 05b57d7 run beside each,
# load 13-17: bai-5.1 21.8 -> 16.5 s, bai-6.1.1 21.2 -> 19.2, bai-6.1.2 14.7 -> 12.9,
# bai-6.2.1 20.5 -> 18.6, bai-6.2.2 13.7 -> 12.4 and 13.6 -> 12.6 (91.9 -> 79.5 s in all);
# the same increments, iterations and cuts, the fibrous and Mindlin runs' numbers to the bit,
# the Eq. 15 runs' within 3e-13 mm or deg. Their figures here are those before times these
# ratios (estimates); coarse not measured again.
# hemisphere-plies with the facing's glue in compiled passes
# and the friction's next mapping made with the history (benchmarks/
# forming_step_overhead.py): main 05b57d7 run beside it (load 12-15), coarse 46.2 -> 40.9 s,
# default 114.7 -> 104.4 s, the same results.json numbers to the bit.
# plies-deck-of-cards' heavy stacks and plies-heavy-cantilever's plies with each Newton update
# turning a director by at most 0.03 rad (``Static(update_turn=0.03)``,
# benchmarks/static_plies_newton.py): case_cpu_s of ``--cases plies-heavy-cantilever,
# plies-deck-of-cards --jobs 1``, the code before (fd53ee8) run beside it, warm caches, load
# 5-17, default 7.8 -> 6.2 s and 32.1 -> 25.2 s, results.json's numbers within 5e-9 relative,
# steps 280 -> 224 and 1977 -> 1731; the default figures here are those before times these
# ratios, the coarse ones those before less the plies' solves' saving measured by the
# benchmark (heavy 2.9 -> 1.7 s, the deck's 4-ply sag 5.0 -> 2.8 s): estimates.
# bai-6.1.1, default, with the sparse node blocks' assembly and the upper triangle's split
# in compiled passes (benchmarks/paper_cases.py): case_cpu_s of ``--cases bai-6.1.1 --jobs
# 1``, main 5781687 run beside it, five pairs, load 2-14: 17.84 -> 16.28 s on average; its
# figure here is the one before times that ratio (an estimate); coarse not measured again.
# The default figures measured anew for every case but the sensitivity (its Dask workers'
# CPU is not counted in its case_cpu_s): case_cpu_s of one whole report, ``--jobs 1``, a
# warm numba cache, main d33e8fc, load 0.9-3.1 (229.5 s in all, every check passed);
# the small cases had kept figures from older, slower code (2-8 x theirs).
# The default figures measured anew (the sparse LDL^T, the ply step's fourth round, the
# decks' curved steps, fewer increments on plies-bai-5.1 and the heavy stacks): case_cpu_s of
# one whole report, ``--jobs 1``, a warm numba cache, main c190105, load 0.9-2.8 (218 s in
# all, every check passed); bai-6.1.1-sensitivity twice its wall (6.8 s: two Dask workers,
# whose CPU its case_cpu_s does not count).
# plies-deck-of-cards with its decks' increments started on soft ply contacts
# (``Static(ply_penalty_start=1e-3)``, benchmarks/static_plies_deck_start.py): case_cpu_s of
# ``--cases plies-deck-of-cards --jobs 1``, a warm numba cache, load 2-4: default 11.2 s,
# coarse 3.6 s (every check passed).
# The default figures measured anew but the sensitivity's (its Dask workers' CPU is not in its
# case_cpu_s, 4.5 s): case_cpu_s of one whole report, ``--jobs 2``, a warm numba cache, main
# 9a25df8, load 1.8-2.0 (192.5 s in all, 187 of 187 checks passed).
# bai-5.1 and plies-bai-5.1 with the arc length aimed at 10 iterations (``arc_iterations``)
# and a phase's first step cut harder: case_cpu_s of ``--cases NAME --jobs 1`` beside the
# code before (benchmarks/arc_iterations.py), load 4.7-7.9: bai-5.1 14.4 -> 8.5 s default,
# 7.8 -> 5.1 coarse; plies-bai-5.1 24.3 -> 21.1 default, 5.0 -> 4.4 coarse.
# The default figures measured anew but the sensitivity's: case_cpu_s of one whole report,
# ``--jobs 2``, a warm numba cache, main 5321585, load 1.9-2.0 (145.6 s in all, 187 of 187
# checks passed; the two-ply hemisphere with the wedge fade's SIDEWAYS 1 and the springs
# weighed by the masses, 74.0 -> 48.9 s). hemisphere-plies again, its springs' bound and
# facing choice compiled and the Mindlin runs' facing lists kept longer: 45.4 s in one whole
# report (--jobs 2, warm cache, main 1ac4991, load 1.8-2.1; 146.4 s in all, 187 of 187).
# The paper cases, the plies' Static cases and both hemispheres measured anew but the
# sensitivity in one whole report (--jobs 2, warm cache, load 1.3-1.8; 128.2 s in all, 187 of
# 187): the plies' kept band plans, the fibrous tangent's chunked scratch, the [0/90] Mindlin
# plies at half the pace.
# The coarse figures measured anew: case_cpu_s of one whole coarse report, ``--jobs 1``, a
# warm numba cache, main 7f9c3d5, load 5-9 (70.4 s in all); the five paper cases' times 0.75
# of theirs since their coarse runs compute no refinement orders (measured 17.4 -> 13.1 s for
# the five). They had kept figures from older code, 2-13 times theirs, so that a first coarse
# report (the test suite's, on a clean checkout) started its small cases before the forming
# runs.
EXPECTED_CPU_S: dict[str, tuple[float, float]] = {
    "bai-5.1": (3.4, 4.6),
    "bai-6.1.1": (3.2, 7.6),
    "bai-6.1.2": (2.5, 5.6),
    "bai-6.2.1": (2.7, 6.6),
    "bai-6.2.2": (2.6, 5.2),
    "bai-6.1.1-sensitivity": (2.3, 13.6),
    "cable-catenary": (0.5, 0.5),
    "cable-elastic-catenary": (0.2, 0.1),
    "bar-wave": (0.4, 0.2),
    "fibrous-curvature": (0.1, 0.1),
    "fibrous-deck-of-cards": (1.1, 0.8),
    "fibrous-heavy-cantilever": (0.2, 0.2),
    "plies-deck-of-cards": (2.2, 5.5),
    "heavy-cantilever-nonlinear": (2.0, 1.8),
    "plies-heavy-cantilever": (1.3, 1.7),
    "plies-bai-5.1": (3.0, 9.7),
    "mindlin-elastica": (0.4, 0.2),
    "mindlin-rollup": (0.1, 0.1),
    "mindlin-plate": (0.3, 0.3),
    "mindlin-scordelis-lo": (0.3, 0.5),
    "mindlin-pinched-cylinder": (0.7, 1.5),
    "hemisphere-forming": (14.7, 24.3),
    "hemisphere-plies": (21.5, 69.1),  # the Mindlin [0/90] part's 20.9 twice since x4
}  # fmt: skip


# The weights of a case's parts in its expected cost (``EXPECTED_CPU_S``) for the order of a
# first report (a folder without the last report's part times): a part's weight is the first
# entry whose words its key holds (hemisphere-plies' keys are "8 cells 0/90 mindlin 20 N" and
# the like, hemisphere-forming's "fibrous", "mindlin", "fibrous n = 12", ...), a part that
# holds none weighs 1 and so does every part of a case not listed. Unequal parts shared
# evenly start the longest one late, on a fresh folder. The parts' CPU times (s) of
# ``python -m validation --cases hemisphere-plies,hemisphere-forming --jobs 2`` at the
# default resolution (results.json's "parts"; one thread, a warm numba cache, main 2d1abf1,
# load 1.2-1.6; 42.1 s of wall). At the fine resolution a forming run on another mesh weighs
# as its kinematics' default run: an order, not a promise.
EXPECTED_PART_WEIGHTS: dict[str, dict[str, float]] = {
    "hemisphere-plies": {
        "0/90 mindlin": 41.8,  # 20.9 at x2, twice the steps slowed x4 (the case's docstring)
        "0/45 mindlin": 13.8,
        "0/45 fibrous": 9.0,
        "0/90 fibrous": 6.5,
    },
    "hemisphere-forming": {"mindlin": 16.1, "fibrous": 8.6},
}


def part_weight(name: str, key: str) -> float:
    """The weight of part ``key`` of case ``name`` in its expected cost
    (``EXPECTED_PART_WEIGHTS``): the first listed words its key holds, else 1."""
    weights = EXPECTED_PART_WEIGHTS.get(name, {})
    return next((weight for words, weight in weights.items() if words in key), 1.0)


def expected_cost(name: str, resolution: str) -> float:
    """The expected CPU time (s) of case ``name`` at ``resolution`` (``EXPECTED_CPU_S``; the
    fine resolution's order is the default's), infinite for a case not measured yet: a new
    case starts first, as it may be the longest."""
    coarse, default = EXPECTED_CPU_S.get(name, (float("inf"), float("inf")))
    return coarse if resolution == "coarse" else default


def measured_costs(out_dir: Path, names: list[str], resolution: str) -> dict[str, float] | None:
    """The case times (s) of the report already in ``out_dir`` (its results.json), when it
    ran every one of ``names`` at ``resolution`` without an error; None otherwise (no report
    there, another resolution, a case missing or failed, a file that does not read)."""
    try:
        content = json.loads((out_dir / "results.json").read_text())
        if content["resolution"] != resolution:
            return None
        cases = content["cases"]
        costs = {name: float(cases[name]["case_time_s"]) for name in names}
        if any("error" in cases[name] for name in names):
            return None
    except (OSError, ValueError, KeyError, TypeError):
        return None
    return costs if all(np.isfinite(list(costs.values()))) else None


def measured_part_costs(
    out_dir: Path, names: list[str], resolution: str
) -> dict[str, dict[str, float]]:
    """The part times (s) of the cases in parts among ``names`` in the report already in
    ``out_dir`` (its results.json's "parts" entries, wall time), by case name and part key,
    when that report ran at ``resolution``; a case without them (no report there, another
    resolution, a failed case, a case not in parts then) is left out."""
    try:
        content = json.loads((out_dir / "results.json").read_text())
        if content["resolution"] != resolution:
            return {}
        cases = content["cases"]
    except (OSError, ValueError, KeyError, TypeError):
        return {}
    found = {}
    for name in names:
        try:
            entry = cases[name]
            costs = {key: float(part["time_s"]) for key, part in entry["parts"].items()}
        except (KeyError, TypeError, ValueError, AttributeError):
            continue
        if "error" not in entry and all(np.isfinite(list(costs.values()))):
            found[name] = costs
    return found


def schedule(
    names: list[str], resolution: str, measured: dict[str, float] | None = None
) -> list[str]:
    """``names`` whole, the largest cost first, report order among equals (the order the
    benchmarks run cases in; the report's workers take ``schedule_tasks``, a case in parts as
    its parts); the cost is ``measured`` (``measured_costs``, case times of the last report)
    when given, else ``expected_cost``."""
    if measured is not None:
        return sorted(names, key=lambda name: -measured[name])
    return sorted(names, key=lambda name: -expected_cost(name, resolution))


def schedule_tasks(
    names: list[str],
    resolution: str,
    measured: dict[str, float] | None = None,
    measured_parts: dict[str, dict[str, float]] | None = None,
) -> list[tuple[str, str | None]]:
    """The worker pool's tasks, (case name, part key or None for the whole case), in the
    order the workers start them: one per case, or one per part of a case in parts
    (``Case.parts``); the largest cost first, report order and then the parts' order among
    equals. A whole case costs as in ``schedule``; a part its time in the last report
    (``measured_part_costs``) when that report timed every part of its case, else its case's
    cost (``measured`` or ``expected_cost``) shared among its parts by their weights
    (``part_weight``; evenly for a case not listed there). The last report's
    part times serve only with ``measured`` (wall times both), never beside the table's CPU
    times."""
    tasks: list[tuple[float, str, str | None]] = []
    for name in names:
        case_cost = measured[name] if measured is not None else expected_cost(name, resolution)
        parts = CASES[name].parts
        if parts is None:
            tasks.append((case_cost, name, None))
            continue
        keys = list(parts(resolution))
        last = (measured_parts or {}).get(name, {}) if measured is not None else {}
        weights = {key: part_weight(name, key) for key in keys}
        for key in keys:
            share = weights[key] / sum(weights.values())
            cost = last[key] if set(last) == set(keys) else case_cost * share
            tasks.append((cost, name, key))
    return [(name, key) for _, name, key in sorted(tasks, key=lambda task: -task[0])]


def default_jobs() -> int:
    """The cases run at once by default: the cores free for the report (femcore.jit's
    ``free_cores``: those this process may run on less those other processes keep busy), at
    least one."""
    return free_cores()


def run_case(name: str, resolution: str, out_dir: Path) -> CaseResult:
    """Compute the named case at ``resolution``, then draw its figures and write its files
    into ``out_dir``.

    A case that raises (in its computation or its figures), or whose ``render`` returns a
    figure without a caption (a file name rather than a ``Figure``), is recorded as failed,
    with its error, and not raised.

    A case in parts (``Case.parts``) runs them one after another here, each timed, then
    combines them: its result's ``parts`` holds each part's (wall, CPU) time, s.
    """
    case = CASES[name]
    started, cpu = time.perf_counter(), time.process_time()
    times: dict[str, tuple[float, float]] = {}
    with kept_warnings() as warned:
        try:
            if case.parts is None:
                outcome = case.compute(resolution)
            else:
                data = {}
                for key, part in case.parts(resolution).items():
                    part_started, part_cpu = time.perf_counter(), time.process_time()
                    data[key] = part()
                    times[key] = (
                        time.perf_counter() - part_started,
                        time.process_time() - part_cpu,
                    )
                assert case.combine is not None  # Case requires both
                outcome = case.combine(resolution, data)
            outcome = _drawn(case, outcome, out_dir)
        except Exception as error:  # a broken case is reported, never hidden
            outcome = Outcome.failed(error)
    return CaseResult(
        case=case,
        outcome=replace(outcome, warnings=tuple(warned)),
        case_time_s=time.perf_counter() - started,
        case_cpu_s=time.process_time() - cpu,
        parts=None if case.parts is None else times,
    )


def _drawn(case: Case, outcome: Outcome, out_dir: Path) -> Outcome:
    """``outcome`` with the figures ``case.render`` drew of its data into ``out_dir``; a
    TypeError when one of them is not a ``Figure`` (a file name without a caption)."""
    figures = list(case.render(outcome.data, out_dir))
    for figure in figures:
        if not isinstance(figure, Figure):
            raise TypeError(
                f"case {case.name!r}: figure {figure!r} has no caption: its render returns "
                "validation.records.Figure(file, caption) records, a caption of a sentence "
                "or two (what is shown, which kinematics, what to look at)"
            )
    return replace(outcome, figures=[_sized(figure, out_dir) for figure in figures])


def _combined(
    case: Case,
    resolution: str,
    data: dict[str, bytes],
    times: dict[str, tuple[float, float]],
    error: str | None,
    out_dir: Path,
    warned: list[str] | None = None,
) -> CaseResult:
    """The result of a case whose parts ran in the workers: their ``data`` (pickled) by key,
    in the parts' order, combined and drawn here; or, when a part raised, the ``error`` (its
    text) of the first such part in their order. The case's wall and CPU times are the sums
    of the parts' ``times`` (wall, CPU; s) and this step's: what the case costs, as in one
    process (``CaseResult``), not the span from its first part's start to its end, which the
    other tasks beside it stretch. ``warned``: the warnings the parts raised, in their
    order, to which those of this step are added."""
    started, cpu = time.perf_counter(), time.process_time()
    with kept_warnings() as here:
        if error is not None:
            outcome = Outcome.failed(error)
        else:
            try:
                assert case.combine is not None  # Case requires both
                made = {key: pickle.loads(payload) for key, payload in data.items()}
                outcome = _drawn(case, case.combine(resolution, made), out_dir)
            except Exception as failure:  # a broken case is reported, never hidden
                outcome = Outcome.failed(failure)
    every = list(dict.fromkeys([*(warned or []), *here]))  # each once, in order
    return CaseResult(
        case=case,
        outcome=replace(outcome, warnings=tuple(every)),
        case_time_s=time.perf_counter() - started + sum(wall for wall, _ in times.values()),
        case_cpu_s=time.process_time() - cpu + sum(used for _, used in times.values()),
        parts=times,
    )


def _sized(figure: Figure, out_dir: Path) -> Figure:
    """``figure`` with the pixel size of its PNG in ``out_dir`` (read from the PNG header),
    or as it is when the file is not a PNG."""
    try:
        with open(out_dir / figure.file, "rb") as file:
            head = file.read(24)
    except OSError:
        return figure
    if head[:8] != b"\x89PNG\r\n\x1a\n" or head[12:16] != b"IHDR":
        return figure
    width, height = (int.from_bytes(head[k : k + 4], "big") for k in (16, 20))
    return replace(figure, width=width, height=height)


def _start_worker(parent: int) -> None:
    """A worker's initializer: ``_end_with(parent)``, then ``_settled``."""
    _end_with(parent)
    _settled()


def _settled() -> None:
    """Move what the worker's imports made (the case modules, numba, scipy, matplotlib: some
    140k objects) out of the cyclic garbage collector's reach (``gc.freeze``) once collected,
    so that a full collection during a case walks only what the cases made since. A full
    collection walked them all, 0.3-0.4 s of CPU each, about one a case (benchmarks/
    report_gc.py); the frozen objects live as long as the worker, which they would anyway.
    No number of a case changes: the collector frees memory, it computes nothing."""
    gc.collect()
    gc.freeze()


def _end_with(parent: int) -> None:
    """A worker's initializer: end the worker once the process ``parent`` (pid) that started it
    is gone. Killed (kill -9, an out-of-memory kill, a closed terminal), the report runs no
    clean-up, and a worker would otherwise finish its case, and the pool's queue, on cores
    nobody wants any more. On Linux the kernel kills it (prctl PR_SET_PDEATHSIG: nothing in the
    worker has to run, where a compiled loop may hold the interpreter for minutes); elsewhere a
    daemon thread watches the parent."""
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        dead_parent_signal = libc.prctl(1, signal.SIGKILL, 0, 0, 0) == 0  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):  # not Linux
        dead_parent_signal = False
    if os.getppid() != parent:  # gone before the signal was asked for
        os._exit(1)
    if dead_parent_signal:
        return

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(0.5)
        os._exit(1)  # no clean-up is wanted: the report that would read the results is gone

    threading.Thread(target=watch, name="end-with-the-report", daemon=True).start()


def _run_in_worker(name: str, resolution: str, out_dir: Path, threads: int):
    """``run_case`` in a worker process: (outcome without its figure data, which stays with
    the worker that drew it, the case time and its CPU time)."""
    import numba

    numba.set_num_threads(threads)  # the cores are shared between the workers
    result = run_case(name, resolution, out_dir)
    return replace(result.outcome, data=None), result.case_time_s, result.case_cpu_s


def _run_part_in_worker(case: Case, resolution: str, key: str, threads: int):
    """One part of ``case`` (``Case.parts``) in a worker process: (its data pickled, None, the
    warnings it raised, its wall time, its CPU time, the pickling's included), or (None, the
    error's text, ...) when it raised. Pickled here, so that the part's time holds what
    sending its data costs (the parent's unpickling is in the combining step's)."""
    import numba

    numba.set_num_threads(threads)  # the cores are shared between the workers
    started, cpu = time.perf_counter(), time.process_time()
    with kept_warnings() as warned:
        try:
            assert case.parts is not None
            data = case.parts(resolution)[key]()
            payload, error = pickle.dumps(data, protocol=pickle.HIGHEST_PROTOCOL), None
        except Exception as failure:  # the case is reported failed, never hidden
            payload, error = None, Outcome.failed(failure).error
    return payload, error, warned, time.perf_counter() - started, time.process_time() - cpu


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
        Every case's outcome; a case that raised is recorded as failed and the others run, as
        is a case whose worker process died (killed, out of memory) before it was done.

    Raises
    ------
    ValueError
        A name that is not a case, a name given twice, or a case in parts with no part at
        ``resolution``.
    fibreshell.FolderInUse
        ``out_dir`` is held by another command (another report, a run: the message names
        it), before any case runs; the report holds it until it returns.
    """
    _check_names(names, resolution)
    out_dir.mkdir(parents=True, exist_ok=True)
    # One report at a time in a folder: two would replace each other's figures and files.
    with folder_lock(out_dir, f"the validation report into {str(out_dir)!r}", "--out"):
        return _run_cases_locked(names, resolution, out_dir, echo, jobs)


def _run_cases_locked(
    names: list[str], resolution: str, out_dir: Path, echo: Callable[..., Any], jobs: int
) -> Report:
    """``run_cases`` in its folder ``out_dir``, which it holds (fibreshell.folder_lock)."""
    # before this report replaces them
    measured = measured_costs(out_dir, names, resolution)
    measured_parts = measured_part_costs(out_dir, names, resolution)
    # One line per case here: the solvers' own progress lines stay off (workers inherit it).
    before = os.environ.get("FIBRESHELL_PROGRESS")
    os.environ["FIBRESHELL_PROGRESS"] = "0"
    try:
        results = _run_all(names, resolution, out_dir, echo, jobs, measured, measured_parts)
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


def _check_names(names: list[str], resolution: str) -> None:
    """A ValueError when ``names`` holds an unknown case, repeats a case (its parts would be
    run and combined twice; a whole case would be run once for two entries) or holds a case in
    parts with no part at ``resolution`` (there would be nothing to combine)."""
    repeated = sorted({name for name in names if names.count(name) > 1})
    if repeated:
        raise ValueError(
            f"case name(s) {', '.join(repeated)} given more than once: expected each case once"
        )
    unknown = [name for name in names if name not in CASES]
    if unknown:
        raise ValueError(
            f"unknown case name(s) {', '.join(unknown)}: expected some of {', '.join(CASES)}"
        )
    for name in names:
        parts = CASES[name].parts
        if parts is not None and not parts(resolution):
            raise ValueError(
                f"case {name!r} has no parts at resolution {resolution!r}: a case in parts "
                "needs at least one (Case.parts) to combine"
            )


def _died(error: BaseException) -> str:
    """The error recorded for a task the pool lost (``error``, its BrokenProcessPool): a
    worker process died (a kill -9, an out-of-memory kill), and the pool ended the others."""
    return (
        "its worker process died before it was done (killed, out of memory?), or another "
        f"worker's did and the pool ended it: {error}"
    )


def _end_workers(workers: set[Any]) -> None:
    """Terminate the ``workers`` (multiprocessing processes) and wait for them, a few seconds
    at most each; kill one that is still there (a handler of SIGTERM that a case set)."""
    for worker in workers:
        worker.terminate()
    for worker in workers:
        worker.join(timeout=5.0)
        if worker.is_alive():
            worker.kill()
            worker.join(timeout=5.0)


def _run_all(
    names: list[str],
    resolution: str,
    out_dir: Path,
    echo: Callable[..., Any],
    jobs: int,
    measured: dict[str, float] | None = None,
    measured_parts: dict[str, dict[str, float]] | None = None,
) -> dict[str, CaseResult]:
    """The cases of ``run_cases``, one after another or in ``jobs`` worker processes: the
    tasks of ``schedule_tasks`` (a case, or a part of a case in parts) the longest first by
    ``measured`` and ``measured_parts``, the last report's times, else ``EXPECTED_CPU_S``. A
    case in parts is combined and drawn here once its last part is in, while the workers go
    on with the other tasks."""
    results: dict[str, CaseResult] = {}

    def done(result: CaseResult, before: str = "") -> None:
        status = (
            "ERROR " + result.outcome.error
            if result.outcome.error is not None
            else f"{result.passed}/{result.counted} checks passed"
        )
        cpu = "" if result.case_cpu_s is None else f" ({result.case_cpu_s:.1f} s CPU)"
        echo(f"{before}{result.case_time_s:.1f} s{cpu}, {status}")

    tasks = schedule_tasks(names, resolution, measured, measured_parts) if jobs > 1 else []
    jobs = min(jobs, len(tasks))  # one task runs here, without a worker to spawn
    if jobs <= 1:
        for i, name in enumerate(names, 1):
            echo(f"[{i}/{len(names)}] {name}: {CASES[name].title} ...", end=" ", flush=True)
            results[name] = run_case(name, resolution, out_dir)
            done(results[name])
        return results
    # Spawned workers: numba's thread pool must not be forked. The longest task first.
    context = multiprocessing.get_context("spawn")
    # The cores shared between the workers, never more threads than numba may start
    # (NUMBA_NUM_THREADS, which the spawned workers inherit).
    most = numba.config.NUMBA_NUM_THREADS  # type: ignore[attr-defined]
    threads = max(1, min((os.cpu_count() or 1) // jobs, most))
    # a case in parts: its parts' keys in their order, the data, times and errors of those in
    waiting = {
        name: list(parts(resolution)) for name in names if (parts := CASES[name].parts) is not None
    }
    gathered: dict[str, dict[str, Any]] = {name: {} for name in names}
    timed: dict[str, dict[str, tuple[float, float]]] = {name: {} for name in names}
    failed: dict[str, dict[str, str]] = {name: {} for name in names}
    raised: dict[str, dict[str, list[str]]] = {name: {} for name in names}  # warnings
    before = set(multiprocessing.active_children())
    pool = ProcessPoolExecutor(
        jobs, mp_context=context, initializer=_start_worker, initargs=(os.getpid(),)
    )
    try:
        futures = {}
        for name, key in tasks:
            if key is None:
                future = pool.submit(_run_in_worker, name, resolution, out_dir, threads)
            else:
                future = pool.submit(_run_part_in_worker, CASES[name], resolution, key, threads)
            futures[future] = (name, key)
        for future in as_completed(futures):
            name, key = futures[future]
            died = future.exception()
            if died is not None and not isinstance(died, BrokenProcessPool):
                raise died  # the report's own machinery failed: not a case's error
            if key is None:
                if died is not None:
                    results[name] = CaseResult(CASES[name], Outcome.failed(_died(died)), 0.0)
                else:
                    outcome, seconds, cpu = future.result()
                    results[name] = CaseResult(CASES[name], outcome, seconds, cpu)
            else:
                if died is not None:
                    data, error, warned, seconds, cpu = None, _died(died), [], 0.0, 0.0
                else:
                    data, error, warned, seconds, cpu = future.result()
                raised[name][key] = warned
                size = f", {len(data) / 1e6:.1f} MB of data" if data is not None else ""
                echo(f"  {name}, part {key}: {seconds:.1f} s ({cpu:.1f} s CPU){size}")
                timed[name][key] = (seconds, cpu)
                if error is not None:
                    failed[name][key] = error
                gathered[name][key] = data
                if len(timed[name]) < len(waiting[name]):
                    continue
                order = waiting[name]  # the parts' own order, for combine
                results[name] = _combined(
                    CASES[name],
                    resolution,
                    {k: gathered[name].pop(k) for k in order},
                    {k: timed[name][k] for k in order},
                    next((failed[name][k] for k in order if k in failed[name]), None),
                    out_dir,
                    [text for k in order for text in raised[name][k]],
                )
            done(results[name], f"[{len(results)}/{len(names)}] {name}: {CASES[name].title}: ")
    except BaseException:
        # Ctrl-C (or any error here): the pool's exit would wait for every queued task, and
        # the workers, which take a KeyboardInterrupt as a task's result, would run them all.
        pool.shutdown(wait=False, cancel_futures=True)
        _end_workers(set(multiprocessing.active_children()) - before)
        raise
    pool.shutdown(wait=True)
    return {name: results[name] for name in names}  # report order


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
