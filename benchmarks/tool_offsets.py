"""What keeping a rigid tool's offset per load factor saves an explicit forming run
(elements.tools.RigidTool.offset and ``moves``): the report's hemisphere-forming case
computed in one process with the offset and ``moves`` as they were written before (the
amplitude and ``np.any`` evaluated at every call, some ten calls a step; kept here as the
reference pass) and as they are, in turn; the CPU time of each and whether every check value
and parameter came out the same.

Measured (one thread, CPU time, 2 cores shared with other jobs, load 4.7-5.7; two rounds,
reference then now in each): hemisphere-forming coarse (the fibrous and the Mindlin run at
12 cells, 16.6k and 27.8k steps) 30.2 / 28.2 s reference, 26.3 / 25.7 s now (-11 %); every
check value and parameter the same (the same bits: the same product of the same numbers).

Run: python benchmarks/tool_offsets.py [--cases hemisphere-forming] [--resolution coarse]
[--repeats 1]
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
os.environ.setdefault("NUMBA_NUM_THREADS", "1")
os.environ["FIBRESHELL_PROGRESS"] = "0"

from elements.tools import RigidTool  # noqa: E402


def reference_moves(self) -> bool:
    """The reference pass: ``RigidTool.moves`` as it was."""
    return bool(np.any(self.motion != 0.0))


def reference_offset(self, load_factor: float) -> np.ndarray:
    """The reference pass: ``RigidTool.offset`` as it was."""
    if not self.moves:
        return np.zeros(3)
    return float(self.amplitude(load_factor)) * self.motion


def values(outcome) -> list:
    """Every check's value and every parameter but the times of a case's outcome, in order."""
    found: list = [c.value for c in outcome.checks]
    for key, value in sorted(outcome.parameters.items()):
        if "time" not in key and "runtime" not in key and "cpu" not in key and "load" not in key:
            found.append((key, repr(value)))
    return found


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--cases", default="hemisphere-forming")
    parser.add_argument("--resolution", default="coarse")
    parser.add_argument("--repeats", type=int, default=1)
    args = parser.parse_args()
    from validation.cases import CASES

    now = (RigidTool.moves, RigidTool.offset)
    passes = {"reference": (property(reference_moves), reference_offset), "now": now}
    print("load before " + ", ".join(f"{x:.2f}" for x in os.getloadavg()))
    for name in args.cases.split(","):
        cpu: dict[str, list[float]] = {label: [] for label in passes}
        found = {}
        for _ in range(args.repeats):
            for label, (moves, offset) in passes.items():
                RigidTool.moves, RigidTool.offset = moves, offset  # type: ignore[method-assign]
                start = time.process_time()
                outcome = CASES[name].compute(args.resolution)
                cpu[label].append(time.process_time() - start)
                found[label] = values(outcome)
        RigidTool.moves, RigidTool.offset = now  # type: ignore[method-assign]
        same = found["reference"] == found["now"]
        print(f"{name} ({args.resolution}): CPU reference "
              + ", ".join(f"{t:.1f}" for t in cpu["reference"]) + " s, now "
              + ", ".join(f"{t:.1f}" for t in cpu["now"]) + " s; "
              + ("every check value and parameter the same" if same else "VALUES DIFFER"),
              flush=True)  # fmt: skip
        if not same:
            for a, b in zip(found["reference"], found["now"]):
                if a != b:
                    print("  ", a, "|", b)
    print("load after " + ", ".join(f"{x:.2f}" for x in os.getloadavg()))


if __name__ == "__main__":
    main()
