"""The curved face's point and tangents (elements/ply_surface.py ``surface_point``) in one
compiled pass, the same bits as its numpy reference ``surface_point_numpy``.

Why. ``surface_point`` is called at every Gauss-Newton step of ``project`` over every listed
patch of every point (2304 rows a call in the hemisphere-plies case's measure of the plies'
order, hemisphere_plies_gaps.py: eight calls a frame, a hundred frames a run); numpy's
three-operand einsums are its cost (measured: 1.8 of the measure's 3.0 s of profiled CPU a
run).

The same bits. Each sum is added from its first term, ``(t_0 + t_1) + t_2``, each term's
factors multiplied from the left, the rest as numpy evaluates the reference's expressions
(``(y - (0.5 e) n) - 0.5 S``), no product fused with a sum (numba's default). The reference
spells its sums out for that reason: numpy's einsum, which it used before, fuses products and
sums in its contiguous loops on CPUs that can (measured on this machine: e = (q - y_k) . n_k
of 215 of 2304 rows 1e-18 mm apart), so that its bits depend on the machine. The case's
figures with the reference against einsum: the same to the bit on the fibrous runs, two of
each Mindlin run's least gaps 2e-15 to 4.2e-15 mm apart (rounding).
tests/test_ply_surface_kernels.py holds the pass to the bit against the reference on 1 and 2
threads.
"""

from __future__ import annotations

import numpy as np

from elements.kernel_inputs import read_only
from femcore.jit import jit, prange

__all__ = ["surface_point"]


def _surface_point(y, n, lam, point, tangents, q, e, dots, partial):
    """Into point (P, 3), tangents (P, 2, 3), q (P, 3) and e (P, 3): ``surface_point_numpy``'s
    arrays from corners y (P, 3, 3), unit normals n (P, 3, 3), mm, and barycentric
    coordinates lam (P, 3); each sum from its first term, as the reference adds them. dots
    and partial (P, 3, 3): scratch, a row's own (an allocation a row cost a third of the
    pass)."""
    for p in prange(y.shape[0]):
        for i in range(3):
            total = lam[p, 0] * y[p, 0, i]
            for k in range(1, 3):
                total = total + lam[p, k] * y[p, k, i]
            q[p, i] = total
        for k in range(3):
            total = (q[p, 0] - y[p, k, 0]) * n[p, k, 0]
            for i in range(1, 3):
                total = total + (q[p, i] - y[p, k, i]) * n[p, k, i]
            e[p, k] = total
        for i in range(3):
            total = (lam[p, 0] * e[p, 0]) * n[p, 0, i]
            for k in range(1, 3):
                total = total + (lam[p, k] * e[p, k]) * n[p, k, i]
            point[p, i] = q[p, i] - 0.5 * total
        for a in range(3):  # dots[p, a, k]: y_a . n_k
            for k in range(3):
                total = y[p, a, 0] * n[p, k, 0]
                for j in range(1, 3):
                    total = total + y[p, a, j] * n[p, k, j]
                dots[p, a, k] = total
        for a in range(3):
            for i in range(3):
                total = (lam[p, 0] * dots[p, a, 0]) * n[p, 0, i]
                for k in range(1, 3):
                    total = total + (lam[p, k] * dots[p, a, k]) * n[p, k, i]
                partial[p, a, i] = (y[p, a, i] - (0.5 * e[p, a]) * n[p, a, i]) - 0.5 * total
        for a in range(2):
            for i in range(3):
                tangents[p, a, i] = partial[p, a, i] - partial[p, 2, i]


_surface_point_compiled = jit(_surface_point)


def surface_point(y: np.ndarray, n: np.ndarray, lam: np.ndarray):
    """``surface_point_numpy`` (elements/ply_surface.py) compiled: the surface's point (P, 3),
    its tangents (P, 2, 3), q (P, 3) and e (P, 3) at barycentric coordinates ``lam`` (P, 3)
    over corners ``y`` and unit normals ``n`` (P, 3, 3), mm. Raises ValueError for other
    shapes (the pass would read and write past its arrays)."""
    count = len(lam) if np.ndim(lam) else -1
    if np.shape(y) != (count, 3, 3) or np.shape(n) != (count, 3, 3) or np.shape(lam) != (count, 3):
        raise ValueError(
            f"corners {np.shape(y)}, normals {np.shape(n)} and barycentric coordinates "
            f"{np.shape(lam)} given: expected (P, 3, 3), (P, 3, 3) and (P, 3) with one P"
        )
    point, tangents = np.empty((count, 3)), np.empty((count, 2, 3))
    q, e = np.empty((count, 3)), np.empty((count, 3))
    dots, partial = np.empty((count, 3, 3)), np.empty((count, 3, 3))
    _surface_point_compiled(
        read_only(y), read_only(n), read_only(lam), point, tangents, q, e, dots, partial
    )
    return point, tangents, q, e
