"""The ply facing search's epoch share (elements/ply_search.py ``EPOCH_SHARE``) on the report's
two-ply hemisphere: whole runs at each share given, alternating, in one process, one thread,
CPU (``time.process_time``), the machine's load printed beside each run.

Each run is hemisphere-plies' model and solver (validation/studies/hemisphere_plies_setup.py:
8 cells, 20 N, the history every record, 100 frames); printed per run: its CPU, steps, ms a
step, the searches of each of its two ply contacts (all lists made again, ``renew``, and some
points' lists made again, ``refresh``) and a hash of the final positions. The share only sets
when the kept lists are made again, never what they answer (the module docstring's bound
holds for any share below 1/2): every share must give the same hash, which the script checks.

    python benchmarks/ply_epoch.py --kinematics mindlin --shares 0.125 0.25 --repeats 2

Measured (one thread, 2 cores shared with other jobs; best of 2 unless said), ms a step:

* Mindlin [0/90], 13939 steps (load 4.3-6.6, one round): share 1/8 1.681 (2110 epochs, no
  refresh), 3/16 1.564 (1398, 0), 1/4 1.546 (1031 epochs, 4 refreshes), 5/16 1.606 (811
  epochs, 1545 refreshes), 1/2 2.275 (every point past half its bound at every epoch's
  end: 9932 searches); a skin of 0.15 at 1/4 1.607 (669 epochs: longer lists, a dearer
  choice at every step). The same positions to the bit in every run.
* Mindlin [0/45], 11868 steps (load 5.1-5.2, one round): share 1/8 1.876 (2010 epochs), 1/4
  1.746 (1008 epochs, 45 refreshes); the same positions.
* fibrous [0/90], 6865 steps (load 6.4-7.8): share 1/8 1.764-1.914 (411 epochs), 1/4
  1.832 (204): within the load's noise; its plies move apart less (no wrinkles).

With M the grown corners' largest move (elements/ply_search.py ``grown_moves``), not (1 + 2
sum reach) times the corners' (main d551120): Mindlin [0/90], 8429 steps, share 1/4 1147 ->
788 epochs (5 -> 21 refreshes), the same final positions (41a89a1e715d29ae in both trees).
Which triangle ends an epoch there (the first 40 % of the run, 712 epochs): mostly an
outline triangle (reach on one or two edges, L = 2 or 3) of the flange's corners, its
centroid 2-4 skins from the nearest point, while the median triangle has moved 0.03-0.13
skin. The shares again with the tighter M (one round, load 4.7-4.9): 3/16 1.581 ms a step
(1054 epochs, 1 refresh), 1/4 1.503 (788, 21), 5/16 1.684 (625, 1373 refreshes): 1/4 still.
"""

from __future__ import annotations

import argparse
import hashlib
import os
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(HERE))  # run from anywhere, no install


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--kinematics", default="mindlin", choices=("fibrous", "mindlin"))
    parser.add_argument("--layup", default="0/90", choices=("0/90", "0/45"))
    parser.add_argument("--shares", type=float, nargs="+", default=[0.125, 0.25])
    parser.add_argument("--repeats", type=int, default=2)
    arguments = parser.parse_args()

    from elements import ply_search
    from validation.studies import hemisphere_plies_setup as setup
    from validation.studies.hemisphere_plies_run import case_solver

    counts = {"renew": 0, "refresh": 0}
    search = ply_search.FacingSearch
    renew, refresh = search._renew, search._refresh

    def counted_renew(self, *args):
        counts["renew"] += 1
        return renew(self, *args)

    def counted_refresh(self, *args):
        counts["refresh"] += 1
        return refresh(self, *args)

    search._renew, search._refresh = counted_renew, counted_refresh  # type: ignore[method-assign]
    layup = setup.LAYUPS[arguments.layup]

    def run(share: float) -> tuple[float, int, str]:
        ply_search.EPOCH_SHARE = share
        counts.update(renew=0, refresh=0)
        _, model = setup.model(8, layup, arguments.kinematics, 20.0)
        solver = case_solver(
            arguments.layup, arguments.kinematics, history=f"/tmp/ply_epoch_{os.getpid()}.csv"
        )
        compiled = model.compile()
        start = time.process_time()
        result = solver.solve(compiled)
        cpu = time.process_time() - start
        return cpu, result.steps, hashlib.sha1(result.positions.tobytes()).hexdigest()[:16]

    # compiled (or read from numba's cache) before the timing: a short run of the same model
    _, model = setup.model(8, layup, arguments.kinematics, 20.0)
    case_solver(
        arguments.layup, arguments.kinematics, 1 / 200, output_interval=None, kinetic_bound=None
    ).solve(model.compile())
    best: dict[float, float] = {}
    hashes = set()
    for _ in range(arguments.repeats):
        for share in arguments.shares:
            cpu, steps, digest = run(share)
            hashes.add(digest)
            best[share] = min(best.get(share, float("inf")), cpu / steps)
            print(
                f"{arguments.kinematics} [{arguments.layup}] share {share}: {cpu:.2f} s CPU, "
                f"{steps} steps, {cpu / steps * 1e3:.3f} ms a step, {counts['renew']} epochs, "
                f"{counts['refresh']} refreshes, positions {digest} "
                f"(load {os.getloadavg()[0]:.1f})",
                flush=True,
            )
    for share, each in best.items():
        print(f"share {share}: best {each * 1e3:.3f} ms a step")
    print("the same final positions in every run" if len(hashes) == 1 else "POSITIONS DIFFER")
    Path(f"/tmp/ply_epoch_{os.getpid()}.csv").unlink(missing_ok=True)


if __name__ == "__main__":
    main()
