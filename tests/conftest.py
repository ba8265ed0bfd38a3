"""Shared fixtures: small cable models whose answers are known in closed form."""

import numpy as np
import pytest

from femcore import Mesh


def chain_mesh(vertices: np.ndarray, segments_per_leg: list[int]) -> Mesh:
    """A polyline through ``vertices`` (k, 3) with each leg cut into equal segments."""
    points = [vertices[0]]
    for (a, b), n in zip(zip(vertices[:-1], vertices[1:]), segments_per_leg):
        for i in range(1, n + 1):
            points.append(a + (b - a) * i / n)
    points = np.array(points)
    lines = np.column_stack([np.arange(len(points) - 1), np.arange(1, len(points))])
    return Mesh(points, lines=lines)


@pytest.fixture
def box_chain() -> Mesh:
    """40 segments of 3 mm hanging from (0,0,0) and (96,0,0): down 12, across 96, up 12
    (unstretched length 120 mm). Far from the catenary it relaxes to."""
    vertices = np.array([[0.0, 0, 0], [0, 0, -12], [96, 0, -12], [96, 0, 0]])
    return chain_mesh(vertices, [4, 32, 4])
