"""The compression the fibrous tangent keeps far from equilibrium (docs/theory.md §6.5).

Newton's iterates far from equilibrium take the tension's stress terms at each fibre's strain
raised to a floor (tangent.py ``membrane_hessian``, ``compression_free``): a step's remainder
compresses fibres whose stiffness is thousands of times the bending's, and the geometric
stiffness of that compression makes the tangent indefinite. The floor is the compression of
the last converged state (``real_compression``; not the increment's start, which a predictor
extrapolates: a straight update shortens turning fibres), the strain raised to at least
min(eps_converged, 0): compression a converged state carries is real, not a step's remainder.
A column under a compressive load carries it in its fibres; with the floor at zero its tangent
lost the geometric softening that leads to buckling, and Newton stopped short of the critical
load (the imperfect fibrous strip at 1.5 P_cr under 10 load steps stopped at a load factor
of 0.6625, P_cr at 2/3: tests/test_compression_free_tangent.py).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from femcore.state import State

__all__ = ["real_compression", "strain_floors"]


def real_compression(block, real: State) -> tuple[np.ndarray, np.ndarray]:
    """The floors (warp, weft) (m, L) of the strains in the compression-free tangent's stress
    terms: min(eps, 0) of each level's fibres at ``real``, the state whose compression is
    real (the last converged state). Kept on the block for that state (every iterate of an
    increment asks for the same one)."""
    kept = block.__dict__.get("_compression_floor")
    if (
        kept is not None
        and kept[0] is real
        and np.array_equal(kept[1], real.positions)
        and np.array_equal(kept[2], real.directors)
    ):  # the same state, not changed in place since (a cheap guard: a State is mutable)
        return kept[3]
    levels = block.zeta.size
    strain = block.fibre_strains(real)
    floors = (
        np.minimum(strain[:, :levels], 0.0),
        np.minimum(strain[:, levels : 2 * levels], 0.0),
    )
    block.__dict__["_compression_floor"] = (
        real,
        real.positions.copy(),
        real.directors.copy(),
        floors,
    )
    return floors


def strain_floors(
    floors: tuple[np.ndarray, np.ndarray] | None,
    cells: int,
    levels: int,
    taken: slice | np.ndarray = slice(None),
) -> tuple[np.ndarray, np.ndarray]:
    """(warp, weft) floors (cells, levels) of the ``taken`` cells of ``floors`` (the block's),
    contiguous; None: zero (every fibre's compression left out)."""
    if floors is None:
        zero = np.zeros((cells, levels))
        return zero, zero
    warp = np.ascontiguousarray(floors[0][taken], dtype=float)
    weft = np.ascontiguousarray(floors[1][taken], dtype=float)
    if warp.shape != (cells, levels) or weft.shape != (cells, levels):
        raise ValueError(
            f"strain floors of shape {warp.shape} and {weft.shape} for {cells} cells of "
            f"{levels} levels: (cells, levels) expected"
        )
    return warp, weft
