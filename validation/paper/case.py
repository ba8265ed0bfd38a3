"""A paper case: its specification, its three solves and what it writes.

A ``PaperCase`` names a specimen (validation.specimens), a fabric, the imposed displacement,
the resolution table and the Mindlin shell's calibration (fibreshell.calibration; "laws", the
fabric's own laws, by default). ``compute_paper_case`` builds three models on the same mesh
(``validation.paper.kinematics.KINEMATICS``), solves each with ``solve`` (``Static`` along the
arc length of the path, load steps past a limit point), measures the sides
(validation.paper.profiles), checks Bai's claims (validation.paper.invariants) and writes the
paragraph on what the numbers mean (validation.paper.discussion); it also solves the fibrous and
the Mindlin model on the two other meshes of the case's refinement sequence at that resolution
and gives the observed orders of the quantities the case reports (validation.paper.orders,
checked where the case states a tolerance); ``render_paper_case`` writes
the VTU and XDMF files of the three runs and draws the figures (validation.paper.figures).
``PaperCase.case`` binds the two into the ``Case`` record of the module.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import partial
from pathlib import Path
from typing import Any

import numpy as np

from femcore import Model
from fibreshell.calibration import Calibration
from materials import Fabric
from solvers import ConvergenceError, Static
from solvers.arc_length import DESIRED_ITERATIONS
from solvers.common import check_integer, check_non_negative
from validation import specimens
from validation.paper.discussion import discussion
from validation.paper.figures import laws_figure, side_elevation, side_figure, view_3d
from validation.paper.invariants import invariant_checks
from validation.paper.kinematics import (
    ARC_CHORDS,
    ELEMENT,
    FIBROUS_THICKNESS,
    INCREMENTS,
    KINEMATICS,
    LABELS,
    calibration_parameters,
)
from validation.paper.orders import (
    ORDER_KINEMATICS,
    mesh_size,
    observed_orders,
    order_checks,
    order_quantities,
)
from validation.paper.profiles import fibre_statistics, key_numbers, side_data
from validation.records import Case, ElementRun, Figure, ObservedOrder, Outcome, SideProfile

__all__ = [
    "PaperCase",
    "PaperRuns",
    "compute_paper_case",
    "corner_case",
    "refinement_orders",
    "render_paper_case",
    "solve",
]


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
    # How the Mindlin shell is made of the fabric (fibreshell.calibration): by default "laws",
    # MindlinShell(fabric) with the fabric's own laws, so that the comparison changes the
    # kinematics alone; stated in the parameters, the figures and the paragraph.
    calibration: Calibration = field(default_factory=Calibration)
    # Where the fabric's laws come from, in the laws figure's caption: Bai's table of this
    # material, or the assumed preset (Bai Fig. 7's moment-curvature data are G1151's).
    laws_source: str = ""
    # What the comparison of the fibrous and the Mindlin run shows on this case, in words
    # (measured; validation.paper.discussion.comparison adds it after the run's numbers).
    comparison_note: str = ""
    # The largest distance between the fibrous and the Mindlin mid-surface along the sides, as
    # a fraction of the largest displacement, that passes (chosen by measuring; every
    # resolution), or None: measured and reported, not checked (validation.paper.invariants).
    midsurface_tolerance: float | None = None
    # The sides along which the plies slip freely from the clamp, where the default fibrous
    # directors' tilt from the normal is compared with atan(theta) (``slip_errors``), and in
    # words why (or why not) for the report's paragraph; the largest |tilt - atan(theta)| that
    # passes per resolution (deg, chosen by measuring), or None: measured and reported, not
    # checked.
    slip_sides: tuple[str, ...] = ()
    slip_note: str = ""
    slip_tolerance_deg: dict[str, float] | None = None
    # The three meshes (cells arguments, coarsest first) on which the observed orders of the
    # reported quantities are measured at each resolution; the resolution's own mesh is one of
    # them (its runs are reused), the two others are solved with the fibrous and the Mindlin
    # kinematics only. A resolution left out shows no orders. The coarse resolution names none
    # in any paper case: its sequences (bai-5.1 6-8-12, the corners 5-10-20 and 4-6-8) were
    # pre-asymptotic and reported only, no check on them, and their eight extra runs cost
    # about a quarter of the five cases' coarse CPU (17.4 -> 13.1 s without them, case_cpu_s
    # summed, one job, a warm numba cache, load 5-8), in the test suite's background report.
    order_cells: dict[str, tuple[int, int, int]] = field(default_factory=dict)
    # Per resolution and quantity ("mindlin deflection", "fibrous thickness": orders.order_kind),
    # the largest |Richardson value - finest value| / |finest value| that passes (with a
    # positive order), chosen by measuring where the order is meaningful; a resolution or a
    # quantity left out: its orders are reported, not checked.
    order_tolerance: dict[str, dict[str, float]] | None = None
    # The arc-length increments of the two other meshes' runs (None: ``increments``): they
    # give their last equilibrium alone, which another path whose increments converge
    # reaches too, within Newton's tolerance (measured per case where it is set:
    # benchmarks/paper_refinement.py --turns).
    order_increments: int | None = None
    # The Newton iterations the arc length's step rule aims each increment at (Static's
    # ``arc_iterations``), in every run of the case (measured per case where it is set).
    arc_iterations: int = DESIRED_ITERATIONS
    # The residual ratio at or below which an arc-length iteration steps with its increment's
    # last factorisation (Static's ``arc_chords``), in every run of the case; 0: never.
    arc_chords: float = ARC_CHORDS

    def __post_init__(self) -> None:
        check_integer(self.arc_iterations, f"{self.name}: arc_iterations")
        check_non_negative(self.arc_chords, f"{self.name}: arc_chords", "a residual ratio")
        if self.order_increments is not None and not (
            # numpy's integers are counts too (an arange of a sweep gives them)
            isinstance(self.order_increments, (int, np.integer))
            and not isinstance(self.order_increments, bool)
            and self.order_increments >= 1
        ):
            raise ValueError(
                f"{self.name}: order_increments must be a whole number >= 1 or None, got "
                f"{self.order_increments!r}"
            )
        for resolution, sequence in self.order_cells.items():
            if len(sequence) != 3 or self.cells[resolution] not in sequence:
                raise ValueError(
                    f"{self.name}: order_cells[{resolution!r}] must be three meshes, the "
                    f"resolution's own ({self.cells[resolution]}) among them, got {sequence}"
                )

    def model(self, specimen, kinematics: str) -> Model:
        """The model of ``kinematics`` (a key of ELEMENT) on ``specimen`` (``make_specimen``'s)
        with the case's fabric, displacement and calibration (validation/specimens.py)."""
        return specimens.build(
            specimen,
            ELEMENT[kinematics],
            self.fabric,
            self.displacement,
            self.calibration,
            thickness=FIBROUS_THICKNESS.get(kinematics, "nodal"),
        )

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
    grip: tuple[float, float] | None = None,
    order_cells: dict[str, tuple[int, int, int]] | None = None,
    order_tolerance: dict[str, dict[str, float]] | None = None,
    comparison_note: str = "",
    midsurface_tolerance: float | None = None,
    order_increments: int | None = None,
    laws_source: str = "",
) -> PaperCase:
    """A §6 test on the free triangle of a ``size`` = (L, W) rectangle beyond its clamped
    diagonal (validation.specimens.corner), ``displacement`` imposed at the free corner (the
    corner node; with ``grip`` = (a, b) (mm), the a x b patch at the corner a gripper holds,
    its directors held too) and ``described`` in words for the report; ``slip_sides``,
    ``slip_note``, ``slip_tolerance_deg``, ``order_cells``, ``order_tolerance``,
    ``comparison_note``, ``midsurface_tolerance``, ``order_increments`` and ``laws_source``
    as in ``PaperCase``."""
    length, width = size
    gripped = {} if grip is None else {"gripped patch (assumed)": "{:g} x {:g} mm".format(*grip)}
    return PaperCase(
        name=name,
        title=title,
        source=source,
        make_specimen=partial(specimens.corner, length, width, grip=grip),
        fabric=fabric,
        displacement=displacement,
        cells=cells,
        increments=increments,
        slip_sides=slip_sides,
        slip_note=slip_note,
        slip_tolerance_deg=slip_tolerance_deg,
        order_cells=order_cells or {},
        order_tolerance=order_tolerance,
        comparison_note=comparison_note,
        midsurface_tolerance=midsurface_tolerance,
        order_increments=order_increments,
        laws_source=laws_source,
        parameters={
            "length_mm": length,
            "width_mm": width,
            "corner displacement (assumed)": described,
            **gripped,
        },
    )


def solve(
    model: Model,
    increments: int,
    arc_iterations: int = DESIRED_ITERATIONS,
    arc_chords: float = ARC_CHORDS,
) -> tuple[Any, str, float]:
    """Static along the arc length of the path: gravity over load factors 0-1, then the
    displacement over 1-2, ``increments`` arc-length steps at most each (their lengths aimed
    at ``arc_iterations`` Newton iterations an increment; an iteration at a residual ratio up
    to ``arc_chords`` steps with the increment's last factorisation); at a limit point the run
    goes on with load steps that land on the stable branch beyond it (the snap a test machine
    shows).
    No other solver is tried: a run that stops is reported as such, with its last equilibrium.

    Returns the result, the solver note for the report (what ran, how many increments and
    Newton iterations, limit points, unstable states) and the wall time (s)."""
    started = time.perf_counter()
    solver = Static(
        increments=increments,
        path="arc_length",
        arc_iterations=arc_iterations,
        arc_chords=arc_chords,
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
        f"increments, {sum(info['iterations_per_increment'])} Newton iterations "
        f"({info['arc_chords']} of them chord steps, {info['evaluations']['tangent']} tangents), "
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


def compute_paper_case(case: PaperCase, resolution: str) -> Outcome:
    """Solve the three kinematics on the case's specimen at ``resolution``; the outcome's data
    (``PaperRuns``) holds the results that ``render_paper_case`` draws and writes."""
    specimen = case.make_specimen(case.cells[resolution])
    h = case.fabric.thickness
    elements: dict[str, ElementRun] = {}
    results: dict[str, Any] = {}
    for kinematics in KINEMATICS:
        model = case.model(specimen, kinematics)
        result, note, wall = solve(model, case.increments, case.arc_iterations, case.arc_chords)
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
    orders, refinement = refinement_orders(case, resolution, specimen, elements)
    checks.extend(order_checks(case, orders or [], resolution))
    solver = "; ".join(f"{k}: {e.solver}" for k, e in elements.items())
    if orders is not None:
        solver += (
            f"; observed orders: {len(refinement['runs'])} more runs ("
            f"{', '.join(refinement['runs'])}), {refinement['wall']:.1f} s"
        )
    return Outcome(
        converged=all(e.converged for e in elements.values()),
        wall_time_s=sum(e.wall_time_s for e in elements.values()) + refinement["wall"],
        steps=sum(e.steps for e in elements.values()) + refinement["steps"],
        solver=solver,
        parameters={
            "triangles": len(specimen.mesh.triangles),
            "thickness_mm": h,
            # (ux, uy, uz) as the reader reads it: "ux free, uy free, uz 40 mm"
            "imposed_displacement": ", ".join(
                f"{axis} free" if value is None else f"{axis} {value:g} mm"
                for axis, value in zip(("ux", "uy", "uz"), case.displacement)
            ),
            **calibration_parameters(case.calibration, case.fabric),
            **case.parameters,
        },
        elements=elements,
        key_numbers=key_numbers(elements, h),
        discussion=discussion(case, specimen, elements, h),
        orders=orders,
        checks=checks,
        data=PaperRuns(
            specimen=specimen,
            results=results,
            sides={kinematics: e.sides for kinematics, e in elements.items()},
        ),
    )


def refinement_orders(
    case: PaperCase,
    resolution: str,
    specimen: specimens.Specimen,
    elements: dict[str, ElementRun],
) -> tuple[list[ObservedOrder] | None, dict[str, Any]]:
    """The observed orders at ``resolution`` on the meshes of ``case.order_cells``: the runs
    of ``elements`` (on ``specimen``) for the resolution's own mesh, the fibrous and the Mindlin
    models solved here on the two others (``case.order_increments`` arc-length increments
    a phase, else ``case.increments``: their last equilibrium alone is read). Returns the
    records (None when the case gives no sequence at this resolution) and what the extra runs
    cost: their names ("fibrous n = 10"), wall time (s) and steps."""
    cost: dict[str, Any] = {"runs": [], "wall": 0.0, "steps": 0}
    sequence = case.order_cells.get(resolution)
    if sequence is None:
        return None, cost
    h = case.fabric.thickness
    measured: dict[str, list] = {kinematics: [] for kinematics in ORDER_KINEMATICS}
    for cells in sequence:
        if cells == case.cells[resolution]:
            for kinematics in ORDER_KINEMATICS:
                record = elements[kinematics]
                quantities = order_quantities(record.sides, kinematics, h)
                measured[kinematics].append(
                    (cells, mesh_size(specimen), quantities, record.converged)
                )
            continue
        other = case.make_specimen(cells)
        for kinematics in ORDER_KINEMATICS:
            model = case.model(other, kinematics)
            increments = case.increments if case.order_increments is None else case.order_increments
            result, _, wall = solve(model, increments, case.arc_iterations, case.arc_chords)
            sides = side_data(result, other, kinematics, h)
            quantities = order_quantities(sides, kinematics, h)
            measured[kinematics].append(
                (cells, mesh_size(other), quantities, bool(result.converged))
            )
            cost["runs"].append(f"{kinematics} n = {cells}")
            cost["wall"] += wall
            cost["steps"] += int(result.steps)
    return observed_orders(measured), cost


def render_paper_case(case: PaperCase, runs: PaperRuns, out_dir: Path) -> list[Figure]:
    """Write the VTU and XDMF files of the three runs and draw the side profiles, the side
    elevation, the 3D view and the laws; returns the figures with their captions."""
    for kinematics, result in runs.results.items():
        for suffix in ("vtu", "xdmf"):
            result.write(out_dir / f"{case.name}-{kinematics}.{suffix}")
    return [
        side_figure(case, runs.sides, out_dir),
        side_elevation(case, runs.sides, out_dir),
        view_3d(case, runs.specimen, runs.results, out_dir),
        laws_figure(case, runs, out_dir),
    ]
