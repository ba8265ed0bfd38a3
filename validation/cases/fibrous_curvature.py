"""Curvature patch test of the rotation-free fibrous bending: quadratic surfaces are exact.

Source: closed-form curvature of imposed surfaces (docs/theory.md §4.2; the rotation-free bending
of Bai et al. 2020, Eqs. 20, 34-37, with the clamped-edge option of docs/theory.md §4.5). A flat
sheet is lifted to z = epsilon f(x, y) with epsilon = 1e-6 (so that the curvature is linear in the
lift) and the warp and weft curvatures of every cell are read from its cell fields
(CompiledModel.fields, from FibrousShell's cell_fields); the interior cells and those at the
clamped wall from elements.fibrous.side_tables;
chi = -d^2 w / ds^2 along the fibre (Bai's sign).
Geometry: a 6 x 7.8 mm sheet, 6 x 6 cells (a = 1 mm, b = 1.3 mm as in docs/theory.md §4.2), warp
along x; and a 6 x 4 mm sheet, 6 x 2 cells, clamped along x = 0 for the clamped-edge option.
Surfaces and expected (warp, weft) curvature on interior cells: x^2/2 (-1, 0), y^2/2 (0, -1),
(x^2 + y^2)/2 (-1, -1), (x + y)^2/2 (-1, -1), x y (0, 0): a pure twist bends no fibre on
this one-way pattern of split quads (on the alternating one every interior cell reads it as
+-b/a, +-a/b: docs/theory.md §4.2, "Twist and the mesh's pattern"); and x^2/2 at the clamped
wall (-1).
Nothing assumed: the references are exact; the material does not enter the curvature.
Same checks as tests/test_fibrous.py::test_constant_curvature_is_exact_on_interior_elements and
::test_clamped_edge_option_gives_the_exact_curvature_at_the_wall. No solver.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from elements import FibrousShell
from elements.fibrous import side_tables
from femcore import Mesh, Model
from materials import BendingLaw, Fabric, ShearLaw
from validation.checks import check
from validation.plots import figure
from validation.records import Case, Figure, Outcome

__all__ = ["CASE", "CurvatureData", "compute", "curvatures", "render", "sheet", "worst"]

NAME = "fibrous-curvature"
TITLE = "Rotation-free fibrous bending: constant curvature is exact (patch test)"
SOURCE = "closed-form curvature of the imposed surface (docs/theory.md §4.2)"
# The patch test is exact on any mesh: the resolutions only change the number of cells.
CELLS = {"coarse": 6, "default": 6, "fine": 12}
EPSILON = 1e-6
TOLERANCE = 1e-6  # absolute, on curvatures of order 1 (1/mm)
SURFACES = [
    ("x^2/2", lambda x, y: x**2 / 2, -1.0, 0.0),
    ("y^2/2", lambda x, y: y**2 / 2, 0.0, -1.0),
    ("(x^2 + y^2)/2", lambda x, y: (x**2 + y**2) / 2, -1.0, -1.0),
    ("(x + y)^2/2", lambda x, y: (x + y) ** 2 / 2, -1.0, -1.0),
    ("x y (twist)", lambda x, y: x * y, 0.0, 0.0),
]


@dataclass(frozen=True)
class CurvatureData:
    """Warp curvature under z = x^2/2 per cell: on the square sheet (centroids, interior
    mask, values) and at the cells of the clamped wall, with and without the option."""

    centroid: np.ndarray
    interior: np.ndarray
    chi_warp: np.ndarray
    wall_centroid: np.ndarray
    at_wall: np.ndarray
    chi_clamped: np.ndarray
    chi_free: np.ndarray


def sheet(mesh: Mesh, **options: Any) -> Any:
    """The compiled model of a fibrous sheet on ``mesh`` (FibrousShell ``options``)."""
    fabric = Fabric(
        thickness=3.0,
        areal_density=1e-9,
        tension=100.0,
        shear=ShearLaw.linear(5.0),
        bending=BendingLaw.linear(20.0),
    )
    model = Model(mesh)
    model.add(FibrousShell(fabric, **options))
    if options.get("clamped") is not None:
        model.fix(options["clamped"])  # a clamped edge is held by the supports
    return model.compile()


def curvatures(
    model: Any, surface: Callable[[np.ndarray, np.ndarray], np.ndarray]
) -> tuple[np.ndarray, np.ndarray]:
    """Warp and weft curvature of every cell when the nodes are lifted to epsilon f(x, y)."""
    state = model.initial_state()
    x, y = model.reference_positions[:, 0], model.reference_positions[:, 1]
    state.positions[:, 2] = EPSILON * surface(x, y)
    fields = model.fields(state)["triangle"]
    return fields["warp_curvature"] / EPSILON, fields["weft_curvature"] / EPSILON


def worst(values: np.ndarray, expected: float) -> float:
    """The value farthest from ``expected``."""
    return float(values[np.argmax(np.abs(values - expected))])


def compute(resolution: str) -> Outcome:
    """Curvatures of every imposed surface on the sheet, and at a clamped wall."""
    started = time.perf_counter()
    n = CELLS[resolution]
    mesh = Mesh.rectangle(1.0 * n, 1.3 * n, nx=n, ny=n)
    model = sheet(mesh)
    interior = (side_tables(model)["neighbour"] >= 0).all(axis=1)
    checks = []
    for name, surface, warp, weft in SURFACES:
        chi_warp, chi_weft = curvatures(model, surface)
        for fibre, chi, expected in (("warp", chi_warp, warp), ("weft", chi_weft, weft)):
            checks.append(
                check(
                    f"{fibre} curvature (1/mm), z = {name}, worst interior cell",
                    expected,
                    worst(chi[interior], expected),
                    TOLERANCE,
                    relative=False,
                    source=SOURCE,
                )
            )

    wall = Mesh.rectangle(1.0 * n, 4.0 * n / 6, nx=n, ny=max(n // 3, 1))
    clamped = sheet(wall, clamped="left")
    at_wall = np.flatnonzero(side_tables(clamped)["clamped_side"].any(axis=1))
    chi_clamped, _ = curvatures(clamped, lambda x, y: x**2 / 2)
    checks.append(
        check(
            "warp curvature (1/mm), z = x^2/2, worst cell at the clamped wall",
            -1.0,
            worst(chi_clamped[at_wall], -1.0),
            TOLERANCE,
            relative=False,
            source="docs/theory.md §4.5 (clamped-edge option)",
        )
    )
    chi_free, _ = curvatures(sheet(wall), lambda x, y: x**2 / 2)
    chi_warp, _ = curvatures(model, SURFACES[0][1])
    data = CurvatureData(
        centroid=mesh.points[mesh.triangles].mean(axis=1),
        interior=interior,
        chi_warp=chi_warp,
        wall_centroid=wall.points[wall.triangles].mean(axis=1),
        at_wall=at_wall,
        chi_clamped=chi_clamped,
        chi_free=chi_free,
    )
    return Outcome(
        converged=True,
        wall_time_s=time.perf_counter() - started,
        steps=0,
        solver="none (FibrousShell.cell_fields of imposed surfaces, lift 1e-6)",
        parameters={
            "cells": f"{n} x {n} (a = 1 mm, b = 1.3 mm); wall sheet {n} x {max(n // 3, 1)}",
            "interior_cells": int(interior.sum()),
            "lift_epsilon": EPSILON,
            "wall_cell_warp_curvature_without_option": worst(chi_free[at_wall], -1.0),
        },
        checks=checks,
        data=data,
    )


def render(data: CurvatureData, out_dir: Path) -> list[Figure]:
    """Warp curvature of every cell under z = x^2/2 against the exact value."""
    interior, at_wall = data.interior, data.at_wall
    with figure(out_dir / f"{NAME}.png", "cell centroid x (mm)", "warp curvature (1/mm)") as ax:
        ax.axhline(-1.0, color="0.3", label="exact, z = x^2/2")
        ax.plot(data.centroid[interior, 0], data.chi_warp[interior], "o", label="interior cells")
        ax.plot(
            data.centroid[~interior, 0],
            data.chi_warp[~interior],
            "x",
            label="cells on a free edge",
        )
        ax.plot(
            data.wall_centroid[at_wall, 0],
            data.chi_clamped[at_wall],
            "s",
            mfc="none",
            ms=9,
            label="cells at a clamped wall, clamped-edge option",
        )
        ax.plot(
            data.wall_centroid[at_wall, 0],
            data.chi_free[at_wall],
            "^",
            label="same cells without the option (free edge)",
        )
    return [
        Figure(
            f"{NAME}.png",
            "The warp curvature of every cell of the fibrous shell's rotation-free bending when "
            "a flat sheet is lifted onto z = x^2/2, against the exact -1: interior cells, cells "
            "on a free edge, and cells at a clamped wall with and without the clamped-edge "
            "option. Interior cells and clamped-edge cells must sit on the line; the free-edge "
            "cells show what the option corrects.",
        )
    ]


CASE = Case(
    name=NAME,
    title=TITLE,
    source=SOURCE,
    description=__doc__,
    group="verification",
    order=40,
    compute=compute,
    render=render,
)
