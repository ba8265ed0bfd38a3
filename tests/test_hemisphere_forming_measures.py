"""The hemisphere forming case's integral measures (validation/forming_measures.py): the
draw-in averaged along the edges, the corners' draw-in and the punch's mean force over the
end of its travel, against closed forms on prescribed blanks and work histories."""

import math

import numpy as np
import pytest

from femcore import Mesh
from femcore.loads import smooth_step
from validation.forming_measures import corner_draw_in, edge_draw_in, late_mean_force

HALF = 100.0


def _blank(cells: int) -> np.ndarray:
    return Mesh.rectangle(
        2 * HALF, 2 * HALF, nx=cells, ny=cells, origin=(-HALF, -HALF, 0.15)
    ).points


@pytest.mark.parametrize("cells", [12, 20])
def test_a_blank_shrunk_about_the_axis_draws_in_by_its_shrink_everywhere(cells):
    """x -> s x: every edge node moves in by half (1 - s), every corner by sqrt(2) half (1 -
    s); exact (1e-12) whatever the mesh."""
    points = _blank(cells)
    shrunk = points * np.array([0.8, 0.8, 1.0])
    assert edge_draw_in(points, shrunk, HALF) == pytest.approx(20.0, rel=1e-12)
    assert corner_draw_in(points, shrunk, HALF) == pytest.approx(math.sqrt(2) * 20.0, rel=1e-12)


def test_the_edge_draw_in_is_the_mean_of_its_profile_not_the_middle_node():
    """A tent profile along each edge, c (1 - |t| / half) with t along it (a node at its
    peak): the trapezoidal mean is c / 2 exactly. One middle node drawn in 5 mm more, as the
    symmetry-held centre line's node is in one of its two states, moves its edge's mean by 5
    h / (2 half) (its weight h over the edge's length) and the four edges' by a quarter of
    that: a node's weight, which falls with the cell h."""
    cells, c = 20, 12.0
    points = _blank(cells)
    x, y = points[:, 0], points[:, 1]
    moved = points.copy()
    moved[:, 0] -= np.sign(x) * np.isclose(np.abs(x), HALF) * c * (1 - np.abs(y) / HALF)
    moved[:, 1] -= np.sign(y) * np.isclose(np.abs(y), HALF) * c * (1 - np.abs(x) / HALF)
    assert edge_draw_in(points, moved, HALF) == pytest.approx(0.5 * c, rel=1e-12)
    middle = np.flatnonzero(np.isclose(x, HALF) & np.isclose(y, 0.0))
    moved[middle, 0] -= 5.0
    h = 2 * HALF / cells
    expected = 0.5 * c + 0.25 * 5.0 * h / (2 * HALF)
    assert edge_draw_in(points, moved, HALF) == pytest.approx(expected, rel=1e-12)
    assert corner_draw_in(points, moved, HALF) == pytest.approx(0.0, abs=1e-12)


def test_the_late_mean_force_is_the_work_over_the_travel_of_the_last_part():
    """A force linear in the travel s, F = a + b s, its work W = a s + b s^2 / 2, the travel
    a smooth step over the stroke: the mean over the last fifth of the travel T is a + 0.9 b
    T (to the linear interpolation of W between 4000 records, 1e-6 relative); a constant
    force gives itself; records stopping short of the travel's end give NaN."""
    duration, total, a, b = 0.3, 50.3, 10.0, 2.0

    def travel(t):
        return total * smooth_step(np.asarray(t) / duration)

    times = np.linspace(0.0, duration, 4001)
    s = travel(times)
    work = a * s + 0.5 * b * s**2
    assert late_mean_force(times, work, travel, 0.2) == pytest.approx(a + 0.9 * b * total, rel=1e-6)
    assert late_mean_force(times, a * s, travel, 0.2) == pytest.approx(a, rel=1e-9)
    assert late_mean_force(times, a * s, travel, 1.0) == pytest.approx(a, rel=1e-9)
    assert math.isnan(late_mean_force(times[:3000], work[:3000], travel, 0.2))
    for share in (0.0, -0.1, 1.5):
        with pytest.raises(ValueError, match="share"):
            late_mean_force(times, work, travel, share)
