"""Elastic catenary: a soft cable that stretches a few per cent under its own weight.

Source: Irvine, *Cable Structures* (1981), §1.3, Eqs. 1.28-1.29 (validation.references.catenary).
Geometry and start: as cable-catenary. Parameters: EA = 10 N (tension / EA up to ~5 %, sag +13 %
over the inextensible one), mu = 1e-6 t/mm, g = 9810 mm/s^2.
Both dynamic-relaxation dampings (kinetic, adaptive viscous) are run.
"""

from __future__ import annotations

import numpy as np

from solvers import DynamicRelaxation
from validation.cases.catenary import LENGTH, MU, SEGMENTS, SPAN, G, arc_length, hanging_model
from validation.checks import check
from validation.plots import figure
from validation.references.catenary import catenary_sag, elastic_catenary_shape

NAME = "cable-elastic-catenary"
TITLE = "Extensible cable under its own weight: the elastic catenary"
SOURCE = "Irvine, Cable Structures (1981), §1.3, Eqs. 1.28-1.29"
AXIAL_STIFFNESS = 10.0


def run(resolution: str, out_dir) -> dict:
    segments = SEGMENTS[resolution]
    checks, steps, wall, converged = [], 0, 0.0, True
    with figure(out_dir / "cable-elastic-catenary.png", "x (mm)", "z (mm)") as ax:
        for damping, marker in (("kinetic", "o"), ("viscous", "x")):
            model = hanging_model(segments, AXIAL_STIFFNESS)
            result = DynamicRelaxation(tol=1e-7, damping=damping).solve(model)
            s = arc_length(model.mesh)
            x, z = elastic_catenary_shape(s, SPAN, LENGTH, MU * G, AXIAL_STIFFNESS)
            sag = -z.min()
            distance = np.hypot(result.positions[:, 0] - x, result.positions[:, 2] - z).max()
            middle = int(np.argmin(np.abs(s - LENGTH / 2)))
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
            ax.plot(
                result.positions[:, 0],
                result.positions[:, 2],
                marker,
                ms=3,
                label=f"dynamic relaxation, {damping} damping ({result.steps} iterations)",
            )
        ax.plot(x, z, "-", color="0.3", label="elastic catenary (Irvine 1981)")
        x0, z0 = elastic_catenary_shape(s, SPAN, LENGTH, MU * G)
        ax.plot(x0, z0, "--", color="0.6", label="inextensible catenary")
        ax.set_aspect("equal")
    return {
        "converged": converged,
        "wall_time_s": wall,
        "steps": steps,
        "solver": "DynamicRelaxation (kinetic and adaptive viscous damping, tol 1e-7)",
        "parameters": {
            "segments": segments,
            "sag_over_inextensible_sag": sag / catenary_sag(SPAN, LENGTH, MU * G),
            "EA_N": AXIAL_STIFFNESS,
            "mu_t_per_mm": MU,
            "g_mm_per_s2": G,
            "span_mm": SPAN,
            "length_mm": LENGTH,
        },
        "checks": checks,
        "figures": ["cable-elastic-catenary.png"],
    }
