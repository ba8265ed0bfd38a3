"""The curved face's point and tangents compiled (elements/ply_surface_kernels.py) give their
numpy reference's numbers to the last bit, and the reference is the surface of
elements/ply_surface.py's docstring.

Reference: ``ply_surface.surface_point_numpy``. The pass does the same IEEE operations in the
same order, so the comparison is exact (no tolerance), on one thread and on all of numba's
(``parallel``). The reference itself against the docstring's formulas, written here with
einsum (y(lambda) = q - 1/2 sum_i lambda_i e_i n_i, q = sum_k lambda_k y_k, e_i = (q - y_i) .
n_i; the tangents dy/dlambda_a - dy/dlambda_3 by central differences of it), within rounding.
"""

import numpy as np
import pytest

from elements import ply_projection, ply_surface, ply_surface_kernels


def _patches(seed: int, count: int = 500):
    """Random patches: corners y (c, 3, 3) about 10 mm apart, unit normals n (c, 3, 3) tilted
    up to ~0.5 rad off the facet's, barycentric coordinates (c, 3) inside and past the edges
    (a point's projection may lie past its patch's edge), one row's values NaN (a folded
    patch's: NaN through, as the reference)."""
    rng = np.random.default_rng(seed)
    y = rng.normal(0.0, 10.0, (count, 3, 3))
    facet = np.cross(y[:, 1] - y[:, 0], y[:, 2] - y[:, 0])
    facet /= np.linalg.norm(facet, axis=1)[:, None]
    n = facet[:, None, :] + rng.normal(0.0, 0.3, (count, 3, 3))
    n /= np.linalg.norm(n, axis=2)[..., None]
    lam = rng.uniform(-0.3, 1.0, (count, 3))
    lam[:, 2] = 1.0 - lam[:, 0] - lam[:, 1]
    lam[7] = np.nan
    return y, n, lam


def _same(a, b) -> bool:
    return all(np.array_equal(u, v, equal_nan=True) for u, v in zip(a, b, strict=True))


@pytest.mark.parametrize("seed", [0, 1])
def test_the_compiled_surface_point_is_the_reference_to_the_bit(seed):
    y, n, lam = _patches(seed)
    assert _same(
        ply_surface_kernels.surface_point(y, n, lam), ply_surface.surface_point_numpy(y, n, lam)
    )


@pytest.mark.parallel
def test_the_compiled_surface_point_on_threads_is_the_reference_to_the_bit():
    y, n, lam = _patches(2, 5000)
    assert _same(
        ply_surface_kernels.surface_point(y, n, lam), ply_surface.surface_point_numpy(y, n, lam)
    )


def test_surface_point_takes_the_compiled_pass_where_the_ply_kernels_are(monkeypatch):
    """``surface_point`` serves the compiled pass with the ply kernels on, the reference with
    them off: the same arrays either way (non-contiguous inputs, as a caller's gathers)."""
    y, n, lam = _patches(3)
    y, n = y[::2], n[::2]  # strided views
    lam = lam[::2]
    on = ply_surface.surface_point(y, n, lam)
    monkeypatch.setattr(ply_projection, "COMPILED", False)
    assert _same(on, ply_surface.surface_point(y, n, lam))


def test_the_reference_is_the_docstring_surface():
    """q, e and the point by the docstring's formulas (einsum, another order: within 1e-12 of
    the ~10 mm values), and the tangents as central differences of the point along lambda_1
    and lambda_2 (lambda_3 = 1 - lambda_1 - lambda_2; y is quadratic in lambda, so the central
    difference is exact but for rounding: within 1e-6 mm per unit of lambda at a step of
    1e-4)."""
    y, n, lam = _patches(4)
    keep = np.all(np.isfinite(lam), axis=1)
    y, n, lam = y[keep], n[keep], lam[keep]
    point, tangents, q, e = ply_surface.surface_point_numpy(y, n, lam)
    q_ref = np.einsum("pk,pki->pi", lam, y)
    e_ref = np.einsum("pki,pki->pk", q_ref[:, None, :] - y, n)
    point_ref = q_ref - 0.5 * np.einsum("pk,pk,pki->pi", lam, e_ref, n)
    assert np.allclose(q, q_ref, rtol=0.0, atol=1e-12)
    assert np.allclose(e, e_ref, rtol=0.0, atol=1e-12)
    assert np.allclose(point, point_ref, rtol=0.0, atol=1e-12)
    h = 1e-4
    for a in range(2):
        step = np.zeros(3)
        step[a], step[2] = h, -h
        ahead = ply_surface.surface_point_numpy(y, n, lam + step)[0]
        behind = ply_surface.surface_point_numpy(y, n, lam - step)[0]
        assert np.allclose(tangents[:, a], (ahead - behind) / (2.0 * h), rtol=0.0, atol=1e-6)


@pytest.mark.parametrize(
    "shapes",
    [((6, 3, 3), (6, 3, 3), (2, 3)), ((2, 3, 3), (2, 3, 3), (6, 3)), ((2, 3, 3), (2, 3), (2, 3))],
    ids=["fewer-coordinates", "more-coordinates", "flat-normals"],
)
def test_the_compiled_surface_point_refuses_arrays_of_other_rows(shapes):
    """Corners, normals and coordinates of different rows (the pass runs over the corners'
    rows and writes the coordinates' count): a ValueError naming the shapes, not a write
    past the arrays."""
    y, n, lam = (np.ones(shape) for shape in shapes)
    with pytest.raises(ValueError, match="expected"):
        ply_surface_kernels.surface_point(y, n, lam)
