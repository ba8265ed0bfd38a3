"""The masses a dynamic relaxation moves with (solvers.relaxation.DynamicRelaxation;
docs/theory.md §6.4a): fictitious masses from a Gershgorin bound of the tangent stiffness
(``GershgorinMasses``, the default), or the physical lumped masses with the stable step
(``PhysicalMasses``). Only the end point of a relaxation matters, so the masses need not be
the physical ones: they set how fast each mode moves, and equal stability limits for every DOF
make the motion converge in the fewest steps.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp

from femcore.assembly import tangent_matrix
from femcore.dofs import N_COLUMNS
from femcore.model import CompiledModel
from femcore.rotation import nodal_frames
from femcore.state import State
from femcore.topology import nodal_normals

__all__ = [
    "REACH_SHARE",
    "TURN",
    "GershgorinMasses",
    "NodeMass",
    "PhysicalMasses",
    "RelaxationMasses",
]

#: Largest turn (rad) of a shell normal between two estimates of the fictitious masses; the
#: normal mass carries TURN^2 of the in-plane one for the stiffness such a turn brings along.
TURN = 0.03
#: The reach of the interactions' springs in the fictitious masses, in element sizes L_e: a
#: node this near a contact carries its spring, one farther off is watched (docs/theory.md
#: §6.4a, "Contact"; 0.02 took the fewest iterations on the capstans of tests/test_capstan.py
#: among 0.02, 0.05, 0.1, 0.2, 0.5 and 1).
REACH_SHARE = 0.02


class NodeMass:
    """Translational masses per node as a diagonal in node axes: M_a = R_a diag(d_a) R_a^T.

    axes : (n, 3, 3), columns the unit axes of each node (identity: the global axes).
    values : (n, 3), the mass along each axis (0: a DOF that never moves).
    """

    def __init__(self, axes: np.ndarray, values: np.ndarray):
        self.axes, self.values = axes, values
        self.inverse = _inverse(values)

    def local(self, vectors: np.ndarray) -> np.ndarray:
        """(n, 3) global components -> components along the node axes."""
        return np.einsum("nji,nj->ni", self.axes, vectors)

    def solve(self, forces: np.ndarray) -> np.ndarray:
        """M^-1 F, (n, 3)."""
        return np.einsum("nij,nj->ni", self.axes, self.inverse * self.local(forces))

    def energy(self, velocities: np.ndarray) -> float:
        """1/2 v.M v."""
        local = self.local(velocities)
        return 0.5 * float(np.sum(self.values * local * local))


class RelaxationMasses:
    """The masses a relaxation moves with: ``__call__(state, inflate)`` gives (translation
    masses (n, 3), rotary inertia (n,), time step)."""

    fictitious = False
    every_restart = True
    #: what the fictitious masses are made of, as a blow-up's message names it
    bound = "the physical masses"
    #: the turn (rad) of a surface normal after which the masses are made again
    turn = TURN

    def turned(self, state: State) -> float:
        """The largest turn (rad) of a surface normal since the last estimate."""
        return 0.0

    def approached(self, state: State) -> bool:
        """Whether a node has moved since the last estimate as far as its clearance to an
        interaction whose springs its masses do not carry (``GershgorinMasses``)."""
        return False

    def __init__(self) -> None:
        self.estimates = 0
        self.recoveries = 0
        self.switches = 0  # stalled increments that went on with the factored masses

    def __call__(self, state: State, inflate: float) -> tuple[NodeMass, np.ndarray, float]:
        raise NotImplementedError


class PhysicalMasses(RelaxationMasses):
    """The physical lumped masses and rotary inertia, ``safety`` x the stable step."""

    def __init__(self, model: CompiledModel, safety: float):
        super().__init__()
        self.model, self.safety = model, safety

    def __call__(self, state: State, inflate: float) -> tuple[NodeMass, np.ndarray, float]:
        self.estimates += 1
        mass, inertia = self.model.lumped_mass(state)
        dt = self.safety * self.model.stable_dt(state)
        axes = np.broadcast_to(np.eye(3), (self.model.n_nodes, 3, 3))
        return NodeMass(axes, np.repeat(mass[:, None], 3, axis=1)), inertia, dt


class GershgorinMasses(RelaxationMasses):
    """Fictitious masses m_i = (dt^2 / 4) sum_j |K_ij| / safety^2 with dt = 1, K_ij over the
    free DOFs: by Gershgorin's theorem every eigenvalue of M^-1 K is then below
    (2 safety / dt)^2, within the central-difference limit (docs/theory.md §6.4a)."""

    bound = 'their Gershgorin bound (masses = "gershgorin": the row sums of |K|)'

    fictitious = True
    every_restart = False

    def __init__(self, model: CompiledModel, safety: float, own: dict | None = None):
        super().__init__()
        self.model = model
        self.scale = 1.0 / (4.0 * safety**2)
        # ``own``: the blocks' own tangents at the start, where the caller has made them
        if own is None:
            own = model.own_tangents(model.initial_state())
        # The interactions that say how far their nodes are from them (a contact): a node
        # about to meet one carries its springs (docs/theory.md §6.4a, "Contact").
        self.springy = model.clearance_parts(model.initial_state())
        self.reach = REACH_SHARE * model.element_size
        self.own = list(own)
        self.others = [i for i in range(len(model.parts)) if i not in own]
        self.watched = np.zeros(0, dtype=np.int64)  # nodes left without a spring they may meet
        self.watch = np.zeros(0)  # mm, how far each may move before it may meet it
        self.at = np.zeros((0, 3))  # mm, where they were at the estimate
        # The colouring loops over the nodes: once per solve.
        self.graph = model.node_graph(self.others) if self.others else None
        self.length = model.element_size
        self.length2 = model.element_size**2
        self.triangles = model.mesh.triangles
        self.local = np.zeros(model.n_nodes, dtype=bool)
        self.normals = np.zeros((0, 3))

    def __call__(self, state: State, inflate: float) -> tuple[NodeMass, np.ndarray, float]:
        self.estimates += 1
        k, axes, local = self.stiffness(state)
        rows = self.row_sums(k)
        return self.diagonal(state, inflate, rows, axes, local)

    def stiffness(self, state: State) -> tuple[sp.csr_matrix, np.ndarray, np.ndarray]:
        """The tangent stiffness at ``state`` in the node axes (Q^T K Q, all slots), the
        node axes (n, 3, 3) and which nodes take a shell's own axes (n,) bool."""
        model, dofs = self.model, self.model.dofs
        n = dofs.n_nodes
        frames = dofs.frames(state.directors)
        parts = model.tangent_parts(state, self.own) if self.own else []
        if parts is None:
            raise RuntimeError(
                "an element block gave a tangent at the start of the solve and none later: a "
                "block's tangent() returns None always or never"
            )
        k = tangent_matrix(dofs, parts, frames)
        if self.graph is not None:
            k = k + model.finite_difference_stiffness(state, self.others, self.graph, frames)
        # Node axes: a shell node whose translations are all free takes two tangent axes and
        # the normal of the mid-surface, so that the soft direction of a shell (along the normal:
        # bending,
        # transverse shear) gets its own small mass while the in-plane axes carry the stiff
        # membrane, and the axes turn with the shell at each estimate; other nodes keep x, y, z.
        axes = np.repeat(np.eye(3)[None], n, axis=0)
        local = dofs.has_rotation & dofs.free[:, :3].all(axis=1)
        if local.any():
            # The normal of the mid-surface, not the director: a fibrous director leans.
            normals = nodal_normals(state.positions, self.triangles)[local]
            t1, t2 = nodal_frames(normals)
            axes[local] = np.stack([t1, t2, normals], axis=2)
        return _in_node_axes(k, axes), axes, local

    def row_sums(self, k: sp.csr_matrix) -> np.ndarray:
        """The Gershgorin row sums of D^-1 |K| D (see below) per slot, (n, N_COLUMNS), N/mm on
        the translations and N mm on the rotations; 0 on the slots that are not free."""
        dofs = self.model.dofs
        n = dofs.n_nodes
        free = dofs.free_slots
        rows = np.zeros(dofs.n_slots)
        # The row sums of D^-1 |K| D, D = 1 on the translations and 1 / L_e on the rotations:
        # the Gershgorin masses of the unknowns (u, L_e theta), all lengths, brought back to
        # the rotations (J = L_e^2 m). Gershgorin's bound holds for any such similarity, and
        # this one is the same in every consistent set of units, where the plain row sums
        # added N/mm to N/rad (a Mindlin cantilever 1000 times larger, in the same units,
        # stalled: the coupling terms K_u,theta made its translations 1000 times too heavy).
        # Without rotations D = 1: the plain sums, in their own order (the same bits).
        lengths = np.ones((n, N_COLUMNS))
        lengths[:, 3:] = 1.0 / self.length
        d = lengths.ravel()[free]
        magnitudes = abs(k[free][:, free])
        if (d == 1.0).all():
            rows[free] = np.asarray(magnitudes.sum(axis=1)).ravel()
        else:
            rows[free] = np.asarray(magnitudes @ d).ravel() / d
        return rows.reshape(n, N_COLUMNS)

    def diagonal(
        self, state: State, inflate: float, rows: np.ndarray, axes: np.ndarray, local: np.ndarray
    ) -> tuple[NodeMass, np.ndarray, float]:
        """The diagonal masses from the row sums ``rows`` (n, N_COLUMNS) in the node ``axes``."""
        model, dofs = self.model, self.model.dofs
        rows = rows * (self.scale * inflate)
        mass = rows[:, :3].copy()
        # Elsewhere (cables, partly held nodes) one mass for the three axes: global axes do
        # not turn with the body, and a stiffness that the motion turns onto a light axis
        # would blow up before the next estimate.
        mass[~local] = mass[~local].max(axis=1, initial=0.0)[:, None]
        mass[local, 2] += self.turn**2 * mass[local, :2].max(axis=1)
        if self.springy:
            # A spring bounds its stiffness along any direction: the same on the three axes.
            springs, watch = model.reachable_springs(state, self.reach, self.springy)
            mass += np.where(dofs.free[:, :3], (self.scale * inflate) * springs[:, None], 0.0)
            self.watched = np.flatnonzero(np.isfinite(watch))
            self.watch = watch[self.watched]
            self.at = state.positions[self.watched]
        self.local, self.normals = local, axes[local, :, 2]
        # One inertia per node, isotropic in the tangent plane: the angular velocity is a
        # vector there, and alpha and beta follow nodal frames that turn with the director.
        inertia = rows[:, 3:].max(axis=1)
        mass = _floor(mass, dofs.free[:, :3], None)
        turning = dofs.free[:, 3:].any(axis=1)
        # A rotation whose row is empty (an unloaded director) still needs a finite inertia:
        # the translations' scale over one element.
        free_masses = mass[dofs.free[:, :3]]
        typical = (
            float(np.median(free_masses)) * self.length2
            if free_masses.size  # else every translation is held: the largest inertia row
            else float(inertia.max(initial=0.0)) or 1.0
        )
        inertia = _floor(inertia, turning, typical)
        return NodeMass(axes, mass), inertia, 1.0

    def approached(self, state: State) -> bool:
        if not len(self.watched):
            return False
        moved = np.linalg.norm(state.positions[self.watched] - self.at, axis=1)
        return bool(np.any(moved >= self.watch))

    def turned(self, state: State) -> float:
        if not self.local.any():
            return 0.0
        normals = nodal_normals(state.positions, self.triangles)[self.local]
        cosine = float(np.min(np.sum(normals * self.normals, axis=1)))
        return math.acos(min(max(cosine, -1.0), 1.0))


def _in_node_axes(k: sp.csr_matrix, axes: np.ndarray) -> sp.csr_matrix:
    """Q^T K Q with Q block-diagonal: the node axes (n, 3, 3) on the translation slots, the
    identity on alpha and beta (already in the nodal frame)."""
    n = axes.shape[0]
    blocks = np.zeros((n, N_COLUMNS, N_COLUMNS))
    blocks[:, :3, :3] = axes
    blocks[:, 3, 3] = blocks[:, 4, 4] = 1.0
    base = (N_COLUMNS * np.arange(n))[:, None, None]
    rows = np.broadcast_to(base + np.arange(N_COLUMNS)[:, None], blocks.shape)
    cols = np.broadcast_to(base + np.arange(N_COLUMNS)[None, :], blocks.shape)
    q = sp.csr_matrix((blocks.ravel(), (rows.ravel(), cols.ravel())), shape=k.shape)
    return (q.T @ k @ q).tocsr()


def _floor(values: np.ndarray, free: np.ndarray, fallback: float | None) -> np.ndarray:
    """No free mass below 1e-3 of the median of its kind (``fallback`` when none is positive):
    a zero-stiffness DOF is stable with any mass, and a small but finite one keeps it from
    flying off when the configuration gives it stiffness before the next estimate."""
    positive = values[free & (values > 0)]
    if positive.size:
        floor = 1e-3 * float(np.median(positive))
    elif fallback is not None and fallback > 0:
        floor = fallback
    else:
        floor = 1.0
    return np.where(free, np.maximum(values, floor), values)


def _inverse(values: np.ndarray) -> np.ndarray:
    """1 / m where m > 0, 0 elsewhere (DOFs without mass never move)."""
    positive = values > 0
    return np.where(positive, 1.0 / np.where(positive, values, 1.0), 0.0)
