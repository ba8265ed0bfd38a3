"""The ply contact's smoothed penalty law compiled: elements/ply_projection.py's
``penalty_law`` (docs/theory.md, the ply contact section) in one pass over the points, where
numpy made some twenty passes over arrays of a few hundred points (the friction's stick
spring asks for it four times an explicit step: about 30 us a call, 8 with the pass;
benchmarks/forming_step_overhead.py).

The same IEEE operations in the same order as numpy's expressions (no fastmath, no fused
multiply-add), and the two numpy results whose bits the compiled code would not reproduce
are taken from numpy: ``np.minimum(gap, 0)`` (its signed zeros) and the cube ``g**3``
(numpy's vectorised ``power`` differs from libm's ``pow`` in the last bit of some cubes;
``ramp_cubes``: only where the ramp reads it), so the same numbers to the last bit
(tests/test_ply_penalty.py). ``ply_projection.COMPILED = False`` keeps numpy's.
"""

from __future__ import annotations

import numpy as np

from femcore.jit import jit_lanes, prange

__all__ = ["ramp_cubes", "smoothed_law"]


def _smoothed(g, cube, stiffness, delta, delta_squared, energy, force, curvature):
    """W, dW/dg and d2W/dg2 of each point (t,) into ``energy``, ``force``, ``curvature``:
    from g = min(gap, 0) (t,) mm, its cube (t,), the penalties (t,) N/mm, the ramp ``delta``
    mm and ``delta_squared`` (Python's delta**2), as ``penalty_law``'s numpy writes them."""
    for i in prange(g.shape[0]):
        k = stiffness[i]
        gi = g[i]
        if gi <= -delta:
            shifted = gi + 0.5 * delta
            energy[i] = (0.5 * k) * (shifted * shifted) + (k * delta_squared) / 24.0
            force[i] = k * shifted
            curvature[i] = k
        else:
            energy[i] = (-k * cube[i]) / (6.0 * delta)
            force[i] = (-k * (gi * gi)) / (2.0 * delta)
            curvature[i] = (-k * gi) / delta


_smoothed_compiled = jit_lanes(_smoothed)


def ramp_cubes(g: np.ndarray, smoothing: float) -> np.ndarray:
    """numpy's g**3 (t,) mm^3 of g = min(gap, 0) (t,) mm where the smoothed law's ramp
    energy reads it (g > -``smoothing``, NaN included; zero elsewhere, where the law does
    not read it, and everywhere without smoothing). numpy's power of a negative base took
    about 170 ns a point (42 us on the 245 touching points of the two-ply hemisphere's
    upper pass, one thread), and there nearly every point lies past the ramp (g <=
    -delta); numpy's power gives each point the same bits whichever others it is given."""
    cube = np.zeros(len(g))
    if smoothing > 0.0:
        ramp = np.flatnonzero(~(g <= -smoothing))
        cube[ramp] = g[ramp] ** 3
    return cube


def smoothed_law(
    gap: np.ndarray, stiffness: np.ndarray, smoothing: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``ply_projection.penalty_law`` for ``smoothing`` delta > 0 (mm): (energy (t,) N mm,
    force (t,) N, stiffness (t,) N/mm) of the points of gaps ``gap`` (t,) mm and penalties
    ``stiffness`` (t,) N/mm, the same bits."""
    g = np.minimum(gap, 0.0)
    cube = ramp_cubes(g, smoothing)
    count = len(g)
    energy, force, curvature = np.empty(count), np.empty(count), np.empty(count)
    _smoothed_compiled(
        np.ascontiguousarray(g, dtype=float),
        np.ascontiguousarray(cube, dtype=float),
        np.ascontiguousarray(stiffness, dtype=float),
        float(smoothing),
        float(smoothing**2),
        energy,
        force,
        curvature,
    )
    return energy, force, curvature
