"""Run one of Bai's specimens with both kinematics and collect what the paper's figures show.

A ``PaperCase`` names a specimen (validation.specimens), a fabric, the imposed displacement and
the resolution table. ``run_paper_case`` builds the fibrous and the Mindlin model on the same
mesh, solves each with ``Static`` (falling back to ``DynamicRelaxation`` when Newton cannot
follow the path), and returns the report's ``Outcome``: per element the solver, its iterations
and time, and along side 1 and side 2 the mid-surface, the director angle to the horizontal and
the thickness along the director; the checks of the invariants. ``render_paper_case`` then
draws the figures (side profiles like Bai Fig. 10/12/14/16, a 3D view with the director
segments drawn along the sides like the lines on the specimens) and writes the VTU and XDMF
files of both runs. ``PaperCase.case`` binds the two into the ``Case`` record of the module.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from functools import partial
from pathlib import Path
from typing import Any

import numpy as np

from femcore import Model
from materials import Fabric
from solvers import ConvergenceError, DynamicRelaxation, Static
from validation import specimens
from validation.checks import check
from validation.plots import plt
from validation.records import Case, Check, ElementRun, Outcome, SideProfile, SideSummary

__all__ = [
    "COLOURS",
    "INCREMENTS",
    "KINEMATICS",
    "LABELS",
    "PAPER",
    "PaperCase",
    "PaperRuns",
    "SHEAR_RATIO",
    "compute_paper_case",
    "corner_case",
    "invariant_checks",
    "key_numbers",
    "render_paper_case",
    "side_data",
    "side_figure",
    "solve",
    "view_3d",
]

PAPER = "Bai, Colmars, Naouar, Boisse, Composites Part A 139 (2020) 106135"
KINEMATICS = ("fibrous", "mindlin")
COLOURS = {"fibrous": "tab:blue", "mindlin": "tab:orange"}
LABELS = {"fibrous": "FibrousShell (Bai)", "mindlin": "MindlinShell (S3-like)"}
INCREMENTS = 10  # load increments of Static (each for gravity and the displacement), default
SHEAR_RATIO = 0.5  # Mindlin G13 / E (stated parameter), default


@dataclass(frozen=True)
class PaperCase:
    """One of the paper's tests: what to build and at which resolutions."""

    name: str
    title: str
    source: str  # the paper's section and figures, quoted in the checks
    make_specimen: Callable[[int], specimens.Specimen]
    fabric: Fabric
    displacement: tuple  # (ux, uy, uz) imposed on the loaded nodes, None = free
    cells: dict  # resolution -> cells argument of make_specimen
    parameters: dict = field(default_factory=dict)  # chosen values, reported
    increments: int = INCREMENTS
    shear_ratio: float = SHEAR_RATIO  # Mindlin G13 / E (stated parameter)

    def case(self, *, source: str, description: str, order: int) -> Case:
        """The ``Case`` record of the module (group "paper"): both kinematics.

        Parameters
        ----------
        source : str
            The reference as the report states it.
        description : str
            The module docstring.
        order : int
            Position among the paper cases.

        Returns
        -------
        Case
            compute = ``compute_paper_case``, render = ``render_paper_case`` on this spec.
        """
        return Case(
            name=self.name,
            title=self.title,
            source=source,
            description=description,
            group="paper",
            order=order,
            compute=partial(compute_paper_case, self),
            render=partial(render_paper_case, self),
        )


@dataclass(frozen=True)
class PaperRuns:
    """What the figures and files of a paper case are made of: the specimen and, per
    kinematics, the solver result and the profiles along the sides."""

    specimen: specimens.Specimen
    results: dict[str, Any]
    sides: dict[str, dict[str, SideProfile]]


def corner_case(
    name: str,
    title: str,
    source: str,
    fabric: Fabric,
    size: tuple[float, float],
    displacement: tuple,
    described: str,
    cells: dict,
    increments: int = INCREMENTS,
) -> PaperCase:
    """A §6 test on the free triangle of a ``size`` = (L, W) rectangle beyond its clamped
    diagonal (validation.specimens.corner), ``displacement`` imposed at the free corner and
    ``described`` in words for the report."""
    length, width = size
    return PaperCase(
        name=name,
        title=title,
        source=source,
        make_specimen=partial(specimens.corner, length, width),
        fabric=fabric,
        displacement=displacement,
        cells=cells,
        increments=increments,
        parameters={
            "length_mm": length,
            "width_mm": width,
            "corner displacement (assumed)": described,
        },
    )


def solve(model: Model, increments: int) -> tuple[Any, str, float]:
    """Static, or DynamicRelaxation when Static stops (a limit point, a bifurcation).

    Returns the result, the solver note for the report and the wall time (s)."""
    started = time.perf_counter()
    try:
        result = Static(
            increments=increments,
            max_iterations=100,
            max_cuts=12,
            step_loads_first=True,
            progress=False,
        ).solve(model)
        note = f"Static (gravity, then the displacement, {increments} increments each)"
        if result.info["indefinite_at"]:
            note += (
                f"; unstable equilibrium (det K < 0) at load factors {result.info['indefinite_at']}"
            )
        return result, note, time.perf_counter() - started
    except ConvergenceError as error:
        reached = getattr(error, "load_factor", 0.0)
        last = error.result.frames[-1]
    # Past a limit point: relax from the last equilibrium Static found (not from scratch, which
    # would retrace the whole path slowly and may settle on another branch). Static's factor
    # 1 + f (gravity in full, a fraction f of the displacement) is DR's load factor f.
    start = None
    fraction = 0.0
    if reached >= 1.0:
        fraction = min(reached - 1.0, 0.999)
        start = (last.positions, last.directors, fraction)
    steps = max(2, round(increments * (1.0 - fraction)))
    result = DynamicRelaxation(increments=steps, tol=1e-5, max_iterations=400_000).solve(
        model, start=start
    )
    note = (
        f"Static to {fraction:.3g} of the displacement (a limit point), then "
        f"DynamicRelaxation from that state ({steps} increments)"
    )
    return result, note, time.perf_counter() - started


def side_data(
    result: Any, specimen: specimens.Specimen, kinematics: str, thickness: float
) -> dict[str, SideProfile]:
    """Along each filmed side: s, mid-surface, director angle to the horizontal (deg) seen by a
    camera facing the side (the angle of the director's projection on the side's vertical
    plane, 90 = vertical) and the thickness along the director (mm)."""
    out = {}
    positions, directors = result.positions, result.directors
    nodal = result.thickness if kinematics == "fibrous" else None
    for name, (nodes, s) in specimen.sides.items():
        x0 = specimen.mesh.points[nodes]
        along = x0[-1] - x0[0]
        along = along / np.linalg.norm(along)  # horizontal direction from the clamp outwards
        d = directors[nodes]
        angle = np.degrees(np.arctan2(d[:, 2], d @ along))
        h = nodal[nodes] if nodal is not None else np.full(len(nodes), thickness)
        out[name] = SideProfile(
            s=s, midsurface=positions[nodes], director_angle_deg=angle, thickness=h
        )
    return out


def compute_paper_case(case: PaperCase, resolution: str) -> Outcome:
    """Solve both kinematics on the case's specimen at ``resolution``; the outcome's data
    (``PaperRuns``) holds the results that ``render_paper_case`` draws and writes."""
    specimen = case.make_specimen(case.cells[resolution])
    h = case.fabric.thickness
    elements, results = {}, {}
    for kinematics in KINEMATICS:
        model = specimens.build(
            specimen, kinematics, case.fabric, case.displacement, case.shear_ratio
        )
        result, note, wall = solve(model, case.increments)
        results[kinematics] = result
        fibre_strain = None
        if kinematics == "fibrous":
            fields = result.frames[-1].fields["triangle"]
            strain = np.maximum(
                np.abs(fields["warp_strain"]).max(axis=1), np.abs(fields["weft_strain"]).max(axis=1)
            )
            # The support acts on one node: the triangles around it carry the point load.
            at_support = np.isin(specimen.mesh.triangles, specimen.loaded).any(axis=1)
            fibre_strain = {
                "max_fibre_strain": float(strain.max()),
                "max_fibre_strain_away_from_support": float(strain[~at_support].max()),
                "max_shear_angle_deg": float(np.degrees(np.abs(fields["shear_angle"]).max())),
            }
        elements[kinematics] = ElementRun(
            converged=bool(result.converged),
            wall_time_s=wall,
            steps=int(result.steps),
            solver=note,
            sides=side_data(result, specimen, kinematics, h),
            fibre_strain=fibre_strain,
        )

    return Outcome(
        converged=all(e.converged for e in elements.values()),
        wall_time_s=sum(e.wall_time_s for e in elements.values()),
        steps=sum(e.steps for e in elements.values()),
        solver="; ".join(f"{k}: {e.solver}" for k, e in elements.items()),
        parameters={
            "triangles": len(specimen.mesh.triangles),
            "thickness_mm": h,
            "imposed_displacement_mm": str(tuple(case.displacement)),
            "Mindlin G13/E": case.shear_ratio,
            **case.parameters,
        },
        elements=elements,
        key_numbers=key_numbers(elements, h),
        checks=invariant_checks(case, elements, h),
        data=PaperRuns(
            specimen=specimen,
            results=results,
            sides={kinematics: e.sides for kinematics, e in elements.items()},
        ),
    )


def render_paper_case(case: PaperCase, runs: PaperRuns, out_dir: Path) -> list[str]:
    """Write the VTU and XDMF files of both runs and draw the side profiles and the 3D view;
    returns the figure names."""
    for kinematics, result in runs.results.items():
        for suffix in ("vtu", "xdmf"):
            result.write(out_dir / f"{case.name}-{kinematics}.{suffix}")
    return [
        side_figure(case, runs.sides, out_dir),
        view_3d(case, runs.specimen, runs.results, out_dir),
    ]


def key_numbers(elements: dict[str, ElementRun], h: float) -> dict[str, SideSummary]:
    """Per element and side: the director angle range, the largest mid-surface slope, the
    thickness range along the director (the numbers the report quotes)."""
    out = {}
    for kinematics, record in elements.items():
        for side in ("side_1", "side_2"):
            if side not in record.sides:
                continue
            data = record.sides[side]
            x = np.asarray(data.midsurface)
            run = np.linalg.norm(np.diff(x[:, :2], axis=0), axis=1)
            slope = np.degrees(np.arctan2(np.abs(np.diff(x[:, 2])), run)).max()
            angle = np.asarray(data.director_angle_deg)
            out[f"{kinematics} {side}"] = SideSummary(
                max_midsurface_slope_deg=float(slope),
                director_angle_min_deg=float(angle.min()),
                director_angle_max_deg=float(angle.max()),
                thickness_max_over_h=float(np.max(data.thickness) / h),
            )
    return out


def invariant_checks(case: PaperCase, elements: dict[str, ElementRun], h: float) -> list[Check]:
    """Bai's claims as checks: both runs converge, the fibres do not stretch, the thickness
    along the fibrous director is at least h, and where the surface is strongly bent the two
    kinematics' directors differ."""
    fibrous, mindlin = elements["fibrous"], elements["mindlin"]
    source = f"{PAPER}, {case.source}"
    checks = [
        check("fibrous run converged", 1.0, float(fibrous.converged), 0.0, source=source),
        check("Mindlin run converged", 1.0, float(mindlin.converged), 0.0, source=source),
        check(
            "fibrous: largest fibre strain away from the loaded node (quasi-inextensible, < 1 %)",
            0.0,
            fibrous.fibre_strain["max_fibre_strain_away_from_support"],
            0.01,
            relative=False,
            source="Bai §2: fibres quasi-inextensible",
        ),
    ]
    thinnest = min(
        np.min(fibrous.sides[s].thickness) for s in ("side_1", "side_2") if s in fibrous.sides
    )
    checks.append(
        replace(
            check(
                "fibrous: thinnest thickness along the director / h (>= 1: Eq. 10)",
                1.0,
                thinnest / h,
                1e-9,
                relative=False,
                source="Bai Eq. 10: h_m = h / (V . n) >= h",
            ),
            passed=bool(thinnest / h >= 1.0 - 1e-9),
        )
    )
    # Where the mid-surface is strongly bent (slope > 20 deg) the two kinematics must differ:
    # the Mindlin director follows the normal, the fibrous one does not (Bai §6.1.1, Fig. 10).
    gaps = []
    for side in ("side_1", "side_2"):
        if side not in fibrous.sides:
            continue
        x = np.asarray(mindlin.sides[side].midsurface)
        run = np.linalg.norm(np.gradient(x[:, :2], axis=0), axis=1)
        slope = np.degrees(np.arctan2(np.abs(np.gradient(x[:, 2])), run))
        bent = slope > 20.0
        if bent.any():
            gap = np.abs(
                np.asarray(fibrous.sides[side].director_angle_deg)
                - np.asarray(mindlin.sides[side].director_angle_deg)
            )
            gaps.append(float(gap[bent].max()))
    if gaps:
        checks.append(
            replace(
                check(
                    "fibrous vs Mindlin director angle where the slope > 20 deg (deg, > 10)",
                    10.0,
                    max(gaps),
                    np.inf,
                    relative=False,
                    source="Bai §6.1.1: directors stay almost parallel, unlike standard shells",
                ),
                passed=bool(max(gaps) > 10.0),
            )
        )
    return checks


def side_figure(case: PaperCase, profiles: dict[str, dict[str, SideProfile]], out_dir: Path) -> str:
    """Bai Fig. 10-style panels: rows = sides, columns = mid-surface, director angle,
    thickness along the director; both kinematics on the same axes. ``profiles`` is
    kinematics -> side -> profile; returns the file name."""
    sides = [s for s in ("side_1", "side_2") if s in profiles["fibrous"]]
    fig, axes = plt.subplots(
        len(sides), 3, figsize=(12, 3.4 * len(sides)), squeeze=False, constrained_layout=True
    )
    for row, side in enumerate(sides):
        for kinematics in KINEMATICS:
            data = profiles[kinematics][side]
            s = np.asarray(data.s)
            x = np.asarray(data.midsurface)
            colour, label = COLOURS[kinematics], LABELS[kinematics]
            horizontal = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(x[:, :2], axis=0), axis=1))]
            axes[row, 0].plot(horizontal, x[:, 2], "-o", ms=2.5, color=colour, label=label)
            axes[row, 1].plot(s, data.director_angle_deg, "-o", ms=2.5, color=colour)
            axes[row, 2].plot(s, data.thickness, "-o", ms=2.5, color=colour)
        name = side.replace("_", " ")
        axes[row, 0].set(
            xlabel=f"horizontal distance from the clamp along {name} (mm)",
            ylabel="mid-surface z (mm)",
            title=f"({'ad'[row]}) mid-surface, {name}",
        )
        axes[row, 0].set_aspect("equal", adjustable="datalim")
        axes[row, 1].set(
            xlabel=f"s along {name} (mm)",
            ylabel="director angle to horizontal (deg)",
            title=f"({'be'[row]}) material director, {name}",
        )
        axes[row, 2].set(
            xlabel=f"s along {name} (mm)",
            ylabel="thickness along director (mm)",
            title=f"({'cf'[row]}) thickness, {name}",
        )
        for ax in axes[row]:
            ax.grid(True, alpha=0.3)
    axes[0, 0].legend(fontsize="small")
    fig.suptitle(f"{case.name}: {case.title}")
    name = f"{case.name}-sides.png"
    fig.savefig(out_dir / name, dpi=100)
    plt.close(fig)
    return name


def view_3d(
    case: PaperCase, specimen: specimens.Specimen, results: dict[str, Any], out_dir: Path
) -> str:
    """Deformed mid-surface with the through-thickness director segments drawn along the
    sides (the lines drawn on the specimens' sides), fibrous and Mindlin side by side;
    returns the file name."""
    fig = plt.figure(figsize=(12, 5.2), constrained_layout=True)
    h = case.fabric.thickness
    for i, kinematics in enumerate(KINEMATICS):
        ax = fig.add_subplot(1, 2, i + 1, projection="3d")
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
        thickness = result.thickness if kinematics == "fibrous" else None
        for nodes, _ in specimen.sides.values():
            half = 0.5 * (thickness[nodes] if thickness is not None else np.full(len(nodes), h))
            d = result.directors[nodes]
            bottom = x[nodes] - half[:, None] * d
            top = x[nodes] + half[:, None] * d
            for a, b in zip(bottom, top):
                ax.plot(*np.column_stack([a, b]), color="k", lw=1.4)
        # True proportions (equal scales on the three axes), the free corner in front.
        low, high = x.min(axis=0) - h, x.max(axis=0) + h
        for setter, a, b in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), low, high):
            setter(a, b)
        ax.set_box_aspect(high - low)
        ax.view_init(elev=22, azim=-140)
        ax.set(xlabel="x (mm)", ylabel="y (mm)", zlabel="z (mm)")
        ax.set_title(f"{LABELS[kinematics]}: directors along the sides")
    name = f"{case.name}-3d.png"
    fig.savefig(out_dir / name, dpi=100)
    plt.close(fig)
    return name
