"""The 1-D material laws of materials.laws as arrays a compiled loop can read (``pack_laws``), and
their value, energy and slope evaluated inside the loops (``law_value``, ``law_energy``,
``law_slope``): the fibrous shell's compiled kernels (elements/fibrous/kernels.py) evaluate the
tension, shear and bending laws per fibre level and per cell without calling back into Python.
The value, slope and energy are spliced into their callers (femcore/jit.py ``inline``), a
table law's energy included: the integrals of its y at the knots are tabled once by
``pack_laws``, so that its energy is a search and a trapezoid, with no call (a compiled call
with the tables' arrays as arguments costs their reference counting, and the registers the
loop must save around it, and each call summed the trapezoids twice): on the G986 sheet of
benchmarks/explicit_step.py (100k triangles, bending laws tables) the force with the energy
takes 0.75 and the energy alone 0.65 of the time they took with the table energy called
(medians of 16 rounds paired in one process, one thread, load 3.9-5.2), the same numbers to
the last bit.
"""

from __future__ import annotations

import numpy as np

from femcore.jit import inline

__all__ = ["law_energy", "law_slope", "law_value", "pack_laws"]

# The kinds of packed law (column 0 of the integer table).
_POLYNOMIAL, _TABLE = 0, 1


def pack_laws(laws) -> tuple[np.ndarray, np.ndarray]:
    """The 1-D laws of materials.laws as two arrays a compiled loop can read.

    Parameters
    ----------
    laws : sequence of materials.Law (k of them).

    Returns
    -------
    integers : (k, 4) int64
        kind (0 odd polynomial, 1 piecewise-linear table), number of coefficients, number of
        knots, 1 if the law acts in compression (0 for a tension-only law).
    reals : (k, 3, w) float
        [i, 1, :] and [i, 2, :] the knots x and y of a table; [i, 0, :] the coefficients c1,
        c3, c5 ... of a polynomial, or of a table the integrals of y from its first knot to
        each knot and, after them, to 0 (``law_energy``).
    """
    width = 1
    for law in laws:
        if law.odd_coefficients is not None:
            width = max(width, len(law.odd_coefficients))
        else:  # the knots, and F at the knots and F(0) (law_energy)
            width = max(width, len(law.knots[0]) + 1)
    integers = np.zeros((len(laws), 4), dtype=np.int64)
    reals = np.zeros((len(laws), 3, width))
    for i, law in enumerate(laws):
        integers[i, 3] = 1 if law.compression else 0
        if law.odd_coefficients is not None:
            integers[i, 0], integers[i, 1] = _POLYNOMIAL, len(law.odd_coefficients)
            reals[i, 0, : len(law.odd_coefficients)] = law.odd_coefficients
        else:
            kx, ky = law.knots
            integers[i, 0], integers[i, 2] = _TABLE, len(kx)
            reals[i, 1, : len(kx)] = kx
            reals[i, 2, : len(ky)] = ky
            # materials.Law.energy's own sums (F at the knots, F(0) last)
            reals[i, 0, : len(kx) + 1] = law.knot_integrals()
    return integers, reals


@inline
def law_slope(integers, reals, i, x):
    """dy/dx of packed law i at x (materials.Law.slope): sum (2j+1) c_j x^(2j) for an odd
    polynomial; for a table the slope of the segment [x_j, x_(j+1)) holding x (the right
    derivative at a knot), the first or last segment's beyond the ends; 0 for x < 0 when the
    law is tension-only."""
    if integers[i, 3] == 0 and x < 0.0:
        return 0.0
    if integers[i, 0] == _POLYNOMIAL:
        s = 0.0
        power = 1.0
        square = x * x
        for j in range(integers[i, 1]):
            s += (2 * j + 1) * reals[i, 0, j] * power
            power *= square
        return s
    count = integers[i, 2]
    # the last knot <= x (numpy's searchsorted(side="right") - 1), clipped to a segment
    j = 0
    while j < count - 2 and reals[i, 1, j + 1] <= x:
        j += 1
    return (reals[i, 2, j + 1] - reals[i, 2, j]) / (reals[i, 1, j + 1] - reals[i, 1, j])


@inline
def law_value(integers, reals, i, x):
    """y(x) of packed law i (materials.Law.value): the odd polynomial sum c_j x^(2j+1), or
    the table interpolated linearly and extended by its end slopes; 0 for x < 0 when the law
    is tension-only."""
    if integers[i, 3] == 0 and x < 0.0:
        return 0.0
    if integers[i, 0] == _POLYNOMIAL:
        y = 0.0
        power = x
        square = x * x
        for j in range(integers[i, 1]):
            y += reals[i, 0, j] * power
            power *= square
        return y
    return _table_value(integers, reals, i, x)


@inline
def _table_segment(integers, reals, i, x):
    """The segment j of table law i whose line gives y(x): the last knot <= x (numpy's
    searchsorted(side="right") - 1), clipped to [0, count - 2] (the end slopes beyond the
    knots)."""
    # reals[i, 1] and reals[i, 2] are the knots x and y (indexed in place: a slice would be
    # a reference-counted view in the hot loop)
    count = integers[i, 2]
    if x < reals[i, 1, 0]:
        return 0
    if x >= reals[i, 1, count - 1]:
        return count - 2
    low, high = 0, count - 1  # x_low <= x < x_high
    while high - low > 1:
        middle = (low + high) // 2
        if reals[i, 1, middle] <= x:
            low = middle
        else:
            high = middle
    return low


@inline
def _table_value(integers, reals, i, x):
    """y(x) of table law i, interpolated linearly and extended by its end slopes."""
    count = integers[i, 2]
    if x == reals[i, 1, count - 1]:
        return reals[i, 2, count - 1]
    j = _table_segment(integers, reals, i, x)
    x0, x1, y0, y1 = reals[i, 1, j], reals[i, 1, j + 1], reals[i, 2, j], reals[i, 2, j + 1]
    return (y1 - y0) / (x1 - x0) * (x - x0) + y0


@inline
def law_energy(integers, reals, i, x):
    """integral_0^x y of packed law i (materials.Law.energy): sum c_j x^(2j+2) / (2j+2) for a
    polynomial; for a table, F(x) - F(0) with F(t) the integral from the first knot, exact
    trapezoids since y is linear on each piece and on the extensions; 0 for x < 0 when the law
    is tension-only."""
    if integers[i, 3] == 0 and x < 0.0:
        return 0.0
    if integers[i, 0] == _POLYNOMIAL:
        e = 0.0
        square = x * x
        power = square
        for j in range(integers[i, 1]):
            e += reals[i, 0, j] * power / (2 * j + 2)
            power *= square
        return e
    # F(x_j) at the knot j at or below x (the last knot beyond the table; F at the knots and
    # F(0) tabled by pack_laws), the trapezoid from x_j to x, exact since y is linear there,
    # less F(0): materials.Law.energy's sum, in its order
    count = integers[i, 2]
    j = _table_segment(integers, reals, i, x)
    x0, x1, y0, y1 = reals[i, 1, j], reals[i, 1, j + 1], reals[i, 2, j], reals[i, 2, j + 1]
    if x >= x1 and j == count - 2:  # on or beyond the last knot: the trapezoid from there
        j = count - 1
        # materials.Law.value's line beyond the table, from the last knot
        y = y1 if x == x1 else y1 + (y1 - y0) / (x1 - x0) * (x - x1)
    else:
        y = (y1 - y0) / (x1 - x0) * (x - x0) + y0
    return reals[i, 0, j] + (x - reals[i, 1, j]) * (reals[i, 2, j] + y) / 2.0 - reals[i, 0, count]
