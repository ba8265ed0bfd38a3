"""Inextensible catenary: a stiff chain hanging between two supports, by dynamic relaxation.

Source: the catenary y = a cosh(x/a), in the elastic form of Irvine, *Cable Structures* (1981),
§1.3, with EA -> inf (validation.references.catenary).
Geometry: unstretched length 120 mm, supports 96 mm apart at the same height; the chain starts
as a box (down 12 mm, across 96 mm, up 12 mm), far from its equilibrium.
Parameters: EA = 5000 N (strain ~1e-4, "stiff": the sag differs from the inextensible one by
3e-4), mu = 1e-6 t/mm, g = 9810 mm/s^2.
Nothing assumed: the reference is closed form.
"""

from __future__ import annotations

import numpy as np

from elements import Cable
from femcore import Mesh, Model
from solvers import DynamicRelaxation
from validation.checks import check
from validation.plots import figure
from validation.references.catenary import catenary_sag, elastic_catenary_shape

NAME = "cable-catenary"
TITLE = "Stiff cable under its own weight: the catenary"
SOURCE = "Irvine, Cable Structures (1981), §1.3 (EA -> infinity)"
SEGMENTS = {"coarse": 20, "default": 40, "fine": 160}
SPAN, LENGTH, DROP = 96.0, 120.0, 12.0
MU, G = 1.0e-6, 9810.0


def box_chain(segments: int) -> Mesh:
    """A chain of ``segments`` equal links (multiple of 10): down, across, up."""
    leg, across = segments // 10, segments - 2 * (segments // 10)
    corners = np.array([[0.0, 0, 0], [0, 0, -DROP], [SPAN, 0, -DROP], [SPAN, 0, 0]])
    points = [corners[0]]
    for a, b, n in zip(corners[:-1], corners[1:], (leg, across, leg)):
        points.extend(a + (b - a) * np.arange(1, n + 1)[:, None] / n)
    points = np.array(points)
    lines = np.column_stack([np.arange(len(points) - 1), np.arange(1, len(points))])
    return Mesh(points, lines=lines)


def hanging_model(segments: int, axial_stiffness: float) -> Model:
    mesh = box_chain(segments)
    model = Model(mesh)
    model.add(Cable(axial_stiffness, MU))
    model.fix(mesh.nodes(lambda x, y, z: np.isclose(z, 0.0)))
    model.gravity((0.0, 0.0, -G))
    return model


def arc_length(mesh: Mesh) -> np.ndarray:
    return np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(mesh.points, axis=0), axis=1))]


def run(resolution: str, out_dir) -> dict:
    segments = SEGMENTS[resolution]
    axial_stiffness = 5000.0
    model = hanging_model(segments, axial_stiffness)
    result = DynamicRelaxation(tol=1e-7).solve(model)
    s = arc_length(model.mesh)
    middle = int(np.argmin(np.abs(s - LENGTH / 2)))
    sag = -result.positions[middle, 2]
    reference = catenary_sag(SPAN, LENGTH, MU * G)
    x, z = elastic_catenary_shape(s, SPAN, LENGTH, MU * G)
    weight = MU * LENGTH * G

    with figure(out_dir / "cable-catenary.png", "x (mm)", "z (mm)") as ax:
        ax.plot(x, z, "-", color="0.3", label="catenary (Irvine 1981)")
        ax.plot(
            result.positions[:, 0], result.positions[:, 2], "o", ms=3, label="dynamic relaxation"
        )
        ax.plot(model.mesh.points[:, 0], model.mesh.points[:, 2], ":", color="0.6", label="start")
        ax.set_aspect("equal")
    result.write(out_dir / "cable-catenary.vtu")
    return {
        "converged": result.converged,
        "wall_time_s": result.wall_time,
        "steps": result.steps,
        "solver": "DynamicRelaxation (kinetic damping, tol 1e-7)",
        "parameters": {
            "segments": segments,
            "EA_N": axial_stiffness,
            "mu_t_per_mm": MU,
            "g_mm_per_s2": G,
            "span_mm": SPAN,
            "length_mm": LENGTH,
        },
        "checks": [
            check("mid-span sag (mm)", reference, sag, 5e-3, source=SOURCE),
            check(
                "largest distance to the catenary / sag",
                0.0,
                np.hypot(result.positions[:, 0] - x, result.positions[:, 2] - z).max() / reference,
                5e-3,
                relative=False,
                source=SOURCE,
            ),
            check(
                "vertical reactions / weight",
                1.0,
                result.reactions[:, 2].sum() / weight,
                1e-5,
                source="static equilibrium",
            ),
        ],
        "figures": ["cable-catenary.png"],
    }
