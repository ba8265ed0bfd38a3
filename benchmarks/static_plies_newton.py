"""Where the Static ply cases' Newton iterations go, increment by increment: each attempt's
residual ratios, the watchdog's step lengths and its trial force passes and energies, the cut
attempts and why they failed, and what the ply contact's points did between the iterates (on
or off the ramp -delta < g < 0 of the smoothed penalty, deeper, in the fade past the outline,
the facing triangle switched, the sign of the gap flipped), docs/theory.md §6.5 and §9.3a.

    python benchmarks/static_plies_newton.py [--case bai|deck|sag] [--resolution coarse]

One thread, CPU time (``time.process_time``); the machine's load is printed.
"""

from __future__ import annotations

import argparse
import functools
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from anywhere, no install

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

import solvers.newton as newton_module  # noqa: E402
import solvers.static as static_module  # noqa: E402
from elements.ply_block import PlyContactBlock  # noqa: E402
from solvers import Static  # noqa: E402

RECORD: dict = {}


def _ply_states(run, state):
    """Per ply-contact block: (touching, on the ramp, faded, triangle, gap) at ``state``."""
    out = []
    for block in run.model.interactions:
        if not isinstance(block, PlyContactBlock):
            continue
        facing = block.facing(state)
        gap = np.asarray(facing.gap)
        touching = np.asarray(facing.touching)
        ramp = touching & (gap > -block.smoothing)
        fade = np.ones_like(gap) if facing.fade is None else np.asarray(facing.fade)
        out.append((touching.copy(), ramp, touching & (fade < 1.0), facing.triangle.copy(), gap))
    return out


def _changes(before, after) -> dict:
    """Counts of the points whose contact state changed between two iterates."""
    keys = ("in", "out", "ramp_in", "ramp_out", "fade_changed", "triangle", "sign")
    total = dict.fromkeys(keys, 0)
    for (t0, r0, f0, tri0, g0), (t1, r1, f1, tri1, g1) in zip(before, after):
        total["in"] += int(np.sum(~t0 & t1))
        total["out"] += int(np.sum(t0 & ~t1))
        total["ramp_in"] += int(np.sum(~r0 & r1))
        total["ramp_out"] += int(np.sum(r0 & ~r1))
        total["fade_changed"] += int(np.sum(f0 != f1))
        total["triangle"] += int(np.sum(tri0 != tri1))
        total["sign"] += int(np.sum((np.sign(g0) != np.sign(g1)) & (np.abs(g0 - g1) > 1e-3)))
    return total


def instrument() -> None:
    """Wrap the solver's pieces to record (module docstring); RECORD holds the attempts."""
    RECORD.update(attempts=[], iterations=[])
    plain_newton = static_module.newton

    def newton(run, state, load_factor, max_iterations=None):
        entry = {"load": load_factor, "iterations": [], "failed": None, "cpu": time.process_time()}
        RECORD["attempts"].append(entry)
        RECORD["current"] = entry
        RECORD["last_ply"] = None
        try:
            out = plain_newton(run, state, load_factor, max_iterations)
        except newton_module.IncrementFailed as failure:
            entry["failed"] = str(failure)
            entry["history"] = failure.history
            entry["cpu"] = time.process_time() - entry["cpu"]
            raise
        entry["history"] = out[3]
        entry["cpu"] = time.process_time() - entry["cpu"]
        return out

    static_module.newton = newton

    plain_tangent = static_module.StaticRun.tangent

    def tangent(self, state, frames, compression_free=False):
        plies = _ply_states(self, state)
        touching = sum(int(p[0].sum()) for p in plies)
        ramp = sum(int(p[1].sum()) for p in plies)
        faded = sum(int(p[2].sum()) for p in plies)
        row = {"touching": touching, "ramp": ramp, "faded": faded, "scale": None, "trials": 0}
        if RECORD.get("last_ply") is not None:
            row.update(_changes(RECORD["last_ply"], plies))
        RECORD["last_ply"] = plies
        RECORD["current"]["iterations"].append(row)
        return plain_tangent(self, state, frames, compression_free)

    static_module.StaticRun.tangent = tangent

    plain_step = newton_module.Watchdog.step

    def step(self, *args, **kwargs):
        before = self.run.counts["residual"]
        energies = self.run.counts["energy"]
        out = plain_step(self, *args, **kwargs)
        rows = RECORD["current"]["iterations"]
        if rows:
            rows[-1]["scale"] = out[0]
            rows[-1]["trials"] = self.run.counts["residual"] - before
            rows[-1]["energies"] = self.run.counts["energy"] - energies
        return out

    newton_module.Watchdog.step = step


def solve_case(name: str, resolution: str, stall: int | None):
    """Solve the Static plies of case ``name`` at ``resolution`` with
    ``Static(stall_iterations=stall)``; the result."""
    if name == "bai":
        from fibreshell.plies import plies_solver, ply_stack, stack_model
        from validation.cases import plies_bai_5_1 as case_module
        from validation.ground_truth import _case

        solver = {
            **case_module.PLIES_SOLVER,
            "increments": case_module.PLIES_INCREMENTS[resolution],
            "stall_iterations": stall,
        }
        if stall is None:
            del solver["stall_iterations"]
        case = _case(case_module.FILE, case_module.CELLS[resolution], {"solver": solver})
        stack = ply_stack(case, case_module.PLIES[resolution])
        model = stack_model(case, stack).compile()
        return plies_solver(case, progress=False).solve(model)
    from validation.cases import plies_deck_of_cards as deck

    deck.Static = functools.partial(Static, stall_iterations=stall)  # type: ignore[attr-defined]
    if name == "deck":
        return deck.bend(deck.COUNTS[resolution][-1], deck.MIDDLE).result
    if name == "sag":
        return deck.sag(deck.SAG_COUNTS[resolution][0]).result
    raise ValueError(f"case {name!r}: expected bai, deck or sag")


def report(result) -> None:
    """Print the attempts, increment by increment."""
    for entry in RECORD["attempts"]:
        status = "CUT: " + entry["failed"] if entry["failed"] else "converged"
        its = entry["iterations"]
        print(
            f"load {entry['load']:.4f}: {len(entry['history']) - 1:3d} iterations, "
            f"{entry['cpu']:.2f} s, {status}"
        )
        history = entry["history"]
        print("   ratios " + " ".join(f"{r:.1e}" for r in history))
        scales = [row["scale"] for row in its if row["scale"] is not None]
        print("   scales " + " ".join(f"{s:.3g}" for s in scales))
        print("   trials " + " ".join(str(row["trials"]) for row in its))
        print("   touching/ramp/faded " + " ".join(
            f"{row['touching']}/{row['ramp']}/{row['faded']}" for row in its))  # fmt: skip
        keys = ("in", "out", "ramp_in", "ramp_out", "triangle", "sign")
        print("   changes (in,out,ramp in,ramp out,triangle,sign) " + " ".join(
            ",".join(str(row.get(k, "-")) for k in keys) for row in its[1:]))  # fmt: skip
    print(f"iterations per increment {result.info['iterations_per_increment']}")
    print(
        f"converged iterations {result.steps}, cut {result.info['iterations_cut']}, cuts "
        f"{result.info['cuts']}; evaluations {result.info['evaluations']}"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--case", default="bai", help="bai, deck or sag")
    parser.add_argument("--resolution", default="coarse")
    parser.add_argument("--stall", type=int, default=25, help="stall_iterations of the new run")
    parser.add_argument("--detail", action="store_true", help="every attempt, before and after")
    args = parser.parse_args()
    print(f"load before (1, 5, 15 min): {np.round(os.getloadavg(), 2).tolist()}")
    instrument()
    results = {}
    for stall in (None, args.stall):
        RECORD.update(attempts=[])
        cpu = time.process_time()
        result = solve_case(args.case, args.resolution, stall)
        cpu = time.process_time() - cpu
        results[stall] = result
        print(f"--- {args.case} {args.resolution}, stall_iterations={stall}: {cpu:.1f} s CPU")
        if args.detail:
            report(result)
        else:
            print(f"iterations per increment {result.info['iterations_per_increment']}")
            print(
                f"converged iterations {result.steps}, cut {result.info['iterations_cut']}, "
                f"cuts {result.info['cuts']}; evaluations {result.info['evaluations']}"
            )
        print(f"load (1, 5, 15 min): {np.round(os.getloadavg(), 2).tolist()}", flush=True)
    before, after = results[None], results[args.stall]
    moved = np.abs(after.positions - before.positions).max()
    turned = np.abs(after.directors - before.directors).max()
    print(f"final positions within {moved:.3g} mm, directors within {turned:.3g}")


if __name__ == "__main__":
    main()
