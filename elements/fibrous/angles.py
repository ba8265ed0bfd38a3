"""Angles for the fibrous shell's compiled cell loops (elements/fibrous/kernels.py,
cell_terms.py) by the arc tangent of one quotient: the corner angles and fold angles
(atan2) and the shear angle (asin).

The C library's arctan2 and arcsin cost about twice its arctan (measured in the compiled
loops: 33 and 27 ns against 15 ns a call; a quotient is 2-3 ns), and a cell takes five of the
first and three of the second per force. Reduced to an arctan of a quotient in [-1, 1] (the
octant reduction the library does inside its own arctan2), each angle keeps the arctan's
accuracy: the quotient's rounding (half a unit in the last place, relative) is not
magnified, since d(atan u) / (atan u) <= du / u, and the result stays within a few units in
the last place of the library's, far inside the 1e-12 the tests hold the loops to against
their numpy reference. Pure arithmetic: the same numbers on every run and thread count.
"""

from __future__ import annotations

import numpy as np

from elements.jit import inline

__all__ = ["arc_sine", "polar_angle"]

HALF_PI = 0.5 * np.pi


@inline
def polar_angle(y, x):
    """atan2(y, x), rad in [-pi, pi], by one arctan of a quotient of magnitude <= 1: y / x
    where |y| <= |x| (plus or minus pi for x < 0), else pi / 2 - atan(x / y) with y's sign.
    0 at the origin (atan2's value there for x = +0)."""
    ax, ay = abs(x), abs(y)
    if ay <= ax:
        if ax == 0.0:
            return np.arctan2(y, x)  # the origin: atan2's signed zeros and pi
        angle = np.arctan(y / x)
        if x < 0.0:
            angle += np.copysign(np.pi, y)
        return angle
    return np.copysign(HALF_PI, y) - np.arctan(x / y)


@inline
def arc_sine(s):
    """asin(s), rad, for s in [-1, 1] (clipped to it): atan(s / c) with c = sqrt((1 - s)
    (1 + s)), the cosine, whose factors are exact or within half a unit (no cancellation
    near |s| = 1, where 1 - s^2 loses digits), by ``polar_angle``'s reduction."""
    s = min(max(s, -1.0), 1.0)
    return polar_angle(s, np.sqrt((1.0 - s) * (1.0 + s)))
