"""A fixed alpha or beta must mean one rotation along its node set (docs/theory.md §1.2).

The nodal frame of Bai Eq. 7 takes V1 from a = e2, and from a = e3 where the director lies
within about 6 deg of +-e2 (``femcore.rotation.FRAME_FALLBACK``). Alpha turns the director
towards V1, beta towards -V2. On a set of nodes whose directors straddle that cone the two
frames can name different rotations by one name: on the plane z = L/2 of a cylinder whose axis
is z, alpha turns the director out of the plane (towards z) on every node but those within
6 deg of +-e2, where it turns the director within the plane. Fixing alpha along the plane then
holds the wrong rotation at those nodes and frees the right one: the pinched cylinder's octant
deflected 0.784 of its reference, 0.951 with the right DOF at each node. ``check_frame_branches``
refuses such a fix when the model is compiled, naming the nodes and the DOF to fix there.

``Model.fix(nodes, dofs, tilt="z")`` says what is meant instead of naming a DOF: hold the
director's turn towards the global axis z (out of a symmetry plane z = const), which
``tilt_columns`` resolves to alpha or beta at each node by its frame, once
``onto_symmetry_planes`` has laid those nodes' directors into the plane (the mirrored whole's:
a one-sided director sits half a facet off it, where Eq. 7's frame near +-e2 swings). A plane
named by its DOFs instead (ux and alpha on x = const) is not laid in; ``warn_named_planes``
warns where its held DOF is not the turn out of it.

Both read the reference directors. A director that turns across the cone during a run changes
frame there, and a DOF fixed alone may then hold another rotation than it did:
``changed_meaning`` finds those nodes at a state, and the solvers warn when they keep a frame
with some (solvers.common.make_frame).
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence

import numpy as np
from scipy.spatial import cKDTree

from femcore.entry_error import EntryError
from femcore.rotation import FRAME_FALLBACK, cross, nodal_frames

__all__ = [
    "BRANCH_ANGLE_DEG",
    "NAMED_PLANE_DEG",
    "changed_meaning",
    "check_frame_branches",
    "facet_spread",
    "onto_symmetry_planes",
    "tilt_columns",
    "warn_named_planes",
]

#: Largest angle (deg) between the directions a fixed DOF turns the director at a node of the
#: fallback frame and at its nearest node of the Eq. 7 frame in the same fix. Neighbours on a
#: smooth edge differ by their facet angle (a few degrees); where the two frames name
#: different rotations they differ by up to 90 deg (the cylinder's plane above: 90).
BRANCH_ANGLE_DEG = 30.0

#: Largest angle (deg) between the turn a named alpha or beta holds on a plane that reads as a
#: symmetry plane and the turn out of it before ``warn_named_planes`` warns: 0 for a director
#: in the plane, the director's own offset (half a facet: 2.8 deg at 16 cells of 5.6 deg on a
#: hemisphere quadrant) off +-e2, 17 deg at the node where Eq. 7's frame swung near +-e2 and
#: the quadrant's two loaded points, equivalent by symmetry, read 18 % apart.
NAMED_PLANE_DEG = 10.0


def check_frame_branches(fixes: Sequence, directors: np.ndarray, has_rotation: np.ndarray) -> None:
    """Refuse a fix that holds alpha or beta alone on nodes whose frames name different
    rotations by that DOF.

    Parameters
    ----------
    fixes : sequence of femcore.model.Fix
        The model's fixes (``nodes`` (k,) int, ``columns`` None or DOF columns).
    directors : numpy.ndarray, shape (n, 3)
        The reference unit directors (zero rows at nodes without rotations).
    has_rotation : numpy.ndarray, shape (n,) bool
        The nodes that carry alpha and beta.

    Raises
    ------
    EntryError
        (a ValueError) naming the fix, the nodes of the fallback frame where the held DOF
        turns the director another way than at the fix's other nodes, and the DOF that holds
        the same rotation there.
    """
    for index, fix in enumerate(fixes):
        if fix.columns is None:
            continue  # every DOF: the director is held whatever the frame
        columns = set(np.asarray(fix.columns).tolist())
        held = columns & {3, 4}
        if len(held) != 1:
            continue  # no rotation held, or both: the director is held whatever the frame
        column = held.pop()
        nodes = np.unique(fix.nodes[has_rotation[fix.nodes]])
        if nodes.size < 2:
            continue
        v = directors[nodes]
        fallback = np.hypot(v[:, 0], v[:, 2]) < FRAME_FALLBACK  # |e2 x V| < FRAME_FALLBACK
        if fallback.all() or not fallback.any():
            continue  # one frame along the set: one meaning
        v1, v2 = nodal_frames(v)
        # alpha turns V towards V1 (about V2), beta towards -V2 (about V1): the direction of
        # the motion the fixed DOF holds, up to its sign
        turns = v1 if column == 3 else v2
        inside, outside = np.flatnonzero(fallback), np.flatnonzero(~fallback)
        # each fallback node's nearest Eq. 7 node of the set, by the angle of their directors
        # (the sign of a director aside: the nearer of V and -V; a tree, not an inside x
        # outside table, which a large set would not fit in memory)
        tree = cKDTree(np.concatenate([v[outside], -v[outside]]))
        _, found = tree.query(v[inside])
        nearest = outside[np.asarray(found) % outside.size]
        agree = np.abs(np.sum(turns[inside] * turns[nearest], axis=1))
        wrong = agree < np.cos(np.radians(BRANCH_ANGLE_DEG))
        if not wrong.any():
            continue
        bad = inside[wrong]
        want = turns[nearest[wrong]]
        # the DOF of the fallback frame that holds the neighbours' rotation there, if one does
        along_v1 = np.abs(np.sum(v1[bad] * want, axis=1))
        along_v2 = np.abs(np.sum(v2[bad] * want, axis=1))
        holds = np.maximum(along_v1, along_v2) >= np.cos(np.radians(BRANCH_ANGLE_DEG))
        name = "alpha" if column == 3 else "beta"
        other = "beta" if column == 3 else "alpha"
        swap, neither = nodes[bad[holds]], nodes[bad[~holds]]
        listed = f"{nodes[bad][:10].tolist()}{' ...' if bad.size > 10 else ''}"
        remedy = []
        if swap.size:
            remedy.append(
                f"fix {other} instead of {name} at nodes {swap[:10].tolist()}"
                f"{' ...' if swap.size > 10 else ''}"
            )
        if neither.size:
            remedy.append(
                f"at nodes {neither[:10].tolist()}{' ...' if neither.size > 10 else ''} no "
                "one DOF holds that rotation: fix both alpha and beta there, or neither"
            )
        raise EntryError(
            "fix",
            index,
            f"{name} means another rotation at nodes {listed} than at the set's other nodes: "
            f"their directors lie within {np.degrees(np.arcsin(FRAME_FALLBACK)):.1f} deg of "
            f"+-e2, where the nodal frame takes a = e3 instead of e2 (docs/theory.md §1.2), "
            f"so there {name} turns the director more than {BRANCH_ANGLE_DEG:g} deg away from "
            f"the way it does at the nearest other node of the set (a symmetry plane z = "
            f"const through directors near +-e2 is the usual case); "
            + "; ".join(remedy)
            + " (femcore.rotation.nodal_frames gives each node's V1 and V2: alpha turns the "
            "director towards V1, beta towards -V2)",
        )


def facet_spread(points: np.ndarray, triangles: np.ndarray, directors: np.ndarray) -> np.ndarray:
    """Per node the local fold of the surface (deg): the largest angle between a director and
    the normal of one of its facets, over the nodes of the node's facets (one ring further,
    so that a corner node of a single facet takes its neighbours' folds); how far a one-sided
    average of facet normals can lie from a plane across which the mirrored facets would
    complete it (``onto_symmetry_planes``; 0 at a node not on a cell).

    Parameters
    ----------
    points : numpy.ndarray, shape (n, 3), mm
    triangles : numpy.ndarray of int, shape (m, 3)
    directors : numpy.ndarray, shape (n, 3), the nodal unit normals
    """
    x = points[triangles]
    normals = np.cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0])
    normals /= np.linalg.norm(normals, axis=1)[:, None]
    cosine = np.einsum("mkj,mj->mk", directors[triangles], normals)
    angles = np.degrees(np.arccos(np.clip(cosine, -1.0, 1.0)))
    own = np.zeros(len(points))
    np.maximum.at(own, triangles.ravel(), angles.ravel())
    ring = np.repeat(own[triangles].max(axis=1), 3)  # each facet's largest, to its corners
    spread = np.zeros(len(points))
    np.maximum.at(spread, triangles.ravel(), ring)
    return spread


#: A symmetry plane's one-sided director lies off the plane by about its own facets' spread;
#: farther than SPREAD_FACTOR x that spread + SPREAD_MARGIN_DEG, the plane is not one of the
#: geometry's symmetry planes (an inclined edge), and laying the director into it would turn it.
SPREAD_FACTOR = 2.0
SPREAD_MARGIN_DEG = 0.1


def _off_plane(v: np.ndarray, axis: int) -> np.ndarray:
    """The angle (deg) of each director (k, 3) from the plane normal to ``axis``."""
    return np.degrees(np.arcsin(np.clip(np.abs(v[:, axis]), 0.0, 1.0)))


def _beyond_symmetry(off: np.ndarray, spread: np.ndarray | None) -> np.ndarray:
    """Directors (their angle ``off`` from a plane, deg) farther from it than their facets'
    ``spread`` allows on a symmetry plane (all False without a spread)."""
    if spread is None:
        return np.zeros(off.shape, dtype=bool)
    return off > SPREAD_FACTOR * spread + SPREAD_MARGIN_DEG


def onto_symmetry_planes(
    fixes: Sequence,
    directors: np.ndarray,
    has_rotation: np.ndarray,
    spread: np.ndarray | None = None,
) -> None:
    """Lay the reference directors of the nodes a ``tilt`` fix holds into its symmetry plane,
    in place: the directors the whole (mirrored) model would give them (docs/theory.md §1.2).

    A node on a symmetry plane averages only its own side's facet normals, so its director
    sits half a facet angle off the plane; the mirrored model's average is the normalised
    projection of that sum onto the plane (n + M n = 2 P n for each facet normal n and its
    mirror M n). In the plane, one of V1, V2 of the node's frame is the plane's normal exactly
    and ``tilt_columns`` holds exactly the director's turn out of the plane; off it, on a plane
    x = const near +-e2, Eq. 7's V1 = e2 x V swings with the small x-component and the held DOF
    mixes the meridional turn into it (the quadrant of a pinched hemisphere read its two
    loaded points, equivalent by symmetry, 18 % apart).

    Parameters
    ----------
    fixes : sequence of femcore.loads.Fix
        The model's fixes; those with ``tilt`` 0, 1 or 2 (x, y, z) name the planes.
    directors : numpy.ndarray, shape (n, 3)
        The reference unit directors, changed in place at the tilt fixes' nodes.
    has_rotation : numpy.ndarray, shape (n,) bool
        The nodes that carry alpha and beta (others are left to ``tilt_columns`` to refuse).
    spread : numpy.ndarray, shape (n,), optional
        ``facet_spread`` of the nodes (deg): a director farther off its plane than
        SPREAD_FACTOR x its spread + SPREAD_MARGIN_DEG is not a symmetry plane's (an edge of a
        cylindrical panel at 20 deg to the plane, its facets 1 deg apart, would have been
        turned 20 deg, silently).

    Raises
    ------
    EntryError
        (a ValueError) for a director more than BRANCH_ANGLE_DEG from its plane, or farther
        than its facets' spread allows: not a symmetry plane's node (its facets do not lie
        across the plane), or a node on two tilt planes whose director cannot lie in both.
    """
    for index, fix in enumerate(fixes):
        if fix.tilt is None:
            continue
        nodes = np.unique(fix.nodes[has_rotation[fix.nodes]])
        if not nodes.size:
            continue
        v = directors[nodes]
        off = _off_plane(v, fix.tilt)
        far = off > BRANCH_ANGLE_DEG
        axis = "xyz"[fix.tilt]
        if far.any():
            bad = nodes[far]
            raise EntryError(
                "fix",
                index,
                f"tilt = {axis!r} holds the director's turn out of a symmetry plane {axis} = "
                f"const, and at nodes {bad[:10].tolist()}{' ...' if bad.size > 10 else ''} "
                f"the director lies {off[far][0]:.1f} deg from that plane (e.g. "
                f"{np.round(v[far][0], 4).tolist()}; more than {BRANCH_ANGLE_DEG:g} deg): a "
                "symmetry plane's nodes have their directors in it, up to half a facet "
                "angle. Is the plane's axis the right one? Elsewhere fix alpha and beta to "
                "hold the director whole",
            )
        astray = _beyond_symmetry(off, None if spread is None else spread[nodes])
        if astray.any():
            bad = nodes[astray]
            first = int(np.flatnonzero(astray)[0])
            assert spread is not None
            raise EntryError(
                "fix",
                index,
                f"tilt = {axis!r} declares a symmetry plane {axis} = const, but at nodes "
                f"{bad[:10].tolist()}{' ...' if bad.size > 10 else ''} the director lies "
                f"{off[first]:.2f} deg from that plane where the surface folds by at most "
                f"{spread[bad[0]]:.2f} deg from one facet to the next around it: the surface "
                "crosses the plane at an "
                "angle, so the plane is not one of its symmetry planes (an inclined edge), and "
                "laying the directors into it would turn them. Hold such an edge by naming "
                "its DOFs (alpha and beta for the whole director)",
            )
        v = v.copy()
        v[:, fix.tilt] = 0.0
        directors[nodes] = v / np.linalg.norm(v, axis=1)[:, None]


def warn_named_planes(
    fixes: Sequence,
    points: np.ndarray,
    directors: np.ndarray,
    has_rotation: np.ndarray,
    spread: np.ndarray | None = None,
) -> None:
    """Warn (UserWarning) where a fix that reads as a symmetry plane by named DOFs (one
    translation, along a coordinate axis, and alpha or beta alone, on nodes of one plane
    normal to that axis whose directors lie within BRANCH_ANGLE_DEG of it) holds at some
    nodes a turn more than NAMED_PLANE_DEG from the turn out of the plane.

    The one-sided directors of such a plane sit half a facet angle off it; near +-e2 on a
    plane x = const Eq. 7's V1 swings with that small part (docs/theory.md §1.2), and a named
    alpha holds part of the in-plane turn there (a hemisphere quadrant's two loaded points,
    equivalent by symmetry, read 0.0263 and 0.0135 per newton). ``tilt`` declares the plane:
    its directors are laid into it and the held DOF is the turn out of it.

    Parameters
    ----------
    fixes : sequence of femcore.loads.Fix
        The model's fixes.
    points : numpy.ndarray, shape (n, 3)
        The reference positions, mm.
    directors : numpy.ndarray, shape (n, 3)
        The reference unit directors.
    has_rotation : numpy.ndarray, shape (n,) bool
        The nodes that carry alpha and beta.
    spread : numpy.ndarray, shape (n,), optional
        ``facet_spread`` (deg): directors farther off the plane than their facets allow on a
        symmetry plane mark an edge support, which is not warned (``tilt`` would turn them).
    """
    size = float(np.ptp(points, axis=0).max(initial=0.0)) or 1.0
    least = np.cos(np.radians(NAMED_PLANE_DEG))
    for index, fix in enumerate(fixes):
        if fix.columns is None or fix.tilt is not None:
            continue
        columns = set(np.asarray(fix.columns).tolist())
        moved, turned = columns & {0, 1, 2}, columns & {3, 4}
        if len(moved) != 1 or len(turned) != 1:
            continue
        axis, column = moved.pop(), turned.pop()
        nodes = np.unique(fix.nodes[has_rotation[fix.nodes]])
        if nodes.size < 2 or np.ptp(points[nodes, axis]) > 1e-6 * size:
            continue  # not one plane normal to the held translation
        v = directors[nodes]
        off = _off_plane(v, axis)
        if (off > BRANCH_ANGLE_DEG).any() or _beyond_symmetry(
            off, None if spread is None else spread[nodes]
        ).any():
            continue  # directors across the plane: an edge support, not a symmetry plane
        v1, v2 = nodal_frames(v)
        turns = v1 if column == 3 else v2  # alpha towards V1, beta towards -V2
        astray = np.abs(turns[:, axis]) < least
        if not astray.any():
            continue
        bad = nodes[astray]
        name, letter = ("alpha" if column == 3 else "beta"), "xyz"[axis]
        other = "beta" if column == 3 else "alpha"
        # The other DOF turns every such director out of the plane: the named one turns it
        # within the plane, the wrong rotation held (not a director lying a little off it).
        swapped = np.abs((v2 if column == 3 else v1)[astray, axis]) >= least
        if swapped.all():
            why = (
                f"{name} turns their directors within the plane, so the turn out of it is "
                f"free: the wrong rotation is held ({other} turns them out of it). Hold "
                f"u{letter} and {other}, or declare the plane"
            )
        else:
            why = (
                "their directors (their own side's facets' average) lie a little off the "
                "plane, and the nodal frame turns with that (docs/theory.md §1.2). Declare "
                "the plane instead"
            )
        warnings.warn(
            f"fix {index} holds u{letter} and {name} on the plane {letter} = const, as a "
            f"symmetry plane, but at nodes {bad[:10].tolist()}{' ...' if bad.size > 10 else ''} "
            f"{name} turns the director more than {NAMED_PLANE_DEG:g} deg from the turn out "
            f"of the plane: {why}: model.fix(nodes, ['u{letter}'], tilt='{letter}') "
            "lays the directors into it and holds the turn out of it at every node",
            UserWarning,
            stacklevel=4,
        )


def tilt_columns(
    fix, index: int, active: np.ndarray, directors: np.ndarray | None
) -> tuple[np.ndarray, np.ndarray]:
    """The DOF that holds the director's turn towards the global axis ``fix.tilt`` at each
    node of ``fix``: alpha (column 3) where V1 of the node's frame lies along the axis, beta
    (column 4) where V2 does.

    Parameters
    ----------
    fix : femcore.loads.Fix
        With ``tilt`` 0, 1 or 2 (x, y, z).
    index : int
        The fix's index in the model's fixes (for the error).
    active : numpy.ndarray, shape (n, 5) bool
        The DOFs the elements give each node.
    directors : numpy.ndarray, shape (n, 3), or None
        The reference unit directors.

    Returns
    -------
    nodes, columns : numpy.ndarray of int, shape (k,) each
        The fix's nodes with rotations and the column held at each.

    Raises
    ------
    EntryError
        (a ValueError) for nodes without rotations, or whose frame turns the director
        towards the axis by neither DOF (within BRANCH_ANGLE_DEG): a director off the plane
        normal to the axis, whose Eq. 7 frame may be turned about it by any angle (near +-e2
        on a plane x = const). Model.compile lays the directors into the plane first
        (``onto_symmetry_planes``), where one of V1, V2 is the plane's normal exactly.
    """
    axis = "xyz"[fix.tilt]
    nodes = np.unique(fix.nodes)
    lacking = nodes[~active[nodes, 3]]
    if lacking.size or directors is None:
        raise EntryError(
            "fix",
            index,
            f"tilt = {axis!r} holds a director's turn, and nodes {lacking[:10].tolist()} have "
            "no director (no rotational DOF)",
        )
    v1, v2 = nodal_frames(directors[nodes])
    along_v1, along_v2 = np.abs(v1[:, fix.tilt]), np.abs(v2[:, fix.tilt])
    least = np.cos(np.radians(BRANCH_ANGLE_DEG))
    neither = np.maximum(along_v1, along_v2) < least
    if neither.any():
        bad = nodes[neither]
        first = directors[bad[0]]
        off = np.degrees(np.arcsin(min(abs(float(first[fix.tilt])), 1.0)))
        raise EntryError(
            "fix",
            index,
            f"tilt = {axis!r}: at nodes {bad[:10].tolist()}{' ...' if bad.size > 10 else ''} "
            f"the nodal frame has neither V1 nor V2 within {BRANCH_ANGLE_DEG:g} deg of {axis}, "
            f"so neither alpha nor beta alone is the director's turn out of the plane {axis} "
            f"= const: the director (e.g. {np.round(first, 4).tolist()}, {off:.1f} deg off "
            f"the plane) is not in the plane, and Eq. 7's V1 = e2 x V / |e2 x V| (e3 x V "
            "within 5.7 deg of +-e2) swings with its small out-of-plane part (docs/theory.md "
            "§1.2). Model.compile lays a tilt plane's reference directors into it "
            "(onto_symmetry_planes) before this pick; pass directors that lie in the plane",
        )
    return nodes, np.where(along_v1 >= along_v2, 3, 4)


def changed_meaning(
    reference: np.ndarray, directors: np.ndarray, rotation_fixed: np.ndarray
) -> np.ndarray:
    """The nodes whose one fixed director DOF holds, at ``directors``, another rotation than
    it did at ``reference``: their director crossed the cone of the frame's fallback, and the
    two frames turn the director by that DOF more than BRANCH_ANGLE_DEG apart there.

    Parameters
    ----------
    reference, directors : numpy.ndarray, shape (n, 3)
        The reference and the current unit directors.
    rotation_fixed : numpy.ndarray, shape (n, 2) bool
        Alpha and beta fixed at each node (CompiledModel.rotation_fixed).

    Returns
    -------
    numpy.ndarray of int, shape (k,)
        The nodes, in order.
    """
    nodes = np.flatnonzero(rotation_fixed[:, 0] != rotation_fixed[:, 1])
    if not nodes.size:
        return nodes
    was = np.hypot(reference[nodes, 0], reference[nodes, 2]) < FRAME_FALLBACK
    now = np.hypot(directors[nodes, 0], directors[nodes, 2]) < FRAME_FALLBACK
    nodes = nodes[was != now]
    if not nodes.size:
        return nodes
    v = directors[nodes]
    turns = []
    for axis in (np.array([0.0, 1.0, 0.0]), np.array([0.0, 0.0, 1.0])):  # a = e2, a = e3
        v1 = cross(axis, v)
        v1 /= np.maximum(np.linalg.norm(v1, axis=1), 1e-300)[:, None]
        # alpha turns V towards V1, beta towards -V2 = -(V x V1)
        turns.append(np.where(rotation_fixed[nodes, :1], v1, cross(v, v1)))
    agree = np.abs(np.sum(turns[0] * turns[1], axis=1))
    return nodes[agree < np.cos(np.radians(BRANCH_ANGLE_DEG))]
