"""Node sets of a case file by bounds: ``{ x_min = 199.9 }`` in mesh units, or
``{ x_min = "100%" }`` as a share of the mesh's extent along that axis.

A bound is a number in mesh units, or a string ``"P%"`` with P from 0 to 100: the
coordinate ``low + P / 100 (high - low)`` of the mesh's extent [low, high] along that axis
(the bounding box of the nodes its cells use when the case is read: a node no cell uses, a
stray point of the mesh file, neither widens the extent nor joins a set). A relative bound
follows the mesh when its size changes, so that a sweep over ``mesh.rectangle.lx`` keeps
``tip = { x_min = "100%" }`` at the tip; an absolute one stays where it was written. A node
is in the set when every bound given holds within ``tolerance`` (mesh units, >= 0; default
1e-6 of the mesh's largest extent). Bounds that select no node are an error naming each
bound, its coordinate and the mesh's extent.

A path (``[output] paths``) is a set that is a line: its nodes ordered along the axis of its
longest extent, one node at each position along it (``order_path``).
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from typing import Any

import numpy as np

__all__ = ["BOUND_KEYS", "BoundsError", "order_path", "select_by_bounds", "unused_in", "used_nodes"]

BOUND_KEYS = ("x_min", "x_max", "y_min", "y_max", "z_min", "z_max", "tolerance")
_PERCENT = re.compile(r"\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*%\s*")


class BoundsError(ValueError):
    """Bounds that cannot be read or select no node; ``key`` is the bound at fault (None:
    the bounds together)."""

    def __init__(self, message: str, key: str | None = None) -> None:
        super().__init__(message)
        self.key = key


def _coordinate(value: Any, key: str, low: float, high: float) -> float:
    """The coordinate (mesh units) of bound ``key``: a number as given, or "P%" of [low,
    high]."""
    if isinstance(value, str):
        match = _PERCENT.fullmatch(value)
        if match is None:
            raise BoundsError(
                f"expected a number (mesh units) or a share of the mesh's extent such as "
                f'"100%", got {value!r}',
                key,
            )
        share = float(match.group(1))
        if not 0.0 <= share <= 100.0:
            raise BoundsError(
                f"expected a share of the mesh's extent from 0% to 100%, got {value!r}", key
            )
        return low + share / 100.0 * (high - low)
    if isinstance(value, bool) or not isinstance(value, int | float) or not np.isfinite(value):
        raise BoundsError(
            f'expected a finite number (mesh units) or a share such as "100%", got {value!r}',
            key,
        )
    return float(value)


def _extent(low: np.ndarray, high: np.ndarray) -> str:
    return ", ".join(f"{a} {lo:g} to {hi:g}" for a, lo, hi in zip("xyz", low, high))


def used_nodes(mesh: Any) -> np.ndarray:
    """The (n,) bool mask of the nodes of ``mesh`` (a femcore Mesh) that some cell uses; every
    node when the mesh has no cell."""
    used = np.zeros(mesh.n_nodes, dtype=bool)
    for kind in mesh.cell_kinds:
        used[mesh.cells(kind).ravel()] = True
    return used if used.any() else np.ones(mesh.n_nodes, dtype=bool)


def unused_in(mesh: Any, ids: np.ndarray) -> np.ndarray:
    """The nodes of ``ids`` that no cell of ``mesh`` uses (they carry no DOF: their
    displacement and reaction are 0 whatever the load)."""
    ids = np.asarray(ids, dtype=np.int64)
    return ids[~used_nodes(mesh)[ids]]


def select_by_bounds(
    points: np.ndarray, bounds: Mapping[str, Any], used: np.ndarray | None = None
) -> np.ndarray:
    """The nodes within ``bounds``.

    Parameters
    ----------
    points : (n, 3) float array, mesh units
        The mesh's node coordinates.
    bounds : mapping
        Some of ``x_min``, ``x_max``, ``y_min``, ``y_max``, ``z_min``, ``z_max`` (a number
        in mesh units, or ``"P%"`` of the mesh's extent along that axis, 0 <= P <= 100) and
        ``tolerance`` (mesh units, >= 0).
    used : (n,) bool array, optional
        The nodes the cells use (``used_nodes``): the extent that shares are of is theirs,
        and only they are selected. None: every node.

    Returns
    -------
    (k,) int array
        The ids of the nodes within every bound, ascending; k >= 1.

    Raises
    ------
    BoundsError (a ValueError)
        An unknown key, a bound that is neither a number nor a share from 0% to 100%, a
        negative tolerance (``key`` names the bound); no bound at all (an empty table or a
        tolerance alone: it would select every node) or bounds that select no node (``key``
        None: the message names each bound, its coordinate and the mesh's extent).
    """
    unknown = [key for key in bounds if key not in BOUND_KEYS]
    if unknown:
        raise BoundsError(
            f"unknown key {unknown[0]!r}; expected one of {', '.join(BOUND_KEYS)}", unknown[0]
        )
    if not any(key in bounds for key in BOUND_KEYS if key != "tolerance"):
        # No bound would hold every node: a table left empty (``nodes = {}``) must not fix,
        # load or watch the whole mesh.
        raise BoundsError(
            f"no bound given, got {dict(bounds)!r}: give at least one of "
            f"{', '.join(BOUND_KEYS[:-1])} (a node-set name selects a named set)",
            None,
        )
    if used is None or not np.any(used):
        used = np.ones(len(points), dtype=bool)
    used = np.asarray(used, dtype=bool)
    # A node no cell uses (a stray point of the mesh file) carries no DOF: it must neither
    # stretch the extent that "100%" is of nor join a set, where it would read 0 forever.
    low, high = points[used].min(axis=0), points[used].max(axis=0)
    size = float((high - low).max()) or 1.0
    tolerance = bounds.get("tolerance", 1e-6 * size)
    if (
        isinstance(tolerance, bool)
        or not isinstance(tolerance, int | float)
        or not np.isfinite(tolerance)
        or tolerance < 0.0
    ):
        raise BoundsError(
            f"expected a finite distance >= 0 (mesh units), got {tolerance!r}", "tolerance"
        )
    mask = used.copy()
    given = []  # (key, text, mask of that bound alone)
    for axis, name in enumerate("xyz"):
        for side in ("min", "max"):
            key = f"{name}_{side}"
            if key not in bounds:
                continue
            at = _coordinate(bounds[key], key, float(low[axis]), float(high[axis]))
            alone = (
                points[:, axis] >= at - tolerance
                if side == "min"
                else points[:, axis] <= at + tolerance
            )
            alone &= used
            mask &= alone
            written = bounds[key]
            text = f"{key} = {written!r} ({name} = {at:g})" if isinstance(written, str) else (
                f"{key} = {at:g}"
            )  # fmt: skip
            given.append((key, text, alone))
    if mask.any():
        return np.flatnonzero(mask)
    spans = _extent(low, high)
    empty = [text for _, text, alone in given if not alone.any()]
    if empty:
        what = f"no node within {'; '.join(empty)}"
    elif given:
        what = f"no node within {', '.join(text for _, text, _ in given)} together"
    else:
        what = "no node"  # no points at all
    hint = (
        ' (a bound written as a share of the extent, "0%" to "100%", follows the mesh)'
        if any(not isinstance(bounds[key], str) for key, _, _ in given)
        else ""
    )
    raise BoundsError(
        f"{what} (tolerance {float(tolerance):g}): the mesh spans {spans}{hint}", None
    )


def order_path(points: np.ndarray, ids: np.ndarray) -> np.ndarray:
    """The nodes ``ids`` of a path ordered along the axis of their longest extent.

    Parameters
    ----------
    points : (n, 3) float
        The mesh's reference coordinates (mesh units).
    ids : (k,) int
        The path's nodes, k >= 2.

    Returns
    -------
    (k,) int
        ``ids`` in increasing coordinate along that axis (the profiles' order, their arc
        length summed node to node).

    Raises
    ------
    BoundsError
        When two nodes stand at one position along the axis (within 1e-6 of the mesh's
        largest extent, the selections' default tolerance), or when, so ordered, a step from
        node to node turns back on the one before (by more than 90 deg): the nodes are an area,
        not a line (a bound forgotten, ``y_min = "0%"`` without ``y_max``; on a mesh not
        aligned with the axes no two nodes share a position, and the order zigzags across the
        area), or a line that turns back along its longest extent (a hat section, the crests
        of a corrugation whose walls are steeper than 45 deg: its points alone cannot tell it
        from two rows of an area), which is given as pieces; the message says which.
    """
    chosen = points[ids]
    axis = int(np.argmax(np.ptp(chosen, axis=0)))
    order = np.argsort(chosen[:, axis], kind="stable")
    along = chosen[order, axis]
    size = float(np.ptp(points, axis=0).max()) or 1.0
    group = np.r_[0, np.cumsum(np.diff(along) > 1e-6 * size)]  # one number per position
    counts = np.bincount(group)
    name = "xyz"[axis]
    way_out = (
        f"a path is one line of nodes, each at its own position along {name}, its longest "
        "extent, and ordered by it: give the bounds that make it one (both y_min and y_max for "
        "a line along x; a line that turns back along its longest extent, a hat section, as "
        "pieces that each run one way)"
    )
    if counts.max() > 1:
        shared = np.flatnonzero(counts > 1)
        first = along[group == shared[0]][0]
        plural = "s" if len(shared) > 1 else ""
        raise BoundsError(
            f"not a line: {counts[shared].sum()} of its {len(ids)} nodes share {len(shared)} "
            f"position{plural} along {name} (the first: {counts[shared[0]]} nodes at {name} = "
            f"{first:g}): an area, or a line that turns back along {name}; {way_out}"
        )
    # Ordered along the axis, a line's steps run on one after another; an area's zigzag
    # across it (a step back over the one before), wherever its nodes stand along the axis:
    # two rows at every node, more rows at two nodes of each column of the mesh (a share of
    # the turns would let those through). A line whose crests turn back by more than 90 deg
    # (a corrugation with walls steeper than 45 deg) cannot be told from two rows by its
    # points alone: refused too, to be given as pieces.
    steps = np.diff(chosen[order], axis=0)
    turned = np.einsum("ij,ij->i", steps[:-1], steps[1:]) <= 0.0
    if turned.any():
        at = chosen[order][1:-1][turned][0]
        raise BoundsError(
            f"not a line: ordered along {name}, its steps from node to node turn back by more "
            f"than 90 deg at {int(turned.sum())} of its {len(turned)} inner nodes (the first "
            f"at {name} = {at[axis]:g}): an area, or a line that turns back along {name}; "
            f"{way_out}"
        )
    return ids[order]
