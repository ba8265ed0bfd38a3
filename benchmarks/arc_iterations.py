"""A paper case's computation with its arc-length steps aimed at the default 5 Newton iterations
an increment (the reference pass) beside the case's ``arc_iterations`` (validation/paper/case.py
``PaperCase.arc_iterations``, Static's ``arc_iterations``): CPU of the whole computation (its
three runs and the orders' four), Newton iterations, tangents (the failed attempts' included),
and how far each check's value moved from the reference pass's.

    python benchmarks/arc_iterations.py --cases bai-5.1 --aims 8,10,14 --resolution default

Measured (one numba thread, CPU, one process, 2 cores shared with other jobs, load 9-10):
  bai-5.1 default, aim 5 -> 10: 12.2 -> 7.4 s (8: 8.2 s, 14: 8.0 s), 1805 -> 965 Newton
    iterations over the seven runs, every check's value within 1.2e-8 relative (the Eq. 15
    tilt, 4e-14 deg, is round-off). The fibrous run at 30 cells: 55 -> 18 increments, 266 ->
    134 iterations, 359 -> 227 tangents; its 7 failed attempts are the rest (one in the
    gravity phase, six halving the first displacement increment to 1/64 of its tangent's,
    12 iterations each before the stall rule cuts them), now 41 % of its tangents (the
    Mindlin run's 13, 54 %). Coarse (load 7.5): 5.3 -> 3.0 s, 1450 -> 840 iterations, 1964
    -> 1391 tangents, the checks within 8.4e-10 relative. Those figures are from before a
    phase's first step was cut harder at each failure (1/2, 1/8, 1/64 of the tangent's guess,
    solvers/arc_length.py): that cut, measured beside the halving at aim 10 (default, load
    9-10), 1696 -> 1462 tangents, 8.6 -> 6.5 s, the checks within 9.3e-13.
  The other paper cases at 10 (load 7-11): bai-6.1.2 693 -> 578 iterations but 8.6 -> 8.9 s,
    bai-6.2.2 700 -> 620 and 8.4 -> 8.0 s, bai-6.1.1 448 -> 467 and 12.3 -> 11.4 s, bai-6.2.1
    392 -> 392 and 9.9 -> 9.4 s: within the machine's noise, so they keep the default.
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys
import time
from dataclasses import replace
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this tree's packages

import solvers.static as static  # noqa: E402
from solvers.arc_length import DESIRED_ITERATIONS  # noqa: E402
from validation.paper.case import compute_paper_case  # noqa: E402


def _spec(name: str):
    """The PaperCase of case ``name`` ("bai-5.1" -> validation.cases.bai_5_1.SPEC)."""
    module = "validation.cases." + name.replace("-", "_").replace(".", "_")
    return importlib.import_module(module).SPEC


def measure(name: str, aims: list[int], resolution: str) -> None:
    """Print the case's computation at the default aim and at each of ``aims``."""
    spec = _spec(name)
    tangents = [0]
    original = static.StaticRun.tangent

    def counted(self, *args, **kwargs):
        tangents[0] += 1
        return original(self, *args, **kwargs)

    static.StaticRun.tangent = counted  # type: ignore[method-assign]
    try:
        outcomes = {}
        for aim in [DESIRED_ITERATIONS, *aims]:
            tangents[0] = 0
            started = time.process_time()
            outcome = compute_paper_case(replace(spec, arc_iterations=aim), resolution)
            cpu = time.process_time() - started
            outcomes[aim] = outcome
            passed = sum(check.passed for check in outcome.checks)
            print(
                f"{name} {resolution} aim {aim:2d}: {cpu:6.2f} s CPU, {outcome.steps} Newton "
                f"iterations, {tangents[0]} tangents, {passed}/{len(outcome.checks)} checks "
                f"passed (load {os.getloadavg()[0]:.1f})",
                flush=True,
            )
    finally:
        static.StaticRun.tangent = original  # type: ignore[method-assign]
    reference = outcomes[DESIRED_ITERATIONS]
    for aim in aims:
        moved = [
            abs(new.value - old.value) / abs(old.value)
            for old, new in zip(reference.checks, outcomes[aim].checks)
            if abs(old.value) > 1e-10  # values at round-off (a tilt of 1e-14 deg) left out
        ]
        print(
            f"  aim {aim}: the checks' values moved at most {max(moved, default=0.0):.2e} relative"
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", default="bai-5.1", help="comma-separated paper cases")
    parser.add_argument("--aims", default="10", help="comma-separated arc_iterations to try")
    parser.add_argument("--resolution", default="default")
    args = parser.parse_args()
    import numba

    numba.set_num_threads(1)
    os.environ.setdefault("FIBRESHELL_PROGRESS", "0")
    aims = [int(value) for value in args.aims.split(",")]
    for name in args.cases.split(","):
        measure(name.strip(), aims, args.resolution)


if __name__ == "__main__":
    main()
