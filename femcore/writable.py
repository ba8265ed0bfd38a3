"""Output folders checked before a run writes into them, and writes that fail said in one line.

A folder is checked before anything runs: it is a folder (not a file, not under a file), it can
be created, a file can be written in it, and its disk has room for the first frames (a frame's
VTU size estimated from the node and cell counts). A write that fails later (a full disk, a
folder made read-only) is one ``OutputError`` naming the path and what was kept.

``OutputError`` is an OSError: the cause is the machine, not the input (the same call succeeds
on another disk), callers that already handle OSError keep handling it, and ``errno`` tells a
full disk (ENOSPC) from a refused one (EACCES, EROFS). A path that cannot be a folder (a file
given as the folder) is bad input and a ValueError.
"""

from __future__ import annotations

import errno as errnos
import os
import shutil
import tempfile
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from femcore.mesh import Mesh

__all__ = ["OutputError", "check_folder", "frame_bytes", "series_frames"]

# Bytes of one VTU frame per node and per cell, an upper bound of the shells' frames (the
# fibrous strip of cases/g1151_strip.toml: 11.7 kB for 27 nodes and 32 cells)
# (meshio's XML VTU: base64 of the positions, displacement, directors, velocities, reactions
# and moments, thickness and tilt per node; connectivity and a dozen fields per cell).
BYTES_PER_NODE = 400
BYTES_PER_CELL = 300
# Frames whose room is asked for before a run starts (the first few: a later full disk is
# reported when it happens).
FIRST_FRAMES = 3


class OutputError(OSError):
    """A folder or file that cannot be written: ``str(error)`` is one line naming the path,
    the reason and what was kept; ``errno`` and ``filename`` as for any OSError."""

    def __init__(
        self,
        message: str,
        code: int | None = None,
        filename: str | None = None,
        reason: str | None = None,
    ):
        super().__init__(code if code is not None else 0, message)
        self.message = message
        self.filename = filename
        self.reason = message if reason is None else reason  # the message without what was kept

    def __str__(self) -> str:
        return self.message

    def __reduce__(self):  # pickled by Dask and process pools: the message, not OSError's args
        return (type(self), (self.message, self.errno, self.filename, self.reason))

    @classmethod
    def from_error(cls, error: OSError, kept: str) -> OutputError:
        """The OutputError of a failed write ``error``, saying that ``kept`` is on disk."""
        path = error.filename if error.filename is not None else "(unnamed file)"
        if isinstance(error, OutputError):
            reason = error.reason
        else:
            why = error.strerror or str(error) or type(error).__name__
            reason = f"cannot write {str(path)!r}: {why}"
        return cls(f"{reason}; stopped, kept: {kept}", error.errno, str(path), reason)


def frame_bytes(mesh: Mesh) -> int:
    """An upper estimate (bytes) of one VTU frame of ``mesh`` (its nodes and its cells of
    every kind)."""
    cells = sum(len(mesh.cells(kind)) for kind in mesh.cell_kinds)
    return BYTES_PER_NODE * len(mesh.points) + BYTES_PER_CELL * cells + 4096


def check_folder(
    folder: str | os.PathLike[str], what: str, needed: int = 0, create: bool = True
) -> Path:
    """``folder`` as a Path, checked for writing: a folder (created with its parents when
    ``create``), writable, with ``needed`` bytes free on its disk.

    Parameters
    ----------
    folder : path
    what : str
        How the caller names it in messages ("--out", "output", "checkpoint").
    needed : int
        Bytes the first writes need (``frame_bytes`` x FIRST_FRAMES for a run).
    create : bool
        Create a missing folder (else a missing folder is a ValueError).

    Raises
    ------
    ValueError
        The path is a file, lies under a file, or (``create`` False) does not exist.
    OutputError
        It cannot be created or written, or its disk has less than ``needed`` bytes free.
    """
    path = Path(folder)
    if path.exists() and not path.is_dir():
        raise ValueError(f"{what} {str(path)!r} is a file: give a folder")
    existing = next((p for p in (path, *path.parents) if p.exists()), None)
    if existing is not None and not existing.is_dir():
        raise ValueError(f"{what} {str(path)!r}: {str(existing)!r} is a file, not a folder")
    if not path.exists():
        if not create:
            raise ValueError(f"{what}: the folder {str(path)!r} does not exist")
        try:
            path.mkdir(parents=True, exist_ok=True)
        except OSError as error:
            raise OutputError(
                f"{what} {str(path)!r} cannot be created: {error.strerror or error}",
                error.errno,
                str(path),
            ) from None
    try:
        with tempfile.TemporaryFile(dir=path, prefix=".write-check-"):
            pass
    except OSError as error:
        raise OutputError(
            f"{what} {str(path)!r} is not writable: {error.strerror or error}",
            error.errno,
            str(path),
        ) from None
    free = shutil.disk_usage(path).free
    if needed > free:
        raise OutputError(
            f"{what} {str(path)!r}: {free / 1e6:.3g} MB free on its disk, the frames need "
            f"about {needed / 1e6:.3g} MB: free some space or give another folder",
            errnos.ENOSPC,
            str(path),
        )
    return path


def series_frames(pvd: Path) -> int:
    """The number of frames a ParaView series index lists (0 if it cannot be read)."""
    try:
        return pvd.read_text().count("<DataSet")
    except (OSError, UnicodeDecodeError):
        return 0
