"""Run one of Bai's specimens with three kinematics and collect what the paper's figures show.

A ``PaperCase`` names a specimen (validation.specimens), a fabric, the imposed displacement and
the resolution table. ``compute_paper_case`` builds three models on the same mesh (``KINEMATICS``:
the fibrous shell with the thickness along the director from the nodal normals, its default;
the fibrous shell with Bai's Eq. 15, each element's own normal; the Mindlin shell), solves each
with ``Static`` along the arc length of the path (load steps past a limit point), and
returns the report's ``Outcome``: per kinematics the solver, its iterations and time, and along
side 1 and side 2 the mid-surface, the director angle to the horizontal, the thickness along the
director, the mid-surface rotation from the clamp and the director's tilt from the normal; the
checks of the invariants; a paragraph on what the director angle and the thickness mean for each
kinematics, with the run's numbers. ``render_paper_case`` then draws the figures (side profiles
like Bai Fig. 10/12/14/16, a 3D view with the director segments drawn along the sides like the
lines on the specimens) and writes the VTU and XDMF files of the three runs.
``PaperCase.case`` binds the two into the ``Case`` record of the module.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from functools import partial
from pathlib import Path
from typing import Any, Literal

import numpy as np
from matplotlib.ticker import MaxNLocator

from femcore import Model
from femcore.topology import nodal_normals
from materials import Fabric
from solvers import ConvergenceError, Static
from validation import specimens
from validation.checks import check
from validation.plots import plt
from validation.records import Case, Check, ElementRun, Outcome, SideProfile, SideSummary

__all__ = [
    "CHECK_NAMES",
    "COLOURS",
    "ELEMENT",
    "EQ15_TOLERANCE_DEG",
    "FIBROUS_THICKNESS",
    "INCREMENTS",
    "KINEMATICS",
    "LABELS",
    "MARKERS",
    "PAPER",
    "PaperCase",
    "PaperRuns",
    "SHEAR_RATIO",
    "Kinematics",
    "compute_paper_case",
    "corner_case",
    "discussion",
    "fibre_statistics",
    "invariant_checks",
    "key_numbers",
    "render_paper_case",
    "side_data",
    "side_figure",
    "slip_checks",
    "slip_errors",
    "solve",
    "view_3d",
]

PAPER = "Bai, Colmars, Naouar, Boisse, Composites Part A 139 (2020) 106135"
# The three models of every paper case, by their key in results.json and in the file names:
# the fibrous shell with the thickness along the director h_m = h / (V . N) from the
# area-weighted nodal normal N (its default), the fibrous shell with Bai's Eq. 15 as published
# (each element's own normal) and the Mindlin shell.
Kinematics = Literal["fibrous", "fibrous_element", "mindlin"]
KINEMATICS: tuple[Kinematics, ...] = ("fibrous", "fibrous_element", "mindlin")
ELEMENT: dict[Kinematics, str] = {
    "fibrous": "fibrous",
    "fibrous_element": "fibrous",
    "mindlin": "mindlin",
}  # the kinematics argument of validation.specimens.build
FIBROUS_THICKNESS: dict[Kinematics, str] = {"fibrous": "nodal", "fibrous_element": "element"}
COLOURS: dict[Kinematics, str] = {
    "fibrous": "tab:blue",
    "fibrous_element": "tab:green",
    "mindlin": "tab:orange",
}
MARKERS: dict[Kinematics, str] = {"fibrous": "o", "fibrous_element": "s", "mindlin": "^"}
LABELS: dict[Kinematics, str] = {
    "fibrous": "FibrousShell, nodal h_m (default)",
    "fibrous_element": "FibrousShell, Bai Eq. 15",
    "mindlin": "MindlinShell (S3-like)",
}
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
    # The sides along which the plies slip freely from the clamp, where the default fibrous
    # directors' tilt from the normal is compared with atan(theta) (``slip_errors``), and in
    # words why (or why not) for the report's paragraph; the largest |tilt - atan(theta)| that
    # passes per resolution (deg, chosen by measuring), or None: measured and reported, not
    # checked.
    slip_sides: tuple[str, ...] = ()
    slip_note: str = ""
    slip_tolerance_deg: dict[str, float] | None = None

    def case(self, *, source: str, description: str, order: int) -> Case:
        """The ``Case`` record of the module (group "paper"): the three kinematics.

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
    slip_sides: tuple[str, ...] = (),
    slip_note: str = "",
    slip_tolerance_deg: dict[str, float] | None = None,
) -> PaperCase:
    """A §6 test on the free triangle of a ``size`` = (L, W) rectangle beyond its clamped
    diagonal (validation.specimens.corner), ``displacement`` imposed at the free corner and
    ``described`` in words for the report; ``slip_sides``, ``slip_note`` and
    ``slip_tolerance_deg`` as in ``PaperCase``."""
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
        slip_sides=slip_sides,
        slip_note=slip_note,
        slip_tolerance_deg=slip_tolerance_deg,
        parameters={
            "length_mm": length,
            "width_mm": width,
            "corner displacement (assumed)": described,
        },
    )


def solve(model: Model, increments: int) -> tuple[Any, str, float]:
    """Static along the arc length of the path: gravity over load factors 0-1, then the
    displacement over 1-2, ``increments`` arc-length steps at most each; at a limit point the
    run goes on with load steps that land on the stable branch beyond it (the snap a test
    machine shows). No other solver is tried: a run that stops is reported as such, with its
    last equilibrium.

    Returns the result, the solver note for the report (what ran, how many increments and
    Newton iterations, limit points, unstable states) and the wall time (s)."""
    started = time.perf_counter()
    solver = Static(
        increments=increments,
        path="arc_length",
        at_limit="jump",
        max_iterations=40,
        max_cuts=10,
        step_loads_first=True,
        progress=False,
    )
    try:
        result = solver.solve(model)
        stopped = ""
    except ConvergenceError as error:
        assert error.result is not None
        result = error.result
        stopped = f"; STOPPED at load factor {error.load_factor:.4g} of 2: {error}"
    info = result.info
    note = (
        f"Static, arc length (gravity, then the displacement): {len(result.frames) - 1} "
        f"increments, {sum(info['iterations_per_increment'])} Newton iterations, "
        f"{info['cuts']} cuts"
    )
    if info["jumps"]:
        listed = ", ".join(f"{value:.3g}" for value in info["jumps"])
        # How far out of its plane (z) the specimen was at the limit point and is at the end:
        # a snap may lead to a flatter state (an in-plane mode) as well as a deeper buckle.
        start = result.frames[0].positions[:, 2]
        at_limit = next(f for f in result.frames if f.load_factor >= info["jumps"][0] - 1e-12)
        deflection = [
            float(np.abs(frame.positions[:, 2] - start).max())
            for frame in (at_limit, result.frames[-1])
        ]
        note += (
            f"; limit point at load factor {listed} (largest deflection {deflection[0]:.3g} "
            f"mm), then load steps to the stable branch (largest deflection at the end "
            f"{deflection[1]:.3g} mm)"
        )
    if info["branch_switches"]:
        listed = ", ".join(f"{value:.3g}" for value in info["branch_switches"])
        note += f"; bifurcation followed along the buckling mode at {listed}"
    if info["indefinite_at"]:
        note += (
            f"; unstable equilibria (negative eigenvalues) at {len(info['indefinite_at'])} frames"
        )
    return result, note + stopped, time.perf_counter() - started


def side_data(
    result: Any, specimen: specimens.Specimen, kinematics: Kinematics, thickness: float
) -> dict[str, SideProfile]:
    """Along each filmed side, seen by a camera facing it (everything projected on the side's
    vertical plane): s, mid-surface, director angle to the horizontal (deg, 90 = vertical), the
    thickness along the director (mm), the mid-surface rotation theta from the clamp's
    (horizontal) orientation, i.e. the slope of the side profile (central differences; deg)
    and the director's tilt from the normal of the profile, 90 + theta - director angle (deg);
    also the director's angle to the nodal normal in three dimensions (deg)."""
    out = {}
    positions, directors = result.positions, result.directors
    nodal = result.thickness if ELEMENT[kinematics] == "fibrous" else None
    normals = nodal_normals(positions, specimen.mesh.triangles)
    normal_tilt = np.degrees(np.arccos(np.clip(np.sum(directors * normals, axis=1), -1.0, 1.0)))
    for name, (nodes, s) in specimen.sides.items():
        x0 = specimen.mesh.points[nodes]
        along = x0[-1] - x0[0]
        along = along / np.linalg.norm(along)  # horizontal direction from the clamp outwards
        d = directors[nodes]
        angle = np.degrees(np.arctan2(d[:, 2], d @ along))
        x = positions[nodes]
        rotation = np.degrees(np.arctan2(np.gradient(x[:, 2]), np.gradient(x @ along)))
        h = nodal[nodes] if nodal is not None else np.full(len(nodes), thickness)
        out[name] = SideProfile(
            s=s,
            midsurface=x,
            director_angle_deg=angle,
            thickness=h,
            rotation_deg=rotation,
            director_tilt_deg=90.0 + rotation - angle,
            normal_tilt_deg=normal_tilt[nodes],
        )
    return out


def fibre_statistics(result: Any, specimen: specimens.Specimen) -> dict[str, float]:
    """The fibrous run's largest fibre strain, also away from the loaded node, and its largest
    in-plane shear angle (deg)."""
    fields = result.frames[-1].fields["triangle"]
    strain = np.maximum(
        np.abs(fields["warp_strain"]).max(axis=1), np.abs(fields["weft_strain"]).max(axis=1)
    )
    # The support acts on one node: the triangles around it carry the point load.
    at_support = np.isin(specimen.mesh.triangles, specimen.loaded).any(axis=1)
    return {
        "max_fibre_strain": float(strain.max()),
        "max_fibre_strain_away_from_support": float(strain[~at_support].max()),
        "max_shear_angle_deg": float(np.degrees(np.abs(fields["shear_angle"]).max())),
    }


def compute_paper_case(case: PaperCase, resolution: str) -> Outcome:
    """Solve the three kinematics on the case's specimen at ``resolution``; the outcome's data
    (``PaperRuns``) holds the results that ``render_paper_case`` draws and writes."""
    specimen = case.make_specimen(case.cells[resolution])
    h = case.fabric.thickness
    elements: dict[str, ElementRun] = {}
    results: dict[str, Any] = {}
    for kinematics in KINEMATICS:
        model = specimens.build(
            specimen,
            ELEMENT[kinematics],
            case.fabric,
            case.displacement,
            case.shear_ratio,
            thickness=FIBROUS_THICKNESS.get(kinematics, "nodal"),
        )
        result, note, wall = solve(model, case.increments)
        results[kinematics] = result
        elements[kinematics] = ElementRun(
            label=LABELS[kinematics],
            converged=bool(result.converged),
            wall_time_s=wall,
            steps=int(result.steps),
            solver=note,
            sides=side_data(result, specimen, kinematics, h),
            fibre_strain=fibre_statistics(result, specimen)
            if ELEMENT[kinematics] == "fibrous"
            else None,
        )

    checks = invariant_checks(case, specimen, elements, h, resolution)
    return Outcome(
        converged=all(e.converged for e in elements.values()),
        wall_time_s=sum(e.wall_time_s for e in elements.values()),
        steps=sum(e.steps for e in elements.values()),
        solver="; ".join(f"{k}: {e.solver}" for k, e in elements.items()),
        parameters={
            "triangles": len(specimen.mesh.triangles),
            "thickness_mm": h,
            # (ux, uy, uz) as the reader reads it: "ux free, uy free, uz 40 mm"
            "imposed_displacement": ", ".join(
                f"{axis} free" if value is None else f"{axis} {value:g} mm"
                for axis, value in zip(("ux", "uy", "uz"), case.displacement)
            ),
            "Mindlin G13/E": case.shear_ratio,
            **case.parameters,
        },
        elements=elements,
        key_numbers=key_numbers(elements, h),
        discussion=discussion(case, specimen, elements, h),
        checks=checks,
        data=PaperRuns(
            specimen=specimen,
            results=results,
            sides={kinematics: e.sides for kinematics, e in elements.items()},
        ),
    )


def render_paper_case(case: PaperCase, runs: PaperRuns, out_dir: Path) -> list[str]:
    """Write the VTU and XDMF files of the three runs and draw the side profiles and the 3D
    view; returns the figure names."""
    for kinematics, result in runs.results.items():
        for suffix in ("vtu", "xdmf"):
            result.write(out_dir / f"{case.name}-{kinematics}.{suffix}")
    return [
        side_figure(case, runs.sides, out_dir),
        side_elevation(case, runs.sides, out_dir),
        view_3d(case, runs.specimen, runs.results, out_dir),
        laws_figure(case, runs, out_dir),
    ]


def key_numbers(elements: dict[str, ElementRun], h: float) -> dict[str, SideSummary]:
    """Per kinematics and side: the director angle range, the largest mid-surface slope, the
    thickness range along the director, the largest tilt of the director from the normal (the
    numbers the report quotes)."""
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
                director_tilt_max_deg=float(np.abs(data.director_tilt_deg).max()),
            )
    return out


# Names of the kinematics in the checks' names (the default fibrous run keeps the plain name).
CHECK_NAMES: dict[Kinematics, str] = {
    "fibrous": "fibrous",
    "fibrous_element": "fibrous Eq. 15",
    "mindlin": "Mindlin",
}
# Largest tilt of the Eq. 15 directors from the vertical (deg): they keep the clamp's
# orientation, measured 0.0 in every corner case and in the strip.
EQ15_TOLERANCE_DEG = 1.0


def slip_errors(
    case: PaperCase, specimen: specimens.Specimen, record: ElementRun
) -> dict[str, np.ndarray]:
    """Per side of ``case.slip_sides``: |tilt - atan(theta)| (deg) at the nodes of the side
    that are neither clamped nor loaded."""
    out = {}
    for side in case.slip_sides:
        nodes, _ = specimen.sides[side]
        free = ~np.isin(nodes, np.r_[specimen.clamp, specimen.loaded])
        data = record.sides[side]
        expected = np.degrees(np.arctan(np.radians(np.asarray(data.rotation_deg))))
        out[side] = np.abs(np.asarray(data.director_tilt_deg) - expected)[free]
    return out


def invariant_checks(
    case: PaperCase,
    specimen: specimens.Specimen,
    elements: dict[str, ElementRun],
    h: float,
    resolution: str,
) -> list[Check]:
    """Bai's claims as checks: the three runs converge; for both fibrous variants the fibres do
    not stretch, the thickness along the director is at least h, and where the surface is
    strongly bent their directors differ from the Mindlin ones; the default fibrous directors
    tilt by atan(theta) from the normal where the plies slip freely; the Eq. 15 directors keep
    the clamp's (vertical) orientation."""
    source = f"{PAPER}, {case.source}"
    checks = [
        check(
            f"{CHECK_NAMES[k]} run converged", 1.0, float(elements[k].converged), 0.0, source=source
        )
        for k in KINEMATICS
    ]
    mindlin = elements["mindlin"]
    for kinematics in ("fibrous", "fibrous_element"):
        record, name = elements[kinematics], CHECK_NAMES[kinematics]
        assert record.fibre_strain is not None
        checks.append(
            check(
                f"{name}: largest fibre strain away from the loaded node (quasi-inextensible, "
                "< 1 %)",
                0.0,
                record.fibre_strain["max_fibre_strain_away_from_support"],
                0.01,
                relative=False,
                source="Bai §2: fibres quasi-inextensible",
            )
        )
        thinnest = min(np.min(side.thickness) for side in record.sides.values())
        checks.append(
            replace(
                check(
                    f"{name}: thinnest thickness along the director / h (>= 1: Eq. 10)",
                    1.0,
                    thinnest / h,
                    1e-9,
                    relative=False,
                    source="Bai Eq. 10: h_m = h / (V . n) >= h",
                ),
                passed=bool(thinnest / h >= 1.0 - 1e-9),
            )
        )
        # Where the mid-surface is strongly bent (slope > 20 deg) the fibrous and the Mindlin
        # directors must differ: the Mindlin director follows the normal, the fibrous one does
        # not (Bai §6.1.1, Fig. 10).
        gaps = []
        for side, data in record.sides.items():
            x = np.asarray(mindlin.sides[side].midsurface)
            run = np.linalg.norm(np.gradient(x[:, :2], axis=0), axis=1)
            slope = np.degrees(np.arctan2(np.abs(np.gradient(x[:, 2])), run))
            bent = slope > 20.0
            if bent.any():
                gap = np.abs(
                    np.asarray(data.director_angle_deg)
                    - np.asarray(mindlin.sides[side].director_angle_deg)
                )
                gaps.append(float(gap[bent].max()))
        if gaps:
            checks.append(
                replace(
                    check(
                        f"{name} vs Mindlin director angle where the slope > 20 deg (deg, > 10)",
                        10.0,
                        max(gaps),
                        np.inf,
                        relative=False,
                        source="Bai §6.1.1: directors stay almost parallel, unlike standard shells",
                    ),
                    passed=bool(max(gaps) > 10.0),
                )
            )
    checks.extend(slip_checks(case, specimen, elements, resolution))
    eq15 = elements["fibrous_element"]
    turned = max(
        float(np.abs(np.asarray(d.director_angle_deg) - 90.0).max()) for d in eq15.sides.values()
    )
    checks.append(
        check(
            f"fibrous Eq. 15: largest director tilt from the vertical along the sides (deg, "
            f"< {EQ15_TOLERANCE_DEG:g}: the clamp's orientation kept)",
            0.0,
            turned,
            EQ15_TOLERANCE_DEG,
            relative=False,
            source="Bai Eq. 15: parallel directors are strain-free at any curvature",
        )
    )
    return checks


def slip_checks(
    case: PaperCase,
    specimen: specimens.Specimen,
    elements: dict[str, ElementRun],
    resolution: str,
) -> list[Check]:
    """Along each side of ``case.slip_sides``: the default fibrous directors' tilt from the
    normal against atan(theta), theta the mid-surface rotation from the clamp (both seen facing
    the side), away from the clamped and the loaded nodes; none without a tolerance."""
    checks: list[Check] = []
    if case.slip_tolerance_deg is None:
        return checks
    tolerance = case.slip_tolerance_deg[resolution]
    for side, error in slip_errors(case, specimen, elements["fibrous"]).items():
        largest = float(error.max())
        checks.append(
            check(
                f"fibrous: director tilt from the normal vs atan(theta) along "
                f"{side.replace('_', ' ')}, largest difference (deg, "
                f"< {tolerance:g})",
                0.0,
                largest,
                tolerance,
                relative=False,
                source="plies slipping freely from the clamp: tilt = atan(theta) "
                "(FibrousShell, thickness='nodal')",
            )
        )
    return checks


def _largest(values: list[np.ndarray]) -> float:
    return float(max(np.abs(v).max() for v in values))


def discussion(
    case: PaperCase, specimen: specimens.Specimen, elements: dict[str, ElementRun], h: float
) -> str:
    """What the director angle (b) and the thickness along the director (c) of the side figure
    mean for each kinematics, with the numbers of this run (one paragraph each), then the
    case's note on the atan(theta) check with the measured differences of both fibrous
    variants."""
    # Away from the clamped node, the first of each side, where the rotation is a one-sided
    # difference over the first element while the director is held.
    numbers = {}
    for kinematics, record in elements.items():
        sides = list(record.sides.values())
        numbers[kinematics] = {
            "rotation": _largest([np.asarray(s.rotation_deg)[1:] for s in sides]),
            "tilt": _largest([np.asarray(s.director_tilt_deg)[1:] for s in sides]),
            "normal_tilt": _largest([np.asarray(s.normal_tilt_deg)[1:] for s in sides]),
            "turned": _largest([np.asarray(s.director_angle_deg) - 90.0 for s in sides]),
            "thick": max(float(np.max(s.thickness)) for s in sides) / h,
        }
    m, f, e = numbers["mindlin"], numbers["fibrous"], numbers["fibrous_element"]
    atan = np.degrees(np.arctan(np.radians(f["rotation"])))
    paragraphs = [
        f"{LABELS['mindlin']}: the director is the rotated normal. It follows the normal up to "
        f"the transverse shear strain, so its angle in (b) is 90 deg plus the slope of the "
        f"profile (a); here it leaves the nodal normal by at most {m['normal_tilt']:.1f} deg "
        f"while the mid-surface turns by up to {m['rotation']:.0f} deg. The thickness along "
        f"it is h = {h:g} mm everywhere (c): a Mindlin section neither thickens nor slips.",
        f"{LABELS['fibrous']}: the director is the material line across the plies, and the "
        f"thickness along it h_m = h / (V . N) uses the nodal normal N. Where the plies slip "
        f"freely from the clamp, a stack whose mid-surface has turned by theta tilts its "
        f"directors from the normal by atan(theta), and the thickness along them is h / "
        f"cos(tilt) = h sqrt(1 + theta^2) >= h. Here the mid-surface turns by up to "
        f"{f['rotation']:.0f} deg (atan of it: {atan:.0f} deg), the directors tilt from the "
        f"normal by up to {f['tilt']:.0f} deg seen facing the side ({f['normal_tilt']:.0f} deg "
        f"in three dimensions) and so turn from the vertical by up to {f['turned']:.1f} deg, "
        f"and the thickness along them, h / cos of the tilt in three dimensions, reaches "
        f"{f['thick']:.3f} h.",
        f"{LABELS['fibrous_element']}: with each element's own normal in h_m = h / (V . n), "
        f"parallel directors are strain-free at any curvature, so the directors keep their "
        f"initial (vertical) orientation: in (b) they stay within {e['turned']:.2f} deg of 90 "
        f"deg, their tilt from the normal is the slope itself (up to {e['tilt']:.0f} deg seen "
        f"facing the side, {e['normal_tilt']:.0f} deg in three dimensions where the surface is "
        f"also bent across the side) and the thickness along them is h / cos(slope), h / (V . "
        f"n) in each element; its nodal mean reaches {e['thick']:.3f} h.",
    ]
    note = case.slip_note
    if case.slip_sides:
        measured = {
            kinematics: _largest(list(slip_errors(case, specimen, elements[kinematics]).values()))
            for kinematics in ("fibrous", "fibrous_element")
        }
        sides = " and ".join(side.replace("_", " ") for side in case.slip_sides)
        note += (
            f" Measured along {sides}, away from the clamped and the loaded nodes: the default "
            f"directors' tilt differs from atan(theta) by at most {measured['fibrous']:.1f} deg "
            f"({'checked' if case.slip_tolerance_deg is not None else 'not checked'}); the "
            f"Eq. 15 directors, whose tilt is theta itself, by up to "
            f"{measured['fibrous_element']:.1f} deg."
        )
    if note:
        paragraphs.append(note.strip())
    return "\n\n".join(paragraphs)


def side_figure(case: PaperCase, profiles: dict[str, dict[str, SideProfile]], out_dir: Path) -> str:
    """Bai Fig. 10-style panels: rows = sides, columns = mid-surface, director angle,
    thickness along the director; the three kinematics on the same axes. ``profiles`` is
    kinematics -> side -> profile; returns the file name."""
    sides = [s for s in ("side_1", "side_2") if s in profiles["fibrous"]]
    fig, axes = plt.subplots(
        len(sides), 3, figsize=(13, 3.6 * len(sides)), squeeze=False, constrained_layout=True
    )
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


def side_elevation(
    case: PaperCase, profiles: dict[str, dict[str, SideProfile]], out_dir: Path
) -> str:
    """The specimen seen from the side, as the paper photographs it (Bai Figs. 9, 11, 13, 15):
    per kinematics (rows) and filmed side (columns), the band between the bottom and top
    surfaces (mid-surface -/+ half the thickness along the director) and the lines drawn
    through the thickness at every node, along the directors; true scale. Returns the file
    name."""
    sides = [s for s in ("side_1", "side_2") if s in profiles["fibrous"]]
    fig, axes = plt.subplots(
        len(KINEMATICS), len(sides), figsize=(6.5 * len(sides), 2.6 * len(KINEMATICS)),
        squeeze=False, constrained_layout=True,
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
            for k in range(len(u)):
                axis.plot([bottom[0][k], top[0][k]], [bottom[1][k], top[1][k]], color="k", lw=0.9)
            axis.set_aspect("equal", adjustable="datalim")
            axis.grid(True, alpha=0.3)
            axis.set_title(f"{LABELS[kinematics]}, {side.replace('_', ' ')}", fontsize="medium")
            axis.set(xlabel="horizontal distance from the clamp (mm)", ylabel="z (mm)")
    fig.suptitle(
        f"{case.name}: the sides seen from the side, true scale (cf. the paper's photographs)"
    )
    name = f"{case.name}-side-elevation.png"
    fig.savefig(out_dir / name, dpi=100)
    plt.close(fig)
    return name


def laws_figure(case: PaperCase, runs: PaperRuns, out_dir: Path) -> str:
    """The fabric's laws (cf. Bai Fig. 7 for bending) from 0 over the range the fibrous run
    reached (they are odd, or zero in compression), warp and weft, with the Mindlin
    calibration's linear bending (E h^3 / 12 = the initial slope) dashed. Returns the file
    name."""
    fabric = case.fabric
    fields = runs.results["fibrous"].frames[-1].fields.get("triangle", {})

    def reach(names: tuple[str, ...], floor: float) -> float:
        values = [np.abs(np.asarray(fields[n])) for n in names if n in fields]
        largest = max((float(np.nanmax(v)) for v in values), default=0.0)
        return max(1.2 * largest, floor)

    panels = (
        ("tension", fabric.tension, fabric.tension_weft, ("warp_strain", "weft_strain"), 1e-3,
         "log strain", "T (N/mm)"),
        ("in-plane shear", fabric.shear, None, ("shear_angle",), 0.05, "shear angle (rad)",
         "M_s (N/mm)"),
        ("bending (cf. Bai Fig. 7)", fabric.bending, fabric.bending_weft,
         ("warp_curvature", "weft_curvature"), 1e-3, "curvature (1/mm)", "M (N mm/mm)"),
    )  # fmt: skip
    fig, axes = plt.subplots(1, 3, figsize=(14, 3.8), constrained_layout=True)
    for axis, (title, warp, weft, names, floor, xlabel, ylabel) in zip(axes, panels):
        x = np.linspace(0.0, reach(names, floor), 401)  # the laws are odd (or tension-only)
        axis.plot(x, warp.value(x), color="k", label="warp")
        if weft is not None and weft is not warp:
            axis.plot(x, weft.value(x), color="0.5", label="weft")
        if title.startswith("bending"):
            initial = float(warp.slope(np.array(0.0)))
            axis.plot(x, initial * x, ls="--", color=COLOURS["mindlin"],
                      label="Mindlin calibration E h^3/12")  # fmt: skip
        axis.set(title=title, xlabel=xlabel, ylabel=ylabel)
        axis.ticklabel_format(axis="both", style="sci", scilimits=(-2, 3))
        axis.locator_params(axis="x", nbins=5)
        axis.grid(True, alpha=0.3)
        axis.legend(fontsize="small")
    fig.suptitle(f"{case.name}: the fabric's laws over the range the fibrous run reached")
    name = f"{case.name}-laws.png"
    fig.savefig(out_dir / name, dpi=100)
    plt.close(fig)
    return name


def view_3d(
    case: PaperCase, specimen: specimens.Specimen, results: dict[str, Any], out_dir: Path
) -> str:
    """Deformed mid-surface with the through-thickness director segments drawn along the
    sides (the lines drawn on the specimens' sides), the three kinematics side by side;
    returns the file name."""
    fig = plt.figure(figsize=(16, 5.0), constrained_layout=True)
    h = case.fabric.thickness
    for i, kinematics in enumerate(KINEMATICS):
        ax = fig.add_subplot(1, len(KINEMATICS), i + 1, projection="3d")
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
            for a, b in zip(bottom, top):
                ax.plot(*np.column_stack([a, b]), color="k", lw=1.4)
        # Equal scales on the three axes, the free corner in front; a shape whose height is
        # under a third of its plan size is drawn with z exaggerated to that, and says so.
        low, high = x.min(axis=0) - h, x.max(axis=0) + h
        for setter, a, b in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), low, high):
            setter(a, b)
        extent = high - low
        exaggeration = max(1.0, (extent[:2].max() / 3.0) / extent[2])
        ax.set_box_aspect((extent[0], extent[1], extent[2] * exaggeration))
        for axis in (ax.xaxis, ax.yaxis, ax.zaxis):  # few ticks on a short axis
            axis.set_major_locator(MaxNLocator(nbins=4))
        ax.view_init(elev=22, azim=-140)
        ax.set(xlabel="x (mm)", ylabel="y (mm)", zlabel="z (mm)")
        scale = "true scale" if exaggeration == 1.0 else f"z exaggerated x {exaggeration:.1f}"
        ax.set_title(
            f"{LABELS[kinematics]}: directors along the sides ({scale})", fontsize="medium"
        )
    name = f"{case.name}-3d.png"
    fig.savefig(out_dir / name, dpi=100)
    plt.close(fig)
    return name
