"""The fibre frame of each cell by the compiled loops of elements/fibrous/fibre_kernels.py
against the numpy functions of elements/fibrous/fibres.py, their reference (Bai Eq. 9).

Both decide, per cell, which corner has one edge along the warp and one along the weft, and
the sign of the shear angle: integers and signs, so the two must agree exactly (no
tolerance) on meshes where no edge lies within a rounding error of the angle tolerance. The
meshes: a flat sheet with the triangles' local numbering rotated at random, the same sheet
curved onto a cylinder and turned in space (the warp projected on each cell's tilted plane,
a warp not along x), and the sheet with the diagonals of either direction.
"""

import numpy as np
import pytest

from elements.fibrous.fibres import fibre_ordering, shear_orientation
from femcore import Mesh


def _sheet(nx=9, ny=7, flip_half=False):
    mesh = Mesh.rectangle(9.0, 7.0, nx=nx, ny=ny)
    points, triangles = mesh.points.copy(), mesh.triangles.copy()
    rng = np.random.default_rng(3)
    shift = rng.integers(0, 3, len(triangles))  # a counter-clockwise rotation of each cell
    triangles = np.take_along_axis(triangles, (shift[:, None] + np.arange(3)) % 3, axis=1)
    if flip_half:  # half of the cells numbered clockwise: the other sign of the shear
        triangles[::2] = triangles[::2, ::-1]
    return points, triangles


def _curved(points, angle_deg=25.0):
    """The sheet rolled onto a cylinder of radius 12 about an axis along y, then turned by
    ``angle_deg`` about (1, 1, 1): the warp of the cells follows the curved x lines."""
    radius = 12.0
    phi = points[:, 0] / radius
    rolled = np.column_stack([radius * np.sin(phi), points[:, 1], radius * (1.0 - np.cos(phi))])
    axis = np.ones(3) / np.sqrt(3.0)
    a = np.radians(angle_deg)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    turn = np.eye(3) + np.sin(a) * k + (1.0 - np.cos(a)) * k @ k
    return rolled @ turn.T, turn


@pytest.mark.parametrize("flip_half", [False, True])
@pytest.mark.parametrize("shape", ["flat", "curved"])
def test_compiled_frame_equals_numpy(shape, flip_half):
    points, triangles = _sheet(flip_half=flip_half)
    warp = np.array([1.0, 0.0, 0.0])
    if shape == "curved":
        # The cells' planes tilt by up to 0.75 rad about y along the cylinder: the warp's
        # projection on each stays along its x edges.
        points, turn = _curved(points)
        warp = turn @ warp
    ids = np.arange(len(triangles))
    ordered, xi_is_warp = fibre_ordering(points, triangles, ids, warp, 1.0)
    ordered_c, xi_is_warp_c = fibre_ordering(points, triangles, ids, warp, 1.0, compiled=True)
    assert np.array_equal(ordered, ordered_c)
    assert np.array_equal(xi_is_warp, xi_is_warp_c)
    assert xi_is_warp.any()
    sign = shear_orientation(points, ordered, xi_is_warp, warp)
    sign_c = shear_orientation(points, ordered, xi_is_warp, warp, compiled=True)
    assert np.array_equal(sign, sign_c)
    assert set(np.unique(sign)) <= {-1.0, 1.0}
    if flip_half:  # both families along edge 0 -> 1, both signs
        assert not xi_is_warp.all()
        assert (sign < 0).any() and (sign > 0).any()


@pytest.mark.parametrize("compiled", [False, True])
def test_frame_errors_name_the_cell(compiled):
    points, triangles = _sheet(nx=3, ny=2)
    ids = np.arange(len(triangles)) + 100
    skewed = points.copy()
    corner = triangles[4, 0]
    skewed[corner] += [0.3, 0.4, 0.0]  # cell 4 (and its neighbours) lose their fibre corner
    first = 100 + min(np.flatnonzero(np.any(triangles == corner, axis=1)))
    with pytest.raises(ValueError, match=f"triangle {first} .*no corner"):
        fibre_ordering(skewed, triangles, ids, np.array([1.0, 0, 0]), 1.0, compiled=compiled)
    with pytest.raises(ValueError, match="triangle 100 is normal to the warp"):
        fibre_ordering(points, triangles, ids, np.array([0, 0, 1.0]), 1.0, compiled=compiled)
