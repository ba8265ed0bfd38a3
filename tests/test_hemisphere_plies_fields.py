"""validation/studies/hemisphere_plies_fields.py on closed-form fields: a cell field recovered
at the nodes and interpolated at fixed material points (exact for a linear field inside the
fibre-aligned blank, second order for a quadratic one), the net's polar angle on its
generators (a great circle: the fibre's arc length over the radius), a fibre's strain, and
the groups of lifted places round a circle."""

from __future__ import annotations

import math

import numpy as np
import pytest

from femcore.blank import ply_blank
from validation.checks import observed_order
from validation.studies.hemisphere_plies_fields import (
    centre_lines,
    field_at,
    groups_round,
    line_strain,
    material_grid,
    net_on_sphere,
    nodal_average,
)

HALF = 100.0


def _recovered(cells, field, at, angle=0.0):
    """``field`` (x, y) -> value sampled at the triangles' centroids of a ply_blank of
    ``cells`` and recovered at ``at``."""
    blank = ply_blank(2 * HALF, 2 * HALF, cells, angle)
    points, triangles = blank.points, blank.triangles
    centroids = points[triangles].mean(axis=1)
    cell_values = field(centroids[:, 0], centroids[:, 1])
    return field_at(points, triangles, nodal_average(points, triangles, cell_values), at)


def _linear(x, y):
    return 0.3 + 0.02 * x - 0.05 * y


def _quadratic(x, y):
    return 1e-3 * (x**2 - 2.0 * x * y + 0.5 * y**2) + 0.01 * x


@pytest.mark.parametrize("angle", [0.0, 90.0])
def test_a_linear_field_is_recovered_exactly_inside_the_blank(angle):
    # an interior node's six triangles lie symmetric about it, so the area average of a
    # linear field's centroid values is its nodal value; one cell (25 mm) off the outline
    at = material_grid(HALF - 25.0, 2.5)
    recovered = _recovered(8, _linear, at, angle)
    assert np.abs(recovered - _linear(at[:, 0], at[:, 1])).max() < 1e-12


def test_a_quadratic_field_is_recovered_at_second_order():
    at = material_grid(50.0, 2.0)  # fixed material points, 50 mm inside the outline
    exact = _quadratic(at[:, 0], at[:, 1])
    cells = [8, 16, 32]
    errors = [np.sqrt(np.mean((_recovered(c, _quadratic, at) - exact) ** 2)) for c in cells]
    order, _ = observed_order([2 * HALF / c for c in cells], errors)
    # second order for the average and the interpolant (measured 2.000: each error a
    # quarter of the last); a field sampled per cell (its centroid's value where a point
    # falls) is first order, 0.99 on these meshes, which 0.02 tells apart
    assert order == pytest.approx(2.0, abs=0.02)


def test_outside_the_triangles_is_nan():
    blank = ply_blank(2 * HALF, 2 * HALF, 4)
    nodal = np.ones(blank.n_nodes)
    values = field_at(blank.points, blank.triangles, nodal, np.array([[0.0, 0.0], [150.0, 0.0]]))
    assert values[0] == pytest.approx(1.0) and math.isnan(values[1])


def test_a_vector_field_is_interpolated_per_column():
    blank = ply_blank(2 * HALF, 2 * HALF, 4)
    at = np.array([[12.5, -30.0], [60.0, 70.0]])
    positions = blank.points * 1.5
    assert np.allclose(field_at(blank.points, blank.triangles, positions, at)[:, :2], 1.5 * at)


def test_mismatched_cell_values_are_refused():
    blank = ply_blank(2 * HALF, 2 * HALF, 4)
    with pytest.raises(ValueError, match="values"):
        nodal_average(blank.points, blank.triangles, np.ones(3))
    with pytest.raises(ValueError, match="spacing"):
        material_grid(10.0, 0.0)


def test_the_net_on_its_generators():
    radius = 50.45
    along = np.array([[0.0, 0.0], [10.0, 0.0], [0.0, -30.0], [55.0, 0.0]])
    net = net_on_sphere(radius, 1.0, 0.0, along)
    # a generator is a great circle: polar angle = arc length / R; the net's segments are
    # chords (their angle 2 asin(a / 2R), 1.6e-5 relative above a / R), 1e-4 relative
    assert np.allclose(net["polar"], np.hypot(along[:, 0], along[:, 1]) / radius, rtol=1e-4)
    assert np.allclose(net["shear"][1:], 0.0, atol=1e-12)  # no shear on the generators


def test_centre_lines_and_a_stretched_fibre():
    blank = ply_blank(2 * HALF, 2 * HALF, 8)
    lines = centre_lines(blank.points, HALF)
    assert len(lines) == 4
    for line, end in zip(lines, [(HALF, 0.0), (0.0, HALF), (-HALF, 0.0), (0.0, -HALF)]):
        assert len(line) == 5
        assert np.allclose(blank.points[line[0], :2], 0.0)
        assert np.allclose(blank.points[line[-1], :2], end)
    stretched = blank.points * [1.01, 1.0, 1.0]
    assert line_strain(blank.points, stretched, lines[0]) == pytest.approx(0.01, rel=1e-12)
    assert line_strain(blank.points, stretched, lines[1]) == pytest.approx(0.0, abs=1e-15)


def test_groups_round_a_circle():
    gap = math.radians(20.0)
    assert groups_round(np.array([]), gap) == 0
    assert groups_round(np.array([1.0]), gap) == 1
    # 0.1 and 6.2 rad lie 0.183 rad apart across the turn: one group with them
    assert groups_round(np.array([0.1, 0.2, 3.0, 6.2]), gap) == 2
    assert groups_round(np.radians([0.0, 90.0, 180.0, 270.0]), gap) == 4
    with pytest.raises(ValueError, match="gap"):
        groups_round(np.array([1.0]), 0.0)
