"""The one-ply hemisphere-forming case's explicit step (validation/cases/hemisphere_forming.py
``run`` at the default 20 cells: 441 nodes, 800 triangles, the die's 71499 facets, the punch
and the plane holder), where its time goes, beside a reference tree; one numba thread.

* default: each of the case's two runs (fibrous, the stroke twice as fast; Mindlin) in this
  tree and in the tree at ``--reference PATH`` (``git archive`` of the code before), each in
  a process of its own, alternating, best of ``--repeats``: CPU a step, and the die's
  contact's parts (wall timers round them, microseconds a step: the contact's whole pass,
  the closest-facet kernel, the candidate lists' searches, the pass of the forces), and a
  digest of the run (steps, final positions, directors, the external work's record) that
  must be the same in both trees;
* ``--replay``: the die's closest-facet kernel (elements/facet_search.py
  ``closest_facets_listed``) replayed in this tree on calls captured from the Mindlin run,
  with its inputs warm in the caches and after 8 MB of other data were written (what a
  step's other work does to the caches between two calls of the kernel).

    python benchmarks/forming_one_ply_step.py --reference /tmp/main --repeats 2
    python benchmarks/forming_one_ply_step.py --replay

Where a step went (main debd499, Mindlin, 46967 steps, 0.39 ms a step, load 2.8; wall
timers): the die's contact 0.14 ms (its closest-facet kernel 0.080, which took 0.047 a call
replayed warm and 0.036-0.053 after the caches were flushed, 0.010-0.016 warm with the
copies below; the searches of the candidate lists 0.025, a batch of some 120 nodes every 90
steps, k-d tree queries; the pass of the forces 0.014), the Mindlin cells 0.056, the punch's
and the holder's contacts 0.02, the rotational update 0.03, the tools' work 0.027, the
rates 0.02, the external load 0.018. The kernel's cost was its memory: a kept facet's
corners read from the die's (71499, 3, 3) array at random, and numba's reference counting
of the array arguments of its helpers at every node (atomic increments: ``_squared_gap``,
``_kept_answers``, 38 -> 19 us a call warm with every node keeping its facet).

The cuts (each the same bits; the digest and the case's results.json compared):

* the helpers without reference counting (femcore/jit.py ``lane_rows``);
* each node's kept facet's and short-listed facets' corners and normal copied into rows in
  the nodes' order (written with the rooms that allow reading them), read by the kernel and
  by the pass of the forces (elements/tool_contact.py) instead of the die's arrays.

* the scans' candidates' corners, normals and bounding spheres copied in the candidate
  lists' order (elements/facet_search.py ``candidate_rows``, made once a list).

Measured side by side with main debd499 (this script, best of 2, one thread; the digests the
same in every run):

* with the first two cuts, load 3.2-3.8: fibrous 617.1 -> 572.0 us a step of CPU (x 1.079),
  Mindlin 366.1 -> 320.8 (x 1.141); Mindlin's die 116.4 -> 79.3 us a step (wall), its
  kernel 64.5 -> 35.2, the searches 17.6 -> 16.8, the forces' pass 11.1 -> 6.5; the third
  cut beside them (the case's ``run``, back to back, load 3.2-3.8): Mindlin 346 -> 327-335;
* all three, load 6.2-11.2 (other jobs rising during the runs): fibrous 651.4 -> 616.9 (x
  1.056), Mindlin 384.8 -> 380.9 (x 1.010, this tree's runs at load 11 against 6): on a
  machine this busy the caches are lost between two steps whatever the layout.

``--replay``, this tree, load 13: 9-29 us a call warm, 19-58 us after 8 MB written (nine
calls of the Mindlin run).

``python -m validation --cases hemisphere-forming --jobs 1``, main and this tree back to
back, one thread: results.json the same in all its 90 numbers but the times; case_cpu_s
28.44 -> 26.70 s (load 3.7-6.1), 27.65 -> 27.32 s (load 6.1-7.2), 26.52 -> 26.86 s (load
2.1-3.1; this tree's kernels compiled again in that run after an edit). The cut asked,
26.5 -> 20 s, is not reached: what is left of the step is the cells' pass, numba's dispatch
of some thirteen kernels (a few microseconds each with twenty arguments) and the Python
between them, each part a few percent.
"""

from __future__ import annotations

import argparse
import inspect
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this tree's packages


HERE = Path(__file__).resolve().parents[1]


def one_run(kinematics: str) -> dict:
    """One run of the case's ``run`` at 20 cells with wall timers round the die's parts (run
    in the tree given by the working directory): CPU a step, the parts' us a step, the
    run's digest."""
    import collections
    import functools
    import hashlib
    import warnings

    warnings.simplefilter("ignore")
    sys.path.insert(0, os.getcwd())
    from elements import rigid_surface, tool_contact
    from validation.cases import hemisphere_forming as forming
    from validation.forming_scaling import TIME_SCALING

    spent: dict[str, float] = collections.defaultdict(float)
    parts = [
        (tool_contact, "surface_forces", "the die's contact"),
        (rigid_surface, "closest_facets_listed", "closest-facet kernel"),
        (rigid_surface.RigidSurface, "_searched", "candidate lists' searches"),
        (tool_contact, "surface_pass", "the forces' pass"),
    ]
    for owner, name, label in parts:
        function = getattr(owner, name)

        def wrapper(*args, _function=function, _label=label, **kwargs):
            start = time.perf_counter()
            try:
                return _function(*args, **kwargs)
            finally:
                spent[_label] += time.perf_counter() - start

        setattr(owner, name, functools.wraps(function)(wrapper))
    speed = TIME_SCALING[kinematics]["default"]
    forming.run(12, kinematics, time_scaling=speed)  # the kernels compiled or loaded
    spent.clear()
    load = os.getloadavg()[0]
    start = time.process_time()
    record = forming.run(20, kinematics, time_scaling=speed)
    cpu = time.process_time() - start
    result = record["result"]
    digest = hashlib.sha256()
    digest.update(np.int64(result.steps).tobytes())
    digest.update(np.ascontiguousarray(result.positions).tobytes())
    digest.update(np.ascontiguousarray(result.frames[-1].directors).tobytes())
    digest.update(np.asarray(result.energies["external_work"]).tobytes())
    steps = result.steps
    return {
        "cpu_us": cpu / steps * 1e6,
        "steps": steps,
        "parts_us": {label: spent[label] / steps * 1e6 for _, _, label in parts},
        "digest": digest.hexdigest()[:16],
        "load": (load, os.getloadavg()[0]),
    }


def run_in(tree: Path, kinematics: str) -> dict:
    """``one_run`` in a process of its own on ``tree``'s code, one numba thread."""
    environment = {**os.environ, "PYTHONPATH": str(tree), "NUMBA_NUM_THREADS": "1"}
    script = (
        "import os, sys, time\nimport numpy as np\n"
        + inspect.getsource(one_run)
        + f"\nimport json\nprint(json.dumps(one_run({kinematics!r})))\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", script], cwd=tree, env=environment, capture_output=True,
        text=True, check=True,
    )  # fmt: skip
    return json.loads(done.stdout.strip().splitlines()[-1])


def side_by_side(reference: Path, repeats: int) -> None:
    trees = {"reference": reference.resolve(), "this": HERE}
    for kinematics in ("fibrous", "mindlin"):
        best: dict[str, dict] = {}
        digests: dict[str, set] = {name: set() for name in trees}
        for _ in range(repeats):
            for name, tree in trees.items():
                ran = run_in(tree, kinematics)
                digests[name].add(ran["digest"])
                if name not in best or ran["cpu_us"] < best[name]["cpu_us"]:
                    best[name] = ran
        old, new = best["reference"], best["this"]
        same = digests["reference"] == digests["this"] and len(digests["this"]) == 1
        print(f"{kinematics}, {new['steps']} steps: CPU a step (best of {repeats}) "
              f"reference {old['cpu_us']:.1f} us, this {new['cpu_us']:.1f} us "
              f"(x {old['cpu_us'] / new['cpu_us']:.3f}); load "
              f"{old['load'][0]:.1f}-{old['load'][1]:.1f} / {new['load'][0]:.1f}-"
              f"{new['load'][1]:.1f}; the same digest: "
              f"{same}")  # fmt: skip
        for label in new["parts_us"]:
            print(f"  {label:28s} {old['parts_us'][label]:7.1f} -> "
                  f"{new['parts_us'][label]:7.1f} us a step (wall)")  # fmt: skip


def replay(every: int = 5000, repeats: int = 100) -> None:
    """The kernel's calls of a Mindlin run captured every ``every`` calls and replayed."""
    import warnings

    warnings.simplefilter("ignore")
    from elements import facet_search, rigid_surface
    from validation.cases import hemisphere_forming as forming

    captured: list[list] = []
    kernel = facet_search.closest_facets_listed
    count = [0]

    def capture(*args):
        count[0] += 1
        if count[0] % every == 0:
            captured.append([a.copy() if isinstance(a, np.ndarray) else a for a in args])
        return kernel(*args)

    rigid_surface.closest_facets_listed = capture
    try:
        forming.run(20, "mindlin")
    finally:
        rigid_surface.closest_facets_listed = kernel
    other = np.ones(1_000_000)  # 8 MB
    serial = kernel.serial
    for args in captured:
        spent = []
        for flush in (False, True):
            times = []
            for _ in range(repeats):
                copies = [a.copy() if isinstance(a, np.ndarray) and a.size < 50_000 else a
                          for a in args]  # fmt: skip
                if flush:
                    other += 1.0
                start = time.perf_counter()
                serial(*copies, 0, 1)
                times.append(time.perf_counter() - start)
            spent.append(np.median(times) * 1e6)
        print(f"closest_facets_listed, {len(args[0])} nodes: {spent[0]:.1f} us warm, "
              f"{spent[1]:.1f} us after 8 MB written (median of {repeats})")  # fmt: skip
    print(f"load {os.getloadavg()[0]:.1f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--reference", type=Path, help="a tree of the code before")
    parser.add_argument("--repeats", type=int, default=1, help="runs per tree (best CPU)")
    parser.add_argument("--replay", action="store_true", help="the kernel replayed, this tree")
    args = parser.parse_args()
    if args.replay:
        replay()
    if args.reference is not None:
        side_by_side(args.reference, args.repeats)


if __name__ == "__main__":
    main()
