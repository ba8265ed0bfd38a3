"""Degrees of freedom: which nodes carry which DOFs, which are fixed or prescribed, and their
global numbering.

Every node has at most five DOFs, always stored in the same columns:

    column  name    meaning
    0       ux      translation along global x
    1       uy      translation along global y
    2       uz      translation along global z
    3       alpha   rotation of the director about the nodal axis V2 (tilts V towards V1)
    4       beta    rotation of the director about the nodal axis V1 (tilts V towards -V2)

(THEORY §1.2-1.3.) A cable node carries the first three; a shell node all five. Keeping the
columns fixed lets every solver work on (n, 3) translation arrays and (n, 3) angular-velocity
vectors without indirection, while the global numbering (for sparse matrices and reactions)
skips the inactive columns.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

import numpy as np

DOF_NAMES: tuple[str, ...] = ("ux", "uy", "uz", "alpha", "beta")
TRANSLATIONS: tuple[str, ...] = ("ux", "uy", "uz")
ROTATIONS: tuple[str, ...] = ("alpha", "beta")


def dof_columns(names: str | Iterable[str] | None) -> np.ndarray:
    """Column indices (into DOF_NAMES) of DOF names; None means all five.

    Raises ValueError for a name that is not one of DOF_NAMES.
    """
    if names is None:
        return np.arange(len(DOF_NAMES))
    if isinstance(names, str):
        names = (names,)
    names = tuple(names)
    if not names:
        raise ValueError("empty DOF list: expected one or more of " + ", ".join(DOF_NAMES))
    columns = []
    for name in names:
        if name not in DOF_NAMES:
            raise ValueError(f"unknown DOF name {name!r}: expected one of {', '.join(DOF_NAMES)}")
        columns.append(DOF_NAMES.index(name))
    return np.array(columns, dtype=np.int64)


class DofManager:
    """DOF layout of a model: active, fixed and prescribed masks and the global numbering.

    Parameters
    ----------
    n_nodes : number of mesh nodes.
    active : (n_nodes, 5) bool, the DOFs some element block needs at each node.
    fixed : (n_nodes, 5) bool, DOFs held at zero displacement / rotation.
    prescribed : (n_nodes, 5) bool, DOFs with an imposed displacement history.

    Attributes
    ----------
    number : (n_nodes, 5) int64, global equation number of each active DOF, -1 elsewhere.
        Numbering runs node by node, so a node's DOFs are contiguous (good sparsity).
    free : (n_nodes, 5) bool, active and neither fixed nor prescribed.
    constrained : (n_nodes, 5) bool, active and fixed or prescribed.
    has_rotation : (n_nodes,) bool, nodes with the rotational DOFs (and so a director).
    """

    def __init__(self, n_nodes: int, active: np.ndarray, fixed: np.ndarray, prescribed: np.ndarray):
        shape = (n_nodes, len(DOF_NAMES))
        for label, mask in (("active", active), ("fixed", fixed), ("prescribed", prescribed)):
            if np.shape(mask) != shape:
                raise ValueError(f"{label} mask has shape {np.shape(mask)}, expected {shape}")
        self.n_nodes = n_nodes
        self.active = np.asarray(active, dtype=bool).copy()
        self.fixed = np.asarray(fixed, dtype=bool) & self.active
        self.prescribed = np.asarray(prescribed, dtype=bool) & self.active

        both = self.fixed & self.prescribed
        if both.any():
            node, col = np.argwhere(both)[0]
            raise ValueError(
                f"DOF {DOF_NAMES[col]} of node {node} is both fixed and prescribed: "
                "a DOF takes one boundary condition"
            )
        half_rotation = self.active[:, 3] != self.active[:, 4]
        if half_rotation.any():
            raise ValueError(
                f"node {np.flatnonzero(half_rotation)[0]} has only one of alpha/beta: "
                "rotational DOFs come in pairs"
            )
        self.free = self.active & ~self.fixed & ~self.prescribed
        self.constrained = self.active & ~self.free
        self.has_rotation = self.active[:, 3]
        self.number = np.full(shape, -1, dtype=np.int64)
        self.number[self.active] = np.arange(int(self.active.sum()))

    @property
    def n_dofs(self) -> int:
        """Total number of active DOFs."""
        return int(self.active.sum())

    @property
    def n_free(self) -> int:
        """Number of free DOFs (the unknowns of a static solve)."""
        return int(self.free.sum())

    def names_at(self, node: int) -> tuple[str, ...]:
        """DOF names active at one node, e.g. ('ux', 'uy', 'uz')."""
        return tuple(n for n, a in zip(DOF_NAMES, self.active[node]) if a)

    def describe(self) -> str:
        """One line: nodes, DOFs, free, fixed, prescribed."""
        return (
            f"{self.n_nodes} nodes, {self.n_dofs} DOFs: {self.n_free} free, "
            f"{int(self.fixed.sum())} fixed, {int(self.prescribed.sum())} prescribed"
        )


def node_dof_mask(n_nodes: int, nodes: Sequence[int] | np.ndarray, names) -> np.ndarray:
    """(n_nodes, 5) bool mask with the given DOF names set at the given nodes."""
    mask = np.zeros((n_nodes, len(DOF_NAMES)), dtype=bool)
    mask[np.ix_(np.asarray(nodes, dtype=np.int64), dof_columns(names))] = True
    return mask
