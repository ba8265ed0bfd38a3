"""The fibrous shell's thickness along the directors and lumped masses (elements/shell_geometry.py,
docs/theory.md §1.4, §1.6)."""

import numpy as np
import pytest

from elements.shell_geometry import GUARD, guarded_thickness, lumped_mass, nodal_thickness
from femcore import Mesh


def unit(v):
    v = np.asarray(v, float)
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def areas_and_normals(points, triangles):
    """Each triangle's area (m,) and unit normal (m, 3), written out here."""
    corners = points[triangles]
    cross = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    size = np.linalg.norm(cross, axis=1)
    return 0.5 * size, cross / size[:, None]


def cosines(directors, triangles, normals):
    """V_k . n_e at each corner (m, 3)."""
    return np.einsum("mkj,mj->mk", directors[triangles], normals)


def test_thickness_along_a_tilted_director_conserves_the_normal_thickness():
    mesh = Mesh.rectangle(2.0, 1.0, 2, 1)
    _, normals = areas_and_normals(mesh.points, mesh.triangles)
    assert normals == pytest.approx(np.tile(np.eye(3)[2], (4, 1)))
    angles = np.linspace(0.0, 1.2, mesh.n_nodes)  # up to 69 deg, below the guard
    directors = np.column_stack([np.sin(angles), np.zeros_like(angles), np.cos(angles)])
    h = 6.0
    cosine = cosines(directors, mesh.triangles, normals)
    h_m, guarded = guarded_thickness(h, cosine)
    assert not guarded.any()
    # Reference: h_m = h / cos(phi) (Bai Eq. 10, 14); h_m V.n = h exactly.
    assert h_m == pytest.approx(h / np.cos(angles[mesh.triangles]), rel=1e-14)
    assert h_m * cosine == pytest.approx(np.full_like(h_m, h), rel=1e-14)


def test_a_thickness_per_element_divides_each_row():
    cosine = np.array([[1.0, 0.5, 0.25], [1.0, 1.0, 0.5]])
    h_m, _ = guarded_thickness(np.array([2.0, 3.0]), cosine)
    assert h_m == pytest.approx(np.array([[2.0, 4.0, 8.0], [3.0, 3.0, 6.0]]), rel=1e-15)


def test_the_guard_bounds_the_thickness_and_flags_the_nodes():
    mesh = Mesh.rectangle(1.0, 1.0, 1, 1)
    _, normals = areas_and_normals(mesh.points, mesh.triangles)
    directors = np.tile(np.eye(3)[2], (4, 1))
    directors[3] = unit([1.0, 0.0, 0.1])  # 84 deg from the normal
    h_m, guarded = guarded_thickness(1.0, cosines(directors, mesh.triangles, normals))
    assert guarded.sum() == np.isin(mesh.triangles, [3]).sum()
    assert h_m.max() == pytest.approx(1.0 / GUARD)


def test_lumped_mass_sums_to_the_total_and_inertia_is_eq_39():
    mesh = Mesh.rectangle(200.0, 150.0, 8, 6)
    areas, _ = areas_and_normals(mesh.points, mesh.triangles)
    rho_a, h = 4.0e-9, 15.0
    h_nodes = nodal_thickness(
        np.full((mesh.n_triangles, 3), h), areas, mesh.triangles, mesh.n_nodes
    )
    mass, inertia = lumped_mass(rho_a, areas, mesh.triangles, h_nodes, mesh.n_nodes)
    assert mass.sum() == pytest.approx(rho_a * 200.0 * 150.0, rel=1e-13)
    assert inertia == pytest.approx(mass * h**2 / 4.0, rel=1e-13)  # Bai Eq. 39
    # interior nodes touch six triangles of area A: m = 6 rho_A A / 3
    assert mass.max() == pytest.approx(2.0 * rho_a * areas[0], rel=1e-13)
