"""A rigid tool meshed with triangles (a die, a table, a holder's plate): the signed distance
of points to it, their normals and the normals' turn, found from candidate lists kept between
calls (``RigidSurface``; the search's compiled loops in elements/facet_search.py, the smoothed
normal field in elements/tool_smoothing.py). The tool's motion, its free axes and their force
are those of every rigid tool (elements/tools.py ``RigidTool``). Units: mm.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from elements.facet_normal import turn_round_features
from elements.facet_search import (
    SHORT,
    SLACK,
    candidate_rows,
    closest_facets,
    closest_facets_kept,
    closest_facets_listed,
    closest_of_nearest,
    closest_on_triangles,
    largest_drift,
    open_edges,
    signed_from_closest,
    spans,
)
from elements.node_rows import same_rows
from elements.tool_smoothing import corner_normals, facet_rings, smoothed_gap
from elements.tools import RigidTool
from femcore.checks import as_flag, check_positive
from femcore.jit import threads_for
from femcore.loads import AmplitudeFunction
from femcore.topology import ZERO_AREA_TOL, opposed_neighbours

__all__ = ["RigidSurface"]


# How far (in facet circumradii) a point may move before RigidSurface searches it again
# (any margin gives the same answers: exact within the search distance, above it beyond;
# larger, the kept lists hold more facets and serve
# longer: on the hemisphere die under the two-ply Mindlin [0/90] blank 0.25 -> 0.5 halved
# the searches, 1002 -> 489 a run, and took its step 1.467-1.500 -> 1.384-1.438 ms, the same
# final positions to the bit; hemisphere-forming the same figures, 33.4 -> 32.7 s of CPU;
# benchmarks/die_margin.py).
MARGIN = 0.5
# When some point has moved past the margin, the points that have moved past this share of it
# are searched again with it: the searches come in batches, one every few hundred explicit
# steps, instead of a few points at every step, each batch paying the merge of the kept
# candidates (O(all candidates)) once (1.0: only the points past the margin).
REBUILD_SHARE = 0.5
# Whether a point that has not moved far enough to change its nearest facet is given that
# facet alone instead of a scan of its candidates (elements/facet_search.closest_facets_kept:
# the same answer to the last bit).
KEEP_NEAREST = True
# Whether a point whose nearest facet may have changed scans its short list (its SHORT nearest
# candidates at its last scan) while the nearest must be on it, instead of every candidate
# (elements/facet_search.closest_facets_listed: the same answer to the last bit).
SHORT_LISTS = True
# How many calls of RigidSurface.distance each point's closest facet is kept for
# (``facet_record``).
FACET_RECORD = 16
# Nearest facet centroids examined per point; more are examined where these cannot be
# shown to contain the closest facet (RigidSurface.distance).
CANDIDATES = 8


# A batched search costs some ten microseconds a point (the k-d tree's queries, the closest
# points on the nearest facets, the candidates' ball), some twenty times a force pass's cell:
# the k-d tree's queries of k points run on the threads of a loop over SEARCH_WEIGHT k cells.
SEARCH_WEIGHT = 20


def _check_facets_agree(triangles: np.ndarray) -> None:
    """ValueError naming the facets for two neighbours whose normals point to opposite
    sides (femcore.topology.opposed_neighbours): the tool's side would change from facet to
    facet, a point above one of them inside the other. Separate pieces may face their own
    ways; an edge of three or more facets is not judged."""
    opposed = opposed_neighbours(triangles)
    if len(opposed):
        t0, t1, start, end = opposed[0].tolist()
        more = f" (and {len(opposed) - 1} more such pairs)" if len(opposed) > 1 else ""
        raise ValueError(
            f"RigidSurface: facets {t0} and {t1} both run their shared edge {start} -> {end} "
            f"the same way{more}: their normals point to opposite sides, so a point above "
            "one is inside the other; reorient the facets so that neighbours run a shared "
            "edge in opposite directions (every normal towards the body), e.g. with the "
            "mesher's 'reorient' or 'fix normals'"
        )


def _workers(points: int) -> int:
    """The threads the k-d tree's queries of ``points`` points run on (scipy's ``workers``):
    femcore/jit.py's count for a loop of SEARCH_WEIGHT times as many cells. Each point's
    answer is its own, whatever the threads."""
    return threads_for(SEARCH_WEIGHT * points)


@dataclass(frozen=True)
class _Candidates:
    """What RigidSurface keeps of its last search: the points (k, 3), in the tool's frame;
    each point's candidate facets facets[start[i]:start[i + 1]] (none for the points ``far``
    (k,) bool, beyond ``far_from``, the search distance plus the margin, mm, when searched);
    the distances (k,) and normals (k, 3) found."""

    points: np.ndarray
    start: np.ndarray
    facets: np.ndarray
    far: np.ndarray
    distance: np.ndarray
    normal: np.ndarray
    far_from: float


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
    sags below the table's plane without being inside it). A point h behind the face that
    crosses such a line goes from +h to -h at once (docs/theory.md §9.3, "Open edges"): a
    tool whose edge a body can pass behind (a holder's bore) is meshed closed there. The
    closest facet is found
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
    search distance plus the margin, which are told their distance less how far they moved,
    more than the search distance), and answers from
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
        from femcore.mesh_io import read_mesh

        super().__init__(motion, amplitude=amplitude, free=free, force=force, mass=mass)
        if not isinstance(mesh, Mesh):
            try:
                # a tool's file: an Abaqus deck's rigid facets (R3D3, R3D4) are read
                mesh = read_mesh(mesh, tool=True)
            except (OSError, TypeError) as error:
                raise ValueError(f"RigidSurface: cannot read {mesh!r}: {error}") from None
        triangles = mesh.triangles
        if len(triangles) == 0:
            raise ValueError("RigidSurface needs a mesh with triangles (its facets), got none")
        self.corners = mesh.points[triangles]  # (f, 3, 3)
        a, b, c = self.corners[:, 0], self.corners[:, 1], self.corners[:, 2]
        normal = np.cross(b - a, c - a)
        length = np.linalg.norm(normal, axis=1)
        span = float(np.linalg.norm(mesh.points.max(axis=0) - mesh.points.min(axis=0)))
        # the mesh's own tolerance (femcore.topology: area <= ZERO_AREA_TOL diagonal^2)
        flat = np.flatnonzero(length <= 2.0 * ZERO_AREA_TOL * span**2)
        if flat.size:
            shown = ", ".join(str(int(t)) for t in flat[:10]) + (", ..." if flat.size > 10 else "")
            raise ValueError(
                f"RigidSurface: {flat.size} facet(s) of no area (coincident or collinear "
                f"nodes): {shown}"
            )
        _check_facets_agree(triangles)
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
        # With those hints: where each point's scan was, its room to keep its facet, and
        # (the short lists' kernel) that facet's corners and normal.
        self._kept: tuple[np.ndarray, ...] | None = None
        # The points' short lists (``_near_lists``).
        self._near: tuple[np.ndarray, ...] | None = None
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
        facet (k,), gap (k,), distance to the furthest centroid examined (k,)), the k-d
        tree's query on the threads ``_workers`` gives, the closest points in one compiled
        pass (elements/facet_search.py ``closest_of_nearest``): ``_closest_numpy``'s
        numbers to the last bit."""
        spread, facets = self.tree.query(x, k=count, workers=_workers(len(x)))
        spread, facets = spread.reshape(len(x), -1), facets.reshape(len(x), -1)
        point = np.empty((len(x), 3))
        facet = np.empty(len(x), dtype=np.int64)
        gap = np.empty(len(x))
        closest_of_nearest(
            np.ascontiguousarray(x, dtype=float), self.corners, facets.astype(np.int64), point,
            facet, gap,
        )  # fmt: skip
        return point, facet, gap, spread[:, -1]

    def _closest_numpy(self, x: np.ndarray, count: int):
        """``_closest`` in numpy passes (the reference it is tested against)."""
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

    @property
    def beside_tolerance(self) -> float:
        """How far (mm) past an open edge's line a point behind its facet must be to count as
        beside the tool, not in it: 1e-9 of the largest facet's circumradius (a point on the
        edge's line, within rounding, is in the facet's plane and stays behind it)."""
        return 1e-9 * self.reach

    @property
    def on_surface_tolerance(self) -> float:
        """The gap (mm) below which a point is on the surface and takes its facet's normal
        (further, the direction from its closest point): 1e-12 of the reach, or of 1 mm for
        tools smaller than that, rounding's scale of the closest point's coordinates."""
        return 1e-12 * max(self.reach, 1.0)

    def exact_within(self, distance: float) -> None:
        if not self._given_search and distance > self.search_distance:
            self.search_distance = float(distance)
            self._cache = self._last = None

    def _candidates(self, local: np.ndarray, gap: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Every facet that can hold a point's closest point while it moves less than the
        cache's margin (MARGIN circumradius): within its distance ``gap`` (k,) (-inf: none)
        plus twice the margin of the point, so with its centroid within that plus the facet's
        own circumradius (the k-d tree finds those within the largest one, then each is held
        to its own), as (start (k + 1,), facets): point i's are facets[start[i]:start[i + 1]].
        A point searched beyond the search distance (the search there is an upper bound of
        its distance, at least the search distance) still gets every facet that can be its
        closest: the true closest is nearer than the bound."""
        near = gap + 2.0 * MARGIN * self.reach
        found = self.tree.query_ball_point(
            local,
            np.maximum(near + self.reach, 0.0),
            return_sorted=False,
            workers=_workers(len(local)),
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
        if not KEEP_NEAREST:
            hint, _, _, _ = self._kept_lists(len(local))
            closest_facets(
                local, self.corners, self._centroids, self._radius, SLACK * self.reach,
                candidates[0], candidates[1], hint, point, facet, gap,
            )  # fmt: skip
            self._hint = facet
            return point, facet, gap
        self._closest_kept(local, candidates[0], candidates[1], point, facet, gap)
        return point, facet, gap

    def _closest_kept(self, local, start, facets, point, facet, gap) -> None:
        """Each point's closest point, facet and gap among its candidate facets[start[i]:
        start[i + 1]] into point (k, 3), facet (k,), gap (k,): its last nearest facet alone
        while it cannot change, else its short list while the nearest is on it, else a scan
        (``SHORT_LISTS``; elements/facet_search.py), the hints, rooms and lists kept for the
        next call."""
        hint, anchor, room, corners = self._kept_lists(len(local), SHORT_LISTS)
        if not SHORT_LISTS:
            closest_facets_kept(
                local, self.corners, self._centroids, self._radius, SLACK * self.reach,
                start, facets, hint, anchor, room, point, facet, gap,
            )  # fmt: skip
            self._hint = facet
            self._kept = (facet, anchor, room)
            return
        near = self._near_lists(len(local))
        rows = getattr(self, "_rows", None)  # the candidates' copies, made once a list
        if rows is None or rows[0] is not facets:
            rows = (facets, *candidate_rows(
                facets, self.corners, self.normals, self._centroids, self._radius
            ))  # fmt: skip
            self._rows = rows
        closest_facets_listed(
            local, self.corners, SLACK * self.reach, start, facets, rows[1], rows[2], hint,
            anchor, room, corners, *near, point, facet, gap,
        )  # fmt: skip
        assert corners is not None  # (asked of _kept_lists with the short lists)
        self._hint = facet
        self._kept = (facet, anchor, room, corners)
        self._near = near

    def _near_lists(self, count: int) -> tuple[np.ndarray, ...]:
        """(anchor (k, 3), room (k,), cut (k,), facets (k, SHORT), the scans' scratch
        (k, SHORT + 1) twice, and the listed facets' corners and normals (k SHORT, 4, 3)) of
        the short lists of ``count`` points, kept from the last call where valid (the rooms
        -1, asking for a scan, otherwise)."""
        near = getattr(self, "_near", None)  # (absent from a tool pickled before the lists)
        kept = getattr(self, "_kept", None)
        if near is None or len(near[1]) != count or kept is None or len(near) < 7:
            near = (
                np.zeros((count, 3)), np.full(count, -1.0), np.zeros(count),
                np.full((count, SHORT), -1, dtype=np.int64), np.zeros((count, SHORT + 1)),
                np.zeros((count, SHORT + 1), dtype=np.int64), np.zeros((count * SHORT, 4, 3)),
            )  # fmt: skip
        return near

    def _kept_lists(
        self, count: int, corners: bool = False
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray | None]:
        """(hint (k,), anchor (k, 3), room (k,), the hints' corners and normals (k, 4, 3) or
        None) for ``count`` points: each point's facet of the last call (mostly its nearest
        again: the candidates further than it are skipped, the answer the same,
        elements/facet_search.py; -1 for none) and its room to move keeping it, valid with
        the hints it was found with (anew, -1, where those are not this tool's, or where
        ``corners`` is asked and the last call kept none: the short lists' kernel reads the
        kept facet's corners from that copy wherever a room is > 0)."""
        hint = getattr(self, "_hint", None)  # (absent from a tool pickled before it was kept)
        if hint is None or hint.shape != (count,):
            hint = np.full(count, -1)
        kept: tuple[np.ndarray, ...] | None = getattr(self, "_kept", None)
        if (
            kept is None
            or kept[0] is not getattr(self, "_hint", None)
            or (corners and len(kept) < 4)
        ):
            kept = (hint, np.zeros((count, 3)), np.full(count, -1.0))
        copied = None
        if corners:
            copied = kept[3] if len(kept) > 3 else np.zeros((count, 4, 3))
        return hint, kept[1], kept[2], copied

    def _forget_nearest(self, rows: np.ndarray) -> None:
        """The points ``rows`` got new candidate lists: their rooms and short lists are
        asked anew."""
        kept = getattr(self, "_kept", None)
        if kept is not None and kept[2].shape == rows.shape:
            kept[2][rows] = -1.0
        near = getattr(self, "_near", None)
        if near is not None and near[1].shape == rows.shape:
            near[1][rows] = -1.0

    def distance(self, x: np.ndarray, load_factor: float = 0.0):
        if np.ndim(x) != 2 or np.shape(x)[1] != 3:
            raise ValueError(f"points of shape {np.shape(x)} given: expected (k, 3) in mm")
        local = np.asarray(x, dtype=float) - self.offset(load_factor)
        if len(local) == 0:
            return np.zeros(0), np.zeros((0, 3))
        last = self._last
        if last is not None and same_rows(last[0], local):
            return last[1].copy(), last[2].copy()  # asked again (the energy check of a step)
        cache = self._prepared(local)
        point, facet, gap = self._from_candidates(local, (cache.start, cache.facets))
        d, n = self._signed(local, point, facet, gap)
        far = cache.far
        if far.any():
            # Points beyond the search distance plus the margin have no candidates: what they
            # are told is a distance less than their true one (the triangle inequality) and,
            # having moved less than the margin since their search, more than the search
            # distance.
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
        self._remember(local.copy(), d.copy(), n.copy(), facet, far)
        return d, n

    def exact_distance(self, x: np.ndarray, load_factor: float = 0.0):
        """(d (k,), n (k, 3)) the signed distance, mm, and normal of the closest point of the
        facets at any distance, whatever the search distance (``distance`` tells a point
        beyond it a lower bound), without the cache (nothing kept: a few points, the landing
        nodes' approach, elements/contact_history.py); with ``smooth``, the Phong gap within
        a facet's reach, as ``distance`` gives it."""
        if np.ndim(x) != 2 or np.shape(x)[1] != 3:
            raise ValueError(f"points of shape {np.shape(x)} given: expected (k, 3) in mm")
        local = np.asarray(x, dtype=float) - self.offset(load_factor)
        if len(local) == 0:
            return np.zeros(0), np.zeros((0, 3))
        point, facet, gap = self._search(local, np.inf)
        d, n = self._signed(local, point, facet, gap)
        if getattr(self, "smooth", False):
            near = np.flatnonzero(np.abs(d) < self.reach)
            gap, normal, found = smoothed_gap(
                local[near], facet[near], self.corners, self._triangles, self.normals,
                self._corner_normals, self._rings,
            )  # fmt: skip
            d[near[found]], n[near[found]] = gap[found], normal[found]
        return d, n

    def _remember(self, local, d, n, facet, far) -> None:
        """Keep the answer of a call (the points ``local`` (k, 3) in the tool's frame, their
        distances d (k,) and normals n (k, 3), given to the tool to keep) for the same points
        asked again, each point's closest facet (k,) for ``normal_gradient``, and, while
        ``record_facets`` is on, that facet (-1 for the points ``far`` (k,) bool beyond the
        search distance) in the record."""
        self._last = (local, d, n)
        self._last_facet = facet
        if getattr(self, "record_facets", True):  # a tool pickled before the switch records
            self._note_facets(np.where(far, -1, facet))

    def _prepared(self, local: np.ndarray) -> _Candidates:
        """The candidate lists for the points ``local`` (k, 3) (the tool's frame), searched
        again where they have moved past the margin (class docstring), kept as the cache."""
        cache = self._cache
        # (A cache pickled before far_from was kept is made anew: its far points were
        # those beyond the search distance alone.)
        if (
            cache is None
            or cache.points.shape != local.shape
            or getattr(cache, "far_from", None) != self._far_from
        ):
            cache = self._searched(local, np.ones(len(local), dtype=bool), None)
            self._kept = self._near = None
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
        """Keep each point's closest facet (k,) (-1 for a point without candidates) of this call
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
        for a point without candidates (beyond the search distance plus the margin). A
        pressed node that a solver carries back and forth across an edge between two facets
        shows the two in turn (solvers/stop_diagnosis.py).
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
        far = gap > self._far_from
        start, facets = self._candidates(here, np.where(far, -np.inf, gap))
        if cache is None:
            return _Candidates(here.copy(), start, facets, far, d, n, self._far_from)
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
        return _Candidates(
            points, merged_start, merged, far_all, distance, normal, self._far_from
        )  # fmt: skip

    @property
    def _far_from(self) -> float:
        """The distance (mm) beyond which a searched point keeps no facets: the search
        distance plus the margin, so that a point told its distance less its move (less
        than the margin while it is not searched again) is told more than the search
        distance, never within it, whatever the search distance given."""
        return self.search_distance + MARGIN * self.reach

    def _search(self, local: np.ndarray, band: float | None = None):
        """The closest facet of each point by the k-d tree (class docstring), proved closest
        below ``band`` (mm; None: the search distance, inf: at any distance)."""
        count = min(CANDIDATES, self.n_facets)
        point, facet, gap, spread = self._closest(local, count)
        band = self.search_distance if band is None else band

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
        tiny = self.on_surface_tolerance
        signed_from_closest(local, point, facet, gap, self.normals, tiny, d, normal)
        behind = np.flatnonzero(np.signbit(d))
        if behind.size:  # past an open edge: beside the tool, not in it (class docstring)
            f = facet[behind]
            past = np.einsum(
                "kej,kej->ke", local[behind, None, :] - self.edge_start[f], self.edge_out[f]
            )
            beside = behind[(past > self.beside_tolerance).any(axis=1)]
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
            side[behind[(past > self.beside_tolerance).any(axis=1)]] = 1.0
        # Off the surface the normal is the direction from the closest point; on it (or
        # within rounding of it) that of the facet.
        along = gap > self.on_surface_tolerance
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
