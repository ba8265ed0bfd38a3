"""Threads on a shared machine: the explicit steps of a fibrous blank on one thread and on the
default threads (femcore/jit.py), with the machine as it is and with busy processes
competing for its cores, for numba's threading layers and wait policies side by side.

Each configuration runs in a process of its own (the wait policy is read when numba loads its
threading layer): ``passive``, the default of femcore/jit.py (OpenMP, OMP_WAIT_POLICY=PASSIVE);
``spinning``, OpenMP with OMP_WAIT_POLICY=ACTIVE (numba's threads spin between two parallel
loops, as they did before); ``workqueue``, numba's own layer. Each times ``--steps`` explicit
steps of the hemisphere forming blank (``--cells`` squares a side, two triangles each; the
element, the meshed die and the punch, the step's updates) on one thread and on the default
threads, in turns, best of ``--repeats``, with a reference pass over the same nodes (one norm
per node) in the same process. Printed per configuration and load: ms per step (wall and CPU),
the threads the default chose, and the ratio of the default's wall time to one thread's (the
issue's bound: at most 1.3 under a competing busy process), the same on all of numba's threads
whatever the load (``femcore.jit.FOLLOW_LOAD`` off: what the wait policy alone gives), with
/proc/loadavg.

Measured on the 2-core machine nearly quiet (load 0.47-1.07, nothing else running but this
script; main c108a2a), ``--cells 224 --busy 0 --configurations passive,workqueue --steps 30
--repeats 3`` (100 352 triangles), ms a step, wall, best of 3:

    configuration  threads  1 thread  default  ratio  all threads  ratio
    passive (omp)  2 of 2     65.01    39.14   0.60     37.47      0.58
    workqueue      2 of 2     52.98    45.54   0.86     47.09      0.89

Two threads of OpenMP with a passive wait give 1.66 times one thread in the same process (1.73
on all threads whatever the load); the workqueue layer 1.16. The one-thread time differs between
the two processes (65.0 against 53.0 ms, the same plain build): against the faster of the two,
the two OpenMP threads give 1.35 times.

With the parallel builds as parts of the plain build (femcore/jit.py), on the same machine
with its load at 0.9-1.4 (one other run): 1 thread 50.23-56.37 ms, 2 threads 32.54-43.86 (three
runs; numba's own parallel build before it, in the same minutes: 60.46 / 35.63). Under two
busy processes (``--busy 2 --configurations passive``, 20k triangles, load 3.1): 1 thread 34.98
ms, the default 33.29 (0.95; it chose one thread), all threads 26.33 (0.75): within the issue's
1.3.

Again on a quiet machine (load 0.56-0.79, nothing else running; main 6529b3b, the fibrous
kernels as before, the ply search and the tools' kept offsets new), ``--cells 224 --busy 0
--configurations passive --steps 30 --repeats 5``, two processes one after the other: 1 thread
46.21 / 45.35 ms a step, the default (2 of 2) 29.43 / 27.39 (ratio 0.64 / 0.60: 1.57-1.66 x),
all threads 28.86 / 27.91 (1.60-1.62 x); the reference pass 0.86 ms. About 0.73-0.75 of the
one-thread step runs on both threads (Amdahl), short of the issue's 1.7 x. Timed inside the
steps (30 steps, wall, FOLLOW_LOAD off, one thread then two, three rounds, load ~1): the
fibrous block's internal force 33.5-35.9 -> 18.8-24.8 ms a step (up to 1.8 x; called alone
on the same state 33.1-33.8 -> 17.6-22.4, 1.9 x at best), the whole step 46.4-49.3 -> 30.2-37.4:
the rest of the step, 13-14 ms on one thread (the die's contact, the rotation update, numpy
updates), takes 11.5-12.6 on two. The two cores are not shared: two compute-bound processes
side by side take the time of one alone (0.86-0.91 s against 0.87-0.91). The blank scales less
at 20k (1.44 x) and 5k (1.10 x). So the serial rest of the step is the limit, not the kernels.
Of that rest, a contact's node positions were gathered by fancy indexing four times a step
(0.49 ms for 50k nodes); the blank's nodes are a range, now copied as a slice (0.03 ms; the
same numbers; np.take, 0.13 ms, for other node sets). Side by side in turns (old, new, twice,
load 0.7-1.3): 1 thread 45.35 / 45.18 -> 43.31 / 43.60 ms a step (-4 %), the default 27.76 /
28.24 -> 25.95 / 27.21 (1.61-1.67 x one thread).

``critical``: the one-thread step's CPU time over the calling thread's CPU time a step on all
threads. With the passive wait the calling thread sleeps while it waits for the other one,
so its CPU time is the step's critical path: its serial part and its own share of the
parallel loops, what a quiet machine's wall time would be without the cost of waking the
threads and of sharing the memory. The load does not hide it (the wall times do: at a load
of 6-10 the default runs on one thread and the other thread of the "all threads" runs waits
for a core), and it overstates the wall-time ratio: 1.66-1.78 for main fdcebfd (below)
where the quiet machine gave 1.61-1.67 above.

The serial rest moved onto the threads (elements/node_rows.py, solvers/dynamics.py,
solvers/turning.py): the velocity and rotation updates run over the nodes in parallel,
their energy terms summed by chunks of femcore.jit.CHUNK nodes in one order; a contact adds
its forces into the model's sums in place (``InteractionBlock.add_internal_force``: no
bincount scatter, no (n, 3) array a contact), its positions less the driven holder's
translation, the meshed die's positions in its frame and the punch's total force compiled
(numpy's ``x - c`` and ``f.sum(axis=0)`` ran an inner loop of 3 a row: 0.25 and 0.74 ms at
50k nodes, on one thread whatever the threads). The trajectory is the same to the last bit
as before (and on 1 and 2 threads); the energy terms differ from before by their chunked
order of summation (1e-13 relative). Side by side, main fdcebfd (through a copy of this
script beside links to main's packages) and after, in turns, ``--cells 224 --busy 0
--configurations passive --steps 30 --repeats 3``, load 6.1-9.8 (the default chose one
thread):

    run      1-thread step CPU ms     critical
    main     46.05 / 44.99 / 45.09    1.75 / 1.68 / 1.66
    after    42.44 / 41.23 / 43.67    1.91 / 1.84 / 1.91

Where the calling thread's CPU goes, 20 steps timed inside (FOLLOW_LOAD off; load 9.0 for
main, 6.5 after), ms a step on two threads (on one thread in brackets), main -> after: the
whole step 25.93 (44.19) -> 22.34 (42.65); the fibrous force 16.82 (33.24) -> 16.75 (34.02),
its code unchanged; the die 3.13 (4.79) -> 2.68 (4.53); the punch 0.67 (0.82) -> 0.50
(0.67); the driven holder 1.62 (1.66) -> 0.35 (0.45); the parts' sum 0.36 -> 0.22; the
punch's work 1.06 (1.05) -> 0.34 (0.35); the rotation update 1.54 (1.53) -> 0.88 (1.59);
the velocity update 0.45 (0.45) -> 0.28 (0.46). The serial rest is now about 1.9 ms of
the calling thread's 22 (the die's own numpy between its compiled passes, the contacts'
caches, the external loads, the sums). The two-thread wall ratio on a quiet machine was not
measured (the machine was never quiet in those hours); with main's distance from
``critical`` to it (0.05-0.11), about 1.73-1.86.
Measured then on the machine quiet (load 0.83-1.13, nothing else running; main 7fd0cbe, the
serial rest on the threads and the fibrous lanes merged), ``--cells 224 --busy 0
--configurations passive --steps 30 --repeats 3``: 1 thread 38.40 ms a step, the default (2
of 2) 20.94 (ratio 0.55: 1.83 x), all threads 20.06 (1.91 x), critical 2.00; the reference
pass 0.854 ms. main fdcebfd right after could not be measured quiet (other runs had started:
the default took 1 of 2 threads, 45.85 / 46.13 ms); its quiet figures above: 1.61-1.67 x.
Quiet again after the director moments' lanes (main 5ca146d, load 1.0-1.1, nothing else
running), the same command, two runs: 1 thread 33.15 / 33.37 ms a step, the default (2 of
2) 19.96 / 18.12 (1.66 / 1.84 x), all threads 19.95 / 18.02, critical 1.90 / 1.93; the
reference pass 0.853 / 0.855 ms. The one-thread step 13 % shorter than before; the two
threads' gain as before within the runs' spread.
Quiet again (main d60fc8c, load 0.6-1.3, nothing else running), ``--cells 224
--configurations passive --steps 30 --repeats 3``, two runs: 1 thread 34.36 / 34.09 ms a
step, the default (2 of 2) 19.65 / 18.52 (1.75 / 1.84 x), all threads 19.04 / 18.59, the
reference pass 0.856 / 0.857 ms; beside one busy process the default 35.31 against 34.88 on
one thread (1.01), beside two 56.98 against 52.30 (1.09; it took 1 of 2 threads).

The small passes on two threads cost more than they save on a busy machine: x - c of 50k
rows took 46 against 56 us (best of 300, load 5-6), the forces' add 66 against 79; the
velocity update (0.39 ms) ran no faster on two threads there either, its second thread
waiting for a core (the calling thread's CPU halved, 545 -> 280 us). A loop follows the free
cores (femcore/jit.py), so on such a machine they run on one.

Run from the project root:

    python benchmarks/threads.py                     # 100 x 100 x 2 = 20k triangles
    python benchmarks/threads.py --cells 40 --busy 0,1,2
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this tree's packages


ROOT = Path(__file__).resolve().parents[1]
CONFIGURATIONS = {
    "passive": {},
    "spinning": {"OMP_WAIT_POLICY": "ACTIVE", "NUMBA_THREADING_LAYER": "omp"},
    "workqueue": {"NUMBA_THREADING_LAYER": "workqueue"},
}


def load() -> str:
    try:
        return Path("/proc/loadavg").read_text().split(" ")[0]
    except OSError:  # pragma: no cover - not Linux
        return "?"


def child(cells: int, steps: int, repeats: int) -> None:
    """Time the steps in this process and print one JSON line."""
    import numba
    import numpy as np

    os.environ.setdefault("FIBRESHELL_PROGRESS", "0")
    from femcore import jit
    from solvers.step import LumpedMasses, explicit_step
    from validation.cases import hemisphere_forming as case

    _, model = case.model(cells, "fibrous")
    compiled = model.compile()
    start = compiled.initial_state()
    masses = LumpedMasses.of(compiled, start)
    dt = 0.5 * compiled.stable_dt(start)
    default = numba.get_num_threads()

    def run(threads: int, follow: bool = True) -> tuple[float, float, float]:
        numba.set_num_threads(threads)
        jit.FOLLOW_LOAD = follow
        state, previous = start, 0.0
        wall, cpu, own = time.perf_counter(), time.process_time(), time.thread_time()
        for _ in range(steps):
            step = explicit_step(compiled, state, dt, masses, dt_prev=previous, duration=0.1)
            state, previous = compiled.commit(step.state), dt
        return (
            (time.perf_counter() - wall) / steps,
            (time.process_time() - cpu) / steps,
            (time.thread_time() - own) / steps,  # the calling thread's: the critical path
        )

    run(default)  # compiles, fills the tools' caches
    times: dict[str, list[tuple[float, float, float]]] = {"one": [], "default": [], "all": []}
    for _ in range(repeats):
        times["one"].append(run(1))
        times["default"].append(run(default))
        times["all"].append(run(default, follow=False))
    numba.set_num_threads(default)
    jit.FOLLOW_LOAD = True
    reference = min(_timed(lambda: np.linalg.norm(start.positions, axis=1)) for _ in range(20))
    print(
        json.dumps(
            {
                "layer": numba.threading_layer(),
                "wait": os.environ.get("OMP_WAIT_POLICY"),
                "threads": jit.threads_for(2 * cells * cells),
                "cap": default,
                **{key: min(values) for key, values in times.items()},
                # the CPU of one thread's step over the calling thread's on all threads
                "critical": min(t[1] for t in times["one"]) / min(t[2] for t in times["all"]),
                "reference": reference,
            }
        )
    )


def _timed(function) -> float:
    start = time.perf_counter()
    function()
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cells", type=int, default=100)
    parser.add_argument("--steps", type=int, default=50)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--busy", default="0,1", help="competing busy processes, a list")
    parser.add_argument("--configurations", default=",".join(CONFIGURATIONS))
    parser.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        child(args.cells, args.steps, args.repeats)
        return
    print(f"{2 * args.cells**2} triangles, {args.steps} steps, best of {args.repeats}; "
          f"cores {len(os.sched_getaffinity(0))}")  # fmt: skip
    print(f"{'busy':>4} {'configuration':>13} {'layer':>9} {'threads':>7} {'1 thread ms':>11} "
          f"{'default ms':>10} {'cpu ms':>6} {'ratio':>5} {'all threads ms':>14} {'ratio':>5} "
          f"{'ref ms':>6} {'critical':>8} {'load':>5}")  # fmt: skip
    for busy in (int(b) for b in args.busy.split(",")):
        hogs = [subprocess.Popen([sys.executable, "-c", "while 1: pass"]) for _ in range(busy)]
        try:
            time.sleep(1.0 if busy else 0.0)
            for name in args.configurations.split(","):
                env = {**os.environ, **CONFIGURATIONS[name]}
                command = [sys.executable, __file__, "--child", "--cells", str(args.cells),
                           "--steps", str(args.steps), "--repeats", str(args.repeats)]  # fmt: skip
                out = subprocess.run(command, env=env, capture_output=True, text=True, check=True)
                r = json.loads(out.stdout.strip().splitlines()[-1])
                one, default, every = r["one"], r["default"], r["all"]
                print(f"{busy:>4} {name:>13} {r['layer']:>9} {r['threads']:>3} of {r['cap']:<1} "
                      f"{one[0] * 1e3:>11.2f} {default[0] * 1e3:>10.2f} {default[1] * 1e3:>6.2f} "
                      f"{default[0] / one[0]:>5.2f} {every[0] * 1e3:>14.2f} "
                      f"{every[0] / one[0]:>5.2f} {r['reference'] * 1e3:>6.3f} "
                      f"{r['critical']:>8.2f} {load():>5}",
                      flush=True)  # fmt: skip
        finally:
            for hog in hogs:
                hog.kill()
                hog.wait()


if __name__ == "__main__":
    main()
