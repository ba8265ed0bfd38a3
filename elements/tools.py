"""Rigid tools for contact (elements/contact.py): analytic surfaces that give, for any points,
the signed distance to the surface and its unit normal there, pointing to the side the body
stays on.

Each tool may move rigidly: ``motion`` (3,) is a translation reached at the end of the run,
through an ``amplitude`` a(tau) (femcore.loads: "linear" by default, "smooth", "step" or a
callable), tau the load factor of the quasi-static solvers or t / duration of the explicit one:
the tool is at ``a(tau) * motion`` from where it was given. Units: mm.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from femcore.checks import check_positive
from femcore.loads import AmplitudeFunction, amplitude_of

__all__ = ["RigidCylinder", "RigidPlane", "RigidSphere", "RigidTool"]


def _vector(value: ArrayLike, name: str, unit: bool = False) -> np.ndarray:
    vector = np.asarray(value, dtype=float).ravel()
    if vector.shape != (3,) or not np.isfinite(vector).all():
        raise ValueError(f"{name} must be 3 finite numbers, got {value!r}")
    if unit:
        length = np.linalg.norm(vector)
        if length == 0.0:
            raise ValueError(f"{name} must be a non-zero vector, got {value!r}")
        vector = vector / length
    return vector


class RigidTool:
    """A rigid surface: ``distance(x, load_factor)`` -> (d (k,), n (k, 3)), the signed
    distance (mm, > 0 on the body's side) and the unit normal towards the body's side, and
    ``curvature(x, load_factor)`` -> (k,) the curvature 1/R of the surface's normal section
    (0 for a plane), for the contact tangent. ``side="inside"`` keeps the body inside a
    sphere or a cylinder (a die) instead of outside (a punch)."""

    def __init__(
        self,
        motion: ArrayLike = (0.0, 0.0, 0.0),
        side: str = "outside",
        amplitude: str | AmplitudeFunction = "linear",
    ):
        self.motion = _vector(motion, "motion")
        if side not in ("outside", "inside"):
            raise ValueError(f"side must be 'outside' or 'inside', got {side!r}")
        self.sign = 1.0 if side == "outside" else -1.0
        self.amplitude = amplitude_of(amplitude).dynamic

    @property
    def moves(self) -> bool:
        """Whether the tool has a motion."""
        return bool(np.any(self.motion != 0.0))

    def offset(self, load_factor: float) -> np.ndarray:
        """(3,) the tool's translation at ``load_factor`` (tau), mm."""
        if not self.moves:
            return np.zeros(3)
        return float(self.amplitude(load_factor)) * self.motion

    def distance(self, x: np.ndarray, load_factor: float = 0.0):
        raise NotImplementedError

    def projector_scale(self, x: np.ndarray, load_factor: float = 0.0) -> np.ndarray:
        """(k,) the factor c of dn/dx = c (I - n n^T - a a^T), a the cylinder's axis (none
        for a sphere): the tool's sign over the distance to its centre or axis; 0 for a
        plane."""
        raise NotImplementedError

    axis: np.ndarray | None = None


class RigidPlane(RigidTool):
    """The plane through ``point`` with unit ``normal`` (towards the body)."""

    def __init__(
        self,
        point: ArrayLike,
        normal: ArrayLike,
        motion: ArrayLike = (0.0, 0.0, 0.0),
        amplitude: str | AmplitudeFunction = "linear",
    ):
        super().__init__(motion, amplitude=amplitude)
        self.point = _vector(point, "RigidPlane point")
        self.normal = _vector(normal, "RigidPlane normal", unit=True)

    def distance(self, x: np.ndarray, load_factor: float = 0.0):
        origin = self.point + self.offset(load_factor)
        d = (x - origin) @ self.normal
        return d, np.broadcast_to(self.normal, x.shape)

    def projector_scale(self, x: np.ndarray, load_factor: float = 0.0) -> np.ndarray:
        return np.zeros(len(x))


class _RoundTool(RigidTool):
    """A sphere or a cylinder: the distance from its centre (point or axis) less its radius,
    the normal along the radius (both with the tool's side)."""

    radius: float

    def _relative(self, x: np.ndarray, load_factor: float) -> np.ndarray:
        """(k, 3) the points' position from the centre, across the axis for a cylinder."""
        raise NotImplementedError

    def _radial(self, x: np.ndarray, load_factor: float):
        r = self._relative(x, load_factor)
        length = np.linalg.norm(r, axis=1)
        return r / np.where(length > 0, length, 1.0)[:, None], length

    def distance(self, x: np.ndarray, load_factor: float = 0.0):
        n, length = self._radial(x, load_factor)
        return self.sign * (length - self.radius), self.sign * n

    def projector_scale(self, x: np.ndarray, load_factor: float = 0.0) -> np.ndarray:
        _, length = self._radial(x, load_factor)
        return self.sign / np.maximum(length, 1e-300)


class RigidSphere(_RoundTool):
    """A sphere of ``radius`` (mm) about ``centre``; the body outside it (a punch head) or,
    with ``side="inside"``, inside it (a bowl)."""

    def __init__(
        self,
        centre: ArrayLike,
        radius: float,
        motion: ArrayLike = (0.0, 0.0, 0.0),
        side: str = "outside",
        amplitude: str | AmplitudeFunction = "linear",
    ):
        super().__init__(motion, side, amplitude)
        self.centre = _vector(centre, "RigidSphere centre")
        self.radius = check_positive(radius, "RigidSphere radius", "mm")

    def _relative(self, x: np.ndarray, load_factor: float) -> np.ndarray:
        return x - (self.centre + self.offset(load_factor))


class RigidCylinder(_RoundTool):
    """An infinite cylinder of ``radius`` (mm) about the line through ``point`` along
    ``axis``; the body outside it or, with ``side="inside"``, inside it."""

    def __init__(
        self,
        point: ArrayLike,
        axis: ArrayLike,
        radius: float,
        motion: ArrayLike = (0.0, 0.0, 0.0),
        side: str = "outside",
        amplitude: str | AmplitudeFunction = "linear",
    ):
        super().__init__(motion, side, amplitude)
        self.point = _vector(point, "RigidCylinder point")
        self.direction = _vector(axis, "RigidCylinder axis", unit=True)
        self.axis = self.direction
        self.radius = check_positive(radius, "RigidCylinder radius", "mm")

    def _relative(self, x: np.ndarray, load_factor: float) -> np.ndarray:
        r = x - (self.point + self.offset(load_factor))
        return r - (r @ self.direction)[:, None] * self.direction
