"""The pin-jointed net on the sphere (validation.references.drape.fishnet_on_sphere), marched
one anti-diagonal of its four quadrants at a time, beside a reference pass that marches it
crossing by crossing as it was written before (kept here): the CPU time of each and whether
they give the same bits.

The report builds these nets once per case that needs them: hemisphere-forming one on the
die's sphere, hemisphere-plies one per ply, 159 x 159 crossings each (1-mm segments).

Measured (one thread, CPU time, best of 3, 2 cores shared with other jobs, load 6.3-6.4):
the die's net (R 50.75 mm, 1-mm cell, 79 cells each way) 0.588 -> 0.023 s; a ply's (R 50.45
mm) 0.588 -> 0.023 s, at 45 deg 0.595 -> 0.020 s; the tests' (R 50, 2-mm cell, 30 cells)
0.111 -> 0.006 s. The same bits in every crossing (NaN where the net leaves the hemisphere
alike), so the same shear angles.

Run: python benchmarks/drape_net.py [--repeats 3]
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from validation.references import drape  # noqa: E402


def _third_crossing(a, b, d, radius, reach):
    """The reference's crossing: the point at distance cell from a and b on the sphere, away
    from d; None when there is none or a neighbour is missing."""
    if not (np.isfinite(a).all() and np.isfinite(b).all() and np.isfinite(d).all()):
        return None
    alpha = reach / (radius**2 + a @ b)
    base = alpha * (a + b)
    normal = np.cross(a, b)
    rest = radius**2 - base @ base
    if rest < 0 or normal @ normal == 0:
        return None
    gamma = np.sqrt(rest / (normal @ normal))
    first, second = base + gamma * normal, base - gamma * normal
    return first if np.linalg.norm(first - d) > np.linalg.norm(second - d) else second


def reference_net(radius: float, cell: float, count: int, angle: float = 0.0) -> np.ndarray:
    """The reference pass: the net's crossings (2 count + 1, 2 count + 1, 3), one by one."""
    n = int(count)
    size = 2 * n + 1
    points = np.full((size, size, 3), np.nan)
    step = 2.0 * np.arcsin(0.5 * cell / radius)
    k = np.arange(-n, n + 1)
    turned = k * step
    on = np.abs(turned) <= 0.5 * np.pi
    turn = np.radians(float(angle))
    warp = np.array([np.cos(turn), np.sin(turn), 0.0])
    weft = np.array([-np.sin(turn), np.cos(turn), 0.0])
    pole = np.array([0.0, 0.0, 1.0])
    along = np.sin(turned)[:, None]
    points[:, n][on] = (radius * (along * warp + np.cos(turned)[:, None] * pole))[on]
    points[n, :][on] = (radius * (along * weft + np.cos(turned)[:, None] * pole))[on]
    reach = radius**2 - 0.5 * cell**2
    for si in (-1, 1):
        for sj in (-1, 1):
            for i in range(1, n + 1):
                for j in range(1, n + 1):
                    a = points[n + si * i - si, n + sj * j]
                    b = points[n + si * i, n + sj * j - sj]
                    d = points[n + si * i - si, n + sj * j - sj]
                    p = _third_crossing(a, b, d, radius, reach)
                    if p is not None and p[2] >= 0.0:
                        points[n + si * i, n + sj * j] = p
    return points


def _best(function, arguments: tuple, repeats: int) -> tuple[float, object]:
    best, value = float("inf"), None
    for _ in range(repeats):
        start = time.process_time()
        value = function(*arguments)
        best = min(best, time.process_time() - start)
    return best, value


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    print("load before " + ", ".join(f"{x:.2f}" for x in os.getloadavg()))
    for radius, cell, count, angle in ((50.75, 1.0, 79, 0.0), (50.45, 1.0, 79, 0.0),
                                       (50.45, 1.0, 79, 45.0), (50.0, 2.0, 30, 0.0)):  # fmt: skip
        given = (radius, cell, count, angle)
        old, reference = _best(reference_net, given, args.repeats)
        new, net = _best(drape.fishnet_on_sphere, given, args.repeats)
        same = np.array_equal(reference, net["points"], equal_nan=True)  # type: ignore[index]
        print(f"R {radius} mm, cell {cell} mm, {count} cells, {angle:g} deg: reference "
              f"{old:.3f} s, now {new:.3f} s CPU (best of {args.repeats}); "
              f"{'the same bits' if same else 'DIFFERENT'}")  # fmt: skip
    print("load after " + ", ".join(f"{x:.2f}" for x in os.getloadavg()))


if __name__ == "__main__":
    main()
