"""Running a case and writing what a user opens: the ParaView series, history.csv and
summary.json (strict JSON: no NaN or Infinity, a non-finite number is null and named in
"notes")."""

from __future__ import annotations

import csv
import json
import math
import os
import time
import warnings
from contextlib import AbstractContextManager, ExitStack
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from femcore.dofs import dof_columns
from femcore.field_names import parts_fields
from femcore.results import Frame, Result
from femcore.writable import FIRST_FRAMES, OutputError, check_folder, frame_bytes, series_frames
from fibreshell.case import Case
from fibreshell.case_reading import _Where
from fibreshell.folder_lock import folder_lock, refuse_if_held
from fibreshell.layup_summary import PENETRATION_SHARE, layup_summary
from fibreshell.outputs import DEFAULT_CHECKPOINT, checkpoint_collision, clean_run
from fibreshell.tilt_flag import say_tilted, tilted_directors
from solvers import Interrupted, SolverError
from solvers.common import SettingError
from solvers.output import ENERGY_KEYS, CheckpointMismatch

# The explicit solver's settings made of the case's [output] history: the energy records'
# watched nodes and the rows of history.csv (FrameRows).
HISTORY_SETTINGS = frozenset({"history_nodes", "frame_summary"})

__all__ = [
    "FrameRows", "Run", "case_held_directors", "check_kinematics", "check_run_options",
    "frame_row", "frames_written", "history_rows", "kept", "path_axis", "profile", "run_case",
    "run_kinematics", "section_thickness", "solve_keeping", "strict_json", "summarise",
]  # fmt: skip


@dataclass
class Run:
    """One solve of a case: the result (every good frame, also after a failure), the solver's
    error message ("" when it reached its goal), the wall time (s) and the summary; a run on a
    mesh other than the case's (the plies) brings its own ``profiles`` along the case's paths
    (``fibreshell.compare.kinematics_record``'s form), else None. ``status`` is "done",
    "stopped" (the solver could not go on) or "interrupted" (SIGINT or SIGTERM inside
    ``solvers.interruptible()``; ``signal`` names it); ``checkpoint`` the file the run can be
    resumed from (None: none)."""

    kinematics: str
    result: Result
    error: str
    wall_time: float
    summary: dict
    profiles: dict | None = None
    status: str = "done"
    signal: str | None = None
    checkpoint: Path | None = None


def check_run_options(
    kinematics=None,
    calibration=None,
    shear_ratio=None,
    bending_scale=None,
    transverse_shear=None,
    twisting=None,
) -> None:
    """Raise ValueError where a calibration or its numbers are given to a run whose
    ``kinematics`` is not "mindlin": a calibration makes the Mindlin shell of the fabric, and a
    run that keeps its fibrous parts (a sweep of shear_ratio without kinematics = "mindlin")
    would ignore it and give the same rows whatever the values."""
    given = {
        name: value
        for name, value in (
            ("calibration", calibration),
            ("shear_ratio", shear_ratio),
            ("bending_scale", bending_scale),
            ("transverse_shear", transverse_shear),
            ("twisting", twisting),
        )
        if value is not None
    }
    if given and kinematics != "mindlin":
        raise ValueError(
            f"{', '.join(given)} set how fibrous parts become Mindlin shells, which only "
            f"kinematics='mindlin' does; with kinematics={kinematics!r} they would be ignored: "
            "run with kinematics='mindlin' (a sweep: vary or set kinematics=mindlin too)"
        )


def check_kinematics(case: Case, kinematics: str | None) -> None:
    """Raise ValueError where ``kinematics`` names a shell the case has no part to run in:
    "fibrous" without a fibrous part (a Mindlin-only case would run as it is, named
    "fibrous"), "mindlin" without a fibrous or Mindlin part (nothing becomes a Mindlin
    shell). None (the case's own parts) is always allowed."""
    if kinematics is None:
        return
    kinds = {part["kind"] for part in case.parts}
    if case.layup is not None:
        kinds = {"fibrous" if case.has_fibrous else "mindlin"}
    runnable = {"fibrous": {"fibrous"}, "mindlin": {"fibrous", "mindlin"}}.get(kinematics)
    if runnable is not None and not kinds & runnable:
        raise ValueError(
            f"{case.path}: kinematics={kinematics!r} needs a part of element "
            f"{' or '.join(sorted(runnable))}; the case's parts are {', '.join(sorted(kinds))} "
            f"(leave kinematics out to run the case as it is)"
        )


def run_case(
    case: Case,
    out: Path,
    kinematics: str | None = None,
    progress: bool | None = None,
    calibration=None,
    shear_ratio: float | None = None,
    bending_scale: float | None = None,
    transverse_shear: float | None = None,
    twisting: float | None = None,
    resume: bool = False,
    write_frames: bool = True,
) -> Run:
    """Build the case (``Case.model``), solve it and write into ``out``: ``result.pvd`` with
    its VTU series (reference coordinates and the displacement field in every frame),
    history.csv and summary.json. An explicit run streams its frames to ``result.pvd`` as it
    goes and appends every energy record (energies, support reactions, the displacements of the
    history sets' nodes) to ``energies.csv``; it keeps only its first and last frames in
    memory, and the rows of history.csv are summarised from each frame as it is streamed
    (one row per frame in every solver, ``history_rows``). A solver that stops keeps its last good
    frames: they are written and the summary says why it stopped.

    Parameters
    ----------
    case : Case
    out : pathlib.Path
        Output folder (created).
    kinematics : None, "fibrous" or "mindlin"
        See ``Case.model``.
    progress : bool or None
        The solver's progress bar on stderr (None: solvers.progress.resolve_progress).
    calibration : fibreshell.calibration.Calibration, str or None
        How the Mindlin shell is made of the fabric ("laws" by default, "fit" values or
        "initial-slope"); shear_ratio, bending_scale, transverse_shear, twisting set its numbers
        (``Calibration.from_options``: a sweep or a fit varies them).
    resume : bool
        Continue from the checkpoint in ``out`` (``[solver] checkpoint``, by default
        ``checkpoint.pkl`` for explicit and relaxation runs) to the same bits as a run never
        stopped. Without it the files a run writes (fibreshell.outputs.clean_run: by their
        exact names, the checkpoint included) are removed from ``out`` first, and only those:
        a series of fewer frames would otherwise sit beside the old frames.
    write_frames : bool
        False: a static or relaxation run writes no ``result.pvd`` series (history.csv and
        summary.json are written, the frames stay in the result), for a caller that throws
        the folder away (fibreshell.sweep without an output folder: its frames' VTU files
        were 0.39 s of the 3.1 s of CPU of the report's sensitivity sweep). An explicit run
        streams its frames whatever it says: that keeps its memory flat.

    The folder is checked first (femcore.writable.check_folder: a folder, writable, room for
    the first frames when frames are written), then held (fibreshell.folder_lock: the file
    ``fibreshell.lock`` there, removed on return) before anything in it is touched: a second
    command writing there is refused (``FolderInUse``) instead of removing this run's frames.
    Static runs write each frame as its increment converges, explicit runs as they go: a
    killed run leaves those frames (and the checkpoint).

    Raises
    ------
    ValueError
        A calibration or its numbers given where ``kinematics`` is not "mindlin" (they would
        be ignored); a ``kinematics`` the case has no part of (``check_kinematics``);
        ``out`` is a file or under one; ``resume`` without a checkpoint to resume from;
        ``out`` held by another command (fibreshell.folder_lock.FolderInUse, naming it); a
        checkpoint path that lands on a file the run writes in ``out``; a CaseError (naming
        the file, the table and the key) for a model that cannot be built or a solver
        setting it cannot be run with (``max_steps``, mass scaling).
    femcore.writable.OutputError
        ``out`` cannot be written or is too full for the first frames, or a write failed
        during the run (the message names the file and what was kept).
    """
    check_run_options(
        kinematics, calibration, shear_ratio, bending_scale, transverse_shear, twisting
    )
    check_kinematics(case, kinematics)
    mesh = case.mesh
    kind = case.solver["kind"]
    # Room for the first frames only where frames are written (an explicit run always).
    frames_written = write_frames or kind == "explicit"
    needed = FIRST_FRAMES * frame_bytes(mesh) if frames_written else 0
    check_folder(out, "output folder", needed=needed)
    task = f"the run of {str(case.path)!r}"
    with folder_lock(out, task), _checkpoint_lock(case, out, task):
        return _run_locked(case, out, kinematics, progress, calibration, shear_ratio,
                           bending_scale, transverse_shear, twisting, resume,
                           write_frames)  # fmt: skip


def _checkpoint_lock(case: Case, out: Path, task: str) -> AbstractContextManager[Any]:
    """The locks of the checkpoint files the run writes or removes (``fibreshell.lock.<name>``
    beside each): the one ``[solver] checkpoint`` names, wherever it puts it (in ``out``, a
    subfolder, or outside it: ``../ck.pkl``, an absolute path, where the lock of ``out`` does
    not reach), and ``out``'s default ``checkpoint.pkl``, which the run's cleaning removes
    whatever its own checkpoint (clean_run). Two runs naming one checkpoint file from
    different output folders would remove and resume from each other's; the second is
    refused (fibreshell.folder_lock.FolderInUse), naming the first. A checkpoint outside
    ``out`` in a folder another command holds (``../a/ck.pkl`` beside a run writing into
    ``a``) is refused too (``refuse_if_held``)."""
    named = case.solver.get("checkpoint")
    checkpoints = [out / DEFAULT_CHECKPOINT]
    if named is not None:
        checkpoint = Path(os.path.normpath(out / named))  # "b/../shared.pkl": "shared.pkl"
        folder = check_folder(checkpoint.parent, "the checkpoint's folder")
        if folder.resolve() != out.resolve():
            refuse_if_held(folder, f"the checkpoint {named!r}")
        if checkpoint.resolve() != checkpoints[0].resolve():
            checkpoints.append(folder / checkpoint.name)
    stack = ExitStack()
    try:
        for checkpoint in checkpoints:
            stack.enter_context(
                folder_lock(checkpoint.parent, task, "the checkpoint", file=checkpoint.name)
            )
    except BaseException:
        stack.close()
        raise
    return stack


def _run_locked(case, out, kinematics, progress, calibration, shear_ratio, bending_scale,
                transverse_shear, twisting, resume, write_frames) -> Run:  # fmt: skip
    """``run_case`` in its checked folder ``out``, which it holds (fibreshell.folder_lock)."""
    from fibreshell.calibration import Calibration

    mesh = case.mesh
    kind = case.solver["kind"]
    named = case.solver.get("checkpoint")
    checkpoint = None if named is None else out / named
    if checkpoint is not None:
        # a Case not read from a file (fibreshell.case checks [solver] checkpoint as read)
        taken = checkpoint_collision(checkpoint.name)
        if taken is not None:
            raise ValueError(
                f"the checkpoint {named!r} would overwrite {taken}; give [solver] "
                "checkpoint another name"
            )
    if resume:
        refuse_diverged_resume(out)
    if resume and (checkpoint is None or not checkpoint.exists()):
        why = (
            "a static run has no checkpoint"
            if kind == "static"
            else "[solver] checkpoint = false"
            if checkpoint is None
            else f"no checkpoint {str(checkpoint)!r}"
        )
        raise ValueError(f"nothing to resume in {str(out)!r}: {why}; run without --resume")
    if not resume:
        clean_run(out, checkpoint)
    if checkpoint is not None:  # "[solver] checkpoint" may name a file in a subfolder
        check_folder(checkpoint.parent, "the checkpoint's folder")
    rule = Calibration.from_options(
        calibration, shear_ratio, bending_scale, transverse_shear, twisting
    )
    model = case.model(kinematics, rule)
    outputs: dict[str, Any] = {"progress": progress}
    options: dict[str, Any] = {}
    if kind == "explicit" or (kind == "static" and write_frames):
        # frames to disk as the run goes: a kill leaves them
        outputs["output"] = out / "result.pvd"
    if kind == "explicit":  # and the energy records: the memory of a long run stays flat
        watched = [mesh.nodes(name) for name in case.history.get("displacements", [])]
        outputs["history"] = out / "energies.csv"
        outputs["history_nodes"] = np.unique(np.concatenate(watched)) if watched else ()
        outputs["frame_summary"] = FrameRows.of(case)
        options["checkpoint_interval"] = case.solver.get("checkpoint_interval", 60.0)
    if checkpoint is not None:
        options["checkpoint"] = checkpoint
    solver = case.make_solver(**outputs)
    try:
        result, failure, wall = _solve(solver, model, **options)
    except SettingError as setting:  # found as the solve starts: at its [solver] key
        key = setting.option if setting.option in case.solver["options"] else None
        raise _Where(case.path, "solver").error(key, str(setting)) from None
    except CheckpointMismatch as refused:
        if not refused.changed or not HISTORY_SETTINGS.issuperset(refused.changed):
            # the model or other settings too: the message names every part, and the case
            # file's way out (a changed [layup] names its plies' contacts and blocks)
            raise CheckpointMismatch(
                f"{refused}; the case {str(case.path)!r} changed since the checkpoint was "
                "written: give it back as it was to resume, or run without --resume to start "
                "again",
                refused.changed,
            ) from None
        raise _Where(case.path, "output").error(
            "history",
            "changed since the checkpoint was written (a set added, removed or redefined): "
            "the rows kept before the stop have the old columns; give it back as it was to "
            f"resume from {str(checkpoint)!r}, or run without --resume to start again",
        ) from None
    error = "" if failure is None else str(failure)
    status = "interrupted" if isinstance(failure, Interrupted) else "stopped" if error else "done"
    label, kinds = run_kinematics(case, kinematics)
    summary = summarise(case, result, label, error, wall, held_directors(model))
    if kinds is not None:  # "mixed": which parts are what
        summary["parts"] = kinds
    summary["status"] = status
    # (a diverged explicit run removes a checkpoint that held a state past its last good one)
    left = checkpoint is not None and checkpoint.exists()
    summary["checkpoint"] = str(checkpoint) if left else None
    try:
        if kind == "relaxation" and write_frames:
            result.write(out / "result.pvd")
        rows = history_rows(case, result)
        with open(out / "history.csv", "w", newline="") as handle:
            writer = csv.DictWriter(handle, fieldnames=list(rows[0]))
            writer.writeheader()
            writer.writerows(rows)
        (out / "summary.json").write_text(strict_json(summary))
    except OSError as failed:
        raise OutputError.from_error(failed, kept(out, checkpoint)) from None
    return Run(label, result, error, wall, summary, status=status,
               signal=getattr(failure, "signal", None),
               checkpoint=checkpoint if left else None)  # fmt: skip


def refuse_diverged_resume(out: Path) -> None:
    """Raise ValueError when the run in ``out`` diverged (its summary.json says so): its
    outputs end at its last good state, and resuming it with the same settings would take the
    same steps to the same divergence."""
    try:
        stopped = json.loads((out / "summary.json").read_text()).get("stopped")
    except (OSError, ValueError, AttributeError):
        return
    if isinstance(stopped, str) and " diverged at step " in stopped:
        first = stopped.split(": ", 1)[0]
        raise ValueError(
            f"nothing to resume in {str(out)!r}: the run there diverged ({first}); resuming "
            "it as it is would diverge again: run without --resume, with a smaller dt or "
            "safety"
        )


def run_kinematics(case: Case, kinematics: str | None) -> tuple[str, list[str] | None]:
    """The kinematics a run of ``case`` is named by (summary.json's "kinematics") and, where
    its parts differ, their elements in the case's order (else None): ``kinematics`` where
    given ("fibrous", "mindlin"), else the parts' one element ("fibrous", "mindlin", ...), or
    "mixed" for parts of different elements (a fibrous and a Mindlin part on shared nodes
    were called "fibrous")."""
    if case.layup is not None:  # the plies' shells are one element
        return kinematics or ("fibrous" if case.has_fibrous else case.parts[0]["kind"]), None
    kinds = [
        "mindlin" if kinematics == "mindlin" and part["kind"] == "fibrous" else part["kind"]
        for part in case.parts
    ]
    if len(set(kinds)) > 1:
        return kinematics or "mixed", kinds
    return kinematics or kinds[0], None


def kept(out: Path, checkpoint: Path | None) -> str:
    """What a run's folder holds, in words: the frames of result.pvd, the other outputs and
    the checkpoint."""
    files = [f"{name} ({series_frames(out / name)} frames)" if name == "result.pvd" else name
             for name in ("result.pvd", "history.csv", "energies.csv", "summary.json")
             if (out / name).exists()]  # fmt: skip
    if checkpoint is not None and checkpoint.exists():
        files.append(f"the checkpoint {checkpoint.name}")
    return f"in {str(out)!r}: {', '.join(files)}" if files else f"nothing in {str(out)!r}"


def _solve(solver, model, **options) -> tuple[Result, SolverError | None, float]:
    """``solver.solve(model, **options)``: the result (the last good frames of a solver that
    stopped), the error that stopped it (None when it reached its goal), the wall time (s;
    of a resumed run, with the parts before the stop up to its checkpoint).

    Raises
    ------
    SolverError
        A solver that stopped before its first frame (nothing to keep).
    """
    started = time.perf_counter()
    failure = None
    try:
        result = solver.solve(model, **options)
    except SolverError as error:
        if error.result is None:
            raise
        result, failure = error.result, error
    earlier = result.info.get("wall_time_before_resume", 0.0)
    return result, failure, time.perf_counter() - started + earlier


def solve_keeping(solver, model) -> tuple[Result, str, float]:
    """``solver.solve(model)``, keeping the last good frames of a solver that stops: the
    result, the solver's message ("" when it reached its goal) and the wall time (s).

    Raises
    ------
    SolverError
        A solver that stopped before its first frame (nothing to keep).
    """
    result, failure, wall = _solve(solver, model)
    return result, "" if failure is None else str(failure), wall


@dataclass(frozen=True)
class FrameRows:
    """The history columns of a frame (``frame_row``), made of what shapes them and nothing
    else: the ``history.reactions`` sets and the ``history.displacements`` sets by name, node
    indices and reference coordinates, in the case's order. An explicit run's solver is given
    it as its ``frame_summary``, and its checkpoint's fingerprint reads it (femcore.fingerprint):
    a resume after ``[output] history`` changed, a set added, removed or redefined under its
    name, is refused before the run goes on, where the rows kept before the stop would have
    carried the old columns."""

    reactions: tuple[tuple[str, np.ndarray], ...]
    displacements: tuple[tuple[str, np.ndarray, np.ndarray], ...]  # name, nodes, (k, 3) mm

    @classmethod
    def of(cls, case: Case) -> FrameRows:
        mesh = case.mesh
        reactions = tuple((name, mesh.nodes(name)) for name in case.history.get("reactions", []))
        displacements = tuple(
            (name, nodes, mesh.points[nodes])
            for name in case.history.get("displacements", [])
            for nodes in [mesh.nodes(name)]
        )
        return cls(reactions, displacements)

    def __call__(self, frame: Frame) -> dict[str, float]:
        row: dict[str, float] = {"time": frame.time, "load_factor": frame.load_factor}
        for name, nodes in self.reactions:
            total = frame.reactions[nodes].sum(axis=0)
            row.update({f"reaction_{name}_{axis}": float(total[i]) for i, axis in enumerate("xyz")})
        for name, nodes, origins in self.displacements:
            mean = (frame.positions[nodes] - origins).mean(axis=0)
            row.update(
                {f"displacement_{name}_{axis}": float(mean[i]) for i, axis in enumerate("xyz")}
            )
        moved = getattr(frame, "tool_displacements", np.zeros((0, 3)))
        for tool, force in enumerate(frame.tool_forces, start=1):
            row.update(
                {f"tool{tool}_force_{axis}": float(force[i]) for i, axis in enumerate("xyz")}
            )
            if len(moved) >= tool:
                row.update(
                    {
                        f"tool{tool}_displacement_{axis}": float(moved[tool - 1][i])
                        for i, axis in enumerate("xyz")
                    }
                )
        return row


def frame_row(case: Case, frame: Frame) -> dict[str, float]:
    """The history columns of one frame: ``time`` (s), ``load_factor``,
    ``reaction_<set>_x/y/z`` the reaction sums over each ``history.reactions`` set (N),
    ``displacement_<set>_x/y/z`` the mean displacement of each ``history.displacements`` set
    (mm), ``tool<k>_force_x/y/z`` the force on each rigid tool (N) and
    ``tool<k>_displacement_x/y/z`` its translation from where it was given (mm)."""
    return FrameRows.of(case)(frame)


def history_rows(case: Case, result: Result) -> list[dict]:
    """One row per output frame: ``frame`` (its index), the columns of ``frame_row``, then
    ``energy_<key>`` (N mm) for the energies the solver records: per frame (Static: the strain
    energy ``energy_internal`` and the friction's dissipation ``energy_friction``), or
    interpolated at the frame times (explicit runs). A streamed explicit run keeps two frames
    in memory; its rows come from every frame of its series (``result.info["frame_summaries"]``,
    the solver's ``frame_summary``)."""
    summaries = result.info.get("frame_summaries")
    if summaries is None:
        summaries = [frame_row(case, frame) for frame in result.frames]
    energies = result.energies if result.energies else {}
    times = np.asarray(energies.get("time", ()))
    frame_times = [row["time"] for row in summaries]
    per_frame = len(times) == len(summaries) and np.array_equal(times, frame_times)
    rows = []
    for index, summary in enumerate(summaries):
        row: dict[str, Any] = {"frame": index, **summary}
        if per_frame:
            row.update({f"energy_{key}": values[index] for key, values in energies.items()
                        if key != "time"})  # fmt: skip
        elif len(times) > 0:
            for key in ENERGY_KEYS:
                if key in energies:
                    row[f"energy_{key}"] = float(
                        np.interp(summary["time"], energies["time"], energies[key])
                    )
        rows.append(row)
    return rows


def frames_written(result: Result) -> int:
    """The frames of the run's series (the rows of history.csv): a streamed explicit run keeps
    only two of them in memory and counts the others in ``result.info["frame_summaries"]``."""
    summaries = result.info.get("frame_summaries")
    return len(summaries if summaries is not None else result.frames)


def path_axis(case: Case, name: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Path ``name``'s nodes, their reference arc length s (mm) and the path's horizontal
    unit direction (3,) from its first to its last node (profiles are drawn along it)."""
    nodes = case.paths[name]
    x0 = case.mesh.points[nodes]
    s = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(x0, axis=0), axis=1))]
    along = x0[-1] - x0[0]
    along[2] = 0.0
    along /= np.linalg.norm(along) or 1.0
    return nodes, s, along


def profile(case: Case, result: Result, name: str, thickness: float) -> dict:
    """Along path ``name`` at the final frame: s (reference arc length, mm), the mid-surface
    x, y, z and its ``horizontal`` coordinate along the path's horizontal direction (mm), the
    director's angle to the horizontal in the vertical plane of the path (deg, 90 =
    vertical) and the thickness along the director (mm; the fibrous shell's h_m, the section
    thickness ``thickness`` for a shell without that field); ``directors`` (k, 3) and their
    ``director_horizontal`` components, for drawing."""
    nodes, s, along = path_axis(case, name)
    x = result.positions[nodes]
    d = result.directors[nodes]
    angle = np.degrees(np.arctan2(d[:, 2], d @ along))
    merged = result.thickness
    h = np.full(len(nodes), thickness) if merged is None else merged[nodes]
    h = np.where(np.isnan(h), thickness, h)  # a node of no block with the field: the section's
    return {
        "s": s, "x": x[:, 0], "y": x[:, 1], "z": x[:, 2], "horizontal": x @ along,
        "director_angle_deg": angle, "thickness": h, "directors": d,
        "director_horizontal": d @ along,
    }  # fmt: skip


def _say_penetrations(penetrations: dict[str, dict[str, Any]]) -> None:
    """Warn once where a ply contact ended pressed deeper than ``PENETRATION_SHARE`` of the
    ply thickness (fibreshell.layup_summary ``ply_penetrations``), naming the penalty that
    would hold it."""
    if not penetrations:
        return
    said = "; ".join(
        f"{p['upper']} into {p['lower']} by up to {p['deepest_mm']:.3g} mm "
        f"({p['share_of_thickness']:.2g} of a ply; {p['nodes']} nodes past the share), "
        f"kept within it by [layup] penalty = {p['penalty']:.3g} N/mm or more"
        for p in penetrations.values()
    )
    warnings.warn(
        f"the plies' contact gave way: {said} (summary.json, layup.penetration; more than "
        f"{PENETRATION_SHARE:g} of the ply thickness). The automatic penalty is the explicit "
        "step's: under a consolidation pressure give [layup] penalty (per upper node; a "
        "larger one shortens an explicit run's stable step)",
        UserWarning,
        stacklevel=2,
    )


def _say_crossings(
    crossed: dict[str, dict[str, Any]], lower_rule: str | None, penetrated: bool = False
) -> None:
    """Warn where the layup's plies ended through each other (fibreshell.layup_summary
    ``ply_crossings``): the ply order there is lost, which the contact's fields do not show.
    Where a contact also gave way under its pressure (``penetrated``) the remedy is a larger
    penalty (``_say_penetrations``), not the mirrored pass."""
    through = {ply: c for ply, c in crossed.items() if c["nodes"]}
    if not through:
        return
    said = "; ".join(
        f"{c['nodes']} nodes of {ply.split('_on_')[0]} and {c.get('lower', 'the ply below')} "
        "passed each other's mid-surface, the "
        f"deepest by {c['deepest_mm']:.3g} mm (nodes {', '.join(map(str, c['first'][:5]))})"
        for ply, c in through.items()
    )
    remedy = (
        'give [layup] lower_rule = "nodes" (the lower ply\'s nodes held off the upper ply too)'
        if lower_rule is None and not penetrated
        else "a larger [layup] penalty, a finer mesh where the tools are sharp, or a slower stroke"
    )
    warnings.warn(
        f"the plies crossed: {said} (summary.json, layup.crossed): the results there are not "
        f"of plies in their order. Try {remedy}",
        UserWarning,
        stacklevel=2,
    )


def held_directors(model: Any) -> np.ndarray:
    """(k,) int: the nodes whose directors the model's supports hold (alpha and beta fixed,
    or every DOF): a clamp, where the director is imposed."""
    alpha, beta = dof_columns(("alpha", "beta"))
    held: list[np.ndarray] = []
    for fix in model.fixes:
        columns = fix.columns
        if columns is None or (alpha in columns and beta in columns):
            held.append(np.asarray(fix.nodes, dtype=np.int64))
    return np.unique(np.concatenate(held)) if held else np.zeros(0, dtype=np.int64)


def case_held_directors(case: Case) -> np.ndarray:
    """(k,) int: the case mesh's nodes whose directors its ``[[fix]]`` tables hold (every DOF,
    or alpha and beta among ``dofs``): a clamp, where the director is imposed. Their tilt from
    the nodal normal is measured against the clamp's one-sided facets, the discretisation's,
    not the run's: the profiles leave it out (NaN), as ``summarise`` does."""
    held = [
        np.asarray(fix["nodes"], dtype=np.int64)
        for fix in case.fixes
        if fix["dofs"] is None or {"alpha", "beta"} <= set(fix["dofs"])
    ]
    return np.unique(np.concatenate(held)) if held else np.zeros(0, dtype=np.int64)


def summarise(
    case: Case,
    result: Result,
    kinematics: str,
    error: str,
    wall: float,
    held: np.ndarray | None = None,
) -> dict:
    """The numbers of a run for summary.json: how it ended, the history sets at the final
    frame, the force on each rigid tool, the largest fibre strain and director tilt where the
    element reports them, the profiles along the paths, a ``[layup]``'s per-ply numbers
    (``layup``: fibreshell.layup_summary), and for an explicit run
    ``quasi_static``: its kinetic energy over external work with the mass and time scaling
    (solvers/quasi_static.py, ``QuasiStaticWatch.report``)."""
    final = result.frames[-1]
    out: dict[str, Any] = {
        "case": case.title,
        "file": str(case.path),
        "kinematics": kinematics,
        "solver": case.solver["kind"],
        "status": "done" if not error else "stopped",  # run_case: or "interrupted"
        "converged": bool(result.converged),
        "stopped": error or None,
        "steps": int(result.steps),
        "frames": frames_written(result),
        "wall_time_s": wall,
        "final_time": final.time,
        "final_load_factor": final.load_factor,
        "reactions": {
            name: final.reactions[case.mesh.nodes(name)].sum(axis=0)
            for name in case.history.get("reactions", [])
        },
        "mean_displacements": {
            name: (final.positions[n] - case.mesh.points[n]).mean(axis=0)
            for name in case.history.get("displacements", [])
            for n in [case.mesh.nodes(name)]
        },
    }
    if "quasi_static" in result.info:  # explicit runs: KE / W, mass and time scaling
        out["quasi_static"] = dict(result.info["quasi_static"])
    if "energy_balance_error" in result.info:  # explicit runs: the step and the balance
        out["explicit_step"] = {
            "dt_s": result.info["dt"],
            "energy_balance_error": result.info["energy_balance_error"],
            "step_limits": result.info.get("step_limits"),
        }
    if "tool_penetration" in result.info:  # how deep the body went into each tool
        out["tool_penetration"] = result.info["tool_penetration"]
    if "round_off_accepted" in result.info:  # Static's acceptances at the round-off floor
        out["round_off_accepted"] = result.info["round_off_accepted"]
    if len(final.tool_forces):  # the force on each tool ([[contact]] order), N
        out["tool_forces"] = {f"tool{i}": f for i, f in enumerate(final.tool_forces, start=1)}
        moved = getattr(final, "tool_displacements", np.zeros((0, 3)))
        out["tool_displacements"] = {f"tool{i}": d for i, d in enumerate(moved, start=1)}
    triangle = final.fields.get("triangle", {})
    if "warp_strain" in triangle:
        out["max_fibre_strain"] = float(
            np.nanmax(
                np.abs(np.r_[triangle["warp_strain"].ravel(), triangle["weft_strain"].ravel()])
            )
        )
    point = final.fields.get("point", {})
    # every block's tilt: a part on nodes another part shares has its own (director_tilt_deg_2),
    # NaN off its block (femcore.compiled: not defined there)
    tilts = [np.array(values, dtype=float) for values in parts_fields(point, "director_tilt_deg")]
    if tilts:
        tilt = np.vstack(tilts)
        if held is not None and held.size and held.size < tilt.shape[1]:
            # a held director is imposed: its tilt is measured against the clamp's one-sided
            # facets (a Mindlin clamp read 13.7 deg where the next node out leans 3.1; the
            # fibrous shell measures its clamp against the reference normal, 0)
            tilt[:, held] = np.nan
        out["director_tilt_deg"] = (
            {"min": float(np.nanmin(tilt)), "max": float(np.nanmax(tilt))}
            if np.isfinite(tilt).any()
            else {"min": None, "max": None}
        )
    tilted = tilted_directors(point, held)  # past the thickness guard's tilt, or at its cap
    if tilted is not None:
        out["tilted_directors"] = tilted
        say_tilted(tilted)
    if case.layup is not None:  # per ply: angle, shear, displacement, slip over the one below
        out["layup"] = layup_summary(case.layup, case.mesh.points, final)
        _say_penetrations(out["layup"]["penetration"])
        _say_crossings(
            out["layup"]["crossed"], case.layup.lower_rule, bool(out["layup"]["penetration"])
        )
    thickness = section_thickness(case)
    out["paths"] = {
        name: {
            k: v
            for k, v in profile(case, result, name, thickness).items()
            if k not in ("directors", "director_horizontal")  # drawing aids
        }
        for name in case.paths
    }
    return out


def section_thickness(case: Case) -> float:
    """The thickness (mm) of the case's first shell part: its fabric's or its section's."""
    for part in case.parts:
        element = part["element"]
        for owner in (getattr(element, "fabric", None), getattr(element, "material", None)):
            if owner is not None and hasattr(owner, "thickness"):
                return float(owner.thickness)
    return 0.0


def strict_json(data: Any) -> str:
    """JSON text of ``data`` (numpy arrays and numbers included) that strict parsers accept:
    every non-finite number becomes null and its place is listed under "notes" (top level)."""
    notes: list[str] = []

    def clean(value: Any, where: str) -> Any:
        if isinstance(value, dict):
            return {str(k): clean(v, f"{where}.{k}" if where else str(k)) for k, v in value.items()}
        if isinstance(value, list | tuple):
            return [clean(v, f"{where}[{i}]") for i, v in enumerate(value)]
        if isinstance(value, np.ndarray):
            return clean(value.tolist(), where)
        if isinstance(value, np.generic):
            return clean(value.item(), where)
        if isinstance(value, float) and not math.isfinite(value):
            notes.append(f"{where}: {value!r} written as null")
            return None
        return value

    cleaned = clean(data, "")
    if notes and isinstance(cleaned, dict):
        cleaned["notes"] = cleaned.get("notes", []) + notes
    return json.dumps(cleaned, indent=1, allow_nan=False) + "\n"
