"""The curved faces' compiled friction pass (elements/ply_curved_friction_kernels.py) of
another revision beside this tree's, in one process, taken in turns: whether the two give the
local loads to the last bit, real and at every complex step of the tangent, and the CPU time
per point of each (benchmarks/mindlin_kernel_pairs.py ``pair``: best of ``--rounds``, median
new / old and quartiles), the uptime before and after. The points are those of
tests/test_ply_curved_friction.py (``_local``: the frictional points of a two-ply hemisphere,
stuck and sliding).

Measured (one numba thread, 2 cores shared, load 10.5-11.5), ``--ref 14e312d`` (the flat
point and its offsets spelled out in the projections and again in the Jacobian maps) beside
``_flat_point`` spliced into both: real (41 points) 1.292 and 1.292 us a point, new / old
0.998; complex (2214 steps) 4.147 and 4.092 us, 0.998; the same bits. First calls on an empty
cache (the builds): real 4.40 s before, 4.28 after; complex 5.94 and 5.58 s. Again by this
script, load 14.7-14.9: real 1.355 and 1.336 us, median 1.001 (0.997-1.012); complex 3.879
and 3.941 us, 1.004 (0.999-1.009); the same bits on one thread and on two.

Run from the project root:

    python benchmarks/curved_friction_pairs.py --ref main --rounds 9
"""

from __future__ import annotations

import argparse
import importlib
import inspect
import os
import sys
import tempfile
from pathlib import Path

os.environ.setdefault("NUMBA_NUM_THREADS", "1")
ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))  # run from anywhere, no install
sys.path.insert(0, str(ROOT / "benchmarks"))
sys.path.insert(0, str(ROOT / "tests"))  # the tests' own imports of one another

from mindlin_kernel_pairs import pair, uptime  # noqa: E402
from revision_modules import revision_modules  # noqa: E402

FILE = {"elements/ply_curved_friction_kernels.py": "elements.ply_curved_friction_kernels"}


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ref", default="main", help="the other revision (a git ref)")
    parser.add_argument("--rounds", type=int, default=9)
    parser.add_argument("--threads", type=int, default=1, help="threads of the bits check")
    args = parser.parse_args(argv)
    import numba

    from elements import ply_curved_friction
    from elements import ply_curved_friction_kernels as new
    from tests.test_ply_curved_friction import _local

    numba.set_num_threads(1)
    print(uptime(), flush=True)
    with tempfile.TemporaryDirectory() as folder:
        package, commit = revision_modules(args.ref, Path(folder), FILE)
        old = importlib.import_module(f"{package}.ply_curved_friction_kernels")
        print(f"{args.ref} ({commit}) beside this tree, one process, CPU time", flush=True)
        # a revision whose pass takes other arguments (before the curved landing anchor's
        # tangent, for one) cannot run on this tree's points: say so rather than fail inside
        ours, theirs = (inspect.signature(m.local_loads).parameters for m in (new, old))
        if list(ours) != list(theirs):
            raise SystemExit(
                f"{args.ref} ({commit}): its local_loads takes ({', '.join(theirs)}), this "
                f"tree's ({', '.join(ours)}); compare with a revision whose pass takes the "
                "same arguments"
            )
        block, data, arguments, stepped, repeated = _local()
        settings = (block.smoothing, block.friction, block.stick == "penalty")
        for name, points, per_point in (("real", data, arguments), ("complex", stepped, repeated)):

            def runner(module, points=points, per_point=per_point):
                return lambda: module.local_loads(
                    points, *per_point, *settings, ply_curved_friction.STEPS
                )

            run_old, run_new = runner(old), runner(new)
            run_old(), run_new()  # built (or loaded) before the clock
            repeats = max(1, 20_000 // len(points))
            line = pair(
                name, run_old, run_new, len(points), args.rounds, repeats, args.threads, "point"
            )
            print(line, flush=True)
    print(uptime(), flush=True)


if __name__ == "__main__":
    main()
