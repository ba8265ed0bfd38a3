"""A meshed tool whose size is off the body's by orders of magnitude: most often a tool mesh
written in metres beside a body in millimetres (or the other way), which the contact cannot
tell from a real size. Warned once, when the model is compiled, naming both extents."""

from __future__ import annotations

import warnings

import numpy as np

__all__ = ["SCALE_FACTOR", "warn_tool_scale"]

#: How many times larger or smaller than the body a meshed tool's extent may be before the
#: start warns: a punch a tenth of its blank or a table ten times its strip is common, a
#: hundred times is not; metres beside millimetres is a thousand.
SCALE_FACTOR = 100.0


def warn_tool_scale(tool, body_points: np.ndarray) -> None:
    """Warn (UserWarning) when a meshed tool's largest extent and that of the body's mesh
    differ by more than SCALE_FACTOR.

    Parameters
    ----------
    tool : elements.tools.RigidTool
        A tool with ``corners`` ((f, 3, 3) facet corners, mm: a ``RigidSurface``); any other
        tool (a plane, a sphere: no extent of its own to compare) is let through.
    body_points : (n, 3) float, mm
        The reference positions of the body's whole mesh, not only of the contact's nodes:
        a contact limited to a patch of a strip (its last 5 mm over a table) is no measure of
        the strip's size, and a table 15 times the strip is not a unit slip.
    """
    corners = getattr(tool, "corners", None)
    if corners is None or len(body_points) < 2:
        return
    tool_points = np.asarray(corners, dtype=float).reshape(-1, 3)
    tool_size = float(np.ptp(tool_points, axis=0).max())
    body_size = float(np.ptp(np.asarray(body_points, dtype=float), axis=0).max())
    if tool_size <= 0.0 or body_size <= 0.0:
        return
    ratio = tool_size / body_size
    if 1.0 / SCALE_FACTOR <= ratio <= SCALE_FACTOR:
        return

    def extent(points: np.ndarray) -> str:
        low, high = points.min(axis=0), points.max(axis=0)
        return " x ".join(f"{float(h - lo):.4g}" for lo, h in zip(low, high))

    tool_extent, body_extent = extent(tool_points), extent(np.asarray(body_points, dtype=float))
    warnings.warn(
        f"the {type(tool).__name__} spans {tool_extent} (largest {tool_size:.4g}) and the "
        f"body's mesh {body_extent} (largest {body_size:.4g}): the tool is "
        f"{ratio:.3g} times the body's size. Are both meshes in the same unit? A mesh in "
        "metres beside one in mm is 1000 times off: scale the tool's mesh (or the body's) to "
        "the model's unit",
        UserWarning,
        stacklevel=2,
    )
