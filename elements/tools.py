"""Rigid tools for contact (elements/contact.py): analytic surfaces that give, for any points,
the signed distance to the surface and its unit normal there, pointing to the side the body
stays on.

Each tool may move rigidly: ``motion`` (3,) is a translation reached at the end of the run,
through an ``amplitude`` a(tau) (femcore.loads: "linear" by default, "smooth", "step" or a
callable), tau the load factor of the quasi-static solvers or t / duration of the explicit one:
the tool is at ``a(tau) * motion`` from where it was given. Units: mm.

A tool may instead be free along some axes (``free``, e.g. ``("z",)``) and driven there by a
prescribed ``force`` (N) with the same amplitude: a blank holder. ``Model.contact`` then gives
the tool a node of its own (``Model.rigid_node``) carrying its translation along those axes,
with the tool's ``mass`` (t; required in explicit dynamics) and the force as a nodal load on
it, its other translations held; the contact couples each contact node with that node
(elements/contact.py, docs/theory.md §9.5). The motion and the force act on different axes.

The analytic tools are here; the meshed one is elements/rigid_surface.py ``RigidSurface``.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike

from femcore.checks import as_reals, check_positive
from femcore.loads import AmplitudeFunction, amplitude_of
from femcore.read_only_state import ReadOnlyState

__all__ = ["RigidCylinder", "RigidPlane", "RigidSphere", "RigidTool"]


AXES = ("x", "y", "z")


def _free_axes(free: str | Sequence[str]) -> tuple[int, ...]:
    """The column indices (0, 1, 2) of the free axes named "x", "y", "z" (or "all")."""
    names: Sequence[str] = (
        ("x", "y", "z") if free == "all" else (free,) if isinstance(free, str) else free
    )
    try:
        names = tuple(names)
    except TypeError:
        names = (free,)  # type: ignore[assignment]
    bad = [name for name in names if name not in AXES]
    if bad:
        raise ValueError(
            f"free must name translation axes among 'x', 'y', 'z' (or be 'all'), got {free!r}"
        )
    if len(set(names)) != len(names):
        raise ValueError(f"free names an axis twice: {free!r}")
    return tuple(sorted(AXES.index(name) for name in names))


def _vector(value: ArrayLike, name: str, unit: bool = False) -> np.ndarray:
    vector = as_reals(value, name, "3 finite numbers").ravel()
    if vector.shape != (3,) or not np.isfinite(vector).all():
        raise ValueError(f"{name} must be 3 finite numbers, got {value!r}")
    if unit:
        length = np.linalg.norm(vector)
        if length == 0.0:
            raise ValueError(f"{name} must be a non-zero vector, got {value!r}")
        vector = vector / length
    return vector


# the tool offsets kept, by load factor (RigidTool.offset)
_OFFSETS_KEPT = 4


class RigidTool(ReadOnlyState):
    """A rigid surface: ``distance(x, load_factor)`` -> (d (k,), n (k, 3)), the signed
    distance (mm, > 0 on the body's side) and the unit normal towards the body's side, and
    ``curvature(x, load_factor)`` -> (k,) the curvature 1/R of the surface's normal section
    (0 for a plane), for the contact tangent. ``side="inside"`` keeps the body inside a
    sphere or a cylinder (a die) instead of outside (a punch).

    Driving options of every tool: ``motion`` (3,) mm reached through ``amplitude``; ``free``
    the axes ("x", "y", "z", or "all") along which the tool moves freely instead, pushed by
    ``force`` (3,) N (components along free axes only; the same amplitude), with ``mass`` t
    (required by the explicit solver). ValueError for a force along a held axis, a motion
    along a free one, or a mass for a tool with no free axis."""

    def __init__(
        self,
        motion: ArrayLike = (0.0, 0.0, 0.0),
        side: str = "outside",
        amplitude: str | AmplitudeFunction = "linear",
        free: str | Sequence[str] = (),
        force: ArrayLike = (0.0, 0.0, 0.0),
        mass: float | None = None,
    ):
        self.motion = _vector(motion, "motion")
        self.motion.setflags(write=False)  # changed by giving another, not in place
        if side not in ("outside", "inside"):
            raise ValueError(f"side must be 'outside' or 'inside', got {side!r}")
        self.sign = 1.0 if side == "outside" else -1.0
        self.amplitude = amplitude_of(amplitude).dynamic
        self.amplitude_given = amplitude
        self.free = _free_axes(free)
        self.force = _vector(force, "force")
        self.mass = None if mass is None else check_positive(mass, "tool mass", "t")
        free_mask = np.isin(np.arange(3), self.free)
        where = ", ".join(AXES[i] for i in np.flatnonzero(~free_mask & (self.force != 0.0)))
        if where:
            raise ValueError(
                f"force = {tuple(float(f) for f in self.force)} N acts along {where}, an axis "
                f"the tool does not move freely along (free = {self.free_names}): add it to "
                "free, or drop that component"
            )
        where = ", ".join(AXES[i] for i in np.flatnonzero(free_mask & (self.motion != 0.0)))
        if where:
            raise ValueError(
                f"motion = {tuple(float(m) for m in self.motion)} mm moves the tool along "
                f"{where}, an axis it is free along (free = {self.free_names}): a free axis "
                "follows the force and the contact, not a prescribed motion"
            )
        if mass is not None and not self.free:
            raise ValueError(
                f"mass = {mass!r} t is given to a tool with no free axis: its motion is "
                "prescribed and its mass unused; give free = (...) to drive it by a force"
            )

    @property
    def driven(self) -> bool:
        """Whether the tool is free along some axis (driven by its force and the contact)."""
        return bool(self.free)

    @property
    def free_names(self) -> tuple[str, ...]:
        """The free axes by name, e.g. ("z",)."""
        return tuple(AXES[i] for i in self.free)

    def reference_point(self) -> np.ndarray:
        """(3,) a point of the tool where it was given, mm: where its own node (a driven
        tool's, ``Model.rigid_node``) is placed."""
        raise NotImplementedError

    @property
    def moves(self) -> bool:
        """Whether the tool has a motion."""
        # asked at every step by the contacts: kept for the motion's value (a new array may
        # be given; the motion itself is read-only, restored copies too)
        kept = self.__dict__.get("_moves")
        motion = self.motion.tobytes()
        if kept is None or kept[0] != motion:
            kept = (motion, bool(np.any(self.motion != 0.0)))
            self.__dict__["_moves"] = kept
        return kept[1]

    def offset(self, load_factor: float) -> np.ndarray:
        """(3,) the tool's translation at ``load_factor`` (tau), mm."""
        # A step asks for it some ten times at two or three load factors (the contacts'
        # forces, the tools' work over the step): the amplitude, a pure function of tau, is
        # evaluated once for each of the last few, the same bits (each kept with the motion's
        # value and the amplitude it was found with: a tool given others computes anew).
        tau = float(load_factor)
        offsets = self.__dict__.setdefault("_offsets", {})
        kept = offsets.get(tau)
        motion = self.motion.tobytes()
        if kept is None or kept[0] != motion or kept[1] is not self.amplitude:
            if len(offsets) >= _OFFSETS_KEPT:
                offsets.pop(next(iter(offsets)))
            found = float(self.amplitude(load_factor)) * self.motion if self.moves else np.zeros(3)
            kept = (motion, self.amplitude, found)
            offsets[tau] = kept
        return kept[2].copy()

    def contact(
        self,
        nodes=None,
        friction: float = 0.0,
        penalty: float | None = None,
        tool_node: int | None = None,
        stick_stiffness: float = 1.0,
        augmented: bool = False,
        augmented_tolerance: float | None = None,
        damping: float = 0.0,
    ):
        """The penalty contact of ``nodes`` (None: every node of the body's elements) with
        this tool (elements.contact.Contact), what ``Model.contact`` adds; ``tool_node`` the
        node carrying a driven tool's free translation (``Model.rigid_node``);
        ``stick_stiffness`` the friction's stick spring over the normal penalty;
        ``augmented`` (and its tolerance, mm) the augmented Lagrangian of the quasi-static
        solvers (elements/augmented_contact.py); ``damping`` the normal contact damping's
        fraction of critical (elements/contact_damping.py)."""
        from elements.contact import Contact  # contact.py builds on this module

        return Contact(
            self,
            nodes,
            penalty=penalty,
            friction=friction,
            tool_node=tool_node,
            stick_stiffness=stick_stiffness,
            augmented=augmented,
            augmented_tolerance=augmented_tolerance,
            damping=damping,
        )

    def distance(self, x: np.ndarray, load_factor: float = 0.0):
        raise NotImplementedError

    def exact_distance(self, x: np.ndarray, load_factor: float = 0.0):
        """``distance`` exact at any distance and keeping nothing (an analytic tool's own;
        a meshed one's past its search distance, elements/rigid_surface.py)."""
        return self.distance(x, load_factor)

    def side_hint(self) -> str:
        """What sets the side the body stays on, for a message about a body on the wrong
        side."""
        return f"side = {'outside' if self.sign > 0 else 'inside'}: is that the body's side?"

    def exact_within(self, distance: float) -> None:
        """A contact asks for exact distances up to ``distance`` (mm, twice its largest offset
        h / 2); analytic tools always give them."""
        return None

    def projector_scale(self, x: np.ndarray, load_factor: float = 0.0) -> np.ndarray:
        """(k,) the factor c of dn/dx = c (I - n n^T - a a^T), a the cylinder's axis (none
        for a sphere): the tool's sign over the distance to its centre or axis; 0 for a
        plane."""
        raise NotImplementedError

    def normal_gradient(
        self, x: np.ndarray, normal: np.ndarray, load_factor: float = 0.0
    ) -> np.ndarray:
        """(k, 3, 3) dn/dx, the turn of the tool's normal n (k, 3) at the points x (k, 3) as
        they move (the contact tangent's curvature term, docs/theory.md §9.1): c (I - n n^T
        - a a^T) with c of ``projector_scale``."""
        across = np.eye(3) - normal[:, :, None] * normal[:, None, :]
        if self.axis is not None:
            across = across - np.outer(self.axis, self.axis)
        return self.projector_scale(x, load_factor)[:, None, None] * across

    axis: np.ndarray | None = None


class RigidPlane(RigidTool):
    """The plane through ``point`` with unit ``normal`` (towards the body)."""

    def __init__(
        self,
        point: ArrayLike,
        normal: ArrayLike,
        motion: ArrayLike = (0.0, 0.0, 0.0),
        amplitude: str | AmplitudeFunction = "linear",
        free: str | Sequence[str] = (),
        force: ArrayLike = (0.0, 0.0, 0.0),
        mass: float | None = None,
    ):
        super().__init__(motion, amplitude=amplitude, free=free, force=force, mass=mass)
        self.point = _vector(point, "RigidPlane point")
        self.normal = _vector(normal, "RigidPlane normal", unit=True)

    def distance(self, x: np.ndarray, load_factor: float = 0.0):
        origin = self.point + self.offset(load_factor)
        d = (x - origin) @ self.normal
        return d, np.broadcast_to(self.normal, x.shape)

    def projector_scale(self, x: np.ndarray, load_factor: float = 0.0) -> np.ndarray:
        return np.zeros(len(x))

    def side_hint(self) -> str:
        return f"normal = {tuple(float(v) for v in self.normal)} must point towards the body"

    def reference_point(self) -> np.ndarray:
        return self.point.copy()


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
        free: str | Sequence[str] = (),
        force: ArrayLike = (0.0, 0.0, 0.0),
        mass: float | None = None,
    ):
        super().__init__(motion, side, amplitude, free, force, mass)
        self.centre = _vector(centre, "RigidSphere centre")
        self.radius = check_positive(radius, "RigidSphere radius", "mm")

    def reference_point(self) -> np.ndarray:
        return self.centre.copy()

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
        free: str | Sequence[str] = (),
        force: ArrayLike = (0.0, 0.0, 0.0),
        mass: float | None = None,
    ):
        super().__init__(motion, side, amplitude, free, force, mass)
        self.point = _vector(point, "RigidCylinder point")
        self.direction = _vector(axis, "RigidCylinder axis", unit=True)
        self.axis = self.direction
        self.radius = check_positive(radius, "RigidCylinder radius", "mm")

    def reference_point(self) -> np.ndarray:
        return self.point.copy()

    def _relative(self, x: np.ndarray, load_factor: float) -> np.ndarray:
        r = x - (self.point + self.offset(load_factor))
        return r - (r @ self.direction)[:, None] * self.direction


def __getattr__(name: str):
    """``elements.tools.RigidSurface`` and the candidate lists it keeps: where models pickled
    before the meshed tool had its own module (elements/rigid_surface.py) look for them. (A
    checkpoint of such a model loads, but its run does not resume: the model's fingerprint
    names each object's module, femcore/fingerprint.py, and refuses it as another model's.)"""
    if name in ("RigidSurface", "_Candidates"):
        from elements import rigid_surface

        return getattr(rigid_surface, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
