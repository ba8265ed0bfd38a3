"""Two Mindlin plies with frictional ply contact, the upper one carried by a prescribed
motion over a held lower one: the models of the ply landing and departure tests
(tests/test_ply_landing.py, test_ply_departure.py; flat, and a cap coming down on a curved
ply), and Static's accepted histories of them."""

from __future__ import annotations

import contextlib
import dataclasses
from collections.abc import Iterator
from typing import Any

import numpy as np
import pytest

from elements import MindlinShell
from elements.ply_block import PlyContactBlock
from elements.ply_contact import PlyContact
from elements.ply_friction import PlyFrictionHistory
from femcore import Mesh, Model
from materials import ElasticShell
from solvers import Static

MU = 0.3
HALF = 0.1  # mm, each ply's half thickness: the faces lie HALF from the mid-surfaces
PENALTY = 50.0  # N/mm per point
CAP_RADIUS = 20.0  # mm, the curved lower ply's mid-surface (``capped_plies``)


def _plies_model(
    lower: tuple[np.ndarray, np.ndarray], upper: tuple[np.ndarray, np.ndarray], **contact
) -> Model:
    """The two plies' model: the lower ply's points (n, 3) mm and triangles, then the upper
    one's (node and cell sets "lower" and "upper"), each a Mindlin shell (aluminium, 2 HALF
    thick), and their contact ``PlyContact("upper", "lower", HALF, HALF, penalty=PENALTY,
    **contact)``."""
    (low_points, low_triangles), (up_points, up_triangles) = lower, upper
    count, cells = len(low_points), len(low_triangles)
    nodes = count + len(up_points)
    mesh = Mesh(
        np.vstack([low_points, up_points]),
        triangles=np.vstack([low_triangles, np.asarray(up_triangles) + count]),
        node_sets={"lower": np.arange(count), "upper": np.arange(count, nodes)},
        element_sets={
            "lower": np.arange(cells),
            "upper": np.arange(cells, cells + len(up_triangles)),
        },
    )
    model = Model(mesh)
    shell = ElasticShell(E=70e3, nu=0.3, thickness=2 * HALF, density=2.7e-9)
    for name in ("lower", "upper"):
        model.add(MindlinShell(shell), cells=name)
    model.interact(PlyContact("upper", "lower", HALF, HALF, penalty=PENALTY, **contact))
    return model


def moved_plies(gap: float, ux: float, uz: float, surface: str = "flat") -> Model:
    """The two plies: the lower one 6 x 6 mm in 3 x 3 cells, held (but a far corner free along
    z, which no contact reaches, so that Static has an unknown); the upper one 2 x 2 mm in 2 x
    2 cells, its face ``gap`` mm over the lower one's (negative: into it), carried by ``ux``
    and ``uz`` mm over the run (linear), its directors held; the contact (mu MU, penalty
    PENALTY a point, Gauss points, no smoothing) on faces ``surface`` ("flat" or "curved":
    the Phong patches of a flat ply are its facets)."""
    lower = Mesh.rectangle(6.0, 6.0, nx=3, ny=3)
    upper = Mesh.rectangle(2.0, 2.0, nx=2, ny=2, origin=(0.7, 0.9, 2 * HALF + gap))
    count, nodes = len(lower.points), len(lower.points) + len(upper.points)
    model = _plies_model(
        (lower.points, lower.triangles), (upper.points, upper.triangles),
        rule="gauss", smoothing=0.0, friction=MU, surface=surface,
    )  # fmt: skip
    model.fix(np.arange(count - 1))
    model.fix([count - 1], ("ux", "uy", "alpha", "beta"))
    model.fix(np.arange(count, nodes), ("alpha", "beta"))
    model.displace(np.arange(count, nodes), ux=ux, uy=0.0, uz=uz, amplitude="linear")
    return model


def _on_cap(mesh: Mesh, radius: float, apex: float) -> np.ndarray:
    """The points of ``mesh`` (a rectangle centred on the z axis) laid on the sphere of
    ``radius`` whose top lies at z = ``apex``."""
    x = mesh.points.copy()
    x[:, 2] = apex - radius + np.sqrt(radius**2 - np.sum(x[:, :2] ** 2, axis=1))
    return x


def capped_plies(
    ux: float, uz: float, mu: float = MU, clear: float = 0.01, smoothing: float = 0.02
) -> Model:
    """A curved lower ply and a cap brought down on it: the lower ply 12 x 12 mm in 4 x 4
    cells on a sphere of radius CAP_RADIUS, clamped at its outline, its interior free; the
    upper ply 6 x 6 mm in 3 x 3 cells on a flatter sphere (1.5 CAP_RADIUS), its face's apex
    ``clear`` mm over the lower one's, carried by ``ux`` along x and ``uz`` along z over the
    run (linear), its rotations held; the contact (mu ``mu``, penalty PENALTY a point, Gauss
    points, normal law's ramp ``smoothing`` mm) on curved faces along the normals. The
    contact zone spreads from the apex as the cap comes down: its points land over several
    increments."""
    lower = Mesh.rectangle(12.0, 12.0, nx=4, ny=4, origin=(-6.0, -6.0, 0.0))
    upper = Mesh.rectangle(6.0, 6.0, nx=3, ny=3, origin=(-3.0, -3.0, 0.0))
    count, nodes = len(lower.points), len(lower.points) + len(upper.points)
    model = _plies_model(
        (_on_cap(lower, CAP_RADIUS, 0.0), lower.triangles),
        (_on_cap(upper, 1.5 * CAP_RADIUS, 2 * HALF + clear), upper.triangles),
        rule="gauss", smoothing=smoothing, friction=mu, surface="curved", faces="normal",
    )  # fmt: skip
    model.fix(np.flatnonzero(np.isclose(np.abs(lower.points[:, :2]).max(axis=1), 6.0)))
    model.fix(np.arange(count, nodes), ("alpha", "beta"))
    model.displace(np.arange(count, nodes), ux=ux, uy=0.0, uz=uz, amplitude="linear")
    return model


def static_histories(
    monkeypatch: pytest.MonkeyPatch, model: Model, increments: int
) -> list[PlyFrictionHistory]:
    """The ply contact's histories Static accepted solving ``model`` in ``increments``
    increments (converged, one per increment, checked)."""
    committed: list[PlyFrictionHistory] = []
    accept = PlyContactBlock.update_history

    def watched(block, state, history):
        committed.append(accept(block, state, history))
        return committed[-1]

    monkeypatch.setattr(PlyContactBlock, "update_history", watched)
    result = Static(increments=increments, progress=False).solve(model)
    assert result.converged and len(committed) == increments
    return committed


def folded_plies(
    gap: float, uy: float, uz: float, dip: float, unknown: bool = True, free: bool = False
) -> Model:
    """A lower ply (6 x 6 mm in 3 x 3 cells, held but a far corner free along z) whose nodes
    on x = 2 lie ``dip`` mm below the rest (negative: above): a valley (a ridge) whose two
    faces meet on the mesh's edges along that line, their slopes dip / 2; and an upper ply of
    one triangle at its nodes (``rule="nodes"``), tilted so that one node's contact point
    lies ``gap`` mm right above the fold's edge line (on the offset faces; negative: below
    it) and the others over half a millimetre clear, carried by ``uy`` along the edge and
    ``uz`` mm over the run (linear), its directors held. The carried point moves in the plane
    normal to the edge through its line: it faces the edge (``Facing.on_edge``, g = +-|p - q|
    along nu = +z) below a valley's line and above a ridge's, a face's plane above a valley's
    and below a ridge's, and passes through the line where its gap is zero. The contact: mu
    MU, penalty PENALTY, no smoothing. ``unknown``: the far corner free (Static's unknown; the
    explicit step at the runs' pace is unstable there, and the fold's round-off forces, 1e-38
    N, seed it: held for an explicit run). ``free``: the carried point's node free in
    translation, the two others carried: it follows them through the shell, and where it
    touches, its place is Static's to find."""
    lower = Mesh.rectangle(6.0, 6.0, nx=3, ny=3)
    points = lower.points.copy()
    points[np.isclose(points[:, 0], 2.0), 2] -= dip
    corner = np.array([[2.0, 2.3, 0.0], [4.0, 2.3, 1.0], [3.0, 4.0, 1.0]])

    def built(shift: np.ndarray) -> Model:
        count = len(points)
        model = _plies_model(
            (points, lower.triangles), (corner + shift, np.array([[0, 1, 2]])),
            rule="nodes", smoothing=0.0, friction=MU,
        )  # fmt: skip
        model.fix(np.arange(count - 1) if unknown else np.arange(count))
        if unknown:
            model.fix([count - 1], ("ux", "uy", "alpha", "beta"))
        model.fix(np.arange(count, count + 3), ("alpha", "beta"))
        carried = np.arange(count + 1 if free else count, count + 3)
        model.displace(carried, ux=0.0, uy=uy, uz=uz, amplitude="linear")
        return model

    # the low node's contact point and the valley's edge line (from its end at (2, 2)), on
    # the offset faces of the reference; measured with the upper ply lifted clear of the
    # lower one (a ridge's faces reach into the unlifted one, which the start check refuses)
    lift = np.array([0.0, 0.0, 2.0 + abs(dip)])
    model = built(lift)
    block = model.compile().interactions[0]
    faces, corners = block._faces(model.compile().initial_state())
    low = int(np.flatnonzero(block.above == len(points))[0])
    at = np.flatnonzero(np.all(np.isclose(points[lower.triangles], [2.0, 2.0, -dip]), axis=2))
    edge = corners.reshape(-1, 3)[at[0]]
    place = edge - (faces[low] - lift)
    return built(place + np.array([0.0, 0.0, gap]) + [0.0, 2.3 - edge[1], 0.0])


def stepped_history(model: Model, way: np.ndarray, steps: int) -> tuple[PlyContactBlock, Any]:
    """(the ply contact's block, its history) accepted over ``steps`` states of ``model``'s
    upper ply carried by ``way`` (3,) mm from the initial state in equal steps (the explicit
    solver's and Static's acceptance alike), by the passes ``ply_projection.COMPILED``
    selects."""
    compiled = model.compile()
    block = compiled.interactions[0]
    state = compiled.initial_state()
    upper = np.unique(block.above)
    history = block.initial_history()
    for step in range(1, steps + 1):
        positions = state.positions.copy()
        positions[upper] += way * step / steps
        history = block.update_history(dataclasses.replace(state, positions=positions), history)
    return block, history


@contextlib.contextmanager
def counted_landings() -> Iterator[list[int]]:
    """A list that gets, at each accepted state while the block is open, the count of ply
    points anchored there that had no anchor before (the landings): PlyContactBlock's
    ``update_history`` watched, restored on leaving."""
    landings: list[int] = []
    accept = PlyContactBlock.update_history

    def watched(block, state, history):
        new = accept(block, state, history)
        landings.append(int(np.sum((history.triangle < 0) & (new.triangle >= 0))))
        return new

    PlyContactBlock.update_history = watched  # type: ignore[method-assign]
    try:
        yield landings
    finally:
        PlyContactBlock.update_history = accept  # type: ignore[method-assign]


def random_lower_faces(rng: np.random.Generator, count: int = 7):
    """(before, now, normal_then, normal_now): ``count`` random lower-ply triangles' corners
    (count, 3, 3) mm at the last accepted state, flattish (z scaled 0.3), and now, moved by
    about 0.05 mm, with their unit normals (count, 3) then and now; the compiled ply kernels'
    bit tests put their points on them."""
    before = rng.uniform(-2.0, 2.0, (count, 3, 3)) * np.array([1.0, 1.0, 0.3])
    now = before + rng.normal(0.0, 0.05, (count, 3, 3))
    normal_then = np.cross(before[:, 1] - before[:, 0], before[:, 2] - before[:, 0])
    normal_then /= np.linalg.norm(normal_then, axis=1)[:, None]
    normal_now = np.cross(now[:, 1] - now[:, 0], now[:, 2] - now[:, 0])
    normal_now /= np.linalg.norm(normal_now, axis=1)[:, None]
    return before, now, normal_then, normal_now
