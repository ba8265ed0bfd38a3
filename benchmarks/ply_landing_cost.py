"""The cost of the ply contact's landing points (elements/ply_landing.py ``landing``, docs/
theory.md §9.3a, "A point's landing step") by the compiled pass (elements/
ply_landing_kernels.py) and by its numpy reference, on the report's two-ply hemisphere
(validation/studies/hemisphere_plies_run.py: 8 cells, 20 N; the Mindlin [0/90] run by
default, whose flange points rest near zero gap and land and leave at almost every step).

* per call: the landings of the first ``--capture`` of the run's stroke captured (block,
  state, history, facing, as ``ply_landing_kept.kept_landing`` asks), then each found by the
  numpy reference and by the kernel, alternating, best of ``--repeats`` rounds, us a call;
  whether every landing is the same bits both ways;
* the run: ``--share`` of the stroke solved in this process with the numpy landing and with
  the compiled one, alternating, best of ``--repeats``: CPU, ms a step, the landing's own CPU
  (a timer round ``ply_landing_kernels.landing``) and whether the frames' positions and
  directors and the energy and tool records (the history file) are the same bytes.

One numba thread, CPU (``time.process_time``), the machine's load printed.

    python benchmarks/ply_landing_cost.py [--share 0.1] [--capture 0.1] [--repeats 3]
        [--layup 0/90] [--kinematics mindlin]

Measured (one thread, load 0.4-0.8, nothing else running; the landing with the continuous
near-parallel blend and the edge rows' Crossing, their bits in the digest), the Mindlin [0/90]
run over a tenth of its stroke (3465 steps): 3484 landings, 2.4 rows a call, every one the
same bits both ways; 214.5 us a call by numpy, 40.5 compiled (the kernel's call and its
Python: the rows' masks, the outputs' allocations, the inputs' types); the run 7.56 s by
numpy (2.183 ms a step; the landing 0.87 s of it) against 6.83 s compiled (1.970 ms a step;
the landing 0.11 s), best of 3 alternating; the frames and the records the same bytes.

Measured before the blend (66be34b, the landing's step fallback near T's plane), the whole
Mindlin [0/90] stroke (``--share 1.0 --capture 0.02``, 32242 steps, about 29k landings;
load 2.9-5.3, alternating, best of 2): the landing 6.80-7.21 s of CPU by numpy against 0.91-1.30 s
compiled; the runs 57.40 / 60.11 s against 55.45 / 55.56 s (1.780 -> 1.720 ms a step, the load's
spread as large as the cut); the frames and records the same bytes. Again (load 2.1-9.1): 220.2 ->
41.2 us a landing; numpy 57.20 s (the landing 6.78 s, load 4.1), compiled 52.23 / 56.36 s (0.81 /
0.90 s, load 5.0 / 9.1). The report's case beside the code before (``python -m validation --cases
hemisphere-plies --jobs 1``, each tree from ``git archive``, the two at once, load 3-5):
results.json the same in all its 333 numbers but the times, the three PNG files byte for byte, 24 of
24 checks; the Mindlin [0/90] run's CPU 63.2 -> 54.1 s (one pair).
"""

from __future__ import annotations

import argparse
import hashlib
import os
import sys
import time
from pathlib import Path

os.environ.setdefault("NUMBA_NUM_THREADS", "1")
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this tree's packages

import numpy as np  # noqa: E402

from elements import ply_landing, ply_landing_kernels  # noqa: E402
from validation.studies import hemisphere_plies_setup as setup  # noqa: E402
from validation.studies.hemisphere_plies_run import case_solver  # noqa: E402

FIELDS = ("rows", "rate", "theta", "dtheta", "weights", "gradients", "normal", "height")
CROSSING = ("before", "now", "then", "point", "feature", "normal", "plane")


def _digest(found) -> bytes:
    if found is None:
        return b""
    parts = [getattr(found, name).tobytes() for name in FIELDS]
    parts += [b"" if found.edge is None else found.edge.tobytes()]
    parts += [b"" if found.place is None else found.place.tobytes()]
    if found.crossing is not None:  # what the tangent moves the edge rows' anchors by
        parts += [getattr(found.crossing, name).tobytes() for name in CROSSING]
    return hashlib.sha256(b"".join(parts)).digest()


def _run(layup: str, kinematics: str, share: float, compiled: bool, capture=None):
    """(CPU s, steps, landing CPU s, digest of frames and records) of one run of ``share`` of
    the stroke; ``capture`` a list the landings' arguments are appended to."""
    ply_landing_kernels.COMPILED = compiled
    _, model = setup.model(8, setup.LAYUPS[layup], kinematics, 20.0)
    history = Path(f"/tmp/ply_landing_cost_{os.getpid()}.csv")
    solver = case_solver(layup, kinematics, share, history=history, kinetic_bound=None)
    spent = [0.0]
    landing = ply_landing_kernels.landing

    def timed(block, state, history, facing, rows=None):
        begin = time.process_time()
        try:
            return landing(block, state, history, facing, rows)
        finally:
            spent[0] += time.process_time() - begin
            if capture is not None:
                capture.append((block, state, history, facing))

    ply_landing_kernels.landing = timed
    try:
        compiled_model = model.compile()
        start = time.process_time()
        result = solver.solve(compiled_model)
        cpu = time.process_time() - start
    finally:
        ply_landing_kernels.landing = landing
    digest = hashlib.sha256()
    for frame in result.frames:
        digest.update(np.ascontiguousarray(frame.positions).tobytes())
        digest.update(np.ascontiguousarray(frame.directors).tobytes())
    digest.update(history.read_bytes())
    history.unlink()
    return cpu, result.steps, spent[0], digest.hexdigest()[:16]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--share", type=float, default=0.1, help="of the run's stroke")
    parser.add_argument(
        "--capture", type=float, default=0.1, help="of the stroke whose landings are timed"
    )
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--layup", default="0/90", choices=sorted(setup.LAYUPS))
    parser.add_argument("--kinematics", default="mindlin", choices=("fibrous", "mindlin"))
    args = parser.parse_args()
    print(f"load {os.getloadavg()[0]:.1f}; warming (compiling or reading numba's cache) ...")
    for compiled in (False, True):
        _run(args.layup, args.kinematics, 1 / 200, compiled)
    captured: list = []
    _run(args.layup, args.kinematics, args.capture, True, captured)
    calls = [call for call in captured if call[0].curved is False]
    # each landing afresh (the keep's answers aside): the numpy reference, then the kernel
    ply_landing_kernels.COMPILED = True
    same = all(
        _digest(ply_landing.landing(*call)) == _digest(ply_landing_kernels.landing(*call))
        for call in calls
    )
    rows = sum(len(ply_landing.landing_rows(call[0], call[2], call[3])) for call in calls)
    best = {"numpy": np.inf, "compiled": np.inf}
    for round_ in range(args.repeats):
        for name in list(best)[:: 1 if round_ % 2 == 0 else -1]:
            find = ply_landing.landing if name == "numpy" else ply_landing_kernels.landing
            start = time.process_time()
            for call in calls:
                find(*call)
            best[name] = min(best[name], (time.process_time() - start) / len(calls) * 1e6)
    print(
        f"{args.kinematics} [{args.layup}], {args.capture:g} of the stroke: {len(calls)} "
        f"landings ({rows / len(calls):.1f} rows a call), the same bits: {same}; us a call, "
        f"best of {args.repeats}: numpy {best['numpy']:.1f}, compiled {best['compiled']:.1f} "
        f"(load {os.getloadavg()[0]:.1f})"
    )
    runs: dict[bool, list] = {False: [], True: []}
    for round_ in range(args.repeats):
        for compiled in (False, True)[:: 1 if round_ % 2 == 0 else -1]:
            runs[compiled].append(_run(args.layup, args.kinematics, args.share, compiled))
            cpu, steps, landing, digest = runs[compiled][-1]
            print(
                f"  {'compiled' if compiled else 'numpy':8s} {cpu:6.2f} s, {steps} steps, "
                f"{cpu / steps * 1e3:.3f} ms a step, the landing {landing:.2f} s, digest "
                f"{digest} (load {os.getloadavg()[0]:.1f})",
                flush=True,
            )
    ply_landing_kernels.COMPILED = True
    for compiled, name in ((False, "numpy"), (True, "compiled")):
        cpu, steps, landing, _ = min(runs[compiled])
        print(
            f"best {name}: {cpu:.2f} s ({cpu / steps * 1e3:.3f} ms a step), landing {landing:.2f} s"
        )
    digests = {run[3] for both in runs.values() for run in both}
    print(f"the runs' frames and records the same bytes: {len(digests) == 1}")


if __name__ == "__main__":
    main()
