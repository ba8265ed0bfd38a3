"""Frictionless penalty contact between two deformable shells: the lower face of an upper ply
against the upper face of a lower ply (the stack as plies, docs/theory.md "The stack as
plies"); an interaction (femcore.interaction) of a node set with a set of triangles.

Surfaces. The upper ply's lower face at a node is p = x - a d (x the node, d its unit director,
a the upper ply's half thickness, mm). The lower ply's upper face over a triangle is the flat
triangle through its corners' offset points y_k = x_k + b d_k (b the lower ply's half
thickness). Offsetting the lower face along the nodes' directors (not along the triangle's
normal) is the shell's own map: a Reissner-Mindlin or fibrous triangle places its top face at
x = sum N_k (x_k + h/2 V_k) (Bai Eq. 5), which is exactly that flat triangle, so the contact
face is the element's face, continuous from one triangle to the next (a facet-normal offset
would open and close cracks of h/2 times the angle between facets at every edge), and the
two faces are built the same way. The price is that the contact acts on the directors of both
plies (moments a F x d), which the tangent below carries.

Gap and energy. Each upper node faces the triangle of the lower face nearest to it (below);
its gap is the signed distance of p to that triangle's plane, g = (p - y_1) . n, n the unit
normal of the offset triangle (towards the upper ply: the lower ply's triangles must be
counter-clockwise about the direction from the lower ply to the upper). The energy is
W = k/2 g^2 for g < 0 (penetration), 0 otherwise, so the force is its exact gradient: on p,
dW/dp = k g n; on the corners, dW/dy_k = -k g lambda_k n, lambda the barycentric coordinates
of the projection of p (the surface point held by them: the derivative of the distance to the
plane brings no other term, see ``PlyContactBlock.tangent``); through the offsets the moments
dW/dpsi = a (dW/dp) x d at the upper node and b d_k x (dW/dy_k) at the corners.

Search, refreshed at every call. A cKDTree over the current centroids of the offset
triangles gives each node ``candidates`` triangles; over them (vectorised, no loop over nodes)
the barycentric projection of p and the approximate distance to the triangle sqrt(g^2 +
(o sqrt(2 A))^2), o = max(0, -min lambda) the projection's overshoot past the triangle's edges;
the facing triangle is, among those that hold the projection, the one p penetrates most
(over a concave fold two do), and when none holds it (over a convex fold, or past the
ply's edge) the nearest. A node touches when g < 0 and its overshoot is at most
``MARGIN`` (the plane of the last triangle carries a node that overhangs the lower ply's
free edge by up to half a cell; further out it is off the ply). Rebuilding the tree costs
O(m log m) per call, small against the shells' forces at the sizes of a ply stack (measured
in benchmarks/plies.py), and no cache needs a proof that it is still valid. Within a region
where the facing triangle does not change the energy is smooth (quadratic in g); where a
node passes from one triangle to the next the plane changes, and the energy jumps by
k g^2 (1 - cos phi) / 2 at most, phi the angle between the two facets (second order in
the small penetration).

Penalty: given (N/mm per upper node), or chosen when the model is compiled (``calibrate``):
k_i = ``PENALTY_SHARE`` m_i (2 / dt)^2, m_i the upper node's lumped mass and dt the model's
critical step without the contact, as elements/contact.py. ``springs`` reports 2 k at the upper
nodes and at the lower ones (a spring between a node and a triangle adds at most k (1 / m_u +
sum lambda_k^2 / m_k) to omega^2, which springs of 2 k to the ground at both bound when the
plies are meshed alike), so the explicit step takes the penalty in. Frictionless only: a
Coulomb friction between plies (anchors on the lower face carried by barycentric coordinates)
is not implemented.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.spatial import cKDTree

from femcore.assembly import CellTangent
from femcore.interaction import Body, Interaction, InteractionBlock
from femcore.state import State

__all__ = ["MARGIN", "PENALTY_SHARE", "Facing", "PlyContact", "PlyContactBlock"]

PENALTY_SHARE = 0.1  # k m^-1 / omega_max^2 of the automatic penalty (as elements/contact.py)
#: How far past a triangle's edges (in barycentric units) its plane still carries a node.
MARGIN = 0.5
#: Barycentric overshoot below which a projection counts as inside a triangle (round-off of
#: a node right above a vertex or an edge).
INSIDE = 1e-9
#: Triangles examined per node (the nearest centroids).
CANDIDATES = 6


def _cross_matrix(v: np.ndarray) -> np.ndarray:
    """(..., 3, 3) the matrices [v]x with [v]x w = v x w."""
    out = np.zeros(v.shape[:-1] + (3, 3))
    out[..., 0, 1], out[..., 0, 2] = -v[..., 2], v[..., 1]
    out[..., 1, 0], out[..., 1, 2] = v[..., 2], -v[..., 0]
    out[..., 2, 0], out[..., 2, 1] = -v[..., 1], v[..., 0]
    return out


class PlyContact(Interaction):
    """Frictionless penalty contact of the upper ply's lower face with the lower ply's upper
    face (module docstring).

    Parameters
    ----------
    upper : str or (s,) int
        The upper ply's nodes: a node-set name of the mesh or node ids.
    lower : str or (m,) int
        The lower ply's triangles: a triangle cell-set name of the mesh or triangle ids
        (counter-clockwise about the direction towards the upper ply).
    upper_offset, lower_offset : float, optional
        The half thicknesses a and b of the upper and lower ply, mm (the faces' distances
        from the mid-surfaces along the directors); None: half the thickness of the elements
        at the nodes (``Body.half_thickness``).
    penalty : float, optional
        k, N/mm per upper node; None: chosen when the model is compiled (module docstring).
    candidates : int
        Triangles examined per node by the search (the nearest centroids), >= 1.

    Raises
    ------
    ValueError
        Empty or non-integer selections, a negative or non-finite offset, a penalty that is
        not a positive number, fewer than one candidate; at bind, unknown set names, ids out
        of range, nodes of the upper set that are corners of the lower triangles, nodes
        without directors.
    """

    dofs = ("ux", "uy", "uz", "alpha", "beta")

    def __init__(
        self,
        upper: str | np.ndarray | list[int],
        lower: str | np.ndarray | list[int],
        upper_offset: float | None = None,
        lower_offset: float | None = None,
        penalty: float | None = None,
        candidates: int = CANDIDATES,
    ):
        self.upper = upper if isinstance(upper, str) else _ids(upper, "upper node")
        self.lower = lower if isinstance(lower, str) else _ids(lower, "lower triangle")
        for name, value in (("upper_offset", upper_offset), ("lower_offset", lower_offset)):
            if value is not None and not (
                isinstance(value, (int, float)) and np.isfinite(value) and value >= 0
            ):
                raise ValueError(f"{name} must be a finite number >= 0 (mm) or None, got {value!r}")
        self.upper_offset, self.lower_offset = upper_offset, lower_offset
        if penalty is not None and not (
            isinstance(penalty, (int, float)) and np.isfinite(penalty) and penalty > 0
        ):
            raise ValueError(f"penalty must be a positive number (N/mm) or None, got {penalty!r}")
        self.penalty = penalty
        if isinstance(candidates, bool) or not isinstance(candidates, (int, np.integer)):
            raise ValueError(f"candidates must be an integer >= 1, got {candidates!r}")
        if candidates < 1:
            raise ValueError(f"candidates must be an integer >= 1, got {candidates!r}")
        self.candidates = int(candidates)

    def bind(self, body: Body) -> PlyContactBlock:
        mesh = body.mesh
        if isinstance(self.upper, str):
            if self.upper not in mesh.node_sets:
                raise ValueError(
                    f"PlyContact: no node set named {self.upper!r}: the mesh has "
                    f"{sorted(mesh.node_sets) or 'none'}"
                )
            upper = np.asarray(mesh.node_sets[self.upper], dtype=np.int64)
        else:
            upper = self.upper
        triangles = mesh.triangles
        if isinstance(self.lower, str):
            sets = mesh.cell_sets("triangle")
            if self.lower not in sets:
                raise ValueError(
                    f"PlyContact: no triangle set named {self.lower!r}: the mesh has "
                    f"{sorted(sets) or 'none'}"
                )
            lower = np.asarray(sets[self.lower], dtype=np.int64)
        else:
            lower = self.lower
        if upper.size == 0 or lower.size == 0:
            raise ValueError("PlyContact: the upper node set and the lower triangles must be given")
        if upper.max() >= mesh.n_nodes:
            raise ValueError(
                f"PlyContact: upper node {int(upper.max())} out of range (mesh has "
                f"{mesh.n_nodes} nodes)"
            )
        if lower.max() >= len(triangles):
            raise ValueError(
                f"PlyContact: lower triangle {int(lower.max())} out of range (mesh has "
                f"{len(triangles)} triangles)"
            )
        cells = triangles[lower]
        shared = np.intersect1d(upper, cells)
        if shared.size:
            raise ValueError(
                f"PlyContact: node {int(shared[0])} is both an upper node and a corner of a "
                "lower triangle: the plies must be separate meshes"
            )
        without = np.linalg.norm(body.directors[np.union1d(upper, cells)], axis=1) == 0.0
        if without.any():
            raise ValueError(
                "PlyContact acts on shells with directors: a node of the contact has none "
                "(add the plies' shell elements before compiling)"
            )
        half = body.half_thickness()
        a = half[upper] if self.upper_offset is None else np.full(upper.size, self.upper_offset)
        b = half if self.lower_offset is None else np.full(mesh.n_nodes, self.lower_offset)
        return PlyContactBlock(self, upper, cells, a, b, body)


def _ids(given: Any, what: str) -> np.ndarray:
    array = np.atleast_1d(np.asarray(given))
    if array.size == 0:
        raise ValueError(f"PlyContact: empty {what} selection")
    if array.dtype == bool or not np.issubdtype(array.dtype, np.integer):
        raise ValueError(f"PlyContact: {what} ids must be integers, got {array.dtype}")
    if array.min() < 0:
        raise ValueError(f"PlyContact: {what} id {int(array.min())} is negative")
    return np.unique(array.astype(np.int64))


@dataclass(frozen=True)
class Facing:
    """Each upper node's facing triangle at a state (``PlyContactBlock.facing``).

    triangle : (s,) int
        Row of the block's lower triangles facing each node.
    gap : (s,) float
        g, mm: signed distance of the node's face point from the facing offset triangle's
        plane (< 0: penetration).
    normal : (s, 3) float
        Unit normal n of the facing offset triangle (towards the upper ply).
    weights : (s, 3) float
        Barycentric coordinates lambda of the projection of the face point.
    gradients : (s, 3, 3) float
        In-plane gradients of the triangle's barycentric functions, 1/mm (row k: grad phi_k).
    touching : (s,) bool
        g <= 0 (up to 1e-9 of the mesh's size: plies laid on each other touch) and the
        projection within ``MARGIN`` of the triangle.
    face : (s, 3) float
        The face points p = x - a d, mm.
    """

    triangle: np.ndarray
    gap: np.ndarray
    normal: np.ndarray
    weights: np.ndarray
    gradients: np.ndarray
    touching: np.ndarray
    face: np.ndarray


def _triangle_frames(corners: np.ndarray):
    """Unit normals (..., 3), twice the areas (...,) and the barycentric gradients
    (..., 3, 3) of triangles with corners (..., 3, 3)."""
    y1, y2, y3 = corners[..., 0, :], corners[..., 1, :], corners[..., 2, :]
    c = np.cross(y2 - y1, y3 - y1)
    area2 = np.linalg.norm(c, axis=-1)
    n = c / area2[..., None]
    edges = np.stack([y3 - y2, y1 - y3, y2 - y1], axis=-2)  # opposite corner k, cyclic
    gradients = np.cross(n[..., None, :], edges) / area2[..., None, None]
    return n, area2, gradients


class PlyContactBlock(InteractionBlock):
    """The bound ply contact: one row of ``connectivity`` per upper node, the node then the
    corners of the triangles it faces in the reference state and their neighbours (the node
    graph of a finite-difference tangent while the plies have slid less than a cell; the
    block's own ``tangent`` follows the sliding)."""

    dofs = PlyContact.dofs
    reach = 1
    n_tools = 0

    def __init__(
        self,
        contact: PlyContact,
        upper: np.ndarray,
        cells: np.ndarray,
        upper_offset: np.ndarray,
        lower_offset: np.ndarray,
        body: Body,
    ):
        self.upper = upper
        self.cells = cells
        self.n_nodes = body.n_nodes
        self.upper_offset = np.asarray(upper_offset, dtype=float)
        self.corner_offset = np.asarray(lower_offset, dtype=float)[cells]  # (m, 3)
        self.candidates = min(contact.candidates, len(cells))
        given = contact.penalty
        self.stiffness = np.full(len(upper), np.nan if given is None else float(given))
        reference = State(
            body.mesh.points.copy(),
            body.directors.copy(),
            np.zeros((self.n_nodes, 3)),
            np.zeros((self.n_nodes, 3)),
        )
        near = self._candidates(reference)[1][:, : min(3, self.candidates)]
        self.connectivity = np.column_stack([upper, cells[near].reshape(len(upper), -1)])
        self.lower_nodes = np.unique(cells)
        # Plies laid on each other touch (g = 0 up to the rounding of the offsets): they
        # count as touching, so that Newton has the contact's stiffness from its first
        # iteration (the force, k min(g, 0), is still zero there).
        size = float(np.ptp(body.mesh.points, axis=0).max(initial=0.0)) or 1.0
        self.tolerance = 1e-9 * size

    def calibrate(self, mass: np.ndarray, stable_dt: float) -> None:
        if np.isnan(self.stiffness).any():  # the automatic penalty (module docstring)
            self.stiffness = PENALTY_SHARE * mass[self.upper] * (2.0 / stable_dt) ** 2

    # ------------------------------------------------------------------ search
    def _faces(self, state: State) -> tuple[np.ndarray, np.ndarray]:
        """Face points p (s, 3) of the upper nodes and offset corners y (m, 3, 3), mm."""
        x, d = state.positions, state.directors
        p = x[self.upper] - self.upper_offset[:, None] * d[self.upper]
        y = x[self.cells] + self.corner_offset[:, :, None] * d[self.cells]
        return p, y

    def _candidates(self, state: State):
        p, y = self._faces(state)
        tree = cKDTree(y.mean(axis=1))
        _, near = tree.query(p, k=self.candidates)
        return p, np.asarray(near).reshape(len(p), self.candidates), y

    def facing(self, state: State) -> Facing:
        """Each upper node's facing triangle, gap, normal and projection at ``state``
        (module docstring: the nearest of the candidates)."""
        p, near, y = self._candidates(state)
        corners = y[near]  # (s, K, 3, 3)
        n, area2, gradients = _triangle_frames(corners)
        relative = p[:, None, :] - corners[..., 0, :]
        gap = np.sum(relative * n, axis=-1)  # (s, K)
        weights = np.einsum("skij,skj->ski", gradients, p[:, None, :] - corners[..., 1, :])
        weights[..., 1] = np.einsum("ski,ski->sk", gradients[..., 1, :], relative)
        weights[..., 2] = 1.0 - weights[..., 0] - weights[..., 1]
        overshoot = np.maximum(0.0, -weights.min(axis=-1))
        distance = np.hypot(gap, overshoot * np.sqrt(area2))
        # Over a concave fold two triangles hold the projection: the deeper penetration
        # counts (W = k/2 max(p_A, p_B)^2 is convex in the pair, a kink Newton crosses);
        # over a convex one none holds it: the nearest triangle.
        inside = overshoot <= INSIDE
        best = np.where(
            inside.any(axis=1),
            np.argmin(np.where(inside, gap, np.inf), axis=1),
            np.argmin(distance, axis=1),
        )
        rows = np.arange(len(p))
        chosen_gap = gap[rows, best]
        touching = (chosen_gap <= self.tolerance) & (overshoot[rows, best] <= MARGIN)
        return Facing(
            triangle=near[rows, best],
            gap=chosen_gap,
            normal=n[rows, best],
            weights=weights[rows, best],
            gradients=gradients[rows, best],
            touching=touching,
            face=p,
        )

    # ------------------------------------------------------------------ loads
    def _pair_loads(self, state: State, facing: Facing):
        """Per touching node: node rows (t, 4) (the node, the triangle's corners), forces
        (t, 4, 3) N and moments (t, 4, 3) N mm, dW/dx and dW/dpsi."""
        on = np.flatnonzero(facing.touching)
        k = self.stiffness[on]
        g, n, lam = np.minimum(facing.gap[on], 0.0), facing.normal[on], facing.weights[on]
        tri = facing.triangle[on]
        nodes = np.column_stack([self.upper[on], self.cells[tri]])
        on_face = (k * g)[:, None] * n  # dW/dp
        forces = np.concatenate([on_face[:, None, :], -lam[:, :, None] * on_face[:, None, :]], 1)
        d = state.directors[nodes]  # (t, 4, 3)
        offset = np.column_stack([-self.upper_offset[on], self.corner_offset[tri]])
        # p = x - a d, y_k = x_k + b d_k: dW/dpsi = (signed offset) d x dW/dpoint.
        moments = offset[:, :, None] * np.cross(d, forces)
        return nodes, forces, moments, on, offset

    def internal_force(self, state: State, history: Any = None):
        facing = self.facing(state)
        nodes, forces, moments, *_ = self._pair_loads(state, facing)
        flat = nodes.ravel()
        force = np.zeros((self.n_nodes, 3))
        moment = np.zeros((self.n_nodes, 3))
        for axis in range(3):
            force[:, axis] = np.bincount(flat, forces[..., axis].ravel(), self.n_nodes)
            moment[:, axis] = np.bincount(flat, moments[..., axis].ravel(), self.n_nodes)
        return force, moment

    def strain_energy(self, state: State, history: Any = None) -> float:
        """sum k g^2 / 2 over the touching nodes, N mm."""
        facing = self.facing(state)
        g = np.where(facing.touching, np.minimum(facing.gap, 0.0), 0.0)
        return float(0.5 * np.sum(self.stiffness * g**2))

    def tangent(self, state: State, history: Any = None) -> list[CellTangent]:
        """Exact d(force, moment)/d(u, psi) of the touching pairs, (t, 4, 6, 4, 6).

        Over the face points z = (p, y_1, y_2, y_3): Hess W = k (G G^T + g H) with G =
        (n, -lambda_k n) the gradient of g and H its Hessian, from dn/dy_m = -grad phi_m n^T
        and dlambda_k = grad phi_k . (dp - g dn - sum_m lambda_m dy_m): H_pp = 0, H_p,m =
        -grad phi_m n^T, H_k,m = -g (grad phi_k . grad phi_m) n n^T + lambda_m n grad phi_k^T
        + lambda_k grad phi_m n^T. Carried to the nodes by dz = du + c [d]x psi (c = a for p,
        -b for y_k, psi the director's rotation), with the geometric term of the turned
        offset, d(c d x F)/dpsi = -c (d F^T - (F . d) I), on each node's psi-psi block.
        """
        facing = self.facing(state)
        nodes, forces, _, on, offset = self._pair_loads(state, facing)
        t = len(on)
        k = self.stiffness[on][:, None, None, None, None]
        g = np.minimum(facing.gap[on], 0.0)
        n, lam, grad = facing.normal[on], facing.weights[on], facing.gradients[on]
        gradient = np.concatenate([n[:, None, :], -lam[:, :, None] * n[:, None, :]], axis=1)
        hessian = np.zeros((t, 4, 3, 4, 3))
        nn = n[:, :, None] * n[:, None, :]
        for m in range(3):
            hessian[:, 0, :, 1 + m, :] = -grad[:, m, :, None] * n[:, None, :]
            hessian[:, 1 + m, :, 0, :] = -n[:, :, None] * grad[:, m, None, :]
        dots = np.einsum("tki,tmi->tkm", grad, grad)
        for a_ in range(3):
            for m in range(3):
                hessian[:, 1 + a_, :, 1 + m, :] = (
                    -(g * dots[:, a_, m])[:, None, None] * nn
                    + lam[:, m, None, None] * n[:, :, None] * grad[:, a_, None, :]
                    + lam[:, a_, None, None] * grad[:, m, :, None] * n[:, None, :]
                )
        outer = gradient[:, :, :, None, None] * gradient[:, None, None, :, :]
        points = k * (outer + g[:, None, None, None, None] * hessian)  # (t, 4, 3, 4, 3)
        d = state.directors[nodes]
        # z = x + c d (c = -a for the face point, b for the corners): dz = du + c psi x d
        # = du - c [d]x psi.
        maps = np.zeros((t, 4, 3, 6))
        maps[:, :, :, :3] = np.eye(3)
        maps[:, :, :, 3:] = -offset[:, :, None, None] * _cross_matrix(d)
        blocks = np.einsum("tria,trisj,tsjb->trasb", maps, points, maps)
        # The moment c' d x F turns with the director (F held): d(c' d x F)/dpsi =
        # c' (psi x d) x F = c' (d F^T - (F . d) I) psi.
        geometric = offset[:, :, None, None] * (
            d[:, :, :, None] * forces[:, :, None, :]
            - np.sum(forces * d, axis=-1)[:, :, None, None] * np.eye(3)
        )
        for row in range(4):
            blocks[:, row, 3:, row, 3:] += geometric[:, row]
        return [CellTangent(nodes, blocks)]

    # ------------------------------------------------------------------ protocol extras
    def springs(self) -> tuple[np.ndarray, np.ndarray]:
        """2 k at the upper nodes and 2 max(k) (times the ratio of upper to lower nodes
        when above 1) at the lower ones, N/mm (module docstring)."""
        ratio = max(1.0, len(self.upper) / len(self.lower_nodes))
        lower = np.full(len(self.lower_nodes), 2.0 * ratio * float(np.max(self.stiffness)))
        return (
            np.concatenate([self.upper, self.lower_nodes]),
            np.concatenate([2.0 * self.stiffness, lower]),
        )

    def node_fields(self, state: State, history: Any = None) -> dict[str, np.ndarray]:
        """ply_gap (mm, the signed gap g of each upper node to the face below, < 0 a
        penetration; NaN off the upper nodes and where the node faces no triangle) and
        ply_contact_force (k max(-g, 0), N; 0 off the upper nodes)."""
        facing = self.facing(state)
        overshoot = np.maximum(0.0, -facing.weights.min(axis=1))
        gap = np.full(self.n_nodes, np.nan)
        gap[self.upper] = np.where(overshoot <= MARGIN, facing.gap, np.nan)
        force = np.zeros(self.n_nodes)
        force[self.upper] = -self.stiffness * np.where(
            facing.touching, np.minimum(facing.gap, 0.0), 0.0
        )
        return {"ply_gap": gap, "ply_contact_force": force}
