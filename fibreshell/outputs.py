"""The files a run writes in its output folder, by their exact names, and their removal before
a new run writes there: a reused folder keeps the user's own files (README "Stopping,
resuming, output folders": other files stay), and a checkpoint may not take the name of a
file the run writes beside it.

A run (``fibreshell.run.run_case``) writes ``result.pvd`` and its frames ``result_<k>.vtu``
(k zero-padded to 5 digits by a streamed series, 4 by ``Result.write``; more digits past
99 999 frames), ``history.csv``, ``summary.json``, ``energies.csv`` (explicit runs), its
checkpoint, and for a moment ``<name>.part`` beside the series index and the checkpoint
(solvers/output.py writes them whole and renames them over the file). ``fibreshell sweep``
adds ``variant.json`` to each variant's folder, the plies of ``fibreshell compare``
``material-lines.vtu`` to theirs; an identification (and compare's fit) writes
``identify.json`` and ``fit.png``."""

from __future__ import annotations

import json
import os
import re
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path, PurePath

from fibreshell.folder_lock import LOCK_FILE, folder_lock

__all__ = [
    "DEFAULT_CHECKPOINT", "IDENTIFY_FILES", "MATERIAL_LINES", "RUN_FILES", "VARIANT_FILE",
    "checkpoint_collision", "clean_run", "is_run_output", "remove_run_folder", "run_folder_lock",
]  # fmt: skip

# The checkpoint of explicit and relaxation runs unless [solver] checkpoint names another.
DEFAULT_CHECKPOINT = "checkpoint.pkl"
# The files of a run's folder by name (the frames are FRAME_FILE).
RUN_FILES = ("result.pvd", "history.csv", "energies.csv", "summary.json")
# A frame of the series: result_00000.vtu (Result.write and a streamed series alike; 4 digits
# in folders written before).
FRAME_FILE = re.compile(r"result_[0-9]{4,}\.vtu")
# A sweep's record of a variant, in the variant's run folder (fibreshell.sweep.run_variant).
VARIANT_FILE = "variant.json"
# The stack's mid-surface beside the plies' series (fibreshell.plies.write_material_lines).
MATERIAL_LINES = "material-lines.vtu"
# What an identification writes in its folder (fibreshell.identify.identify): the fit and
# its figure.
IDENTIFY_FILES = ("identify.json", "fit.png")


def is_run_output(name: str) -> bool:
    """Whether the file name ``name`` (no folder) is one a run writes: RUN_FILES, a frame of
    its series (FRAME_FILE), or the series index's temporary ``result.pvd.part``."""
    return name in RUN_FILES or name == "result.pvd.part" or FRAME_FILE.fullmatch(name) is not None


def checkpoint_collision(name: str | os.PathLike[str]) -> str | None:
    """What a checkpoint at ``name`` (relative to the output folder, or absolute) would
    overwrite, in words ("'result.pvd', which a run writes in its output folder"), or None:
    a checkpoint named ``result.pvd`` would turn a ParaView series into a pickle, one named
    ``history.csv`` be overwritten by the history at the end of a run. Whatever folder it is
    in: ``../a/result.pvd`` or ``saved/result.pvd`` is (or may become) another run's."""
    path = PurePath(os.path.normpath(name))
    if is_run_output(path.name):
        return f"{path.name!r}, which a run writes in its output folder"
    if path.name == LOCK_FILE or path.name.startswith(LOCK_FILE + "."):
        return f"{path.name!r}, the lock a command holds on its folder while it writes"
    if path.name == VARIANT_FILE:
        return f"{path.name!r}, which a sweep writes in each variant's folder"
    if path.name == MATERIAL_LINES:
        return f"{path.name!r}, which a run of plies writes in its output folder"
    if path.name in IDENTIFY_FILES:
        return f"{path.name!r}, which an identification writes in its folder"
    return None


def clean_run(out: Path, checkpoint: Path | None, extra: tuple[str, ...] = ()) -> None:
    """Remove from the folder ``out`` the files a run writes there (``is_run_output``), the
    default checkpoint (an earlier run of another kind may have left it), ``checkpoint`` and
    the temporary ``.part`` of each checkpoint, and the files named in ``extra``; nothing else
    (a user's ``result_scan.vtu`` or ``notes.part`` stays)."""
    if not out.is_dir():
        return
    stale = [path for path in out.iterdir() if is_run_output(path.name)]
    stale += [out / name for name in extra]
    for saved in (out / DEFAULT_CHECKPOINT, checkpoint):
        if saved is not None:
            stale += [saved, saved.with_name(saved.name + ".part")]
    for path in stale:
        if not path.is_dir():
            path.unlink(missing_ok=True)


@contextmanager
def run_folder_lock(folder: Path, task: str) -> Iterator[None]:
    """Hold ``folder`` (fibreshell.folder_lock) and its default checkpoint's file, which
    ``clean_run`` removes: another run may keep its checkpoint there (``[solver] checkpoint =
    "../folder/checkpoint.pkl"``), holding that file's lock; then this is refused
    (FolderInUse) rather than remove it."""
    with (
        folder_lock(folder, task),
        folder_lock(folder, task, "the checkpoint", file=DEFAULT_CHECKPOINT),
    ):
        yield


def remove_run_folder(folder: Path, extra: tuple[str, ...] = ()) -> None:
    """Remove a folder an earlier command wrote a run into: the run's files (``clean_run``,
    with the checkpoint its summary.json names when that is in the folder), the files named
    in ``extra`` (what the command added beside the run), then the folder itself if nothing
    else is left in it (a user's own file keeps it). The folder is held while its files go
    (fibreshell.folder_lock, which removes the staged lock records of killed commands:
    ``remove_dead_staging``): one another command holds is refused (FolderInUse)."""
    if not folder.is_dir():
        return
    checkpoint = None
    try:
        named = json.loads((folder / "summary.json").read_text()).get("checkpoint")
    except (OSError, ValueError, AttributeError):
        named = None
    if isinstance(named, str) and Path(named).parent.resolve() == folder.resolve():
        checkpoint = folder / Path(named).name
    # held while emptied: a command writing there now (fibreshell run --out into a sweep's
    # variant folder) keeps its files, and this command is refused
    with run_folder_lock(folder, f"the removal of an earlier run's files from {str(folder)!r}"):
        clean_run(folder, checkpoint, extra)
    try:
        folder.rmdir()
    except OSError:  # not empty: the user's files stay, and the folder with them
        pass
