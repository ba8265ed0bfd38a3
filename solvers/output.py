"""Output written while a run goes: frames as a VTU series with its ParaView index, histories as
CSV rows, and checkpoints to resume from. Each file is complete after every write, so a run that
is killed leaves a readable series, history and checkpoint."""

from __future__ import annotations

import csv
import hashlib
import io
import os
import pickle
from pathlib import Path
from typing import Any
from xml.etree import ElementTree
from xml.sax.saxutils import quoteattr

import numpy as np

from femcore.checks import as_path
from femcore.fingerprint import Fingerprint
from femcore.mesh import Mesh
from femcore.results import Frame, Result, series_timesteps, write_vtu

__all__ = [
    "CHECKPOINT_MAGIC",
    "CheckpointMismatch",
    "ENERGY_KEYS",
    "FrameStream",
    "HistoryWriter",
    "checkpoint_path",
    "load_checkpoint",
    "resume",
    "save_checkpoint",
]


def _atomic_write(path: Path, data: bytes) -> None:
    """Write ``data`` to a temporary file next to ``path``, flush it to disk and rename it over
    ``path``: a reader (or a run resumed after a kill) sees the old file or the new, never
    half of one."""
    temporary = path.with_name(path.name + ".part")
    with open(temporary, "wb") as handle:
        handle.write(data)
        handle.flush()
        os.fsync(handle.fileno())
    os.replace(temporary, path)


def output_path(path: str | os.PathLike[str], suffix: str, what: str) -> Path:
    """``path`` as a Path with the given suffix in an existing directory, else ValueError."""
    checked = as_path(path, what)
    if checked.suffix.lower() != suffix:
        raise ValueError(f"{what} must be a {suffix} path, got {str(path)!r}")
    if not checked.parent.is_dir():
        raise ValueError(f"{what}: the directory {str(checked.parent)!r} does not exist")
    return checked


class FrameStream:
    """Frames written as they come: ``<stem>_<k>.vtu`` next to the ``.pvd`` index, which is
    rewritten after each frame. The solver then keeps only the first and the newest frame in
    memory, so a long run's memory does not grow with its number of frames. Each frame's
    ``timestep`` in the index is its time while the times rise, else (``by_index``: a Static
    arc-length path) its index (femcore.results.series_timesteps); the VTU frame keeps its
    time and load factor as field data."""

    def __init__(self, path: Path, mesh: Mesh, has_rotation: np.ndarray, by_index: bool = False):
        self.path, self.mesh, self.has_rotation = path, mesh, has_rotation
        # the index's timesteps: the frames' times, or their indices (femcore.results
        # series_timesteps: a Static arc-length path's load factor falls past a limit point)
        self.by_index = by_index
        self.entries: list[tuple[float, str]] = []  # (time, file name) per written frame

    def write(self, frame: Frame) -> None:
        stem = self.path.with_suffix("")
        part = stem.parent / f"{stem.name}_{len(self.entries):05d}.vtu"
        # The folder was checked once before the run (solvers.interrupts.check_outputs);
        # Result.write would probe it again at every frame. A failed write is an OSError the
        # solve turns into one OutputError (solvers.interrupts.keeps_writes).
        write_vtu(Result(self.mesh, [frame], has_rotation=self.has_rotation).to_meshio(0), part)
        self.entries.append((frame.time, part.name))
        self._write_index()

    def check_written(self) -> None:
        """Check, before a resumed run goes on, that the index on disk lists the frames the
        checkpoint counted (``entries``) and that their files are there.

        Raises
        ------
        ValueError
            Naming the index and the counts when a frame is missing: the series would have a
            hole.
        """
        try:
            listed = [e.get("file") for e in ElementTree.parse(self.path).getroot().iter("DataSet")]
        except (OSError, ElementTree.ParseError) as error:
            raise ValueError(
                f"cannot resume: the series index {str(self.path)!r} cannot be read "
                f"({type(error).__name__}), and the checkpoint counted {len(self.entries)} "
                "frames in it; delete the checkpoint to start again"
            ) from None
        names = [name for _, name in self.entries]
        missing = [name for name in names if not (self.path.parent / name).is_file()]
        if listed[: len(names)] != names or missing:
            what = f"the file {missing[0]!r} is missing" if missing else "its frames differ"
            raise ValueError(
                f"cannot resume: the series index {str(self.path)!r} lists {len(listed)} frames "
                f"where the checkpoint counted {len(names)} ({what}); delete the checkpoint to "
                "start again"
            )

    def drop_after(self, time: float) -> None:
        """Unlist (and delete) the frames written after ``time``: a diverged run's series ends
        with its last good state."""
        for t, name in self.entries:
            if t > time * (1.0 + 1e-12):
                (self.path.parent / name).unlink(missing_ok=True)
        self.entries = [(t, name) for t, name in self.entries if t <= time * (1.0 + 1e-12)]
        self._write_index()

    def _write_index(self) -> None:
        steps = series_timesteps([t for t, _ in self.entries], self.by_index)
        lines = [
            f"    <DataSet timestep={quoteattr(repr(step))} file={quoteattr(name)}/>"
            for step, (_, name) in zip(steps, self.entries)
        ]
        text = (
            '<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n'
            "  <Collection>\n" + "\n".join(lines) + "\n  </Collection>\n</VTKFile>\n"
        )
        _atomic_write(self.path, text.encode())


#: The energies a history records, N mm (the keys of ``Result.energies`` after "time"); the
#: columns are ``energy_<key>``, as in fibreshell's history.csv. "internal" is the energy
#: stored (the internal forces' work less "friction", the interactions' dissipation), so that
#: kinetic + internal + damping + friction = external_work (docs/theory.md §6.1, "The energy
#: records").
ENERGY_KEYS = ("kinetic", "internal", "external_work", "damping", "friction")


#: The rows a history keeps in memory at most before writing them (one file open per this many
#: steps: a negligible share of a step, and a killed run loses at most these).
PENDING_ROWS = 256


class HistoryWriter:
    """CSV rows appended as the run goes, kept in memory and written to the file by ``flush``
    (the solver flushes at each frame, before each checkpoint and when the run ends or stops,
    and ``append`` itself once ``PENDING_ROWS`` rows wait: opening the file for every row cost
    a fifth of a millisecond an explicit step of the two-ply hemisphere, about 5 % of it;
    benchmarks/forming_step_overhead.py). A run killed where Python cannot finish it (SIGKILL,
    the kernel's out-of-memory killer) loses at most the rows since the last write; the file a
    user watches during a run is at most that far behind. Columns: ``time`` (s),
    ``energy_kinetic``,
    ``energy_internal``, ``energy_external_work``, ``energy_damping``, ``energy_friction``
    (N mm), ``reaction_all_x/y/z`` the sum of the support reactions (N),
    ``tool<k>_force_x/y/z`` the force on each rigid tool (N) and ``tool<k>_displacement_x/y/z``
    its translation (mm), and ``displacement_node<i>_x/y/z`` the displacements (mm) of chosen
    nodes: the names fibreshell's history.csv gives the same quantities."""

    def __init__(self, path: Path, nodes: np.ndarray, tools: int = 0):
        self.path, self.nodes, self.tools = path, nodes, tools
        self.rows = 0  # data rows written; a resumed run cuts the file back to them
        self._pending: list[list[str]] = []  # rows appended, not yet written

    def header(self) -> list[str]:
        columns = ["time"] + [f"energy_{key}" for key in ENERGY_KEYS]
        columns += [f"reaction_all_{axis}" for axis in "xyz"]
        for tool in range(1, self.tools + 1):
            columns += [f"tool{tool}_force_{axis}" for axis in "xyz"]
            columns += [f"tool{tool}_displacement_{axis}" for axis in "xyz"]
        for node in self.nodes:
            columns += [f"displacement_node{node}_{axis}" for axis in "xyz"]
        return columns

    def start(self) -> None:
        """Write the header, or keep the rows a checkpoint counted and drop any after them.

        Raises
        ------
        ValueError
            When the file holds fewer rows than the checkpoint counted, or another header (it
            was cut short, or written by another run): carrying on would leave a history with
            a hole.
        """
        if self.rows == 0:
            with open(self.path, "w", newline="") as handle:
                csv.writer(handle).writerow(self.header())
            return
        if not self.path.exists():
            raise ValueError(
                f"cannot resume: the history {str(self.path)!r} is missing, and the checkpoint "
                f"counted {self.rows} rows in it; delete the checkpoint to start again"
            )
        header = self.header()
        try:
            with open(self.path, newline="") as handle:
                kept = list(csv.reader(handle))[: self.rows + 1]
        except (UnicodeDecodeError, csv.Error):
            kept = [[]]  # not the CSV this writer wrote: refused below as another header
        if not kept or kept[0] != header:
            found = "another header"
        elif len(kept) - 1 < self.rows or any(len(row) != len(header) for row in kept):
            found = f"{sum(len(row) == len(header) for row in kept[1:])} whole rows"
        else:
            found = ""
        if found:
            raise ValueError(
                f"cannot resume: the history {str(self.path)!r} has {found} where the "
                f"checkpoint counted {self.rows} rows (a file cut short or replaced); delete "
                "the checkpoint to start again"
            )
        with open(self.path, "w", newline="") as handle:
            csv.writer(handle).writerows(kept)

    def append(
        self,
        energies: tuple,
        reactions: np.ndarray,
        displacements: np.ndarray,
        tool_forces: np.ndarray | None = None,
        tool_displacements: np.ndarray | None = None,
    ) -> None:
        tools = np.zeros((self.tools, 3)) if tool_forces is None else tool_forces
        moved = np.zeros((self.tools, 3)) if tool_displacements is None else tool_displacements
        paired = np.concatenate([np.reshape(tools, (-1, 3)), np.reshape(moved, (-1, 3))], axis=1)
        # the numbers as one float64 row, made Python floats at once (``tolist``: the same
        # doubles, so the same text, as a float() of each numpy scalar)
        numbers = np.concatenate(
            [
                np.asarray(energies, dtype=np.float64),
                reactions.sum(axis=0),
                paired.ravel(),
                displacements[self.nodes].ravel(),
            ]
        )
        self._pending.append(list(map(repr, numbers.tolist())))
        if len(self._pending) >= PENDING_ROWS:
            self.flush()

    def drop_after(self, time: float) -> None:
        """Write the rows waiting, then keep in the file only those at ``time`` (s) or before
        (rewritten whole through a temporary file): a diverged run's history ends with its
        last good state, as its series does."""
        self.flush()
        with open(self.path, newline="") as handle:
            lines = list(csv.reader(handle))
        whole = [row for row in lines[1:] if len(row) == len(lines[0])]  # (not a part row)
        kept = [lines[0]] + [row for row in whole if float(row[0]) <= time * (1.0 + 1e-12)]
        text = io.StringIO(newline="")
        csv.writer(text).writerows(kept)
        _atomic_write(self.path, text.getvalue().encode())
        self.rows = len(kept) - 1

    def flush(self) -> None:
        """Write the rows appended since the last flush to the file (``rows`` counts the rows
        written: what a checkpoint may count). The rows are taken off the queue before the
        write, so that a write that fails part way (a full disk, a second interrupt) is not
        repeated by the next flush: the file may then end in a part row, which a resume cuts
        back to the rows counted."""
        if not self._pending:
            return
        pending, self._pending = self._pending, []
        with open(self.path, "a", newline="") as handle:
            csv.writer(handle).writerows(pending)
        self.rows += len(pending)


#: The first bytes of a checkpoint file; then the sha256 of the payload (32 bytes), its length
#: (8 bytes, little-endian) and the pickled payload. The number is the format's: 3 since the
#: energy records' "internal" became the stored energy (docs/theory.md §6.1, "The energy
#: records"), 4 since a tool contact's landing node is anchored where its way touched the
#: surface (docs/theory.md §9.2; its history no longer keeps the approach's gap), 5 since a
#: node leaving a tool dissipates its slip up to where it left (docs/theory.md §9.2; its
#: history keeps each anchored node's place), 6 since a ply contact's landing point is
#: anchored where its way crossed the lower face (§9.3a; its history's sides serve as the place
#: it came from), 7 since a ply contact's point leaving the lower face dissipates its slip up to
#: where it left (§9.3a), 8 since a ply contact's point whose gap is to an edge or a vertex lands
#: where its way crossed that gap's zero and leaves with its slip counted (§9.3a), 9 since such a
#: point's anchor near T's plane (|nu . n| <= TILT) takes the continuous blend and a sliding
#: point's moved anchor is re-expressed by the same rule (§9.3a), 10 since the fingerprint knows
#: a frame_summary by what it is made of (the rows kept before a stop match the rest; 9 knew it
#: as given or not), so that a run resumed from an older checkpoint cannot change its meaning
#: midway.
CHECKPOINT_PREFIX = b"fibreshell checkpoint "
CHECKPOINT_FORMAT = 10
CHECKPOINT_MAGIC = CHECKPOINT_PREFIX + f"{CHECKPOINT_FORMAT}\n".encode()


def save_checkpoint(path: Path, payload: dict[str, Any]) -> None:
    """Pickle ``payload`` to ``path`` atomically, framed with its checksum (CHECKPOINT_MAGIC)."""
    data = pickle.dumps(payload, protocol=pickle.HIGHEST_PROTOCOL)
    header = CHECKPOINT_MAGIC + hashlib.sha256(data).digest() + len(data).to_bytes(8, "little")
    _atomic_write(path, header + data)


def load_checkpoint(path: Path) -> dict[str, Any] | None:
    """The payload of ``path``, or None if there is no such file.

    Raises
    ------
    ValueError
        Naming ``path``, when it is not a checkpoint this program wrote, or a damaged one
        (its checksum does not match: a flipped bit, a file cut short). Only a payload whose
        checksum matches is unpickled (unpickling runs code).
    """
    if not path.exists():
        return None
    try:
        data = path.read_bytes()
    except OSError as error:
        raise ValueError(f"cannot read the checkpoint {str(path)!r}: {error.strerror}") from None
    start = len(CHECKPOINT_MAGIC)
    if data.startswith(CHECKPOINT_PREFIX) and not data.startswith(CHECKPOINT_MAGIC):
        written = data[len(CHECKPOINT_PREFIX) : data.find(b"\n", 0, 40)].decode("ascii", "replace")
        raise ValueError(
            f"{str(path)!r} is a checkpoint of format {written}, written by another version of "
            f"this program (this one reads format {CHECKPOINT_FORMAT}): delete it to run "
            "afresh, or resume it with the version that wrote it"
        )
    if not data.startswith(CHECKPOINT_MAGIC):
        raise ValueError(
            f"{str(path)!r} is not a checkpoint this program wrote (or its header is damaged): "
            "delete it, or give another path"
        )
    checksum, size = data[start : start + 32], data[start + 32 : start + 40]
    body = data[start + 40 :]
    if hashlib.sha256(body).digest() != checksum or int.from_bytes(size, "little") != len(body):
        raise ValueError(
            f"the checkpoint {str(path)!r} is damaged: its checksum does not match its contents "
            "(a corrupted or truncated file); delete it, or give another path"
        )
    try:
        payload = pickle.loads(body)
    except Exception as error:  # a checksum that matches a payload it cannot read
        raise ValueError(
            f"{str(path)!r} is not a checkpoint this program wrote ({type(error).__name__}): "
            "delete it, or give another path"
        ) from None
    if not isinstance(payload, dict) or "signature" not in payload:
        raise ValueError(f"{str(path)!r} is not a checkpoint this program wrote")
    return payload


def checkpoint_path(checkpoint: str | os.PathLike[str] | None) -> Path | None:
    """The ``checkpoint`` argument of a solve as a Path in an existing directory, or None."""
    if checkpoint is None:
        return None
    path = as_path(checkpoint, "checkpoint")
    if not path.parent.is_dir():
        raise ValueError(f"checkpoint: the directory {str(path.parent)!r} does not exist")
    return path


class CheckpointMismatch(ValueError):
    """A checkpoint written for another model or with other solver settings; ``changed``
    names the items that differ (labels of ``Fingerprint.items``, e.g. "gravity 0",
    "history_nodes")."""

    def __init__(self, message: str, changed: list[str]):
        super().__init__(message)
        self.changed = changed


def resume(path: Path | None, signature: Fingerprint | None) -> dict[str, Any] | None:
    """The checkpoint at ``path`` to resume from, None if there is none.

    Parameters
    ----------
    path : Path or None
    signature : femcore.fingerprint.Fingerprint or None
        The fingerprint of the model and the solver settings of this run (None, not computed,
        when there is no ``path``).

    Raises
    ------
    CheckpointMismatch
        When the checkpoint was written for another model or with other solver settings,
        naming the parts that differ (and the items within them).
    ValueError
        When it is damaged or not a checkpoint.
    """
    payload = load_checkpoint(path) if path is not None else None
    if payload is None:
        return None
    assert signature is not None, "a checkpoint path comes with its run's fingerprint"
    saved = payload.get("signature")
    if not isinstance(saved, Fingerprint):
        raise ValueError(
            f"the checkpoint {str(path)!r} was written by another version of this program "
            "(it does not carry the fingerprint of its model); delete it or point checkpoint= "
            "elsewhere"
        )
    differences = signature.differences(saved)
    if differences:
        only_solver = all(d.startswith("its solver settings") for d in differences)
        written = "with other solver settings" if only_solver else "for another model"
        # (getattr: a Fingerprint pickled before the kind was kept has no attribute of its own
        # but the class's default, "")
        kinds = (getattr(saved, "solver", ""), signature.solver)
        if all(kinds) and kinds[0] != kinds[1]:
            written = f"by another solver, {kinds[0]} (this run is {kinds[1]})"
        changed = sorted(
            label
            for label in set(signature.items) | set(saved.items)
            if signature.items.get(label) != saved.items.get(label)
        )
        raise CheckpointMismatch(
            f"the checkpoint {str(path)!r} was written {written}: "
            f"{'; '.join(differences)}; delete it or point checkpoint= elsewhere",
            changed,
        )
    return payload
