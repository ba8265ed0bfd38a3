"""The elastic catenary: a cable of unstretched length L0, weight w per unstretched length and
axial stiffness EA hanging between two supports at the same height, a span S apart.

Irvine, *Cable Structures* (MIT Press 1981; Dover 1992), §1.3, Eqs. 1.28-1.29: with H the
horizontal tension and V = W/2 the vertical reaction (W = w L0), in the Lagrangian coordinate
s of the unstretched cable measured from the left support,

    x(s) = H s / EA + (H / w) [asinh(V / H) - asinh((V - w s) / H)]
    d(s) = (V s - w s^2 / 2) / EA + (H / w) [sqrt(1 + (V/H)^2) - sqrt(1 + ((V - w s)/H)^2)]

where d is the drop below the supports. (Both follow from dx/ds = H/T + H/EA and
dd/ds = (V - w s)/T + (V - w s)/EA with T(s) = sqrt(H^2 + (V - w s)^2).)

The inextensible catenary is the limit EA -> inf: S = 2 (H/w) asinh(V/H) and the sag at
mid-span is (H/w) (sqrt(1 + (V/H)^2) - 1).
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq


def _span(horizontal: float, weight_per_length: float, length: float, axial_stiffness: float):
    w, L0 = weight_per_length, length
    vertical = 0.5 * w * L0
    return horizontal * L0 / axial_stiffness + 2.0 * horizontal / w * np.arcsinh(
        vertical / horizontal
    )


def elastic_catenary_tension(
    span: float, length: float, weight_per_length: float, axial_stiffness: float = np.inf
) -> float:
    """Horizontal tension H (N) of the symmetric elastic catenary (inextensible if EA = inf).

    span: S (mm), length: unstretched L0 (mm) > S for an inextensible cable,
    weight_per_length: w (N/mm), axial_stiffness: EA (N).
    """

    def mismatch(h):
        return _span(h, weight_per_length, length, axial_stiffness) - span

    if not np.isfinite(axial_stiffness) and span >= length:
        raise ValueError(f"an inextensible cable of length {length} cannot span {span}")
    low, high = 1e-9 * weight_per_length * length, 1.0
    while mismatch(high) < 0:
        high *= 2.0
    return brentq(mismatch, low, high, xtol=1e-14 * high, rtol=4 * np.finfo(float).eps)


def elastic_catenary_shape(s, span, length, weight_per_length, axial_stiffness=np.inf):
    """Points (x(s), z(s)) of the hanging cable, z measured upwards from the supports (so the
    sag is -z at mid-span), for Lagrangian coordinates s in [0, L0] (mm)."""
    s = np.asarray(s, dtype=float)
    w = weight_per_length
    horizontal = elastic_catenary_tension(span, length, w, axial_stiffness)
    vertical = 0.5 * w * length
    x = horizontal * s / axial_stiffness + horizontal / w * (
        np.arcsinh(vertical / horizontal) - np.arcsinh((vertical - w * s) / horizontal)
    )
    z = -(
        w * s / axial_stiffness * (vertical / w - 0.5 * s)
        + horizontal
        / w
        * (
            np.sqrt(1.0 + (vertical / horizontal) ** 2)
            - np.sqrt(1.0 + ((vertical - w * s) / horizontal) ** 2)
        )
    )
    return x, z


def catenary_sag(span, length, weight_per_length, axial_stiffness=np.inf) -> float:
    """Mid-span sag (mm, positive downwards) of the symmetric elastic catenary."""
    _, z = elastic_catenary_shape(0.5 * length, span, length, weight_per_length, axial_stiffness)
    return float(-z)
