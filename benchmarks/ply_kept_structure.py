"""K_ff's structure kept over the plies' changing contact pairs (femcore/assembly.py
``FreeTangentAssembler(superset=True)``, which Static's tangent takes) against one built anew
at every new pattern, both with the kept band plans (solvers/linear.py ``KEEP_BAND_PLANS``),
on the report's three Static ply cases (``python -m validation``'s ``compute``: plies-bai-5.1,
plies-deck-of-cards, plies-heavy-cantilever).

Each case both ways in alternating turns in this process, best of ``--repeat``: the case's CPU
(``time.process_time``, one thread), the CPU inside the structure's restructuring
(``FreeTangentAssembler._restructure``: the parts' node pairs, their lookup and the builds)
and the upper triangle's plan of each new K_ff pattern (``LinearSolver._plan_for``), the
whole assembly's, the tangents, the structures built, the orderings, and a digest of the
case's checks (the same bits both ways: the kept structure's extra entries are stored zeros
the upper triangle's split leaves out, docs/theory.md §6.5). The machine's load is printed.

    python benchmarks/ply_kept_structure.py [--cases plies-bai-5.1,...]
        [--resolution default] [--repeat 2]

Measured (one thread, CPU, 2 cores shared, load 7.6-14.2, default resolution, best of 2;
kept / built anew):

* plies-bai-5.1: restructuring and upper plans 0.45 / 1.36 s (0.28 + 0.16 / 0.75 + 0.61),
  the assembly 1.48 / 1.84 s; tangents 847 both ways, structures 42 / 304, orderings 30;
  case CPU 11.89 / 13.06 s.
* plies-deck-of-cards: 0.31 / 0.53 s (0.20 + 0.10 / 0.32 + 0.21), assembly 0.66 / 0.77 s;
  tangents 820, structures 126 / 406, orderings 121; case CPU 6.44 / 6.78 s.
* plies-heavy-cantilever: 0.06 / 0.11 s (0.04 + 0.02 / 0.07 + 0.05), assembly 0.16 / 0.18 s;
  tangents 189, structures 16 / 73, orderings 22; case CPU 1.71 / 1.72 s.
* The checks' digest the same both ways on each case. The cases' CPU moves with the load as
  much as by the parts (an earlier pair of turns of plies-bai-5.1, load 10-12: 13.10 / 12.67
  s, kept / built anew); the parts' timers are the measure.
"""

from __future__ import annotations

import argparse
import hashlib
import os
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

from femcore import assembly  # noqa: E402
from solvers import linear, newton  # noqa: E402
from validation.report import CASES  # noqa: E402

KEEP = {"superset": True}
SPENT = {"restructure": 0.0, "upper plan": 0.0, "assembly": 0.0}
MADE: dict[str, list] = {"assemblers": [], "solvers": []}
COUNTS = {"tangents": 0}


class Assembler(assembly.FreeTangentAssembler):
    """Static's assembler with the structure kept or not (``KEEP``), counted."""

    def __init__(self, dofs, superset: bool = False):
        super().__init__(dofs, superset=KEEP["superset"])
        MADE["assemblers"].append(self)

    def __call__(self, parts, frames):
        COUNTS["tangents"] += 1
        return super().__call__(parts, frames)


def _timed(owner, name: str, label: str) -> None:
    """``owner.name`` with its CPU added to ``SPENT[label]``."""
    original = getattr(owner, name)

    def timed(self, *args, **kwargs):
        start = time.process_time()
        try:
            return original(self, *args, **kwargs)
        finally:
            SPENT[label] += time.process_time() - start

    setattr(owner, name, timed)


def _install() -> None:
    _timed(assembly.FreeTangentAssembler, "_restructure", "restructure")
    _timed(assembly.FreeTangentAssembler, "__call__", "assembly")
    _timed(linear.LinearSolver, "_plan_for", "upper plan")
    made = linear.LinearSolver.__init__

    def counted(self):
        made(self)
        MADE["solvers"].append(self)

    linear.LinearSolver.__init__ = counted  # type: ignore[method-assign]
    newton.FreeTangentAssembler = Assembler  # type: ignore[misc]


def run(name: str, resolution: str, kept: bool) -> dict:
    """One ``compute`` of the case: its CPU, the parts', the counts and the checks' digest."""
    KEEP["superset"] = kept
    SPENT.update(dict.fromkeys(SPENT, 0.0))
    MADE["assemblers"].clear()
    MADE["solvers"].clear()
    COUNTS["tangents"] = 0
    start = time.process_time()
    outcome = CASES[name].compute(resolution)
    cpu = time.process_time() - start
    checks = repr([(check.name, check.value) for check in outcome.checks]).encode()
    return {
        "cpu": cpu,
        **SPENT,
        "tangents": COUNTS["tangents"],
        "structures": sum(a.builds for a in MADE["assemblers"]),
        "orderings": sum(s.symbolic for s in MADE["solvers"]),
        "digest": hashlib.sha1(checks).hexdigest()[:12],
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--cases", default="plies-bai-5.1,plies-deck-of-cards,plies-heavy-cantilever"
    )
    parser.add_argument("--resolution", default="default")
    parser.add_argument("--repeat", type=int, default=2)
    args = parser.parse_args()
    _install()
    print(f"load {os.getloadavg()}", flush=True)
    for name in args.cases.split(","):
        run(name, "coarse", True)  # the kernels loaded
        best: dict[bool, dict] = {}
        for turn in range(args.repeat):
            for kept in (True, False) if turn % 2 == 0 else (False, True):
                found = run(name, args.resolution, kept)
                parts = found["restructure"] + found["upper plan"]
                if kept not in best or parts < best[kept]["restructure"] + best[kept]["upper plan"]:
                    best[kept] = found
        a, b = best[True], best[False]
        print(
            f"{name} ({args.resolution}), kept / built anew: restructuring and upper plans "
            f"{a['restructure'] + a['upper plan']:.2f} / {b['restructure'] + b['upper plan']:.2f} "
            f"s ({a['restructure']:.2f} + {a['upper plan']:.2f} / {b['restructure']:.2f} + "
            f"{b['upper plan']:.2f}), assembly {a['assembly']:.2f} / {b['assembly']:.2f} s; "
            f"tangents {a['tangents']} / {b['tangents']}, structures {a['structures']} / "
            f"{b['structures']}, orderings {a['orderings']} / {b['orderings']}; case CPU "
            f"{a['cpu']:.2f} / {b['cpu']:.2f} s; checks {a['digest']} / {b['digest']}",
            flush=True,
        )
    print(f"load {os.getloadavg()}")


if __name__ == "__main__":
    main()
