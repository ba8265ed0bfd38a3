"""Mindlin cantilever strip rolled into a quarter circle by an end moment.

Source: Euler-Bernoulli bending, M = EI kappa: a uniform moment bends an inextensible strip
into a circular arc of radius R = EI / M (closed form; a standard large-rotation test of
shell elements, e.g. Sze, Liu & Lo, Finite Elem. Anal. Des. 40 (2004) 1551, "cantilever
subjected to end moment").
Geometry: strip 100 x 10 mm, h = 1 mm (L/h = 100), clamped at x = 0, an end moment M about -y
spread over the tip nodes; nx x 1 cells.
Parameters: E = 1e5 MPa, nu = 0 (EI = E b h^3 / 12), M = (pi / 2) EI / L: a quarter circle,
R = 2 L / pi = 63.66 mm; the moment is ramped in 4 equal load increments, each giving an arc of
radius EI / (lambda M).
Assumed: the end moment is dead (its axis stays -y, which it does in this plane motion); the
shear and membrane compliances neglected by the closed form are of order (h/L)^2.
Same setup as tests/test_static.py::test_cantilever_rolls_up_into_a_circle_under_an_end_moment.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from solvers import Static
from validation.checks import check
from validation.plots import figure
from validation.records import Case, Figure, Outcome
from validation.specimens import mindlin_strip

__all__ = ["CASE", "RollupData", "compute", "render"]

NAME = "mindlin-rollup"
TITLE = "Mindlin cantilever strip rolled into a quarter circle by an end moment"
SOURCE = "Euler-Bernoulli: R = EI / M (closed form)"
CELLS = {"coarse": 10, "default": 20, "fine": 80}
LENGTH, WIDTH, THICKNESS, YOUNG = 100.0, 10.0, 1.0, 1e5
INCREMENTS = 4
BENDING = YOUNG * WIDTH * THICKNESS**3 / 12  # EI, N mm^2


@dataclass(frozen=True)
class RollupData:
    """Per load increment the radius EI / M of the exact arc and the positions of the edge
    y = 0; the number of cells and the solver result."""

    radii: list[float]
    edges: list[np.ndarray]
    cells: int
    result: Any


def compute(resolution: str) -> Outcome:
    """Roll the strip up with Static; check its tip and its nodes against the circle."""
    cells = CELLS[resolution]
    mesh, model = mindlin_strip(LENGTH, WIDTH, THICKNESS, YOUNG, cells)
    moment = 0.25 * 2 * np.pi * BENDING / LENGTH  # a quarter circle
    tip = mesh.nodes("right")
    model.moment(tip, (0.0, -moment / len(tip), 0.0), amplitude="linear")
    result = Static(increments=INCREMENTS).solve(model)

    radius = BENDING / moment
    x, _, z = result.positions[tip].mean(axis=0)
    # Every node against the circle through the clamp with its centre at (0, R).
    p = result.positions
    off_circle = np.abs(np.hypot(p[:, 0], p[:, 2] - radius) - radius).max() / radius
    # Tip rotation: the directors start along +z and end along -x.
    d = result.directors[tip].mean(axis=0)
    rotation = np.degrees(np.arctan2(-d[0], d[2]))

    edge = np.flatnonzero(np.isclose(mesh.points[:, 1], 0.0))
    edge = edge[np.argsort(mesh.points[edge, 0])]
    increments = result.frames[1:]
    return Outcome(
        converged=result.converged,
        wall_time_s=result.wall_time,
        steps=result.steps,
        solver=f"Static (Newton, element tangent, {INCREMENTS} increments, tol 1e-8)",
        parameters={
            "cells": cells,
            "length_mm": LENGTH,
            "width_mm": WIDTH,
            "thickness_mm": THICKNESS,
            "E_MPa": YOUNG,
            "nu": 0.0,
            "M_N_mm": moment,
            "R_mm": radius,
        },
        checks=[
            check("tip x (mm)", radius, x, 1e-2, source=SOURCE),
            check("tip z (mm)", radius, z, 1e-2, source=SOURCE),
            check(
                "largest distance of a node from the circle / R",
                0.0,
                off_circle,
                1e-2,
                relative=False,
                source=SOURCE,
            ),
            check("tip rotation (deg)", 90.0, rotation, 1e-2, source=SOURCE),
        ],
        data=RollupData(
            radii=[BENDING / (frame.load_factor * moment) for frame in increments],
            edges=[frame.positions[edge] for frame in increments],
            cells=cells,
            result=result,
        ),
    )


def render(data: RollupData, out_dir: Path) -> list[Figure]:
    """The edge y = 0 per increment on the exact arcs; the VTU file."""
    s = np.linspace(0.0, LENGTH, 200)
    with figure(out_dir / f"{NAME}.png", "x (mm)", "z (mm)", size=(6.4, 4.4)) as ax:
        for k, (r, edge) in enumerate(zip(data.radii, data.edges)):
            label = "circle R = EI / M" if k == 0 else None
            ax.plot(r * np.sin(s / r), r * (1 - np.cos(s / r)), "-", color="0.3", label=label)
            ax.plot(
                edge[:, 0],
                edge[:, 2],
                "o",
                ms=3,
                color="C0",
                label=f"MindlinShell, {data.cells} cells (per increment)" if k == 0 else None,
            )
        ax.plot([0, LENGTH], [0, 0], ":", color="0.6", label="unloaded")
        ax.set_aspect("equal")

    data.result.write(out_dir / f"{NAME}.vtu")
    return [
        Figure(
            f"{NAME}.png",
            "A Mindlin cantilever strip rolled up by an end moment, one set of points per load "
            "increment, on the circles of radius EI / M (lines): at full load a quarter "
            "circle. Every increment's points should sit on its circle.",
        )
    ]


CASE = Case(
    name=NAME,
    title=TITLE,
    source=SOURCE,
    description=__doc__,
    group="verification",
    order=70,
    compute=compute,
    render=render,
)
