"""The "plies" kinematics of ``fibreshell compare``: the case's fibrous stack as N shells of
thickness h / N in frictionless contact (elements.plies.PlyStack; docs/theory.md "The stack as
plies"), the discrete ground truth of the fibrous shell's directors.

Each ply is ``MindlinShell(ply_fabric)``, the fabric's laws shared out among the plies
(``Fabric.plies``), with the fibrous part's warp. The case's supports, imposed displacements
and gravity act on every ply's copy of their nodes; a point force or moment is shared out
equally among the copies. Profiles along the case's paths are those of the material lines:
the line through the points of the plies that started on one normal gives the director, its
tilt from the stack's normal and the thickness along it; the stack's mid-surface is the middle
of that extent.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from elements import FibrousShell, MindlinShell
from elements.plies import PlyStack
from femcore.results import write_vtu
from fibreshell.case import SOLVERS, Case
from fibreshell.outputs import MATERIAL_LINES, clean_run, run_folder_lock
from fibreshell.run import Run, case_held_directors, path_axis, solve_keeping, strict_json

__all__ = [
    "plies_profiles", "plies_solver", "ply_stack", "run_plies", "stack_model",
    "write_material_lines",
]  # fmt: skip


def _fibrous_part(case: Case) -> FibrousShell:
    fibrous = [p["element"] for p in case.parts if isinstance(p["element"], FibrousShell)]
    if len(fibrous) != 1 or len(case.parts) != 1:
        raise ValueError(
            f"{case.path}: the plies kinematics splits a case of one fibrous part (this one "
            f"has {len(case.parts)} parts, {len(fibrous)} fibrous)"
        )
    return fibrous[0]


def ply_stack(
    case: Case, count: int | None = None, penalty: float | None = None, static_law: str = "ramp"
) -> PlyStack:
    """The PlyStack of the case's fibrous part: ``count`` plies (default the fabric's
    ``ply_count``), each ``MindlinShell(ply_fabric)`` with the part's warp, their contact's
    normal law under Static ``static_law`` (``elements.plies.PlyStack``).

    Raises
    ------
    ValueError
        A case with a ``[layup]``, not one fibrous part, no count given for a fabric without
        a ply count, tools, an unknown ``static_law`` (``elements.ply_active_set.LAWS``).
    """
    if case.layup is not None:
        raise ValueError(
            f"{case.path}: the plies kinematics splits one fibrous part into plies; this case's "
            "[layup] is plies already: compare fibrous and mindlin on it"
        )
    element = _fibrous_part(case)
    fabric = element.fabric
    if count is None:
        count = fabric.ply_count
        if count is None:
            raise ValueError(
                f"{case.path}: the fabric states no ply count; give the number of plies (--plies N)"
            )
    if case.contacts:
        raise ValueError(
            f"{case.path}: the plies kinematics does not take rigid tools yet (which ply a tool "
            "touches depends on the side); compare fibrous and mindlin on this case"
        )
    warp = element.warp
    return PlyStack(
        case.mesh, fabric, count, element=lambda ply: MindlinShell(ply, warp=warp),
        penalty=penalty, static_law=static_law,
    )  # fmt: skip


def stack_model(case: Case, stack: PlyStack):
    """The case's supports and loads on the stack's model: every ply's copy of a node set
    held or moved alike; forces and moments shared out among the copies; gravity on all."""
    model = stack.model()
    share = 1.0 / stack.count
    for fix in case.fixes:
        model.fix(stack.nodes(fix["nodes"]), fix["dofs"])
    for item in case.displacements:
        model.displace(
            stack.nodes(item["nodes"]), **item["components"], amplitude=item["amplitude"]
        )
    for item in case.forces:
        vector = share * np.asarray(item["vector"], dtype=float)
        model.force(stack.nodes(item["nodes"]), vector, amplitude=item["amplitude"])
    for item in case.moments:
        vector = share * np.asarray(item["vector"], dtype=float)
        model.moment(stack.nodes(item["nodes"]), vector, amplitude=item["amplitude"])
    if case.gravity is not None:
        model.gravity(case.gravity["acceleration"], amplitude=case.gravity["amplitude"])
    return model


def plies_solver(case: Case, progress: bool | None = None):
    """The case's solver for its plies. A static solver runs without ``seek_stable`` unless
    the case sets it: the plies' tangent goes indefinite on the way (points step in and out of
    contact), and the search of its negative modes then takes most of the time and stalls
    (docs/theory.md §9.3a); it allows at least 150 Newton iterations per increment, as the
    last increments of sliding plies converge linearly."""
    options = dict(case.solver["options"])
    if case.solver["kind"] == "static":
        options.setdefault("seek_stable", False)
        options["max_iterations"] = max(int(options.get("max_iterations", 50)), 150)
    return SOLVERS[case.solver["kind"]](**options, progress=progress)


def plies_profiles(case: Case, stack: PlyStack, positions, directors) -> dict[str, Any]:
    """Per path of the case, the material lines' profile in the form of
    ``fibreshell.compare.kinematics_record``: s (reference arc length, mm), the stack's
    mid-surface x, y, z and horizontal coordinate, the director angle to the horizontal in
    the path's vertical plane (deg), its tilt from the stack's normal (deg), the thickness
    along it (mm; NaN at a node whose directors the case's fixes hold: ``case_held_directors``,
    a clamp, where every ply's director is imposed and the nodal normal's one-sided facets
    made the tilt read 26-28 deg), and the largest ply-to-ply gap (mm)."""
    lines = stack.material_lines(positions, directors)
    held = case_held_directors(case)
    out = {}
    for name in case.paths:
        nodes, s, along = path_axis(case, name)
        mid = lines.midpoint[nodes]
        d = lines.direction[nodes]
        tilt = np.degrees(lines.angle[nodes])
        tilt[np.isin(nodes, held)] = np.nan
        out[name] = {
            "s": s,
            "x": mid[:, 0],
            "y": mid[:, 1],
            "z": mid[:, 2],
            "horizontal": mid @ along,
            "director_angle_deg": np.degrees(np.arctan2(d[:, 2], d @ along)),
            "director_tilt_deg": tilt,
            "thickness": lines.thickness[nodes],
            "gap_max_mm": lines.gap[nodes],
        }
    return out


def run_plies(case: Case, out: Path, count: int | None = None, progress: bool | None = None) -> Run:
    """Run the case as its stack of plies into ``out`` (result.pvd on the plies' mesh,
    material-lines.vtu on the case's mesh: ``write_material_lines``, summary.json) with the
    case's solver, holding ``out`` (fibreshell.folder_lock) while it writes there.

    Returns
    -------
    Run
        With the material lines' ``profiles`` along the case's paths and, in the summary, the
        mean displacement of each history set (of the stack's mid-surface), the reaction sums
        over every ply's copy of each set, and "plies": the count, the ply thickness, the
        largest gap and overlap between plies (mm) and the contact penalty.
    """
    out.mkdir(parents=True, exist_ok=True)
    with run_folder_lock(out, f"the plies' run of {str(case.path)!r}"):
        clean_run(out, None, extra=(MATERIAL_LINES,))  # an earlier run's frames, by their names
        stack = ply_stack(case, count)
        model = stack_model(case, stack)
        result, error, wall = solve_keeping(plies_solver(case, progress), model)
        result.write(out / "result.pvd")
        final = result.frames[-1]
        lines = stack.material_lines(final.positions, final.directors)
        profiles = plies_profiles(case, stack, final.positions, final.directors)
        summary: dict[str, Any] = {
            "case": case.title,
            "kinematics": "plies",
            "solver": case.solver["kind"],
            "converged": bool(result.converged),
            "stopped": error or None,
            "steps": int(result.steps),
            "wall_time_s": wall,
            "reactions": {
                name: final.reactions[stack.nodes(name)].sum(axis=0)
                for name in case.history.get("reactions", [])
            },
            "mean_displacements": {
                name: (lines.midpoint[n] - case.mesh.points[n]).mean(axis=0)
                for name in case.history.get("displacements", [])
                for n in [case.mesh.nodes(name)]
            },
            "plies": {
                "count": stack.count,
                "ply_thickness_mm": stack.ply_thickness,
                "element": "MindlinShell(fabric.plies(N)), the fabric's laws shared out",
                "contact": "frictionless penalty between neighbouring plies' faces",
                "largest_gap_mm": float(np.max(lines.gap)),
                "largest_overlap_mm": float(max(0.0, -np.min(lines.gap))),
            },
            "paths": profiles,
        }
        (out / "summary.json").write_text(strict_json(summary))
        write_material_lines(case, stack, lines, out / MATERIAL_LINES)
        return Run("plies", result, error, wall, summary, profiles=profiles)


def write_material_lines(case: Case, stack: PlyStack, lines, path: Path) -> Path:
    """The stack's mid-surface (the middle of each material line) as a VTU on the case's
    mesh, with the fields the fibrous shell writes under the same names: ``director`` (unit,
    from ply 1 to ply N), ``director_tilt_deg`` (deg, from the stack's normal), ``thickness``
    (along the director, mm), and ``displacement`` (mm, from the reference mid-surface) for
    ParaView's Warp By Vector, plus ``ply_gap`` (the largest gap between plies, mm) and
    ``straightness`` (the largest distance of a ply from the line, mm)."""
    import meshio

    mesh = case.mesh
    write_vtu(
        meshio.Mesh(
            mesh.points,
            [("triangle", mesh.triangles)],
            point_data={
                "displacement": lines.midpoint - mesh.points,
                "director": lines.direction,
                "director_tilt_deg": np.degrees(lines.angle),
                "thickness": lines.thickness,
                "ply_gap": lines.gap,
                "straightness": lines.straightness,
            },
        ),
        path,
    )
    return path
