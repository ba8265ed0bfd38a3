"""Generators of :class:`femcore.mesh.Mesh`: structured grids and the corner specimen.

Users call them as the classmethods :meth:`Mesh.rectangle`, :meth:`Mesh.line`,
:meth:`Mesh.quadrilateral`, :meth:`Mesh.from_quads` and :meth:`Mesh.corner`, which document
their parameters and delegate here.

Fibre-aligned generators (:func:`rectangle`, :func:`quadrilateral`) split each grid cell into
two triangles whose first local node is the corner where the warp (first grid direction) and
weft (second grid direction) meet: with 0-based local numbering, edge 0 -> 1 runs along the
warp and edge 0 -> 2 along the weft, in the positive or negative sense ("node 1 at the right
angle, 1 -> 2 along warp, 1 -> 3 along weft" in 1-based terms).

``diagonals`` chooses the diagonal that splits each grid cell (docs/theory.md §5.3):
"one-way" (the default) splits every cell along the same diagonal, from (i + 1, j) to
(i, j + 1); "alternating" flips it on every other cell, a checkerboard, splitting those cells
along (i, j) to (i + 1, j + 1) into (b, c, a) and (d, a, c) of the cell (a, b, c, d): still
counter-clockwise and right-angled at local node 0, with edge 0 -> 1 along the weft there (the
fibrous shell renumbers each triangle from its fibre corner at bind, docs/theory.md §1.5). The
MITC3 triangle locks in two-way bending of thin plates on the one-way pattern and not on the
alternating one; the fibrous shell's bending wants the one-way pattern (docs/theory.md §5.3).
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterator, Mapping
from types import ModuleType
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from femcore.checks import as_number, as_reals
from femcore.memory import check_mesh_memory
from femcore.mesh import Mesh

__all__ = [
    "DIAGONALS",
    "corner",
    "from_quads",
    "grid_quads",
    "line",
    "quadrilateral",
    "rectangle",
    "split_quads",
]

#: The diagonal patterns of the structured generators (the module's docstring).
DIAGONALS = ("one-way", "alternating")

# Relative tolerances of the quadrilateral corner checks (times the corner diameter).
_PLANARITY_TOL = 1e-9
_CONVEXITY_TOL = 1e-12


def rectangle(
    lx: float,
    ly: float,
    nx: int,
    ny: int,
    origin: ArrayLike = (0.0, 0.0, 0.0),
    diagonals: str = "one-way",
) -> Mesh:
    """Fibre-aligned right-triangle mesh of an lx x ly rectangle (length units), nx x ny
    grid cells split along ``diagonals``: the implementation of :meth:`Mesh.rectangle`, which
    documents the numbering, the sets and the errors."""
    lx = _positive_length(lx, "lx")
    ly = _positive_length(ly, "ly")
    nx = _positive_int(nx, "nx")
    ny = _positive_int(ny, "ny")
    _check_diagonals(diagonals)
    base = _point3(origin, "origin")
    _check_grid_memory(f"Mesh.rectangle(nx={nx}, ny={ny})", nx, ny)
    # linspace hits the far edge exactly, unlike i * (lx / nx).
    x, y = np.meshgrid(np.linspace(0.0, lx, nx + 1), np.linspace(0.0, ly, ny + 1))
    points = base + np.column_stack((x.ravel(), y.ravel(), np.zeros(x.size)))
    triangles = split_quads(grid_quads(nx, ny), _flipped(nx, ny, diagonals))
    return Mesh(
        points,
        triangles,
        node_sets=_grid_node_sets(nx, ny),
        element_sets={"all": np.arange(len(triangles))},
    )


def line(p0: ArrayLike, p1: ArrayLike, n: int) -> Mesh:
    """n equal 2-node line cells from p0 to p1 (points (3,) or (2,), length units): the
    implementation of :meth:`Mesh.line`, which documents the numbering, the sets and the
    errors."""
    a = _point3(p0, "p0")
    b = _point3(p1, "p1")
    n = _positive_int(n, "n")
    check_mesh_memory(n, n + 1, f"Mesh.line(n={n})", "lines")
    if np.array_equal(a, b):
        raise ValueError(f"p0 and p1 must differ, both are {a.tolist()}")
    t = np.linspace(0.0, 1.0, n + 1)[:, None]
    points = (1.0 - t) * a + t * b  # exact at both ends, unlike a + t * (b - a)
    lines = np.column_stack((np.arange(n), np.arange(1, n + 1)))
    return Mesh(
        points,
        lines=lines,
        node_sets={"start": [0], "end": [n]},
        line_sets={"all": np.arange(n)},
    )


def quadrilateral(corners: ArrayLike, nx: int, ny: int, diagonals: str = "one-way") -> Mesh:
    """Fibre-aligned structured triangle mesh of a planar convex quadrilateral (corners
    (4, 3) or (4, 2), length units) via gmsh, its cells split along ``diagonals``: the
    implementation of :meth:`Mesh.quadrilateral`, which documents the numbering, the sets
    and the errors."""
    quad, normal = _validate_quadrilateral(corners)
    nx = _positive_int(nx, "nx")
    ny = _positive_int(ny, "ny")
    _check_diagonals(diagonals)
    _check_grid_memory(f"Mesh.quadrilateral(nx={nx}, ny={ny})", nx, ny)
    coords, quads = _gmsh_structured_quads(quad, nx, ny)
    if len(quads) != nx * ny:
        raise RuntimeError(f"gmsh returned {len(quads)} quadrangles, expected {nx * ny}")
    points, quads = _structured_numbering(quad, coords, quads, nx, ny)
    quads = _orient_quads(points, quads, normal)
    eta = (quads // (nx + 1)).min(axis=1) / ny + 0.5 / ny  # weft parameter of centroid
    warp = (1.0 - eta)[:, None] * (quad[1] - quad[0]) + eta[:, None] * (quad[2] - quad[3])
    triangles = split_quads(_rotate_to_warp(points, quads, warp), _flipped(nx, ny, diagonals))
    return Mesh(
        points,
        triangles,
        node_sets=_grid_node_sets(nx, ny),
        element_sets={"all": np.arange(len(triangles))},
    )


def from_quads(
    points: ArrayLike,
    quads: ArrayLike,
    node_sets: Mapping[str, ArrayLike] | None = None,
    quad_sets: Mapping[str, ArrayLike] | None = None,
) -> Mesh:
    """A triangle mesh from quads (q, 4), each quad (a, b, c, d) split into (a, b, d) and
    (c, d, b): the implementation of :meth:`Mesh.from_quads`, which documents the
    parameters, the sets and the errors."""
    quads = np.asarray(quads)
    if quads.ndim != 2 or quads.shape[1] != 4 or len(quads) == 0:
        raise ValueError(f"quads must have shape (q, 4) with q >= 1, got {quads.shape}")
    check_mesh_memory(2 * len(quads), len(np.asarray(points)), "Mesh.from_quads", "triangles")
    sets = {}
    for name, ids in (quad_sets or {}).items():
        ids = np.asarray(ids, dtype=np.int64).ravel()
        if ids.size and (ids.min() < 0 or ids.max() >= len(quads)):
            raise ValueError(f"quad set {name!r} refers to quads outside 0..{len(quads) - 1}")
        sets[name] = np.column_stack([2 * ids, 2 * ids + 1]).ravel()
    return Mesh(
        points,
        triangles=split_quads(quads.astype(np.int64)),
        node_sets=node_sets,
        element_sets=sets,
    )


def corner(
    lx: float, ly: float, n: int, grip: ArrayLike | None = None, diagonals: str = "one-way"
) -> Mesh:
    """The corner specimen of Bai et al. (2020) §6 (Fig. 8): the free triangle of an lx x ly
    rectangle beyond its diagonal, cut from :func:`rectangle` with n x n cells (or, with
    ``grip``, from the graded grid of :func:`_corner_grid`), split along ``diagonals`` (the
    cells on the clamp always along it): the implementation of :meth:`Mesh.corner`, which
    documents the result."""
    lx = _positive_length(lx, "lx")
    ly = _positive_length(ly, "ly")
    n = _positive_int(n, "n")
    _check_diagonals(diagonals)
    _check_grid_memory(f"Mesh.corner(n={n})", n, n)
    # the checkerboard's phase that keeps the cells i + j = n - 1, cut by the clamp, one-way
    flipped = _flipped(n, n, diagonals, phase=n - 1)
    if grip is None:
        x, y = np.linspace(0.0, lx, n + 1), np.linspace(0.0, ly, n + 1)
    else:
        grip_x, grip_y = _grip_size(grip, lx, ly)
        x, y = _corner_grid(lx, ly, n, grip_x, grip_y)
    gx, gy = np.meshgrid(x, y)
    full = Mesh(
        np.column_stack((gx.ravel(), gy.ravel(), np.zeros(gx.size))),
        split_quads(grid_quads(n, n), flipped),
    )
    p = full.points
    centroids = p[full.triangles].mean(axis=1)
    keep = centroids[:, 0] / lx + centroids[:, 1] / ly < 1.0
    used = np.unique(full.triangles[keep])
    renumber = np.full(len(p), -1)
    renumber[used] = np.arange(used.size)
    points = p[used]
    mesh = Mesh(points, renumber[full.triangles[keep]])
    on_diagonal = np.abs(points[:, 0] / lx + points[:, 1] / ly - 1.0) < 1e-9
    mesh.add_node_set("clamp", np.flatnonzero(on_diagonal))
    mesh.add_node_set("corner", np.flatnonzero(np.linalg.norm(points[:, :2], axis=1) < 1e-9 * lx))
    if grip is not None:
        inside = (points[:, 0] <= grip_x * (1.0 + 1e-9)) & (points[:, 1] <= grip_y * (1.0 + 1e-9))
        mesh.add_node_set("grip", np.flatnonzero(inside))
    return mesh


def _grip_size(grip: ArrayLike, lx: float, ly: float) -> tuple[float, float]:
    """The gripped patch (a, b) along x and y (mm) of ``grip``, one size (a square) or two;
    the patch must leave at least one cell of the grid free before the clamp."""
    try:
        size = np.broadcast_to(as_reals(grip, "grip", "a size or a pair of sizes"), (2,))
    except ValueError as err:
        raise ValueError(f"grip must be a size or a pair of sizes, got {grip!r}") from err
    a, b = (float(v) for v in size)
    if not (np.isfinite(a) and np.isfinite(b) and a > 0.0 and b > 0.0 and a / lx + b / ly < 1.0):
        raise ValueError(
            f"grip must be positive sizes (a, b) with a / lx + b / ly < 1 (the patch before "
            f"the clamped diagonal), got {grip!r} for lx = {lx}, ly = {ly}"
        )
    return a, b


def _corner_grid(lx: float, ly: float, n: int, a: float, b: float) -> tuple[np.ndarray, np.ndarray]:
    """Grid lines x (n + 1,) and y (n + 1,) of the corner specimen with a gripped a x b patch
    at the origin whose edges x = a and y = b are grid lines at every n.

    The clamp must stay a line of cell diagonals: node (i, n - i) on x / lx + y / ly = 1, so
    the grid is one parameter t (0 .. 1) with x_i = lx t_i and y_j = ly (1 - t_(n - j)); t has
    nodes at a / lx (the patch's edge in x) and 1 - b / ly (its edge in y). Between them and
    the ends it is uniform, at least one cell per piece; the patch's pieces take as many cells
    as keep them no longer than 1 / n in t (the patch is never coarser than the uniform grid),
    the piece between takes the rest (its cells longer than 1 / n by the at most two cells the
    rounding up gave the patch).
    """
    low, high = a / lx, 1.0 - b / ly
    # ceil less a hair, so that a patch of exactly k / n keeps k cells
    first = max(1, int(np.ceil(low * n - 1e-9)))
    last = max(1, int(np.ceil((1.0 - high) * n - 1e-9)))
    middle = n - first - last
    if middle < 1:
        raise ValueError(
            f"n = {n} cells leave none between the gripped patch and the clamp; give n >= "
            f"{first + last + 1}"
        )
    t = np.concatenate(
        (
            np.linspace(0.0, low, first + 1),
            np.linspace(low, high, middle + 1)[1:],
            np.linspace(high, 1.0, last + 1)[1:],
        )
    )
    return lx * t, ly * (1.0 - t[::-1])


# --------------------------------------------------------------------------------------------
# Argument checks and structured grids
# --------------------------------------------------------------------------------------------


def _positive_int(value: Any, name: str) -> int:
    # bool is an int subclass, but Mesh.rectangle(1, 1, True, 2) is certainly a mistake.
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 1:
        raise ValueError(f"{name} must be a positive integer, got {value!r}")
    return int(value)


def _positive_length(value: Any, name: str) -> float:
    length = as_number(value, name, "a positive finite number")
    if not np.isfinite(length) or length <= 0.0:
        raise ValueError(f"{name} must be a positive finite number, got {value!r}")
    return length


def _point3(value: ArrayLike, name: str) -> np.ndarray:
    point = as_reals(value, name, "a point (x, y[, z])")
    if point.shape not in ((2,), (3,)) or not np.isfinite(point).all():
        raise ValueError(f"{name} must be a finite point (x, y[, z]), got {value!r}")
    return np.append(point, 0.0) if point.size == 2 else point


def _check_grid_memory(call: str, nx: int, ny: int) -> None:
    """Refuse an nx x ny grid of 2 nx ny triangles that cannot be built in memory; ``call``
    names the generator in the message, e.g. "Mesh.rectangle(nx=10, ny=20)"."""
    check_mesh_memory(2 * nx * ny, (nx + 1) * (ny + 1), call, "triangles")


def grid_quads(nx: int, ny: int) -> np.ndarray:
    """(nx * ny, 4) counter-clockwise grid cells (a, b, c, d), a at (i, j), "for j, for i"."""
    j, i = np.divmod(np.arange(nx * ny), nx)
    a = j * (nx + 1) + i
    return np.column_stack((a, a + 1, a + nx + 2, a + nx + 1))


def split_quads(quads: np.ndarray, flipped: np.ndarray | None = None) -> np.ndarray:
    """(2q, 3) triangles T_A = (a, b, d), T_B = (c, d, b) of quads (q, 4), interleaved; the
    quads where ``flipped`` (q,) bool is True split along the other diagonal into (b, c, a)
    and (d, a, c) (both keep the quad's sense and a right angle of a rectangle at node 0)."""
    pattern = np.stack((quads[:, [0, 1, 3]], quads[:, [2, 3, 1]]), axis=1)
    if flipped is not None and flipped.any():
        pattern[flipped] = np.stack((quads[flipped][:, [1, 2, 0]], quads[flipped][:, [3, 0, 2]]), 1)
    return pattern.reshape(-1, 3)


def _check_diagonals(diagonals: Any) -> None:
    if diagonals not in DIAGONALS:
        raise ValueError(
            f"diagonals must be one of {', '.join(repr(d) for d in DIAGONALS)}, got "
            f'{diagonals!r} ("alternating": a checkerboard, which MITC3 needs for thin plates '
            "in two-way bending, docs/theory.md §5.3)"
        )


def _flipped(nx: int, ny: int, diagonals: str, phase: int = 0) -> np.ndarray | None:
    """(nx * ny,) bool: the grid cells (i, j) ("for j, for i") split along the other diagonal,
    those with i + j + phase odd on the "alternating" pattern; None for "one-way"."""
    if diagonals == "one-way":
        return None
    j, i = np.divmod(np.arange(nx * ny), nx)
    return (i + j + phase) % 2 == 1


def _grid_node_sets(nx: int, ny: int) -> dict[str, np.ndarray]:
    """Side node sets of a structured grid numbered j * (nx + 1) + i."""
    column = np.arange(ny + 1) * (nx + 1)
    row = np.arange(nx + 1)
    return {"left": column, "right": column + nx, "bottom": row, "top": row + ny * (nx + 1)}


# --------------------------------------------------------------------------------------------
# Quadrilateral generator (gmsh)
# --------------------------------------------------------------------------------------------


def _validate_quadrilateral(corners: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Corners (4, 3) of a planar convex quadrilateral and its unit normal (3,)."""
    try:
        quad = np.array(corners, dtype=np.float64)
    except (TypeError, ValueError) as err:
        raise ValueError(f"corners must be a (4, 3) or (4, 2) array: {err}") from err
    if quad.shape not in ((4, 2), (4, 3)):
        raise ValueError(f"corners must have shape (4, 3) or (4, 2), got {quad.shape}")
    if not np.isfinite(quad).all():
        raise ValueError("corners must have finite coordinates")
    if quad.shape[1] == 2:
        quad = np.column_stack((quad, np.zeros(4)))
    size = np.linalg.norm(quad[:, None] - quad[None], axis=2).max()
    # Newell's normal: twice the vector area; robust for slightly non-planar input.
    newell = np.cross(quad, np.roll(quad, -1, axis=0)).sum(axis=0)
    if size == 0.0 or np.linalg.norm(newell) <= _CONVEXITY_TOL * size**2:
        raise ValueError(
            "corners enclose no area: they coincide, are collinear, or form a "
            "self-intersecting quadrilateral"
        )
    normal = newell / np.linalg.norm(newell)
    offset = np.abs((quad - quad.mean(axis=0)) @ normal)
    if offset.max() > _PLANARITY_TOL * size:
        raise ValueError(
            f"corners must be coplanar: corner {int(offset.argmax())} is "
            f"{offset.max():.3g} off their mean plane"
        )
    # At a convex corner of a counter-clockwise polygon the boundary turns left.
    turns = np.cross(quad - np.roll(quad, 1, axis=0), np.roll(quad, -1, axis=0) - quad) @ normal
    bad = np.flatnonzero(turns <= _CONVEXITY_TOL * size**2)
    if bad.size:
        raise ValueError(
            "corners must form a convex, non-self-intersecting quadrilateral in cyclic "
            f"order; the boundary does not turn consistently at corner {int(bad[0])}"
        )
    return quad, normal


# Options forced while meshing (and restored afterwards if gmsh was already running).
_GMSH_OPTIONS = {"General.Terminal": 0.0, "Mesh.ElementOrder": 1.0}


@contextlib.contextmanager
def _gmsh_model(name: str) -> Iterator[ModuleType]:
    """A fresh, silent gmsh model that is removed afterwards.

    If gmsh is not running it is initialised and finalised here; if the caller already runs
    gmsh, its current model and the options we touch are restored instead.
    """
    # Imported here: gmsh loads a large native library that only this generator needs.
    import gmsh

    owner = not gmsh.isInitialized()
    if owner:
        try:
            # interruptible=False: do not install a SIGINT handler (breaks Ctrl-C / threads).
            gmsh.initialize(readConfigFiles=False, interruptible=False)
        except TypeError:  # gmsh < 4.11 has no `interruptible` keyword
            gmsh.initialize(readConfigFiles=False)
        previous_model, saved = "", {}
    else:
        previous_model = gmsh.model.getCurrent()
        saved = {key: gmsh.option.getNumber(key) for key in _GMSH_OPTIONS}
    try:
        for key, value in _GMSH_OPTIONS.items():
            gmsh.option.setNumber(key, value)
        gmsh.model.add(name)
        try:
            yield gmsh
        finally:
            gmsh.model.remove()
    finally:
        if owner:
            gmsh.finalize()
        else:
            for key, value in saved.items():
                gmsh.option.setNumber(key, value)
            gmsh.model.setCurrent(previous_model)


def _gmsh_structured_quads(quad: np.ndarray, nx: int, ny: int) -> tuple[np.ndarray, np.ndarray]:
    """Transfinite quad mesh of corners (4, 3): coordinates (p, 3) and quads (q, 4) in 0..p-1."""
    with _gmsh_model("femcore-quadrilateral") as gmsh:
        geo = gmsh.model.geo
        corner_tags = [geo.addPoint(*c) for c in quad.tolist()]
        curves = [geo.addLine(corner_tags[k], corner_tags[(k + 1) % 4]) for k in range(4)]
        surface = geo.addPlaneSurface([geo.addCurveLoop(curves)])
        for curve, divisions in zip(curves, (nx, ny, nx, ny), strict=True):
            geo.mesh.setTransfiniteCurve(curve, divisions + 1)
        geo.mesh.setTransfiniteSurface(surface, cornerTags=corner_tags)
        geo.mesh.setRecombine(2, surface)
        geo.synchronize()
        gmsh.model.mesh.generate(2)
        tags, coords, _ = gmsh.model.mesh.getNodes()
        _, quad_tags = gmsh.model.mesh.getElementsByType(3)  # 3 = 4-node quadrangle
    tags = np.asarray(tags, dtype=np.int64)
    lookup = np.full(tags.max() + 1, -1, dtype=np.int64)
    lookup[tags] = np.arange(len(tags))
    quads = lookup[np.asarray(quad_tags, dtype=np.int64).reshape(-1, 4)]
    # Compact numbering: keep only nodes that some quad uses.
    used, compact = np.unique(quads, return_inverse=True)
    return np.asarray(coords).reshape(-1, 3)[used], compact.reshape(-1, 4)


def _bilinear_inverse(quad: np.ndarray, x: np.ndarray, tol: float = 1e-13) -> np.ndarray:
    """Parameters (k, 2) = (xi, eta) in [0, 1]^2 of points x (k, 3) under the bilinear map.

    x(xi, eta) = (1-xi)(1-eta) c0 + xi (1-eta) c1 + xi eta c2 + (1-xi) eta c3. Gauss-Newton
    on all points at once (the loop is over iterations only); it converges quadratically
    from the centre for convex quadrilaterals.
    """
    c0, c1, c2, c3 = quad
    uv = np.full((len(x), 2), 0.5)
    for _ in range(50):
        xi, eta = uv[:, :1], uv[:, 1:]
        residual = (
            (1 - xi) * (1 - eta) * c0 + xi * (1 - eta) * c1 + xi * eta * c2 + (1 - xi) * eta * c3
        ) - x
        d_xi = (1 - eta) * (c1 - c0) + eta * (c2 - c3)
        d_eta = (1 - xi) * (c3 - c0) + xi * (c2 - c1)
        jac = np.stack((d_xi, d_eta), axis=2)  # (k, 3, 2)
        jtj = np.einsum("kdi,kdj->kij", jac, jac)
        jtr = np.einsum("kdi,kd->ki", jac, residual)
        step = np.linalg.solve(jtj, jtr[..., None])[..., 0]
        uv -= step
        if np.abs(step).max() < tol:
            break
    return uv


def _structured_numbering(
    quad: np.ndarray, coords: np.ndarray, quads: np.ndarray, nx: int, ny: int
) -> tuple[np.ndarray, np.ndarray]:
    """Renumber gmsh nodes as j * (nx + 1) + i and sort quads "for j, for i".

    (i, j) come from the bilinear parameters of each node, which a transfinite mesh of a
    straight-sided quadrilateral places exactly at (i / nx, j / ny).
    """
    scaled = _bilinear_inverse(quad, coords) * (nx, ny)
    grid = np.rint(scaled).astype(np.int64)
    ids = grid[:, 1] * (nx + 1) + grid[:, 0]
    n_grid = (nx + 1) * (ny + 1)
    on_grid = np.abs(scaled - grid).max() < 1e-6 and len(ids) == n_grid
    if not on_grid or not np.array_equal(np.sort(ids), np.arange(n_grid)):
        raise RuntimeError("gmsh did not return the expected structured grid of nodes")
    points = np.empty_like(coords)
    points[ids] = coords
    quads = ids[quads]
    cell = (quads // (nx + 1)).min(axis=1) * nx + (quads % (nx + 1)).min(axis=1)
    return points, quads[np.argsort(cell)]


def _orient_quads(points: np.ndarray, quads: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """Reverse the node order of quads (q, 4) whose normal opposes ``normal`` (3,)."""
    x = points[quads]
    flip = np.cross(x[:, 2] - x[:, 0], x[:, 3] - x[:, 1]) @ normal < 0.0
    out = quads.copy()
    out[flip] = out[flip, ::-1]
    return out


def _rotate_to_warp(points: np.ndarray, quads: np.ndarray, warp: np.ndarray) -> np.ndarray:
    """Cyclically rotate quads (q, 4) so edge 0 -> 1 is the one most aligned with warp (q, 3)."""
    x = points[quads]
    edges = np.roll(x, -1, axis=1) - x  # edge k runs from node k to node k + 1
    edges /= np.linalg.norm(edges, axis=2, keepdims=True)
    shift = np.argmax(np.einsum("qkd,qd->qk", edges, warp), axis=1)
    return np.take_along_axis(quads, (shift[:, None] + np.arange(4)) % 4, axis=1)
