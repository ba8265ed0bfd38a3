"""The ply contact's fade Hessian in closed form (elements/ply_fade_hessian.py) against the
central difference of the fade's exact gradient it replaced (elements/ply_fade.py
``central_fade_hessian`` by 1e-6 (1 + max |y|) mm, the reference pass), side by side in one
run: the Static solves of the plies' cases and tests, and the cost of one fade Hessian.

Each solve runs twice in the same process, the tangent's fade Hessian by one then the other
(``elements.ply_block.fade_hessian`` swapped); printed: the Newton iterations per increment,
cuts, CPU time (time.process_time), the fade Hessians taken (calls and points), the largest
difference of the two final states' positions (mm), and the machine's load (os.getloadavg)
before and after.

Cases: the 4-ply bai-5.1 strip at the coarse resolution (validation/cases/plies_bai_5_1.py,
12 cells, its plies' solver: 10 increments a phase, no seek_stable); the 4-ply sag and the
2 plies pulled with friction of tests/test_plies.py; two [0/45] plies under a holder pushed by
2 N on a flat die (tests/test_ply_layups.py); the deck of cards' bent 2-ply deck and 4-ply
heavy stack (validation/cases/plies_deck_of_cards.py ``bend(2, 10)``, ``sag(4, 10)``); and an
upper ply overhanging a lower ply's outline edge under gravity (``_overhang``), whose points
past the edge are in the fade's band.

Measured (one thread, 2 cores shared, load 5.5 before, 5.1 after), closed form | central
difference (the code before), Newton iterations, cuts, CPU:
    bai-5.1 4 plies (coarse)  358, 6, 24.0 s | 358, 6, 23.7 s   no point in the fade's band
    sag 4 plies                23, 0,  0.4 s |  23, 0,  0.4 s   none in the band
    pulled 2 plies             13, 0,  0.1 s |  13, 0,  0.2 s   none
    layup holder                6, 0,  0.1 s |   6, 0,  0.1 s   none
    deck 2 plies              130, 1,  1.2 s | 130, 1,  1.1 s   none
    heavy stack 4 plies       237, 2,  6.0 s | 237, 2,  5.8 s   9 | 10 points (8 | 9 tangents)
    overhang 2 plies           67, 7,  1.5 s |  67, 7,  2.0 s   614 points in 103 tangents
the final positions the same to the bit, the overhang's within 8.9e-16 mm: the Static cases of
the plies rarely put a point in the fade's band, and none of them 1e-3 mm from an outline
vertex, where the central difference was off (tests/test_ply_fade_hessian.py); so Newton's
iterations do not change. One fade Hessian of 1000 points (half beside a growth's edge):
23.9 ms CPU in closed form against 46.0 ms by the central difference (36.5 against 53.8 at
load 8.4). Another run (load 6.8 before): the same iterations, bai-5.1 30.3 | 25.3 s CPU (the
first solve of the process pays its imports; 24.0 | 23.7 above, the kernels warmed first).

Since then the line search backs off further from an increment's first iterate
(solvers/line_search.py, ``SMALLEST_FIRST_STEP``): the overhang takes 41 iterations and no cut
(benchmarks/ply_overhang.py), the other cases above the same.

Run: python benchmarks/ply_fade_hessian.py [--quick] (--quick: leaves out bai-5.1)
"""

from __future__ import annotations

import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this tree's packages

import elements.ply_block as ply_block
from elements.ply_fade import central_fade_hessian
from elements.ply_fade_hessian import fade_hessian

_seen = {"y": None, "calls": 0, "points": 0}
_faces = ply_block.PlyContactBlock._faces


def _recording_faces(self, state):
    p, y = _faces(self, state)
    _seen["y"] = y
    return p, y


def closed(p, corners, reach, beside, ends, length, joined=None, lines=None, ends_cut=None):
    """The closed form, counted."""
    _seen["calls"] += 1
    _seen["points"] += len(p)
    return fade_hessian(p, corners, reach, beside, ends, length, joined, lines, ends_cut)


def central(p, corners, reach, beside, ends, length, joined=None, lines=None, ends_cut=None):
    """The code before: the central difference by 1e-6 (1 + max |y|) mm, y every lower corner
    of the contact (``PlyContactBlock._faces``, called just before in ``_fade_tangent``)."""
    _seen["calls"] += 1
    _seen["points"] += len(p)
    step = 1e-6 * (1.0 + float(np.abs(_seen["y"]).max()))
    return central_fade_hessian(
        p, corners, reach, beside, ends, length, step, joined, lines, ends_cut
    )


def _bai():
    from fibreshell.plies import plies_solver, ply_stack, stack_model
    from validation.cases.plies_bai_5_1 import (
        BEFORE_STALL_RULE,
        CELLS,
        FILE,
        PLIES,
        PLIES_INCREMENTS,
    )
    from validation.ground_truth import _case

    solver = {**BEFORE_STALL_RULE, "increments": PLIES_INCREMENTS["coarse"]}
    case = _case(FILE, CELLS["coarse"], {"solver": solver})
    stack = ply_stack(case, PLIES["coarse"])
    return plies_solver(case, False).solve(stack_model(case, stack))


def _deck():
    from validation.cases.plies_deck_of_cards import bend

    return bend(2, 10).result


def _heavy():
    from validation.cases.plies_deck_of_cards import sag

    return sag(4, cells=10).result


def _sag():
    from elements.plies import PlyStack
    from femcore import Mesh
    from materials import Fabric
    from solvers import Static

    fabric = Fabric(thickness=1.0, areal_density=1e-9, tension=1e4, shear=1.0, bending=100.0)
    stack = PlyStack(Mesh.rectangle(100.0, 5.0, nx=10, ny=1), fabric, 4)
    model = stack.model()
    model.fix(stack.nodes("left"))
    model.gravity((0.0, 0.0, -9810.0))
    return Static(increments=1, progress=False).solve(model)


def _holder():
    from elements import RigidPlane
    from elements.layup import Layup
    from materials import Fabric
    from solvers import Static

    ply = Fabric(thickness=0.3, areal_density=2.85e-10, tension=60.0, shear=0.2, bending=0.375)
    layup = Layup(ply, (0.0, 45.0), 40.0, cells=2, friction=0.2)
    model = layup.model()
    model.fix(lambda x, y, z: np.ones_like(x, dtype=bool), ["ux", "uy"])
    model.contact(RigidPlane((0.0, 0.0, 0.0), (0.0, 0.0, 1.0)), nodes="ply_1")
    holder = RigidPlane(
        (0.0, 0.0, 2 * ply.thickness),
        (0.0, 0.0, -1.0),
        free="z",
        force=(0.0, 0.0, -2.0),
        amplitude="linear",
    )
    model.contact(holder, nodes="ply_2")
    return Static(increments=2, seek_stable=False, progress=False).solve(model)


def _pulled():
    from elements.plies import PlyStack
    from femcore import Mesh
    from materials import Fabric
    from solvers import Static

    mu, k, g = 0.3, 1.0, 9810.0
    fabric = Fabric(thickness=1.0, areal_density=1e-6, tension=1e4, shear=1.0, bending=1.0)
    stack = PlyStack(Mesh.rectangle(10.0, 10.0, nx=2, ny=2), fabric, 2, penalty=k, friction=mu)
    model = stack.model()
    lower, upper = stack.ply_nodes
    model.fix(lower)
    model.fix(upper, ("alpha", "beta"))
    weight = stack.ply_fabric.areal_density * 100.0 * g
    model.displace(upper, ux=2.5 * mu * weight / (k * len(upper)), uy=0.0)
    model.gravity((0.0, 0.0, -g))
    return Static(increments=4, step_loads_first=True, progress=False).solve(model)


def _overhang():
    """An upper ply (10 x 10 mm, 6 x 6 cells) clamped at its edge y = 6 mm over a lower ply
    held whole (20 x 20 mm, 4 x 4 cells), overhanging its outline edge y = 0 by 4 mm and
    pressed on it by gravity (validation/studies/ply_overhang_setup.py): its centroids past
    the edge in the fade's band."""
    from solvers import Static
    from validation.studies.ply_overhang_setup import two_plies

    model = two_plies(-4.0, penalty=10.0)[0]
    solver = Static(increments=8, seek_stable=False, max_iterations=100, progress=False)
    return solver.solve(model)


def cost(count: int = 1000, repeats: int = 5) -> None:
    """CPU of one fade Hessian of ``count`` points near a triangle with an outline edge
    (half of them beside its growth's edge), best of ``repeats``, each form."""
    rng = np.random.default_rng(0)
    corners = np.tile([[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.2, 1.0, 0.1]]], (count, 1, 1))
    reach = np.tile([[0.0, 0.0, 0.5]], (count, 1))
    p = np.column_stack(
        [
            rng.uniform(-0.2, 1.2, count),
            rng.uniform(-0.2, 0.05, count),
            rng.uniform(-0.08, 0.02, count),
        ]
    )
    beside = rng.integers(2, size=count).astype(bool)
    ends = np.array([[-0.3, 0.0, 0.01], [1.0, 0.0, 0.0]]) + rng.normal(0, 0.01, (count, 2, 3))
    for label, form in (
        ("closed form", lambda: fade_hessian(p, corners, reach, beside, ends, 0.15)),
        ("central", lambda: central_fade_hessian(p, corners, reach, beside, ends, 0.15, 2e-6)),
    ):
        times = []
        for _ in range(repeats):
            start = time.process_time()
            form()
            times.append(time.process_time() - start)
        print(
            f"fade Hessian of {count} points, {label:12s} {1e3 * min(times):7.1f} ms CPU",
            flush=True,
        )


def _run(name, build):
    finals = {}
    for label, hessian in (("closed form", closed), ("central", central)):
        ply_block.fade_hessian = hessian
        _seen["calls"] = _seen["points"] = 0
        start = time.process_time()
        try:
            result = build()
            stopped = "" if result.converged else "not converged"
        except Exception as error:  # a stalled solve is a figure too
            result, stopped = getattr(error, "result", None), f"stopped: {error}"[:120]
        cpu = time.process_time() - start
        if result is None:
            print(f"{name:22s} {label:12s} {stopped}", flush=True)
            continue
        iterations = list(result.info["iterations_per_increment"])
        finals[label] = result.positions
        print(
            f"{name:22s} {label:12s} {sum(iterations):4d} iterations {iterations} cuts "
            f"{result.info['cuts']} CPU {cpu:7.1f} s, fade Hessians {_seen['calls']} calls "
            f"{_seen['points']} points {stopped}",
            flush=True,
        )
    if len(finals) == 2:
        apart = float(np.abs(finals["closed form"] - finals["central"]).max())
        print(f"{name:22s} final positions apart by {apart:.3g} mm", flush=True)


def main(argv: list[str]) -> None:
    ply_block.PlyContactBlock._faces = _recording_faces  # type: ignore[method-assign]
    # the kernels compiled (or loaded from numba's cache) before any timing
    ply_block.fade_hessian = closed
    _sag(), _holder()
    print(f"load before {os.getloadavg()[0]:.1f}", flush=True)
    cases = [
        ("sag 4 plies", _sag),
        ("pulled 2 plies", _pulled),
        ("layup holder", _holder),
        ("deck 2 plies", _deck),
        ("heavy stack 4 plies", _heavy),
        ("overhang 2 plies", _overhang),
    ]
    if "--quick" not in argv:
        cases.insert(0, ("bai-5.1 4 plies", _bai))
    cost()
    for name, build in cases:
        _run(name, build)
    print(f"load after {os.getloadavg()[0]:.1f}", flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
