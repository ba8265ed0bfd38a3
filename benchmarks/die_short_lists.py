"""The meshed die's closest-facet loop with and without the points' short lists
(elements.rigid_surface.SHORT_LISTS; elements/facet_search.py ``closest_facets_listed``
against ``closest_facets_kept``), on the hemisphere forming case's 20k-triangle blank
(validation/cases/hemisphere_forming.py, 100 cells) laid in its die and sliding towards the
axis by ``--slide`` mm a call (benchmarks/hemisphere_forming.py ``die_pace``'s blank: the
punch at its peak speed moves 7e-4 mm in a step), or as the unscaled stroke left it
(``--states``: hemisphere_<cells>_<fraction>.pkl saved by benchmarks/hemisphere_stroke.py,
each moved on by its own velocities, dt a call).

Two tools, one with each setting, asked the same points in turn in one process, ``--rounds``
rounds of ``--calls`` calls each way: the CPU a call of ``RigidSurface.distance`` (the
candidate lists' upkeep, the closest-facet loop, the signed distances), how many points took
each way (kept facet, short list, scan: counted before each call from the tool's kept
arrays), the machine's load, and a reference pass (a norm per node); the answers must be
the same to the last bit (checked at every call).

    python benchmarks/die_short_lists.py --slide 7e-4
    python benchmarks/die_short_lists.py --states /tmp --at 0.1,0.5,0.9
"""

from __future__ import annotations

import argparse
import os
import pickle
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install
sys.path.insert(0, str(Path(__file__).resolve().parent))

from contact_search import best  # noqa: E402

from elements import RigidSurface  # noqa: E402
from elements import rigid_surface as surfaces  # noqa: E402
from validation.cases import hemisphere_forming as case  # noqa: E402
from validation.specimens import hemisphere_die  # noqa: E402


def laid_blank(cells: int, slide: float, calls: int) -> list[np.ndarray]:
    """The blank's nodes laid on the die (half a ply inside the bowl, half a ply above the
    flange), slid towards the axis from 5 mm by ``slide`` mm a call, ``calls`` of them."""
    mesh = case.model(cells, "fibrous", rim=case.DIE_RIM)[0]
    radius = case.DIE - 0.5 * case.THICKNESS
    r0 = np.linalg.norm(mesh.points[:, :2], axis=1)
    angle = np.arctan2(mesh.points[:, 1], mesh.points[:, 0])

    def laid(moved: float) -> np.ndarray:
        r = np.maximum(r0 - moved, 0.0)
        z = np.where(r < radius, -np.sqrt(np.maximum(radius**2 - r**2, 0.0)), 0.5 * case.THICKNESS)
        return np.column_stack([r * np.cos(angle), r * np.sin(angle), z])

    return [laid(5.0 + slide * call) for call in range(calls + 1)]


def stroke_blank(cells: int, fraction: float, folder: Path, calls: int) -> list[np.ndarray]:
    """The nodes of the unscaled stroke's state at ``fraction`` (saved), moved on by their
    velocities dt a call, ``calls`` of them, where the die sees them (its offset at that
    load factor is zero: the die stands still)."""
    saved = pickle.loads((folder / f"hemisphere_{cells}_{fraction:g}.pkl").read_bytes())
    state, dt = saved["state"], saved["dt"]
    return [state.positions + call * dt * state.velocities for call in range(calls + 1)]


def ways(tool: RigidSurface, x: np.ndarray) -> np.ndarray:
    """How many of the points x (k, 3) the tool will answer from their kept facet, from
    their short list, by a scan, and without candidates (beyond the search distance: an
    empty scan), from its kept arrays (before the call)."""
    kept = getattr(tool, "_kept", None)
    if kept is None or len(kept[0]) != len(x):
        return np.array([0, 0, len(x), 0])
    facet, anchor, room = kept
    kept_way = (facet >= 0) & (np.linalg.norm(x - anchor, axis=1) < room)
    near = getattr(tool, "_near", None)
    listed = np.zeros(len(x), dtype=bool)
    if near is not None:
        listed = ~kept_way & (np.linalg.norm(x - near[0], axis=1) < near[1])
    cache = tool._cache
    empty = np.zeros(len(x), dtype=bool)
    if cache is not None and len(cache.start) == len(x) + 1:
        empty = np.diff(cache.start) == 0
    scanned = ~kept_way & ~listed & ~empty
    return np.array([kept_way.sum(), listed.sum(), scanned.sum(), (empty & ~kept_way).sum()])


def compare(points: list[np.ndarray], rounds: int, label: str) -> None:
    """The two settings on the same calls, in turns, the answers held to the same bits."""
    reference = best(lambda: np.linalg.norm(points[0], axis=1), 20)
    spent = {False: [], True: []}
    counted = {False: np.zeros(4, dtype=np.int64), True: np.zeros(4, dtype=np.int64)}
    before = os.getloadavg()[0]
    for _ in range(rounds):
        answers = {}
        for short in (False, True):
            surfaces.SHORT_LISTS = short
            die = RigidSurface(
                hemisphere_die(case.DIE, 1.7 * case.HALF, rings=48, rim=case.DIE_RIM)
            )
            die.distance(points[0])  # the lists built, the first scan of every point
            got = []
            cpu = 0.0
            for x in points[1:]:
                counted[short] += ways(die, x)
                start = time.process_time()
                d, n = die.distance(x)
                cpu += time.process_time() - start
                got.append((d, n))
            spent[short].append(cpu / (len(points) - 1))
            answers[short] = got
        for (d0, n0), (d1, n1) in zip(answers[False], answers[True]):
            np.testing.assert_array_equal(d0, d1)
            np.testing.assert_array_equal(n0, n1)
    surfaces.SHORT_LISTS = True
    share = {k: v / v.sum() for k, v in counted.items()}
    print(f"{label}: {len(points[0])} points, {len(points) - 1} calls x {rounds} rounds (load "
          f"{before:.1f} -> {os.getloadavg()[0]:.1f}); CPU a call without the short lists "
          f"{' / '.join(f'{t * 1e3:.3f}' for t in spent[False])} ms (kept / scanned / none "
          f"{share[False][0]:.3f} / {share[False][2]:.3f} / {share[False][3]:.3f}), with them "
          f"{' / '.join(f'{t * 1e3:.3f}' for t in spent[True])} ms (kept / listed / scanned "
          f"{share[True][0]:.3f} / {share[True][1]:.3f} / {share[True][2]:.3f}); best "
          f"{min(spent[True]) / min(spent[False]):.3f} x; the same answers to the last bit; "
          f"reference pass {reference * 1e3:.3f} ms", flush=True)  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cells", type=int, default=100)
    parser.add_argument("--slide", type=float, default=7e-4, help="mm a call, the laid blank")
    parser.add_argument("--calls", type=int, default=200)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--states", default="", help="the saved states' folder (else laid)")
    parser.add_argument("--at", default="0.1,0.5,0.9", help="the saved states' fractions")
    args = parser.parse_args()
    if args.states:
        for fraction in (float(f) for f in args.at.split(",")):
            points = stroke_blank(args.cells, fraction, Path(args.states), args.calls)
            compare(points, args.rounds, f"the stroke's state at {fraction:g}")
        return
    points = laid_blank(args.cells, args.slide, args.calls)
    compare(points, args.rounds, f"the blank laid in the die, sliding {args.slide:g} mm a call")


if __name__ == "__main__":
    main()
