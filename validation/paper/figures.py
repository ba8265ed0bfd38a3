"""The figures of a paper case.

``side_figure``: side profiles like Bai Figs. 10/12/14/16 (mid-surface, director angle,
thickness along the director); ``side_elevation``: the sides seen from the side at true scale,
as the paper photographs them; ``laws_figure``: the fabric's laws over the range the fibrous
run reached, which are the Mindlin shell's too with the "laws" calibration; ``view_3d``: the
deformed mid-surface with the director segments drawn along the sides like the lines on the
specimens. Each states the Mindlin shell's calibration in its title, writes a PNG into the
output folder and returns it as a ``Figure`` with its caption.
"""

from __future__ import annotations

import textwrap
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from matplotlib.ticker import MaxNLocator

from validation import specimens
from validation.paper.kinematics import (
    COLOURS,
    ELEMENT,
    KINEMATICS,
    LABELS,
    MARKERS,
    calibration_title,
)
from validation.plots import plt, save, segments
from validation.records import Figure, SideProfile

if TYPE_CHECKING:
    from validation.paper.case import PaperCase, PaperRuns

__all__ = ["laws_figure", "side_elevation", "side_figure", "view_3d"]


# The three kinematics in a caption, in the figures' colours.
IN_WORDS = (
    "the fibrous shell with nodal normals (blue), the fibrous shell with Bai's Eq. 15 (green) "
    "and the reference Mindlin shell (orange)"
)
# The characters of an 11-pt title per inch of figure, less a margin.
TITLE_CHARACTERS_PER_INCH = 11
# What to look at in every paper case: where the three sets of directors point.
DIRECTORS = (
    "the Mindlin directors follow the normal, the Eq. 15 ones stay vertical and the default "
    "fibrous ones lean in between as the plies slip"
)


def _title(lines: tuple[str, ...], width: float) -> str:
    """``lines`` wrapped to a figure ``width`` inches wide (11-pt text), one under another."""
    return "\n".join(textwrap.fill(line, int(TITLE_CHARACTERS_PER_INCH * width)) for line in lines)


def side_figure(
    case: PaperCase, profiles: dict[str, dict[str, SideProfile]], out_dir: Path
) -> Figure:
    """Bai Fig. 10-style panels: per side, the mid-surface, the director angle and the
    thickness along the director (a column per side, or one row for one side); the three
    kinematics on the same axes. ``profiles`` is kinematics -> side -> profile; returns the
    figure with its caption."""
    sides = [s for s in ("side_1", "side_2") if s in profiles["fibrous"]]
    # 9 in at 100 dpi (900 px): its 10-pt text reads as 9 pt on an 800-px screen (a row of
    # three per side was 1,300 px, 7 px there). axes[side] holds that side's three panels,
    # lettered (a)-(c), then (d)-(f).
    width = 9.0
    if len(sides) == 1:
        fig, axes = plt.subplots(1, 3, figsize=(width, 3.6), squeeze=False, layout="constrained")
    else:
        fig, grid = plt.subplots(
            3, len(sides), figsize=(width, 8.4), squeeze=False, layout="constrained"
        )
        axes = grid.T
    for row, side in enumerate(sides):
        for kinematics in KINEMATICS:
            data = profiles[kinematics][side]
            s = np.asarray(data.s)
            x = np.asarray(data.midsurface)
            style = {
                "color": COLOURS[kinematics],
                "marker": MARKERS[kinematics],
                "ms": 3,
                "lw": 1.2,
                "mfc": "none",
            }
            horizontal = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(x[:, :2], axis=0), axis=1))]
            axes[row, 0].plot(horizontal, x[:, 2], label=LABELS[kinematics], **style)
            axes[row, 1].plot(s, data.director_angle_deg, **style)
            axes[row, 2].plot(s, data.thickness, **style)
        name = side.replace("_", " ")
        axes[row, 0].set(
            xlabel="horizontal distance from the clamp (mm)",
            ylabel="mid-surface z (mm)",
            title=f"({'ad'[row]}) mid-surface, {name}",
        )
        axes[row, 0].set_aspect("equal", adjustable="datalim")
        axes[row, 1].set(
            xlabel=f"s along {name} (mm)",
            ylabel="director angle (deg)",
            title=f"({'be'[row]}) director angle to the horizontal, {name}",
        )
        axes[row, 2].set(
            xlabel=f"s along {name} (mm)",
            ylabel="thickness (mm)",
            title=f"({'cf'[row]}) thickness along the director, {name}",
        )
        for ax in axes[row]:
            ax.grid(True, alpha=0.3)
            # a third of the width each for one side: the titles on two lines
            ax.set_title(textwrap.fill(ax.get_title(), 30 if len(sides) == 1 else 50))
    # Under the panels, where it hides no curve.
    handles, labels = axes[0, 0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside lower center", ncols=3, fontsize=10)
    lines = (f"{case.name}: {case.title}", calibration_title(case.calibration, case.fabric))
    fig.suptitle(_title(lines, width), fontsize=11)
    name = f"{case.name}-sides.png"
    save(fig, out_dir / name, dpi=100)
    plt.close(fig)
    return Figure(
        name,
        f"Side profiles of {case.title} (Bai {case.source}): along each filmed side, the "
        f"mid-surface, the director angle to the horizontal and the thickness along the "
        f"director, for {IN_WORDS}. Look at the director angle: {DIRECTORS}, and the "
        "thickness along the fibrous directors grows where they lean.",
    )


def side_elevation(
    case: PaperCase, profiles: dict[str, dict[str, SideProfile]], out_dir: Path
) -> Figure:
    """The specimen seen from the side, as the paper photographs it (Bai Figs. 9, 11, 13, 15):
    per kinematics (rows) and filmed side (columns), the band between the bottom and top
    surfaces (mid-surface -/+ half the thickness along the director) and the lines drawn
    through the thickness at every node, along the directors; true scale. Returns the figure
    with its caption."""
    sides = [s for s in ("side_1", "side_2") if s in profiles["fibrous"]]
    # 9 in at 100 dpi (900 px): its 10-pt text reads as 9 pt on an 800-px screen. A column
    # per side, or for one side the three kinematics in a row: axes[row, column].
    width = 9.0
    if len(sides) == 1:
        fig, grid = plt.subplots(1, 3, figsize=(width, 3.0), squeeze=False, layout="constrained")
        axes = grid.T
    else:
        fig, axes = plt.subplots(
            len(KINEMATICS), len(sides), figsize=(width, 2.4 * len(KINEMATICS)),
            squeeze=False, layout="constrained",
        )  # fmt: skip
    for row, kinematics in enumerate(KINEMATICS):
        for column, side in enumerate(sides):
            data = profiles[kinematics][side]
            x = np.asarray(data.midsurface)
            u = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(x[:, :2], axis=0), axis=1))]
            angle = np.radians(np.asarray(data.director_angle_deg))
            half = 0.5 * np.asarray(data.thickness)
            du, dz = half * np.cos(angle), half * np.sin(angle)
            bottom, top = (u - du, x[:, 2] - dz), (u + du, x[:, 2] + dz)
            band = np.column_stack([np.r_[bottom[0], top[0][::-1]], np.r_[bottom[1], top[1][::-1]]])
            axis = axes[row, column]
            axis.fill(band[:, 0], band[:, 1], color=COLOURS[kinematics], alpha=0.25, lw=0)
            axis.plot(*bottom, color=COLOURS[kinematics], lw=0.8)
            axis.plot(*top, color=COLOURS[kinematics], lw=0.8)
            through = segments(np.column_stack(bottom), np.column_stack(top))
            axis.plot(through[:, 0], through[:, 1], color="k", lw=0.9)
            axis.set_aspect("equal", adjustable="datalim")
            axis.grid(True, alpha=0.3)
            title = f"{LABELS[kinematics]}, {side.replace('_', ' ')}"
            axis.set_title(textwrap.fill(title, 38 * len(sides)), fontsize=10)
            axis.set(xlabel="horizontal distance from the clamp (mm)", ylabel="z (mm)")
    lines = (
        f"{case.name}: the sides seen from the side, true scale",
        calibration_title(case.calibration, case.fabric),
    )
    fig.suptitle(_title(lines, width), fontsize=11)
    name = f"{case.name}-side-elevation.png"
    # The tight box keeps the wrapped titles whole.
    save(fig, out_dir / name, dpi=100, bbox_inches="tight", pad_inches=0.1)
    plt.close(fig)
    return Figure(
        name,
        f"The sides of {case.name} seen from the side at true scale, as the paper photographs "
        f"its specimens: a panel per kinematics and side ({IN_WORDS}), the band between the "
        "bottom and top surfaces with a black line through the thickness at every node along "
        "its director. Compare the black lines with the lines drawn on the specimens: square "
        "to the surface in the Mindlin panels, leaning in the fibrous ones.",
    )


def laws_figure(case: PaperCase, runs: PaperRuns, out_dir: Path) -> Figure:
    """The fabric's laws (their source: ``case.laws_source``) from 0 over the range the fibrous run
    reached (they are odd, or zero in compression), warp and weft. With the "laws"
    calibration they are the Mindlin section's laws as well (MindlinShell(fabric)), and the
    title says so; a calibration that changes the bending law draws the Mindlin one dashed
    (the "fit" scale, or the "initial-slope" line E h^3 / 12 = B0 at every curvature).
    Returns the figure with its caption."""
    fabric = case.fabric
    rule = case.calibration
    fields = runs.results["fibrous"].frames[-1].fields.get("triangle", {})

    def reach(names: tuple[str, ...], floor: float, to_law: float) -> float:
        values = [np.abs(np.asarray(fields[n])) * to_law for n in names if n in fields]
        largest = max((float(np.nanmax(v)) for v in values), default=0.0)
        return max(1.2 * largest, floor)

    # Each panel: its fields, the factor from their unit to the law's argument (the shear
    # angle field is in degrees, the shear law takes radians), the axes drawn in the fields'.
    panels = (
        ("tension", fabric.tension, fabric.tension_weft, ("warp_strain", "weft_strain"), 1.0,
         1e-3, "log strain", "T (N/mm)"),
        ("in-plane shear", fabric.shear, None, ("shear_angle_deg",), np.pi / 180.0, 0.05,
         "shear angle (deg)", "M_s (N/mm)"),
        ("bending", fabric.bending, fabric.bending_weft,
         ("warp_curvature", "weft_curvature"), 1.0, 1e-3, "curvature (1/mm)", "M (N mm/mm)"),
    )  # fmt: skip
    both = "" if rule.name == "initial-slope" else " (both shells)"
    # 9 in at 110 dpi (990 px): its 10-pt text reads as 9 pt on an 800-px screen.
    fig, axes = plt.subplots(1, 3, figsize=(9.0, 3.9), layout="constrained")
    for axis, (title, warp, weft, names, to_law, floor, xlabel, ylabel) in zip(axes, panels):
        x = np.linspace(0.0, reach(names, floor, to_law), 401)  # the laws are odd (or tension-only)
        shown = x / to_law
        axis.plot(shown, warp.value(x), color="k", label=f"warp{both}")
        if weft is not None and weft is not warp:
            axis.plot(shown, weft.value(x), color="0.5", label=f"weft{both}")
        if title.startswith("bending") and rule.name == "initial-slope":
            initial = float(warp.slope(np.array(0.0)))
            axis.plot(shown, initial * x, ls="--", color=COLOURS["mindlin"],
                      label="Mindlin, warp: E h^3/12 = B0")  # fmt: skip
        elif title.startswith("bending") and rule.bending_scale != 1.0:
            scaled = rule.section_fabric(fabric).bending
            axis.plot(shown, scaled.value(x), ls="--", color=COLOURS["mindlin"],
                      label=f"Mindlin, warp x {rule.bending_scale:.3g}")  # fmt: skip
        axis.set(xlabel=xlabel, ylabel=ylabel)
        # Padded: the y axis's scale (e.g. "1e-2") sits at the panel's top left, under the title.
        axis.set_title(title, pad=14)
        axis.ticklabel_format(axis="both", style="sci", scilimits=(-2, 3))
        axis.locator_params(axis="x", nbins=5)
        axis.grid(True, alpha=0.3)
        axis.legend(fontsize=9)
    shared = (
        "the Mindlin section's own laws too"
        if rule.name != "initial-slope"
        else "the Mindlin section is elastic"
    )
    lines = (
        f"{case.name}: the fabric's laws over the range the fibrous run reached ({shared})",
        calibration_title(rule, fabric),
    )
    fig.suptitle(_title(lines, 9.0), fontsize=11)
    name = f"{case.name}-laws.png"
    save(fig, out_dir / name, dpi=110)
    plt.close(fig)
    mindlin = (
        "With the 'laws' calibration the Mindlin section uses these same laws, so that the "
        "runs differ by their kinematics alone."
        if rule.name == "laws"
        else f"The Mindlin section (calibration '{rule.name}') draws its bending dashed where "
        "it differs from the fabric's."
    )
    source = f" The laws' source: {case.laws_source}." if case.laws_source else ""
    return Figure(
        name,
        f"The fabric's laws of {case.name} over the range its fibrous run reached: fibre "
        f"tension, in-plane shear and bending, warp and weft.{source} {mindlin}",
    )


# The 3D view (elevation, azimuth; deg): from the free corner's side, the sides sloping away
# (a corner sagging below its clamp, a cantilever's fall).
VIEW = (22.0, -140.0)
# A corner lifted above its clamp (bai-6.1.1, 6.2.1) rises towards that viewer at about the
# view's elevation, so its surface showed as a sliver, its 40-mm lift hidden and its director
# segments all looking vertical. Seen from beyond side 1 (y = 0), the far end of its clamp on
# the right, its rise along side 1 is in profile and the directors' lean along it shows.
LIFTED_VIEW = (20.0, -55.0)
# The axes box enlarged in its panel (matplotlib draws it at 0.8 of it, ticks outside).
ZOOM = 1.2


def _lifted(specimen: specimens.Specimen, results: dict[str, Any]) -> bool:
    """Whether ``specimen`` is a corner (two filmed sides) whose loaded nodes end above its
    clamp by more than a tenth of its plan size in any run of ``results`` (not a sag)."""
    if "side_2" not in specimen.sides or not len(specimen.loaded):
        return False
    plan = np.ptp(specimen.mesh.points[:, :2], axis=0).max()
    rises = [
        r.positions[specimen.loaded, 2].mean() - r.positions[specimen.clamp, 2].mean()
        for r in results.values()
    ]
    return bool(max(rises) > 0.1 * plan)


def view_3d(
    case: PaperCase, specimen: specimens.Specimen, results: dict[str, Any], out_dir: Path
) -> Figure:
    """Deformed mid-surface with the through-thickness director segments drawn along the
    sides (the lines drawn on the specimens' sides), the three kinematics side by side;
    returns the figure with its caption."""
    # Two rows of two, 9 in at 110 dpi (990 px): on an 800-px screen the 10-pt text still
    # reads as 9 pt (a row of three was 1,332 px, its text 8 px there). The fourth place
    # holds the title's calibration and the key.
    fig = plt.figure(figsize=(9.0, 8.0), layout="constrained")
    fig.get_layout_engine().set(h_pad=0.3)  # room for the upper panels' y labels
    h = case.fabric.thickness
    lifted = _lifted(specimen, results)
    elevation, azimuth = LIFTED_VIEW if lifted else VIEW
    for i, kinematics in enumerate(KINEMATICS):
        ax = fig.add_subplot(2, 2, i + 1, projection="3d")
        result = results[kinematics]
        x = result.positions
        ax.plot_trisurf(
            x[:, 0],
            x[:, 1],
            x[:, 2],
            triangles=specimen.mesh.triangles,
            color=COLOURS[kinematics],
            alpha=0.35,
            linewidth=0.1,
            edgecolor="0.4",
        )
        thickness = result.thickness if ELEMENT[kinematics] == "fibrous" else None
        for nodes, _ in specimen.sides.values():
            half = 0.5 * (thickness[nodes] if thickness is not None else np.full(len(nodes), h))
            d = result.directors[nodes]
            bottom = x[nodes] - half[:, None] * d
            top = x[nodes] + half[:, None] * d
            ax.plot(*segments(bottom, top).T, color="k", lw=1.4)
        # Equal scales on the three axes, the free corner in front; a shape whose height is
        # under a third of its plan size is drawn with z exaggerated to that, and says so.
        low, high = x.min(axis=0) - h, x.max(axis=0) + h
        for setter, a, b in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), low, high):
            setter(a, b)
        extent = high - low
        exaggeration = max(1.0, (extent[:2].max() / 3.0) / extent[2])
        ax.set_box_aspect((extent[0], extent[1], extent[2] * exaggeration), zoom=ZOOM)
        for axis in (ax.xaxis, ax.yaxis, ax.zaxis):  # few ticks on a short axis
            axis.set_major_locator(MaxNLocator(nbins=4))
        ax.view_init(elev=elevation, azim=azimuth)
        # The z label only in the left column: a 3D axes' z label sits outside its box, over
        # the panel to its left, where it hid behind it.
        ax.set(xlabel="x (mm)", ylabel="y (mm)", zlabel="z (mm)" if i % 2 == 0 else "")
        scale = "true scale" if exaggeration == 1.0 else f"z exaggerated x {exaggeration:.1f}"
        # Two short lines: a 3D axes' title is not made room for by the layout.
        ax.set_title(f"({'abc'[i]}) {LABELS[kinematics]}\n({scale})", fontsize=11)
    key = fig.add_subplot(2, 2, 4)
    key.axis("off")
    key.text(
        0.5, 0.5,
        "\n".join([
            *textwrap.wrap(calibration_title(case.calibration, case.fabric), 50),
            "",
            "black lines: through the thickness",
            "along the directors, on the sides",
            "axes in mm, z upward",
        ]),
        ha="center", va="center", fontsize=10, transform=key.transAxes,
    )  # fmt: skip
    fig.suptitle(f"{case.name}: directors along the sides", fontsize=12)
    name = f"{case.name}-3d.png"
    # The layout does not see a 3D axes' z label; the tight box keeps the left ones in view.
    save(fig, out_dir / name, dpi=110, bbox_inches="tight", pad_inches=0.15)
    plt.close(fig)
    return Figure(
        name,
        f"The deformed {case.name} in 3D: the mid-surface with the through-thickness segments "
        f"(black, at their length: the thickness along the director) along the filmed sides, for "
        f"{IN_WORDS}, in (a), (b) and (c). {_seen(specimen, lifted)} Look at the black segments: "
        f"{DIRECTORS}.",
    )


def _seen(specimen: specimens.Specimen, lifted: bool) -> str:
    """Where the 3D view of ``specimen`` looks from, in words (``LIFTED_VIEW`` or ``VIEW``)."""
    elevation, _ = LIFTED_VIEW if lifted else VIEW
    if not lifted:
        return f"Seen {elevation:g} deg from above, from the side of x = 0 and y = 0."
    side_1, _ = specimen.sides["side_1"]
    far, near = specimen.mesh.points[side_1[[0, -1]], :2]
    return (
        f"Seen {elevation:g} deg from above, from beyond side 1 (y = 0), so that the lift is in "
        f"profile: the lifted corner ({near[0]:g}, {near[1]:g}) at the left, its height read on "
        f"the z axis, the clamp's end ({far[0]:g}, {far[1]:g}) at the right; side 1's segments "
        "in front, side 2's (x = 0) running away at the back left."
    )
