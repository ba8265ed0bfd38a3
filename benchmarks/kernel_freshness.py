"""What it costs a process that its kernels' cached builds are checked against the project
modules they depend on (femcore/kernel_cache.py), beside a reference pass: numba's own check,
the hash of each kernel's own file.

Three figures, each in fresh processes (one numba thread, numba's caches warm):

* the digests alone: ``dependency_digest`` of every file of the library that defines a
  kernel, read afresh (read, hash and follow the imports of every file they depend on: what
  a process pays once, at the import of the kernels' modules), against the reference pass:
  one sha256 of each of those files (numba's stamp);
* the import of the library (elements, femcore, materials, solvers), and
* a whole small run: a fresh process that imports the library and takes 20 explicit steps of
  a Mindlin plate with rotations (the velocity and rotation loops, the Mindlin force, the
  stable step), its CPU time,

each in turns with the same on a checkout of the code before (``--reference PATH``), if
given.

Measured (2 cores shared with other jobs, load 7-8.7, CPU time, best of 5): the digests of
the 21 kernel files (68 files with what they import) 0.030 s, the reference pass (21
hashes) 0.0006 s; the import of the library 0.709 s against 0.668 s before (0.747 against
0.734 in another run); the whole small run 1.21 s against 1.24 s before (1.36 against 1.33
in another): the difference within the machine's noise. The 20 steps give the same bits on
both (and, with and without the change, on 1 and 2 threads).

Run: python benchmarks/kernel_freshness.py [--repeats 5] [--reference /path/to/old/checkout]
"""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

RUN = """
import hashlib
import numpy as np
from elements import MindlinShell
from femcore import Mesh, Model
from femcore.rotation import rotate_about
from materials import ElasticShell
from solvers import LumpedMasses, explicit_step
mesh = Mesh.rectangle(100.0, 50.0, nx=60, ny=40)
model = Model(mesh)
model.add(MindlinShell(ElasticShell(E=70e3, nu=0.3, thickness=1.0, density=2.7e-9)))
model.fix(mesh.nodes(lambda x, y, z: x <= 1e-9), ["ux", "uy", "uz", "alpha", "beta"])
model.moment(mesh.nodes(lambda x, y, z: x >= 100.0 - 1e-9), (0.0, 5.0, 1.0))
compiled = model.compile()
state = compiled.initial_state()
rng = np.random.default_rng(11)
shape = state.positions.shape
state.positions = state.positions + rng.normal(scale=0.2, size=shape)
tilt = np.cross(state.directors, rng.normal(scale=0.3, size=shape))
state.directors = rotate_about(state.directors, tilt)
state.velocities = rng.normal(scale=10.0, size=shape)
state.angular_velocities = np.cross(state.directors, rng.normal(scale=5.0, size=shape))
masses = LumpedMasses.of(compiled, state)
dt = 0.5 * compiled.stable_dt(state)
h = hashlib.sha256()
for k in range(20):
    step = explicit_step(compiled, state, dt, masses, dt_prev=0.8 * dt, damping=300.0,
                         checking=k % 3 == 0)
    state = step.state
    h.update(repr(step.energy).encode())
for a in (state.positions, state.directors, state.angular_velocities, step.reaction_moments):
    h.update(np.ascontiguousarray(a).tobytes())
print(h.hexdigest())
"""

IMPORT = """
import time
start = time.process_time()
import elements, femcore, materials, solvers
print(time.process_time() - start)
"""

DIGESTS = """
import hashlib, importlib, pkgutil, time
from numba.core.dispatcher import Dispatcher
try:
    from femcore import jit
except ImportError:  # a checkout from before femcore/jit.py (it was elements/jit.py)
    from elements import jit
from femcore import kernel_cache
files = set()
for name in ("elements", "femcore", "materials", "solvers"):
    package = importlib.import_module(name)
    for module in [package] + [importlib.import_module(m.name) for m in
                               pkgutil.walk_packages(package.__path__, name + ".")]:
        for value in vars(module).values():
            if isinstance(value, jit._Parallel):
                files.add(value._function.__code__.co_filename)
            elif isinstance(value, Dispatcher):
                files.add(value.py_func.__code__.co_filename)
files = sorted(files)
# read afresh (the import took the digests already)
kernel_cache._Read.files, kernel_cache._Read.closures, kernel_cache._Read.digests = {}, {}, {}
start = time.process_time()
for file in files:
    hashlib.sha256(open(file, "rb").read()).digest()
reference = time.process_time() - start
start = time.process_time()
closure = set()
for file in files:
    kernel_cache.dependency_digest(file)
    closure.update(kernel_cache.dependency_files(file))
now = time.process_time() - start
print(len(files), len(closure), reference, now)
"""


def _child(code: str, checkout: Path) -> tuple[str, float]:
    """(standard output, CPU seconds) of ``code`` run in a fresh process on ``checkout``."""
    env = {**os.environ, "PYTHONPATH": str(checkout), "NUMBA_NUM_THREADS": "1"}
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    out = subprocess.run(
        [sys.executable, "-c", code], cwd=checkout, env=env, capture_output=True, text=True
    )
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if out.returncode != 0:
        raise RuntimeError(out.stderr[-2000:])
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return out.stdout.strip(), cpu


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--reference", type=Path, default=None, help="a checkout before")
    args = parser.parse_args()
    print("load before " + ", ".join(f"{x:.2f}" for x in os.getloadavg()))
    sides = [("now", ROOT)] + ([("reference", args.reference)] if args.reference else [])
    for _, checkout in sides:  # warm numba's caches
        _child(RUN, checkout)
    best_digest = [float("inf"), float("inf")]
    best_run = {label: float("inf") for label, _ in sides}
    best_import = {label: float("inf") for label, _ in sides}
    bits = {}
    for _ in range(args.repeats):
        out = _child(DIGESTS, ROOT)[0].split()
        files, closure, reference, now = out[0], out[1], float(out[2]), float(out[3])
        best_digest = [min(best_digest[0], reference), min(best_digest[1], now)]
        for label, checkout in sides:
            best_import[label] = min(best_import[label], float(_child(IMPORT, checkout)[0]))
            digest, cpu = _child(RUN, checkout)
            bits[label] = digest
            best_run[label] = min(best_run[label], cpu)
    print(f"{files} kernel files ({closure} with what they import)")
    print(f"reference  numba's stamps (one hash a kernel file): {best_digest[0]:.4f} s CPU")
    print(f"now        dependency_digest of every kernel file:  {best_digest[1]:.4f} s CPU")
    for label, _ in sides:
        print(f"{label:10s} import of the library: {best_import[label]:.3f} s CPU")
    for label, _ in sides:
        print(f"{label:10s} fresh process, 20 explicit steps: {best_run[label]:.2f} s CPU "
              f"(best of {args.repeats}), bits {bits[label][:12]}")  # fmt: skip
    print("load after " + ", ".join(f"{x:.2f}" for x in os.getloadavg()))


if __name__ == "__main__":
    main()
