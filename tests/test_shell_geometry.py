"""Shell geometry shared by both shells (docs/theory.md §1): frames, director update, thickness
along
the director, lumped mass."""

import numpy as np
import pytest

from elements.shell_geometry import (
    GUARD,
    director_increment,
    element_areas,
    element_normals,
    lumped_mass,
    nodal_frames,
    nodal_thickness,
    thickness_along_director,
)
from femcore import Mesh

E1, E2, E3 = np.eye(3)


def unit(v):
    v = np.asarray(v, float)
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def test_flat_sheet_frame_is_the_global_basis():
    # Bai Eq. 7 with V = e3: V1 = e2 x e3 = e1, V2 = V3 x V1 = e2.
    v1, v2 = nodal_frames(np.array([E3]))
    assert v1[0] == pytest.approx(E1) and v2[0] == pytest.approx(E2)


def test_frames_are_orthonormal_and_fall_back_near_e2():
    rng = np.random.default_rng(0)
    directors = unit(np.vstack([rng.normal(size=(50, 3)), [E2, -E2, unit([0.01, 1, 0.02])]]))
    v1, v2 = nodal_frames(directors)
    for a, b in ((v1, v2), (v1, directors), (v2, directors)):
        assert np.abs(np.sum(a * b, axis=1)).max() < 1e-14
    for v in (v1, v2):
        assert np.linalg.norm(v, axis=1) == pytest.approx(1.0, abs=1e-14)
    # right-handed: V1 x V2 = V3
    assert np.cross(v1, v2) == pytest.approx(directors, abs=1e-14)


def test_director_update_is_eq_13_to_first_order_and_keeps_unit_length():
    rng = np.random.default_rng(1)
    directors = unit(rng.normal(size=(20, 3)))
    v1, v2 = nodal_frames(directors)
    d_alpha, d_beta = rng.normal(scale=1e-5, size=(2, 20))
    linear = directors + d_alpha[:, None] * v1 - d_beta[:, None] * v2  # Bai Eq. 13
    updated = director_increment(directors, d_alpha, d_beta)
    assert np.abs(updated - linear).max() < 1e-9  # second order in 1e-5
    big = director_increment(directors, 10 * d_alpha / 1e-5, 0 * d_beta)
    assert np.linalg.norm(big, axis=1) == pytest.approx(1.0, abs=1e-14)


def test_alpha_tilts_the_director_towards_v1():
    # A quarter turn of alpha on V = e3 brings V onto V1 = e1 (docs/theory.md §1.3).
    turned = director_increment(np.array([E3]), np.array([np.pi / 2]), np.array([0.0]))
    assert turned[0] == pytest.approx(E1, abs=1e-15)
    turned = director_increment(np.array([E3]), np.array([0.0]), np.array([np.pi / 2]))
    assert turned[0] == pytest.approx(-E2, abs=1e-15)


def test_thickness_along_a_tilted_director_conserves_the_normal_thickness():
    mesh = Mesh.rectangle(2.0, 1.0, 2, 1)
    normals = element_normals(mesh.points, mesh.triangles)
    assert normals == pytest.approx(np.tile(E3, (4, 1)))
    angles = np.linspace(0.0, 1.2, mesh.n_nodes)  # up to 69 deg, below the guard
    directors = np.column_stack([np.sin(angles), np.zeros_like(angles), np.cos(angles)])
    h = 6.0
    h_m, guarded = thickness_along_director(h, directors, mesh.triangles, normals)
    assert not guarded.any()
    # Reference: h_m = h / cos(phi) (Bai Eq. 10, 14); h_m V.n = h exactly.
    assert h_m == pytest.approx(h / np.cos(angles[mesh.triangles]), rel=1e-14)
    cosines = np.einsum("mkj,mj->mk", directors[mesh.triangles], normals)
    assert h_m * cosines == pytest.approx(np.full_like(h_m, h), rel=1e-14)


def test_the_guard_bounds_the_thickness_and_flags_the_nodes():
    mesh = Mesh.rectangle(1.0, 1.0, 1, 1)
    normals = element_normals(mesh.points, mesh.triangles)
    directors = np.tile(E3, (4, 1))
    directors[3] = unit([1.0, 0.0, 0.1])  # 84 deg from the normal
    h_m, guarded = thickness_along_director(1.0, directors, mesh.triangles, normals)
    assert guarded.sum() == np.isin(mesh.triangles, [3]).sum()
    assert h_m.max() == pytest.approx(1.0 / GUARD)


def test_lumped_mass_sums_to_the_total_and_inertia_is_eq_39():
    mesh = Mesh.rectangle(200.0, 150.0, 8, 6)
    areas = element_areas(mesh.points, mesh.triangles)
    rho_a, h = 4.0e-9, 15.0
    h_nodes = nodal_thickness(
        np.full((mesh.n_triangles, 3), h), areas, mesh.triangles, mesh.n_nodes
    )
    mass, inertia = lumped_mass(rho_a, areas, mesh.triangles, h_nodes, mesh.n_nodes)
    assert mass.sum() == pytest.approx(rho_a * 200.0 * 150.0, rel=1e-13)
    assert inertia == pytest.approx(mass * h**2 / 4.0, rel=1e-13)  # Bai Eq. 39
    # interior nodes touch six triangles of area A: m = 6 rho_A A / 3
    assert mass.max() == pytest.approx(2.0 * rho_a * areas[0], rel=1e-13)
