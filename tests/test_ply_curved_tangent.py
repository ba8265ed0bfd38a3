"""The curved faces' exact tangent (elements/ply_curved_tangent.py, docs/theory.md §9.3a
"Curved faces"): the gap's Hessian through the projection's own motion on the Phong patch
(elements/ply_curved_hessian.py), the nodal normals' first and second derivatives
(elements/ply_normal_hessian.py), and the contact's tangent as the derivative of its loads.

References: central differences of what the code computes by other means (the Gauss-Newton
projection's gap, ``nodal_normals``, ``normal_pullback`` and the block's loads), none of
them built from the derivatives under test.
"""

import numpy as np
import pytest

from elements import ply_surface
from elements.layup import Layup
from elements.ply_curved_hessian import gap_derivatives
from elements.ply_normal_hessian import normal_jacobian, normal_second
from femcore.interaction_checks import check_tangent
from tests.test_ply_surface import PLY, _contact, _on_sphere


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v, axis=-1)[..., None]


def _patches(count: int, seed: int = 0):
    """``count`` upper and lower patches near the pole of spheres of radius 20.05 and 20 mm
    (corners ~2 and ~6 mm apart, the upper patch over the lower one's middle; jittered by
    0.05 mm, normals tilted ~1.5 deg off the radial), the
    local data v (count, 36) of elements/ply_curved_hessian.py, and the upper points'
    coordinates sigma."""
    rng = np.random.default_rng(seed)
    base = np.array([[0.0, 0.0], [0.3, 0.0], [0.15, 0.26]])

    def patch(radius, size):
        angle = size * (base[None] - base.mean(axis=0)) + 0.005 * rng.standard_normal((count, 3, 2))
        points = radius * np.stack(
            [angle[..., 0], angle[..., 1], np.sqrt(1.0 - np.sum(angle**2, axis=-1))], axis=-1
        )
        normals = _unit(points + 0.5 * rng.standard_normal(points.shape))
        return points + 0.05 * rng.standard_normal(points.shape), normals

    z, upper_normals = patch(20.05, 0.1)
    y, n = patch(20.0, 0.3)
    data = np.concatenate([a.reshape(count, 9) for a in (z, upper_normals, y, n)], axis=1)
    sigma = rng.uniform(0.2, 1.0, (count, 3))
    sigma /= sigma.sum(axis=1)[:, None]
    return data, sigma


def _projected_gap(data: np.ndarray, sigma: np.ndarray):
    """g, lambda, nu of each point's projection (elements/ply_surface.py ``project``, 30
    Gauss-Newton steps from the centroid)."""
    count = len(data)
    z, upper_normals, y, n = (data[:, 9 * k : 9 * k + 9].reshape(count, 3, 3) for k in range(4))
    p = ply_surface.surface_point_numpy(z, upper_normals, sigma)[0]
    lam, _, nu, gap, _, _ = ply_surface.project(
        p, y, n, np.full((count, 3), 1.0 / 3.0), steps=30, settled=1e-12
    )
    return gap, lam, nu


def test_the_gaps_gradient_and_hessian_are_the_projections_differences():
    """Over the 36 local data (corners and normals of both patches), the gradient and the
    Hessian of the gap against central first and second differences of the projected gap
    (the projection made again at each step). Steps 1e-5 and 1e-3 mm: truncation ~1e-10 and
    ~1e-6 relative, rounding ~1e-11 and ~1e-10; held to 1e-7 and 1e-5 of the largest entry.
    Measured: 4.7e-10 and 3.1e-7."""
    data, sigma = _patches(3)
    gap, lam, nu = _projected_gap(data, sigma)
    assert np.all(lam > 0.0) and np.all(np.abs(gap) < 0.3)  # inside the patches, near
    count = len(data)
    z, upper_normals, y, n = (data[:, 9 * k : 9 * k + 9].reshape(count, 3, 3) for k in range(4))
    gradient, hessian = gap_derivatives(z, upper_normals, sigma, y, n, lam, nu, gap)

    def gaps(moves: np.ndarray) -> np.ndarray:
        """(k, count) the projected gaps of the data moved by each of ``moves`` (k, 36),
        projected together (each point's projection its own: the rows are independent)."""
        moved = (data[None] + moves[:, None, :]).reshape(-1, 36)
        return _projected_gap(moved, np.tile(sigma, (len(moves), 1)))[0].reshape(len(moves), count)

    step = 1e-5
    eye = np.eye(36)
    plus, minus = gaps(step * eye), gaps(-step * eye)
    differences = ((plus - minus) / (2.0 * step)).T
    np.testing.assert_allclose(gradient, differences, atol=1e-7 * np.abs(gradient).max())
    step = 1e-3
    pairs = [(i, j) for i in range(36) for j in range(i, 36)]
    signs = ((1, 1), (1, -1), (-1, 1), (-1, -1))
    moves = np.array([step * (si * eye[i] + sj * eye[j]) for i, j in pairs for si, sj in signs])
    corners = gaps(moves).reshape(len(pairs), 4, count)
    second = np.zeros_like(hessian)
    for (i, j), at in zip(pairs, corners):
        second[:, i, j] = second[:, j, i] = (at[0] - at[1] - at[2] + at[3]) / (4.0 * step**2)
    np.testing.assert_allclose(hessian, second, atol=1e-5 * np.abs(hessian).max())


def _sphere_mesh():
    layup = Layup(PLY, (0.0, 45.0), 40.0, cells=3, rule="gauss", surface="curved")
    x = layup.mesh.points.copy()
    x[:, 2] = np.sqrt(50.0**2 - x[:, 0] ** 2 - x[:, 1] ** 2)
    x += 0.3 * np.random.default_rng(2).standard_normal(x.shape)
    return x, layup.mesh.triangles


def test_the_nodal_normals_derivatives_are_their_differences():
    """dN/dx against central differences of ``nodal_normals`` and sum G_i . d2N_i/dx2
    against those of ``normal_pullback`` (dN/dx^T G, itself held to the energy's
    differences in tests/test_ply_surface.py) on the [0/45] pair on the 50-mm sphere
    jittered by 0.3 mm, every node moved along every axis. Step 1e-6 mm: truncation ~1e-12
    relative, rounding ~1e-10 of the largest entry; held to 1e-7 of it. Measured: ~3e-9."""
    x, triangles = _sphere_mesh()
    count = len(x)
    normals, lengths = ply_surface.nodal_normals(x, triangles, count)
    on_normals = np.random.default_rng(4).standard_normal((count, 3))
    jacobian = normal_jacobian(x, triangles, normals, lengths).toarray()
    second = normal_second(x, triangles, normals, lengths, on_normals).toarray()
    step = 1e-6
    first_differences = np.zeros_like(jacobian)
    second_differences = np.zeros_like(second)
    for column in range(3 * count):
        moved = []
        for sign in (1.0, -1.0):
            at = x.copy()
            at.flat[column] += sign * step
            turned, length = ply_surface.nodal_normals(at, triangles, count)
            pulled = ply_surface.normal_pullback(at, triangles, turned, length, on_normals)
            moved.append((turned.ravel(), pulled.ravel()))
        first_differences[:, column] = (moved[0][0] - moved[1][0]) / (2.0 * step)
        second_differences[:, column] = (moved[0][1] - moved[1][1]) / (2.0 * step)
    np.testing.assert_allclose(jacobian, first_differences, atol=1e-7 * np.abs(jacobian).max())
    np.testing.assert_allclose(second, second_differences, atol=1e-7 * np.abs(second).max())


@pytest.mark.parametrize("faces", ["normal", "director"])
def test_the_curved_contacts_tangent_is_the_derivative_of_its_loads(faces):
    """Plies 0.1 mm into each other on the 50-mm sphere, 30 mm at 10-mm cells, [0/45],
    jittered by 0.02 mm (41 touching Gauss points): the block's tangent against central
    differences of its forces and moments at every node, translations and director turns
    (femcore.interaction_checks ``check_tangent``, 1e-6 of the largest entry). Passes at an
    rtol of 1e-9 (faces along the normals) and 1e-8 (along the directors), the rounding
    allowance included, as did the 40-mm plies of 4 x 4 cells (96 points); the flat facet's
    tangent at the curved projection, the tangent before, was off
    by 0.21 of it (17.6 N/mm of 85.2)."""
    layup, contact = _contact(3, 30.0, "curved", faces)
    state = _on_sphere(layup, 0.1, jitter=0.02)
    assert contact.facing(state).touching.sum() >= 40
    assert check_tangent(contact, state)


def test_the_mirrored_passs_curved_tangent_is_the_derivative_of_its_loads():
    """The mirrored pass (``points="lower"``: the lower ply's nodes against the upper ply's
    curved face) on the same pair, the same check."""
    layup = Layup(
        PLY, (0.0, 45.0), 30.0, cells=3, rule="gauss", faces="normal", surface="curved",
        penalty=100.0, lower_rule="vertices",
    )  # fmt: skip
    contact = layup.model().compile().interactions[1]
    state = _on_sphere(layup, 0.1, jitter=0.02)
    assert contact.mirrored and contact.facing(state).touching.sum() >= 20
    assert check_tangent(contact, state)
