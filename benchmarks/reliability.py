"""What the safety nets cost: checkpoints with a checksum and a fingerprint, the interrupt
watch, the per-frame history rows, the mesh checks and the memory estimate.

Each figure is printed beside a reference pass over the same data in the same run:

- an explicit run of a Mindlin sheet (``--cells`` triangles, ``--steps`` steps) with
  everything on (inside ``solvers.interruptible()``, a frame summary per frame, a checkpoint
  at the default interval, then at every chance: every 10 steps) against the same run with
  all of it off;
- the model's fingerprint (femcore.fingerprint) against one strain-energy pass of the model;
- saving and loading a checkpoint (sha256 framed) against pickling the same payload raw;
- ``Mesh(points, triangles)`` with its checks (repeated cells, coordinate range, memory)
  against copying the two arrays.

Run from the project root:

    python benchmarks/reliability.py                  # 10k triangles, 200 steps
    python benchmarks/reliability.py --cells 40000 --steps 100
"""

from __future__ import annotations

import argparse
import os
import pickle
import platform
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install

from elements import MindlinShell  # noqa: E402
from femcore import Mesh, Model  # noqa: E402
from femcore.fingerprint import fingerprint  # noqa: E402
from materials import ElasticShell  # noqa: E402
from solvers import CentralDifference, interruptible  # noqa: E402
from solvers.output import load_checkpoint, save_checkpoint  # noqa: E402


def sheet(cells: int) -> Model:
    """A square aluminium sheet of about ``cells`` triangles, clamped at one edge, sagging."""
    n = max(1, int(round(np.sqrt(cells / 2.0))))
    model = Model(Mesh.rectangle(100.0, 100.0, nx=n, ny=n))
    model.add(MindlinShell(ElasticShell(E=70e3, nu=0.3, thickness=1.0, density=2.7e-9)))
    model.fix("left")
    model.gravity((0.0, 0.0, -9810.0))
    return model


def best_of(repeats: int, call) -> float:
    """The shortest of ``repeats`` wall times of ``call()`` (s): the least disturbed."""
    times = []
    for _ in range(repeats):
        started = time.perf_counter()
        call()
        times.append(time.perf_counter() - started)
    return min(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cells", type=int, default=10_000)
    parser.add_argument("--steps", type=int, default=200)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    threads = os.environ.get("NUMBA_NUM_THREADS", "default")
    print(f"python {platform.python_version()}, {os.cpu_count()} cores, load average "
          f"{os.getloadavg()[0]:.2f}, numba threads {threads}")  # fmt: skip

    compiled = sheet(args.cells).compile()
    cells = sum(len(block.cell_ids) for block in compiled.blocks)
    dt = 0.9 * compiled.stable_dt(compiled.initial_state())
    duration = args.steps * dt
    folder = Path(tempfile.mkdtemp())

    def bare():
        CentralDifference(duration=duration, dt=dt, progress=False).solve(compiled)

    def guarded(interval: float):
        checkpoint = folder / "run.ckpt"
        checkpoint.unlink(missing_ok=True)
        solver = CentralDifference(
            duration=duration, dt=dt, progress=False, frame_summary=lambda frame: {}
        )
        with interruptible():
            solver.solve(compiled, checkpoint=checkpoint, checkpoint_interval=interval)

    bare()  # compile the kernels outside the timings
    plain = best_of(args.repeats, bare)
    default = best_of(args.repeats, lambda: guarded(60.0))
    often = best_of(args.repeats, lambda: guarded(0.0))
    per = 1e6 / (cells * args.steps)
    print(f"\nexplicit run, {cells} triangles, {args.steps} steps:")
    for label, wall in (
        ("reference (no checkpoint, no interrupt watch)", plain),
        ("watch + summaries + checkpoint every 60 s", default),
        ("watch + summaries + checkpoint every 10 steps", often),
    ):
        print(f"  {label:46s} {wall:7.3f} s  {wall * per:.3f} us/element-step  "
              f"({wall / plain:.2f} x)")  # fmt: skip

    state = compiled.initial_state()
    energy = best_of(args.repeats, lambda: compiled.strain_energy(state))
    stamp = best_of(args.repeats, lambda: fingerprint(compiled, {"dt": dt}))
    print(f"\nfingerprint of the model: {stamp * 1e3:8.2f} ms; one strain-energy pass "
          f"{energy * 1e3:.2f} ms ({stamp / energy:.1f} x)")  # fmt: skip

    payload = load_checkpoint(folder / "run.ckpt")  # the explicit run's last checkpoint
    path = folder / "bench.ckpt"
    raw = folder / "bench.pickle"
    save = best_of(args.repeats, lambda: save_checkpoint(path, payload))
    load = best_of(args.repeats, lambda: load_checkpoint(path))
    dump = best_of(args.repeats, lambda: raw.write_bytes(pickle.dumps(payload, protocol=5)))
    read = best_of(args.repeats, lambda: pickle.loads(raw.read_bytes()))
    size = path.stat().st_size / 1e6
    print(f"\ncheckpoint of {size:.2f} MB: save {save * 1e3:.2f} ms, load {load * 1e3:.2f} ms; "
          f"raw pickle {dump * 1e3:.2f} / {read * 1e3:.2f} ms")  # fmt: skip

    mesh = compiled.mesh
    points, triangles = mesh.points.copy(), mesh.cells("triangle").copy()
    checked = best_of(args.repeats, lambda: Mesh(points, triangles))
    copied = best_of(args.repeats, lambda: (points.copy(), triangles.copy()))
    print(f"\nMesh({len(points)} nodes, {len(triangles)} triangles) with its checks: "
          f"{checked * 1e3:.2f} ms; copying the arrays {copied * 1e3:.3f} ms")  # fmt: skip


if __name__ == "__main__":
    main()
