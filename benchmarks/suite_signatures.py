"""The kernels numba's cache holds more than one build of, with the signatures that differ:
each build is a compilation of its own in a fresh checkout, and a helper built once per
constant its callers give it (numba's Literal[int] or Literal[bool] of a constant argument),
or once for a loop's uint64 index beside an int64 one, compiles again for nothing.

Reads the cache's index files (``*.nbi``: numba's pickled version, then (stamp, overloads))
of a folder: the NUMBA_CACHE_DIR a run of the suite used, or a checkout (its ``__pycache__``
folders). Nothing is compiled or imported but numba's types to unpickle the signatures.

Measured on the cache of a whole run of the suite (main 9864ff6, a fresh clone, a fresh
NUMBA_CACHE_DIR, ``python -m pytest`` with the coarse report): 107 builds, 11 of them a
kernel's second or later: the table law helpers ``_table_energy`` and ``_table_integral`` 4
each (Literal[int] 2, 3, 4 and int64: one build each since the index is given as int64,
elements/fibrous/packed_laws.py); fibrous ``cell_terms.corner_thickness`` 3 (its node index
int64 or uint64, ``nodal`` Literal[bool] True or False), ``cell_terms.wall_fold`` 2 (int64
or uint64), ``hessian_kernels._tension_level`` 2 (``edge`` Literal[int] 0 or 1); Mindlin
``kernels._base_vectors`` 2 (a writable and a read-only array).

After those helpers were given one set of argument types (``corner_thickness``'s ``nodal``
and ``_tension_level``'s edge passed as variables, not constants; the parallel loops' index
no longer reaching the helpers, femcore/jit.py ``_Parallel``; the Mindlin tables and fields
given read-only positions and directors alike), the cache of one process running
tests/test_fibrous.py, test_mindlin.py, test_fibrous_hessian_kernels.py,
test_fibrous_tangent_kernels.py, test_threads.py and test_bias_extension.py
(``-m "not slow"``, numba on 2 threads, fresh NUMBA_CACHE_DIR): 73 builds, none a kernel's
second.

A whole run of the suite on a fresh empty cache (main db6c2b7, a fresh export, ``--run --
python -m pytest``: two xdist workers beside the coarse report; 2184 passed, 7 skipped in 22
min 27 s wall, load 2.2 rising to 12 with other jobs): 193 builds, 17 of them a kernel's
second, all but one a writable array beside a read-only one in the ply contact's kernels,
their inputs kept read-only by the block (elements/ply_block.py: the faces p and y, the
offset directions along the normals) or fresh and writable (a caller's own; a state's
directors): ply_choice ``_choose`` (p, y), ply_chosen ``_fade_inputs`` (p, y; plain and
parallel builds), ply_face_points ``_points`` (d), ply_feature_normals ``_angle_parts``,
``_normals`` and their helper ``_unit_normal`` (y), ply_kernels ``_facets_at`` (p, y; plain
and parallel) and ``_grown`` (the corners; plain and parallel), ply_load_kernels ``_loads``
and its helpers ``_add``, ``_add_upper`` (the offset directions), ply_search ``_moves`` 3
builds (y, p). The one other: node_rows ``_same_rows`` 2 (0.1 s each), an A-layout array
beside a C one: tests/test_node_rows.py's strided view, which the test gives on purpose (the
library passes C arrays), left as it is. The compile log of that run holds the xdist workers'
compilations only: the coarse report's processes import numba's dispatcher in their own
sitecustomize (tests/report_site, compile_once) before this one's hook was set, which now
registers at once where numba's dispatcher is imported already; the cache's index above holds
every build.

The CPU of those second builds, one process (``-n 0``) running tests/test_ply_kernels.py,
test_ply_search.py, test_ply_penalty.py, test_ply_cut_kernels.py and test_plies.py (``-m
"not slow"``) on a fresh cache, one numba thread: before (db6c2b7, load 2.2 -> 9) 70 builds,
13 a kernel's second, 40.9 s of compiling of which 7.2 s the second builds (``_choose`` 2.12
+ 2.06, ``_loads`` 1.43 + 1.35, ``_normals`` 0.87 + 0.90, ``_facets_at`` 0.57 + 0.59, ``_moves``
0.60 + 0.31 + 0.35, ``_fade_inputs`` 0.31 + 0.33, ``_points`` 0.38 + 0.30, ``_angle_parts``
0.36 + 0.30, ``_unit_normal`` 0.24 + 0.20, ``_add`` and ``_add_upper`` 0.2 + 0.2 each,
``_grown`` 0.18 + 0.15 s). The items that paid them: test_ply_kernels.py's direct calls with
the faces writable (the facing and loads through the block had built the read-only ones)
and test_ply_search.py's kept lists (``_moves``' third build). After (the wrappers hand those
inputs through ``elements.kernel_inputs.read_only``, a read-only view of the caller's array,
no copy: about 0.35 us an array at a load of 9, against 0.15 us for ``np.ascontiguousarray``
alone), the same tests on a fresh cache (load 5.7 -> 4.7): 57 builds, none a kernel's second,
33.7 s of compiling. tests/test_ply_kernel_signatures.py holds it: 7 of its 9 kernels had two
builds on the old wrappers.

The default report's first run after (``--run -- python -m validation --jobs 2``, a fresh
cache, one numba thread, load 4.2 -> 3.8): 473 s wall, 426 s of CPU, 116 builds, none a
kernel's second; 100.7 s of compiling in its two jobs, 18.5 s of it 18 kernels that both jobs
compiled for the same signature (each asked for them before the other had saved its build:
the fibrous Hessian's cells 5.6 + 5.9 s, the Mindlin tangent's 2.4 + 2.4, ply_choice
``_choose`` 2.0 + 2.2, the fibrous tangent's shares 1.6 + 1.5, ...). The suite shared its
compilations through tests/compile_once.py; the report had no such lock.

The coarse report with the compile lock in the library (femcore/compile_lock.py, on for every
kernel), beside the code before it (main 05b57d7, a fresh export each, each on its own empty
NUMBA_CACHE_DIR, ``--run -- python -m validation --resolution coarse --jobs 2``, both at once
on 2 cores shared with other jobs, load 10.5 -> 15): before, 129 compilations, 124.9 s of CPU
compiling, 10 kernels compiled in both jobs (32.5 s); after, 119 compilations, 92.1 s, none
compiled twice. The command's CPU (user + system, its workers included) 291.2 -> 257.6 s,
wall 2561 -> 2501 s (the load, not the report: 3-4 times its quiet wall); results.json the
same in every number but the times (160/160 checks both).

The bias extension's arc-length test (tests/test_bias_extension.py, 47.5 s cold and 0.8 s warm
in CI), alone on a fresh cache (``--run -- python -m pytest -n 0 ... -k arc_length``, load
6-11): 47 builds, none a kernel's second, 51.5 s of compiling, 25.6 s of it the fibrous force
pass (``_cells_pass``), 6.1 s the Hessian's cells, 2.5 s the tangent's normal pulls: the
kernels of every fibrous Static solve, which the first of them in a process compiles (or
waits for and loads, under the lock); nothing there to compile fewer of.

Kernels no run calls: once the ply facing's glue was fused into its passes
(elements/ply_edge_kernels.py ``edge_sides``, ply_fade_kernels.py ``outline_fade_at``), four
compiled functions were called by tests alone (ply_feature_normals ``feature_normals`` with
``_angle_parts`` and ``_normals``, ply_chosen ``fade_inputs``, ply_fade_kernels
``outline_fade`` with ``_fade``, ply_kernels ``every_segment``); removed with their bit tests,
the fused passes' tests covering their cases. tests/test_ply_kernels.py (``-n 0``, ``-m "not
slow"``) from an empty NUMBA_CACHE_DIR, the trees before (92d9ba4) and after at once, twice,
load 4.7-7.7: 47.5, 46.9 -> 42.9, 43.5 s of CPU (user + system), 41 -> 33 tests.

Five more kernels with two builds in a run of the ply tests (``--run -- python -m pytest -n
0 -p no:randomly tests/test_ply_*.py tests/test_node_rows.py tests/test_static_curved_contact.py
-m "not slow"``, one numba thread, a fresh cache; main 368d61b, load 6.7 -> 3.4): 128 builds,
6 a kernel's second, 7.0 s of their CPU: ply_friction_kernels ``_return_mapping`` (the facing
read-only from the block, writable from tests/test_ply_stick_spring_pass.py's own; 0.42 s),
ply_face_points ``_toward`` (the directions; 0.12 s), ply_edge_couple_kernels ``_couples``
(the facing; 0.77 s), ply_cut_kernels ``closest_cut_at``, a helper compiled with each of its
two callers (the cut's pass handed it writable points and corners, the fade's pass read-only
ones; 0.59 s), node_rows ``_same_rows`` (tests/test_node_rows.py's strided rows; 0.07 s);
and ply_curved_friction_kernels ``_local_loads``' complex build beside its real one (5.0 s),
the tangent's complex step, which needs it. The wrappers now hand each input with the flag the
library's own call gives it (elements/kernel_inputs.py ``read_only``, ``writable``; the
costs, benchmarks/kernel_input_types.py). The same tests and tests/test_kernel_input_types.py
after (load 11 -> 5.7): 123 builds, one a kernel's second (the complex local loads).

A whole run of the suite on a fresh cache (main 1620fbc, a fresh clone, ``--run -- python -m
pytest``; load 0.2 rising to 6): 252 builds in the cache, 3 a kernel's second or later; 270
compilations of the project's kernels in 6 processes, 150.6 s of CPU (161.5 s with numba's
own overloads); 6 a signature compiled again in another process, 3.1 s: the supernodal
factors built for a generic CPU in a subprocess of their own (tests/test_supernodal.py, on
purpose). The second builds: the complex local loads (above) and fibrous level_lanes
``law_row`` three times (``k`` Literal[int] 0, 1, 2 and its rows' offsets literal, 1.03 +
1.05 + 1.12 s). Tried and not kept: ``law_row`` handed them as int64 values, one build;
the same bits, but the fibrous force slower, its rows' offsets no longer known where the
loops are compiled (benchmarks/kernel_pairs.py --ref 1620fbc, 100352 cells, one thread, 10
rounds, load 4.8: force new / old 1.050, quartiles 1.037-1.062; force and energy 1.066,
1.059-1.088): 2 s of compiling once against 5 % of every fibrous step.

A sample of the suite as CI runs it, 13 modules (tests/test_bias_extension.py,
test_bad_input_more.py, test_identify.py, test_mindlin.py, test_explicit.py, test_plies.py,
test_ply_kernels.py, test_static.py, test_contact.py, test_gershgorin.py, test_fibrous.py,
test_relaxation.py, test_mindlin_fabric.py; ``--run -- python -m pytest -n 2 -p no:randomly
...``, one numba thread, a fresh cache), main 4cc9eb3, load 8.3 -> 15 with other jobs: 427
tests, the command's CPU 171.4 s, of it 109.6 s compiling the project's kernels (180
compilations in the two workers and the fit's Dask worker): compiling is two thirds of this
sample's CPU. No signature compiled in two processes; 5 builds a kernel's second: law_row's
(kept, above) and ply_face_points ``_points``, ``_toward`` and ply_search ``_moves``, each
built for the fused front pass's writable outputs (elements/ply_facing_front.py) beside the
block's read-only faces in the chained calls (0.3, 0.1 and 0.5 s). The largest compilations
(CPU s): fabric_section_kernels ``_response_cells`` 9.57 (its laws spliced 11 times), fibrous
``_hessian_cells`` 6.10, ``_cells_pass`` 5.12, ply_load_kernels ``_loads`` 3.92, level_lanes
``law_row`` 3.90 (3 builds), the Mindlin fabric tangent's cells 3.17 and elastic tangent's
2.95, tangent_pattern ``_pattern_arrays`` 2.31, ply_choice ``_choose`` 2.29, fibrous
level_kernels ``_gradient_cells`` 1.99, tangent_kernels ``_normal_pull_cells`` 1.96; 26
kernels of 1 s or more, 62.3 s in all; 118 builds under 0.5 s, 25.0 s. By package: fibrous
35.8 s, ply contact 31.3, Mindlin and the fabric section 23.0, solvers 10.7, femcore 6.5.
With the laws spliced once in the fabric section's response and in the fibrous Hessian's
cells (elements/fabric_section_kernels.py, fibrous/hessian_kernels.py), the same sample run
at the same time as 4cc9eb3's (a fresh export of each, each on its own empty cache, load
6.8-9.3): the command's CPU 176.5 -> 163.9 s, compiling 109.8 -> 99.8 s (180 compilations
each, the same 5 second builds), ``_response_cells`` 9.99 -> 4.28 s, ``_hessian_cells``
6.25 -> 3.53 s; wall 685 -> 669 s.

The waits (``--log`` prints them: a process waiting for another's build of a kernel, under
femcore/compile_lock.py): in the sample with the section's change alone, one, 1.1 s
(fibrous ``_bending_sides``), in 319 s of wall at load 7.9-9.7; in the two runs side by side
above (4cc9eb3's, then this), 2 waits, 13.9 s, and 6
waits, 30.3 s (the ply friction pass's ``_history`` 13.9 and 16.9 s: its holder compiled
slowly on the shared cores, which the waiting process's core served meanwhile). A warm-up
that compiled the kernels in the pytest controller on both cores before the workers start
would shorten the wall by at most such idle time, where nothing else had the core: the
workers compile each kernel once between them already, and the CPU of the compilations
themselves stays whoever does them (in CI the coarse report's two jobs run beside the two
workers from the start, so a core left by a waiting process is taken by another). Not made.

Run: python benchmarks/suite_signatures.py [FOLDER]
     python benchmarks/suite_signatures.py --log FOLDER
     python benchmarks/suite_signatures.py --run -- python -m pytest tests/test_x.py ...

``--run`` runs the command on a fresh empty numba cache (``NUMBA_CACHE_DIR``, a temporary
folder) with a compile log in each of its Python processes (a ``sitecustomize`` first on
their PYTHONPATH: numba's ``numba:compile`` event, which numba raises for a build it does
not find in the cache, timed in CPU, ``time.process_time``, less the builds it compiled
inside it: a helper typed with its caller), then prints the cache's kernels with more than
one build (above) and, from the log, each such kernel's builds with their CPU, the largest
compilations (``TOP``) and the waits for another process's build of a kernel (their wall
seconds). ``--log`` prints the log of an earlier ``--run`` (its folder is printed).
"""

from __future__ import annotations

import argparse
import json
import os
import pickle
import resource
import subprocess
import sys
import tempfile
from collections import defaultdict
from pathlib import Path

import numba  # noqa: F401 - the signatures' types, to unpickle them

# Run at the start of each Python process of ``--run``: numba's compilations logged, one
# JSON line each, in the folder SUITE_SIGNATURES_LOG (a file a process). The listener is
# registered once numba's dispatcher module is imported (a process that never imports numba
# pays nothing); the next sitecustomize on the path is run after it, as Python would have.
SITE = """
import importlib.abc, importlib.util, json, os, sys, time, traceback
from pathlib import Path

_log = Path(os.environ["SUITE_SIGNATURES_LOG"]) / f"{os.getpid()}.jsonl"


def _register():
    from numba.core import event

    stack = []

    class Listener(event.Listener):
        def on_start(self, ev):
            stack.append([time.process_time(), 0.0])

        def on_end(self, ev):
            started, inner = stack.pop()
            spent = time.process_time() - started
            if stack:
                stack[-1][1] += spent
            function = ev.data["dispatcher"].py_func
            # the call that asked for the build: the innermost frames of the project's own
            # files (not numba's, nor the dispatch of femcore/jit.py)
            frames = [f"{Path(f.filename).parent.name}/{Path(f.filename).name}:{f.lineno}"
                      for f in traceback.extract_stack()
                      if "/lib/python" not in f.filename and "jit.py" not in f.filename
                      and "kernel_cache" not in f.filename and "compile_lock" not in f.filename
                      and "sitecustomize" not in f.filename and "<" not in f.filename]
            record = {"module": function.__module__, "name": function.__qualname__,
                      "args": [str(a) for a in ev.data["args"]], "cpu": spent - inner,
                      "pid": os.getpid(), "where": frames[-4:]}
            with open(_log, "a") as handle:
                handle.write(json.dumps(record) + "\\n")

    event.register("numba:compile", Listener())


def _name(handle):
    # the lock file's name (the handle is os.fdopen's: its name is the descriptor)
    try:
        return Path(os.readlink(f"/proc/self/fd/{handle.fileno()}")).name
    except OSError:
        return str(handle.name)


def _watch_locks(module):
    # each wait for another process's compilation of a kernel (femcore/compile_lock.py): its
    # wall seconds, logged as a record of its own ("wait"), so that the log tells how long
    # the processes sat idle behind each other's builds
    take = module._take

    def timed(handle, wait_s):
        started = time.monotonic()
        taken = take(handle, wait_s)
        waited = time.monotonic() - started
        if waited > 0.01:
            with open(_log, "a") as out:
                out.write(json.dumps({"wait": waited, "lock": _name(handle),
                                      "pid": os.getpid(), "at": time.time()}) + "\\n")
        return taken

    module._take = timed


_WATCHED = {"numba.core.dispatcher": lambda module: _register(),
            "femcore.compile_lock": _watch_locks}


class _Hook(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path, target=None):
        if name not in _WATCHED or _busy:
            return None
        _busy.append(name)
        try:
            spec = importlib.util.find_spec(name)
        finally:
            _busy.pop()
        if spec is None:
            return None
        run, then = spec.loader.exec_module, _WATCHED.pop(name)
        if not _WATCHED:
            sys.meta_path.remove(self)

        def exec_module(module):
            run(module)
            then(module)

        spec.loader.exec_module = exec_module
        return spec


_busy: list = []
for _name in [n for n in _WATCHED if n in sys.modules]:  # imported already (a sitecustomize)
    _WATCHED.pop(_name)(sys.modules[_name])
if _WATCHED:
    sys.meta_path.insert(0, _Hook())

_here = Path(__file__).resolve().parent
_self = sys.modules.pop("sitecustomize")
_path = sys.path
try:
    sys.path = [p for p in _path if Path(p or ".").resolve() != _here]
    importlib.import_module("sitecustomize")
except ImportError:
    sys.modules["sitecustomize"] = _self
finally:
    sys.path = _path
"""


#: The largest compilations ``--log`` lists.
TOP = 40


def builds(index: Path) -> list[tuple]:
    """The signatures of the builds in one index file."""
    with open(index, "rb") as handle:
        pickle.load(handle)  # numba's version
        _, overloads = pickle.loads(handle.read())
    return [key[0] for key in overloads]


def read_cache(folder: Path) -> None:
    """Print the kernels the numba cache of ``folder`` holds more than one build of."""
    total = repeated = 0
    for index in sorted(folder.glob("**/*.nbi")):
        if ".venv" in index.parts:
            continue
        signatures = builds(index)
        total += len(signatures)
        if len(signatures) < 2:
            continue
        repeated += len(signatures) - 1
        name = index.name.split(".py")[0]
        print(f"{len(signatures)} builds  {name}")
        for position in range(len(signatures[0])):
            kinds = {str(signature[position]) for signature in signatures}
            if len(kinds) > 1:
                print(f"    argument {position}: {', '.join(sorted(kinds))}")
    print(f"{total} builds in all, {repeated} of them a kernel's second or later")


def read_log(folder: Path) -> None:
    """Print the compile log of ``--run``: the CPU of all builds, and per kernel built for
    more than one signature each build's CPU and the arguments that differ."""
    records = []
    for path in sorted(folder.glob("*.jsonl")):
        records += [json.loads(line) for line in path.read_text().splitlines() if line]
    waits = [r for r in records if "wait" in r]
    records = [r for r in records if "wait" not in r]
    # the project's kernels (numba's own overloads, np.empty's and the like, are compiled in
    # each caller that uses them: not kernels of the project)
    records = [r for r in records if not r["module"].startswith("numba.")]
    by_kernel: dict[tuple[str, str], list[dict]] = defaultdict(list)
    for record in records:
        by_kernel[(record["module"], record["name"])].append(record)
    total = sum(r["cpu"] for r in records)
    again = again_cpu = same = same_cpu = 0.0
    for (module, name), compiled in sorted(by_kernel.items()):
        kinds: dict[tuple, list[dict]] = defaultdict(list)
        for record in compiled:
            kinds[tuple(record["args"])].append(record)
        for copies in kinds.values():  # the same signature compiled in two processes
            same += len(copies) - 1
            same_cpu += sum(r["cpu"] for r in copies[1:])
        if len(kinds) < 2:
            continue
        signatures = list(kinds)
        first = signatures[0]
        again += len(signatures) - 1
        cpu = [kinds[s][0]["cpu"] for s in signatures]
        again_cpu += sum(cpu[1:])
        print(
            f"{len(signatures)} builds  {module}.{name}  CPU "
            + " + ".join(f"{c:.2f}" for c in cpu)
            + " s"
        )
        for position in range(len(first)):
            seen = {s[position] for s in signatures if position < len(s)}
            if len(seen) > 1:
                print(f"    argument {position}: {', '.join(sorted(seen))}")
        for number, signature in enumerate(signatures):
            where = " < ".join(reversed(kinds[signature][0].get("where", [])))
            print(f"    build {number + 1} asked by {where}")
    print(f"{len(records)} compilations in {len({r['pid'] for r in records})} processes, "
          f"{total:.1f} s of CPU; {again:.0f} a kernel's second or later signature, "
          f"{again_cpu:.1f} s; {same:.0f} a signature compiled again in another process, "
          f"{same_cpu:.1f} s")  # fmt: skip
    # the largest compilations, each kernel's builds summed over signatures and processes
    summed: dict[str, list[float]] = defaultdict(list)
    for record in records:
        summed[f"{record['module']}.{record['name']}"].append(record["cpu"])
    print("the largest compilations (CPU s, builds):")
    for name, cpu in sorted(summed.items(), key=lambda item: -sum(item[1]))[:TOP]:
        print(f"  {sum(cpu):6.2f}  {len(cpu)}  {name}")
    print(f"{len(waits)} waits for another process's build of a kernel, "
          f"{sum(r['wait'] for r in waits):.1f} s of wall in all"
          + "".join(f"; {r['lock']} {r['wait']:.1f} s" for r in
                    sorted(waits, key=lambda r: -r["wait"])[:5]))  # fmt: skip


def run(command: list[str]) -> None:
    """``command`` on a fresh numba cache with the compile log; its cache and log read."""
    work = Path(tempfile.mkdtemp(prefix="suite-signatures-"))
    cache, log, site = work / "cache", work / "log", work / "site"
    for folder in (cache, log, site):
        folder.mkdir()
    (site / "sitecustomize.py").write_text(SITE)
    path = os.pathsep.join([str(site), *filter(None, [os.environ.get("PYTHONPATH")])])
    env = {**os.environ, "NUMBA_CACHE_DIR": str(cache), "SUITE_SIGNATURES_LOG": str(log),
           "PYTHONPATH": path}  # fmt: skip
    print(f"load {os.getloadavg()[0]:.2f}; cache and log in {work}", flush=True)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    done = subprocess.run(command, env=env)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    print(f"exit {done.returncode}; the command's CPU {cpu:.1f} s (user + system, the "
          f"processes it reaped included); load {os.getloadavg()[0]:.2f}")  # fmt: skip
    read_cache(cache)
    read_log(log)


def main() -> None:
    argv = sys.argv[1:]
    if "--run" in argv:  # the command: everything after --run (and a "--")
        command = argv[argv.index("--run") + 1 :]
        run(command[1:] if command[:1] == ["--"] else command)
        return
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder", nargs="?", default=str(Path(__file__).resolve().parents[1]))
    parser.add_argument("--log", help="the log folder of an earlier --run")
    args = parser.parse_args(argv)
    if args.log:
        read_log(Path(args.log))
    else:
        read_cache(Path(args.folder))


if __name__ == "__main__":
    main()
