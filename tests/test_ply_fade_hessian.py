"""The ply contact's tangent near an outline vertex of the lower ply, where the outline fade
(elements/ply_fade.py) varies over lengths as small as the point's distance from the vertex.

The tangent takes W Hess w, the fade's second derivative times the penalty energy. It took
Hess w as a central difference of the fade's exact gradient by 1e-6 (1 + max |y|) mm, 1e-4 mm
on a blank whose nodes lie 100 mm from the origin (the hemisphere's 200-mm blank), where the
angle's fade beside a growth's edge or a cut changes over h ~ SIDEWAYS |p - q|: 1e-3 mm from
the vertex the tangent was 0.17 of its largest entry off the force's derivative. Now in closed
form (elements/ply_fade_hessian.py).

The lower ply: the fan of tests/test_ply_wedge.py (the outline vertex v = (0, 0) held by the
outline triangles A and B and the middle one M, one row below; A's and B's growths cut past
v, elements/ply_wedge.py), moved 100 mm from the origin, flat, folded along v-a and v-b (A's
and B's normals 127 deg apart), or bound flat and folded after. Faces 0.1 mm from the
mid-surfaces; one upper triangle 0.02 mm across (its centroid the contact point, the directors
along z), the plain penalty of 100 N/mm.

Reference: central differences of the contact's exact force (the gradient of its energy,
tests/test_ply_outline_fade.py) over every node's coordinates, by a step of 1e-4 of the
point's distance from the vertex or the edge (the fade's shortest length there). Their own
error, measured by halving the step, is at most 7e-10 to 2.8e-7 of the largest entry over
the samples of a case (a premise: below 1e-6; at one sample it can be far smaller, where
truncation and round-off cancel). Allowed: the largest error over a case's samples within 10
times that largest own error (measured: the closed form at most 1.2 times it, 1.7e-7; the
central difference of before 5.5e-7 to 0.17 of the largest entry, 28 to 1.2e6 times it,
round the vertex).
"""

import functools

import numpy as np
import pytest
from ply_point_loops import point_round, translational_tangent

from elements.ply_fade import central_fade_hessian, outline_fade
from elements.ply_fade_hessian import fade_hessian
from femcore.state import State

SHIFT = np.array([100.0, 60.0, 0.0])  # mm: the fan's place, as on a 200-mm blank
SLOPE = 2.0  # mm a mm: A's and B's fall across the fold
TOLERANCE = 10.0  # times the central differences' largest own error over the samples
SELF = 1e-6  # the central differences' own error (by halving their step), a premise


@functools.cache
def _fan(shape: str):
    """(block, positions (n, 3), directors (n, 3), lower nodes (8, 3)) of the fan ``shape``:
    "flat", "folded", or "flat at bind" (bound flat, folded after)."""
    plan = np.array(
        [[0, 0], [-1, 0], [-0.5, -1], [0.5, -1], [1, 0], [-1, -1], [0, -1.5], [1, -1.0]]
    )
    slope = 0.0 if shape == "flat" else SLOPE
    low = np.column_stack([plan, -slope * np.abs(plan[:, 0])])
    low[6, 2] = low[2, 2]  # the row below level with a and b
    low += SHIFT
    lower = np.array([[1, 2, 0], [0, 2, 3], [0, 3, 4], [1, 5, 2], [2, 6, 3], [3, 7, 4]])
    flat = np.column_stack([plan, np.zeros(len(plan))]) + SHIFT
    block, positions, directors = point_round(
        low,
        lower,
        steps=1,
        penalty=100.0,
        radius=0.08,
        past=0.05,
        bound_at=flat if shape == "flat at bind" else None,
    )
    return block, positions[0].copy(), directors, low


def _placed(x: np.ndarray, face: np.ndarray) -> np.ndarray:
    """The positions with the upper triangle's contact point (its face, 0.1 mm below its
    centroid) at ``face``."""
    x = x.copy()
    x[-3:] = x[-3:] - x[-3:].mean(axis=0) + face + [0.0, 0.0, 0.1]
    return x


def _tangent(block, x, directors) -> np.ndarray:
    """The contact's translational tangent (3n, 3n), N/mm."""
    zero = np.zeros_like(x)
    return translational_tangent(block, State(x, directors, zero, zero))


def _central(block, x, directors, step) -> np.ndarray:
    """Central differences (3n, 3n) of the contact's force over every node's coordinates."""
    zero = np.zeros_like(x)
    stiffness = np.zeros((x.size, x.size))
    for node in range(len(x)):
        for axis in range(3):
            plus, minus = x.copy(), x.copy()
            plus[node, axis] += step
            minus[node, axis] -= step
            stiffness[:, 3 * node + axis] = (
                block.internal_force(State(plus, directors, zero, zero))[0]
                - block.internal_force(State(minus, directors, zero, zero))[0]
            ).ravel() / (2.0 * step)
    return stiffness


def _round_the_vertex(block, low, radius):
    """Faces at ``radius`` mm from the offset face's vertex v, on 6 sides in the plane of each
    of A, M and B, 0.3, 3 and 30 deg behind that plane."""
    offset = low + [0.0, 0.0, 0.1]
    faces = []
    for row in range(3):
        corners = offset[block.cells[row]]
        normal = np.cross(corners[1] - corners[0], corners[2] - corners[0])
        normal /= np.linalg.norm(normal)
        first = np.cross(normal, [0.0, 1.0, 0.0]) + np.cross(normal, [1.0, 0.0, 0.0])
        first /= np.linalg.norm(first)
        second = np.cross(normal, first)
        for azimuth in np.radians(np.arange(0.0, 360.0, 60.0) + 7.0):
            side = np.cos(azimuth) * first + np.sin(azimuth) * second
            for dip in np.radians([0.3, 3.0, 30.0]):
                faces.append(offset[0] + radius * (np.cos(dip) * side - np.sin(dip) * normal))
    return faces


def _past_the_edge(low):
    """Faces past the middle of A's outline edge (v to (-1, 0)) by 1e-3, 1e-2 and 0.1 mm in
    A's plane, 0.3 and 3 deg behind it (the past factor alone)."""
    offset = low + [0.0, 0.0, 0.1]
    a, x1, corner = offset[0], offset[1], offset[2]
    normal = np.cross(corner - x1, a - x1)
    normal /= np.linalg.norm(normal)
    out = np.cross(a - x1, normal)
    out /= np.linalg.norm(out)
    if out @ (0.5 * (a + x1) - corner) < 0.0:
        out = -out
    faces = []
    for distance in (1e-3, 1e-2, 1e-1):
        for dip in np.radians([0.3, 3.0]):
            faces.append(0.5 * (a + x1) + distance * (np.cos(dip) * out - np.sin(dip) * normal))
    return [(face, distance) for face, distance in zip(faces, np.repeat([1e-3, 1e-2, 1e-1], 2))]


def _errors(shape, placed):
    """(tangent's error, the central differences' own error), each over the largest entry of
    the central differences, at the faces of ``placed`` [(face, length mm)] that touch with a
    fade below 1 (and the count of them)."""
    block, x0, directors, _ = _fan(shape)
    zero = np.zeros_like(x0)
    errors, own, count = [], [], 0
    for face, length in placed:
        x = _placed(x0, face)
        facing = block.facing(State(x, directors, zero, zero))
        if not facing.touching[0] or facing.fade[0] >= 1.0:
            continue
        count += 1
        step = 1e-4 * length
        coarse = _central(block, x, directors, step)
        fine = _central(block, x, directors, 0.5 * step)
        scale = np.abs(fine).max()
        errors.append(np.abs(_tangent(block, x, directors) - fine).max() / scale)
        own.append(np.abs(coarse - fine).max() / scale)
    return np.array(errors), np.array(own), count


SHAPES = ["flat", "folded", "flat at bind"]


@pytest.mark.parametrize("radius", [1e-3, 1e-2, 1e-1])
@pytest.mark.parametrize("shape", SHAPES)
def test_the_tangent_round_an_outline_vertex_is_the_forces_derivative(shape, radius):
    """Round the vertex at 1e-3, 1e-2 and 0.1 mm, over the samples that touch faded (at
    least 8 of 54): the tangent's largest error within TOLERANCE times the central
    differences' largest own error. Measured, the largest error in times the largest entry:
    2.4e-10, 6.5e-9, 6.0e-9 (flat), 1.7e-7, 2.5e-9, 9.9e-9 (folded), 1.7e-7, 5.7e-9, 1.7e-8
    (bound flat); the code before 6.9e-5, 5.5e-7, 5.6e-6 (flat), 0.17, 3.3e-3, 1.4e-3
    (folded), 0.17, 3.4e-3, 2.8e-3 (bound flat), beside the cuts and the growths' edges."""
    block, _, _, low = _fan(shape)
    faces = _round_the_vertex(block, low, radius)
    errors, own, count = _errors(shape, [(face, radius) for face in faces])
    assert count >= 8
    assert own.max() <= SELF
    assert errors.max() <= TOLERANCE * own.max()


@pytest.mark.parametrize("shape", SHAPES)
def test_the_tangent_past_an_outline_edge_is_the_forces_derivative(shape):
    """Past the middle of A's outline edge by 1e-3, 1e-2 and 0.1 mm, over the samples that
    touch faded (at least 4 of 6), as round the vertex. Measured: at most 2.3e-7 of the
    largest entry, 0.8 times the own error; the code before passes too (the past factor's
    length there is the fade's D, 0.15 of the outline triangles' least height, not the
    point's distance)."""
    low = _fan(shape)[3]
    errors, own, count = _errors(shape, _past_the_edge(low))
    assert count >= 4
    assert own.max() <= SELF
    assert errors.max() <= TOLERANCE * own.max()


def test_the_closed_form_is_the_central_difference_of_the_fades_gradient():
    """On one triangle with an outline edge (y = 0, grown 0.5 past it), 300 random points
    within 0.2 mm of it, beside its growth's edge or not, the outline's nearest edge moved
    about: ``fade_hessian`` against ``central_fade_hessian`` by 5e-7 mm (its own error 8.1e-9
    of the largest entry, by halving the step): within 1e-6 at each of the 205 points where
    0 < w < 1 (measured 1.1e-8)."""
    rng = np.random.default_rng(0)
    corners = np.array([[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.2, 1.0, 0.1]]])
    reach = np.array([[0.0, 0.0, 0.5]])
    worst, count = 0.0, 0
    for _ in range(300):
        p = np.array([[rng.uniform(-0.2, 1.2), rng.uniform(-0.2, 0.05), rng.uniform(-0.08, 0.02)]])
        beside = np.array([bool(rng.integers(2))])
        ends = np.array([[[-0.3, 0.0, 0.01], [1.0, 0.0, 0.0]]]) + rng.normal(0, 0.01, (1, 2, 3))
        w = outline_fade(p, corners, reach, beside, ends, 0.15)[0]
        if not 0.0 < w[0] < 1.0:
            continue
        count += 1
        exact = fade_hessian(p, corners, reach, beside, ends, 0.15)
        central = central_fade_hessian(p, corners, reach, beside, ends, 0.15, 5e-7)
        worst = max(worst, float(np.abs(exact - central).max() / np.abs(central).max()))
    assert count >= 200
    assert worst <= 1e-6
