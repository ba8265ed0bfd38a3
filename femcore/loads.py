"""Boundary conditions and loads as plain records, and the amplitudes that ramp them.

A record only describes; ``femcore.model.CompiledModel`` turns the records into nodal arrays once.
Every load and prescribed displacement has an amplitude a(tau) of the step progress
tau in [0, 1]: tau = t / duration in the explicit solver. The quasi-static solvers
(dynamic relaxation, static) apply everything in load-factor increments lambda = i / n; a named
amplitude there only tells a suddenly applied load ("step") from a ramped one (linear in lambda),
because a quasi-static answer does not depend on how fast it was reached, while a user callable
is followed: a(lambda) at each load factor (Static's arc-length path refuses one that is not
proportional, docs/theory.md §6.5).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

__all__ = [
    "AMPLITUDES",
    "Amplitude",
    "AmplitudeFunction",
    "Fix",
    "Gravity",
    "NodalLoad",
    "Prescribed",
    "RigidNode",
    "amplitude_of",
    "linear",
    "smooth_step",
    "step",
]

AmplitudeFunction = Callable[[Any], Any]
"""An amplitude a(tau): takes tau (a float or an array, dimensionless) and returns a(tau) of the
same shape (dimensionless, 1 = full load)."""


def smooth_step(tau: ArrayLike) -> np.ndarray:
    """Smooth-step amplitude 10 tau^3 - 15 tau^4 + 6 tau^5, clipped to [0, 1].

    Zero slope and curvature at both ends, as Abaqus's SMOOTH STEP.

    Parameters
    ----------
    tau : array_like
        Step progress (dimensionless), any shape; values outside [0, 1] are clipped.

    Returns
    -------
    numpy.ndarray
        a(tau) in [0, 1], same shape as ``tau`` (a 0-d array or numpy scalar for a scalar).
    """
    clipped: Any
    if isinstance(tau, float) and 0.0 < tau < 1.0:  # a Python float or a numpy float64
        # An explicit run asks for one tau at a time, a few times a step: np.clip's dispatch
        # (2-3 us) skipped where it would return tau itself as a numpy float64, the same
        # operations after it (the same bits).
        clipped = np.float64(tau)
    elif isinstance(tau, float) and (tau >= 1.0 or tau < 0.0):
        # Past either end (a holder's closing amplitude after its closing, at every step):
        # np.clip's bound as the numpy float64 it returns (tau = +-0 and nan stay np.clip's,
        # which keeps the sign of -0.0 and the nan).
        clipped = np.float64(1.0 if tau >= 1.0 else 0.0)
    else:
        clipped = np.clip(tau, 0.0, 1.0)
    return clipped**3 * (10.0 - 15.0 * clipped + 6.0 * clipped**2)


def linear(tau: ArrayLike) -> np.ndarray:
    """Linear ramp from 0 at the start to 1 at the end, clipped to [0, 1].

    Parameters
    ----------
    tau : array_like
        Step progress (dimensionless), any shape.

    Returns
    -------
    numpy.ndarray
        a(tau) = clip(tau, 0, 1), same shape as ``tau``.
    """
    return np.clip(tau, 0.0, 1.0)


def step(tau: ArrayLike) -> np.ndarray:
    """Full value from the first instant (a suddenly applied load).

    Parameters
    ----------
    tau : array_like
        Step progress (dimensionless), any shape.

    Returns
    -------
    numpy.ndarray
        Ones of the shape of ``tau``.
    """
    return np.ones_like(np.asarray(tau, dtype=float))


AMPLITUDES: dict[str, AmplitudeFunction] = {
    "smooth": smooth_step,
    "linear": linear,
    "step": step,
}
"""The named amplitudes, name -> a(tau)."""


@dataclass(frozen=True)
class Amplitude:
    """How a load grows: ``dynamic(tau)`` in time, ``quasi_static(lam)`` over load increments.

    Named amplitudes ramp linearly over quasi-static increments ("step": full from the first
    increment); a user callable is used as it is in both: a(tau) in time, a(lambda) at each
    load factor of DynamicRelaxation and of Static's load path.

    Parameters
    ----------
    name : str
        A key of AMPLITUDES, or "user" for a user callable.
    dynamic : AmplitudeFunction
        a(tau) with tau = t / duration, used by the explicit solver.
    quasi_static : AmplitudeFunction
        a(lambda) over the load increments lambda = i / n of the quasi-static solvers.
    """

    name: str
    dynamic: AmplitudeFunction
    quasi_static: AmplitudeFunction


def amplitude_of(amplitude: str | AmplitudeFunction) -> Amplitude:
    """The Amplitude for a name or a callable.

    Parameters
    ----------
    amplitude : str or AmplitudeFunction
        A name in AMPLITUDES ("smooth", "linear", "step") or a callable a(tau).

    Returns
    -------
    Amplitude
        The named amplitude, or ``Amplitude("user", amplitude, amplitude)``.

    Raises
    ------
    ValueError
        Unknown name, or a callable that fails or is not finite at tau = 1.
    """
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
    """Zero displacement / rotation of some DOF columns at some nodes.

    Parameters
    ----------
    nodes : numpy.ndarray of int, shape (s,)
        Node ids.
    columns : numpy.ndarray of int, shape (d,), or None
        DOF columns (see femcore.dofs); None: every DOF the nodes carry.
    tilt : int or None
        The global axis (0, 1, 2 for x, y, z) towards which the director's turn is held too:
        alpha or beta at each node, whichever its nodal frame turns the director along that
        axis with (resolved when the model is compiled: femcore.frame_branches); None: none.
    """

    nodes: np.ndarray
    columns: np.ndarray | None  # None: every DOF the nodes carry
    tilt: int | None = None


@dataclass(frozen=True)
class Prescribed:
    """Imposed translations at nodes, reached at tau = 1 through the amplitude.

    Parameters
    ----------
    nodes : numpy.ndarray of int, shape (s,)
        Node ids.
    values : numpy.ndarray, shape (s, 3)
        Final displacements (length units), NaN where a component is not prescribed.
    amplitude : Amplitude
        How the displacements grow.
    """

    nodes: np.ndarray
    values: np.ndarray
    amplitude: Amplitude


@dataclass(frozen=True)
class NodalLoad:
    """The same global force or moment vector on each node.

    Parameters
    ----------
    kind : str
        "force" (vector in N) or "moment" (vector in N mm).
    nodes : numpy.ndarray of int, shape (s,)
        Node ids.
    vector : numpy.ndarray, shape (3,)
        Global force (N) or moment (N mm) applied at each node at full load.
    amplitude : Amplitude
        How the load grows.
    """

    kind: str
    nodes: np.ndarray
    vector: np.ndarray
    amplitude: Amplitude


@dataclass(frozen=True)
class Gravity:
    """Uniform acceleration of gravity acting on the (physical, unscaled) lumped mass.

    Parameters
    ----------
    vector : numpy.ndarray, shape (3,)
        Acceleration (length units / s^2, e.g. (0, 0, -9810) mm/s^2).
    amplitude : Amplitude
        How the load grows.
    """

    vector: np.ndarray
    amplitude: Amplitude


@dataclass(frozen=True)
class RigidNode:
    """A node no cell uses, carrying the translations of a rigid body (a force-driven tool's
    free translation, ``Model.rigid_node``).

    Parameters
    ----------
    node : int
        Its id in the model's mesh.
    mass : float or None
        Its mass, t; None: none stated (the quasi-static solvers give it a nominal mass and
        no weight; the explicit solver refuses it).
    """

    node: int
    mass: float | None
