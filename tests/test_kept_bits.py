"""``same_bits`` (elements/kept_bits.py), the test of the ply contact's per-state caches: a hit
only where the array holds the kept one's shape, dtype and bytes, so that a cached answer is
the one the computation would give."""

import numpy as np

from elements.kept_bits import same_bits


def test_a_copy_holds_the_same_bits_and_any_change_of_value_shape_or_dtype_does_not():
    kept = np.random.default_rng(0).normal(size=(17, 3))
    assert same_bits(kept, kept.copy())
    assert same_bits(kept, np.asfortranarray(kept))  # another layout, the same numbers
    moved = kept.copy()
    moved[5, 1] = np.nextafter(moved[5, 1], np.inf)  # one bit of one number
    assert not same_bits(kept, moved)
    assert not same_bits(kept, kept.reshape(51, 1))  # the same bytes, another shape
    assert not same_bits(kept, kept.view(np.int64))  # the same bytes, another dtype


def test_signed_zeros_and_nans_compare_by_their_bits():
    """-0.0 against +0.0 (equal values) is not a hit: the cache computes again, as the numbers
    could differ in a sign; a NaN holds its own bits (np.array_equal never matches it)."""
    zero = np.zeros((2, 3))
    assert not same_bits(zero, -zero)
    assert np.array_equal(zero, -zero)
    nan = np.full((2, 3), np.nan)
    assert same_bits(nan, nan.copy())


def test_large_arrays_compare_by_their_bits_in_place_as_small_ones_do():
    """Above SMALL entries the numbers are compared as integers of their width (no copy): a
    copy or another layout hits, one bit of one number, a signed zero or another dtype does
    not, a NaN holds its own bits."""
    from elements.kept_bits import SMALL

    kept = np.random.default_rng(1).normal(size=(SMALL, 3))
    assert same_bits(kept, kept.copy())
    assert same_bits(kept, np.asfortranarray(kept))
    assert same_bits(kept[::2], kept[::2].copy())  # a strided view against its copy
    moved = kept.copy()
    moved[-1, 2] = np.nextafter(moved[-1, 2], np.inf)
    assert not same_bits(kept, moved)
    zero = np.zeros((SMALL, 3))
    assert not same_bits(zero, -zero)
    assert not same_bits(kept, kept.astype(np.float32))
    nan = np.full((SMALL, 3), np.nan)
    assert same_bits(nan, nan.copy())
