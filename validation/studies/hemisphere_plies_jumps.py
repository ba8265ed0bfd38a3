"""The two-ply hemisphere's ply contacts, point by point: each contact point's penalty energy
against the work of its force over every step (validation/studies/hemisphere_plies.py, "Mindlin
[0/90] at 10 cells"). Energy made or lost in a step with no work is a contact's defect (a
point switching into contact, or its gap's sign flipping, deep in the penalty), not physics.

Per point and step, on the contact faces (the point p and its facing triangle's offset corners
y_k, which the force moves): jump = W_new - W_old - (trapezoidal work of dW/dp on p and of
dW/dy_k on the corners of the old and of the new facing triangle), dW/dp = w W' n + W dw/dp and
dW/dy_k = -lambda_k w W' n + W dw/dy_k (w the outline's fade, elements/ply_projection.py
"Past the outline, faded"; 1 and 0 on code without it). Summed over the points of each ply
contact (the pass of the top ply's points and the mirrored pass), a step's jump above 1 N mm
is counted. Run it with ``python -m validation.studies.hemisphere_plies_jumps 10 "0/90"
mindlin 20``.

Measured (Mindlin [0/90], 10 cells, 20 N; one thread, one run at a time, CPU of the run):
see docs/hemisphere_plies.md, "The outline's fade", "The fade by the distance to the
outline" and "Growths joined at a fold". On d004b4e and with the growths joined (one thread,
CPU of the run, load 5-12): 8 cells 2 steps above +1 N mm (+3.3) in 13351 and 3 (+9.9) in
13262, 10 cells 16 (+46.1) in 17040 and 8 (+18.2) in 16955, every check passing in the four,
134 / 135 / 225 / 211 s; the runs part early, and every jump left is at an outline vertex of
three triangles, where no growths are joined. With the growths cut there (elements/
ply_wedge.py; docs/hemisphere_plies.md, "The wedge cut"; the codes side by side, load 5-13):
8 cells 3 (+5.7) in 13705, the holder's check failing, 10 cells 1 (+1.6) in 17019, every
check passing, 176 / 252 s. Each jump's line names what the point faced
before and after: the facing triangle's row, the closest point's feature (its plane, an edge
or a vertex), whether on the outline, on a growth's edge, on a joined growth's edge, its fade
and whether it touches.
"""

from __future__ import annotations

import sys
import time
from typing import Any

import numpy as np

from elements.ply_block import PlyContactBlock
from elements.ply_projection import penalty_law
from femcore.state import State

__all__ = ["Jumps", "measure"]


class Jumps:
    """The recorder of one ply contact block: wraps its ``internal_force`` (called once a
    step by the explicit solver) and keeps, at each new state, each point's penalty energy
    and its gradient on the faces; ``steps`` (s,) the summed jump of each step, N mm,
    ``largest`` the point jumps above 1 N mm as (step, point, jump N mm, gap before, gap
    after, mm, what the point faced before and after)."""

    def __init__(self, block: PlyContactBlock):
        self.block = block
        self.steps: list[float] = []
        self.largest: list[tuple[int, int, float, float, float, str]] = []
        self._last: tuple | None = None
        self._state_before: Any = None
        self._state_now: Any = None
        original = block.internal_force

        def recorded(state, history=None):
            out = original(state, history)
            self.record(state, history)
            return out

        block.internal_force = recorded  # type: ignore[method-assign]

    def record(self, state: Any, history: Any = None) -> None:
        block = self.block
        # the facing the loads take: the points the history's sides keep off not touching
        # (elements/ply_sides.py; a code before them has no ``_held``)
        held = getattr(block, "_held", None)
        facing = block.facing(state) if held is None else held(state, history)
        p, y = block._faces(state)
        on = facing.touching
        fade = getattr(facing, "fade", None)
        fade = np.ones(len(p)) if fade is None else fade
        slope_of_fade = getattr(facing, "fade_gradient", None)
        if slope_of_fade is None:
            slope_of_fade = np.zeros((len(p), 6, 3))
        if slope_of_fade.shape[1] == 4:  # code whose fade moves with the facing corners alone
            slope_of_fade = np.concatenate([slope_of_fade, np.zeros((len(p), 2, 3))], axis=1)
        # the outline's edge the fade measures from (elements/ply_fade.py), -1: none
        edge = getattr(facing, "fade_edge", None)
        edge = np.full(len(p), -1) if edge is None else edge.copy()
        energy, slope, _ = penalty_law(facing.gap, block.stiffness, block.smoothing)
        energy = np.where(on, energy, 0.0)
        slope = np.where(on, slope, 0.0)
        on_p = (fade * slope)[:, None] * facing.normal + energy[:, None] * slope_of_fade[:, 0]
        on_y = (
            -(fade * slope)[:, None, None] * facing.weights[:, :, None] * facing.normal[:, None, :]
            + energy[:, None, None] * slope_of_fade[:, 1:4]
        )
        on_e = energy[:, None, None] * slope_of_fade[:, 4:]
        outline = block.outline[facing.triangle].any(axis=1)
        growth = getattr(facing, "on_growth", None)
        growth = np.zeros(len(p), dtype=bool) if growth is None else growth
        joined = getattr(facing, "joined", None)
        joined = np.zeros(len(p), dtype=bool) if joined is None else joined
        reach = getattr(facing, "reach", None)
        reach = np.zeros((len(p), 3)) if reach is None else reach
        # the closest point's feature: the facing triangle's plane, an edge (a growth's edge
        # joined to its neighbour's growth or not) or a vertex
        bounds = (facing.weights <= -reach + 1e-9).sum(axis=1)
        feature = np.array(["plane", "edge", "vertex", "vertex"])[bounds]
        # what each point faces: its row, a triangle on the outline or not, a growth's edge,
        # its fade
        kind = [
            f"row {r} {f} outline {int(o)} growth {int(g)} joined {int(j)} fade {w:.3f} "
            f"touching {int(t)}"
            for r, f, o, g, j, w, t in zip(
                facing.triangle, feature, outline, growth, joined, fade, on
            )
        ]
        now = (
            fade * energy,
            on_p,
            on_y,
            facing.triangle.copy(),
            p.copy(),
            y.copy(),
            facing.gap,
            kind,
            on_e,
            edge,
        )
        last = self._last
        if last is not None and np.array_equal(last[4], p) and np.array_equal(last[5], y):
            return
        self._last = now
        # the states' copies (the solver may move its arrays in place): the ends' moves
        zero = np.zeros_like(state.positions)
        self._state_before = self._state_now
        self._state_now = State(state.positions.copy(), state.directors.copy(), zero, zero)
        if last is None:
            return
        dp, dy = p - last[4], y - last[5]
        work = 0.5 * np.einsum("pi,pi->p", last[1] + on_p, dp)
        work += 0.5 * np.einsum("pki,pki->p", last[2], dy[last[3]])
        work += 0.5 * np.einsum("pki,pki->p", on_y, dy[facing.triangle])
        # the outline's ends a, b: each side's force times the move of its own edge's ends
        for force, ids in ((last[8], last[9]), (on_e, edge)):
            moved = self._ends(self._state_now, ids) - self._ends(self._state_before, ids)
            work += 0.5 * np.einsum("pki,pki->p", force, moved)
        jump = now[0] - last[0] - work
        step = len(self.steps)
        self.steps.append(float(jump.sum()))
        for i in np.flatnonzero(np.abs(jump) > 1.0):
            self.largest.append(
                (
                    step,
                    int(i),
                    float(jump[i]),
                    float(last[6][i]),
                    float(facing.gap[i]),
                    f"before: {last[7][i]}; after: {kind[i]}",
                )
            )

    def _ends(self, state: Any, edge: np.ndarray) -> np.ndarray:
        """(P, 2, 3) the offset ends y = x + c d of the outline's edges ``edge`` (P,) at
        ``state``, mm (zeros where -1, or on code without them)."""
        block = self.block
        nodes = getattr(block, "outline_nodes", None)
        if nodes is None or not len(nodes):
            return np.zeros((len(edge), 2, 3))
        rows = np.maximum(edge, 0)
        ends = nodes[rows]
        d = block.offset_directions(state)[ends]
        return state.positions[ends] + block.outline_offsets[rows][..., None] * d

    def summary(self) -> dict[str, float]:
        steps = np.array(self.steps)
        up, down = steps[steps > 1.0], steps[steps < -1.0]
        return {
            "steps": len(steps),
            "above_1": int(up.size),
            "above_1_sum": float(up.sum()),
            "below_minus_1": int(down.size),
            "below_minus_1_sum": float(down.sum()),
            "largest": float(steps.max(initial=0.0)),
            "net": float(steps.sum()),
        }


def measure(cells: int, name: str, kinematics: str, force: float) -> dict[str, Any]:
    """One run of the study (``hemisphere_plies_run.run``) with each ply contact recorded:
    its checks (label, passed), the per-block ``Jumps.summary`` and the run's CPU time."""
    from validation.studies.hemisphere_plies_run import run

    recorders: list[Jumps] = []

    def instrument(compiled):
        recorders.extend(
            Jumps(block) for block in compiled.interactions if isinstance(block, PlyContactBlock)
        )

    start = time.process_time()
    parameters, checks, *_ = run(cells, name, kinematics, force, instrument=instrument)
    return {
        "cpu_s": time.process_time() - start,
        "checks": [(c.name, bool(c.passed)) for c in checks],
        "stopped": {k: v for k, v in parameters.items() if k.endswith("stopped")},
        "blocks": [r.summary() for r in recorders],
        "largest": [r.largest for r in recorders],
    }


if __name__ == "__main__":
    cells, name, kinematics, force = sys.argv[1:5]
    outcome = measure(int(cells), name, kinematics, float(force))
    print("cpu", round(outcome["cpu_s"], 1), "s", outcome["stopped"])
    for label, passed in outcome["checks"]:
        print("PASS" if passed else "FAIL", label)
    for k, (summary, largest) in enumerate(zip(outcome["blocks"], outcome["largest"])):
        print("block", k, summary)
        for row in largest[:40]:
            print("   step {} point {} jump {:+.3f} N mm gap {:+.4f} -> {:+.4f}, {}".format(*row))
