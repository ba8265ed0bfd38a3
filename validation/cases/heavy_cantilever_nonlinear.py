"""G986 strip under its own weight with Bai's bilinear bending law: both kinematics against the
non-linear heavy elastica, and Peirce's cantilever test.

Source: the inextensible heavy cantilever with a bending law M(kappa), dM/ds = -q (L - s)
cos(theta), dtheta/ds = kappa(M), theta(0) = 0, M(L) = 0 (Frisch-Fay, Flexible Bars, 1962,
ch. 3), solved as a boundary-value problem in
validation.references.elastica.heavy_cantilever_law, independent of any finite element
(checked there against a shooting solution to 1e-11 and against q L^4 / (8 B) for small loads,
tests/test_nonlinear_bending.py). MindlinShell(fabric)'s reference is the same strip with its
stated transverse shear stiffness S (Reissner's beam: the centre line leans from the sections
by Q / S). Peirce's cantilever test (Peirce, J. Textile Inst. 21 (1930) T377; ASTM D1388):
the overhang whose chord from the clamp to the tip makes 41.5 deg below the horizontal
(validation.references.elastica.peirce_overhang), and the stiffness q (l / 2)^3 it reports.
Geometry: strip 50 x 10 mm, h = 6 mm; n x 1 cells, three meshes per resolution; the fibrous
shell clamped with the clamped-edge option (validation.specimens.fibrous_strip), the Mindlin
shell with translations and rotations fixed at x = 0 (validation.specimens.mindlin_fabric_strip).
Parameters: materials.presets.g986_stack(): Bai Table 1, bending 7.5 N mm up to 1e-3 1/mm,
0.5 N mm beyond (knee moment 0.0075 N), tension 1200 N/mm; 20 plies of 0.3 mm and 285 g/m^2,
shear 4 N/mm (assumed by the preset); q = rho_A g = 5.59e-5 N/mm^2. Root moment 6.9x the knee
moment, the inner 56 % of the strip past the knee. MindlinShell(fabric) with its default
transverse shear S = 5 B0 / h^2 = 1.04 N/mm. Gravity in 3 equal load increments (Static).
Assumed: the fibres are inextensible against the bending (tension / (q L) ~ 4e5); the fibrous
shell has no transverse shear (its directors are free), so its reference is shear rigid.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from elements.mindlin_fabric import default_transverse_shear
from materials.presets import g986_stack
from solvers import Static
from validation.checks import check
from validation.plots import figure
from validation.records import Case, Figure, Outcome
from validation.references.elastica import (
    PEIRCE_ANGLE_DEG,
    heavy_cantilever_law,
    peirce_bending_length_ratio,
    peirce_overhang,
)
from validation.specimens import GRAVITY, fibrous_strip, mindlin_fabric_strip

__all__ = ["CASE", "NonlinearCantileverData", "compute", "render"]

NAME = "heavy-cantilever-nonlinear"
TITLE = "G986 strip under its own weight, bilinear bending: both kinematics and Peirce's test"
SOURCE = "Heavy elastica with M(kappa) (Frisch-Fay 1962), BVP; Peirce (1930) / ASTM D1388"
# Meshes per resolution; the checks are made on the middle one, the order over all three.
CELLS = {"coarse": (5, 10, 20), "default": (10, 20, 40), "fine": (20, 40, 80)}
# Measured against the references, (tip deflection, tip x):
#   FibrousShell:        (+3.46 %, -2.06 %), (+0.90 %, -0.51 %), (+0.22 %, -0.12 %),
#                        (+0.056 %, -0.031 %) at 5, 10, 20, 40 cells: second order.
#   MindlinShell(fabric): (+2.51 %, -3.18 %), (+0.60 %, -0.71 %), (+0.15 %, -0.18 %),
#                        (+0.037 %, -0.041 %) at 5, 10, 20, 40 cells: second order (1.94-2.18).
# 1 % on the middle mesh of each resolution.
TOLERANCE = 0.01
# Peirce: the chord angle's error is sin phi cos phi (e_delta - e_x) of the tip errors:
# measured 0.39 / 0.32 deg (fibrous / Mindlin) at 10 cells, 0.094 / 0.106 deg at 20.
PEIRCE_TOLERANCE_DEG = {"coarse": 0.5, "default": 0.2, "fine": 0.2}
# Observed order over the two finer meshes: second order expected, measured 1.92-2.18.
ORDER, ORDER_TOLERANCE = 2.0, 0.35
INCREMENTS = 3
LENGTH, WIDTH, INITIAL_SLOPE = 50.0, 10.0, 7.5
KINEMATICS = {
    "fibrous": ("FibrousShell", fibrous_strip),
    "mindlin": ("MindlinShell(fabric)", mindlin_fabric_strip),
}


@dataclass(frozen=True)
class NonlinearCantileverData:
    """The references and, per kinematics, the side y = 0 of the middle mesh, the errors per
    mesh and the solver result of the middle mesh."""

    references: dict[str, dict[str, Any]]
    linear_fit: dict[str, Any]
    sides: dict[str, np.ndarray]
    errors: dict[str, np.ndarray]
    meshes: tuple[int, ...]
    results: dict[str, Any]


def _solve(kinematics: str, length: float, cells: int):
    """Mesh, result and tip (mean of the nodes at x = L, (3,) mm) of one strip."""
    build = KINEMATICS[kinematics][1]
    mesh, model = build(length, WIDTH, g986_stack(), cells)
    result = Static(increments=INCREMENTS, progress=False).solve(model)
    return mesh, result, result.positions[mesh.nodes("right")].mean(axis=0)


def compute(resolution: str) -> Outcome:
    """Solve the strip with both kinematics on three meshes and the Peirce strip on the middle
    one; check tips, orders and the chord angle against the references."""
    meshes = CELLS[resolution]
    fabric = g986_stack()
    weight = fabric.areal_density * GRAVITY
    shear = default_transverse_shear(fabric)
    references = {
        "fibrous": heavy_cantilever_law(LENGTH, weight, fabric.bending),
        "mindlin": heavy_cantilever_law(LENGTH, weight, fabric.bending, shear_stiffness=shear),
    }
    linear_fit = heavy_cantilever_law(LENGTH, weight, INITIAL_SLOPE)
    peirce = peirce_overhang(weight, fabric.bending)
    linear_peirce = peirce_overhang(weight, INITIAL_SLOPE)
    source = "validation.references.elastica.heavy_cantilever_law"
    checks, sides, errors, results = [], {}, {}, {}
    parameters: dict[str, Any] = {
        "meshes": list(meshes),
        "length_mm": LENGTH,
        "width_mm": WIDTH,
        "thickness_mm": fabric.thickness,
        "rho_A_t_per_mm2": fabric.areal_density,
        "bending_law": repr(fabric.bending),
        "mindlin_transverse_shear_N_per_mm": shear,
        "reference_tip_deflection_mm": references["fibrous"]["tip_deflection"],
        "reference_tip_x_mm": references["fibrous"]["tip_x"],
        "reference_tip_slope_deg": float(np.degrees(references["fibrous"]["tip_slope"])),
        "root_moment_over_knee_moment": references["fibrous"]["root_moment"] / 0.0075,
        "linear_fit_tip_deflection_mm": linear_fit["tip_deflection"],
        "bilinear_over_linear_fit_deflection": references["fibrous"]["tip_deflection"]
        / linear_fit["tip_deflection"],
        "shear_flexible_over_rigid_deflection": references["mindlin"]["tip_deflection"]
        / references["fibrous"]["tip_deflection"],
        "peirce_overhang_mm": peirce["overhang"],
        "peirce_apparent_stiffness_N_mm": peirce["apparent_stiffness"],
        "peirce_overhang_linear_7.5_mm": linear_peirce["overhang"],
        "peirce_c_over_l_exact_linear": (INITIAL_SLOPE / weight) ** (1 / 3)
        / linear_peirce["overhang"],
        "peirce_c_over_l_peirce_formula": peirce_bending_length_ratio(),
    }
    wall, steps, converged = 0.0, 0, True
    middle = meshes[1]
    for kinematics, (label, _) in KINEMATICS.items():
        reference = references[kinematics]
        table = []
        for cells in meshes:
            mesh, result, tip = _solve(kinematics, LENGTH, cells)
            wall, steps = wall + result.wall_time, steps + result.steps
            converged &= bool(result.converged)
            table.append(
                (-tip[2] / reference["tip_deflection"] - 1.0, tip[0] / reference["tip_x"] - 1.0)
            )
            if cells == middle:
                side = np.flatnonzero(np.isclose(mesh.points[:, 1], 0.0))
                side = side[np.argsort(mesh.points[side, 0])]
                sides[kinematics], results[kinematics] = result.positions[side], result
                checks += [
                    check(
                        f"{label}: tip deflection (mm), {cells} cells",
                        reference["tip_deflection"],
                        -tip[2],
                        TOLERANCE,
                        source=source,
                    ),
                    check(
                        f"{label}: tip x (mm), {cells} cells",
                        reference["tip_x"],
                        tip[0],
                        TOLERANCE,
                        source=source,
                    ),
                ]
        errors[kinematics] = np.array(table)
        orders = np.log2(np.abs(errors[kinematics][:-1] / errors[kinematics][1:]))
        parameters[f"{kinematics}_errors_deflection_x"] = errors[kinematics].tolist()
        parameters[f"{kinematics}_observed_orders_deflection_x"] = orders.tolist()
        for component, what in enumerate(("tip deflection", "tip x")):
            checks.append(
                check(
                    f"{label}: observed order of the {what} error, {meshes[1]}-{meshes[2]} cells",
                    ORDER,
                    orders[-1, component],
                    ORDER_TOLERANCE,
                    relative=False,
                    source="second-order convergence (measured 1.92-2.18)",
                )
            )
        _, result, tip = _solve(kinematics, peirce["overhang"], middle)
        wall, steps = wall + result.wall_time, steps + result.steps
        converged &= bool(result.converged)
        checks.append(
            check(
                f"{label}: chord angle of the Peirce overhang {peirce['overhang']:.2f} mm (deg),"
                f" {middle} cells",
                PEIRCE_ANGLE_DEG,
                np.degrees(np.arctan2(-tip[2], tip[0])),
                PEIRCE_TOLERANCE_DEG[resolution],
                relative=False,
                source="Peirce (1930), ASTM D1388; validation.references.elastica.peirce_overhang",
            )
        )
    return Outcome(
        converged=converged,
        wall_time_s=wall,
        steps=steps,
        solver=f"Static (Newton, element tangent, {INCREMENTS} increments)",
        parameters=parameters,
        checks=checks,
        data=NonlinearCantileverData(
            references=references,
            linear_fit=linear_fit,
            sides=sides,
            errors=errors,
            meshes=tuple(meshes),
            results=results,
        ),
    )


def render(data: NonlinearCantileverData, out_dir: Path) -> list[Figure]:
    """The reference shapes and both kinematics (side y = 0, middle mesh); the errors against
    the mesh; the VTU files."""
    shape, convergence = f"{NAME}.png", f"{NAME}-convergence.png"
    middle = data.meshes[1]
    with figure(out_dir / shape, "x (mm)", "z (mm)") as ax:
        rigid, linear = data.references["fibrous"], data.linear_fit
        ax.plot(rigid["x"], rigid["z"], "-", color="0.3", label="heavy elastica, bilinear (BVP)")
        flexible = data.references["mindlin"]
        ax.plot(flexible["x"], flexible["z"], ":", color="k", label="same, shear-flexible (S)")
        ax.plot(
            linear["x"],
            linear["z"],
            "--",
            color="0.6",
            label="linear law of the initial slope, B = 7.5 N mm",
        )
        for (kinematics, (label, _)), marker in zip(KINEMATICS.items(), ("o", "s")):
            if kinematics in data.sides:
                p = data.sides[kinematics]
                name = f"{label}, {middle} cells"
                ax.plot(p[:, 0], p[:, 2], marker, ms=4, mfc="none", label=name)
        ax.set_aspect("equal")
    with figure(out_dir / convergence, "cells along the strip", "|relative tip error|") as ax:
        for kinematics, (label, _) in KINEMATICS.items():
            e = np.abs(data.errors[kinematics])
            ax.loglog(data.meshes, e[:, 0], "o-", label=f"{label}: deflection")
            ax.loglog(data.meshes, e[:, 1], "s--", label=f"{label}: x")
        h = np.array(data.meshes, dtype=float)
        ax.loglog(h, 0.9e-2 * (h / h[0]) ** -2, ":", color="0.5", label="second order")
    for kinematics, result in data.results.items():
        result.write(out_dir / f"{NAME}-{kinematics}.vtu")
    return [
        Figure(
            shape,
            "A G986 strip under its own weight with Bai's bilinear bending law, side y = 0: "
            "the fibrous and the Mindlin shell against the heavy elastica of the bilinear law "
            "(line; dotted with the Mindlin shell's transverse shear) and of the linear law of "
            "the initial slope, B = 7.5 N mm (dashed). Each kinematics should sit on its own "
            "reference, not on the linear law.",
        ),
        Figure(
            convergence,
            "The relative tip errors of the fibrous and the Mindlin shell against their "
            "references on three meshes (log-log), deflection and x, with a second-order "
            "line. The errors should fall with the mesh at about that slope.",
        ),
    ]


CASE = Case(
    name=NAME,
    title=TITLE,
    source=SOURCE,
    description=__doc__,
    group="verification",
    order=55,
    compute=compute,
    render=render,
)
