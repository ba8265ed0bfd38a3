"""A cheap validation case in parts for the report's tests (tests/test_report_parts.py):
three independent parts, each a dense linear solve seeded by its key, combined into one
outcome whose numbers depend on every bit of every part's data and on the parts' order; and
the same case with a fourth part that raises (``BROKEN``); one whose second part kills its own
worker process a second into it (``KILLING``, a worker killed by the kernel); one of six parts
that sleep (``SLEEPING``, a report to interrupt); one whose fourth part warns (``WARNING``)
and a case in one task that warns (``WARNING_WHOLE``). Importable by the report's spawned
workers (pytest puts tests/ on sys.path, which a spawned process inherits), which unpickle
its functions."""

import os
import signal
import time
import warnings
from dataclasses import replace
from functools import partial
from pathlib import Path
from typing import Any

import numpy as np

from validation.checks import check
from validation.records import Case, Outcome, compute_parts

__all__ = ["BROKEN", "CASE", "KILLING", "SIZE", "SLEEPING", "WARNED", "WARNING", "WARNING_WHOLE"]

SIZE = 60  # unknowns of each part's system
WARNED = "a part that warns, on purpose"  # what ``WARNING``'s part and ``WARNING_WHOLE`` say


def _part(seed: int) -> dict[str, Any]:
    """A diagonally dominant system seeded by ``seed``, solved: its matrix, load and
    solution."""
    rng = np.random.default_rng(seed)
    matrix = rng.random((SIZE, SIZE)) + SIZE * np.eye(SIZE)
    load = rng.random(SIZE)
    return {"matrix": matrix, "load": load, "solution": np.linalg.solve(matrix, load)}


def _broken() -> None:
    raise ValueError("a part that fails, on purpose")


def _warns() -> dict[str, Any]:
    warnings.warn(WARNED, stacklevel=1)
    return _part(5)


def _killed() -> None:
    time.sleep(1.0)  # the other case's parts (a millisecond each) are in by then
    os.kill(os.getpid(), signal.SIGKILL)


def _slept(seconds: float) -> float:
    time.sleep(seconds)
    return seconds


def parts(resolution: str) -> dict[str, Any]:
    return {f"seed {seed}": partial(_part, seed) for seed in (3, 1, 2)}


def broken_parts(resolution: str) -> dict[str, Any]:
    return {**parts(resolution), "broken": _broken}


def warning_parts(resolution: str) -> dict[str, Any]:
    return {**parts(resolution), "warns": _warns}


def warning_compute(resolution: str) -> Outcome:
    return compute_parts(warning_parts, combine, resolution)


def killing_parts(resolution: str) -> dict[str, Any]:
    return {"seed 4": partial(_part, 4), "killed": _killed}


def sleeping_parts(resolution: str) -> dict[str, Any]:
    return {f"sleep {i}": partial(_slept, 5.0) for i in range(6)}


def combine(resolution: str, made: dict[str, Any]) -> Outcome:
    solutions = np.concatenate([record["solution"] for record in made.values()])
    residual = max(
        float(np.abs(r["matrix"] @ r["solution"] - r["load"]).max()) for r in made.values()
    )
    return Outcome(
        converged=True,
        wall_time_s=0.0,
        steps=len(made),
        solver="numpy.linalg.solve",
        parameters={
            "keys": list(made),
            "solution_sum": float(solutions.sum()),
            "weighted_sum": float(solutions @ np.arange(solutions.size)),
            "first_values": solutions[:4],
        },
        checks=[
            check(
                "the largest residual of the parts' systems",
                0.0,
                residual,
                1e-12,
                relative=False,
                source="the systems solved",
            )
        ],  # fmt: skip
        data=solutions,
    )


def compute(resolution: str) -> Outcome:
    return compute_parts(parts, combine, resolution)


def render(data: np.ndarray, out_dir: Path) -> list:
    np.savetxt(out_dir / "cheap-parts.txt", data)
    return []


CASE = Case(
    name="cheap-parts",
    title="A cheap case in parts",
    source="none: the report's machinery",
    description=__doc__,
    group="verification",
    order=999,
    compute=compute,
    render=render,
    parts=parts,
    combine=combine,
)
BROKEN = replace(CASE, name="cheap-parts-broken", parts=broken_parts)
KILLING = replace(CASE, name="cheap-parts-killing", parts=killing_parts)
SLEEPING = replace(CASE, name="cheap-parts-sleeping", parts=sleeping_parts)
WARNING = replace(CASE, name="cheap-parts-warning", parts=warning_parts)
WARNING_WHOLE = replace(
    CASE, name="cheap-warning", compute=warning_compute, parts=None, combine=None
)
