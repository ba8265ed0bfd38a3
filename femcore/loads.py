"""Boundary conditions and loads as plain records, and the amplitudes that ramp them.

A record only describes; ``femcore.model.CompiledModel`` turns the records into nodal arrays once.
Every load and prescribed displacement has an amplitude a(tau) of the step progress
tau in [0, 1]: tau = t / duration in the explicit solver. The quasi-static solvers
(dynamic relaxation, static) apply everything in equal load-factor increments tau = i / n and use
the amplitude only to tell a suddenly applied load ("step") from a ramped one, because a
quasi-static answer does not depend on how fast it was reached.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np


def smooth_step(tau):
    """Smooth-step amplitude 10 tau^3 - 15 tau^4 + 6 tau^5 (zero slope and curvature at both ends,
    as Abaqus's SMOOTH STEP), clipped to [0, 1]."""
    tau = np.clip(tau, 0.0, 1.0)
    return tau**3 * (10.0 - 15.0 * tau + 6.0 * tau**2)


def linear(tau):
    """Linear ramp from 0 at the start to 1 at the end, clipped to [0, 1]."""
    return np.clip(tau, 0.0, 1.0)


def step(tau):
    """Full value from the first instant (a suddenly applied load)."""
    return np.ones_like(np.asarray(tau, dtype=float))


AMPLITUDES: dict[str, Callable] = {"smooth": smooth_step, "linear": linear, "step": step}


@dataclass(frozen=True)
class Amplitude:
    """How a load grows: ``dynamic(tau)`` in time, ``quasi_static(lam)`` over load increments.

    Named amplitudes ramp linearly over quasi-static increments ("step": full from the first
    increment); a user callable is used as it is in both.
    """

    name: str
    dynamic: Callable
    quasi_static: Callable


def amplitude_of(amplitude: str | Callable) -> Amplitude:
    """Amplitude for a name in AMPLITUDES ("smooth", "linear", "step") or a callable a(tau)."""
    if callable(amplitude):
        try:
            value = float(amplitude(1.0))
        except Exception as exc:  # the user's function: report what it did
            raise ValueError(f"amplitude callable failed at tau = 1: {exc}") from exc
        if not np.isfinite(value):
            raise ValueError(f"amplitude callable returned {value!r} at tau = 1: expected a number")
        return Amplitude("user", amplitude, amplitude)
    if not isinstance(amplitude, str) or amplitude not in AMPLITUDES:
        raise ValueError(
            f"unknown amplitude {amplitude!r}: "
            f"expected one of {', '.join(AMPLITUDES)} or a callable"
        )
    return Amplitude(amplitude, AMPLITUDES[amplitude], step if amplitude == "step" else linear)


@dataclass(frozen=True)
class Fix:
    """Zero displacement / rotation of some DOF columns at some nodes (columns: femcore.dofs)."""

    nodes: np.ndarray
    columns: np.ndarray | None  # None: every DOF the nodes carry


@dataclass(frozen=True)
class Prescribed:
    """Imposed translations at nodes: values (len(nodes), 3), with NaN where not prescribed,
    reached at tau = 1 through the amplitude."""

    nodes: np.ndarray
    values: np.ndarray
    amplitude: Amplitude


@dataclass(frozen=True)
class NodalLoad:
    """The same global force (kind "force") or moment (kind "moment") vector on each node."""

    kind: str
    nodes: np.ndarray
    vector: np.ndarray
    amplitude: Amplitude


@dataclass(frozen=True)
class Gravity:
    """Uniform acceleration of gravity acting on the (physical, unscaled) lumped mass."""

    vector: np.ndarray
    amplitude: Amplitude
