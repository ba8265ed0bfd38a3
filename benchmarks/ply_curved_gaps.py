"""Why Static's curved steps lose with ply contact, measured, and two curved steps that hold
the plies' gaps, tried (not the project's method): on the weight-carrying stacks of
benchmarks/ply_newton_table.py (plies-heavy-cantilever's 4 plies, plies-bai-5.1's), each with
its case's own solver, side by side in this process; per side the Newton iterations per
increment, the attempts cut, the tangents, the curved steps taken, CPU (one thread), and per
iteration what each update did to the ply contact's gaps g (mm, < 0 pressed):

* ``apart``: points with g > 0 after the update (no contact stiffness in the next tangent:
  the smoothed penalty's W'' is 0 there, docs/theory.md §9.3a);
* ``crossed``: points an update carried from g > 0 to g < -delta (through the ramp), and the
  updates that crossed any.

The sides: ``straight`` (the case's solver: no curved step with interactions); ``curved``
(``Static(curved_with_contact=True)``, solvers/newton_curvature.py as it is); ``curved s^2``
(the update cap's scale s applied as s delta + s^2 w to a curved step delta + w, the path's
own parametrisation, where Watchdog scales the whole step by s); ``held`` (the curved step's
correction with the gaps held to second order: the probes' second difference of the residual
without the ply contact's share, then the least-energy correction in K with A w = -g''/2 on
the points touching or that the step brings into touch, A = dg/dq their gap gradients
(translations, and the directors through the faces' offsets), g'' the gaps' second central
difference along the step: the KKT system [K A^T; A 0], by one solve per held point);
``kept`` (the same with A w = 0: the gaps of the straight step's end). ``--events`` corrects
every side's steps for the points they would carry through (``event_correction``: those
points given the deep branch's linear law in the step's system, by K's factors and one
solve a point, at most ``--rounds`` times); ``--floor r`` floors the contact's W'' at k
within delta of touching in the tangents of iterates whose residual ratio is above r.

    python benchmarks/ply_curved_gaps.py [--cases heavy,bai] [--resolution coarse]
        [--sides straight,curved,curved s^2,held,kept] [--update-turn case|none|rad]
        [--events [--rounds 3]] [--floor 1e-2] [--trace 12]

``--trace N`` prints the first N updates of each side (scale, curved or not, largest turn,
crossed, apart, smallest gap, residual ratio after, the residual's norm and the contact
forces' norm).

Measured (coarse, one thread, CPU, the 2 cores shared, load 8.3-9.8; tangents; updates that
crossed of all updates, and the points they carried through):

* heavy (4 plies, the case's update cap 0.03 rad): straight 125 (29-33-29-19-15), 2 of 125
  crossed (2 points); curved 316 (45-101-46-32-47, 42 cut), 66 of 313 (603); curved s^2 478
  (96 cut); held 303 (42-77-76-33-35, 37 cut), 51 of 300; kept 364 (81 cut), 89 of 361.
  Without the cap (``--update-turn none``, Static's 0.5 rad): straight 277, 89 of 277
  crossed (757 points); curved 288, 92 of 286; held 206 (11 cut), 59 of 205.
* bai (plies-bai-5.1's 4 plies; its cap 0.5 rad, so curved s^2 = curved): straight 271 (257
  + 8 cut), 39 of 265 crossed (420 points); curved 599 (403 + 187), 292 of 590 (5189); held
  448 (370 + 71), 202 of 441; kept 428 (320 + 102), 180 of 422.
* The first update of the heavy stack's first increment (``--trace 3``; the plies laid at
  g = 0): straight, none of the 60 points apart after it (the unturned offsets press all of
  them onto the ramp, -6.7e-4 mm at the deepest); curved, 40 apart, and the next update, a
  Newton step from a tangent without those points, carries 20 of them through the ply below
  (to -1.07 mm), the next ones cut back to 0.1-0.3 of their steps; held, the gaps within
  3.5e-8 mm of 0, yet 58 apart (the step's third order), and the next update carries 56
  through (-0.17 mm).
* ``--events``: heavy straight 122, curved 269 (no update crossing, none cut), held 273;
  without the cap straight 207, curved 211, held 148 (22-45-30-34-17, none cut); bai
  straight 277, curved 533, held 481. With the crossings gone the curved updates of the heavy
  stack still leave a residual ratio of 1 (``--trace``): |r| 0.2-1.6 N where the contact
  forces are 0.01-0.2 N (the plies' own residual), on updates the cap scales to 0.4-0.9.
* ``--floor 1e-2``: straight fails in the first increment (load factor 0.125 after 8 cuts),
  held 1510 tangents (801 + 700 cut).
* The final positions within 2e-10 mm of the straight steps' on every side.

So the curved steps with contact lose first by the contact events they cause: they move the
plies' points off the ramp (g > 0, where the tangent has no contact stiffness), and a
following Newton step, which does not see those points, drives the plies through each other
(the update cap's gain on the straight steps, 277 -> 125, is the crossings it removes too).
Holding the gaps to second order keeps them, but on the open side of the ramp's double root;
giving the steps the points they close removes the crossings but not the plies' own residual
after curved updates that the cap scales. The best pair measured, the held correction with
the event correction and no cap, takes 148 tangents on heavy against today's 125; its
remaining iterations (``--events --update-turn none --sides held --trace 70``) mostly halve
the gaps of points on the ramp, the contact forces the whole residual (-7.5e-4, -3.8e-4,
-2.0e-4, -1.25e-4 mm at a ratio near 1): the ramp's double root (docs/theory.md §6.5, "The
deck's last increment").
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np
import scipy.sparse as sp

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

import solvers.line_search as line_search  # noqa: E402
import solvers.newton as newton_module  # noqa: E402
import solvers.static as static_module  # noqa: E402
from benchmarks.ply_newton_table import CASE_RULES  # noqa: E402
from benchmarks.static_plies_case import solve_case  # noqa: E402
from elements import ply_block  # noqa: E402
from femcore.dofs import N_COLUMNS  # noqa: E402
from solvers import newton_curvature  # noqa: E402

PLAIN_CURVED = newton_module.curved_step
PLAIN_STEP = line_search.Watchdog.step
SIDES = ("straight", "curved", "curved s^2", "held", "kept")
# per side: the updates' records and the held points' count
TRACE: dict = {"rows": [], "held": 0, "print": 0, "events": 0}
# ``--events``: the Newton steps corrected for the points they carry through (the last
# factorisation of the run kept here for it)
EVENTS: dict = {"on": False, "factor": None, "rounds": 3}
PLAIN_FACTORISE = static_module.StaticRun.factorise


def kept_factorise(self, k_ff):
    """StaticRun.factorise keeping its factors for ``event_correction``."""
    EVENTS["factor"] = PLAIN_FACTORISE(self, k_ff)
    return EVENTS["factor"]


def ply_blocks(model) -> list:
    """The model's ply contacts (elements/ply_block.py)."""
    return [b for b in model.interactions if isinstance(b, ply_block.PlyContactBlock)]


def gaps(model, state) -> np.ndarray:
    """(P,) every ply contact point's gap at ``state``, mm."""
    return np.concatenate([block.facing(state).gap for block in ply_blocks(model)])


def gap_gradients(block, state, facing, points: np.ndarray, frames, dofs):
    """The nodes (t, 6) and dg/dq (t, 6, 5) of the contact ``points`` (t,) at ``state``: g =
    n . (p - y), p = sum N_j (x_j - a_j d_j) on the upper triangle, y the facing triangle's
    point (corners y_k = x_k + b_k d_k, weights lambda_k), the directors turned by psi =
    alpha V2 + beta V1 (elements/ply_block.py, its loads with W' = 1)."""
    n, lam = facing.normal[points], facing.weights[points]
    triangle = facing.triangle[points]
    nodes = np.column_stack([block.above[points], block.cells[triangle]])
    along = np.concatenate(
        [block.shape[points][:, :, None] * n[:, None, :], -lam[:, :, None] * n[:, None, :]],
        axis=1,
    )  # dg/dx (t, 6, 3)
    d = block.offset_directions(state)[nodes]
    offset = block.lever * np.column_stack(
        [-block.upper_offset[points], block.corner_offset[triangle]]
    )
    turning = offset[:, :, None] * np.cross(d, along)  # dg/dpsi (t, 6, 3)
    v1, v2 = frames
    rows = np.zeros((*along.shape[:2], N_COLUMNS))
    rows[..., :3] = along
    rows[..., 3] = np.sum(turning * v2[nodes], axis=2)
    rows[..., 4] = np.sum(turning * v1[nodes], axis=2)
    rows[..., 3:] *= dofs.has_rotation[nodes][..., None]
    return nodes, rows


def held_curved_step(run, equilibrium, state, frames, delta, r, factor, hold: bool):
    """solvers.newton_curvature.curved_step with the ply gaps held (module docstring):
    ``hold`` A w = -g''/2 (``held``), else A w = 0 (``kept``)."""
    model, dofs = run.model, run.model.dofs
    size = model.element_size
    turned = float(np.abs(delta[:, 3:]).max(initial=0.0))
    moved = float(np.abs(delta[:, :3]).max(initial=0.0)) / size
    if max(turned, moved) <= newton_curvature.CURVED_FROM:
        return None
    h = newton_curvature.CURVATURE_PROBE
    ahead = dofs.advance(state, h * delta, frames)
    behind = dofs.advance(state, -h * delta, frames)
    second = (
        equilibrium.residual(ahead, frames)[0] - 2.0 * r + equilibrium.residual(behind, frames)[0]
    ) / h**2
    contacts = list(range(len(model.blocks), len(model.parts)))
    f = [model.internal_force(s, parts=contacts) for s in (ahead, state, behind)]
    share = dofs.generalised(
        frames, f[0][0] - 2.0 * f[1][0] + f[2][0], f[0][1] - 2.0 * f[1][1] + f[2][1]
    )
    second = second + np.where(dofs.free, share, 0.0) / h**2  # r = F_ext - F_int
    index = dofs.free_slots
    w = factor.solve(0.5 * second.ravel()[index])
    if w is None:
        return None
    slot = np.full(dofs.n_slots, -1)
    slot[index] = np.arange(index.size)
    rows, columns, values, targets = [], [], [], []
    for block in ply_blocks(model):
        here, up, down = block.facing(state), block.facing(ahead), block.facing(behind)
        first = (up.gap - down.gap) / (2.0 * h)
        curvature = (up.gap - 2.0 * here.gap + down.gap) / h**2
        same = (up.triangle == here.triangle) & (down.triangle == here.triangle)
        # a facing found at the three states (``touching`` is g < 0 alone)
        faced = same & (here.triangle >= 0) & np.isfinite(up.gap + here.gap + down.gap)
        points = np.flatnonzero(faced & ((here.gap <= 0.0) | (here.gap + first <= 0.0)))
        if not points.size:
            continue
        nodes, gradient = gap_gradients(block, state, here, points, frames, dofs)
        flat = slot[(nodes[..., None] * N_COLUMNS + np.arange(N_COLUMNS)).reshape(len(points), -1)]
        row = np.repeat(np.arange(len(points)) + sum(map(len, targets)), flat.shape[1])
        used = flat.ravel() >= 0
        rows.append(row[used])
        columns.append(flat.ravel()[used])
        values.append(gradient.reshape(len(points), -1).ravel()[used])
        targets.append(-0.5 * curvature[points] if hold else np.zeros(len(points)))
    if targets:
        target = np.concatenate(targets)
        a = sp.csr_matrix(
            (np.concatenate(values), (np.concatenate(rows), np.concatenate(columns))),
            shape=(target.size, index.size),
        )
        z = factor.solve(a.T.toarray())
        if z is None:
            return None
        z = z.reshape(index.size, target.size)
        multipliers = np.linalg.lstsq(a @ z, target - a @ w, rcond=1e-12)[0]
        w = w + z @ multipliers
        TRACE["held"] += target.size
    flat_w = np.zeros(dofs.n_slots)
    flat_w[index] = w
    correction = flat_w.reshape(-1, N_COLUMNS)
    limit = newton_curvature.CURVATURE_LIMIT * newton_curvature.scaled_norm(delta, size)
    if not np.all(np.isfinite(w)) or newton_curvature.scaled_norm(correction, size) > limit:
        return None
    run.info["curved_steps"] += 1
    return delta + correction


def event_correction(run, state, frames, delta, factor, rounds: int = 3) -> np.ndarray | None:
    """The change (n, 5) of the Newton step ``delta`` that holds the points it would carry
    from apart (g > 0) through the ramp (g < -delta at the step's end): each such point given
    the deep branch's linear law k (g + A dq + delta / 2) in the step's system, (K + A^T k A)
    dq = r - A^T k (g + delta / 2), solved with K's factors (Woodbury: one solve a point),
    repeated while the corrected step carries others through (at most ``rounds``); None when
    it carries none."""
    model, dofs = run.model, run.model.dofs
    index = dofs.free_slots
    slot = np.full(dofs.n_slots, -1)
    slot[index] = np.arange(index.size)
    blocks = ply_blocks(model)
    facings = [block.facing(state) for block in blocks]
    chosen = [np.zeros(len(facing.gap), dtype=bool) for facing in facings]
    start = delta.ravel()[index]
    change = np.zeros(index.size)
    for _ in range(rounds):
        trial = dofs.advance(state, delta + _full(change, dofs), frames)
        added = False
        for block, facing, held in zip(blocks, facings, chosen):
            faced = (facing.triangle >= 0) & np.isfinite(facing.gap)
            crossing = faced & (facing.gap > 0.0) & (block.facing(trial).gap < -block.smoothing)
            added |= bool(np.any(crossing & ~held))
            held |= crossing
        if not added:
            break
        a, offset, stiffness = _gap_rows(blocks, facings, chosen, state, frames, dofs, slot)
        z = factor.solve(a.T.toarray())
        if z is None:
            return None
        z = z.reshape(index.size, -1)
        shifted = start - z @ (stiffness * offset)
        multipliers = np.linalg.solve(np.diag(1.0 / stiffness) + a @ z, a @ shifted)
        change = shifted - z @ multipliers - start
    if not np.any(change):
        return None
    TRACE["events"] += 1
    return _full(change, dofs)


def _full(values: np.ndarray, dofs) -> np.ndarray:
    """(n, 5) with the free slots' ``values``, zero elsewhere."""
    flat = np.zeros(dofs.n_slots)
    flat[dofs.free_slots] = values
    return flat.reshape(-1, N_COLUMNS)


def _gap_rows(blocks, facings, chosen, state, frames, dofs, slot):
    """The chosen points' gap gradients A (t, n_free) sparse, g + delta / 2 (t,) and k (t,)."""
    rows, columns, values, offsets, stiffness = [], [], [], [], []
    count = 0
    for block, facing, held in zip(blocks, facings, chosen):
        points = np.flatnonzero(held)
        if not points.size:
            continue
        nodes, gradient = gap_gradients(block, state, facing, points, frames, dofs)
        flat = slot[(nodes[..., None] * N_COLUMNS + np.arange(N_COLUMNS)).reshape(len(points), -1)]
        used = flat.ravel() >= 0
        rows.append(np.repeat(np.arange(len(points)) + count, flat.shape[1])[used])
        columns.append(flat.ravel()[used])
        values.append(gradient.reshape(len(points), -1).ravel()[used])
        offsets.append(facing.gap[points] + 0.5 * block.smoothing)
        stiffness.append(block.stiffness[points])
        count += len(points)
    a = sp.csr_matrix(
        (np.concatenate(values), (np.concatenate(rows), np.concatenate(columns))),
        shape=(count, dofs.free_slots.size),
    )
    return a, np.concatenate(offsets), np.concatenate(stiffness)


def traced_step(side: str):
    """Watchdog.step recording each update's gaps (and, ``curved s^2``, scaling a capped
    curved step along its path)."""

    def step(self, state, frames, delta, r, whole, straight=None):
        if EVENTS["on"] and not whole and EVENTS.get("factor") is not None:
            change = event_correction(
                self.run, state, frames, delta, EVENTS["factor"], EVENTS["rounds"]
            )
            if change is not None:
                straight = (delta if straight is None else straight) + change
                delta = delta + change
        if side == "curved s^2" and straight is not None and not whole and self.enabled:
            scale = self._cap(straight)
            if scale < 1.0:
                delta = scale * straight + scale**2 * (delta - straight)
                straight = scale * straight
        out = PLAIN_STEP(self, state, frames, delta, r, whole, straight)
        model = self.run.model
        before, after = gaps(model, state), gaps(model, out[1])
        smoothing = min(block.smoothing for block in ply_blocks(model))
        crossed = int(np.sum((before > 0.0) & (after < -smoothing)))
        TRACE["rows"].append((crossed, int(np.sum(after > 0.0))))
        if TRACE["print"] > 0:
            TRACE["print"] -= 1
            residual, ratio, _ = self.equilibrium.residual(out[1], frames)
            contacts = list(range(len(model.blocks), len(model.parts)))
            force, moment = model.internal_force(out[1], parts=contacts)
            free = model.dofs.free
            contact = np.where(free, model.dofs.generalised(frames, force, moment), 0.0)
            print(
                f"    scale {out[0]:.3f}, curved {straight is not None}, turn "
                f"{np.abs(delta[:, 3:]).max():.3f} rad: crossed {crossed}, apart "
                f"{TRACE['rows'][-1][1]} of {after.size}, smallest gap {after.min():+.2e} mm, "
                f"ratio after {ratio:.2e}, |r| {np.linalg.norm(residual):.2e} N, the contact's "
                f"forces {np.linalg.norm(contact):.2e} N"
            )
        return out

    return step


PLAIN_TANGENT = ply_block.PlyContactBlock.tangent
PLAIN_LAW = ply_block.penalty_law
PLAIN_RESIDUAL = newton_module.Residual.residual
FLOOR = {"far": None, "ratio": 1.0}  # ``--floor``: the ratio above which the floor holds


def floored_law(gap, stiffness, smoothing):
    """The smoothed penalty (elements/ply_projection.py) with W'' at least k within
    ``smoothing`` of touching: the tangent's only (``--floor``)."""
    energy, force, curvature = PLAIN_LAW(gap, stiffness, smoothing)
    return energy, force, np.where(gap < smoothing, np.maximum(curvature, stiffness), curvature)


def floored_tangent(self, state, history=None):
    """PlyContactBlock.tangent with ``floored_law`` while the last residual ratio is above
    ``FLOOR["far"]``."""
    if FLOOR["far"] is None or FLOOR["ratio"] <= FLOOR["far"]:
        return PLAIN_TANGENT(self, state, history)
    ply_block.penalty_law = floored_law
    try:
        return PLAIN_TANGENT(self, state, history)
    finally:
        ply_block.penalty_law = PLAIN_LAW


def recorded_residual(self, state, frames, forces=None):
    """Residual.residual keeping the last ratio (the next tangent's iterate's)."""
    out = PLAIN_RESIDUAL(self, state, frames, forces)
    FLOOR["ratio"] = out[1]
    return out


def use(side: str) -> None:
    """Patch Static for ``side`` (module docstring); ``straight`` restores it."""
    line_search.Watchdog.step = traced_step(side) if side != "straight" else PLAIN_STEP
    if side in ("held", "kept"):
        hold = side == "held"

        def curved(run, equilibrium, state, frames, delta, r, factor):
            return held_curved_step(run, equilibrium, state, frames, delta, r, factor, hold)

        newton_module.curved_step = curved
    else:
        newton_module.curved_step = PLAIN_CURVED


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cases", default="heavy,bai")
    parser.add_argument("--resolution", default="coarse")
    parser.add_argument("--sides", default=",".join(SIDES))
    parser.add_argument("--trace", type=int, default=0, help="updates printed per side")
    parser.add_argument("--update-turn", default="case", help="'case', 'none' or rad")
    parser.add_argument(
        "--floor", type=float, default=None, help="the floored tangent above this ratio"
    )
    parser.add_argument(
        "--events", action="store_true", help="every side's steps corrected for the crossings"
    )
    parser.add_argument("--rounds", type=int, default=3, help="with --events: at most")
    args = parser.parse_args()
    if args.events:
        EVENTS.update(on=True, rounds=args.rounds)
        static_module.StaticRun.factorise = kept_factorise
    if args.floor is not None:
        FLOOR["far"] = args.floor
        ply_block.PlyContactBlock.tangent = floored_tangent
        newton_module.Residual.residual = recorded_residual
    turn = {"case": "case", "none": None}.get(args.update_turn)
    update_turn = float(args.update_turn) if turn is None and args.update_turn != "none" else turn
    print(f"load before (1, 5, 15 min): {np.round(os.getloadavg(), 2).tolist()}")
    for name in args.cases.split(","):
        stall, first_turn = CASE_RULES[name]
        results = {}
        for side in args.sides.split(","):
            TRACE.update(rows=[], held=0, print=args.trace, events=0)
            use(side if side != "straight" else "traced")
            cpu = time.process_time()
            try:
                curved = None if side == "straight" else True
                result = solve_case(name, args.resolution, stall, first_turn, update_turn, curved)
            except Exception as failure:  # a failed solve is a figure too
                print(f"{name} {side}: failed: {str(failure)[:200]}", flush=True)
                continue
            finally:
                use("straight")
            cpu = time.process_time() - cpu
            info, rows = result.info, np.array(TRACE["rows"]).reshape(-1, 2)
            print(
                f"{name} {args.resolution} {side:10s}: {info['iterations_per_increment']}, "
                f"{result.steps} + {info['iterations_cut']} cut, "
                f"{info['evaluations']['tangent']} tangents, {info['curved_steps']} curved, "
                f"held points {TRACE['held']}, event steps {TRACE['events']}; "
                f"{int((rows[:, 0] > 0).sum())} of {len(rows)} "
                f"updates crossed ({int(rows[:, 0].sum())} points); {cpu:.1f} s CPU, load "
                f"{np.round(os.getloadavg(), 2).tolist()}",
                flush=True,
            )
            results[side] = result
        if "straight" in results:
            for side, result in results.items():
                moved = np.abs(result.positions - results["straight"].positions).max()
                print(f"  {side}: final positions within {moved:.3g} mm of the straight steps'")


if __name__ == "__main__":
    main()
