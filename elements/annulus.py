"""A flat rigid ring (``RigidAnnulus``): the face of a die's flange or of a blank holder, with
a bore that leaves the die's opening and its entry free (docs/theory.md §9.5).

Why not a plane: a plane pressed on the flange also covers the die's opening, and a blank
drawn over the die's entry then cannot rise above the flange's level there, though no tool is
there to hold it; the real holder is a ring whose bore is the flange's inner edge.

The ring lies in the plane through ``point`` with unit ``normal`` (towards the body), about
the axis along the normal through ``point``, from ``inner`` (mm) out (to infinity: the
flange's outer edge is past the blank). It is the face of a solid: the half-space behind the
face less the bore, a cylinder of radius ``inner`` about the axis. So its distance is that
solid's signed distance, continuous everywhere:

* in front of the face (radius >= inner): the plane's distance;
* in front of the bore: the distance to the inner edge's circle (the edge is sharp), so a node
  that leaves the face for the bore is released smoothly;
* behind the face, in the bore: the distance to the bore's wall, inner - radius. A blank drawn
  through a die's opening goes behind the flange's plane; the die's wall is there, and a node
  that reaches the edge radius behind the plane meets that wall, not the far side of the
  flange (which would throw it |height| + h/2 deep);
* inside the solid: minus the distance to the nearer of the face and the wall.

A point on the axis has no radial direction; any direction across the axis gives its distance
(the edge circle is equally far all round).
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
    radius ``inner`` (mm, > 0) about the normal through ``point`` out, the face of the
    solid behind it less its bore (a die's flange with its wall, or a holder); the driving
    options of ``RigidTool`` (a holder: ``free="z"``, a ``force`` and a ``mass``)."""

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
        """(height along the normal (k,), unit radial direction in the ring's plane (k, 3),
        radius (k,)), mm, of the points x (k, 3) from the ring's centre; on the axis the radial
        direction is a fixed unit vector across the normal."""
        relative = x - (self.point + self.offset(load_factor))
        height = relative @ self.normal
        radial = relative - height[:, None] * self.normal
        length = np.linalg.norm(radial, axis=1)
        outward = np.where(
            (length > 0.0)[:, None],
            radial / np.where(length > 0.0, length, 1.0)[:, None],
            self.radial_on_axis,
        )
        return height, outward, length

    @property
    def radial_on_axis(self) -> np.ndarray:
        """(3,) a unit vector across the normal: the radial direction taken on the axis."""
        trial = np.eye(3)[int(np.argmin(np.abs(self.normal)))]
        across = trial - (trial @ self.normal) * self.normal
        return across / np.linalg.norm(across)

    def _regions(self, height: np.ndarray, length: np.ndarray):
        """Boolean masks (k,) of the points whose nearest part of the ring's solid is the bore's
        edge circle (in front of the bore) and the bore's wall (behind the face, nearer the
        wall than the face when inside the solid)."""
        in_bore = length < self.inner
        at_edge = in_bore & (height >= 0.0)
        at_wall = (in_bore & (height < 0.0)) | (
            ~in_bore & (height < 0.0) & (length - self.inner < -height)
        )
        return at_edge, at_wall

    def distance(self, x: np.ndarray, load_factor: float = 0.0):
        """(d (k,), n (k, 3)): the signed distance of the points x (k, 3) to the ring's solid
        (mm; negative inside it) and the unit normal of its nearest part, towards the point:
        the face's plane, the inner edge's circle, or the bore's wall (the module's
        docstring)."""
        height, outward, length = self._parts(x, load_factor)
        at_edge, at_wall = self._regions(height, length)
        # From the edge's closest point to x: (length - inner) outward + height normal.
        to_edge = (length - self.inner)[:, None] * outward + height[:, None] * self.normal
        edge_distance = np.linalg.norm(to_edge, axis=1)
        edge_normal = to_edge / np.where(edge_distance > 0.0, edge_distance, 1.0)[:, None]
        d = np.where(at_edge, edge_distance, np.where(at_wall, self.inner - length, height))
        n = np.where(
            at_edge[:, None],
            edge_normal,
            np.where(at_wall[:, None], -outward, self.normal),
        )
        return d, n

    def _scale(self, height: np.ndarray, length: np.ndarray, at_edge, at_wall) -> np.ndarray:
        """``projector_scale`` from the points' parts and regions."""
        distance = np.hypot(length - self.inner, height)
        return np.where(
            at_edge,
            1.0 / np.maximum(distance, 1e-300),
            np.where(at_wall, -1.0 / np.maximum(length, 1e-300), 0.0),
        )

    def projector_scale(self, x: np.ndarray, load_factor: float = 0.0) -> np.ndarray:
        """0 on the face (a plane); in front of the bore 1 / the distance to the edge's circle;
        at the bore's wall -1 / radius (a concave cylinder seen from its axis side); the
        factor c of ``normal_gradient``."""
        height, _, length = self._parts(x, load_factor)
        return self._scale(height, length, *self._regions(height, length))

    def normal_gradient(
        self, x: np.ndarray, normal: np.ndarray, load_factor: float = 0.0
    ) -> np.ndarray:
        """(k, 3, 3) dn/dx at the points x (k, 3) with their normals (k, 3), c of
        ``projector_scale``: on the face 0; at the bore's wall c (I - n n^T - a a^T) (a the
        ring's axis, along which the wall's normal does not turn); in front of the bore, where
        n = (x - p) / d from the edge circle's nearest point p = inner e_r, which turns with
        the point's azimuth, (I - n n^T)(I - dp/dx) / d = c (I - n n^T - (inner / r) t t^T),
        t = a x e_r the circle's direction at p (on the axis, r = 0, p is any point of the
        circle and the term is left out: the circle is then inner away)."""
        height, outward, length = self._parts(x, load_factor)
        at_edge, at_wall = self._regions(height, length)
        across = np.eye(3) - normal[:, :, None] * normal[:, None, :]
        across = across - at_wall[:, None, None] * np.outer(self.normal, self.normal)
        along = np.cross(self.normal, outward)  # the circle's direction at p (k, 3)
        turn = np.where(at_edge & (length > 0.0), self.inner / np.where(length > 0, length, 1), 0)
        across = across - turn[:, None, None] * along[:, :, None] * along[:, None, :]
        scale = self._scale(height, length, at_edge, at_wall)
        return scale[:, None, None] * across

    def side_hint(self) -> str:
        return f"normal = {tuple(float(v) for v in self.normal)} must point towards the body"

    def reference_point(self) -> np.ndarray:
        return self.point.copy()
