"""The two-ply hemisphere's Mindlin [0/90] run (validation/studies/hemisphere_plies_run.py, 8
cells, holder 20 N) and its ply contact's landing steps (elements/ply_landing.py; docs/theory.md
§9.3a, "A point's landing step"): how often its points land, where the rule anchors them, the
friction work of the landing steps themselves, and the run's measures, with the landing
counted or not (``--without``: every landing found is dropped, the code before the rule) and
the friction coefficient scaled by ``--mu-scale`` (a perturbation far below any physical one).

    python -m validation.studies.hemisphere_plies_landing [--slowing 2] [--mu-scale 1.000001]
        [--without]

Per accepted step (the explicit commit, ``PlyContactBlock.update_history``) the points whose
side passes from not touching to touching are counted as landings and back as leaves; for each
landing point the rule's theta, the length of its way over the step on the plane of the
triangle it faces (|sum_k (Lambda_k - Lambda_0,k) y_k|), its slip |s| from the landing anchor
after the return mapping and the cosine of s with the way's tangential part (friction acts
against -s) and its normal force N; the landing step's friction work is
mu (0 + N) / 2 times the slip past the stick limit (the accepted history's rule). Measured:
docs/theory.md §9.3a, "A point's landing step".
"""

from __future__ import annotations

import argparse
import time
from typing import Any

import numpy as np

from elements import ply_block, ply_departure, ply_friction, ply_landing, ply_landing_kernels
from elements.ply_sides import TOUCHING
from validation.studies import hemisphere_plies_run as study
from validation.studies.hemisphere_plies_setup import HOLDER_FORCES


def _edges(found: Any) -> np.ndarray:
    """(r,) bool: the landing points ``found`` whose gap is to an edge or a vertex."""
    edge = getattr(found, "edge", None)
    return np.zeros(len(found.rows), dtype=bool) if edge is None else edge


class _Probe:
    """The landings counted per point and the landing steps' records (module docstring)."""

    def __init__(self, without: bool) -> None:
        self.without = without
        self.committing = False
        self.lands: dict[int, np.ndarray] = {}
        self.leaves: dict[int, np.ndarray] = {}
        self.theta: list[np.ndarray] = []
        self.way: list[np.ndarray] = []
        self.slip: list[np.ndarray] = []
        self.cosine: list[np.ndarray] = []
        self.work = 0.0
        self.edges: list[np.ndarray] = []  # per landing step: its points facing an edge
        self.departures = [0, 0]  # points leaving by a plane's gap, by an edge's
        self.departure_slip = [0.0, 0.0]  # their largest slip, mm
        self.dissipated: dict[int, float] = {}
        self._landing = ply_landing.landing
        self._departure = ply_departure.departure
        self._landed = ply_landing.landed
        self._update = ply_block.PlyContactBlock.update_history

    def landing(self, block, state, history, facing):  # noqa: ANN001, ANN201
        return None if self.without else self._landing(block, state, history, facing)

    def landed(self, block, state, history, facing, found=None):  # noqa: ANN001, ANN201
        found = self.landing(block, state, history, facing) if found is None else found
        out = self._landed(block, state, history, facing, found)
        if self.committing and found is not None:
            sliding = ply_friction.friction_state(block, state, out, facing)
            rows = found.rows
            _, y = block._faces(state)
            way = np.einsum("rk,rki->ri", found.rate, y[facing.triangle[rows]])
            slip = np.linalg.norm(sliding.slip[rows], axis=1)
            # (a point facing an edge: its way off T's plane too, the heights' change)
            heights = (
                found.height
                - ply_landing.plane_places(
                    history.sides.corners[facing.triangle[rows]], history.sides.faces[rows]
                )[1]
            )
            edge = _edges(found)
            way = np.where(edge[:, None], way + heights[:, None] * found.normal, way)
            n = facing.normal[rows]
            along = way - np.sum(way * n, axis=1)[:, None] * n  # the way's tangential part
            size = np.linalg.norm(along, axis=1) * slip
            cosine = np.sum(along * sliding.slip[rows], axis=1) / np.where(size > 0, size, 1.0)
            self.cosine.append(cosine[size > 1e-12])
            limit = block.friction * sliding.pressing[rows]
            spring = np.where(sliding.spring[rows] > 0, sliding.spring[rows], 1.0)
            past = np.where(sliding.sliding[rows], slip - limit / spring, 0.0)
            self.work += float(np.sum(0.5 * limit * past))
            self.edges.append(_edges(found))
            self.theta.append(found.theta)
            self.way.append(np.linalg.norm(way, axis=1))
            self.slip.append(slip)
        return out

    def departure(self, block, y, history, facing):  # noqa: ANN001, ANN201
        rows, slip = self._departure(block, y, history, facing)
        if self.committing and len(rows) and facing.on_edge is not None:
            edge = facing.on_edge[rows]
            for k, picked in enumerate((~edge, edge)):
                self.departures[k] += int(picked.sum())
                if picked.any():
                    self.departure_slip[k] = max(self.departure_slip[k], float(slip[picked].max()))
        return rows, slip

    def install(self) -> None:
        probe = self

        def update_history(block: Any, state: Any, history: Any) -> Any:
            probe.committing = True
            try:
                new = probe._update(block, state, history)
            finally:
                probe.committing = False
            before, after = getattr(history, "sides", None), getattr(new, "sides", None)
            if before is not None and after is not None:
                was, now = before.sides == TOUCHING, after.sides == TOUCHING
                count = probe.lands.setdefault(id(block), np.zeros(len(was), dtype=int))
                count += ~was & now
                gone = probe.leaves.setdefault(id(block), np.zeros(len(was), dtype=int))
                gone += was & ~now
            probe.dissipated[id(block)] = float(getattr(new, "dissipated", 0.0))
            return new

        # the landing by numpy's ``ply_landing.landing`` (watched here): the kept landing
        # asks the compiled one on flat faces (elements/ply_landing_kernels.py, the same bits)
        ply_landing_kernels.COMPILED = False
        ply_landing.landing, ply_landing.landed = self.landing, self.landed  # type: ignore[assignment]
        ply_departure.departure = self.departure  # type: ignore[assignment]
        ply_block.PlyContactBlock.update_history = update_history  # type: ignore[method-assign]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--slowing", type=float, default=2.0, help="the stroke's slowing")
    parser.add_argument("--mu-scale", type=float, default=1.0, help="the friction's factor")
    parser.add_argument("--without", action="store_true", help="no landing counted")
    args = parser.parse_args()
    probe = _Probe(args.without)
    probe.install()
    keep = ply_block.PlyContactBlock.__init__

    def scaled(block: Any, *a: Any, **k: Any) -> None:
        keep(block, *a, **k)
        block.friction = block.friction * args.mu_scale

    ply_block.PlyContactBlock.__init__ = scaled  # type: ignore[method-assign]
    study.STROKE_SLOWING = {**study.STROKE_SLOWING, ("0/90", "mindlin"): args.slowing}
    start = time.process_time()
    found, *_ = study.run(8, "0/90", "mindlin", HOLDER_FORCES[0])
    prefix = f"0-90_mindlin_{HOLDER_FORCES[0]:g}_N_"
    print(
        f"slowing {args.slowing:g}, mu x {args.mu_scale!r}, landing "
        f"{'dropped' if args.without else 'counted'}: {time.process_time() - start:.1f} s CPU"
    )
    for key, value in found.items():
        if key.startswith(prefix) and any(w in key for w in ("slip", "draw_in", "punch")):
            print(f"  {key[len(prefix) :]} {value:.4f}")
    lands = np.concatenate(list(probe.lands.values()))
    leaves = np.concatenate(list(probe.leaves.values()))
    print(
        f"  landings {lands.sum()} and leaves {leaves.sum()} of {len(lands)} points: "
        f"{np.sum(lands >= 50)} landed 50 times or more, at most {lands.max()}"
    )
    print(f"  ply friction records {sum(probe.dissipated.values()):.4f} N mm")
    print(
        f"  departures by a plane's gap {probe.departures[0]} (slip at most "
        f"{probe.departure_slip[0]:.4f} mm), by an edge's {probe.departures[1]} (at most "
        f"{probe.departure_slip[1]:.4f} mm)"
    )
    if probe.theta:
        theta, way, slip = (np.concatenate(x) for x in (probe.theta, probe.way, probe.slip))
        edge = np.concatenate(probe.edges)
        if edge.any():
            print(
                f"  landing steps facing an edge {edge.sum()}: theta 10/50/90 % "
                f"{np.percentile(theta[edge], [10, 50, 90]).round(3)}, way at most "
                f"{way[edge].max():.4f} mm, slip at most {slip[edge].max():.4f} mm"
            )
        deciles = np.percentile(theta, [10, 50, 90])
        print(
            f"  landing steps {len(theta)}: theta 10/50/90 % {deciles.round(3)}, theta = 0 in "
            f"{np.sum(theta == 0.0)}; way at most {way.max():.4f} mm (mean {way.mean():.5f}); "
            f"slip at most {slip.max():.4f} mm (mean {slip.mean():.5f}); their friction work "
            f"{probe.work:.3f} N mm"
        )
        cosine = np.concatenate(probe.cosine)
        print(
            f"  the slip along the way's tangential part: cosine at least {cosine.min():.4f}, "
            f"below 0.99 in {np.sum(cosine < 0.99)} of {len(cosine)}"
        )


if __name__ == "__main__":
    main()
