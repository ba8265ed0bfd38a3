"""Symmetry planes of the rotation-free bending (docs/theory.md §4.5, "Symmetry plane"): the
``symmetric`` option of FibrousShell read into the block's sides and the projection of its
nodes' normal sums, and the supports a plane needs checked.

A boundary side on a symmetry plane bends against the mirror image of its own cell (the
ghost element of the rotation-free shells' symmetry edges: Onate and Zarate's BST, Flores and
Onate): the ghost's normal is n_g = R n with R = I - 2 p p^T, its height over the side is the
cell's own, and the fold angle between the two, theta_s = 2 phi, is twice the cell's fold
against the wall through the side perpendicular to the plane, w = (p x t) / |p x t| (t the
side in the cell's own direction, p signed so that w is the cell's reference normal on a
sheet that meets the plane at a right angle). With the two cells' heights, c_as = 2 (u_a .
n^c_s)^2 / (2 h_s) is half the clamp's, and the fold's variation twice the cell's own share,
2 D[s, k] n, while the side stays in the plane: c_as theta_s = c_clamp phi and the side moment
times its gradient is the clamp's. So a symmetry side is a clamped side (``clamped_side``)
whose wall is w of its current side instead of the reference plane (``mirror_normal``, the
signed p of each such side, 0 elsewhere): the forces, the energy (the half of the symmetric
whole's) and the tangent are the clamp's with that wall.

The plane's nodes must keep their translation along p and the turn of their director out of
the plane fixed (the side then stays in the plane, where theta_s's variation is exact).

A plane node's nodal normal sum (docs/theory.md §1.4) is the whole's: over the half's cells
around it and their mirror images, S + R S = 2 (I - p p^T) S, the half's sum projected on the
plane (on two planes, on both: their line); the factor 2 leaves N = S / |S| alone. The
projection zeroes the sum's component along p (a coordinate axis), and the sum's variation
and the pull dW/dS_k are projected alike (``plane_keep``, ``corner_keep``).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from elements.fibrous.geometry import SIDE_FROM, SIDE_TO
from femcore.entry_error import OptionError
from femcore.mesh import Mesh
from femcore.rotation import nodal_frames

if TYPE_CHECKING:
    from elements.fibrous.block import FibrousShellBlock

__all__ = [
    "check_plane_supports",
    "corner_keep",
    "on_planes",
    "plane_projection",
    "symmetry_sides",
]

# How far a plane's nodes may lie off it, as a share of the block's extent; how close to a
# coordinate axis its normal must be (the supports fix a global translation along it).
PLANE_TOLERANCE = 1e-6
# How far the sides' planes (perpendicular to their cells) may lean from the symmetry plane:
# a faceted curved shell's cells lean by half their facet angle (5 deg for 10-deg facets of a
# cylinder cut along its crown); 30 deg is a facet of 60 deg, coarser than any mesh that
# bends well.
LEAN = np.radians(30.0)
AXES = ("ux", "uy", "uz")


def node_sets(mesh: Mesh, given, option: str = "symmetric") -> list[np.ndarray]:
    """The node ids of each set of a node-set option (``symmetric``, ``clamped``): one node
    set (a set name or node ids) or a list of them. OptionError (a ValueError that a case file
    places at the option's key) naming ``option`` for an empty list, an item that is neither,
    fractional or out-of-range ids; ValueError for an unknown set name (the mesh's)."""
    if given is None:
        return []
    several = isinstance(given, (list, tuple)) and all(
        isinstance(item, str) or np.ndim(item) >= 1 for item in given
    )
    sets = list(given) if several else [given]
    if not sets:
        raise OptionError(
            f"{option}: give a node set (a name or node ids) or a list of them", option
        )
    nodes = []
    for item in sets:
        if isinstance(item, str):
            ids = mesh.nodes(item)
        else:
            ids = _whole_ids(mesh, item, option)
        nodes.append(np.asarray(ids, dtype=np.int64))
    return nodes


def _whole_ids(mesh: Mesh, item, option: str) -> np.ndarray:
    """Node ids ``item`` as int64 (unique), or OptionError naming ``option``: not numbers,
    fractional (a cast would truncate 0.9 to node 0 silently), or out of the mesh's range."""
    try:
        array = np.asarray(item, dtype=float).ravel()
    except (TypeError, ValueError):
        raise OptionError(
            f"{option}: a node set is a name or node ids, got {item!r}", option
        ) from None
    if isinstance(item, (bool, np.bool_)) or np.asarray(item).dtype == bool:
        raise OptionError(f"{option}: a node set is a name or node ids, got {item!r}", option)
    if not np.all(np.isfinite(array)) or np.any(array != np.round(array)):
        raise OptionError(
            f"{option}: node ids must be integers, got {item!r}: give whole node ids or a "
            "node-set name",
            option,
        )
    ids = np.unique(array.astype(np.int64))
    if ids.size and (ids.min() < 0 or ids.max() >= mesh.n_nodes):
        raise OptionError(f"{option}: node ids must be in 0..{mesh.n_nodes - 1}", option)
    return ids


def symmetry_sides(
    mesh: Mesh,
    connectivity: np.ndarray,
    neighbour: np.ndarray,
    reference_normal: np.ndarray,
    symmetric,
) -> np.ndarray:
    """The signed plane normal p (m, 3, 3) of each side of the cells ``connectivity`` (m, 3)
    on a symmetry plane of the ``symmetric`` option (0 on the others).

    A plane's sides are the boundary sides (``neighbour`` -1) whose two nodes are in its set;
    its normal p is the coordinate axis nearest the mean of the sides' planes (each
    perpendicular to its side and to its cell's ``reference_normal`` (m, 3), leaning from
    the plane by half a facet angle on a curved shell), signed per side so that p x t points
    along the cell's normal (t the side from ``SIDE_FROM`` to ``SIDE_TO``).

    Raises ValueError when a set makes no boundary side, when its sides' planes differ by more
    than ``LEAN`` from their mean, when its nodes do not lie on one coordinate plane (within
    ``PLANE_TOLERANCE`` of the block's extent; a plane whose normal is no coordinate axis
    said so), or when the shell meets it more than ``LEAN`` from a right angle.
    """
    points = np.asarray(mesh.points, dtype=float)
    used = points[np.unique(connectivity)]
    extent = float(np.linalg.norm(used.max(axis=0) - used.min(axis=0)))
    mirror = np.zeros(connectivity.shape + (3,))
    for number, nodes in enumerate(node_sets(mesh, symmetric)):
        member = np.zeros(mesh.n_nodes, dtype=bool)
        member[nodes] = True
        sides = member[connectivity[:, SIDE_FROM]] & member[connectivity[:, SIDE_TO]]
        sides &= neighbour < 0
        cell, side = np.nonzero(sides)
        if cell.size == 0:
            raise ValueError(
                f"symmetric: node set {number} makes no boundary edge of the block; a "
                "symmetry plane is a line of the shell's boundary edges (both nodes in the set)"
            )
        conn = connectivity[cell]
        t = points[conn[np.arange(cell.size), SIDE_TO[side]]]
        t = t - points[conn[np.arange(cell.size), SIDE_FROM[side]]]
        normal = np.cross(t, reference_normal[cell])
        normal /= np.linalg.norm(normal, axis=1, keepdims=True)
        # the sides' planes, perpendicular to the shell: on a faceted curved shell each leans
        # from the plane by half its cell's facet angle, so they are judged against their
        # mean, within LEAN (a shell meeting its plane at a right angle)
        mean = (normal * np.sign(normal @ normal[0])[:, None]).sum(axis=0)
        mean /= np.linalg.norm(mean)
        spread = float(np.arccos(np.clip(np.abs(normal @ mean), 0.0, 1.0)).max())
        if spread > LEAN:
            raise ValueError(
                f"symmetric: the edges of node set {number} do not lie in one plane normal to "
                f"the shell (their planes' normals differ by up to {spread:.2g} rad); give one "
                "set a plane"
            )
        axis = int(np.argmax(np.abs(mean)))
        p = np.zeros(3)
        p[axis] = 1.0
        off = np.abs((points[nodes] - points[nodes[0]]) @ p).max()
        if off > PLANE_TOLERANCE * extent:
            if 1.0 - abs(mean[axis]) > PLANE_TOLERANCE:
                raise ValueError(
                    f"symmetric: node set {number}'s plane has the normal "
                    f"{np.round(mean, 6).tolist()}, not a coordinate axis: its nodes must be "
                    "held along the normal with model.fix, which fixes ux, uy or uz"
                )
            raise ValueError(
                f"symmetric: node set {number} is not on one plane: its nodes lie up to "
                f"{off:.3g} mm apart along the plane's normal {AXES[axis][1]}"
            )
        lean = float(np.arccos(np.clip(abs(mean[axis]), 0.0, 1.0)))
        if lean > LEAN:
            raise ValueError(
                f"symmetric: the shell meets node set {number}'s plane ({AXES[axis][1]} = "
                f"{points[nodes[0], axis]:.6g}) {np.degrees(lean):.3g} deg from a right "
                "angle: a symmetric shell meets its plane at a right angle (a coarse facet "
                f"leans by half its angle; at most {np.degrees(LEAN):.3g} deg here)"
            )
        mirror[cell, side] = np.sign(normal @ p)[:, None] * p
    return mirror


def check_plane_supports(
    block: FibrousShellBlock, held: np.ndarray, constrained: np.ndarray | None
) -> None:
    """Refuse (ValueError) a symmetry plane whose nodes the supports leave free to leave it:
    at each node of a symmetry side not ``held`` (n,), ``constrained`` (n, 5) (the block's
    DOFs ux, uy, uz, alpha, beta fixed or prescribed) must hold the translation along the
    plane's normal p and each director DOF that turns the director out of the plane (alpha
    turns it towards V1, beta towards -V2, docs/theory.md §1.3: the one whose |V1 . p| or
    |V2 . p| exceeds 1e-9 at the reference). Nothing is checked when ``constrained`` is None.
    """
    if constrained is None or not block.mirror_normal.any():
        return
    v1, v2 = nodal_frames(block.reference_directors)
    cell, side = np.nonzero(np.any(block.mirror_normal != 0.0, axis=-1))
    for ends in (SIDE_FROM, SIDE_TO):
        nodes = block.connectivity[cell, ends[side]]
        p = np.abs(block.mirror_normal[cell, side])
        axis = np.argmax(p, axis=1)
        needed = np.zeros((nodes.size, 5), dtype=bool)
        needed[np.arange(nodes.size), axis] = True
        needed[:, 3] = np.abs(np.sum(v1[nodes] * p, axis=1)) > 1e-9
        needed[:, 4] = np.abs(np.sum(v2[nodes] * p, axis=1)) > 1e-9
        loose = needed & ~constrained[nodes] & ~held[nodes, None]
        if loose.any():
            row = int(np.flatnonzero(loose.any(axis=1))[0])
            names = [name for name, free in zip(block.dofs, loose[row]) if free]
            raise ValueError(
                f"symmetric: node {int(nodes[row])} of a symmetry plane must have "
                f"{', '.join(names)} fixed with model.fix (the translation along the plane's "
                "normal and the director's turn out of the plane: a symmetry plane keeps its "
                "nodes and directors in it)"
            )


def plane_projection(
    connectivity: np.ndarray, symmetry_normal: np.ndarray, n_nodes: int
) -> tuple[np.ndarray, np.ndarray]:
    """The nodes of the symmetry sides (p,) int and, for each, (p, 3) float the factors 1.0,
    or 0.0 on the components along its planes' normals, that project its normal sum on them;
    from the cells' nodes ``connectivity`` (m, 3) and the sides' signed plane normals
    ``symmetry_normal`` (m, 3, 3) (``symmetry_sides``)."""
    cell, side = np.nonzero(np.any(symmetry_normal != 0.0, axis=-1))
    keep = np.ones((n_nodes, 3))
    factor = 1.0 - np.abs(symmetry_normal[cell, side])  # 0 along the plane's axis
    for ends in (SIDE_FROM, SIDE_TO):
        np.minimum.at(keep, connectivity[cell, ends[side]], factor)
    ids = np.flatnonzero((keep != 1.0).any(axis=1))
    return ids, keep[ids]


def corner_keep(block: FibrousShellBlock, nodes: np.ndarray) -> np.ndarray | None:
    """The projection factors (..., 3) of ``plane_projection`` at the nodes ``nodes`` (...,)
    int (1.0 off the planes), or None when the block has no symmetry plane."""
    if not block.plane_node_ids.size:
        return None
    keep = np.ones((block.n_nodes, 3))
    keep[block.plane_node_ids] = block.plane_keep
    return keep[nodes]


def on_planes(block: FibrousShellBlock, nodes: np.ndarray, ds_dx: np.ndarray) -> np.ndarray:
    """The corner shares' Jacobians ``ds_dx`` (m, 3 k, 3 i, 3 j, 3 c) of the cells whose
    corners are ``nodes`` (m, 3), their rows i projected on the symmetry planes at the planes'
    nodes (the sums' variation, as the sums); ``ds_dx`` itself without a plane."""
    keep = corner_keep(block, nodes)
    return ds_dx if keep is None else ds_dx * keep[..., None, None]
