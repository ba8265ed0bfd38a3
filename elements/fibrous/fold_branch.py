"""The fold angles followed through a flat fold (docs/theory.md §4.2, "The fold's branch").

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

The pass over every side after every step cost 1.20 times a step on a fibrous sheet
(benchmarks/fold_branch.py). A fold nears pi only from far above pi / 2, and no node moves far
in a step: the history also keeps the positions of the last pass over every side and the
sides whose fold then exceeded pi / 2 (``WATCHED``); after an accepted step only those
sides' folds are taken (numpy, a few sides), until some node has moved by more than
``REFRESH`` times the block's least reference cell height since that pass, when every side is
taken again. Within that motion each cell's normal turns by at most about 2 REFRESH h0 / h
(a corner moved by d relative to its side turns it by d / h), 0.6 rad for cells sheared to
0.64 of their height: a side below pi / 2 at the last pass stays below pi.
"""

from __future__ import annotations

import copy
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from elements.fibrous import geometry_kernels
from elements.fibrous.geometry import SIDE_FROM, SIDE_TO
from femcore.jit import AVAILABLE, serial

if TYPE_CHECKING:
    from elements.fibrous.block import FibrousShellBlock

__all__ = [
    "REFRESH",
    "WATCHED",
    "FoldBranch",
    "branch_view",
    "initial_branch",
    "largest_move",
    "side_folds",
    "updated_branch",
]

#: Sides whose fold exceeded this (rad) at the last pass over every side are followed
#: after every step in between.
WATCHED = 0.5 * np.pi
#: Every side is taken again once a node has moved by this many times the block's least
#: reference cell height since the last such pass.
REFRESH = 0.1


@dataclass(frozen=True, eq=False)
class FoldBranch:
    """The fibrous block's history (never mutated: its ``turns`` array is made read-only, the
    caller's own array if it gave one; a new branch takes new turns).

    fold : (m, 3) float
        Each interior side's fold angle on the principal branch at the last accepted state,
        rad (0 on the other sides).
    turns : (m, 3) float
        Whole turns added to it, a side's fold being theta_s + 2 pi turns_s.
    positions : (n, 3) float or None
        The positions of the last pass over every side, mm (None: none yet).
    watched : (k, 2) int
        The (cell, side) of the sides whose fold exceeded ``WATCHED`` then.
    """

    fold: np.ndarray
    turns: np.ndarray
    positions: np.ndarray | None = None
    watched: np.ndarray | None = None

    def __post_init__(self) -> None:
        # ``branch_view`` keeps its answer while the turns are the same array: an edit in
        # place would leave that answer stale, so the turns refuse one (a new branch is
        # made with new turns, ``updated_branch``).
        self.turns.flags.writeable = False

    def __setstate__(self, state: dict) -> None:
        # A checkpoint's branch refuses an edit as a new one does.
        self.__dict__.update(state)
        self.turns.flags.writeable = False


def side_folds(block: FibrousShellBlock, positions: np.ndarray) -> np.ndarray:
    """The principal-branch fold angle (m, 3), rad, of each interior side at ``positions``
    (n, 3), 0 on free and clamped sides: one pass over the cells' normals and one over the
    sides (geometry_kernels.py) or bending.py ``geometry`` (the numpy kernel)."""
    if block.compiled:
        x = geometry_kernels.loop_array(positions)
        normal, double_area, _ = geometry_kernels._cell_normals(block, x, False)
        fold, _ = geometry_kernels._shared_folds(block, x, normal, double_area)
    else:
        from elements.fibrous import bending

        fold = bending.geometry(block, positions)["fold"]
    return np.where(block.interior_side, fold, 0.0)


def initial_branch(block: FibrousShellBlock) -> FoldBranch:
    """The history of the reference state: its folds (the reference ones), no turns."""
    fold = np.where(block.interior_side, block.reference_fold, 0.0)
    return FoldBranch(fold, np.zeros_like(fold))


def watched_folds(block: FibrousShellBlock, positions: np.ndarray, sides: np.ndarray):
    """The principal-branch fold angle (k,), rad, of the interior ``sides`` (k, 2) (cell,
    side) at ``positions``: bending.py ``geometry``'s formula on those sides alone."""
    cell, side = sides[:, 0], sides[:, 1]

    def normals(cells):
        x = positions[block.connectivity[cells]]
        normal = np.cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0])
        return x, normal / np.linalg.norm(normal, axis=1)[:, None]

    x, n = normals(cell)
    _, other = normals(block.across_cell[cell, side])
    rows = np.arange(len(cell))
    edge = x[rows, SIDE_TO[side]] - x[rows, SIDE_FROM[side]]
    outward = np.cross(edge, n) / np.linalg.norm(edge, axis=1)[:, None]
    return np.arctan2(-np.sum(other * outward, axis=1), np.sum(other * n, axis=1))


def updated_branch(
    block: FibrousShellBlock, positions: np.ndarray, branch: FoldBranch
) -> FoldBranch:
    """The history after a step accepted at ``positions``: a side whose principal fold moved
    by more than pi crossed the branch at +-pi and gains a turn (from +pi to -pi) or loses
    one. Every side is taken when a node has moved by ``REFRESH`` least heights since the
    last such pass, the ``WATCHED`` sides alone otherwise. The turns array is the same
    object when no side crossed (``branch_view`` keeps its view)."""
    cached = block.__dict__.get("_branch_nodes")
    if cached is None:  # the block's nodes and least reference cell height, once
        height = float(np.min(2.0 * block.reference_area / _longest_sides(block)))
        cached = block.__dict__["_branch_nodes"] = (np.flatnonzero(block.node_in_block), height)
    nodes, height = cached
    moved = (
        np.inf
        if branch.positions is None
        else largest_move(positions, branch.positions, nodes)
        if AVAILABLE
        else float(np.abs(positions[nodes] - branch.positions).max(initial=0.0))
    )
    if moved > REFRESH * height:
        fold = side_folds(block, positions)
        jump = fold - branch.fold
        crossed = (jump < -np.pi).astype(float) - (jump > np.pi).astype(float)
        turns = branch.turns + crossed if crossed.any() else branch.turns
        return FoldBranch(fold, turns, positions[nodes].copy(), np.argwhere(np.abs(fold) > WATCHED))
    watched = branch.watched
    assert watched is not None
    if not len(watched):
        return FoldBranch(branch.fold, branch.turns, branch.positions, watched)
    # the watched sides alone (each once: argwhere's rows), the other folds as they were
    cell, side = watched[:, 0], watched[:, 1]
    now = watched_folds(block, positions, watched)
    jump = now - branch.fold[cell, side]
    crossed = (jump < -np.pi).astype(float) - (jump > np.pi).astype(float)
    fold = branch.fold.copy()
    fold[cell, side] = now
    turns = branch.turns
    if crossed.any():
        turns = turns.copy()
        turns[cell, side] += crossed
    return FoldBranch(fold, turns, branch.positions, watched)


@serial
def largest_move(positions, last, nodes):
    """max |positions[nodes[i], j] - last[i, j]| over the nodes i and axes j (mm; 0 for no
    node, nan where a difference is nan): ``np.abs(positions[nodes] - last).max(initial=0)``
    in one compiled pass without its three (k, 3) temporaries (the numpy form took 2.2 ms
    a step of the 100k sheet, 0.02 us an element-step, benchmarks/explicit_step.py)."""
    largest = 0.0
    for i in range(nodes.shape[0]):
        node = nodes[i]
        for j in range(3):
            move = abs(positions[node, j] - last[i, j])
            if move > largest:
                largest = move
            elif move != move:
                return np.nan
    return largest


def _longest_sides(block: FibrousShellBlock) -> np.ndarray:
    """Each cell's longest side in the reference configuration (m,), mm."""
    x = block.reference_points[block.connectivity]
    return np.linalg.norm(x[:, SIDE_TO] - x[:, SIDE_FROM], axis=-1).max(axis=1)


def branch_view(block: FibrousShellBlock, branch: FoldBranch | None) -> FibrousShellBlock:
    """``block`` itself where no side has turned, else a shallow copy whose reference fold is
    theta_s0 - 2 pi turns_s, which every loop of the block reads (kept while the turns are
    the same array; so is the answer that no side has turned, which asked of the array at
    every call cost 0.9 ms a step of the 100k sheet)."""
    if branch is None:
        return block
    cached = block.__dict__.get("_branch_view")
    if cached is not None and cached[0] is branch.turns:
        return block if cached[1] is None else cached[1]
    view = None  # the block itself, not kept in its own dict (a cycle only the collector frees)
    if branch.turns.any():
        view = copy.copy(block)
        view.reference_fold = block.reference_fold - 2.0 * np.pi * branch.turns
        view.__dict__.pop("_branch_view", None)
    block.__dict__["_branch_view"] = (branch.turns, view)
    return block if view is None else view
