"""A ply overhanging a lower ply's outline edge against its twin over a rigid meshed table's
edge: the droop, and where the support ends, as the lower ply's cells and the upper ply's
cells are refined.

The model (benchmarks/ply_overhang.py, tests/test_ply_overhang.py): an upper Mindlin ply
(10 x 10 mm, h = 0.5 mm, bending 0.05 N mm, 1e-8 t/mm^2) clamped at its edge of largest y,
4 mm past the outline edge y = 0 of a lower ply (20 x 20 mm) held whole, mid-surfaces 0.5 mm
apart, under gravity, solved by Static at its defaults with the automatic penalty. Its twin:
the upper ply alone, node-to-surface contact (elements/contact.py) with a RigidSurface, the
lower ply's upper face (20 x 20 mm at z = 0.25, 4 x 4 cells: flat, its cells do not matter),
whose open edge is the lower ply's outline edge.

Printed: the lowest z of the upper ply's mid-surface, its tip's z (the middle node of the
free edge y = -4), and where the support ends: the contact point with a force (ply contact:
touching, g < 0 and w > 0; table: the node's face point with a negative distance) furthest
past the edge y = 0, in mm and in the lower ply's outline heights h_l (the height of its
outline triangles over the outline edge), with its fade w. The ply contact's point is the
upper triangle's centroid (``rule="centroid"``, its default) or its corners (``"nodes"``,
the table's node-to-surface). ``FADE`` (elements/ply_fade.py) is varied by its module
constant: the fade w_e = S(1 - d / D) is 0 beyond D = FADE h_l past the outline, within the
growths' reach MARGIN h_l = 0.5 h_l (elements/ply_projection.py), so D bounds the support's
reach past the edge and MARGIN has no effect while FADE < MARGIN.

Measured (one thread, CPU of a solve 0.4-31 s, load 5.6-8.5 on 2 cores), tip z (the closed
form 0.3780 at L = 4 mm) and L_e - 4 mm, L_e the overhang whose closed-form droop is the tip's
(> 0: the support ends behind the edge); lowest z is within 0.006 of the tip's:

    table (node-to-surface), upper cells 6 | 12 | 22 | 24 | 32 | 36 | 42
        tip z 0.2245 | 0.3552 | 0.3650 | 0.3549 | 0.3686 | 0.3547 | 0.3705
        L_e - L +0.904 | +0.175 | +0.103 | +0.178 | +0.075 | +0.179 | +0.061
        (its last node behind the edge 1.0 | 1/6 | 1/11 | 1/6 | 1/16 | 1/6 | 1/21 mm)
    ply contact, centroids (the default), tip z (L_e - L), lower cells 4 | 8 | 16 | 32:
        upper 6    0.4117 (-0.310) | 0.4117 (-0.310) | 0.4117 (-0.310) | 0.3460 (+0.240)
        upper 12   0.4230 (-0.434) | 0.3959 (-0.155) | 0.3958 (-0.155) | 0.3225 (+0.394)
        upper 24   0.4307 (-0.527) | 0.3909 (-0.110) | 0.3909 (-0.110) | 0.3745 (+0.028)
        upper 36   0.4335 (-0.563) | 0.4093 (-0.286) | 0.3791 (-0.009) | 0.3791 (-0.009)
      support's end past the edge, upper 36: 0.572 mm (w 0.14), 0.293 (w 0.12), 0.015, 0.015
      (D = 0.75, 0.375, 0.19, 0.094 mm); upper 24: 0.525, 0.108, 0.108, -0.032.
      lower 32 | 64, upper 12: 0.3225 | 0.3225; 22: 0.3855 (-0.063) | 0.3462 (+0.239);
      32: 0.3821 (-0.034) | 0.3822 (-0.034); 42: 0.3806 (-0.021) | 0.3806 (-0.021)
    ply contact at the nodes, lower 4 | 8 | 16 | 32 (| 64):
        upper 6    0.4405 (-0.657, the node row 0.665 mm past held, w 0.036) | 0.2234 | 0.2234
                   | 0.2235 (the table's 0.2245: the last node 1.0 mm behind)
        upper 12   0.4400 (-0.651, w 0.036) | 0.3546 | 0.3546 | 0.3546 | 0.3547 (table 0.3552)
        upper 22, 32, 42 on 32 (and 64) lower cells: 0.3645, 0.3682, 0.3700 (tables 0.3650,
        0.3686, 0.3705)
    FADE (lower 4, upper 12; D = 5 FADE mm) 0.05 | 0.15 | 0.3 | 0.45:
        centroids  0.3958 (-0.155) | 0.4230 (-0.434) | 0.4738 (-1.277) | 0.4938 (-2.104)
        nodes      0.3546 (+0.179) | 0.4400 (-0.651) | 0.4516 (-0.826) | 0.4807 (-1.478)
    MARGIN 0.5 | 0.3 | 0.2 (lower 4, upper 12, centroids): the same bits.
    with the mirrored pass at the lower ply's nodes (lower, upper cells): (4, 6), (8, 6)
        0.4117 (-0.310) as without it; (32, 6) 0.4022 (-0.215; without 0.3460); (8, 12),
        (16, 12) 0.3959, 0.3958 (-0.155) as without; (32, 12), (64, 12) 0.3824 (-0.036;
        without 0.3225), the support's end the lower ply's edge node; (32, 22) 0.3856 (-0.063)
        and (32, 32) 0.3821 (-0.034) as without (a centroid within D past the edge).

Read: the ply contact's support ends at its last point within D = FADE h_l past the outline
edge (the growths' reach MARGIN h_l plays no part while FADE < MARGIN), held there even at w
of a few hundredths by the stiff automatic penalty; on a fine upper ply at about 0.75 D past
(0.563 of 0.75, 0.286 of 0.375 mm). The table's twin ends at the last node before the edge.
At the coarse mesh (6 upper cells, tip z 0.412 against 0.2245) the difference is the contact
points' places, a centroid 0.11 mm past the edge against a node 1.0 mm behind it; with the
ply contact's points at the nodes and no node within D, the two twins agree to 1e-3 mm.
Both converge to the closed form at first order in the cells; the table's 0.355 at 12, 24
and 36 cells is its node 1/6 mm behind the edge on all three, not a converged answer. With
the mirrored pass at the lower ply's nodes, its outline node on the edge holds the upper ply
there: the support's end lies between the edge and D past it, whatever the upper points'
places, and its error is D's alone (first order in the lower cell).

Run: python benchmarks/ply_margin.py [quick | refined]   (none: the full study; --help lists
the choices)
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this tree's packages

import elements.ply_fade as ply_fade
from elements import RigidSurface
from elements.plies import mindlin_ply
from femcore import Mesh, Model
from solvers import Static
from validation.studies import ply_overhang_setup as setup

BENDING = 0.05  # D, N mm (moment per unit width per curvature): PLY's linear bending law
PLY, HALF = setup.PLY, setup.HALF
SHIFT = -4.0  # the upper ply's free edge, mm: 4 mm past the lower ply's outline edge y = 0
WEIGHT = PLY.areal_density * 9810.0  # q, N/mm^2 (per unit width, N/mm per mm)
# The heavy strip over a rigid edge (tests/test_table_contact.py, Euler-Bernoulli): the tip
# droops (1/8 + sqrt(2)/12) q L^4 / D below the face, L the overhang past the last support.
DROOP = (1.0 / 8.0 + np.sqrt(2.0) / 12.0) * WEIGHT / BENDING  # 1/mm^3


def reach(tip: float) -> float:
    """The overhang L (mm) whose closed-form droop is the tip's: L - 4 is how far past the
    edge the support effectively holds the ply (< 0: short of it)."""
    return float(((2.0 * HALF - tip) / DROOP) ** 0.25)


def _upper(cells: int) -> tuple[np.ndarray, np.ndarray]:
    upper = setup.upper_ply(SHIFT, cells)
    return upper.points, upper.triangles


def _finish(model: Model, up: np.ndarray, first: int) -> None:
    model.fix(first + np.flatnonzero(up[:, 1] >= up[:, 1].max() - 1e-9))
    model.gravity((0.0, 0.0, -9810.0))


def _figures(positions: np.ndarray, up: np.ndarray) -> tuple[float, float]:
    """The lowest z of the upper ply and its tip's z (the free edge's middle node)."""
    free = np.flatnonzero(up[:, 1] <= SHIFT + 1e-9)
    tip = free[np.argmin(np.abs(up[free, 0] - 7.5))]
    return float(positions[:, 2].min()), float(positions[tip, 2])


def on_ply(
    lower_cells: int, upper_cells: int, rule: str = "centroid", lower_rule: str | None = None
) -> dict:
    """The upper ply on the lower ply held whole (ply contact), with the mirrored pass
    (``points="lower"``, its points at the lower ply's ``lower_rule``) when given."""
    model, first, up = setup.two_plies(SHIFT, upper_cells, lower_cells, lower_rule, rule=rule)
    compiled = model.compile()
    result = Static(progress=False).solve(compiled)
    state = replace(
        compiled.initial_state(), positions=result.positions, directors=result.directors
    )
    ys, ws = [], []
    for block in compiled.interactions:  # the ply contact, and its mirrored pass if asked
        facing = block.facing(state)
        fade = np.ones(len(facing.gap)) if facing.fade is None else facing.fade
        carrying = facing.touching & (facing.gap < 0.0) & (fade > 0.0)
        ys.append(facing.face[carrying, 1])
        ws.append(fade[carrying])
    lowest, tip = _figures(result.positions[first:], up)
    y, w = np.concatenate(ys), np.concatenate(ws)
    last = int(np.argmin(y))
    return {
        "result": result,
        "lowest": lowest,
        "tip": tip,
        "past": -float(y[last]),
        "w": float(w[last]),
        "height": 20.0 / lower_cells,
    }


def on_table(upper_cells: int) -> dict:
    """The upper ply alone over the rigid meshed table (node-to-surface contact)."""
    up, triangles = _upper(upper_cells)
    model = Model(Mesh(up, triangles=triangles))
    model.add(mindlin_ply(PLY))
    top = Mesh.rectangle(20.0, 20.0, nx=4, ny=4)
    tool = RigidSurface(Mesh(top.points + [0.0, 0.0, HALF], triangles=top.triangles))
    model.contact(tool)
    _finish(model, up, 0)
    result = Static(progress=False).solve(model)
    # the contact's gap: the mid-surface's distance less the half thickness (Model.contact)
    carrying = tool.distance(result.positions)[0] - HALF < 0.0
    face = result.positions - HALF * result.directors
    lowest, tip = _figures(result.positions, up)
    return {
        "result": result,
        "lowest": lowest,
        "tip": tip,
        "past": -float(face[carrying, 1].min()),
        "w": 1.0,
        "height": 5.0,
    }


def _print(name: str, run, *args) -> dict:
    start = time.process_time()
    out = run(*args)
    cpu = time.process_time() - start
    result = out["result"]
    iterations = sum(result.info["iterations_per_increment"])
    flag = "" if result.converged else " NOT CONVERGED"
    print(
        f"{name:30s} lowest z {out['lowest']:.4f} tip z {out['tip']:.4f} "
        f"(L {reach(out['tip']) + SHIFT:+.3f} mm) support to "
        f"{out['past']:+.3f} mm past ({out['past'] / out['height']:+.3f} h_l, w {out['w']:.3f})"
        f" {iterations:3d} it, {result.info['cuts']} cuts, CPU {cpu:5.1f} s{flag}",
        flush=True,
    )
    return out


def refined() -> None:
    """Both twins as the upper ply refines with n = 2 mod 5 cells, whose last node before
    the edge lies 2 / n mm behind it (6, 12, 24, 36 cells all put one 1/6 mm behind), the
    lower ply's fade D = 0.15 h_l small (lower 32 and 64: D 0.094 and 0.047 mm)."""
    print(f"load before {os.getloadavg()[0]:.1f}", flush=True)
    print(f"closed form: tip z {2.0 * HALF - DROOP * SHIFT**4:.4f}", flush=True)
    for n in (12, 22, 32, 42):
        _print(f"table, upper {n}", on_table, n)
        for m in (32, 64):
            _print(f"ply, lower {m}, upper {n}", on_ply, m, n)
            _print(f"ply nodes, lower {m}, upper {n}", on_ply, m, n, "nodes")
    print(f"load after {os.getloadavg()[0]:.1f}", flush=True)


def mirrored() -> None:
    """The ply contact with its mirrored pass, points at the lower ply's nodes (its outline
    nodes on the edge itself hold the upper ply there)."""
    for m, n in ((4, 6), (8, 6), (32, 6), (8, 12), (16, 12), (32, 12), (64, 12), (32, 22)):
        _print(f"ply + mirrored, lower {m}, up {n}", on_ply, m, n, "centroid", "nodes")


def margins() -> None:
    """The growths' reach MARGIN (elements/ply_projection.py, imported by name by the modules
    that use it) at 0.5, 0.3 and 0.2 of the outline heights, lower 4, upper 12."""
    import elements.ply_block as ply_block
    import elements.ply_contact as ply_contact
    import elements.ply_projection as ply_projection
    import elements.ply_search as ply_search

    modules = (ply_projection, ply_block, ply_search, ply_contact)
    kept = ply_projection.MARGIN
    first = None
    for margin in (kept, 0.3, 0.2):
        for module in modules:
            module.MARGIN = margin  # type: ignore[attr-defined]
        out = _print(f"ply, MARGIN {margin}, lower 4, up 12", on_ply, 4, 12)
        positions = out["result"].positions
        first = positions if first is None else first
        print(f"{'':30s} apart from MARGIN {kept}: {np.abs(positions - first).max():.3g} mm")
    for module in modules:
        module.MARGIN = kept  # type: ignore[attr-defined]


def main(quick: bool = False) -> None:
    print(f"load before {os.getloadavg()[0]:.1f}", flush=True)
    print(f"closed form: tip z {2.0 * HALF - DROOP * SHIFT**4:.4f}", flush=True)
    uppers = (6, 12) if quick else (6, 12, 24, 36)
    lowers = (4, 8, 16) if quick else (4, 8, 16, 32)
    for n in uppers:
        _print(f"table, upper {n}", on_table, n)
        for m in lowers:
            _print(f"ply, lower {m}, upper {n}", on_ply, m, n)
    for n in uppers[:2]:
        for m in lowers:
            _print(f"ply nodes, lower {m}, upper {n}", on_ply, m, n, "nodes")
    kept = ply_fade.FADE
    for fade in (0.05, 0.15, 0.3, 0.45):
        ply_fade.FADE = fade
        for rule in ("centroid", "nodes"):
            _print(f"ply {rule}, FADE {fade}, lower 4, up 12", on_ply, 4, 12, rule)
    ply_fade.FADE = kept
    margins()
    mirrored()
    print(f"load after {os.getloadavg()[0]:.1f}", flush=True)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "study", nargs="?", choices=("quick", "refined"),
        help="quick: 6 and 12 upper cells on 4, 8, 16 lower cells; refined: the upper ply at "
        "12, 22, 32, 42 cells on 32 and 64 lower cells; none: the full study (docstring)",
    )  # fmt: skip
    arguments = parser.parse_args()
    if arguments.study == "refined":
        refined()
    else:
        main(arguments.study == "quick")
