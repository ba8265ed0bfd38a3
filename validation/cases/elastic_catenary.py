"""Elastic catenary: a soft cable that stretches a few per cent under its own weight.

Source: Irvine, *Cable Structures* (1981), §1.3, Eqs. 1.28-1.29 (validation.references.catenary).
Geometry and start: as cable-catenary. Parameters: EA = 10 N (tension / EA up to ~5 %, sag +13 %
over the inextensible one), mu = 1e-6 t/mm, g = 9810 mm/s^2.
Both dynamic-relaxation dampings (kinetic, adaptive viscous) are run.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

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

__all__ = ["CASE", "ElasticCatenaryData", "compute", "render"]

NAME = "cable-elastic-catenary"
TITLE = "Extensible cable under its own weight: the elastic catenary"
SOURCE = "Irvine, Cable Structures (1981), §1.3, Eqs. 1.28-1.29"
AXIAL_STIFFNESS = 10.0
DAMPINGS = ("kinetic", "viscous")


@dataclass(frozen=True)
class ElasticCatenaryData:
    """Per damping the relaxed positions and the iterations; the elastic and the
    inextensible catenary (x, z)."""

    positions: dict[str, np.ndarray]
    iterations: dict[str, int]
    elastic: tuple[np.ndarray, np.ndarray]
    inextensible: tuple[np.ndarray, np.ndarray]


def compute(resolution: str) -> Outcome:
    """Relax the soft chain with each damping; check its sag and shape."""
    segments = CHAIN_SEGMENTS[resolution]
    checks, steps, wall, converged = [], 0, 0.0, True
    positions, iterations = {}, {}
    for damping in DAMPINGS:
        model = hanging_chain(segments, AXIAL_STIFFNESS)
        result = DynamicRelaxation(tol=1e-7, damping=damping).solve(model)
        s = arc_length(model.mesh)
        x, z = elastic_catenary_shape(
            s, CHAIN_SPAN, CHAIN_LENGTH, CHAIN_MU * GRAVITY, AXIAL_STIFFNESS
        )
        sag = -z.min()
        distance = np.hypot(result.positions[:, 0] - x, result.positions[:, 2] - z).max()
        middle = int(np.argmin(np.abs(s - CHAIN_LENGTH / 2)))
        checks.append(
            check(
                f"mid-span sag, mm ({damping})",
                sag,
                -result.positions[middle, 2],
                5e-3,
                source=SOURCE,
            )
        )
        checks.append(
            check(
                f"largest distance to the elastic catenary / sag ({damping})",
                0.0,
                distance / sag,
                5e-3,
                relative=False,
                source=SOURCE,
            )
        )
        steps += result.steps
        wall += result.wall_time
        converged &= result.converged
        positions[damping] = result.positions
        iterations[damping] = result.steps
    inextensible = elastic_catenary_shape(s, CHAIN_SPAN, CHAIN_LENGTH, CHAIN_MU * GRAVITY)
    return Outcome(
        converged=converged,
        wall_time_s=wall,
        steps=steps,
        solver="DynamicRelaxation (kinetic and adaptive viscous damping, tol 1e-7)",
        parameters={
            "segments": segments,
            "sag_over_inextensible_sag": sag
            / catenary_sag(CHAIN_SPAN, CHAIN_LENGTH, CHAIN_MU * GRAVITY),
            "EA_N": AXIAL_STIFFNESS,
            "mu_t_per_mm": CHAIN_MU,
            "g_mm_per_s2": GRAVITY,
            "span_mm": CHAIN_SPAN,
            "length_mm": CHAIN_LENGTH,
        },
        checks=checks,
        data=ElasticCatenaryData(
            positions=positions,
            iterations=iterations,
            elastic=(x, z),
            inextensible=inextensible,
        ),
    )


def render(data: ElasticCatenaryData, out_dir: Path) -> list[Figure]:
    """Both relaxed chains on the elastic catenary, with the inextensible one."""
    with figure(out_dir / "cable-elastic-catenary.png", "x (mm)", "z (mm)") as ax:
        for damping, marker in zip(DAMPINGS, ("o", "x")):
            positions = data.positions[damping]
            ax.plot(
                positions[:, 0],
                positions[:, 2],
                marker,
                ms=3,
                label=(
                    f"dynamic relaxation, {damping} damping ({data.iterations[damping]} iterations)"
                ),
            )
        x, z = data.elastic
        ax.plot(x, z, "-", color="0.3", label="elastic catenary (Irvine 1981)")
        x0, z0 = data.inextensible
        ax.plot(x0, z0, "--", color="0.6", label="inextensible catenary")
        ax.set_aspect("equal")
    return [
        Figure(
            "cable-elastic-catenary.png",
            "A soft cable that stretches a few per cent under its own weight, relaxed with "
            "kinetic and with adaptive viscous damping, against Irvine's elastic catenary "
            "(line) and the inextensible one (dashed). Both sets of nodes should sit on the "
            "elastic line, whose sag is 13 % deeper than the inextensible one.",
        )
    ]


CASE = Case(
    name=NAME,
    title=TITLE,
    source=SOURCE,
    description=__doc__,
    group="verification",
    order=20,
    compute=compute,
    render=render,
)
