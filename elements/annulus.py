"""A flat rigid ring (``RigidAnnulus``): the face of a blank holder that rests on a die's flat
flange and leaves the die's opening and its entry round free (docs/theory.md §9.5).

Why not a plane: a plane pressed on the flange also covers the die's opening, and a blank
drawn over the die's entry round then cannot rise above the flange's level there, though no
tool is there to hold it; the real holder is a ring whose bore is the flange's inner edge.

The ring lies in the plane through ``point`` with unit ``normal`` (towards the body), about
the axis along the normal through ``point``, from ``inner`` (mm) out (to infinity: the
flange's outer edge is past the blank). Its inner edge is sharp: the distance of a point over
the bore is its distance to the edge's circle, so it is continuous across the edge and a node
that leaves the face for the bore is released smoothly.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike

from elements.tools import RigidTool, _vector
from femcore.checks import check_positive
from femcore.loads import AmplitudeFunction

__all__ = ["RigidAnnulus"]


class RigidAnnulus(RigidTool):
    """The flat ring through ``point`` with unit ``normal`` (towards the body), its face from
    radius ``inner`` (mm, > 0) about the normal through ``point`` out; the driving options of
    ``RigidTool`` (a holder: ``free="z"``, a ``force`` and a ``mass``)."""

    def __init__(
        self,
        point: ArrayLike,
        normal: ArrayLike,
        inner: float,
        motion: ArrayLike = (0.0, 0.0, 0.0),
        amplitude: str | AmplitudeFunction = "linear",
        free: str | Sequence[str] = (),
        force: ArrayLike = (0.0, 0.0, 0.0),
        mass: float | None = None,
    ):
        super().__init__(motion, amplitude=amplitude, free=free, force=force, mass=mass)
        self.point = _vector(point, "RigidAnnulus point")
        self.normal = _vector(normal, "RigidAnnulus normal", unit=True)
        self.inner = check_positive(inner, "RigidAnnulus inner radius", "mm")

    def _parts(self, x: np.ndarray, load_factor: float):
        """(height along the normal (k,), radial vector in the ring's plane (k, 3), its length
        (k,)), mm, of the points x (k, 3) from the ring's centre."""
        relative = x - (self.point + self.offset(load_factor))
        height = relative @ self.normal
        radial = relative - height[:, None] * self.normal
        return height, radial, np.linalg.norm(radial, axis=1)

    def distance(self, x: np.ndarray, load_factor: float = 0.0):
        """(d (k,), n (k, 3)): over the face (radius >= inner) the plane's signed distance and
        normal; over the bore the distance to the inner edge's circle, along the line from
        it (never negative: the bore is open)."""
        height, radial, length = self._parts(x, load_factor)
        outward = radial / np.where(length > 0.0, length, 1.0)[:, None]
        # From the edge's closest point to x: (length - inner) outward + height normal.
        to_edge = (length - self.inner)[:, None] * outward + height[:, None] * self.normal
        edge_distance = np.linalg.norm(to_edge, axis=1)
        over_face = length >= self.inner
        d = np.where(over_face, height, edge_distance)
        edge_normal = to_edge / np.where(edge_distance > 0.0, edge_distance, 1.0)[:, None]
        n = np.where(over_face[:, None], self.normal, edge_normal)
        return d, n

    def projector_scale(self, x: np.ndarray, load_factor: float = 0.0) -> np.ndarray:
        """0 over the face (a plane); over the bore 1 / the distance to the edge, the edge
        taken as a point (the Newton tangent's curvature term only: the circle's own
        direction is left in it, which slows Newton's convergence near the edge, not its
        result)."""
        height, _, length = self._parts(x, load_factor)
        distance = np.hypot(length - self.inner, height)
        return np.where(length >= self.inner, 0.0, 1.0 / np.maximum(distance, 1e-300))

    def side_hint(self) -> str:
        return f"normal = {tuple(float(v) for v in self.normal)} must point towards the body"

    def reference_point(self) -> np.ndarray:
        return self.point.copy()
