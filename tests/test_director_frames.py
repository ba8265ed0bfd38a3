"""The nodal frames of the directors and the director update (docs/theory.md §1.2-1.3): Bai
Eq. 7 with its fallback (femcore.rotation.nodal_frames), and the finite rotation by the
increments (d_alpha, d_beta) that the solvers apply (femcore.dofs.DofManager.advance)."""

import numpy as np
import pytest

from femcore.dofs import DofManager
from femcore.rotation import nodal_frames
from femcore.state import State

E1, E2, E3 = np.eye(3)


def unit(v):
    v = np.asarray(v, float)
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def advanced(directors, d_alpha, d_beta):
    """The directors after the generalised increment (0, 0, 0, d_alpha, d_beta) at every node."""
    n = len(directors)
    dofs = DofManager(n, np.ones((n, 5), bool), np.zeros((n, 5), bool), np.zeros((n, 5), bool))
    dq = np.zeros((n, 5))
    dq[:, 3], dq[:, 4] = d_alpha, d_beta
    state = State(np.zeros((n, 3)), directors, np.zeros((n, 3)), np.zeros((n, 3)))
    return dofs.advance(state, dq).directors


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
    updated = advanced(directors, d_alpha, d_beta)
    assert np.abs(updated - linear).max() < 1e-9  # second order in 1e-5
    big = advanced(directors, 10 * d_alpha / 1e-5, 0 * d_beta)
    assert np.linalg.norm(big, axis=1) == pytest.approx(1.0, abs=1e-14)


def test_alpha_tilts_the_director_towards_v1():
    # A quarter turn of alpha on V = e3 brings V onto V1 = e1 (docs/theory.md §1.3).
    turned = advanced(np.array([E3]), np.array([np.pi / 2]), np.array([0.0]))
    assert turned[0] == pytest.approx(E1, abs=1e-15)
    turned = advanced(np.array([E3]), np.array([0.0]), np.array([np.pi / 2]))
    assert turned[0] == pytest.approx(-E2, abs=1e-15)
