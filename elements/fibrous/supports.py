"""Where the rotation-free bending meets the supports (docs/theory.md §4.5): the side tables
of a block (which sides couple two cells, which bend against a clamped wall, which cells are
held), the ``clamped`` option checked against the supports, and the wall normals of the held
nodes.

A side with both nodes clamped couples no two cells and is a clamped side of each cell that
has a node not clamped: it bends against the wall of its reference plane. A held cell (three
nodes clamped) has no fold at all. A held node's nodal normal is the wall's (the reference
one), not the mean of the cells that bend away from it (docs/theory.md §1.4).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from elements.fibrous import bending, geometry
from elements.fibrous.geometry import SIDE_FROM, SIDE_TO
from elements.fibrous.symmetry import check_plane_supports, node_sets
from femcore.entry_error import OptionError
from femcore.mesh import Mesh

if TYPE_CHECKING:
    from elements.fibrous.block import FibrousShellBlock

__all__ = [
    "apply_supports",
    "clamped_sides",
    "neighbour_sides",
    "requested_clamp",
    "set_sides",
    "shared_sides",
    "wall_moments",
]


def neighbour_sides(neighbour: np.ndarray) -> np.ndarray:
    """For each (cell, side) with a neighbour, the side index of the shared edge in the
    neighbour (-1 on free sides); ``neighbour`` (m, 3) the cell across each side (-1 on free
    sides)."""
    m = len(neighbour)
    nb = np.where(neighbour >= 0, neighbour, 0)
    back = neighbour[nb] == np.arange(m)[:, None, None]  # (m, 3 sides, 3 neighbour sides)
    side = np.argmax(back, axis=2)
    return np.where(neighbour >= 0, side, -1)


def clamped_sides(
    connectivity: np.ndarray, clamp: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """From the clamped nodes ``clamp`` (n,) bool and the cells' nodes ``connectivity``
    (m, 3): the clamped sides (m, 3) (both nodes clamped, in a cell with a node that is not),
    the sides with both nodes clamped (m, 3), and the held cells (m,) (all three nodes
    clamped)."""
    ends = clamp[connectivity[:, SIDE_FROM]] & clamp[connectivity[:, SIDE_TO]]
    held = clamp[connectivity].all(axis=1)
    return ends & ~held[:, None], ends, held


def requested_clamp(mesh: Mesh, connectivity: np.ndarray, clamped) -> np.ndarray:
    """The nodes (n,) bool of the ``clamped`` option (all False without it): node ids or a
    node-set name of ``mesh``, or a list of them as ``symmetric`` takes (their union; each
    set must make an edge); they must make at least one edge of the cells
    ``connectivity`` (m, 3). ValueError for fractional or out-of-range ids."""
    member = np.zeros(mesh.n_nodes, dtype=bool)
    if clamped is None:
        return member
    sets = node_sets(mesh, clamped, "clamped")
    for number, nodes in enumerate(sets):
        one = np.zeros(mesh.n_nodes, dtype=bool)
        one[nodes] = True
        if not clamped_sides(connectivity, one)[1].any():
            which = "the given set" if len(sets) == 1 else f"node set {number}"
            raise ValueError(
                f"clamped: no edge of the block has both its nodes in {which}; a clamped "
                "edge is a line of mesh edges (the shell's boundary, or an interior line)"
            )
        member |= one
    return member


def _fix_tables(block: FibrousShellBlock, loose: np.ndarray) -> str:
    """What a case file writes to hold the ``clamped`` option's ``loose`` nodes (k,) int: "a
    [[fix]] ..." table for each set of the option that has loose nodes (a set all of whose
    nodes the supports hold already is not named), in a form the case reader takes
    (fibreshell/case.py: a node-set name or a bounds table, no node ids): a set given by its
    name by that name; one given by node ids by the name of a mesh set of exactly its loose
    nodes, else by the bounds table (``_bounds_table``) that selects exactly them, else a
    [sets] entry to write (a list of ids cannot be one)."""
    option = block.clamped_option
    several = isinstance(option, list | tuple) and all(
        isinstance(item, str) or np.ndim(item) >= 1 for item in option
    )
    items = list(option) if several else [option]
    mesh = block.clamp_mesh
    assert mesh is not None  # a loose clamp has the option, whose mesh the block keeps
    tables = []
    for item, ids in zip(items, block.clamped_sets):
        left = np.intersect1d(ids, loose)
        if not left.size:
            continue  # held by the supports already
        if isinstance(item, str):
            tables.append(f'[[fix]] nodes = "{item}"')
            continue
        named = [
            name for name, nodes in mesh.node_sets.items() if np.array_equal(np.unique(nodes), left)
        ]
        bounds = None if named else _bounds_table(mesh, left)
        if named:
            tables.append(f'[[fix]] nodes = "{named[0]}"')
        elif bounds is not None:
            tables.append(f"[[fix]] nodes = {bounds}")
        else:
            tables.append(
                f"[[fix]] of a set of [sets] that holds nodes {left.tolist()} (the case "
                "reader takes a set's name or a bounds table, not node ids)"
            )
    return " and ".join(f"a {table}" for table in tables)


def _bounds_table(mesh: Mesh, nodes: np.ndarray) -> str | None:
    """The bounds table of a case file (fibreshell/case_sets.py) that selects exactly
    ``nodes`` (k,) int of ``mesh``: their bounding box, each bound that the extent of the
    nodes the cells use already sets left out; None where that box holds another used node.
    The case reader's default tolerance, 1e-6 of the mesh's largest extent, is the one
    checked; coordinates written to 12 digits, within it."""
    used = np.zeros(mesh.n_nodes, dtype=bool)
    for kind in mesh.cell_kinds:
        used[mesh.cells(kind).ravel()] = True
    points = np.asarray(mesh.points, dtype=float)
    low, high = points[used].min(axis=0), points[used].max(axis=0)
    tolerance = 1e-6 * float((high - low).max())
    chosen = points[nodes]
    first, last = chosen.min(axis=0), chosen.max(axis=0)
    bounds = []
    inside = used.copy()
    for axis, name in enumerate("xyz"):
        if first[axis] > low[axis] + tolerance:
            bounds.append(f"{name}_min = {float(f'{first[axis]:.12g}')!r}")
        if last[axis] < high[axis] - tolerance:
            bounds.append(f"{name}_max = {float(f'{last[axis]:.12g}')!r}")
        inside &= (points[:, axis] >= first[axis] - tolerance) & (
            points[:, axis] <= last[axis] + tolerance
        )
    if not bounds or not np.array_equal(np.flatnonzero(inside), np.unique(nodes)):
        return None
    return "{ " + ", ".join(bounds) + " }"


def set_sides(block: FibrousShellBlock, clamp: np.ndarray) -> None:
    """The block's side tables from the clamped nodes ``clamp`` (n,) bool: ``clamped_side``,
    ``held_cell``, ``interior_side`` and the gather indices ``across_cell``, ``across_side``.

    A side with both nodes clamped couples no two cells (``interior_side`` False in both)
    and is a clamped side of each cell that has a node not clamped: it bends against the
    wall of its reference plane. A held cell (three nodes clamped) has no fold at all, so
    zero curvature coefficients: its shape is imposed and it stores no bending energy.
    """
    block.clamped_side, ends, block.held_cell = clamped_sides(block.connectivity, clamp)
    # A symmetry side (symmetry.py) is a clamped side whose wall follows the side, unless
    # the supports hold its two nodes: then it is clamped against the reference plane.
    mirror = np.any(block.symmetry_normal != 0.0, axis=-1) & ~ends
    block.mirror_normal = np.where(mirror[..., None], block.symmetry_normal, 0.0)
    block.clamped_side = block.clamped_side | mirror
    block.interior_side = (block.neighbour >= 0) & ~ends
    # Gather indices with free sides pointing at cell 0, masked by interior_side.
    block.across_cell = np.where(block.interior_side, block.neighbour, 0)
    block.across_side = np.where(block.interior_side, block.neighbour_side, 0)
    block.shared_sides, block.shared_sign = shared_sides(
        block.connectivity, block.interior_side, block.neighbour, block.neighbour_side
    )


def shared_sides(
    connectivity: np.ndarray,
    interior: np.ndarray,
    neighbour: np.ndarray,
    neighbour_side: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """Each side that couples two cells once, for the loop that evaluates its fold angle
    once for both (geometry_kernels.py ``_side_folds``, docs/theory.md §4.1).

    Parameters
    ----------
    connectivity : (m, 3) int, the cells' nodes.
    interior : (m, 3) bool, the sides that couple a cell with its neighbour.
    neighbour, neighbour_side : (m, 3) int, the cell across each side and the side's index
        there (-1 on free sides).

    Returns
    -------
    table : (e, 2) int32 (int64 past 2**31 cells)
        Per side: its cell c (the lower index of the two) and its side s there. The cell
        across and its side there are the block's ``across_cell[c, s]``,
        ``across_side[c, s]``, and the side runs from node ``connectivity[c, SIDE_FROM[s]]``
        to ``connectivity[c, SIDE_TO[s]]``: not held twice (the table is 8 bytes a side
        where the six columns of all of them took 48, 27 MB at 400k cells).
    sign : (e,) int8
        +1 where the cell across runs the side from q to p (the two cells oriented alike:
        the fold is the same angle seen from either), -1 where it runs it from p to q (its
        normal flipped: the angle seen from it is the opposite); 0 where the cell across
        does not name c back (a side of more than two cells): c's side then has a row of
        its own, as has each of the other cells', and the row serves c alone.
    """
    m = len(connectivity)
    across = np.where(interior, neighbour, 0)
    back = np.where(interior, neighbour_side, 0)
    mutual = interior & (neighbour[across, back] == np.arange(m)[:, None])
    owned = interior & (~mutual | (np.arange(m)[:, None] < neighbour))
    cell, side = np.nonzero(owned)
    other, other_side = across[cell, side], back[cell, side]
    end = connectivity[cell, SIDE_TO[side]]
    index = np.int32 if m < 2**31 else np.int64
    table = np.column_stack([cell, side]).astype(index)
    reverse = connectivity[other, SIDE_FROM[other_side]] == end
    sign = np.where(mutual[cell, side], np.where(reverse, 1, -1), 0).astype(np.int8)
    return table, sign


def apply_supports(
    block: FibrousShellBlock, held: np.ndarray, constrained: np.ndarray | None = None
) -> None:
    """Clamp the block's rotation-free bending where the model holds the nodes: every node
    ``held`` (n,) bool (translations and directors fixed or prescribed) is a clamped node, as
    are those of the ``clamped`` option, which must be held. Sets the side tables, the wall
    nodes and their normal sums, and the reference folds and curvature coefficients
    recomputed with the clamps. ``constrained`` (n, 5) bool, the block's DOFs fixed or
    prescribed, is checked against the symmetry planes (symmetry.py ``check_plane_supports``).

    Raises ValueError when a node of a requested clamped edge is not held, or a node of a
    symmetry plane is free to leave it.
    """
    held = np.asarray(held, dtype=bool)
    connectivity = block.connectivity
    _, requested, _ = clamped_sides(connectivity, block.requested_clamp)
    on_edges = np.zeros_like(held)
    on_edges[connectivity[:, SIDE_FROM][requested]] = True
    on_edges[connectivity[:, SIDE_TO][requested]] = True
    loose = np.flatnonzero(on_edges & ~held)
    if loose.size:
        nodes = f"clamped nodes {loose[:5].tolist()}{'...' if loose.size > 5 else ''}"
        why = "(a clamped edge is held by the supports; its bending then acts against a wall)"
        raise OptionError(
            f"{nodes} must have their translations and directors fixed with model.fix {why}",
            "clamped",
            f"{nodes} are not held: add {_fix_tables(block, loose)} (no dofs "
            f"key: the translations and the directors), or drop the option {why}",
        )
    check_plane_supports(block, held, constrained)
    set_sides(block, held | block.requested_clamp)
    # A held node stays where it was: its nodal normal is the wall's, the reference one,
    # not the mean of the cells that bend away from it (docs/theory.md §1.4).
    wall = block.node_in_block
    block.wall_nodes = np.zeros_like(held)  # the reference sums with no wall yet
    # A writable copy of the mesh's read-only points: numba compiles a kernel once for each
    # array type it is given, read-only and writable apart, and the states' positions are
    # writable (benchmarks/suite_kernels.py: the normals and bending-side loops were compiled
    # twice, the second time for the reference geometry of the bind).
    points = np.array(block.reference_points)
    block.reference_sums = geometry.normal_sums(block, points)
    block.wall_nodes = wall & (held | block.requested_clamp)
    block.wall_node_ids = np.flatnonzero(block.wall_nodes)
    block.wall_sums = block.reference_sums[block.wall_node_ids]
    reference = bending.geometry(block, points)
    block.reference_fold = reference["fold"]
    block.reference_coefficients = reference["coefficients"]


def wall_moments(block: FibrousShellBlock, positions: np.ndarray) -> np.ndarray:
    """The moment the clamp's walls exert on the block (docs/theory.md §4.5, "The wall's
    moment"), (m, 3, 3) per cell corner, N mm: on each clamped side s of a cell, running
    from p to q along the unit t_s, the wall carries -mu_s t_s, mu_s = -A0 sum_a M_a c_as
    the side's moment, half at p and half at q. The cell's share mu_s D[s, k] n of the
    bending forces has the moment mu_s t_s about any point, which no force of the model
    balances: the wall's reaction does. A symmetry plane's sides (whose wall follows the
    side) carry none. ``positions`` (n, 3) mm; ``block`` the block as its loops read it
    (fold_branch.py ``branch_view`` for the folds' turns)."""
    out = np.zeros((len(block.connectivity), 3, 3))
    wall = block.clamped_side & ~np.any(block.mirror_normal != 0.0, axis=-1)
    if not wall.any():
        return out
    bend = bending.geometry(block, positions)
    chi, coefficients = bending.curvatures(block, bend)
    mu = bending.side_moments(block, bending.moments(block, chi), coefficients)
    x = positions[block.connectivity]
    side = x[:, SIDE_TO] - x[:, SIDE_FROM]  # (m, 3 sides, 3)
    t = side / np.linalg.norm(side, axis=-1, keepdims=True)
    half = np.where(wall, -0.5 * mu, 0.0)[..., None] * t  # (m, 3 sides, 3)
    cells = np.arange(len(out))[:, None]
    np.add.at(out, (cells, SIDE_FROM[None, :]), half)
    np.add.at(out, (cells, SIDE_TO[None, :]), half)
    return out
