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

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from solvers import DynamicRelaxation
from validation.checks import check
from validation.plots import figure
from validation.records import Case, Figure, Outcome
from validation.references.catenary import catenary_sag, elastic_catenary_shape
from validation.specimens import (
    CHAIN_LENGTH,
    CHAIN_MU,
    CHAIN_SEGMENTS,
    CHAIN_SPAN,
    GRAVITY,
    arc_length,
    hanging_chain,
)

__all__ = ["CASE", "CatenaryData", "compute", "render"]

NAME = "cable-catenary"
TITLE = "Stiff cable under its own weight: the catenary"
SOURCE = "Irvine, Cable Structures (1981), §1.3 (EA -> infinity)"
AXIAL_STIFFNESS = 5000.0


@dataclass(frozen=True)
class CatenaryData:
    """The catenary (x, z) at the nodes' arc lengths, the start and the relaxed chain."""

    x: np.ndarray
    z: np.ndarray
    start: np.ndarray
    result: Any


def compute(resolution: str) -> Outcome:
    """Relax the chain from its box shape; check its sag and shape against the catenary."""
    segments = CHAIN_SEGMENTS[resolution]
    model = hanging_chain(segments, AXIAL_STIFFNESS)
    result = DynamicRelaxation(tol=1e-7).solve(model)
    s = arc_length(model.mesh)
    middle = int(np.argmin(np.abs(s - CHAIN_LENGTH / 2)))
    sag = -result.positions[middle, 2]
    reference = catenary_sag(CHAIN_SPAN, CHAIN_LENGTH, CHAIN_MU * GRAVITY)
    x, z = elastic_catenary_shape(s, CHAIN_SPAN, CHAIN_LENGTH, CHAIN_MU * GRAVITY)
    weight = CHAIN_MU * CHAIN_LENGTH * GRAVITY
    return Outcome(
        converged=result.converged,
        wall_time_s=result.wall_time,
        steps=result.steps,
        solver="DynamicRelaxation (kinetic damping, tol 1e-7)",
        parameters={
            "segments": segments,
            "EA_N": AXIAL_STIFFNESS,
            "mu_t_per_mm": CHAIN_MU,
            "g_mm_per_s2": GRAVITY,
            "span_mm": CHAIN_SPAN,
            "length_mm": CHAIN_LENGTH,
        },
        checks=[
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
        data=CatenaryData(x=x, z=z, start=model.mesh.points, result=result),
    )


def render(data: CatenaryData, out_dir: Path) -> list[Figure]:
    """The relaxed chain on the catenary; the VTU file of the result."""
    positions = data.result.positions
    with figure(out_dir / "cable-catenary.png", "x (mm)", "z (mm)") as ax:
        ax.plot(data.x, data.z, "-", color="0.3", label="catenary (Irvine 1981)")
        ax.plot(positions[:, 0], positions[:, 2], "o", ms=3, label="dynamic relaxation")
        ax.plot(data.start[:, 0], data.start[:, 2], ":", color="0.6", label="start")
        ax.set_aspect("equal")
    data.result.write(out_dir / "cable-catenary.vtu")
    return [
        Figure(
            "cable-catenary.png",
            "A stiff chain of cables relaxed by dynamic relaxation from a box-shaped start "
            "(dotted) onto the closed-form catenary of Irvine (1981, line). The dots are the "
            "nodes: they should sit on the line, sag included.",
        )
    ]


CASE = Case(
    name=NAME,
    title=TITLE,
    source=SOURCE,
    description=__doc__,
    group="verification",
    order=10,
    compute=compute,
    render=render,
)
