"""Degrees of freedom: which nodes carry which DOFs, which are fixed or prescribed, and their
global numbering.

Every node has at most five DOFs, always stored in the same columns:

    column  name    meaning
    0       ux      translation along global x
    1       uy      translation along global y
    2       uz      translation along global z
    3       alpha   rotation of the director about the nodal axis V2 (tilts V towards V1)
    4       beta    rotation of the director about the nodal axis V1 (tilts V towards -V2)

(docs/theory.md §1.2-1.3.) A cable node carries the first three; a shell node all five. Keeping the
columns fixed lets every solver work on (n, 3) translation arrays and (n, 3) angular-velocity
vectors without indirection.

Two numberings, both owned here and used by every solver:

- *slots*: ``N_COLUMNS * node + column`` over all n x 5 columns, active or not: the index of
  the generalised vectors (n, 5) flattened, and of the rows and columns of the sparse tangent
  (``DofManager.slots``, ``free_slots``, ``prescribed_slots``);
- *equations*: ``DofManager.number``, consecutive over the active DOFs only (node by node).

Generalised coordinates q = (ux, uy, uz, alpha, beta) per node map to the (u, psi) of the
elements through the nodal frames of the directors: psi = alpha V2 + beta V1 (Bai Eq. 7, 13).
``DofManager.advance`` is the one configuration update of the project: translations added,
directors turned by the finite rotation psi (Rodrigues, so |V| = 1 exactly).
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import replace

import numpy as np

from femcore.rotation import nodal_frames, rotate_about
from femcore.state import State

__all__ = [
    "DOF_NAMES",
    "N_COLUMNS",
    "ROTATIONS",
    "TRANSLATIONS",
    "DofManager",
    "Frames",
    "dof_columns",
    "dof_names",
]

DOF_NAMES: tuple[str, ...] = ("ux", "uy", "uz", "alpha", "beta")
TRANSLATIONS: tuple[str, ...] = ("ux", "uy", "uz")
ROTATIONS: tuple[str, ...] = ("alpha", "beta")
#: Columns per node in the generalised (n, 5) arrays and in the slot numbering.
N_COLUMNS: int = len(DOF_NAMES)

#: Nodal frames (V1, V2), (n, 3) each, of the directors; None for a model without rotations.
Frames = tuple[np.ndarray, np.ndarray] | None


def dof_columns(names: str | Iterable[str] | None) -> np.ndarray:
    """Column indices (into DOF_NAMES) of DOF names; None means all five.

    Raises ValueError for a name that is not one of DOF_NAMES.
    """
    if names is None:
        return np.arange(len(DOF_NAMES))
    if isinstance(names, str):
        names = (names,)
    try:
        names = tuple(names)
    except TypeError:
        raise ValueError(
            f"DOFs must be a name or a sequence of names among {', '.join(DOF_NAMES)}, "
            f"got {names!r}"
        ) from None
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
        self.free_slots = np.flatnonzero(self.free.ravel())
        self.prescribed_slots = np.flatnonzero(self.prescribed.ravel())
        self.any_rotation = bool(self.has_rotation.any())

    # ------------------------------------------------------------------ numbering
    @staticmethod
    def slots(nodes: np.ndarray, columns: np.ndarray | int) -> np.ndarray:
        """Slot numbers ``N_COLUMNS * node + column`` (broadcast over both arguments)."""
        return N_COLUMNS * np.asarray(nodes) + np.asarray(columns)

    @property
    def n_slots(self) -> int:
        """n x 5: the size of the generalised vectors and of the sparse tangent."""
        return N_COLUMNS * self.n_nodes

    # ------------------------------------------------------------------ generalised coordinates
    def frames(self, directors: np.ndarray) -> Frames:
        """Nodal frames (V1, V2), (n, 3) each, of the directors (Bai Eq. 7 with its fallback).

        A Newton iteration keeps one set of frames for its residual, tangent and update: near
        the fallback of Eq. 7 a frame may switch between two nearby states, and mixing frames
        would make the tangent inconsistent with the residual. Nodes without a director get
        the frame of e3 (unused).
        """
        if not self.any_rotation:
            return None
        return nodal_frames(np.where(self.has_rotation[:, None], directors, [0, 0, 1.0]))

    def generalised(self, frames: Frames, force: np.ndarray, moment: np.ndarray) -> np.ndarray:
        """(n, 5): forces (n, 3) and the moment components conjugate to alpha (about V2) and
        beta (about V1), zero at nodes without a director."""
        out = np.zeros((self.n_nodes, N_COLUMNS))
        out[:, :3] = force
        if frames is not None:
            v1, v2 = frames
            out[:, 3] = np.sum(moment * v2, axis=1)
            out[:, 4] = np.sum(moment * v1, axis=1)
            out[~self.has_rotation, 3:] = 0.0
        return out

    def node_maps(self, frames: Frames) -> np.ndarray:
        """(n, 6, 5): per node the map T with (u, psi) = T q, psi = alpha V2 + beta V1."""
        maps = np.zeros((self.n_nodes, 6, N_COLUMNS))
        maps[:, :3, :3] = np.eye(3)
        if frames is not None:
            v1, v2 = frames
            maps[:, 3:, 3] = v2
            maps[:, 3:, 4] = v1
        return maps

    # ------------------------------------------------------------------ configuration update
    def move(self, state: State, displacement: np.ndarray, rotation: np.ndarray | None) -> State:
        """A new State: positions + displacement (n, 3); directors turned by the finite rotation
        vectors ``rotation`` (n, 3), rad, at the nodes that have one (None: not turned)."""
        directors = state.directors
        if rotation is not None and self.any_rotation:
            directors = np.where(
                self.has_rotation[:, None], rotate_about(directors, rotation), directors
            )
        return replace(state, positions=state.positions + displacement, directors=directors)

    def advance(self, state: State, dq: np.ndarray, frames: Frames = None) -> State:
        """A new State moved by the generalised increment dq (n, 5): translations added, the
        directors turned about V2 by alpha and about V1 by beta of ``frames`` (default: the
        frames of ``state.directors``)."""
        rotation = None
        current = self.frames(state.directors) if frames is None else frames
        if current is not None:
            v1, v2 = current
            rotation = dq[:, 3:4] * v2 + dq[:, 4:5] * v1
        return self.move(state, dq[:, :3], rotation)

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
        return dof_names(self.active[node])

    def describe(self) -> str:
        """One line: nodes, DOFs, free, fixed, prescribed."""
        return (
            f"{self.n_nodes} nodes, {self.n_dofs} DOFs: {self.n_free} free, "
            f"{int(self.fixed.sum())} fixed, {int(self.prescribed.sum())} prescribed"
        )


def dof_names(row: np.ndarray) -> tuple[str, ...]:
    """The DOF names of the set entries of a (5,) bool row, e.g. ('ux', 'uy', 'uz')."""
    return tuple(name for name, flag in zip(DOF_NAMES, row) if flag)
