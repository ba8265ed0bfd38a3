"""The fold angles followed through a flat fold (docs/theory.md §4.1, "The fold's branch").

A side's fold angle theta_s = atan2(-n' . n^c_s, n . n') (bending.py ``geometry``) lies on the
principal branch (-pi, pi]: two cells folded onto each other and a little further read -(2 pi
- theta), so the bending energy would fall past the flat fold, its moment turn to close the
fold further, and the energy jump by what the side's other curvatures make of the 2 pi (35.4
N mm in 21 steps of the 24-cell two-ply hemisphere's flange fold, docs/hemisphere_plies.md
"The fold's sides"). The block's history keeps, for each interior side, its fold at the last
accepted state and the whole turns added to it so far: after each accepted step a fold that
moved by more than pi (it cannot by the step's motion: it crossed the branch) gains or loses a
turn, and the curvatures take theta_s + 2 pi turns_s, through the reference fold the loops
read (``branch_view``: theta_s - (theta_s0 - 2 pi turns_s)), so that no compiled loop
changes and a block whose sides never crossed the branch computes what it did to the bit.
Clamped sides (folds against the wall of the reference plane) are not followed.
"""

from __future__ import annotations

import copy
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from elements.fibrous import kernels

if TYPE_CHECKING:
    from elements.fibrous.block import FibrousShellBlock

__all__ = ["FoldBranch", "branch_view", "initial_branch", "side_folds", "updated_branch"]


@dataclass(frozen=True, eq=False)
class FoldBranch:
    """The fibrous block's history (never mutated).

    fold : (m, 3) float
        Each interior side's fold angle on the principal branch at the last accepted state,
        rad (0 on the other sides).
    turns : (m, 3) float
        Whole turns added to it, a side's fold being theta_s + 2 pi turns_s.
    """

    fold: np.ndarray
    turns: np.ndarray


def side_folds(block: FibrousShellBlock, positions: np.ndarray) -> np.ndarray:
    """The principal-branch fold angle (m, 3), rad, of each interior side at ``positions``
    (n, 3), 0 on free and clamped sides: one pass over the cells' normals and one over the
    sides (kernels.py) or bending.py ``geometry`` (the numpy kernel)."""
    if block.compiled:
        x = kernels.loop_array(positions)
        normal, double_area, _ = kernels._cell_normals(block, x, False)
        fold, _ = kernels._shared_folds(block, x, normal, double_area)
    else:
        from elements.fibrous import bending

        fold = bending.geometry(block, positions)["fold"]
    return np.where(block.interior_side, fold, 0.0)


def initial_branch(block: FibrousShellBlock) -> FoldBranch:
    """The history of the reference state: its folds (the reference ones), no turns."""
    fold = np.where(block.interior_side, block.reference_fold, 0.0)
    return FoldBranch(fold, np.zeros_like(fold))


def updated_branch(
    block: FibrousShellBlock, positions: np.ndarray, branch: FoldBranch
) -> FoldBranch:
    """The history after a step accepted at ``positions``: a side whose principal fold moved
    by more than pi crossed the branch at +-pi and gains a turn (from +pi to -pi) or loses
    one. The turns array is the same object when no side crossed (``branch_view`` keeps its
    view)."""
    fold = side_folds(block, positions)
    jump = fold - branch.fold
    crossed = (jump < -np.pi).astype(float) - (jump > np.pi).astype(float)
    turns = branch.turns + crossed if crossed.any() else branch.turns
    return FoldBranch(fold, turns)


def branch_view(block: FibrousShellBlock, branch: FoldBranch | None) -> FibrousShellBlock:
    """``block`` itself where no side has turned, else a shallow copy whose reference fold is
    theta_s0 - 2 pi turns_s, which every loop of the block reads (kept while the turns are
    the same array)."""
    if branch is None or not branch.turns.any():
        return block
    cached = block.__dict__.get("_branch_view")
    if cached is not None and cached[0] is branch.turns:
        return cached[1]
    view = copy.copy(block)
    view.reference_fold = block.reference_fold - 2.0 * np.pi * branch.turns
    view.__dict__.pop("_branch_view", None)
    block.__dict__["_branch_view"] = (branch.turns, view)
    return view
