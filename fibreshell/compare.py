"""``fibreshell compare``: one case with the fibrous shell and with the calibrated Mindlin shell
(``ElasticShell.equivalent``) on the same mesh, supports, loads and solver, side by side."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from fibreshell.case import Case
from fibreshell.run import Run, profile, run_case, section_thickness, strict_json

__all__ = ["COLOURS", "compare_case", "path_figure", "view_3d"]

KINEMATICS = ("fibrous", "mindlin")
COLOURS = {"fibrous": "tab:blue", "mindlin": "tab:orange"}  # the same in every figure


def compare_case(
    case: Case, out: Path, progress: bool | None = None, shear_ratio: float = 0.5
) -> dict[str, Run]:
    """Run ``case`` with both kinematics into ``out/fibrous`` and ``out/mindlin`` and write
    ``out/comparison.json`` (both summaries and, per history set and path, the differences)
    ``out/view-3d.png`` (both deformed shells at true scale, the directors drawn across the
    thickness along the paths) and one figure per path (``out/path-<name>.png``: the side
    elevation with the drawn through-thickness lines, the director angle and the thickness
    along the director).

    Raises
    ------
    ValueError
        A case without a fibrous part: there is nothing to calibrate the Mindlin shell on.
    """
    if not case.has_fibrous:
        raise ValueError(
            f'{case.path}: compare needs a fibrous part (element = "fibrous"): the Mindlin '
            "shell is calibrated on its fabric"
        )
    out.mkdir(parents=True, exist_ok=True)
    runs = {
        kinematics: run_case(case, out / kinematics, kinematics, progress, shear_ratio)
        for kinematics in KINEMATICS
    }
    comparison: dict = {
        "case": case.title,
        "mindlin_calibration": {
            "rule": "E = 12 B / h^3 per direction, nu12 = 0, G12 = K / h, G13 = G23 = "
            "shear_ratio x E (materials.ElasticShell.equivalent)",
            "shear_ratio": shear_ratio,
        },
        "runs": {kinematics: run.summary for kinematics, run in runs.items()},
        "difference_mindlin_minus_fibrous": {
            "mean_displacements": {
                name: np.asarray(runs["mindlin"].summary["mean_displacements"][name])
                - np.asarray(runs["fibrous"].summary["mean_displacements"][name])
                for name in case.history.get("displacements", [])
            },
            "reactions": {
                name: np.asarray(runs["mindlin"].summary["reactions"][name])
                - np.asarray(runs["fibrous"].summary["reactions"][name])
                for name in case.history.get("reactions", [])
            },
        },
        "figures": [],
    }
    comparison["figures"].append(view_3d(case, runs, out).name)
    for name in case.paths:
        comparison["figures"].append(path_figure(case, runs, name, out).name)
    (out / "comparison.json").write_text(strict_json(comparison))
    return runs


def path_figure(case: Case, runs: dict[str, Run], name: str, out: Path) -> Path:
    """The figure of path ``name``: (a) side elevation, the mid-surface of each kinematics
    and its through-thickness lines (the directors drawn across the thickness along them, at
    true scale); (b) director angle to the horizontal; (c) thickness along the director."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    h = section_thickness(case)
    figure, axes = plt.subplots(1, 3, figsize=(15, 4.2), constrained_layout=True)
    for kinematics, run in runs.items():
        line = profile(case, run.result, name, h)
        colour = COLOURS[kinematics]
        horizontal, d = line["horizontal"], line["directors"]
        axes[0].plot(horizontal, line["z"], color=colour, label=kinematics)
        for u, z, dh, dz, t in zip(
            horizontal, line["z"], line["director_horizontal"], d[:, 2], line["thickness"]
        ):
            axes[0].plot(
                [u - 0.5 * t * dh, u + 0.5 * t * dh], [z - 0.5 * t * dz, z + 0.5 * t * dz],
                color=colour, linewidth=0.8,
            )  # fmt: skip
        axes[1].plot(line["s"], line["director_angle_deg"], color=colour, label=kinematics)
        axes[2].plot(line["s"], line["thickness"], color=colour, label=kinematics)
    axes[0].set_aspect("equal", adjustable="datalim")
    axes[0].set(xlabel="horizontal distance along the path (mm)", ylabel="z (mm)",
                title=f"(a) side elevation of path '{name}', true scale")  # fmt: skip
    axes[1].set(xlabel="s, reference arc length (mm)", ylabel="degrees",
                title="(b) director angle to the horizontal")  # fmt: skip
    axes[2].set(xlabel="s, reference arc length (mm)", ylabel="mm",
                title="(c) thickness along the director")  # fmt: skip
    for axis in axes:
        axis.grid(True, alpha=0.3)
        axis.legend()
    figure.suptitle(f"{case.title}: fibrous shell and calibrated Mindlin shell")
    path = out / f"path-{name}.png"
    figure.savefig(path, dpi=110)
    plt.close(figure)
    return path


def view_3d(case: Case, runs: dict[str, Run], out: Path) -> Path:
    """Both deformed shells side by side at true scale (equal axes), the directors drawn
    across the thickness at the nodes of the paths."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import MaxNLocator

    h = section_thickness(case)
    triangles = case.mesh.triangles
    figure = plt.figure(figsize=(14, 5.5), constrained_layout=True)
    everything = np.vstack([run.result.positions for run in runs.values()])
    low, high = everything.min(axis=0) - h, everything.max(axis=0) + h
    for i, (kinematics, run) in enumerate(runs.items()):
        axis = figure.add_subplot(1, len(runs), i + 1, projection="3d")
        x = run.result.positions
        if len(triangles):
            axis.plot_trisurf(
                x[:, 0], x[:, 1], x[:, 2], triangles=triangles, alpha=0.35,
                color=COLOURS[kinematics], linewidth=0.1, edgecolor="0.4",
            )  # fmt: skip
        thickness = run.result.thickness
        for nodes in case.paths.values():
            t = thickness[nodes] if thickness is not None else np.full(len(nodes), h)
            d = run.result.directors[nodes]
            for a, b in zip(x[nodes] - 0.5 * t[:, None] * d, x[nodes] + 0.5 * t[:, None] * d):
                axis.plot(*np.column_stack([a, b]), color="k", linewidth=1.2)
        for setter, a, b in zip((axis.set_xlim, axis.set_ylim, axis.set_zlim), low, high):
            setter(a, b)
        axis.set_box_aspect(np.maximum(high - low, 1e-9))
        axis.view_init(elev=22, azim=-130)
        for ticks in (axis.xaxis, axis.yaxis, axis.zaxis):  # readable ticks at true scale
            ticks.set_major_locator(MaxNLocator(nbins=4))
        axis.set(xlabel="x (mm)", ylabel="y (mm)", zlabel="z (mm)")
        axis.set_title(f"{kinematics}: deformed, true scale; directors along the paths")
    path = out / "view-3d.png"
    figure.savefig(path, dpi=100)
    plt.close(figure)
    return path
