"""The cost of the departure's slip in a ply contact's accepted history (elements/
ply_departure.py; docs/theory.md §9.3a, "A point's departure step"), by the compiled pass
(elements/ply_departure_kernels.py) and by its numpy reference: an upper ply of 40 x 40
cells (9600 Gauss points) pressed 0.05 mm into a lower ply of 50 x 50 cells with friction,
its history's update (``update_history``, the compiled history pass) timed when no point
leaves and when the points around a node or of a band of its cells leave, with the compiled
departure, with the numpy one and with the departure giving no rows (the rule before it),
alternating, best of 15; then the departure alone, numpy and compiled, and the machine's
load.

    python benchmarks/ply_departure_cost.py
    python benchmarks/ply_departure_cost.py --case /tmp/reference [--turns 2] [--bits]

``--case REF``: the report's hemisphere-plies case's four runs (8 cells, 20 N; validation/
studies/hemisphere_plies_run.py ``run``) in fresh processes of this tree and of the tree REF
(the code before, from ``git archive``), one numba thread each, alternating from one turn to
the next, a warming run of each first (numba's caches: NUMBA_CACHE_DIR per tree); each run's
CPU (its solve's process time) best of the turns, and whether the two trees' final positions
are the same bits. With ``--bits``: short runs of the case's Mindlin [0/90] and fibrous [0/45]
plies (6 cells, a few hundred steps, points landing and leaving at most steps) in the
reference tree and in this one three ways (the points facing an edge or a vertex held out of
the landing and the departure, as the rule before theirs; the numpy departure; as it is):
whether the face points alone are the reference's bits and the numpy departure the compiled
one's (final positions and energy and tool records, step by step), how far the edge rule
moves the final positions and the friction record, and how many edge rows land and leave.

Measured so against main 8d92574 and 496f564 alike (load 5.5-7.8): Mindlin [0/90] over 405
steps, 13 edge landings, 20 edge rows leaving (9 beside a growth's edge): the face points
alone the same bits as the reference, the numpy and compiled departures the same bits, the
edge rule moves the final positions by 0.0772 mm at most (rms 0.0153), the friction record
114.926 -> 114.994 N mm; fibrous [0/45] over 266 steps, no edge landing, 7 edge rows leaving
(none beside a growth): the same bits both ways, the positions the same bits (the departure
moves records only), the friction record 802.538 -> 802.617 N mm.

Measured (one thread; 2 cores shared with other jobs, load 7.2-9.6), the history update best
of 15: no point leaving 1.00 / 1.14 ms with the compiled departure, 1.07 / 1.16 with the
numpy one, 1.02 / 1.09 without (the rule's selection alone either way, 0.015 ms); the 3
points about a node leaving 1.18 / 1.23 ms, 1.35 / 1.32, 1.07 / 1.06 without (the departure
alone 0.042-0.044 ms compiled against 0.149-0.177 numpy); the band's 400 points 1.23 / 1.12,
1.64 / 1.61, 1.05 / 1.04 (alone 0.094-0.098 against 0.40-0.44). Before the compiled pass
(load 0.8): 0.94 / 0.92 ms with none leaving, 1.12 with 3, 1.41 with 400, 0.92-0.96 without.

The case's runs (``--case``, 7f9c3d5 from git archive, best of 2 alternating turns, load
6.3-9.4, the compiled departure then called apart from the fused pass): [0/90] fibrous 10.05
s of CPU against 10.06, [0/90] Mindlin 34.61 against 35.30, [0/45] fibrous 13.34 against
12.39, [0/45] Mindlin 19.14 against 18.87: 77.1 against 76.6 s, within the load's spread
(a tree's two turns up to 29 % apart); every run's final positions the same bits. With the
departure inside the fused pass (``--only 0/90:mindlin``, load 5.4-7.7): [0/90] Mindlin 32.33
s against 33.56 (0.963; turns 32.33 / 32.82 against 33.56 / 34.33), the same bits. In one
process, alternating, best of 4 (load 4.8-10): the first 15 % of the Mindlin [0/90] run's
stroke 5.41 s against 6.11 with the numpy departure and the landing asked at each call, the
first quarter of the fibrous [0/45] run 4.13 against 4.41. Where the time goes (the Mindlin
[0/90] run over a tenth of its stroke, 6.0 s): the departure 0.18 s with the kernel (the
selection's masks with it) against 0.40 s numpy, over 3502 history updates; the landing
0.77 s (the accepted history's, where points land: its numpy calls, not compiled here).
"""

from __future__ import annotations

import dataclasses
import os
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(HERE))  # run from anywhere, no install


def main() -> None:
    import numpy as np

    from elements import MindlinShell, ply_departure, ply_departure_kernels
    from elements.ply_contact import PlyContact
    from femcore import Mesh, Model
    from materials import ElasticShell

    half, pressed = 0.1, 0.05
    lower = Mesh.rectangle(60.0, 60.0, nx=50, ny=50)
    upper = Mesh.rectangle(40.0, 40.0, nx=40, ny=40, origin=(10.0, 10.0, 2 * half - pressed))
    count = len(lower.points)
    mesh = Mesh(
        np.vstack([lower.points, upper.points]),
        triangles=np.vstack([lower.triangles, upper.triangles + count]),
        element_sets={
            "lower": np.arange(len(lower.triangles)),
            "upper": np.arange(len(lower.triangles), len(lower.triangles) + len(upper.triangles)),
        },
    )
    model = Model(mesh)
    shell = ElasticShell(E=70e3, nu=0.3, thickness=2 * half, density=2.7e-9)
    for name in ("lower", "upper"):
        model.add(MindlinShell(shell), cells=name)
    model.interact(
        PlyContact("upper", "lower", half, half, penalty=50.0, rule="gauss", friction=0.3)
    )
    compiled = model.compile()
    block = compiled.interactions[0]
    state = compiled.initial_state()
    upper_nodes = np.arange(count, len(mesh.points))

    def moved(shift, lifted=None):
        positions = state.positions.copy()
        positions[upper_nodes] += shift
        if lifted is not None:
            positions[lifted, 2] += 0.2
        return dataclasses.replace(state, positions=positions)

    history = block.initial_history()
    history = block.update_history(moved([0.05, 0.0, 0.0]), history)  # sliding
    band = upper_nodes[mesh.points[upper_nodes, 1] < 12.0]  # the first two rows of nodes
    rule = ply_departure.departure

    def none(block, y, history, facing):
        return np.zeros(0, dtype=np.int64), np.zeros(0)

    load = os.getloadavg()[0]
    for name, at in (
        ("no point leaves", moved([0.1, 0.0, 0.0])),
        ("a node's points leave", moved([0.1, 0.0, 0.0], band[20:21])),
        ("a band leaves", moved([0.1, 0.0, 0.0], band)),
    ):
        times: dict[str, list[float]] = {key: [] for key in ("kernel", "numpy", "none")}
        alone: dict[str, list[float]] = {"numpy": [], "kernel": []}
        facing = block.facing(at)
        _, y = block._faces(at)
        for _ in range(15):
            for key in times:  # the history pass with each departure
                ply_departure_kernels.COMPILED = key == "kernel"
                ply_departure.departure = none if key == "none" else rule
                start = time.perf_counter()
                block.update_history(at, history)
                times[key].append(time.perf_counter() - start)
            ply_departure_kernels.COMPILED = True
            ply_departure.departure = rule
            # the departure alone, each way, in turns first (the arrays warm for the second)
            ways = {"numpy": rule, "kernel": ply_departure_kernels.departure_slip}
            for key in sorted(ways, reverse=len(alone["numpy"]) % 2 == 1):
                start = time.perf_counter()
                rows, _ = ways[key](block, y, history, facing)
                alone[key].append(time.perf_counter() - start)
        print(
            f"{name} ({len(rows)} of {len(block.above)} points): update_history "
            f"{1e3 * min(times['kernel']):.3f} ms with the compiled departure, "
            f"{1e3 * min(times['numpy']):.3f} with the numpy one, "
            f"{1e3 * min(times['none']):.3f} without; the departure alone "
            f"{1e3 * min(alone['kernel']):.3f} ms compiled, {1e3 * min(alone['numpy']):.3f} numpy"
        )
    print(f"load {load:.1f} -> {os.getloadavg()[0]:.1f}")


#: One run of the case in a fresh process of a tree (its root the working directory and
#: first on the path): the solve's CPU and a digest of the final positions, as JSON.
RUN = """
import hashlib, json, sys, warnings
warnings.simplefilter("ignore")
sys.path.insert(0, ".")
from validation.studies.hemisphere_plies_run import run
parameters, _, _, result, *_ = run(8, sys.argv[1], sys.argv[2], 20.0)
cpu = [value for key, value in parameters.items() if key.endswith("_cpu_time_s")]
digest = hashlib.sha256(result.positions.tobytes()).hexdigest()[:16]
print(json.dumps({"cpu": cpu[0], "positions": digest}))
"""
#: A short run of the case (6 cells; Mindlin [0/90] 405 steps, fibrous [0/45] 266): digests of
#: its final positions and of its energy and tool records, step by step (friction among them),
#: and, given a folder, both saved there (``--bits``). Its variant (argv[5], this tree only):
#: "numpy" the numpy departure (ply_departure_kernels.COMPILED False), "faces" the points whose
#: gap is to an edge or a vertex held out of the landing and the departure (as the rule before
#: theirs: the face points' bits alone).
SHORT = """
import dataclasses, hashlib, json, shutil, sys, tempfile, warnings
from pathlib import Path
import numpy as np
warnings.simplefilter("ignore")
sys.path.insert(0, ".")
from validation.studies.hemisphere_plies_run import case_solver
from validation.studies.hemisphere_plies_setup import LAYUPS, model
name, kinematics, share = sys.argv[1], sys.argv[2], float(sys.argv[3])
keep, variant = (sys.argv[4], sys.argv[5]) if len(sys.argv) > 5 else ("", "")
if variant == "numpy":
    from elements import ply_departure_kernels
    ply_departure_kernels.COMPILED = False
if variant in ("faces", "edges", "numpy"):
    # their landings watched in (with "numpy" timed by) numpy's ``ply_landing.landing``,
    # which the kept landing asks only with the compiled one off (elements/
    # ply_landing_kernels.py: the same bits), as these variants were measured
    from elements import ply_landing_kernels
    ply_landing_kernels.COMPILED = False
if variant == "faces":
    from elements import ply_departure, ply_landing
    leaving, landing = ply_departure.leaving, ply_landing.landing
    def face_leaving(block, history, facing):
        rows = leaving(block, history, facing)
        return rows if facing.on_edge is None else rows[~facing.on_edge[rows]]
    def face_landing(block, state, history, facing):
        if facing.on_edge is not None:
            touching = facing.touching & ~facing.on_edge
            facing = dataclasses.replace(facing, touching=touching, on_edge=None)
        return landing(block, state, history, facing)
    ply_departure.leaving, ply_landing.landing = face_leaving, face_landing
counts = {"edge landings": 0, "edge leavings": 0, "growth-edge leavings": 0}
if variant in ("numpy", "edges"):  # the edge rows counted (the calls' answers unchanged)
    from elements import ply_departure, ply_landing
    leaving, landing = ply_departure.leaving, ply_landing.landing
    def counted_leaving(block, history, facing):
        rows = leaving(block, history, facing)
        if facing.on_edge is not None:
            counts["edge leavings"] += int(facing.on_edge[rows].sum())
            counts["growth-edge leavings"] += int(ply_departure.beside_growth(facing, rows).sum())
        return rows
    def counted_landing(block, state, history, facing):
        found = landing(block, state, history, facing)
        if found is not None and found.edge is not None:
            counts["edge landings"] += int(found.edge.sum())
        return found
    ply_departure.leaving, ply_landing.landing = counted_leaving, counted_landing
with tempfile.TemporaryDirectory() as folder:
    records = Path(folder) / "history.csv"
    result = case_solver(name, kinematics, share=share, history=records).solve(
        model(6, LAYUPS[name], kinematics, 20.0)[1].compile()
    )
    table = records.read_bytes()
    if keep:
        np.save(Path(keep) / "positions.npy", result.positions)
        shutil.copy(records, Path(keep) / "history.csv")
print(json.dumps({
    "positions": hashlib.sha256(result.positions.tobytes()).hexdigest()[:16],
    "records": hashlib.sha256(table).hexdigest()[:16],
    "steps": table.count(b"\\n") - 1,
    "counts": counts,
}))
"""
SHORT_RUNS = (("0/90", "mindlin", 0.03), ("0/45", "fibrous", 0.051))
RUNS = (("0/90", "fibrous"), ("0/90", "mindlin"), ("0/45", "fibrous"), ("0/45", "mindlin"))


def _short_bits(once) -> None:
    """The short runs in the reference tree and in this one with the edge rule's points held
    out ("faces"), with the numpy departure ("numpy") and as it is: whether each pair that
    should be the same bits is, and how far this tree's run moved from the reference's (its
    final positions, mm, and its friction's records, N mm)."""
    import tempfile

    import numpy as np

    for name, kinematics, share in SHORT_RUNS:
        with tempfile.TemporaryDirectory() as folder:
            runs = {}
            for tree, variant in (("reference", ""), ("this", "faces"), ("this", "numpy"),
                                  ("this", "edges")):  # fmt: skip
                keep = Path(folder) / (variant or tree)
                keep.mkdir()
                runs[variant or tree] = once(tree, name, kinematics, share, keep, variant,
                                             script=SHORT)  # fmt: skip
            saved = {
                key: (
                    np.load(Path(folder) / key / "positions.npy"),
                    np.genfromtxt(Path(folder) / key / "history.csv", delimiter=",", names=True),
                )
                for key in runs
            }
        moved = np.linalg.norm(saved["edges"][0] - saved["reference"][0], axis=1)
        columns = [
            column for column in saved["edges"][1].dtype.names if "friction" in column.lower()
        ]
        reference, edges = saved["reference"][1], saved["edges"][1]
        records = ", ".join(
            f"{column} {reference[column][-1]:.6g} -> {edges[column][-1]:.6g}" for column in columns
        )
        digest = {key: (run["positions"], run["records"]) for key, run in runs.items()}
        pairs = (("faces", "reference"), ("numpy", "edges"))
        same = {key: digest[key] == digest[other] for key, other in pairs}
        print(
            f"[{name}] {kinematics} over {runs['edges']['steps']} steps: the face points alone "
            f"against the reference: {'the same bits' if same['faces'] else 'DIFFER'}; the "
            f"numpy departure against the compiled one: "
            f"{'the same bits' if same['numpy'] else 'DIFFER'}; with the edge rule the final "
            f"positions moved by {moved.max():.3e} mm at most (rms "
            f"{np.sqrt(np.mean(moved**2)):.3e}); {records}; {runs['edges']['counts']} "
            f"(numpy: {runs['numpy']['counts']})",
            flush=True,
        )


def case(
    reference: Path, turns: int, bits: bool = False, only: tuple[str, ...] | None = None
) -> None:
    """The case's runs' CPU, this tree beside ``reference``, or with ``bits`` the short
    runs' digests of both (module docstring)."""
    import json
    import subprocess

    trees = {"this": HERE, "reference": reference.resolve()}

    def once(tree: str, *arguments: object, script: str = RUN) -> dict:
        environment = os.environ | {
            "NUMBA_NUM_THREADS": "1",
            "PYTHONPATH": str(trees[tree]),
            "NUMBA_CACHE_DIR": f"/tmp/numba_ply_departure_cost_{tree}",
        }
        done = subprocess.run(
            [sys.executable, "-c", script, *map(str, arguments)],
            cwd=trees[tree],
            env=environment,
            capture_output=True,
            text=True,
            check=True,
        )
        return json.loads(done.stdout.strip().splitlines()[-1])

    load = os.getloadavg()[0]
    if bits:  # the short runs' digests, this tree's (three ways) against the reference's
        _short_bits(once)
        return
    for name, kinematics in RUNS if only is None else (only,):
        for tree in trees:  # numba's caches warmed
            once(tree, name, kinematics)
        found: dict[str, list[dict]] = {tree: [] for tree in trees}
        for turn in range(turns):
            order = list(trees) if turn % 2 == 0 else list(trees)[::-1]
            for tree in order:
                found[tree].append(once(tree, name, kinematics))
        best = {tree: min(run["cpu"] for run in runs) for tree, runs in found.items()}
        same = {run["positions"] for runs in found.values() for run in runs}
        print(
            f"[{name}] {kinematics}: {best['this']:.2f} s of CPU against {best['reference']:.2f} "
            f"for the reference ({best['this'] / best['reference']:.3f}; turns "
            f"{[round(run['cpu'], 2) for run in found['this']]} / "
            f"{[round(run['cpu'], 2) for run in found['reference']]}), final positions "
            f"{'the same bits' if len(same) == 1 else 'differ'}",
            flush=True,
        )
    print(f"load {load:.1f} -> {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    import argparse

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--case", type=Path, help="the reference tree's root (git archive)")
    parser.add_argument("--turns", type=int, default=2)
    parser.add_argument("--bits", action="store_true", help="the short runs' digests alone")
    parser.add_argument("--only", help="one run of the case, as LAYUP:KINEMATICS (0/90:mindlin)")
    arguments = parser.parse_args()
    if arguments.case is None:
        main()
    else:
        only = None if arguments.only is None else tuple(arguments.only.split(":"))
        case(arguments.case, arguments.turns, arguments.bits, only)
