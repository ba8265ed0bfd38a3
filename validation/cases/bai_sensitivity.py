"""Sensitivity of the paper-stack corner test (bai-6.1.1) to the values the paper does not give.

Source: Bai et al. (2020) §6.1 gives no material data for the 130-sheet paper stack; the case
bai-6.1.1 assumes bending B = 50 N mm and in-plane shear K = 1000 N/mm
(materials.presets.paper_stack). Here the fibrous run is repeated with B halved and doubled and
K divided and multiplied by 10 (the other values as in bai-6.1.1), and the Mindlin run with B
halved and doubled (its E = 12 B / h^3 follows B).
What is compared: along side 1, the mid-surface and the director angle. The conclusion the
paper draws (fibrous directors stay nearly vertical while the Mindlin ones follow the normal)
must not depend on these choices; the check states it for every variant.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from materials import BendingLaw, Fabric, ShearLaw
from materials.presets import paper_stack
from validation import specimens
from validation.checks import check
from validation.paper import INCREMENTS, SHEAR_RATIO, solve
from validation.plots import plt
from validation.records import Case, Outcome

__all__ = ["CASE", "SensitivityData", "compute", "render", "variant"]

NAME = "bai-6.1.1-sensitivity"
TITLE = "Paper stack corner test: sensitivity to the assumed bending and shear stiffness"
SOURCE = "Bai et al. (2020) §6.1.1 with the assumed data of materials.presets.paper_stack"
CELLS = {"coarse": 6, "default": 12, "fine": 20}
# The set-up of bai-6.1.1: its specimen (specimens.PAPER_STACK_SIZE), its corner lift, and the
# paper cases' default increments and Mindlin G13 / E (validation.paper).
DISPLACEMENT = specimens.CORNER_LIFT
VARIANTS = [
    ("fibrous", "B, K as assumed", 1.0, 1.0),
    ("fibrous", "B / 2", 0.5, 1.0),
    ("fibrous", "B x 2", 2.0, 1.0),
    ("fibrous", "K / 10", 1.0, 0.1),
    ("fibrous", "K x 10", 1.0, 10.0),
    ("mindlin", "B, K as assumed", 1.0, 1.0),
    ("mindlin", "B / 2", 0.5, 1.0),
    ("mindlin", "B x 2", 2.0, 1.0),
]


@dataclass(frozen=True)
class SensitivityData:
    """Along side 1: s, and per (kinematics, label) variant its mid-surface z and director
    angle (deg), in the order of ``VARIANTS``."""

    s: np.ndarray
    profiles: dict[tuple[str, str], tuple[np.ndarray, np.ndarray]]


def variant(base: Fabric, bending_scale: float = 1.0, shear_scale: float = 1.0) -> Fabric:
    """``base`` with its (linearised) bending and shear stiffness scaled."""
    b = base.bending.slope(np.array(0.0)).item() * bending_scale
    k = base.shear.slope(np.array(0.0)).item() * shear_scale
    return Fabric(
        thickness=base.thickness,
        areal_density=base.areal_density,
        tension=base.tension,
        shear=ShearLaw.linear(k),
        bending=BendingLaw.linear(b),
    )


def compute(resolution: str) -> Outcome:
    """Solve every variant of ``VARIANTS`` on the bai-6.1.1 specimen; check each."""
    base = paper_stack()
    specimen = specimens.corner(*specimens.PAPER_STACK_SIZE, CELLS[resolution])
    nodes, s = specimen.sides["side_1"]
    checks, wall, steps, converged = [], 0.0, 0, True
    angles, profiles = {}, {}
    for kinematics, label, b_scale, k_scale in VARIANTS:
        fabric = variant(base, b_scale, k_scale)
        model = specimens.build(specimen, kinematics, fabric, DISPLACEMENT, SHEAR_RATIO)
        result, note, seconds = solve(model, INCREMENTS)
        wall += seconds
        steps += result.steps
        converged &= bool(result.converged)
        x = result.positions[nodes]
        d = result.directors[nodes]
        along = specimen.mesh.points[nodes[-1]] - specimen.mesh.points[nodes[0]]
        along /= np.linalg.norm(along)
        angle = np.degrees(np.arctan2(d[:, 2], d @ along))
        run_ = np.linalg.norm(np.gradient(x[:, :2], axis=0), axis=1)
        slope = np.degrees(np.arctan2(np.abs(np.gradient(x[:, 2])), run_)).max()
        angles[(kinematics, label)] = (angle, slope)
        profiles[(kinematics, label)] = (x[:, 2], angle)
    for (kinematics, label), (angle, slope) in angles.items():
        # Tilt of the directors from the vertical against the largest mid-surface slope:
        # ~1 for a standard shell (director = normal), ~0 for Bai's fibrous shell.
        ratio = float(np.abs(angle - 90.0).max() / slope)
        if kinematics == "fibrous":
            checks.append(
                check(
                    f"fibrous, {label}: director tilt / largest slope (< 0.2)",
                    0.0,
                    ratio,
                    0.2,
                    relative=False,
                    source="Bai §6.1.1: the directors remain almost parallel",
                )
            )
        else:
            # Same B, same mesh: the Mindlin directors turn with the surface, the fibrous
            # ones do not.
            gap = float(np.abs(angle - angles[("fibrous", label)][0]).max())
            checks.append(
                replace(
                    check(
                        f"Mindlin vs fibrous, {label}: largest director angle difference "
                        "(deg, > 5)",
                        5.0,
                        gap,
                        np.inf,
                        relative=False,
                        source="Bai §6.1.1: fibrous directors differ from standard shell normals",
                    ),
                    passed=bool(gap > 5.0),
                )
            )
    return Outcome(
        converged=converged,
        wall_time_s=wall,
        steps=steps,
        solver="Static along the arc length (load steps past a limit point), each variant",
        parameters={
            "triangles": len(specimen.mesh.triangles),
            "B assumed (N mm)": base.bending.slope(np.array(0.0)).item(),
            "K assumed (N/mm)": base.shear.slope(np.array(0.0)).item(),
            "variants": "B x 0.5, 2; K x 0.1, 10",
        },
        checks=checks,
        data=SensitivityData(s=s, profiles=profiles),
    )


def render(data: SensitivityData, out_dir: Path) -> list[str]:
    """Mid-surface and director angle along side 1, every variant: one row per kinematics, one
    colour per variant (the same in both rows), each row with its own legend."""
    labels = list(dict.fromkeys(label for _, label in data.profiles))
    colour = {label: f"C{i}" for i, label in enumerate(labels)}
    rows = list(dict.fromkeys(kinematics for kinematics, _ in data.profiles))
    fig, axes = plt.subplots(
        len(rows), 2, figsize=(12, 3.6 * len(rows)), squeeze=False, constrained_layout=True
    )
    for (kinematics, label), (z, angle) in data.profiles.items():
        row = axes[rows.index(kinematics)]
        row[0].plot(data.s, z, marker="o", ms=2, color=colour[label], label=label)
        row[1].plot(data.s, angle, marker="o", ms=2, color=colour[label], label=label)
    for kinematics, row in zip(rows, axes):
        row[0].set(xlabel="s along side 1 (mm)", ylabel="mid-surface z (mm)",
                   title=f"{kinematics}: mid-surface")  # fmt: skip
        row[1].set(xlabel="s along side 1 (mm)", ylabel="director angle to horizontal (deg)",
                   title=f"{kinematics}: director")  # fmt: skip
        for ax in row:
            ax.grid(True, alpha=0.3)
        row[1].legend(fontsize="small", title="variant")
    figure = f"{NAME}.png"
    fig.suptitle(
        "bai-6.1.1, side 1: each kinematics for the varied B and K (same colour, same variant)"
    )
    fig.savefig(out_dir / figure, dpi=100)
    plt.close(fig)
    return [figure]


CASE = Case(
    name=NAME,
    title=TITLE,
    source=SOURCE,
    description=__doc__,
    group="sensitivity",
    order=10,
    compute=compute,
    render=render,
)
