"""The figures of the report's case hemisphere-forming (validation/cases/hemisphere_forming.py):
the shear angle fields of both shells beside the pin-jointed net's over the blank, the formed
blank's fibres seen from above, the punch force against its travel, and each run's frames as
a ParaView series."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from femcore.loads import smooth_step  # the punch's amplitude
from validation.forming_scaling import quasi_static_words
from validation.plots import figure, save
from validation.records import Figure

if TYPE_CHECKING:
    from validation.cases.hemisphere_forming import HemisphereData

__all__ = ["render"]


# The two blanks differ in material as well as kinematics: what every figure says of them.
MATERIAL_DIFFERS = (
    "The Mindlin blank is not the fabric: it is a linear elastic section at the fabric's "
    "initial shear slope (ElasticShell.equivalent), 1.9, 2.9 and 4.0 x softer in in-plane "
    "shear than the fabric at 30, 36 and 40.5 deg, so that the two blanks differ in material "
    "as well as in kinematics."
)


def render(data: HemisphereData, out_dir: Path) -> list[Figure]:
    """The shear angle fields (fibrous, Mindlin, the net) over the blank, the deformed
    fibres seen from above (the draw-in), and the punch force against its travel."""
    import matplotlib.pyplot as plt
    from matplotlib.tri import Triangulation

    # the case's geometry, named where the case states it (imported here: the case module
    # imports this one)
    from validation.cases.hemisphere_forming import (
        DIE,
        DURATION,
        HALF,
        NAME,
        TRAVEL,
        flange_start,
    )

    mesh = data.mesh
    figures = []
    flat = Triangulation(mesh.points[:, 0], mesh.points[:, 1], mesh.triangles)
    # Two rows of two, 8.5 in at 110 dpi (935 px): on an 800-px screen its 10-pt text
    # still reads as 9 pt. The fourth place holds the colour scale the three share.
    fig, grid = plt.subplots(2, 2, figsize=(8.5, 8.0), layout="constrained")
    axes, key = grid.ravel()[:3], grid[1, 1]
    fields = [
        ("(a) fibrous shell", data.shear["fibrous"]),
        ("(b) Mindlin shell", data.shear["mindlin"]),
        ("(c) pin-jointed net (Mack and Taylor)", data.net_shear),
    ]
    top = np.nanmax(np.abs(np.degrees(data.net_shear)))
    for ax, (label, values) in zip(axes, fields):
        shown = np.degrees(np.where(np.isfinite(values), values, np.nan))
        art = ax.tripcolor(flat, shown, cmap="coolwarm", vmin=-top, vmax=top)
        ax.set_title(label, fontsize=11)
        ax.set_aspect("equal")
        ax.set_xlabel("blank x (mm)")
        ax.set_ylabel("blank y (mm)")
    key.axis("off")
    bar = fig.colorbar(art, cax=key.inset_axes((0.05, 0.55, 0.9, 0.08)), orientation="horizontal")
    bar.set_label("shear angle (deg) of (a), (b) and (c)", fontsize=11)
    key.text(
        0.5, 0.3, "over the flat blank,\nafter forming into the hemisphere",
        ha="center", va="center", fontsize=11, transform=key.transAxes,
    )  # fmt: skip
    save(fig, out_dir / f"{NAME}-shear.png", dpi=110)
    plt.close(fig)
    figures.append(
        Figure(
            f"{NAME}-shear.png",
            "The shear angle over the flat blank after forming into the hemisphere: the "
            "fibrous shell, the Mindlin shell and the pin-jointed net draped on the same "
            "sphere (Mack and Taylor), on one colour scale. Inside the die the shells should "
            "show the net's pattern, largest along the diagonals, and its magnitudes."
            f" {MATERIAL_DIFFERS}",
        )
    )

    # 9 in at 110 dpi (990 px), its 10-pt text read as 9 pt on an 800-px screen.
    fig, axes = plt.subplots(1, 2, figsize=(9.0, 4.9), layout="constrained")
    for ax, kinematics in zip(axes, ("fibrous", "mindlin")):
        x = data.runs[kinematics].positions[: mesh.n_nodes]  # less the holder's node
        step = max(1, data.cells // 16)
        grid = x.reshape(data.cells + 1, data.cells + 1, 3)
        # each family's fibres as one line broken by NaN (not a hundred artists to lay out)
        for fibres, colour in ((grid[::step], "C0"), (grid[:, ::step].transpose(1, 0, 2), "C3")):
            broken = np.concatenate([fibres[..., :2], np.full((len(fibres), 1, 2), np.nan)], 1)
            ax.plot(*broken.reshape(-1, 2).T, "-", color=colour, lw=0.8)
        ax.plot(
            [-HALF, HALF, HALF, -HALF, -HALF], [-HALF, -HALF, HALF, HALF, -HALF], ":", color="0.5"
        )
        circle = np.linspace(0, 2 * np.pi, 200)
        # the bowl's edge, and where the entry round meets the flat flange (the holder's bore)
        ax.plot(DIE * np.cos(circle), DIE * np.sin(circle), ":", color="0.3", lw=0.8)
        flange = flange_start()
        ax.plot(flange * np.cos(circle), flange * np.sin(circle), "--", color="0.3", lw=0.8)
        ax.set_title(f"{kinematics}: warp (blue) and weft (red) from above", fontsize=10)
        ax.set_aspect("equal")
        ax.set_xlabel("x (mm)")
    axes[0].set_ylabel("y (mm)")
    save(fig, out_dir / f"{NAME}-fibres.png", dpi=110)
    plt.close(fig)
    figures.append(
        Figure(
            f"{NAME}-fibres.png",
            "The formed blank seen from above: warp (blue) and weft (red) fibres of the "
            "fibrous (left) and the Mindlin (right) shell, the blank's outline (dotted "
            f"square), the bowl's edge (dotted circle, radius {DIE:.1f} mm) and the start of "
            f"the die's flat flange past its entry round (dashed, {flange_start():.1f} mm). "
            "Look at the draw-in of the edges and the wrinkles on the flange."
            f" {MATERIAL_DIFFERS}",
        )
    )

    with figure(out_dir / f"{NAME}-force.png", "punch travel (mm)", "punch force (N)") as ax:
        for kinematics, result in data.runs.items():
            stroke = DURATION / data.time_scaling.get(kinematics, 1.0)
            travel = [TRAVEL * float(smooth_step(f.time / stroke)) for f in result.frames]
            force = [f.tool_forces[1, 2] if len(f.tool_forces) > 1 else 0.0 for f in result.frames]
            ax.plot(travel, force, "o-", ms=3, label=kinematics)
    figures.append(
        Figure(
            f"{NAME}-force.png",
            "The punch force against its travel for the fibrous and the Mindlin shell. Both "
            "rise as the blank is drawn into the die; compare their levels and where they "
            f"start to climb. {MATERIAL_DIFFERS} {quasi_static_words(data.runs)}",
        )
    )
    for kinematics, result in data.runs.items():
        result.write(out_dir / f"{NAME}-{kinematics}.pvd")
    return figures
