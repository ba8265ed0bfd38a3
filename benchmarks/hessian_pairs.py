"""The fibrous membrane Hessian's compiled cell loop (elements/fibrous/hessian_kernels.py
``membrane_hessians``) of another revision beside this tree's, in one process, taken in
turns: whether the two give the same numbers to the last bit, the best CPU time per cell of
each over ``--rounds`` rounds and the median of new / old with its quartiles; ``--compile``
first times the build of each (a fresh process on an empty numba cache for each side, the CPU
of the first call on a small sheet less that of the second).

The inputs are tests/test_fibrous_hessian_kernels.py's: a jittered sheet with tilted
directors, of the g986 stack and of the tests' table and polynomial fabrics, with and without
the thickness variation; the Hessians with the stress terms of slack fibres
(``compression_free``) too.

Measured on the 2-core machine shared with other jobs, one numba thread, ``--ref cb44972``
(each law's value and slope spliced per call: 5 and 3 copies) beside the three laws of a
level evaluated in one loop (one copy each), ``--cells 2000 --rounds 9 --compile``, load
2.0-2.4: the build 7.01 -> 5.22 s of CPU; per cell (1936 cells, about 6 us each) new / old
medians 0.996-1.011 over the nine cases (quartiles 0.992-1.014), the same bits in every case.
The loop over the laws first read their indices from a small array: 1.00-1.02 (load 5-6),
the index chosen in the loop since.

Run from the project root (the other revision must be a git ref of this repository):

    python benchmarks/hessian_pairs.py --ref main --cells 2000 --rounds 9 [--compile]
"""

from __future__ import annotations

import argparse
import importlib
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

os.environ.setdefault("NUMBA_NUM_THREADS", "1")
ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))  # run from anywhere, no install

import numpy as np  # noqa: E402
from revision_modules import revision_modules  # noqa: E402

MODULES = {"elements/fibrous/hessian_kernels.py": "elements.fibrous.hessian_kernels"}


def cases(cells: int) -> dict:
    """name: (block, x, v, sums, compression_free) of about ``cells`` triangles each."""
    sys.path.insert(0, str(ROOT / "tests"))
    from test_fibrous_hessian_kernels import FABRICS, _cells

    ny = max(2, int(round(np.sqrt(cells / 4.0))))
    found = {}
    for name, fabric in sorted(FABRICS.items()):
        for variation in (True, False):
            inputs = _cells(fabric(), variation, nx=2 * ny, ny=ny)
            found[f"{name} variation {variation}"] = (*inputs, False)
        found[f"{name} compression-free"] = (*_cells(fabric(), True, nx=2 * ny, ny=ny), True)
    return found


def call(module, inputs):
    block, x, v, sums, free = inputs
    return lambda: module.membrane_hessians(block, x, v, sums, compression_free=free)


def flat(result) -> np.ndarray:
    return np.concatenate([np.ravel(p) for p in result])


def first_build(package: str | None, folder: str | None) -> float:
    """CPU s of the first call less the second's (on an empty cache: numba's build), in this
    process: this tree's module (``package`` None) or the revision's in ``folder``."""
    if folder is not None:
        sys.path.insert(0, folder)
    name = "elements.fibrous.hessian_kernels" if package is None else package
    module = importlib.import_module(name if package is None else f"{name}.hessian_kernels")
    run = call(module, next(iter(cases(40).values())))
    started = time.process_time()
    run()
    first = time.process_time() - started
    started = time.process_time()
    run()
    return first - (time.process_time() - started)


def uptime() -> str:
    return subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ref", default="main", help="the other revision (a git ref)")
    parser.add_argument("--cells", type=int, default=2000, help="triangles of each sheet")
    parser.add_argument("--rounds", type=int, default=9)
    parser.add_argument("--compile", action="store_true", help="time the builds first")
    parser.add_argument("--build", nargs="*", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.build is not None:  # a child of --compile
        package, folder = (args.build + [None, None])[:2]
        print(json.dumps(first_build(package, folder)))
        return
    print(uptime(), flush=True)
    with tempfile.TemporaryDirectory() as folder:
        package, commit = revision_modules(args.ref, Path(folder), MODULES)
        print(f"{args.ref} ({commit}) beside this tree, one process, CPU time", flush=True)
        if args.compile:
            built = {}
            for side, extra in (("old", [package, folder]), ("new", [])):
                with tempfile.TemporaryDirectory() as cache:
                    done = subprocess.run(
                        [sys.executable, __file__, "--build", *extra],
                        env=dict(os.environ, NUMBA_CACHE_DIR=cache, NUMBA_NUM_THREADS="1"),
                        capture_output=True, text=True, check=True,
                    )  # fmt: skip
                built[side] = json.loads(done.stdout.strip().splitlines()[-1])
            print(f"build old {built['old']:.2f} s  new {built['new']:.2f} s", flush=True)
            print(uptime(), flush=True)
        old = importlib.import_module(f"{package}.hessian_kernels")
        from elements.fibrous import hessian_kernels as new

        for name, inputs in cases(args.cells).items():
            run_old, run_new = call(old, inputs), call(new, inputs)
            a, b = flat(run_old()), flat(run_new())
            bits = "same bits" if np.array_equal(a, b) else "DIFFER"
            m = len(inputs[1])
            times: dict = {run_old: [], run_new: []}
            ratios = []
            for r in range(args.rounds):
                for kernel in (run_old, run_new) if r % 2 == 0 else (run_new, run_old):
                    started = time.process_time()
                    kernel()
                    times[kernel].append((time.process_time() - started) / m * 1e6)
                ratios.append(times[run_new][-1] / times[run_old][-1])
            q1, median, q3 = np.percentile(ratios, [25, 50, 75])
            print(
                f"{name:32s} {m:5d} cells  old {min(times[run_old]):7.3f}  new "
                f"{min(times[run_new]):7.3f} us/cell  new/old {median:.3f} ({q1:.3f}-{q3:.3f})"
                f"  {bits}",
                flush=True,
            )
    print(uptime(), flush=True)


if __name__ == "__main__":
    main()
