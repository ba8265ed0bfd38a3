"""What a quasi-static solver may call converged: a state the model is valid in
(docs/theory.md §6.4d).

Why. A balanced residual is not enough. The fibrous tension of a linear law, b K ln(lambda) /
lambda per fibre, peaks at lambda = e and falls to zero beyond (3.2e7 N at a stretch of 2,
5e-13 N at 1e22 on a 100 mm sheet): a sheet flown to infinity is a zero-force "equilibrium"
that passes the ratio test. Dynamic relaxation found such states when a prescribed
displacement went in one jump (a bias extension pulled 30 mm at once: nodes at 1e16 mm,
reported converged with a reaction of 7e-6 N against 41 N), and states with cells folded onto
their neighbours (a picture frame: 2 of 32 triangles flipped, the force 15 % off). So an
accepted state must also be one where

- every position and director is finite, and the nodes of the cells span at most SPREAD
  times the model's size plus its prescribed motion (a larger spread needs strains of order
  ln(SPREAD) = 2.3, past any law's range);
- no triangle of a block has lost its area (below MIN_AREA of its reference area: a fabric
  sheared to 89.9 deg keeps cos(89.9 deg) = 1.7e-3) or turned over against its
  neighbours (its normal opposite to the area-weighted normal of the block at each of its
  corners) or against its directors (at or past 90 deg from them at every corner: the
  measure of ``ElementBlock.inverted_cells`` of the Mindlin shell, which Static refuses
  too), and no cell is turned inside out by its block's own measure;
- no fibre strain ln(lambda) of a block that has them (``fibre_strains``) lies past its
  law's own range (``fibre_strain_range``): where the force per unit reference width T / lambda
  stops rising with the stretch, lambda = e for a linear law (a hundred times the breaking
  strain of any reinforcement fibre), never for a law that stiffens fast enough
  (materials/tension_peak.py); nothing in compression for a law whose force does not fall
  there (a tension-only law carries none).
"""

from __future__ import annotations

import numpy as np

from femcore.model import CompiledModel
from femcore.state import State

__all__ = ["MIN_AREA", "SPREAD", "invalid_state"]

#: The least area of a triangle over its reference area in an accepted state.
MIN_AREA = 1e-3
#: The largest spread of the nodes over the model's size plus its prescribed motion.
SPREAD = 10.0
#: The most cells or nodes a message names.
_NAMED = 5


def invalid_state(model: CompiledModel, state: State, load_factor: float) -> str | None:
    """Why ``state`` is no state the model is valid in, or None where it is one.

    Parameters
    ----------
    model : CompiledModel
    state : State
        Positions (n, 3) mm and directors (n, 3) of a state a solver would accept.
    load_factor : float
        Its load factor: the prescribed motion the spread allows for.

    Returns
    -------
    str or None
        The first failed check with the cells or nodes at fault (a clause that completes
        "the state is not valid: ..."), or None.
    """
    positions, directors = state.positions, state.directors
    if not (np.isfinite(positions).all() and np.isfinite(directors).all()):
        bad = np.flatnonzero(~np.isfinite(positions).all(axis=1))
        return f"non-finite positions or directors (nodes {_names(bad)})"
    used = _used_nodes(model)
    if used.size:
        spread = float(np.ptp(positions[used], axis=0).max())
        reference = float(np.ptp(model.reference_positions[used], axis=0).max())
        moved = model.prescribed_displacement(load_factor, quasi_static=True)
        allowed = SPREAD * (reference + 2.0 * float(np.abs(moved).max(initial=0.0)))
        if not spread <= allowed:
            far = used[
                np.argsort(-np.abs(positions[used] - model.reference_positions[used]).max(axis=1))
            ]
            return (
                f"the nodes span {spread:.3g} mm, more than {SPREAD:g} times the model's size "
                f"plus its prescribed motion ({allowed:.3g} mm): nodes {_names(far)} flew off"
            )
    for entry, block in zip(model.block_entries, model.blocks):
        if block.cell_type != "triangle":
            continue
        shell = entry.element.defines_directors
        reason = _bad_triangles(model, block, positions, directors if shell else None)
        if reason is not None:
            return reason
    inverted = model.inverted_cells(state)
    if inverted.size:
        return f"cells {_names(inverted)} are turned inside out"
    for block in model.blocks:
        if block.has_fibre_strains and (reason := _past_the_law(block, state)):
            return reason
    return None


def _past_the_law(block, state: State) -> str | None:
    """The cells of ``block`` with a fibre strain past its law's range (the block's
    ``fibre_strain_range``), as a clause naming the worst strain and its bound, or None."""
    strains = block.fibre_strains(state)
    # (p,) bounds per column, or (m, p) per cell and column
    lower, upper = (np.broadcast_to(bound, strains.shape) for bound in block.fibre_strain_range())
    # how far past its bound each strain lies (a NaN strain is the farthest)
    beyond = np.nan_to_num(np.maximum(strains - upper, lower - strains), nan=np.inf)
    over = np.flatnonzero((beyond > 0.0).any(axis=1))
    if not over.size:
        return None
    cell, column = np.unravel_index(int(np.argmax(beyond)), beyond.shape)
    strain = float(strains[cell, column])
    bound = float(upper[cell, column] if strain > 0.0 else lower[cell, column])
    digits = _telling_digits(strain, bound)
    how = "stretches" if strain > 0.0 else "shortens"
    return (
        f"fibre strains ln(lambda) up to {strain:.{digits}g} (a stretch lambda = "
        f"{np.exp(strain):.{digits}g}) in cells {_names(block.cell_ids[over])}, past "
        f"{bound:.{digits}g} (lambda = {np.exp(bound):.{digits}g}), where their tension "
        f"law's force per unit reference width T / lambda peaks and then falls as the fibre {how}"
    )


def _telling_digits(value: float, bound: float) -> int:
    """The fewest significant digits (at least 4) that print ``value`` and ``bound`` apart:
    a strain just past its bound read "up to 1 ... past 1" at three."""
    for digits in range(4, 18):
        if f"{value:.{digits}g}" != f"{bound:.{digits}g}":
            return digits
    return 17


def _used_nodes(model: CompiledModel) -> np.ndarray:
    """The nodes of the blocks' cells, ascending (a rigid tool's node is not the body's)."""
    if not model.blocks:
        return np.zeros(0, dtype=np.int64)
    return np.unique(np.concatenate([block.connectivity.ravel() for block in model.blocks]))


def _bad_triangles(
    model: CompiledModel, block, positions: np.ndarray, directors: np.ndarray | None
) -> str | None:
    """The triangles of ``block`` that lost their area or turned over, as a clause, or None;
    ``directors`` (n, 3) those of a shell block, None for a block whose cells define none."""
    cells = block.connectivity
    corners = positions[cells]
    normal = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    start = model.reference_positions[cells]
    area0 = np.linalg.norm(np.cross(start[:, 1] - start[:, 0], start[:, 2] - start[:, 0]), axis=1)
    area = np.linalg.norm(normal, axis=1)
    flat = np.flatnonzero(~(area >= MIN_AREA * area0))
    if flat.size:
        return (
            f"cells {_names(block.cell_ids[flat])} lost their area (below {MIN_AREA:g} of "
            "their reference area)"
        )
    # The area-weighted normal of the block at each node: a cell whose normal opposes it at
    # all three corners is folded back onto its neighbours, not bent.
    sums = np.zeros_like(positions)
    np.add.at(sums, cells, normal[:, None, :])
    facing = np.einsum("mk,mjk->mj", normal, sums[cells])
    over = np.flatnonzero((facing < 0.0).all(axis=1))
    if over.size:
        return f"cells {_names(block.cell_ids[over])} turned over onto their neighbours"
    if directors is None:
        return None
    # A shell cell whose normal has turned away from the directors at all its corners (the
    # through-thickness fibres) is inside out, whatever its neighbours do (a picture frame's
    # corner cell pulled over its neighbour, its directors still up).
    along = np.einsum("mk,mjk->mj", normal, directors[cells])
    inside_out = np.flatnonzero((along <= 0.0).all(axis=1))
    if inside_out.size:
        return (
            f"cells {_names(block.cell_ids[inside_out])} are turned inside out (their normal "
            "at or past 90 deg from the directors at every corner)"
        )
    return None


def _names(ids: np.ndarray) -> str:
    shown = ", ".join(str(int(i)) for i in ids[:_NAMED])
    return shown + (f" and {ids.size - _NAMED} more" if ids.size > _NAMED else "")
