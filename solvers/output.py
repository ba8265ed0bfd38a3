"""Output written while a run goes: frames as a VTU series with its ParaView index, histories as
CSV rows, and checkpoints to resume from. Each file is complete after every write, so a run that
is killed leaves a readable series, history and checkpoint."""

from __future__ import annotations

import csv
import os
import pickle
from pathlib import Path
from typing import Any
from xml.sax.saxutils import quoteattr

import numpy as np

from femcore.mesh import Mesh
from femcore.results import Frame, Result

__all__ = [
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
    checked = Path(path)
    if checked.suffix.lower() != suffix:
        raise ValueError(f"{what} must be a {suffix} path, got {str(path)!r}")
    if not checked.parent.is_dir():
        raise ValueError(f"{what}: the directory {str(checked.parent)!r} does not exist")
    return checked


class FrameStream:
    """Frames written as they come: ``<stem>_<k>.vtu`` next to the ``.pvd`` index, which is
    rewritten after each frame. The solver then keeps only the first and the newest frame in
    memory, so a long run's memory does not grow with its number of frames."""

    def __init__(self, path: Path, mesh: Mesh, has_rotation: np.ndarray):
        self.path, self.mesh, self.has_rotation = path, mesh, has_rotation
        self.entries: list[tuple[float, str]] = []  # (time, file name) per written frame

    def write(self, frame: Frame) -> None:
        stem = self.path.with_suffix("")
        part = stem.parent / f"{stem.name}_{len(self.entries):05d}.vtu"
        Result(self.mesh, [frame], has_rotation=self.has_rotation).write(part)
        self.entries.append((frame.time, part.name))
        self._write_index()

    def drop_after(self, time: float) -> None:
        """Unlist (and delete) the frames written after ``time``: a diverged run's series ends
        with its last good state."""
        for t, name in self.entries:
            if t > time * (1.0 + 1e-12):
                (self.path.parent / name).unlink(missing_ok=True)
        self.entries = [(t, name) for t, name in self.entries if t <= time * (1.0 + 1e-12)]
        self._write_index()

    def _write_index(self) -> None:
        lines = [
            f"    <DataSet timestep={quoteattr(repr(t))} file={quoteattr(name)}/>"
            for t, name in self.entries
        ]
        text = (
            '<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n'
            "  <Collection>\n" + "\n".join(lines) + "\n  </Collection>\n</VTKFile>\n"
        )
        _atomic_write(self.path, text.encode())


class HistoryWriter:
    """CSV rows appended (and flushed) as the run goes: time, the energies (N mm), the sum of
    the support reactions (N), the force on each rigid tool (N) and the displacements (mm) of
    chosen nodes."""

    def __init__(self, path: Path, nodes: np.ndarray, tools: int = 0):
        self.path, self.nodes, self.tools = path, nodes, tools
        self.rows = 0  # data rows written; a resumed run cuts the file back to them

    def header(self) -> list[str]:
        columns = ["time", "kinetic", "internal", "external_work", "damping", "friction"]
        columns += ["reaction_x", "reaction_y", "reaction_z"]
        for tool in range(1, self.tools + 1):
            columns += [f"tool{tool}_f{axis}" for axis in "xyz"]
        for node in self.nodes:
            columns += [f"u{axis}_{node}" for axis in "xyz"]
        return columns

    def start(self) -> None:
        """Write the header, or keep the rows a checkpoint counted and drop any after them."""
        if self.rows == 0 or not self.path.exists():
            with open(self.path, "w", newline="") as handle:
                csv.writer(handle).writerow(self.header())
            self.rows = 0
            return
        with open(self.path, newline="") as handle:
            kept = list(csv.reader(handle))[: self.rows + 1]
        with open(self.path, "w", newline="") as handle:
            csv.writer(handle).writerows(kept)

    def append(
        self,
        energies: tuple,
        reactions: np.ndarray,
        displacements: np.ndarray,
        tool_forces: np.ndarray | None = None,
    ) -> None:
        tools = np.zeros((0, 3)) if tool_forces is None else tool_forces
        row = [*energies, *reactions.sum(axis=0), *tools.ravel()]
        row += [*displacements[self.nodes].ravel()]
        with open(self.path, "a", newline="") as handle:
            csv.writer(handle).writerow([repr(float(v)) for v in row])
            handle.flush()
        self.rows += 1


def save_checkpoint(path: Path, payload: dict[str, Any]) -> None:
    """Pickle ``payload`` to ``path`` atomically."""
    _atomic_write(path, pickle.dumps(payload, protocol=pickle.HIGHEST_PROTOCOL))


def load_checkpoint(path: Path) -> dict[str, Any] | None:
    """The payload of ``path``, or None if there is no such file. Only load checkpoints this
    program wrote: unpickling runs code."""
    if not path.exists():
        return None
    try:
        with open(path, "rb") as handle:
            payload = pickle.load(handle)
    except Exception as error:  # any unpickling failure means the same thing to the user
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
    path = Path(checkpoint)
    if not path.parent.is_dir():
        raise ValueError(f"checkpoint: the directory {str(path.parent)!r} does not exist")
    return path


def resume(path: Path | None, signature: tuple) -> dict[str, Any] | None:
    """The checkpoint at ``path`` to resume from, None if there is none; ValueError when it
    was written by another model or other solver settings (another ``signature``)."""
    payload = load_checkpoint(path) if path is not None else None
    if payload is not None and payload.get("signature") != signature:
        raise ValueError(
            f"the checkpoint {str(path)!r} was written by another model or other solver "
            "settings: delete it, or give another path"
        )
    return payload
