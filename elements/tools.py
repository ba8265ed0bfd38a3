"""Rigid tools for contact (elements/contact.py): analytic surfaces that give, for any points,
the signed distance to the surface and its unit normal there, pointing to the side the body
stays on.

Each tool may move rigidly: ``motion`` (3,) is a translation reached at the end of the run,
through an ``amplitude`` a(tau) (femcore.loads: "linear" by default, "smooth", "step" or a
callable), tau the load factor of the quasi-static solvers or t / duration of the explicit one:
the tool is at ``a(tau) * motion`` from where it was given. Units: mm.

A tool may instead be free along some axes (``free``, e.g. ``("z",)``) and driven there by a
prescribed ``force`` (N) with the same amplitude: a blank holder. ``Model.contact`` then gives
the tool a node of its own (``Model.rigid_node``) carrying its translation along those axes,
with the tool's ``mass`` (t; required in explicit dynamics) and the force as a nodal load on
it, its other translations held; the contact couples each contact node with that node
(elements/contact.py, docs/theory.md §9.5). The motion and the force act on different axes.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from elements.facet_normal import turn_round_features
from elements.facet_search import (
    SLACK,
    closest_facets,
    closest_facets_kept,
    closest_on_triangles,
    largest_drift,
    open_edges,
    signed_from_closest,
    spans,
)
from elements.tool_smoothing import corner_normals, facet_rings, smoothed_gap
from femcore.checks import as_flag, as_reals, check_positive
from femcore.loads import AmplitudeFunction, amplitude_of

__all__ = ["RigidCylinder", "RigidPlane", "RigidSphere", "RigidSurface", "RigidTool"]


AXES = ("x", "y", "z")


def _free_axes(free: str | Sequence[str]) -> tuple[int, ...]:
    """The column indices (0, 1, 2) of the free axes named "x", "y", "z" (or "all")."""
    names: Sequence[str] = (
        ("x", "y", "z") if free == "all" else (free,) if isinstance(free, str) else free
    )
    try:
        names = tuple(names)
    except TypeError:
        names = (free,)  # type: ignore[assignment]
    bad = [name for name in names if name not in AXES]
    if bad:
        raise ValueError(
            f"free must name translation axes among 'x', 'y', 'z' (or be 'all'), got {free!r}"
        )
    if len(set(names)) != len(names):
        raise ValueError(f"free names an axis twice: {free!r}")
    return tuple(sorted(AXES.index(name) for name in names))


def _vector(value: ArrayLike, name: str, unit: bool = False) -> np.ndarray:
    vector = as_reals(value, name, "3 finite numbers").ravel()
    if vector.shape != (3,) or not np.isfinite(vector).all():
        raise ValueError(f"{name} must be 3 finite numbers, got {value!r}")
    if unit:
        length = np.linalg.norm(vector)
        if length == 0.0:
            raise ValueError(f"{name} must be a non-zero vector, got {value!r}")
        vector = vector / length
    return vector


class RigidTool:
    """A rigid surface: ``distance(x, load_factor)`` -> (d (k,), n (k, 3)), the signed
    distance (mm, > 0 on the body's side) and the unit normal towards the body's side, and
    ``curvature(x, load_factor)`` -> (k,) the curvature 1/R of the surface's normal section
    (0 for a plane), for the contact tangent. ``side="inside"`` keeps the body inside a
    sphere or a cylinder (a die) instead of outside (a punch).

    Driving options of every tool: ``motion`` (3,) mm reached through ``amplitude``; ``free``
    the axes ("x", "y", "z", or "all") along which the tool moves freely instead, pushed by
    ``force`` (3,) N (components along free axes only; the same amplitude), with ``mass`` t
    (required by the explicit solver). ValueError for a force along a held axis, a motion
    along a free one, or a mass for a tool with no free axis."""

    def __init__(
        self,
        motion: ArrayLike = (0.0, 0.0, 0.0),
        side: str = "outside",
        amplitude: str | AmplitudeFunction = "linear",
        free: str | Sequence[str] = (),
        force: ArrayLike = (0.0, 0.0, 0.0),
        mass: float | None = None,
    ):
        self.motion = _vector(motion, "motion")
        if side not in ("outside", "inside"):
            raise ValueError(f"side must be 'outside' or 'inside', got {side!r}")
        self.sign = 1.0 if side == "outside" else -1.0
        self.amplitude = amplitude_of(amplitude).dynamic
        self.amplitude_given = amplitude
        self.free = _free_axes(free)
        self.force = _vector(force, "force")
        self.mass = None if mass is None else check_positive(mass, "tool mass", "t")
        free_mask = np.isin(np.arange(3), self.free)
        where = ", ".join(AXES[i] for i in np.flatnonzero(~free_mask & (self.force != 0.0)))
        if where:
            raise ValueError(
                f"force = {tuple(float(f) for f in self.force)} N acts along {where}, an axis "
                f"the tool does not move freely along (free = {self.free_names}): add it to "
                "free, or drop that component"
            )
        where = ", ".join(AXES[i] for i in np.flatnonzero(free_mask & (self.motion != 0.0)))
        if where:
            raise ValueError(
                f"motion = {tuple(float(m) for m in self.motion)} mm moves the tool along "
                f"{where}, an axis it is free along (free = {self.free_names}): a free axis "
                "follows the force and the contact, not a prescribed motion"
            )
        if mass is not None and not self.free:
            raise ValueError(
                f"mass = {mass!r} t is given to a tool with no free axis: its motion is "
                "prescribed and its mass unused; give free = (...) to drive it by a force"
            )

    @property
    def driven(self) -> bool:
        """Whether the tool is free along some axis (driven by its force and the contact)."""
        return bool(self.free)

    @property
    def free_names(self) -> tuple[str, ...]:
        """The free axes by name, e.g. ("z",)."""
        return tuple(AXES[i] for i in self.free)

    def reference_point(self) -> np.ndarray:
        """(3,) a point of the tool where it was given, mm: where its own node (a driven
        tool's, ``Model.rigid_node``) is placed."""
        raise NotImplementedError

    @property
    def moves(self) -> bool:
        """Whether the tool has a motion."""
        return bool(np.any(self.motion != 0.0))

    def offset(self, load_factor: float) -> np.ndarray:
        """(3,) the tool's translation at ``load_factor`` (tau), mm."""
        if not self.moves:
            return np.zeros(3)
        return float(self.amplitude(load_factor)) * self.motion

    def contact(
        self,
        nodes=None,
        friction: float = 0.0,
        penalty: float | None = None,
        tool_node: int | None = None,
        stick_stiffness: float = 1.0,
        augmented: bool = False,
        augmented_tolerance: float | None = None,
        damping: float = 0.0,
    ):
        """The penalty contact of ``nodes`` (None: every node of the body's elements) with
        this tool (elements.contact.Contact), what ``Model.contact`` adds; ``tool_node`` the
        node carrying a driven tool's free translation (``Model.rigid_node``);
        ``stick_stiffness`` the friction's stick spring over the normal penalty;
        ``augmented`` (and its tolerance, mm) the augmented Lagrangian of the quasi-static
        solvers (elements/augmented_contact.py); ``damping`` the normal contact damping's
        fraction of critical (elements/contact_damping.py)."""
        from elements.contact import Contact  # contact.py builds on this module

        return Contact(
            self,
            nodes,
            penalty=penalty,
            friction=friction,
            tool_node=tool_node,
            stick_stiffness=stick_stiffness,
            augmented=augmented,
            augmented_tolerance=augmented_tolerance,
            damping=damping,
        )

    def distance(self, x: np.ndarray, load_factor: float = 0.0):
        raise NotImplementedError

    def side_hint(self) -> str:
        """What sets the side the body stays on, for a message about a body on the wrong
        side."""
        return f"side = {'outside' if self.sign > 0 else 'inside'}: is that the body's side?"

    def exact_within(self, distance: float) -> None:
        """A contact asks for exact distances up to ``distance`` (mm, twice its largest offset
        h / 2); analytic tools always give them."""
        return None

    def projector_scale(self, x: np.ndarray, load_factor: float = 0.0) -> np.ndarray:
        """(k,) the factor c of dn/dx = c (I - n n^T - a a^T), a the cylinder's axis (none
        for a sphere): the tool's sign over the distance to its centre or axis; 0 for a
        plane."""
        raise NotImplementedError

    def normal_gradient(
        self, x: np.ndarray, normal: np.ndarray, load_factor: float = 0.0
    ) -> np.ndarray:
        """(k, 3, 3) dn/dx, the turn of the tool's normal n (k, 3) at the points x (k, 3) as
        they move (the contact tangent's curvature term, docs/theory.md §9.1): c (I - n n^T
        - a a^T) with c of ``projector_scale``."""
        across = np.eye(3) - normal[:, :, None] * normal[:, None, :]
        if self.axis is not None:
            across = across - np.outer(self.axis, self.axis)
        return self.projector_scale(x, load_factor)[:, None, None] * across

    axis: np.ndarray | None = None


class RigidPlane(RigidTool):
    """The plane through ``point`` with unit ``normal`` (towards the body)."""

    def __init__(
        self,
        point: ArrayLike,
        normal: ArrayLike,
        motion: ArrayLike = (0.0, 0.0, 0.0),
        amplitude: str | AmplitudeFunction = "linear",
        free: str | Sequence[str] = (),
        force: ArrayLike = (0.0, 0.0, 0.0),
        mass: float | None = None,
    ):
        super().__init__(motion, amplitude=amplitude, free=free, force=force, mass=mass)
        self.point = _vector(point, "RigidPlane point")
        self.normal = _vector(normal, "RigidPlane normal", unit=True)

    def distance(self, x: np.ndarray, load_factor: float = 0.0):
        origin = self.point + self.offset(load_factor)
        d = (x - origin) @ self.normal
        return d, np.broadcast_to(self.normal, x.shape)

    def projector_scale(self, x: np.ndarray, load_factor: float = 0.0) -> np.ndarray:
        return np.zeros(len(x))

    def side_hint(self) -> str:
        return f"normal = {tuple(float(v) for v in self.normal)} must point towards the body"

    def reference_point(self) -> np.ndarray:
        return self.point.copy()


class _RoundTool(RigidTool):
    """A sphere or a cylinder: the distance from its centre (point or axis) less its radius,
    the normal along the radius (both with the tool's side)."""

    radius: float

    def _relative(self, x: np.ndarray, load_factor: float) -> np.ndarray:
        """(k, 3) the points' position from the centre, across the axis for a cylinder."""
        raise NotImplementedError

    def _radial(self, x: np.ndarray, load_factor: float):
        r = self._relative(x, load_factor)
        length = np.linalg.norm(r, axis=1)
        return r / np.where(length > 0, length, 1.0)[:, None], length

    def distance(self, x: np.ndarray, load_factor: float = 0.0):
        n, length = self._radial(x, load_factor)
        return self.sign * (length - self.radius), self.sign * n

    def projector_scale(self, x: np.ndarray, load_factor: float = 0.0) -> np.ndarray:
        _, length = self._radial(x, load_factor)
        return self.sign / np.maximum(length, 1e-300)


class RigidSphere(_RoundTool):
    """A sphere of ``radius`` (mm) about ``centre``; the body outside it (a punch head) or,
    with ``side="inside"``, inside it (a bowl)."""

    def __init__(
        self,
        centre: ArrayLike,
        radius: float,
        motion: ArrayLike = (0.0, 0.0, 0.0),
        side: str = "outside",
        amplitude: str | AmplitudeFunction = "linear",
        free: str | Sequence[str] = (),
        force: ArrayLike = (0.0, 0.0, 0.0),
        mass: float | None = None,
    ):
        super().__init__(motion, side, amplitude, free, force, mass)
        self.centre = _vector(centre, "RigidSphere centre")
        self.radius = check_positive(radius, "RigidSphere radius", "mm")

    def reference_point(self) -> np.ndarray:
        return self.centre.copy()

    def _relative(self, x: np.ndarray, load_factor: float) -> np.ndarray:
        return x - (self.centre + self.offset(load_factor))


class RigidCylinder(_RoundTool):
    """An infinite cylinder of ``radius`` (mm) about the line through ``point`` along
    ``axis``; the body outside it or, with ``side="inside"``, inside it."""

    def __init__(
        self,
        point: ArrayLike,
        axis: ArrayLike,
        radius: float,
        motion: ArrayLike = (0.0, 0.0, 0.0),
        side: str = "outside",
        amplitude: str | AmplitudeFunction = "linear",
        free: str | Sequence[str] = (),
        force: ArrayLike = (0.0, 0.0, 0.0),
        mass: float | None = None,
    ):
        super().__init__(motion, side, amplitude, free, force, mass)
        self.point = _vector(point, "RigidCylinder point")
        self.direction = _vector(axis, "RigidCylinder axis", unit=True)
        self.axis = self.direction
        self.radius = check_positive(radius, "RigidCylinder radius", "mm")

    def reference_point(self) -> np.ndarray:
        return self.point.copy()

    def _relative(self, x: np.ndarray, load_factor: float) -> np.ndarray:
        r = x - (self.point + self.offset(load_factor))
        return r - (r @ self.direction)[:, None] * self.direction


# How far (in facet circumradii) a point may move before RigidSurface searches it again.
MARGIN = 0.25
# When some point has moved past the margin, the points that have moved past this share of it
# are searched again with it: the searches come in batches, one every few hundred explicit
# steps, instead of a few points at every step, each batch paying the merge of the kept
# candidates (O(all candidates)) once (1.0: only the points past the margin).
REBUILD_SHARE = 0.5
# Whether a point that has not moved far enough to change its nearest facet is given that
# facet alone instead of a scan of its candidates (elements/facet_search.closest_facets_kept:
# the same answer to the last bit).
KEEP_NEAREST = True
# How many calls of RigidSurface.distance each point's closest facet is kept for
# (``facet_record``).
FACET_RECORD = 16
# Nearest facet centroids examined per point; more are examined where these cannot be
# shown to contain the closest facet (RigidSurface.distance).
CANDIDATES = 8


@dataclass(frozen=True)
class _Candidates:
    """What RigidSurface keeps of its last search: the points (k, 3), in the tool's frame;
    each point's candidate facets facets[start[i]:start[i + 1]] (none for the points beyond
    the search distance, ``far`` (k,) bool); the distances (k,) and normals (k, 3) found."""

    points: np.ndarray
    start: np.ndarray
    facets: np.ndarray
    far: np.ndarray
    distance: np.ndarray
    normal: np.ndarray


class RigidSurface(RigidTool):
    """A rigid tool meshed with triangles: a Mesh (its triangles), or any file meshio or
    Mesh.read reads (gmsh .msh, .inp, .vtu, .stl, ...). The body stays on the side the
    facets' normals point to (right-hand rule on each triangle's nodes); ``flip=True`` takes
    the other side.

    The signed distance of a point is that to the closest point of the surface, positive on
    the normals' side; its normal is along the line to that point (the facet's normal inside
    a facet; around an edge or a vertex, the direction from it). An open surface (a table, a
    die's flange) ends at its boundary edges (those of one facet only): a point past such an
    edge's line, in its facet's plane, is beside the tool whichever side of the facets it
    lies on, its distance that to the edge, positive (the overhang of a strip on a table
    sags below the table's plane without being inside it). The closest facet is found
    among the nearest facet centroids of a k-d tree (scipy.spatial.cKDTree, built once):
    CANDIDATES of them, more where those cannot be shown to include it (a centroid further
    than the closest point found plus the largest facet's circumradius cannot belong to a
    closer facet). That proof is asked only below ``search_distance`` (mm; by default two
    facet circumradii, or twice the largest contact offset h / 2 of the contacts that use the
    tool if more): further away the distance returned is never less than the true one.
    The contact tangent takes the normal's turn round edges and vertices, and over the smoothed
    surface its curvature (``normal_gradient``, docs/theory.md §9.3).

    A meshed tool free along some axes may be driven by a ``pressure`` (N/mm^2) instead of a
    force: the force is then the pressure times the facets' area vectors summed (each
    facet's area along its normal, towards the body), along the free axes: a holder of face
    A pressed at p pushes with p A (docs/theory.md §9.5).

    ``smooth=True`` measures the gap along a normal field interpolated from the vertices
    (elements/tool_smoothing.py) where the closest facet is within the largest facet's
    circumradius: the contact force then turns continuously over a faceted curved tool
    instead of jumping by the dihedral angle where a pressed node's closest facet changes on
    the tool's concave side (Static's Newton cannot converge on such a jump). Off by default:
    the closest-point distance.

    Speed: that search costs tens of microseconds per point. The tool keeps, for the last
    points it was asked about, every facet that can become their closest while they move
    less than ``MARGIN`` circumradius (those whose centroid lies within the proof's distance
    plus twice that margin plus their own circumradius; none for the points beyond the
    search distance, which are told their distance less how far they moved), and answers from
    those alone (a compiled loop); when a point has moved further, it is searched again with
    every point that has moved more than ``REBUILD_SHARE`` of that margin (a Verlet list's
    rebuild, in batches a few hundred explicit steps apart rather than a few points at every
    step), the others keeping theirs; between scans of its list, a point keeps its nearest
    facet alone while it cannot change (``KEEP_NEAREST``, docs/theory.md §9.3): microseconds
    per point and step in an explicit run (benchmarks/contact_search.py). The same points
    asked again get the same answer without a search.
    """

    def __init__(
        self,
        mesh,
        motion: ArrayLike = (0.0, 0.0, 0.0),
        flip: bool = False,
        amplitude: str | AmplitudeFunction = "linear",
        search_distance: float | None = None,
        free: str | Sequence[str] = (),
        force: ArrayLike = (0.0, 0.0, 0.0),
        mass: float | None = None,
        pressure: float | None = None,
        smooth: bool = False,
    ):
        from scipy.spatial import cKDTree

        from femcore.mesh import Mesh

        super().__init__(motion, amplitude=amplitude, free=free, force=force, mass=mass)
        if not isinstance(mesh, Mesh):
            try:
                mesh = Mesh.read(mesh)
            except (OSError, TypeError) as error:
                raise ValueError(f"RigidSurface: cannot read {mesh!r}: {error}") from None
        triangles = mesh.triangles
        if len(triangles) == 0:
            raise ValueError("RigidSurface needs a mesh with triangles (its facets), got none")
        self.corners = mesh.points[triangles]  # (f, 3, 3)
        a, b, c = self.corners[:, 0], self.corners[:, 1], self.corners[:, 2]
        normal = np.cross(b - a, c - a)
        length = np.linalg.norm(normal, axis=1)
        if (length == 0).any():
            raise ValueError(
                f"RigidSurface: facet {int(np.argmin(length))} has no area (collinear nodes)"
            )
        self.flipped = as_flag(flip, "RigidSurface flip")
        self.normals = (-1.0 if flip else 1.0) * normal / length[:, None]
        self.edge_start, self.edge_out = open_edges(triangles, self.corners)
        centroids = self.corners.mean(axis=1)
        # Each facet's circumradius about its centroid (f,), mm; the largest is the reach.
        self._radius = np.linalg.norm(self.corners - centroids[:, None], axis=2).max(axis=1)
        self._centroids = centroids
        self.reach = float(self._radius.max())
        self.tree = cKDTree(centroids)
        self._given_search = search_distance is not None
        self.search_distance = (
            2.0 * self.reach
            if search_distance is None
            else check_positive(search_distance, "RigidSurface search_distance", "mm")
        )
        self.n_facets = len(triangles)
        self._centre = centroids.mean(axis=0)
        self._cache: _Candidates | None = None
        # The last points asked about (in the tool's frame) with their answer (d, n).
        self._last: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None
        self._last_facet = np.zeros(0, dtype=np.int64)  # with it, each point's closest facet
        # The closest facet of each point over the last FACET_RECORD calls, column by
        # column in turn (``facet_record``): what a stopped solver's diagnosis reads.
        self._record = np.zeros((0, FACET_RECORD), dtype=np.int64)
        self._recorded = 0
        self.record_facets = False  # kept only when asked (ContactBlock.freeze: Static's)
        self._hint = np.zeros(0, dtype=np.int64)  # each point's facet of the last search
        # With those hints: where each point's scan was, and its room to keep its facet.
        self._kept: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None
        self.pressure: float | None = None
        if pressure is not None:
            self._drive_by_pressure(pressure, 0.5 * length[:, None] * self.normals)
        self.smooth = as_flag(smooth, "RigidSurface smooth")
        if self.smooth:  # the normal field of elements/tool_smoothing.py, once
            self._triangles = triangles.copy()
            self._corner_normals = corner_normals(self.corners, triangles, self.normals)
            self._rings = facet_rings(triangles)

    def _drive_by_pressure(self, pressure: float, areas: np.ndarray) -> None:
        """force = pressure x the facets' area vectors summed (f, 3) (each facet's area along
        its normal, towards the body), its components along the free axes: what a pressure
        on the whole face pushes the tool with, the guides holding the rest."""
        self.pressure = check_positive(pressure, "RigidSurface pressure", "N/mm^2")
        if not self.free:
            raise ValueError(
                f"pressure = {pressure!r} N/mm^2 is given to a tool with no free axis: give "
                "free = (...) for the axes the pressure drives it along"
            )
        if np.any(self.force != 0.0):
            raise ValueError(
                "pressure and force are both given: the pressure makes the force (pressure x "
                "the facets' area along their normals); give one"
            )
        resultant = self.pressure * areas.sum(axis=0)
        force = np.zeros(3)
        force[list(self.free)] = resultant[list(self.free)]
        if not np.any(np.abs(force) > 1e-12 * np.abs(resultant).max(initial=0.0)):
            raise ValueError(
                f"the pressure's resultant {tuple(float(r) for r in resultant)} N has no "
                f"component along the free axes {self.free_names}: the facets face across them"
            )
        self.force = force

    def _closest(self, x: np.ndarray, count: int):
        """The closest points on the count nearest facets (by centroid): (point (k, 3),
        facet (k,), distance to the furthest centroid examined (k,))."""
        spread, facets = self.tree.query(x, k=count)
        spread, facets = spread.reshape(len(x), -1), facets.reshape(len(x), -1)
        corners = self.corners[facets]  # (k, count, 3, 3)
        points = closest_on_triangles(
            x[:, None, :], corners[..., 0, :], corners[..., 1, :], corners[..., 2, :]
        )
        gaps = np.linalg.norm(points - x[:, None, :], axis=2)
        best = np.argmin(gaps, axis=1)
        rows = np.arange(len(x))
        return points[rows, best], facets[rows, best], gaps[rows, best], spread[:, -1]

    def reference_point(self) -> np.ndarray:
        return self._centre.copy()

    def exact_within(self, distance: float) -> None:
        if not self._given_search and distance > self.search_distance:
            self.search_distance = float(distance)
            self._cache = self._last = None

    def _candidates(self, local: np.ndarray, gap: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Every facet that can hold a point's closest point while it moves less than the
        cache's margin (MARGIN circumradius): within the proof's distance plus twice the
        margin of the point, so with its centroid within that plus the facet's own
        circumradius (the k-d tree finds those within the largest one, then each is held to
        its own), as (start (k + 1,), facets): point i's are facets[start[i]:start[i + 1]]."""
        near = np.minimum(gap, self.search_distance) + 2.0 * MARGIN * self.reach
        found = self.tree.query_ball_point(
            local, np.maximum(near + self.reach, 0.0), return_sorted=False
        )
        counts = np.fromiter((len(f) for f in found), dtype=np.int64, count=len(found))
        facets = np.fromiter(itertools.chain.from_iterable(found), np.int64, count=counts.sum())
        owner = np.repeat(np.arange(len(local)), counts)
        apart = np.linalg.norm(self._centroids[facets] - local[owner], axis=1)
        kept = apart <= near[owner] + self._radius[facets]
        counts = np.bincount(owner[kept], minlength=len(local))
        return np.concatenate([[0], np.cumsum(counts)]), facets[kept]

    def _from_candidates(self, local: np.ndarray, candidates):
        """(point, facet, gap) of each point among its kept candidate facets."""
        # A point without candidates (beyond the search distance) keeps these; distance()
        # replaces what they give.
        point = local.copy()
        facet = np.zeros(len(local), dtype=np.int64)
        gap = np.zeros(len(local))
        hint, anchor, room = self._kept_lists(len(local))
        if not KEEP_NEAREST:
            closest_facets(
                local, self.corners, self._centroids, self._radius, SLACK * self.reach,
                candidates[0], candidates[1], hint, point, facet, gap,
            )  # fmt: skip
            self._hint = facet
            return point, facet, gap
        closest_facets_kept(
            local, self.corners, self._centroids, self._radius, SLACK * self.reach,
            candidates[0], candidates[1], hint, anchor, room, point, facet, gap,
        )  # fmt: skip
        self._hint = facet
        self._kept = (facet, anchor, room)
        return point, facet, gap

    def _kept_lists(self, count: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(hint (k,), anchor (k, 3), room (k,)) for ``count`` points: each point's facet of
        the last call (mostly its nearest again: the candidates further than it are skipped,
        the answer the same, elements/facet_search.py; -1 for none) and its room to move
        keeping it, valid with the hints it was found with (anew, -1, where those are not
        this tool's)."""
        hint = getattr(self, "_hint", None)  # (absent from a tool pickled before it was kept)
        if hint is None or hint.shape != (count,):
            hint = np.full(count, -1)
        kept = getattr(self, "_kept", None)
        if kept is None or kept[0] is not getattr(self, "_hint", None):
            kept = (hint, np.zeros((count, 3)), np.full(count, -1.0))
        return hint, kept[1], kept[2]

    def _forget_nearest(self, rows: np.ndarray) -> None:
        """The points ``rows`` got new candidate lists: their rooms are asked anew."""
        kept = getattr(self, "_kept", None)
        if kept is not None and kept[2].shape == rows.shape:
            kept[2][rows] = -1.0

    def distance(self, x: np.ndarray, load_factor: float = 0.0):
        local = np.asarray(x, dtype=float) - self.offset(load_factor)
        last = self._last
        if last is not None and np.array_equal(last[0], local):
            return last[1].copy(), last[2].copy()  # asked again (the energy check of a step)
        cache = self._prepared(local)
        point, facet, gap = self._from_candidates(local, (cache.start, cache.facets))
        d, n = self._signed(local, point, facet, gap)
        far = cache.far
        if far.any():
            # Points beyond the search distance have no candidates: what they are told is a
            # distance less than their true one and more than the search distance.
            moved_by = np.linalg.norm(local[far] - cache.points[far], axis=1)
            d[far] = cache.distance[far] - np.sign(cache.distance[far]) * moved_by
            n[far] = cache.normal[far]
        if getattr(self, "smooth", False):
            near = np.flatnonzero(~far & (np.abs(d) < self.reach))
            gap, normal, found = smoothed_gap(
                local[near], facet[near], self.corners, self._triangles, self.normals,
                self._corner_normals, self._rings,
            )  # fmt: skip
            d[near[found]], n[near[found]] = gap[found], normal[found]
        self._last = (local.copy(), d.copy(), n.copy())
        self._last_facet = facet  # each point's closest facet, for normal_gradient
        if getattr(self, "record_facets", True):
            self._note_facets(np.where(far, -1, facet))
        return d, n

    def _prepared(self, local: np.ndarray) -> _Candidates:
        """The candidate lists for the points ``local`` (k, 3) (the tool's frame), searched
        again where they have moved past the margin (class docstring), kept as the cache."""
        cache = self._cache
        if cache is None or cache.points.shape != local.shape:
            cache = self._searched(local, np.ones(len(local), dtype=bool), None)
            self._kept = None
        else:
            # Each coordinate within MARGIN / sqrt(3): the point within MARGIN of where it
            # was searched, and its kept candidates still hold its closest facet.
            limit = MARGIN / np.sqrt(3.0) * self.reach
            if largest_drift(local, cache.points) >= limit:  # (compiled: at every call)
                drift = np.abs(local - cache.points).max(axis=1, initial=0.0)
                # Those nearly past it too (REBUILD_SHARE): a search is exact whenever done.
                rows = drift >= REBUILD_SHARE * limit
                cache = self._searched(local, rows, cache)
                self._forget_nearest(rows)
        self._cache = cache
        return cache

    def _note_facets(self, facet: np.ndarray) -> None:
        """Keep each point's closest facet (k,) (-1 beyond the search distance) of this call
        in the record, a column a call; points asked in another number start it anew."""
        record = getattr(self, "_record", None)
        if record is None or len(record) != len(facet):
            self._record = record = np.full((len(facet), FACET_RECORD), -1, dtype=np.int64)
            self._recorded = 0
        record[:, self._recorded % FACET_RECORD] = facet
        self._recorded += 1

    def facet_record(self) -> np.ndarray:
        """(k, m) the closest facet of each of the points of the last calls of ``distance``
        (k of them in every call), oldest first, m = min(calls, FACET_RECORD) columns; -1
        beyond the search distance. A pressed node that a solver carries back and forth
        across an edge between two facets shows the two in turn (solvers/stop_diagnosis.py).
        Kept while ``record_facets`` is on (a contact's ``freeze``, Static's): an explicit
        run does not pay for it."""
        record = getattr(self, "_record", np.zeros((0, FACET_RECORD), dtype=np.int64))
        calls = getattr(self, "_recorded", 0)
        if calls < FACET_RECORD:
            return record[:, :calls].copy()
        return np.roll(record, -(calls % FACET_RECORD), axis=1)

    def _searched(self, local: np.ndarray, rows: np.ndarray, cache: _Candidates | None):
        """The candidates kept, with the points ``rows`` (k,) bool searched again where they
        are now (all of them without a ``cache``): the other points keep theirs."""
        at = np.flatnonzero(rows)
        here = local[at]
        point, facet, gap = self._search(here)
        d, n = self._signed(here, point, facet, gap)
        far = gap > self.search_distance
        start, facets = self._candidates(here, np.where(far, -np.inf, gap))
        if cache is None:
            return _Candidates(here.copy(), start, facets, far, d, n)
        counts = np.diff(cache.start)
        kept = np.flatnonzero(~rows)
        counts[at] = np.diff(start)
        merged_start = np.concatenate([[0], np.cumsum(counts)])
        merged = np.empty(merged_start[-1], dtype=np.int64)
        merged[spans(merged_start, kept)] = cache.facets[spans(cache.start, kept)]
        merged[spans(merged_start, at)] = facets
        points, distance, normal = cache.points.copy(), cache.distance.copy(), cache.normal.copy()
        points[at], distance[at], normal[at] = here, d, n
        far_all = cache.far.copy()
        far_all[at] = far
        return _Candidates(points, merged_start, merged, far_all, distance, normal)

    def _search(self, local: np.ndarray):
        """The closest facet of each point by the k-d tree (class docstring)."""
        count = min(CANDIDATES, self.n_facets)
        point, facet, gap, spread = self._closest(local, count)
        band = self.search_distance

        def doubtful(spread, gap):  # a facet closer than min(gap, band) may be unexamined
            return spread < np.minimum(gap, band) + self.reach

        unsure = doubtful(spread, gap)
        while unsure.any() and count < self.n_facets:
            count = min(4 * count, self.n_facets)
            p, f, g, s = self._closest(local[unsure], count)
            point[unsure], facet[unsure], gap[unsure] = p, f, g
            spread[unsure] = s
            unsure[unsure] = doubtful(s, g)
        return point, facet, gap

    def _signed(self, local, point, facet, gap):
        """Signed distance and normal from the closest points (class docstring): the
        formulas of ``_signed_numpy`` in one compiled pass (elements/facet_search.py), the
        points behind a facet (rare: past an open edge, or inside the tool) corrected after
        it; the same numbers to the last bit."""
        d = np.empty(len(local))
        normal = np.empty((len(local), 3))
        tiny = 1e-12 * max(self.reach, 1.0)
        signed_from_closest(local, point, facet, gap, self.normals, tiny, d, normal)
        behind = np.flatnonzero(np.signbit(d))
        if behind.size:  # past an open edge: beside the tool, not in it (class docstring)
            f = facet[behind]
            past = np.einsum(
                "kej,kej->ke", local[behind, None, :] - self.edge_start[f], self.edge_out[f]
            )
            beside = behind[(past > 1e-9 * self.reach).any(axis=1)]
            d[beside] = gap[beside]
            turned = beside[gap[beside] > tiny]  # the direction from the point, side +1
            normal[turned] = -normal[turned]
        return d, normal

    def _signed_numpy(self, local, point, facet, gap):
        """``_signed`` in numpy passes over the points (the reference it is tested against)."""
        facet_normal = self.normals[facet]
        towards = local - point
        side = np.where(np.sum(towards * facet_normal, axis=1) < 0.0, -1.0, 1.0)
        behind = np.flatnonzero(side < 0.0)
        if behind.size:  # past an open edge: beside the tool, not in it (class docstring)
            f = facet[behind]
            past = np.einsum(
                "kej,kej->ke", local[behind, None, :] - self.edge_start[f], self.edge_out[f]
            )
            side[behind[(past > 1e-9 * self.reach).any(axis=1)]] = 1.0
        # Off the surface the normal is the direction from the closest point; on it (or
        # within rounding of it) that of the facet.
        along = gap > 1e-12 * max(self.reach, 1.0)
        normal = np.where(
            along[:, None],
            side[:, None] * towards / np.where(along, gap, 1.0)[:, None],
            facet_normal,
        )
        return side * gap, normal

    def projector_scale(self, x: np.ndarray, load_factor: float = 0.0) -> np.ndarray:
        return np.zeros(len(x))

    def normal_gradient(
        self, x: np.ndarray, normal: np.ndarray, load_factor: float = 0.0
    ) -> np.ndarray:
        """(k, 3, 3) dn/dx at the points x (k, 3) whose normals ``distance`` gave as ``normal``
        (k, 3) (docs/theory.md §9.3). Inside a facet the normal is the facet's: 0. Where the
        closest point c lies on an edge of direction e, n = (x - c) / d turns about it:
        (I - n n^T - e e^T) / d, d the signed distance; on a vertex (I - n n^T) / d. A
        smoothed normal (``smooth``) turns with its Phong patch as the closest point slides
        on it (elements/facet_normal.py ``turn_on_patches``). A point whose normal is neither
        (a point beyond the search distance, or on the surface) gets 0."""
        local = np.asarray(x, dtype=float) - self.offset(load_factor)
        d, _ = self.distance(x, load_factor)
        out = np.zeros((len(local), 3, 3))
        tiny = 1e-9 * max(self.reach, 1.0)
        near = np.abs(d) <= self.search_distance
        rows = np.flatnonzero(near & (np.abs(d) > tiny))
        if rows.size:
            point, facet, _ = self._search(local[rows])
            out[rows] = turn_round_features(
                local[rows],
                d[rows],
                normal[rows],
                point,
                self.corners[facet],
                self.normals[facet],
                tiny,
            )
        rows = np.flatnonzero(near)
        if getattr(self, "smooth", False) and rows.size:
            # Where distance() gave the patch's normal, the patch's turn: from the facet it
            # was found with (at a tie on a shared edge another facet's ring may pick the
            # neighbouring patch, whose normal differs by the patches' own 0.005 deg).
            facet = self._last_facet[rows]
            _, patch_normal, found, turn = smoothed_gap(
                local[rows], facet, self.corners, self._triangles, self.normals,
                self._corner_normals, self._rings, turning=True,
            )  # fmt: skip
            agrees = found & (np.linalg.norm(patch_normal - normal[rows], axis=1) <= 1e-9)
            out[rows[agrees]] = turn[agrees]
        return out

    def side_hint(self) -> str:
        flipped = "flip = true" if self.flipped else "flip = false"
        return f"the facets' normals (with {flipped}) must point towards the body"
