"""Mindlin cantilever strip under a large dead tip load: the elastica.

Source: Bisshopp & Drucker, Q. Appl. Math. 3 (1945) 272 (tip drop 0.3017 L at P L^2 / EI = 1,
0.603 L at P L^2 / EI = 3); here the reference curve is the boundary-value solve of
validation.references.elastica.tip_loaded_cantilever (EI theta'' = -P cos theta), which is
checked against their values first.
Geometry: strip 100 x 5 mm, h = 1 mm (L/h = 100), clamped at x = 0, a vertical dead load P at
x = L spread over the tip nodes; nx x 1 cells.
Parameters: E = 1e5 MPa, nu = 0 (no plate effect: EI = E b h^3 / 12 of a beam), P L^2 / EI = 3
(tip slope about 60 degrees), applied in 5 equal load increments.
Assumed: the shell is thin enough (L/h = 100) to follow the inextensible, shear-rigid elastica;
the shear and membrane compliances it neglects are of order (h/L)^2 = 1e-4.
Same setup as tests/test_mindlin.py::test_cantilever_under_a_large_tip_load_follows_the_elastica.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from femcore import Mesh
from solvers import Static
from validation.checks import check
from validation.plots import figure
from validation.records import Case, Figure, Outcome
from validation.references.elastica import tip_loaded_cantilever
from validation.specimens import mindlin_strip

__all__ = ["CASE", "ElasticaData", "compute", "render", "stations"]

NAME = "mindlin-elastica"
TITLE = "Mindlin cantilever strip under a large tip load: the elastica"
SOURCE = "Bisshopp & Drucker, Q. Appl. Math. 3 (1945) 272 (elastica, P L^2 / EI = 3)"
SOURCE_AT_1 = "Bisshopp & Drucker, Q. Appl. Math. 3 (1945) 272 (elastica, P L^2 / EI = 1)"
CELLS = {"coarse": 10, "default": 20, "fine": 80}
LENGTH, WIDTH, THICKNESS, YOUNG = 100.0, 5.0, 1.0, 1e5
LOAD_PARAMETER = 3.0  # P L^2 / EI
INCREMENTS = 5
BENDING = YOUNG * WIDTH * THICKNESS**3 / 12  # EI, N mm^2


@dataclass(frozen=True)
class ElasticaData:
    """The reference elastica, the strip's centre line, the tip drop per load increment, the
    elastica's load-deflection curve, the number of cells and the solver result."""

    reference: dict[str, Any]
    centre: np.ndarray
    factors: np.ndarray
    drops: np.ndarray
    curve: np.ndarray
    elastica: list[float]
    cells: int
    result: Any


def stations(mesh: Mesh, values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Reference x of each cross-section and ``values`` averaged over its nodes."""
    x = np.unique(np.round(mesh.points[:, 0], 9))
    index = np.searchsorted(x, np.round(mesh.points[:, 0], 9))
    mean = np.array([values[index == i].mean(axis=0) for i in range(len(x))])
    return x, mean


def compute(resolution: str) -> Outcome:
    """Solve the strip under the tip load with Static; check its tip against the elastica."""
    cells = CELLS[resolution]
    load = LOAD_PARAMETER * BENDING / LENGTH**2
    mesh, model = mindlin_strip(LENGTH, WIDTH, THICKNESS, YOUNG, cells)
    tip = mesh.nodes("right")
    model.force(tip, (0.0, 0.0, -load / len(tip)))
    result = Static(increments=INCREMENTS).solve(model)

    reference = tip_loaded_cantilever(LENGTH, load, BENDING)
    unit = tip_loaded_cantilever(LENGTH, BENDING / LENGTH**2, BENDING)  # P L^2 / EI = 1
    moved = result.displacements[tip].mean(axis=0)
    _, centre = stations(mesh, result.positions)

    # Tip load-deflection: one point per load increment against the elastica.
    factors = np.array([frame.load_factor for frame in result.frames])
    drops = np.array([-frame.positions[tip, 2].mean() for frame in result.frames])
    curve = np.linspace(0.0, 1.0, 16)
    elastica = [0.0] + [
        tip_loaded_cantilever(LENGTH, f * load, BENDING, points=201)["tip_deflection"]
        for f in curve[1:]
    ]

    bvp = "validation.references.elastica (boundary-value solve)"
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
            "P_N": load,
            "PL2_over_EI": LOAD_PARAMETER,
        },
        checks=[
            check(
                "elastica tip drop / L at P L^2 / EI = 1, to the printed digits (self-check)",
                0.3017,
                unit["tip_deflection"] / LENGTH,
                5e-5,
                relative=False,
                source=SOURCE_AT_1,
            ),
            check(
                "elastica tip drop / L at P L^2 / EI = 3, to the printed digits (self-check)",
                0.603,
                reference["tip_deflection"] / LENGTH,
                5e-4,
                relative=False,
                source=SOURCE,
            ),
            check(
                "tip deflection (mm)",
                reference["tip_deflection"],
                -moved[2],
                1e-2,
                source=bvp,
            ),
            check("tip x (mm)", reference["tip_x"], LENGTH + moved[0], 1e-2, source=bvp),
        ],
        data=ElasticaData(
            reference=reference,
            centre=centre,
            factors=factors,
            drops=drops,
            curve=curve,
            elastica=elastica,
            cells=cells,
            result=result,
        ),
    )


def render(data: ElasticaData, out_dir: Path) -> list[Figure]:
    """The deformed strip on the elastica; the tip load-deflection curve; the VTU file."""
    reference, centre, curve = data.reference, data.centre, data.curve
    with figure(out_dir / f"{NAME}.png", "x (mm)", "z (mm)") as ax:
        ax.plot(reference["x"], reference["z"], "-", color="0.3", label="elastica (BVP)")
        ax.plot(centre[:, 0], centre[:, 2], "o", ms=4, label=f"MindlinShell, {data.cells} cells")
        ax.plot([0, LENGTH], [0, 0], ":", color="0.6", label="unloaded")
        ax.set_aspect("equal")

    with figure(out_dir / f"{NAME}-load.png", "P L^2 / EI", "tip deflection / L") as ax:
        ax.plot(
            LOAD_PARAMETER * curve,
            np.array(data.elastica) / LENGTH,
            "-",
            color="0.3",
            label="elastica",
        )
        ax.plot(
            LOAD_PARAMETER * curve,
            LOAD_PARAMETER * curve / 3.0,
            "--",
            color="0.6",
            label="linear: P L^3 / (3 EI)",
        )
        ax.plot(
            LOAD_PARAMETER * data.factors, data.drops / LENGTH, "o", label="Static, per increment"
        )
        ax.plot([1.0, 3.0], [0.3017, 0.603], "kx", ms=8, label="Bisshopp & Drucker (1945)")
        ax.set_ylim(0, 0.8)

    data.result.write(out_dir / f"{NAME}.vtu")
    return [
        Figure(
            f"{NAME}.png",
            "A Mindlin cantilever strip under a large tip load (P L^2 / EI = 3): its centre "
            "line on the elastica solved as a boundary-value problem (line). The nodes should "
            "sit on the line down to the tip, about 60 degrees steep.",
        ),
        Figure(
            f"{NAME}-load.png",
            "The tip deflection of the same Mindlin strip at each load increment against the "
            "elastica, the linear solution (dashed) and Bisshopp and Drucker's values "
            "(crosses). The dots should follow the elastica, well below the linear line.",
        ),
    ]


CASE = Case(
    name=NAME,
    title=TITLE,
    source=SOURCE,
    description=__doc__,
    group="verification",
    order=60,
    compute=compute,
    render=render,
)
