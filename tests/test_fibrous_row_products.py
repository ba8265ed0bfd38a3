"""The row products of elements/fibrous/geometry.py against numpy's reductions they replace
in the reference geometry (``row_dot``: np.sum(a * b, axis=-1); ``row_norm``:
np.linalg.norm(a, axis=-1)): the built model's arrays are to stay the same to the last bit,
so the two must be equal bit for bit (no tolerance) on vectors of mixed magnitudes and signs,
(m, 3) and (m, L, 3)."""

import numpy as np
import pytest

from elements.fibrous.geometry import row_dot, row_norm


@pytest.mark.parametrize("shape", [(5000, 3), (2000, 3, 3), (7, 4, 2, 3)])
def test_row_products_are_numpys_reductions_to_the_last_bit(shape):
    rng = np.random.default_rng(11)
    scale = 10.0 ** rng.uniform(-8, 8, shape)
    a = rng.standard_normal(shape) * scale
    b = rng.standard_normal(shape) * scale[..., ::-1]
    assert np.array_equal(row_dot(a, b), np.sum(a * b, axis=-1))
    assert np.array_equal(row_norm(a), np.linalg.norm(a, axis=-1))
    strided = a[::2]  # a view, as the corner arrays of a cell gather are
    assert np.array_equal(row_norm(strided), np.linalg.norm(strided, axis=-1))
